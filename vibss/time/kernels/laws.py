"""The nonlinear mount axes of a time response as local coordinates: each axis's force beyond the linear
rate the plant carries, its slope and curvature, and which side of its stop it is on (its regime).

A time run keeps the linear part of every mount in the plant (a nonlinear axis at the rate the
assembly used, :attr:`~vibss.model.nonlinearity.AxisLaw.stiffness`) and adds, on each nonlinear axis
``a``, the local force ``g_a(e) = f_nl(d_op + e) - f_nl(d_op)`` with ``f_nl(d) = f(d) - k0 d`` (the law
beyond the linear rate), ``d_op`` the axis's deflection at the operating point and ``e`` the deflection
from there [m]. A stop is piecewise linear: within one regime (free, on the positive stop, on the
negative stop) its force is a straight line, so the integrator locates every crossing of a clearance
and never steps over a kink.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ...model.nonlinearity import AxisLaw

__all__ = ["LocalLaws"]


@dataclass(frozen=True, eq=False)
class LocalLaws:
    """The r nonlinear mount axes (local coordinates) of a simulation.

    Attributes
    ----------
    names : tuple of str
        ``"<mount>.<axis>"`` per coordinate, axis ``x``, ``y`` or ``z`` (local).
    laws : tuple of AxisLaw
        Each axis's law.
    d0 : (r,) ndarray
        Deflection at the operating point [m] (the time response starts there).
    """

    names: tuple[str, ...]
    laws: tuple[AxisLaw, ...]
    d0: np.ndarray

    def __post_init__(self) -> None:
        object.__setattr__(self, "k0", np.array([law.stiffness for law in self.laws], float))
        object.__setattr__(self, "ks", np.array([law.stop for law in self.laws], float))
        object.__setattr__(self, "lo", np.array([law.clearance[0] for law in self.laws], float))
        object.__setattr__(self, "hi", np.array([law.clearance[1] for law in self.laws], float))
        object.__setattr__(self, "curved", np.array([i for i, law in enumerate(self.laws) if law.curve is not None],
                                                    int))
        object.__setattr__(self, "_pieces", self._piecewise())
        object.__setattr__(self, "_gap", (np.where(np.isfinite(self.lo), self.lo, 0.0),
                                          np.where(np.isfinite(self.hi), self.hi, 0.0)))
        g_op = self._stop(self.d0, self.regime(self.d0)) + self._curve(self.d0)[0]
        object.__setattr__(self, "g_op", g_op)

    k0: np.ndarray = field(init=False, repr=False)       # linear rates [N/m]
    ks: np.ndarray = field(init=False, repr=False)       # stop rates [N/m] (0: none)
    lo: np.ndarray = field(init=False, repr=False)       # negative-side clearances [m]
    hi: np.ndarray = field(init=False, repr=False)       # positive-side clearances [m]
    curved: np.ndarray = field(init=False, repr=False)   # indices of the curved axes
    g_op: np.ndarray = field(init=False, repr=False)     # force beyond the linear rate at d0 [N]
    _pieces: tuple[np.ndarray, ...] = field(init=False, repr=False)         # the curves as cubics
    _gap: tuple[np.ndarray, np.ndarray] = field(init=False, repr=False)     # clearances, 0 for no stop [m]

    def _piecewise(self) -> tuple[np.ndarray, ...]:
        """The curved axes' pieces for :meth:`_curve`: first and last breakpoints (rc,) [m], inner
        breakpoints (rc, n - 1) padded with inf, the last piece's index, each axis's offset into the
        flat piece list, and per flat piece its cubic's coefficients in powers of the distance from its
        start (scipy's PPoly form) with that start [m] as a fifth row; and the axes' linear rates."""
        curves = [self.laws[i].curve for i in self.curved]
        n = max((cv.c.shape[1] for cv in curves), default=0)
        inner = np.full((len(curves), max(n - 1, 0)), np.inf)
        for j, cv in enumerate(curves):
            inner[j, :cv.x.size - 2] = cv.x[1:-1]
        sizes = np.array([cv.c.shape[1] for cv in curves], int)
        coef = np.hstack([np.vstack([cv.c, cv.x[None, :-1]]) for cv in curves]) if curves else np.zeros((5, 0))
        return (np.array([cv.x[0] for cv in curves], float), np.array([cv.x[-1] for cv in curves], float), inner,
                sizes - 1, np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(int), coef, self.k0[self.curved])

    @property
    def r(self) -> int:
        """Number of local coordinates."""
        return len(self.laws)

    @property
    def stops(self) -> np.ndarray:
        """(r,) bool: the axis has a stop."""
        return self.ks > 0

    def regime(self, d: np.ndarray) -> np.ndarray:
        """(r,) int: +1 past the positive clearance, -1 past the negative one, 0 free (``d`` total [m])."""
        return np.where(d > self.hi, 1, np.where(d < -self.lo, -1, 0)).astype(int)

    def _stop(self, d: np.ndarray, regime: np.ndarray) -> np.ndarray:
        # an axis without a stop has infinite clearances, a zero rate and regime 0: its finite stand-ins
        # (self._gap) keep the product 0 without an inf - inf
        lo, hi = self._gap
        return self.ks * np.where(regime > 0, d - hi, d + lo) * (regime != 0)

    def _curve(self, d: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The curved axes' force beyond the linear rate [N], its slope [N/m] and curvature [N/m^2] at
        ``d`` [m], every curve at once from its piecewise cubic (an integration step calls this in each
        Newton iteration: a scalar call per axis cost 0.4 ms of the 0.5 ms step of a 6-DOF cabinet)."""
        out = np.zeros((3, d.size))
        c = self.curved
        if not c.size:
            return out[0], out[1], out[2]
        first, ends, inner, last, base, coef, k0 = self._pieces
        dc = d[c]
        x = np.minimum(np.maximum(dc, first), ends)
        at = base + np.minimum((x[:, None] >= inner).sum(axis=1), last)
        t = x - coef[4, at]
        c0, c1, c2, c3 = coef[:4, at]
        p1 = (3.0 * c0 * t + 2.0 * c1) * t + c2
        out[0, c] = ((c0 * t + c1) * t + c2) * t + c3 + p1 * (dc - x) - k0 * dc   # end slopes beyond
        out[1, c] = p1 - k0
        out[2, c] = (6.0 * c0 * t + 2.0 * c1) * ((dc > first) & (dc < ends))
        return out[0], out[1], out[2]

    def force(self, e: np.ndarray, regime: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Local force ``g(e)`` [N], its slope [N/m] and curvature [N/m^2] in the given regimes
        (each stop's straight line continued past its clearance: a step that crosses it is split)."""
        d = self.d0 + e
        g = self._stop(d, regime) - self.g_op
        g1 = self.ks * (regime != 0)
        g2 = np.zeros_like(d)
        if self.curved.size:
            f, f1, f2 = self._curve(d)
            g, g1, g2 = g + f, g1 + f1, f2
        return g, g1, g2

    def linear_in_regime(self) -> bool:
        """Every axis is a stop on a linear rate: the force is a straight line within each regime."""
        return self.curved.size == 0
