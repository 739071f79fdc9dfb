"""The old home of :func:`~vibss.linear.eigen.basis.projected_damping` (issue 28 merged it into
:mod:`vibss.linear.eigen.basis`, beside the modal basis and the classical-damping test).

Kept only for ``vibss/time``, which was being reshaped at the same time; the lead switches its
imports after the merge and deletes this module.
"""

from __future__ import annotations

from .basis import projected_damping

__all__ = ["projected_damping"]
