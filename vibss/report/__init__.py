"""The engineer's report of a model: every analysis that applies, as text, PNG figures and HTML.

One module per part: :mod:`~vibss.report.section` (the :class:`Section` and :class:`Report` data,
the order and titles), :mod:`~vibss.report.sections` (one module per analysis, each building its
section), :mod:`~vibss.report.study` (:func:`study`: runs them in order; a section that fails is
noted and the others still run) and :mod:`~vibss.report.html` (the PNG figures, ``index.html`` and
``report.txt``). See :mod:`vibss.report.study` for what each section shows.

Examples
--------
>>> import vibss
>>> from vibss.report import study
>>> t = vibss.MountType("t", [1e4, 2e4, 3e4])
>>> m = vibss.Model([vibss.Body("b", 1000.0, [10, 20, 30])],
...                 vibss.symmetric(vibss.Mount("m", t, "b", at=[1, 2, 0])), name="prism")
>>> [s.key for s in study(m, figures=False).sections if not s.skipped]
['model', 'modes', 'design', 'frequency']
"""

from __future__ import annotations

from .html import html_table, render_report, write_report
from .section import MAX_MODE_PANELS, STEPS, TITLES, Progress, Report, Section, default_folder, progress_on_stderr, slug
from .study import _RUNNERS, SECTION_ERRORS, study

__all__ = ["Section", "Report", "study", "write_report", "render_report", "html_table", "slug", "default_folder",
           "progress_on_stderr", "STEPS", "MAX_MODE_PANELS"]
