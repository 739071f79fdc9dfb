"""Measured data in, models out: a mount's rheology fitted to its measured dynamic stiffness, and a
flexible foundation known by its receptance, coupled by frequency-based substructuring."""

from __future__ import annotations

from .api import fit_rheology
from .blocked import blocked_forces
from .fbs import Foundation
from .modes import MeasuredModes
from .result import RheologyFit
from .update import update
from .update_result import UpdateResult

__all__ = ["fit_rheology", "RheologyFit", "Foundation", "MeasuredModes", "update", "UpdateResult", "blocked_forces"]
