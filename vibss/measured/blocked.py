"""Blocked forces of a source for transfer path analysis: :func:`blocked_forces`.

The blocked forces are the forces a source puts into a rigid foundation: its mounts' ground ends
held fixed. They belong to the source alone, so they carry over to any foundation: on one of
receptance ``Y_B`` at those points the foundation moves by

    z = (I - Y_B H_gz)^-1 Y_B f_blocked

(``-H_gz`` the source's blocked dynamic stiffness; :mod:`vibss.measured.coupling`).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from ..errors import ArgumentError
from ..frequency.api import frequency_response
from ..frequency.result import FrequencyResponse
from ..model.model import GROUND, Model
from .coupling import _skews, on_supports, signals, source_response, to_points
from .fbs import components

__all__ = ["blocked_forces"]

_WHO = "blocked_forces"


def blocked_forces(model: Model, inputs: Sequence[Any], frequencies: Any, points: Sequence[str] | None = None, *,
                   rotations: bool = False, method: str | Callable[..., np.ndarray] = "auto") -> FrequencyResponse:
    """The source's blocked forces at the ground ends of its mounts to ground, per input and frequency.

    The force (and with ``rotations`` the moment about the mount's point) each mount puts into its
    ground end held fixed, global axes: on rigid ground these are the ground mounts' own forces; on
    a flexible foundation they drive its motion (:mod:`vibss.measured.blocked`).

    Parameters
    ----------
    model : Model
        The source.
    inputs : sequence of str or Excitation
        Input signals (forces on the bodies, actuators ...).
    frequencies : (nf,) array_like [Hz], FrequencyGrid, mapping or None
        As :func:`vibss.frequency_response`.
    points : sequence of str or None
        Mounts to ground (default: every mount to ground), in the order of the outputs.
    rotations : bool
        Also the moments ``mx, my, mz`` [N m] about each mount's point.
    method : str or callable
        Method of the source's solve (as :func:`vibss.frequency_response`).

    Returns
    -------
    FrequencyResponse
        Outputs ``<mount>.fx|fy|fz`` (``mx|my|mz``) [N, N m per input unit], quantity
        ``"blocked force"``.

    Raises
    ------
    ModelError
        A point that is not a mount to ground (named, with did-you-mean).

    Examples
    --------
    >>> from vibss import Body, Model, Mount, MountType
    >>> m = Model([Body("b", 10.0, [1, 1, 1])], [Mount("m", MountType("t", [1e4] * 3, [20.0] * 3), "b")])
    >>> r = blocked_forces(m, ["b.fz"], [0.0])
    >>> print(f"{abs(r.response[2, 0, 0]):.6g} N/N")                  # statics: the whole force
    1 N/N
    """
    if not isinstance(model, Model):
        raise ArgumentError(f"{_WHO}: model: expected a vibss Model (its mounts are named), got "
                            f"{type(model).__name__}", argument="model", received=type(model).__name__)
    if points is None:
        points = [m.name for m in model.mounts if m.to == GROUND]
    elif isinstance(points, str):
        points = [points]
    points = list(points)
    if not points or len(set(points)) != len(points):
        raise ArgumentError(f"{_WHO}: points: expected distinct mounts to ground, got {points}",
                            argument="points", received=points)
    src, supports = on_supports(model, points, _WHO)
    _, gout = signals(supports, rotations)
    if _explicit(frequencies):          # a long list: blocks of frequencies (CHUNK_BYTES each)
        parts = [r for _, r in source_response(src, list(inputs), gout, np.asarray(frequencies, dtype=float), method)]
    else:
        parts = [frequency_response(src, list(inputs), gout, frequencies, method=method)]
    h = np.concatenate([r.response for r in parts], axis=2)
    if rotations:
        h = np.moveaxis(h, 2, 0)                       # (nf, n, m): moments taken to the points
        to_points(h, _skews(model, points), slice(None), None)
        h = np.moveaxis(h, 0, 2)
    r = parts[0]
    _, comps, _, load = components(rotations)
    names = tuple(f"{p}.{c}" for p in points for c in comps)
    units = load * len(points)
    f = np.concatenate([x.frequency_hz for x in parts])
    marks = (r.natural_hz, r.mode_numbers, r.mode_labels) if len(parts) == 1 else (np.zeros(0), (), ())
    note = f"the forces into {len(points)} mount ends held fixed (supports of their own); {r.note}"
    return FrequencyResponse(f, np.ascontiguousarray(h), names, r.inputs, units, "blocked force", r.method, note,
                             marks[0], model.name, r.input_units, marks[1], marks[2])


def _explicit(frequencies: Any) -> bool:
    """Whether ``frequencies`` is an explicit list (blocks of it are solved apart); a grid spec is not."""
    try:
        return np.asarray(frequencies, dtype=float).ndim == 1
    except (TypeError, ValueError):
        return False
