"""The nonlinear mount axes of a time response as local coordinates: each axis's force beyond the linear
rate the plant carries, its slope and curvature, and which side of its stop it is on (its regime).

A time run keeps the linear part of every mount in the plant (a nonlinear axis at the rate the
assembly used, :attr:`~vibss.model.nonlinearity.AxisLaw.stiffness`) and adds, on each nonlinear axis
``a``, the local force ``g_a(e) = f_nl(d_op + e) - f_nl(d_op)`` with ``f_nl(d) = f(d) - k0 d`` (the law
beyond the linear rate), ``d_op`` the axis's deflection at the operating point and ``e`` the deflection
from there [m]. A stop is piecewise linear: within one regime (free, on the positive stop, on the
negative stop) its force is a straight line, so the integrator locates every crossing of a clearance
and never steps over a kink. A force-deflection curve is a piecewise cubic (PCHIP, continued by its end
slopes): its second derivative jumps at each breakpoint, so the integrator locates those crossings too
(each axis's *piece*: 0 below the first breakpoint, ``1 .. n`` the n cubics, ``n + 1`` above the last) and
within a step the force is one polynomial of the deflection: the steps keep their fourth order.
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
        object.__setattr__(self, "stops", self.ks > 0)
        object.__setattr__(self, "lo", np.array([law.clearance[0] for law in self.laws], float))
        object.__setattr__(self, "hi", np.array([law.clearance[1] for law in self.laws], float))
        object.__setattr__(self, "curved", np.array([i for i, law in enumerate(self.laws) if law.curve is not None],
                                                    int))
        object.__setattr__(self, "_pieces", self._piecewise())
        object.__setattr__(self, "_edges", self._segment_edges())
        object.__setattr__(self, "_gap", (np.where(np.isfinite(self.lo), self.lo, 0.0),
                                          np.where(np.isfinite(self.hi), self.hi, 0.0)))
        g_op = self._stop(self.d0, self.regime(self.d0)) + self._curve(self.d0)[0]
        object.__setattr__(self, "g_op", g_op)

    k0: np.ndarray = field(init=False, repr=False)       # linear rates [N/m]
    ks: np.ndarray = field(init=False, repr=False)       # stop rates [N/m] (0: none)
    stops: np.ndarray = field(init=False, repr=False)    # (r,) bool: the axis has a stop
    lo: np.ndarray = field(init=False, repr=False)       # negative-side clearances [m]
    hi: np.ndarray = field(init=False, repr=False)       # positive-side clearances [m]
    curved: np.ndarray = field(init=False, repr=False)   # indices of the curved axes
    g_op: np.ndarray = field(init=False, repr=False)     # force beyond the linear rate at d0 [N]
    _pieces: tuple[np.ndarray, np.ndarray] = field(init=False, repr=False)  # the curves as cubics, offsets
    _gap: tuple[np.ndarray, np.ndarray] = field(init=False, repr=False)     # clearances, 0 for no stop [m]
    _edges: np.ndarray = field(init=False, repr=False)    # (rc, knots + 2) -inf, breakpoints, +inf padded [m]

    def _segment_edges(self) -> np.ndarray:
        """Per curved axis ``[-inf, x_0, ..., x_n, +inf, ...]`` (padded with +inf): piece ``s`` spans
        ``[edges[s], edges[s + 1])``."""
        knots = [self.laws[i].curve.x for i in self.curved]
        n = max((x.size for x in knots), default=0)
        edges = np.full((len(knots), n + 2), np.inf)
        edges[:, 0] = -np.inf
        for j, x in enumerate(knots):
            edges[j, 1:x.size + 1] = x
        return edges

    def _piecewise(self) -> tuple[np.ndarray, np.ndarray]:
        """The curved axes' segments for :meth:`_curve` as one flat table: per axis its ``n + 2``
        pieces (the end line below the first breakpoint, the n cubics, the end line above the last),
        each a cubic in the distance from its start (scipy's PPoly form; the end lines with zero
        leading coefficients) with that start [m] as a fifth row; and each axis's offset into it."""
        cols: list[np.ndarray] = []
        base: list[int] = []
        for i in self.curved:
            cv = self.laws[i].curve
            base.append(sum(c.shape[1] for c in cols))
            lo_v, hi_v = float(cv(cv.x[0])), float(cv(cv.x[-1]))
            lo_s, hi_s = float(cv(cv.x[0], 1)), float(cv(cv.x[-1], 1))
            cols.append(np.array([[0.0], [0.0], [lo_s], [lo_v], [cv.x[0]]]))
            cols.append(np.vstack([cv.c, cv.x[None, :-1]]))
            cols.append(np.array([[0.0], [0.0], [hi_s], [hi_v], [cv.x[-1]]]))
        coef = np.hstack(cols) if cols else np.zeros((5, 0))
        return coef, np.array(base, int)

    @property
    def r(self) -> int:
        """Number of local coordinates."""
        return len(self.laws)

    def regime(self, d: np.ndarray) -> np.ndarray:
        """(r,) int: +1 past the positive clearance, -1 past the negative one, 0 free (``d`` total [m])."""
        return np.where(d > self.hi, 1, np.where(d < -self.lo, -1, 0)).astype(int)

    def _stop(self, d: np.ndarray, regime: np.ndarray) -> np.ndarray:
        # an axis without a stop has infinite clearances, a zero rate and regime 0: its finite stand-ins
        # (self._gap) keep the product 0 without an inf - inf
        lo, hi = self._gap
        return self.ks * np.where(regime > 0, d - hi, d + lo) * (regime != 0)

    def piece(self, d: np.ndarray) -> np.ndarray:
        """(r,) int: the piece of its curve each curved axis is on at ``d`` (total [m]; 0 for the others)."""
        out = np.zeros(d.size, int)
        if self.curved.size:
            out[self.curved] = (d[self.curved, None] >= self._edges[:, 1:]).sum(axis=1)
        return out

    def bounds(self, piece: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(r,) lower and upper breakpoints [m] of each curved axis's ``piece`` (-inf and +inf past its
        ends and on the axes without a curve)."""
        lo, hi = np.full(piece.size, -np.inf), np.full(piece.size, np.inf)
        c = self.curved
        if c.size:
            rows = np.arange(c.size)
            lo[c], hi[c] = self._edges[rows, piece[c]], self._edges[rows, piece[c] + 1]
        return lo, hi

    def _curve(self, d: np.ndarray, piece: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The curved axes' force beyond the linear rate [N], its slope [N/m] and curvature [N/m^2] at
        ``d`` [m], every curve at once from its piecewise cubic (an integration step calls this in each
        Newton iteration: a scalar call per axis cost 0.4 ms of the 0.5 ms step of a 6-DOF cabinet); on
        the given ``piece`` of each curve (its cubic, or end line, continued past its breakpoints), or on
        the piece ``d`` is in."""
        out = np.zeros((3, d.size))
        c = self.curved
        if not c.size:
            return out[0], out[1], out[2]
        coef, base = self._pieces
        dc = d[c]
        at = base + (self.piece(d) if piece is None else piece)[c]
        c0, c1, c2, c3, x0 = coef[:, at]
        t = dc - x0
        out[0, c] = ((c0 * t + c1) * t + c2) * t + c3 - self.k0[c] * dc
        out[1, c] = (3.0 * c0 * t + 2.0 * c1) * t + c2 - self.k0[c]
        out[2, c] = 6.0 * c0 * t + 2.0 * c1
        return out[0], out[1], out[2]

    def force(self, e: np.ndarray, regime: np.ndarray,
              piece: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Local force ``g(e)`` [N], its slope [N/m] and curvature [N/m^2] in the given regimes
        (each stop's straight line continued past its clearance: a step that crosses it is split) and
        on the given pieces of the curves (each continued past its breakpoints; None: where ``e`` is)."""
        d = self.d0 + e
        g = self._stop(d, regime) - self.g_op
        g1 = self.ks * (regime != 0)
        g2 = np.zeros_like(d)
        if self.curved.size:
            f, f1, f2 = self._curve(d, piece)
            g, g1, g2 = g + f, g1 + f1, f2
        return g, g1, g2

    def linear_in_regime(self) -> bool:
        """Every axis is a stop on a linear rate: the force is a straight line within each regime (else
        a cubic within each piece)."""
        return self.curved.size == 0
