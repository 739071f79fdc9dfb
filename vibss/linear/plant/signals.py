"""The old home of :func:`~vibss.linear.plant.build.build_plant` and
:func:`~vibss.linear.plant.names.control_name` (issue 28 split it into ``names``, ``build`` and
``mountform``).

Kept only for ``vibss/frequency``, ``vibss/time``, ``vibss/reduction`` and ``vibss/modal``, which
were being reshaped at the same time; the lead switches their imports after the merge and deletes
this module. Import from :mod:`vibss.linear.plant.build` and :mod:`vibss.linear.plant.names`.
"""

from __future__ import annotations

from .build import build_plant
from .names import control_name

__all__ = ["build_plant", "control_name"]
