"""Power spectral densities as specifications write them: breakpoints (frequency, level) joined by
straight lines on log-log axes, zero outside the table.

A level table in g²/Hz (IEC 60068-2-64, MIL-STD-810 514) is the default for acceleration inputs;
``unit`` says otherwise: ``"g^2/Hz"``, ``"(m/s^2)^2/Hz"``, ``"N^2/Hz"``, ``"(N m)^2/Hz"``,
``"m^2/Hz"``, ``"(m/s)^2/Hz"``, ``"rad^2/Hz"`` ... Levels are kept in SI ((m/s²)²/Hz etc.).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import _validate as v
from ..errors import ArgumentError, did_you_mean
from ..model.units import G

__all__ = ["PSD", "G", "UNITS", "as_psd"]

UNITS: dict[str, float] = {"g^2/Hz": G * G, "(m/s^2)^2/Hz": 1.0, "N^2/Hz": 1.0, "(N m)^2/Hz": 1.0,
                           "m^2/Hz": 1.0, "(m/s)^2/Hz": 1.0, "rad^2/Hz": 1.0, "(rad/s^2)^2/Hz": 1.0,
                           "(rad/s)^2/Hz": 1.0, "mm^2/Hz": 1e-6}
"""Accepted level units and their factor to SI."""

EDGE_RTOL = 1e-12
"""A frequency this close (relative) to a band edge is on it: a grid built in ln f meets the edges
only to rounding, and the first point of the band read 0."""


@dataclass(frozen=True)
class PSD:
    """A one-sided power spectral density given by breakpoints.

    Parameters
    ----------
    frequency_hz : (k,) array_like
        Breakpoint frequencies [Hz], increasing, > 0 (k >= 1; one point: a single line).
    level : (k,) array_like
        Levels at the breakpoints in ``unit`` (>= 0).
    unit : str
        Unit of ``level`` (:data:`UNITS`).
    name : str
        Label.

    Examples
    --------
    >>> p = PSD([20, 80, 350, 2000], [0.01, 0.04, 0.04, 0.007])     # g^2/Hz
    >>> round(p.rms_g, 3)
    6.058
    """

    frequency_hz: Any
    level: Any
    unit: str = "g^2/Hz"
    name: str = "psd"
    si: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        who = f"PSD {self.name!r}"
        f = np.atleast_1d(v.array(self.frequency_hz, "frequency_hz", None, who=who))
        lv = np.atleast_1d(v.array(self.level, "level", None, who=who))
        if f.ndim != 1 or lv.shape != f.shape:
            raise ArgumentError(f"{who}: frequency_hz and level must be lists of the same length, got "
                                f"{f.shape} and {lv.shape}", argument="level", received=self.level)
        if np.any(f <= 0) or np.any(np.diff(f) <= 0):
            raise ArgumentError(f"{who}: frequency_hz must be positive and increasing, got {f.tolist()}",
                                argument="frequency_hz", received=self.frequency_hz)
        if np.any(lv < 0):
            raise ArgumentError(f"{who}: level must not be negative, got {lv.tolist()}", argument="level",
                                received=self.level)
        if self.unit not in UNITS:
            raise ArgumentError(f"{who}: unit: unknown {self.unit!r}; expected one of {list(UNITS)}"
                                + did_you_mean(self.unit, UNITS), argument="unit", received=self.unit)
        object.__setattr__(self, "frequency_hz", f)
        object.__setattr__(self, "level", lv)
        object.__setattr__(self, "si", lv * UNITS[self.unit])

    @property
    def band(self) -> tuple[float, float]:
        """(lowest, highest) breakpoint [Hz]."""
        return float(self.frequency_hz[0]), float(self.frequency_hz[-1])

    def __call__(self, f: Any) -> np.ndarray:
        """Level in SI at frequencies ``f`` [Hz]: log-log between breakpoints, 0 outside (a band
        edge met to within :data:`EDGE_RTOL`, e.g. ``exp(log(20))``, counts as the edge)."""
        f = np.asarray(f, dtype=float)
        fp, lp = self.frequency_hz, self.si
        f = np.where(np.abs(f - fp[0]) <= EDGE_RTOL * fp[0], fp[0],
                     np.where(np.abs(f - fp[-1]) <= EDGE_RTOL * fp[-1], fp[-1], f))
        out = np.zeros(f.shape)
        inside = (f >= fp[0]) & (f <= fp[-1])
        if fp.size == 1:
            return np.where(f == fp[0], lp[0], 0.0)
        k = np.clip(np.searchsorted(fp, f[inside], side="right") - 1, 0, fp.size - 2)
        a, b = lp[k], lp[k + 1]
        ok = (a > 0) & (b > 0)
        t = np.log(f[inside] / fp[k]) / np.log(fp[k + 1] / fp[k])
        vals = np.where(ok, np.exp(np.log(np.where(ok, a, 1.0)) * (1 - t) + np.log(np.where(ok, b, 1.0)) * t),
                        a + (b - a) * t)                 # a zero end: linear
        out[inside] = vals
        return out

    @property
    def mean_square(self) -> float:
        """Exact integral of the log-log segments [SI unit^2] (the square of the RMS)."""
        fp, lp = self.frequency_hz, self.si
        total = 0.0
        for f1, f2, a, b in zip(fp[:-1], fp[1:], lp[:-1], lp[1:]):
            if a > 0 and b > 0:
                n = np.log(b / a) / np.log(f2 / f1)          # slope on log-log axes
                total += a * f1 * np.log(f2 / f1) if abs(n + 1) < 1e-12 else a / (n + 1) * f1 * ((f2 / f1) ** (n + 1) - 1)
            else:
                total += 0.5 * (a + b) * (f2 - f1)
        return float(total)

    @property
    def rms_g(self) -> float:
        """RMS of an acceleration PSD in g (``sqrt(mean_square) / G``)."""
        return float(np.sqrt(self.mean_square)) / G


def as_psd(value: Any, kind: str, name: str) -> PSD:
    """A :class:`PSD`, or a ``(frequency_hz, level)`` pair in the default unit of the input kind
    (acceleration: g²/Hz; force: N²/Hz; displacement: m²/Hz; velocity: (m/s)²/Hz)."""
    if isinstance(value, PSD):
        return value
    default = {"acceleration": "g^2/Hz", "force": "N^2/Hz", "displacement": "m^2/Hz",
               "velocity": "(m/s)^2/Hz"}.get(kind, "g^2/Hz")
    if isinstance(value, tuple) and len(value) == 2:
        return PSD(value[0], value[1], default, name)
    raise ArgumentError(f"inputs[{name!r}]: expected a PSD or a (frequency_hz, level) pair (level in "
                        f"{default} for a {kind} input), got {value!r}", argument="inputs", received=value)
