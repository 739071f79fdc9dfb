"""Undamped and damped modes: frequencies, shapes, energies, poles and damping ratios."""

from .damped import DampedModes, damped_modes
from .undamped import Modes, modes

__all__ = ["DampedModes", "Modes", "damped_modes", "modes"]
