"""Measured modes: natural frequencies and mode shapes read at named points, as an experimental
modal analysis (sdypy-EMA, a modal test) gives them: :class:`MeasuredModes`, what
:func:`vibss.update` takes besides a measured frequency response."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validate import array
from ..errors import ArgumentError
from ..results import ReadOnly

__all__ = ["MeasuredModes"]

_WHO = "MeasuredModes"


@dataclass(frozen=True, eq=False)
class MeasuredModes(ReadOnly):
    """Measured natural frequencies and real mode shapes at named outputs of a model.

    Parameters
    ----------
    frequencies : (k,) array_like
        Natural frequencies [Hz], finite, > 0.
    shapes : (q, k) array_like
        Mode shapes, one column per mode, one row per output: real amplitudes in any scale and
        sign (each mode is compared with the model's after a best scale factor) [m, rad or the
        outputs' units].
    outputs : sequence of str
        Names of the rows, as the model names its output signals: a body DOF (``"engine.z"``), a
        control point (``"sensor.x"``), or their velocity or acceleration (``"engine.z.acc"``).
    name : str
        Name of the measurement.

    Examples
    --------
    >>> m = MeasuredModes([5.0, 8.0], [[1.0, 0.2], [0.1, -1.0]], ["b.x", "b.z"])
    >>> m.shapes.shape, m.outputs
    ((2, 2), ('b.x', 'b.z'))
    """

    frequencies: Any
    shapes: Any
    outputs: Sequence[str]
    name: str = "measured modes"

    def __post_init__(self) -> None:
        f = array(self.frequencies, "frequencies", (None,), who=_WHO, unit="Hz")
        if f.size == 0 or np.any(f <= 0):
            raise ArgumentError(f"{_WHO}: frequencies: expected at least one natural frequency > 0 [Hz], got "
                                f"{f.tolist()}", argument="frequencies", received=self.frequencies, expected="> 0")
        if isinstance(self.outputs, str) or not all(isinstance(o, str) and o for o in self.outputs):
            raise ArgumentError(f"{_WHO}: outputs: expected a list of output names such as 'engine.z', got "
                                f"{self.outputs!r}", argument="outputs", received=self.outputs)
        outputs = tuple(self.outputs)
        if len(set(outputs)) != len(outputs):
            dup = sorted({o for o in outputs if outputs.count(o) > 1})
            raise ArgumentError(f"{_WHO}: outputs: {dup} given more than once", argument="outputs", received=dup)
        shapes = array(self.shapes, "shapes", who=_WHO)
        if shapes.ndim == 1 and f.size == 1:
            shapes = shapes[:, None]
        if shapes.shape != (len(outputs), f.size):
            raise ArgumentError(f"{_WHO}: shapes: expected shape ({len(outputs)}, {f.size}) (one row per output, "
                                f"one column per mode), got {shapes.shape}", argument="shapes",
                                received=shapes.shape, expected=(len(outputs), f.size))
        zero = np.flatnonzero(~np.any(shapes != 0, axis=0))
        if zero.size:
            raise ArgumentError(f"{_WHO}: shapes: mode {int(zero[0]) + 1} ({f[zero[0]]:g} Hz) is zero at every "
                                "output; a shape must move somewhere", argument="shapes", received=int(zero[0]) + 1)
        object.__setattr__(self, "frequencies", f)
        object.__setattr__(self, "shapes", shapes)
        object.__setattr__(self, "outputs", outputs)
        super().__post_init__()

    @property
    def frequency_hz(self) -> np.ndarray:
        """(k,) natural frequencies [Hz]."""
        return np.asarray(self.frequencies)

    def __len__(self) -> int:
        return int(np.asarray(self.frequencies).size)
