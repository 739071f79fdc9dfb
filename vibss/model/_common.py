"""Names and small checks shared by the model's parts (bodies, mounts, points, loads).

Private to :mod:`vibss.model`: the public names (``GROUND``, ``DOF_NAMES``) are re-exported by
:mod:`vibss.model.model`.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .._validate import vector
from ..errors import ModelError
from .geometry import Orientation

__all__ = ["GROUND", "DOF_NAMES"]

GROUND = "ground"
"""Name of the fixed (or prescribed-motion) reference body."""

DOF_NAMES = ("x", "y", "z", "rx", "ry", "rz")
"""The six DOFs of a body, in the order used everywhere."""



def unit_direction(d: np.ndarray) -> np.ndarray | None:
    """``d / |d|`` (read-only), or None for a zero vector; scaled by its largest entry first, so a
    direction of ``[1e308, 1, 0]`` is ``[1, 1e-308, 0]``, not an overflow to ``[0, 0, 0]`` (issue 18's
    fuzzer: a sensor direction became the zero vector with an overflow warning)."""
    big = float(np.abs(d).max()) if d.size else 0.0
    if not big > 0:
        return None
    d = np.asarray(d, float) / big
    out = d / float(np.linalg.norm(d))
    out.setflags(write=False)
    return out


def _freeze(a: np.ndarray) -> np.ndarray:
    a.setflags(write=False)
    return a


def _vec(value: Any, n: int, who: str, key: str) -> np.ndarray:
    return _freeze(vector(value, n, key, who=who))


def _name(value: Any, who: str) -> str:
    if not isinstance(value, str) or not value.strip():
        raise ModelError(f"{who}: name must be a non-empty string, got {value!r}")
    if value == GROUND:
        raise ModelError(f"{who}: the name {GROUND!r} is reserved for the fixed reference")
    return _signal_safe(value, who)


def _signal_safe(value: str, who: str) -> str:
    """Refuse names that would make signal names ambiguous.

    ``:`` is python-control's spelling of ``.`` in signal names (two names would collide), and a
    body or point named ``<x>.into`` would give an input ``<x>.into.fz`` (a force on it) with the
    same name as the output ``<x>.into.fz`` (the force into body ``<x>``).
    """
    if ":" in value:
        raise ModelError(f"{who}: name {value!r} contains ':', which python-control signal names use "
                         "in place of '.'; use another character")
    return value


def _point_name(value: str, who: str) -> str:
    """Body and control point names: also not ``into`` or ending in ``.into`` (see _signal_safe)."""
    if value == "into" or value.endswith(".into"):
        raise ModelError(f"{who}: name {value!r} would make '{value}.fz' both a force input and "
                         "an '<body>.into.fz' output; choose another name")
    return value


def _orientation(value: Any, who: str, key: str) -> Orientation:
    try:
        return Orientation.coerce(value, key)
    except ModelError as exc:
        raise ModelError(f"{who}: {exc}") from None


def _frame(value: str, who: str) -> str:
    if value not in ("body", "global"):
        raise ModelError(f"{who}: frame must be 'body' or 'global', got {value!r}")
    return value
