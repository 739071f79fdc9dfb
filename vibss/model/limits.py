"""What a rigid-body mount model can mean: the one range per quantity that model files and the
Python API both enforce (issue 18: a 1e-300 kg mass or an Euler angle of -1e20 degrees was accepted
in Python while files refused it).

>>> check_range([2.0, 0.0], "stiffness", "mount type 't'", "stiffness", "N/m")   # 0: no stiffness
>>> check_range(1e-300, "mass", "body 'b'", "mass", "kg")
Traceback (most recent call last):
...
vibss.errors.ModelError: body 'b': mass: 1e-300 kg is outside what a rigid-body model means (1e-09 .. 1e+10 kg)
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..errors import ModelError

__all__ = ["PLAUSIBLE", "MAX_EULER_RAD", "check_range"]

PLAUSIBLE: dict[str, tuple[float, float]] = {
    "mass": (1e-9, 1e10),
    "inertia": (1e-15, 1e14),
    "stiffness": (1e-6, 1e20),
    "damping": (0.0, 1e16),
    "length": (0.0, 1e5),
}
"""The range [SI] of the magnitude of a value per quantity: what a rigid-body mount model can mean
(a 1 microgram part to a 10,000 t machine; a link of 1e20 N/m is already rigid to 15 digits). The
lower bound applies to values that must be positive and to nonzero stiffnesses (zero means "no
stiffness")."""

MAX_EULER_RAD = 2 * np.pi
"""Largest magnitude of an Euler angle [rad] (360 degrees)."""


def check_range(value: Any, quantity: str, who: str, field: str, unit: str) -> None:
    """Refuse values of ``quantity`` outside :data:`PLAUSIBLE` with a :class:`ModelError` naming
    ``who`` and ``field`` (zeros pass for stiffness, damping and lengths: "none" or "here")."""
    lo, hi = PLAUSIBLE[quantity]
    size = np.abs(np.asarray(value, dtype=float)).ravel()
    bad = (size > hi) | ((size < lo) & ((size > 0) | (quantity in ("mass", "inertia"))))
    if np.any(bad):
        v = float(np.asarray(value, dtype=float).ravel()[int(np.flatnonzero(bad)[0])])
        raise ModelError(f"{who}: {field}: {v:.4g} {unit} is outside what a rigid-body model means "
                         f"({lo:g} .. {hi:g} {unit})")
