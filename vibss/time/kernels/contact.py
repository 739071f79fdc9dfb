"""Nonlinear mount forces on the exact modal propagation, with located stop contacts.

The response is the linear part (the plant driven by its inputs, by the exact modal method) plus the
response, from rest, to the local forces ``g(t)`` of the r nonlinear axes (:mod:`.laws`). Over each
step the local force is the cubic Hermite of ``g, dg/dt = g'(e) v`` at both ends and the modal blocks
propagate exactly under it (:func:`vibss.time.phi.foh_blocks`); the end values are implicit,
``[e; v] = lin + free + W [g(e); g'(e) v]`` (Newton on 2 r unknowns; one solve where every axis is a
stop). A step that crosses a clearance or a curve's breakpoint (its second derivative jumps there) is
cut at the crossing, found by Newton's method on the exact sub-step, and continued in the new regime
or piece: within a step each force is one polynomial of the deflection, and the error is fourth
order in ``omega_c h`` (``omega_c``: the contact frequencies). An extremum that beats an axis's
running peak is located the same way (``v = 0``): the peaks are the integration's, not the samples'.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ...errors import AnalysisError
from .laws import LocalLaws
from .step import Step, coefficients, discretise

__all__ = ["ContactSystem", "ContactRun", "integrate", "NEWTON_TOL", "LOCATE_TOL"]

NEWTON_TOL = 1e-13
"""Newton's method on a step stops when the update is below this times the step's local scale (the
largest deflection; for velocities, also that over a grid step: at rest in a stop their round-off is more)."""

LOCATE_TOL = 1e-12
"""A crossing (or an extremum) is located when its residual is below this times the deflection scale."""


@dataclass(frozen=True, eq=False)
class ContactSystem:
    """The modal blocks the local forces drive: per set ``A`` (nb, b, b), forcing per local force
    ``F`` (nb, r) (into the last row of a 2x2 block), local rows ``H`` (2 r, nb, b): deflections then
    velocities of the r axes, and output rows ``Y`` (p, nb, b); ``D`` (p, r) the outputs' direct
    feedthrough of the local forces."""

    A: tuple[np.ndarray, ...]
    F: tuple[np.ndarray, ...]
    H: tuple[np.ndarray, ...]
    Y: tuple[np.ndarray, ...]
    D: np.ndarray
    _steps: dict = field(default_factory=dict, repr=False)
    _recent: dict = field(default_factory=dict, repr=False)
    prepared: list = field(default_factory=list, repr=False)     # per set, what every step uses (step.py)

    def step(self, h: float) -> Step:
        """The exact discretisation over ``h`` [s] (kept per length to 13 digits: the grid's differ in bits)."""
        key = float(f"{h:.13g}")
        got = self._steps.get(key)
        if got is None:
            got = discretise(self, float(h))
            if len(self._steps) < 64:
                self._steps[key] = got
        return got

    def sub(self, h: float) -> Step:
        """The exact discretisation over a sub-step ``h`` [s] (the last few kept: a located crossing's
        last Newton iterate is the sub-step taken, and its end is read once more)."""
        key = float(h)
        got = self._recent.get(key)
        if got is None:
            got = discretise(self, key)
            if len(self._recent) >= 4:
                del self._recent[next(iter(self._recent))]
            self._recent[key] = got
        return got


@dataclass
class ContactRun:
    """What the integration recorded besides the outputs: per local axis the peak deflections on each
    side (total, [m]) and their times [s]; the contact intervals per (axis, side); step counts."""

    peak_hi: np.ndarray
    peak_lo: np.ndarray
    t_hi: np.ndarray
    t_lo: np.ndarray
    intervals: dict[tuple[int, int], list[list[float]]]
    steps: int = 0
    events: int = 0
    newton: int = 0
    crossings: int = 0
    h: float = 0.0          # the grid's step [s]: velocities converge against deflection over it


@dataclass
class _State:
    x: list[np.ndarray]     # per set (nb * b,) complex or real
    e: np.ndarray           # (r,) local deflection from the operating point [m]
    v: np.ndarray           # (r,) local velocity [m/s]
    g: np.ndarray           # (r,) local force [N]
    dg: np.ndarray          # (r,) its rate [N/s]
    regime: np.ndarray      # (r,) int: the side of each stop
    piece: np.ndarray       # (r,) int: the piece of each curve (LocalLaws.piece)


def _solve(laws: LocalLaws, st: Step, s: _State, lin: np.ndarray,
           run: ContactRun) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The step's end ``e, v, g, dg`` from state ``s`` over ``st.h`` with the linear part ``lin`` (2r,) at
    its end, in the regimes of ``s``."""
    r = laws.r
    quiet = not (s.regime.any() or laws.curved.size or s.g.any() or s.dg.any())
    free = lin.copy() if quiet else lin + st.Wc @ np.concatenate([s.g, s.dg])
    for HE, x in zip(st.HE, s.x):
        free += (HE @ x).real
    if quiet:
        return free[:r], free[r:], np.zeros(r), np.zeros(r)
    if laws.linear_in_regime():      # one Newton step is the answer: the force is a line in each regime
        key = s.regime.tobytes()
        inv = st.inverse.get(key)
        g, g1, _ = laws.force(free[:r], s.regime, s.piece)
        if inv is None:
            J = np.eye(2 * r)
            J[:, :r] -= st.Wg[:, :r] * g1
            J[:, r:] -= st.Wg[:, r:] * g1
            inv = st.inverse[key] = np.linalg.inv(J)
        z = free + inv @ (st.Wg @ np.concatenate([g, g1 * free[r:]]))
        run.newton += 1
        e, v = z[:r], z[r:]
        g, g1, _ = laws.force(e, s.regime, s.piece)
        return e, v, g, g1 * v
    z = free.copy()
    for it in range(40):
        e, v = z[:r], z[r:]
        g, g1, g2 = laws.force(e, s.regime, s.piece)
        res = z - free - st.Wg @ np.concatenate([g, g1 * v])
        D = np.empty((2 * r, 2 * r))                      # I - J
        D[:, :r] = st.Wg[:, :r] * g1 + st.Wg[:, r:] * (g2 * v)
        D[:, r:] = st.Wg[:, r:] * g1
        te = NEWTON_TOL * (np.abs(e).max() + 1e-300)
        tv = NEWTON_TOL * np.abs(v).max() + te / max(st.h, run.h)
        if it:      # the next update bounded without it: |dz|/tol <= |res|/tol / (1 - q), q = |D| in that scale
            a = np.abs(D)
            w = a[:, :r].sum(axis=1) * te + a[:, r:].sum(axis=1) * tv
            q = max(w[:r].max() / te, w[r:].max() / tv)
            if q < 1.0 and max(np.abs(res[:r]).max() / te, np.abs(res[r:]).max() / tv) <= 1.0 - q:
                return e, v, g, g1 * v
        dz = np.linalg.solve(np.eye(2 * r) - D, -res)
        z = z + dz
        run.newton += 1
        if np.abs(dz[:r]).max() <= te and np.abs(dz[r:]).max() <= tv:
            break
    e, v = z[:r], z[r:]
    g, g1, _ = laws.force(e, s.regime, s.piece)
    return e, v, g, g1 * v


def _advance(st: Step, s: _State, g: np.ndarray, dg: np.ndarray) -> list[np.ndarray]:
    """The modal states at the end of the step (the force polynomial now known)."""
    a = coefficients(st.h, s.g, s.dg, g, dg).ravel()          # (4 r,) k-major
    forcing = st.G() if a.any() else None
    out = []
    for i, (E, x) in enumerate(zip(st.E, s.x)):
        nb, b = E.shape[:2]
        y = np.einsum("nij,nj->ni", E, x.reshape(nb, b)).ravel() if b > 1 else E[:, 0, 0] * x
        out.append(y if forcing is None else y + forcing[i] @ a)
    return out


def _hermite(t: Any, h: float, y0: Any, v0: Any, y1: Any, v1: Any) -> tuple[Any, Any]:
    """Cubic Hermite value and slope at ``t`` in [0, h] from end values and slopes."""
    s = np.asarray(t) / h
    h00, h10, h01, h11 = 2 * s**3 - 3 * s**2 + 1, s**3 - 2 * s**2 + s, -2 * s**3 + 3 * s**2, s**3 - s**2
    d00, d10, d01, d11 = (6 * s**2 - 6 * s) / h, 3 * s**2 - 4 * s + 1, (-6 * s**2 + 6 * s) / h, 3 * s**2 - 2 * s
    return (h00 * y0 + h10 * h * v0 + h01 * y1 + h11 * h * v1,
            d00 * y0 + d10 * v0 + d01 * y1 + d11 * v1)


def _quintic(t: float, h: float, y0: np.ndarray, v0: np.ndarray, a0: np.ndarray, y1: np.ndarray, v1: np.ndarray,
             a1: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Quintic Hermite value and slope at ``t`` in [0, h] from end values, slopes and curvatures."""
    s = t / h
    s2, s3, s4, s5 = s * s, s**3, s**4, s**5
    y = ((1 - 10 * s3 + 15 * s4 - 6 * s5) * y0 + (s - 6 * s3 + 8 * s4 - 3 * s5) * h * v0
         + 0.5 * (s2 - 3 * s3 + 3 * s4 - s5) * h * h * a0 + (10 * s3 - 15 * s4 + 6 * s5) * y1
         + (-4 * s3 + 7 * s4 - 3 * s5) * h * v1 + 0.5 * (s3 - 2 * s4 + s5) * h * h * a1)
    v = ((-30 * s2 + 60 * s3 - 30 * s4) / h * y0 + (1 - 18 * s2 + 32 * s3 - 15 * s4) * v0
         + 0.5 * (2 * s - 9 * s2 + 12 * s3 - 5 * s4) * h * a0 + (30 * s2 - 60 * s3 + 30 * s4) / h * y1
         + (-12 * s2 + 28 * s3 - 15 * s4) * v1 + 0.5 * (3 * s2 - 8 * s3 + 5 * s4) * h * a1)
    return y, v


@dataclass
class _Interval:
    """One grid interval being integrated: the linear part at its ends, its length, how far done."""

    sys: ContactSystem
    laws: LocalLaws
    lin0: np.ndarray
    lin1: np.ndarray
    h: float
    t0: float
    run: ContactRun
    done: float = 0.0

    def lin(self, t: float) -> np.ndarray:
        """The linear part's local deflections and velocities (2r,) at ``t`` after the current sub-step's
        start: the quintic Hermite interpolant of its deflections, velocities and accelerations at the
        interval's ends (sixth order)."""
        r = self.laws.r
        if self.done + t >= self.h:
            return self.lin1[:2 * r]
        a, b = self.lin0, self.lin1
        return np.concatenate(_quintic(self.done + t, self.h, a[:r], a[r:2 * r], a[2 * r:], b[:r], b[r:2 * r],
                                       b[2 * r:]))

    def ends(self, s: _State, t: float) -> tuple[np.ndarray, np.ndarray]:
        """Local deflection and velocity ``t`` after the current sub-step's start (exact sub-step)."""
        if t <= 0.0:
            return s.e, s.v
        st = self.sys.step(t) if self.done == 0.0 and t == self.h else self.sys.sub(t)
        e, v, _, _ = _solve(self.laws, st, s, self.lin(t), self.run)
        return e, v


def integrate(sys: ContactSystem, laws: LocalLaws, t: np.ndarray, lin: np.ndarray, samples: np.ndarray,
              e0: np.ndarray, v0: np.ndarray) -> tuple[np.ndarray, np.ndarray, ContactRun]:
    """Integrate the local forces' response over the grid ``t``.

    Parameters
    ----------
    sys : ContactSystem
    laws : LocalLaws
    t : (ng,) ndarray
        Grid times [s].
    lin : (ng, 3 r) ndarray
        The linear part's local deflections [m], velocities [m/s] and accelerations [m/s^2] at the grid
        points (from the operating point).
    samples : (ns,) int ndarray
        Grid indices of the output samples.
    e0, v0 : (r,) ndarray
        Local deflection and velocity at ``t = 0`` (the linear part's initial values).

    Returns
    -------
    y : (ns, p) ndarray
        The local forces' part of the outputs at the samples.
    local : (ns, 2 r) ndarray
        Local deflections (from the operating point) and velocities at the samples.
    run : ContactRun
    """
    r = laws.r
    p = sys.D.shape[0]
    run = ContactRun(peak_hi=laws.d0 + e0, peak_lo=laws.d0 + e0, t_hi=np.zeros(r), t_lo=np.zeros(r),
                     intervals={}, h=float(t[-1] - t[0]) / max(len(t) - 1, 1))
    x = [np.zeros(A.shape[0] * A.shape[1], complex if np.iscomplexobj(A) or np.iscomplexobj(F) else float)
         for A, F in zip(sys.A, sys.F)]
    regime, piece = laws.regime(laws.d0 + e0), laws.piece(laws.d0 + e0)
    g, g1, _ = laws.force(e0, regime, piece)
    s = _State(x, e0.copy(), v0.copy(), g, g1 * v0, regime, piece)
    for a in np.flatnonzero(regime):
        run.intervals[(int(a), int(regime[a]))] = [[0.0, np.nan]]
    want = np.zeros(len(t), bool)
    want[samples] = True
    y = np.zeros((len(samples), p))
    local = np.zeros((len(samples), 2 * r))
    buf: list[list[np.ndarray]] = [[] for _ in sys.A]
    gbuf: list[np.ndarray] = []
    done = [0]

    def flush() -> None:
        if not gbuf:
            return
        n, k = len(gbuf), done[0]
        acc = np.array(gbuf) @ sys.D.T
        for Y, xs in zip(sys.Y, buf):
            acc = acc + np.real(np.array(xs) @ Y.reshape(p, -1).T)
            xs.clear()
        y[k:k + n] += acc
        done[0] += n
        gbuf.clear()

    def record() -> None:
        for xs, xi in zip(buf, s.x):
            xs.append(xi)
        local[done[0] + len(gbuf)] = np.concatenate([s.e, s.v])
        gbuf.append(s.g)
        if len(gbuf) >= 512:
            flush()

    if want[0]:
        record()
    for i in range(len(t) - 1):
        _interval(_Interval(sys, laws, lin[i], lin[i + 1], float(t[i + 1] - t[i]), float(t[i]), run), s)
        if want[i + 1]:
            record()
    flush()
    for spans in run.intervals.values():
        if spans and np.isnan(spans[-1][1]):
            spans[-1][1] = float(t[-1])
    return y, local, run


def _interval(iv: _Interval, s: _State) -> None:
    """Advance ``s`` over one grid interval, cut at every located crossing of a clearance or of a
    curve's breakpoint."""
    laws, run = iv.laws, iv.run
    last: set[tuple[int, int]] = set()
    events, most = laws.stops.any() or laws.curved.size > 0, 8 * laws.r + 8 + 4 * laws.curved.size
    for _ in range(most):
        rest = iv.h - iv.done
        if rest <= 1e-14 * iv.h:                # the last event was at the interval's end
            return
        st = iv.sys.step(rest) if iv.done == 0.0 else iv.sys.sub(rest)
        e, v, g, dg = _solve(laws, st, s, iv.lin1[:2 * laws.r], run)
        run.steps += 1
        guess = _crossing(laws, s, e, v, rest) if events else None
        found = _locate(iv, s, guess, last) if guess is not None else None
        if found is None and guess is not None and guess < rest:    # the exact crossing after the cubic's
            found = _locate(iv, s, rest, last)
        if found is None:
            _peaks(iv, s, rest, e, v)
            s.x = _advance(st, s, g, dg)
            s.e, s.v, s.g, s.dg = e, v, g, dg
            return
        tau, hits = found
        sub = iv.sys.sub(tau)
        e, v, g, dg = _solve(laws, sub, s, iv.lin(tau), run)
        _peaks(iv, s, tau, e, v)
        s.x = _advance(sub, s, g, dg)
        s.e, s.v = e, v
        now = iv.t0 + iv.done + tau
        for axis, side, kind in hits:
            old = int(s.regime[axis])
            if kind == _KNOT:                           # onto the curve's next piece
                s.piece[axis] += side
                run.crossings += 1
                continue
            if old != 0:                                # leaving the stop
                spans = run.intervals.get((axis, old))
                if spans:
                    spans[-1][1] = now
                s.regime[axis] = 0
            else:                                       # touching it
                s.regime[axis] = side
                run.intervals.setdefault((axis, side), []).append([now, np.nan])
            run.events += 1
        g, g1, _ = laws.force(s.e, s.regime, s.piece)
        s.g, s.dg = g, g1 * s.v
        iv.done += tau
        last = {(axis, kind) for axis, _, kind in hits}
    raise AnalysisError(f"simulate: more than {most} stop events and curve breakpoints in one step at "
                        f"t = {iv.t0:.6g} s (a stop chattering): take a smaller dt")


_S = np.linspace(0.0, 1.0, 17)[1:, None]
_BASIS = (2 * _S**3 - 3 * _S**2 + 1, _S**3 - 2 * _S**2 + _S, -2 * _S**3 + 3 * _S**2, _S**3 - _S**2)
"""Cubic Hermite basis at 16 points of a step: where a crossing is looked for."""


def _crossing(laws: LocalLaws, s: _State, e: np.ndarray, v: np.ndarray, h: float) -> float | None:
    """First time in (0, h] at which the cubic through the step's end values leaves a stop's regime or
    its curve's piece (looked for at 16 points, after a bound on the cubic's range rules most steps
    out), or None."""
    y0, y1 = laws.d0 + s.e, laws.d0 + e
    reach = (4 / 27) * h * (np.abs(s.v) + np.abs(v))              # |h10|, |h11| <= 4/27
    top, bottom = np.maximum(y0, y1) + reach, np.minimum(y0, y1) - reach
    inside = s.regime == 0
    near = laws.stops & np.where(inside, (top > laws.hi) | (bottom < -laws.lo),
                                 np.where(s.regime > 0, bottom <= laws.hi, top >= -laws.lo))
    curved = laws.curved.size > 0
    if curved:
        lo_b, hi_b = laws.bounds(s.piece)
        near |= (top >= hi_b) | (bottom < lo_b)
    if not near.any():
        return None
    b0, b1, b2, b3 = _BASIS
    d = b0 * y0[near] + (b1 * h) * s.v[near] + b2 * y1[near] + (b3 * h) * v[near]     # (16, k)
    hi, lo, reg = laws.hi[near], laws.lo[near], s.regime[near]
    off = np.where(d > hi, 1, np.where(d < -lo, -1, 0)) != reg
    if curved:
        off |= (d >= hi_b[near]) | (d < lo_b[near])
    rows = np.flatnonzero(off.any(axis=1))
    return float(h * _S[rows[0], 0]) if rows.size else None


def _root(fun: Any, ta: float, tb: float, fa: float, fb: float, guess: float, tol: float, floor: float) -> float:
    """A root of ``fun`` in the bracket ``[ta, tb]`` (``fa``, ``fb`` of opposite signs): Newton from
    ``guess``, kept in the bracket (bisection when a step leaves it). ``fun(t) -> (value, derivative)``."""
    t = min(max(guess, ta), tb)
    for _ in range(60):
        f, df = fun(t)
        if abs(f) <= tol or tb - ta <= floor:
            return t
        if np.sign(f) == np.sign(fb):
            tb, fb = t, f
        else:
            ta, fa = t, f
        step = t - f / df if df != 0 else np.nan
        t = step if ta < step < tb else 0.5 * (ta + tb)
    return t


def _cubic_roots(h: float, y0: np.ndarray, v0: np.ndarray, y1: np.ndarray, v1: np.ndarray,
                 c: np.ndarray) -> np.ndarray:
    """Per column a crossing of ``c`` by the cubic Hermite on ``[0, h]`` whose end values bracket it
    (bisection, all columns at once)."""
    lo, hi = np.zeros_like(c), np.full_like(c, h)
    sa = np.sign(y0 - c)
    for _ in range(8):                  # to 4e-3 of the step, then Newton on the cubic kept in the bracket
        mid = 0.5 * (lo + hi)
        same = np.sign(_hermite(mid, h, y0, v0, y1, v1)[0] - c) == sa
        lo, hi = np.where(same, mid, lo), np.where(same, hi, mid)
    t = 0.5 * (lo + hi)
    for _ in range(3):                  # a guess: the exact solution's Newton refines it
        y, dy = _hermite(t, h, y0, v0, y1, v1)
        with np.errstate(divide="ignore", invalid="ignore"):
            t = np.where(dy != 0, t - (y - c) / dy, t)
        t = np.where((t > lo) & (t < hi), t, 0.5 * (lo + hi))
    return t


_STOP, _KNOT = 0, 1
"""The two kinds of event: a stop's clearance, a curve's breakpoint."""


def _events(laws: LocalLaws, s: _State, d: np.ndarray) -> list[tuple[int, int, float, int]]:
    """The boundaries the sub-step's end ``d`` (total [m]) is past: ``(axis, side, boundary [m], kind)``."""
    out = []
    for a in np.flatnonzero(laws.stops):
        old = int(s.regime[a])
        if old == 0:
            if d[a] > laws.hi[a]:
                out.append((int(a), 1, float(laws.hi[a]), _STOP))
            elif d[a] < -laws.lo[a]:
                out.append((int(a), -1, float(-laws.lo[a]), _STOP))
        else:
            c = float(laws.hi[a] if old > 0 else -laws.lo[a])
            if np.sign(d[a] - c) != old:
                out.append((int(a), old, c, _STOP))
    lo_b, hi_b = laws.bounds(s.piece)
    for a in laws.curved:
        if d[a] >= hi_b[a]:
            out.append((int(a), 1, float(hi_b[a]), _KNOT))
        elif d[a] < lo_b[a]:
            out.append((int(a), -1, float(lo_b[a]), _KNOT))
    return out


SIMULTANEOUS = 100.0
"""Boundaries within this many times :data:`LOCATE_TOL` of the first located crossing are crossed with
it (mirrored mounts cross together: one event, not one per mount each re-located after the others)."""


def _locate(iv: _Interval, s: _State, tau: float, last: set[tuple[int, int]]) -> tuple[float, list] | None:
    """The first crossing of a clearance or a breakpoint before ``tau`` into the sub-step, on its exact
    solution (Newton on the time): ``(time [s], [(axis, side, kind), ...] crossed then)``, or None."""
    laws = iv.laws
    e, v = iv.ends(s, tau)
    d = laws.d0 + e
    cands = []
    for a, side, c, kind in _events(laws, s, d):
        f0, f1 = laws.d0[a] + s.e[a] - c, d[a] - c
        if (a, kind) in last and abs(f0) <= LOCATE_TOL * (abs(c) + abs(f1)):
            continue                                    # the boundary just crossed
        cands.append((a, side, c, kind, f0, LOCATE_TOL * (abs(c) + abs(f0) + abs(f1))))
    if not cands:
        return None
    ax, cs = np.array([x[0] for x in cands]), np.array([x[2] for x in cands])
    guess = _cubic_roots(tau, laws.d0[ax] + s.e[ax], s.v[ax], d[ax], v[ax], cs)
    best, at, first = tau, (e, v), -1
    for i in np.argsort(guess, kind="stable"):
        a, side, c, kind, f0, tol = cands[i]
        fb = laws.d0[a] + at[0][a] - c
        if first >= 0 and (np.sign(fb) == np.sign(f0) or abs(fb) <= SIMULTANEOUS * tol):
            continue                                    # not crossed before the earliest crossing so far

        def fun(t: float, a: Any = a, c: float = c) -> tuple[float, float]:
            em, vm = iv.ends(s, t)
            return float(laws.d0[a] + em[a] - c), float(vm[a])

        tc = _root(fun, 0.0, best, f0, fb, float(min(guess[i], best)), tol, 1e-15 * iv.h)
        if first < 0 or tc < best:
            first, best = int(i), tc
            at = iv.ends(s, tc)
    past = [laws.d0[x[0]] + at[0][x[0]] - x[2] for x in cands]      # at the crossing: crossed, or together
    hits = [(x[0], x[1], x[3]) for x, f in zip(cands, past)
            if np.sign(f) != np.sign(x[4]) or abs(f) <= SIMULTANEOUS * x[5]]
    if not hits:        # nothing bracketed: the state was past it already (a grazing return skipped)
        hits.append((cands[first][0], cands[first][1], cands[first][3]))
    return best, hits


PEAK_NOISE = 1e-9
"""An extremum within this fraction of the largest excursion of any axis is round-off (a symmetry keeps
its axis at rest): its peak is the step's cubic's, not located (9 of 10 on a symmetric cabinet)."""


def _peaks(iv: _Interval, s: _State, h: float, e: np.ndarray, v: np.ndarray) -> None:
    """Update the running peaks with the sub-step's end and, where ``v`` changes sign inside it and
    the cubic's extremum beats the peak, with the extremum located on the exact sub-step (secant on
    ``v = 0``; once for the axes that reach it together, as mirrored mounts do)."""
    laws, run = iv.laws, iv.run
    d1 = laws.d0 + e
    now = iv.t0 + iv.done + h
    up, dn = d1 > run.peak_hi, d1 < run.peak_lo
    run.peak_hi[up], run.t_hi[up] = d1[up], now
    run.peak_lo[dn], run.t_lo[dn] = d1[dn], now
    turning = np.flatnonzero(s.v * v < 0)
    if not turning.size:
        return
    scale = max(float(np.abs(run.peak_hi - laws.d0).max()), float(np.abs(run.peak_lo - laws.d0).max()))
    located: list[tuple[float, np.ndarray, np.ndarray]] = []
    for a in turning:
        y0, v0 = laws.d0[a] + s.e[a], s.v[a]
        rising = v0 > 0
        tc = _slope_root(h, y0, v0, d1[a], v[a])
        dc = float(_hermite(tc, h, y0, v0, d1[a], v[a])[0])
        if not (dc > run.peak_hi[a] if rising else dc < run.peak_lo[a]):
            continue
        t_, dm = tc, dc
        if abs(dc - laws.d0[a]) > PEAK_NOISE * scale:
            t_, em = _extremum(iv, s, h, int(a), tc, float(v[a]), located)
            dm = float(laws.d0[a] + em[a])
        if rising and dm > run.peak_hi[a]:
            run.peak_hi[a], run.t_hi[a] = dm, iv.t0 + iv.done + t_
        elif not rising and dm < run.peak_lo[a]:
            run.peak_lo[a], run.t_lo[a] = dm, iv.t0 + iv.done + t_


def _extremum(iv: _Interval, s: _State, h: float, a: int, tc: float, v_end: float, located: list) -> tuple[float, Any]:
    """Where axis ``a``'s velocity vanishes in the sub-step of length ``h`` (secant from the cubic's
    ``tc``, kept in the bracket; ``v_end`` its velocity at the end), and the local deflections there;
    an extremum ``located`` already in this sub-step serves when ``a``'s velocity vanishes there too."""
    d0 = iv.laws.d0[a]
    for t_, em, vm in located:
        if abs(vm[a]) * h <= LOCATE_TOL * abs(d0 + em[a]):
            return t_, em
    ta, tb, fa, fb = 0.0, h, float(s.v[a]), float(v_end)
    t_ = tc
    prev: tuple[float, float] | None = None
    for _ in range(30):                              # secant on v = 0, kept in the bracket
        em, vm = iv.ends(s, t_)
        dm, f = float(d0 + em[a]), float(vm[a])
        at = t_
        if np.sign(f) == np.sign(fb):
            tb, fb = t_, f
        else:
            ta, fa = t_, f
        if abs(f) * (tb - ta) <= LOCATE_TOL * (abs(dm) + 1e-300) or tb - ta <= 1e-14 * iv.h:
            break
        if prev is not None and f != prev[1]:
            nxt = t_ - f * (t_ - prev[0]) / (f - prev[1])
        else:
            nxt = t_ - f * (tb - ta) / (fb - fa) if fb != fa else 0.5 * (ta + tb)
        prev = (t_, f)
        t_ = nxt if ta < nxt < tb else 0.5 * (ta + tb)
    located.append((at, em, vm))
    return at, em


def _slope_root(h: float, y0: float, v0: float, y1: float, v1: float) -> float:
    """Where the cubic Hermite's slope vanishes inside ``(0, h)`` (its slopes at the ends have opposite
    signs: the slope, a quadratic in ``s = t / h``, has exactly one root there; in closed form, the
    stable one of the two formulas)."""
    c2 = 3.0 * (v0 + v1) - 6.0 * (y1 - y0) / h
    c1 = 6.0 * (y1 - y0) / h - 4.0 * v0 - 2.0 * v1
    c0 = v0
    disc = max(c1 * c1 - 4.0 * c2 * c0, 0.0)
    q = -0.5 * (c1 + np.copysign(np.sqrt(disc), c1))
    roots = [r for r in ((q / c2) if c2 != 0 else np.nan, (c0 / q) if q != 0 else np.nan) if 0.0 <= r <= 1.0]
    if not roots:                       # round-off at an end: bisection on the sign
        lo, hi = 0.0, 1.0
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if np.sign((c2 * mid + c1) * mid + c0) == np.sign(v0) else (lo, mid)
        roots = [0.5 * (lo + hi)]
    return float(min(roots) * h)
