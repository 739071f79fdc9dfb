"""Nonlinear mount axes: bump stops and force-deflection curves.

A mount type may make any of its three local (principal) axes nonlinear:

- **stops** ``{"z": (clearance, stiffness)}``: past the clearance [m] (one number, symmetric, or
  ``(negative side, positive side)``, both >= 0) a stop of ``stiffness`` [N/m] adds its force to
  the mount's own: ``k_s (d - c+)`` above ``c+``, ``k_s (d + c-)`` below ``-c-``;
- **curve** ``{"z": [(deflection, force), ...]}``: the axis's elastic force [N] at a deflection [m]
  is the monotone piecewise-cubic (PCHIP) interpolant of the points, which include (0, 0), and
  continues beyond them with its end slopes. It replaces the axis's linear stiffness, whose value
  is the curve's slope at zero (the small-deflection rate every linear analysis of the unloaded
  model uses).

An :class:`AxisLaw` evaluates one axis: force, tangent stiffness and stored energy (the integral
of the force, which makes the static equilibrium the minimum of a convex potential when every law
is monotone). Deflection is body side minus ``to`` side, along the local axis, as everywhere in
vibss.

Examples
--------
>>> law = AxisLaw.build(1e4, stop=((1e-3, 1e-3), 1e6))
>>> float(law.force(2e-3)), float(law.tangent(2e-3))      # 1e4 * 2e-3 + 1e6 * (2e-3 - 1e-3)
(1020.0, 1010000.0)
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from .._validate import is_numeric
from ..errors import ModelError

__all__ = ["AXES", "AxisLaw", "parse_stops", "parse_curve", "refuse_nonlinear"]

AXES = ("x", "y", "z")
"""Local axes a stop or a curve may name (the mount type's principal axes 1, 2, 3)."""

SLOPE_RTOL = 1e-9
"""A given stiffness on a curved axis must equal the curve's slope at zero to this (relative)."""


@dataclass(frozen=True)
class AxisLaw:
    """The elastic force law of one local axis of a mount: linear or curved, with or without a stop.

    Attributes
    ----------
    stiffness : float
        Linear rate [N/m] (the curve's slope at zero when ``curve`` is given).
    curve : PchipInterpolator or None
        Force [N] of deflection [m] inside the points; linear beyond them with the end slopes.
    span : (2,) tuple of float
        First and last deflection of the curve's points [m] (``(0, 0)`` without a curve).
    clearance : (2,) tuple of float
        Stop clearance on the negative and positive side [m] (``inf`` without a stop).
    stop : float
        Stop stiffness [N/m] (0 without a stop).
    """

    stiffness: float
    curve: Any = None
    span: tuple[float, float] = (0.0, 0.0)
    clearance: tuple[float, float] = (np.inf, np.inf)
    stop: float = 0.0

    @classmethod
    def build(cls, stiffness: float, stop: tuple[tuple[float, float], float] | None = None,
              points: np.ndarray | None = None) -> AxisLaw:
        """A law from a linear rate, an optional stop ``((c-, c+), k_s)`` and optional curve points
        ``(k, 2)`` [m, N] (already validated, :func:`parse_curve`)."""
        curve, span, k = None, (0.0, 0.0), float(stiffness)
        if points is not None:
            from scipy.interpolate import PchipInterpolator   # heavy at start-up (scipy.optimize); curves only
            curve = PchipInterpolator(points[:, 0], points[:, 1], extrapolate=False)
            span = (float(points[0, 0]), float(points[-1, 0]))
            k = float(curve(0.0, 1))
        clearance, ks = ((np.inf, np.inf), 0.0) if stop is None else (stop[0], float(stop[1]))
        return cls(k, curve, span, (float(clearance[0]), float(clearance[1])), ks)

    @property
    def linear(self) -> bool:
        """No stop and no curve."""
        return self.curve is None and self.stop == 0.0

    def _elastic(self, d: np.ndarray, order: int) -> np.ndarray:
        """The curve (or the linear rate) and its derivatives: order 0 force, 1 tangent, -1 energy."""
        if self.curve is None:
            return {0: self.stiffness * d, 1: np.full_like(d, self.stiffness), -1: 0.5 * self.stiffness * d * d}[order]
        lo, hi = self.span
        c = self.curve
        inside = np.clip(d, lo, hi)
        if order == 1:
            slope_lo, slope_hi = float(c(lo, 1)), float(c(hi, 1))
            return np.where(d < lo, slope_lo, np.where(d > hi, slope_hi, c(inside, 1)))
        f_lo, f_hi = float(c(lo)), float(c(hi))
        s_lo, s_hi = float(c(lo, 1)), float(c(hi, 1))
        if order == 0:
            return np.where(d < lo, f_lo + s_lo * (d - lo), np.where(d > hi, f_hi + s_hi * (d - hi), c(inside)))
        anti = c.antiderivative()
        e0 = float(anti(0.0))
        e = anti(inside) - e0                           # energy inside the span, zero at d = 0
        over = np.where(d > hi, d - hi, 0.0)
        under = np.where(d < lo, d - lo, 0.0)
        return e + f_hi * over + 0.5 * s_hi * over**2 + f_lo * under + 0.5 * s_lo * under**2

    def force(self, d: npt.ArrayLike) -> np.ndarray:
        """Elastic force [N] at deflection ``d`` [m] (stop included)."""
        d = np.asarray(d, dtype=float)
        out = self._elastic(d, 0)
        if self.stop:
            lo, hi = self.clearance
            out = out + self.stop * (np.maximum(d - hi, 0.0) + np.minimum(d + lo, 0.0))
        return out

    def tangent(self, d: npt.ArrayLike) -> np.ndarray:
        """Tangent stiffness ``df/dd`` [N/m] at ``d`` [m] (the stop's rate once engaged)."""
        d = np.asarray(d, dtype=float)
        out = self._elastic(d, 1)
        if self.stop:
            lo, hi = self.clearance
            out = out + self.stop * ((d > hi) | (d < -lo))
        return out

    def energy(self, d: npt.ArrayLike) -> np.ndarray:
        """Stored energy ``int_0^d f`` [J] at ``d`` [m]."""
        d = np.asarray(d, dtype=float)
        out = self._elastic(d, -1)
        if self.stop:
            lo, hi = self.clearance
            out = out + 0.5 * self.stop * (np.maximum(d - hi, 0.0) ** 2 + np.minimum(d + lo, 0.0) ** 2)
        return out

    def room(self, d: npt.ArrayLike) -> np.ndarray:
        """Clearance left before the stop [m]: ``c+ - d`` or ``c- + d``, the smaller (negative once
        in contact; ``inf`` without a stop)."""
        d = np.asarray(d, dtype=float)
        lo, hi = self.clearance
        return np.minimum(hi - d, lo + d)


def _axis(key: Any, who: str, what: str) -> int:
    if key not in AXES:
        raise ModelError(f"{who}: {what}: unknown axis {key!r}; use the local axes {list(AXES)}",
                         argument=what, received=key, expected=AXES)
    return AXES.index(key)


def parse_stops(value: Any, who: str) -> dict[int, tuple[tuple[float, float], float]]:
    """``{"z": (clearance, stiffness)}`` -> ``{2: ((c-, c+), k_s)}``, validated.

    Raises
    ------
    ModelError
        Not a mapping, an unknown axis, a negative or non-finite clearance, a stiffness <= 0.
    """
    if not isinstance(value, Mapping):
        raise ModelError(f"{who}: stops: expected a mapping of local axis to (clearance [m], stiffness "
                         f"[N/m]), e.g. {{'z': (0.005, 2e6)}}, got {value!r}", argument="stops", received=value)
    out: dict[int, tuple[tuple[float, float], float]] = {}
    for key, spec in value.items():
        j = _axis(key, who, "stops")
        where = f"{who}: stops[{key!r}]"
        if isinstance(spec, Mapping):
            spec = (spec.get("clearance"), spec.get("stiffness"))
        if not isinstance(spec, (tuple, list)) or len(spec) != 2:
            raise ModelError(f"{where}: expected (clearance [m], stiffness [N/m]), got {spec!r}",
                             argument="stops", received=spec)
        clearance, stiffness = spec
        c = np.array(clearance, dtype=float) if is_numeric(clearance) else None
        if c is None or c.shape not in ((), (2,)):
            raise ModelError(f"{where}: clearance: expected one number [m] or (negative side, positive "
                             f"side), got {clearance!r}", argument="clearance", received=clearance)
        c = np.broadcast_to(c, (2,))
        if not np.all(np.isfinite(c)) or np.any(c < 0):
            raise ModelError(f"{where}: clearance must be finite and not negative (the gap to the stop on "
                             f"each side) [m], got {c.tolist()}", argument="clearance", received=c.tolist())
        k = float(stiffness) if is_numeric(stiffness) and np.ndim(stiffness) == 0 else None
        if k is None or not np.isfinite(k) or k <= 0:
            raise ModelError(f"{where}: stiffness: expected a positive stop rate [N/m], got {stiffness!r}",
                             argument="stiffness", received=stiffness)
        out[j] = ((float(c[0]), float(c[1])), k)
    return out


def parse_curve(value: Any, who: str) -> dict[int, np.ndarray]:
    """``{"z": [(deflection, force), ...]}`` -> ``{2: (k, 2) points}``, validated.

    Raises
    ------
    ModelError
        An unknown axis, fewer than 3 points, a curve not through (0, 0), deflections not
        increasing, forces not increasing (a mount that pushes back less when pressed further
        has no unique static equilibrium).
    """
    if not isinstance(value, Mapping):
        raise ModelError(f"{who}: curve: expected a mapping of local axis to [(deflection [m], force [N]), "
                         f"...], got {value!r}", argument="curve", received=value)
    out: dict[int, np.ndarray] = {}
    for key, pts in value.items():
        j = _axis(key, who, "curve")
        where = f"{who}: curve[{key!r}]"
        a = np.array(pts, dtype=float) if is_numeric(pts) else None
        if a is None or a.ndim != 2 or a.shape[1] != 2 or a.shape[0] < 3:
            raise ModelError(f"{where}: expected at least 3 (deflection [m], force [N]) pairs, got {pts!r}",
                             argument="curve", received=pts)
        if not np.all(np.isfinite(a)):
            raise ModelError(f"{where}: points must be finite, got {a.tolist()}", argument="curve",
                             received=a.tolist())
        a = a[np.argsort(a[:, 0], kind="stable")]
        if not np.any((a[:, 0] == 0) & (a[:, 1] == 0)):
            raise ModelError(f"{where}: the curve must pass through (0, 0) (no force at zero deflection); "
                             f"got {a.tolist()}", argument="curve", received=a.tolist(),
                             expected="a point (0, 0)")
        dd, df = np.diff(a[:, 0]), np.diff(a[:, 1])
        if np.any(dd <= 0):
            raise ModelError(f"{where}: deflections must be distinct, got {a[:, 0].tolist()}", argument="curve",
                             received=a.tolist())
        if np.any(df <= 0):
            i = int(np.flatnonzero(df <= 0)[0])
            raise ModelError(f"{where}: the force must increase with the deflection (a monotone curve); it "
                             f"goes from {a[i, 1]:.6g} N at {a[i, 0]:.6g} m to {a[i + 1, 1]:.6g} N at "
                             f"{a[i + 1, 0]:.6g} m", argument="curve", received=a.tolist(), expected="monotone")
        out[j] = a
    return out


def refuse_nonlinear(model: Any, where: str) -> None:
    """Refuse a linear analysis of a model whose mounts have stops or curves, naming them and the
    linear model that answers instead: the tangent at the operating point.

    Raises
    ------
    ModelError
        The model has nonlinear mounts.
    """
    names = [m.name for m in getattr(model, "mounts", ()) if getattr(m.type, "nonlinear", False)]
    if names:
        raise ModelError(f"{where}: mounts {names} have stops or force-deflection curves, and this analysis is "
                         "linear: analyse the tangent model at the operating point, "
                         "vibss.operating_point(model).tangent (vibss.modes and vibss.static take the model "
                         "itself)", argument="model", received=names)
