"""The old home of :func:`~vibss.linear.plant.build.build_plant` (issue 28 split it into
:mod:`~vibss.linear.plant.names`, :mod:`~vibss.linear.plant.build` and
:mod:`~vibss.linear.plant.mountform`).

Kept only for ``vibss/time``, which was being reshaped at the same time; the lead switches its
imports to :mod:`vibss.linear.plant.build` after the merge and deletes this module.
"""

from __future__ import annotations

from .build import build_plant

__all__ = ["build_plant"]
