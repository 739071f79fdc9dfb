"""Undamped and damped modes: frequencies, shapes, energies, poles and damping ratios (api / result / methods / kernels)."""

from .api import damped_modes, modes
from .result import DampedModes, Modes

__all__ = ["DampedModes", "Modes", "damped_modes", "modes"]
