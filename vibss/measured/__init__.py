"""Measured data in, models out: a mount's rheology fitted to its measured dynamic stiffness."""

from __future__ import annotations

from .api import fit_rheology
from .result import RheologyFit

__all__ = ["fit_rheology", "RheologyFit"]
