"""One module per analysis: each builds its :class:`~vibss.report.section.Section` of the report
(a section that fails is noted by :func:`vibss.report.study`, the others still run)."""
