"""The harmonic-balance equations and their pseudo-arclength continuation in frequency.

The equations on the stacked real coefficients ``X`` of the local deflections (:mod:`.aft`) are

    R(X, omega) = X - U(omega) + G(omega) F(X) = 0,

``G`` the condensed compliance, ``U`` the local linear response to the inputs and ``F`` the AFT
coefficients of the forces beyond the tangent (:mod:`.condensed`). ``dR/dX = I + G dF/dX``;
``dR/domega`` is a forward difference (only the linear part depends on ``omega``).

The branch is followed in the scaled unknowns ``v = (X / x_s, omega / w_s)`` (``x_s`` the largest
linear local amplitude, ``w_s`` the frequency range) by Keller's pseudo-arclength method: an Euler
predictor along the unit tangent, a Newton corrector on the plane normal to it, step halving when
the corrector fails or the chord turns from the tangent by more than :data:`MAX_TURN`, growth after easy steps.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from ...errors import AnalysisError
from .aft import Basis, LocalLaws, aft, to_real
from .condensed import Condensed

__all__ = ["Problem", "Branch", "follow", "NEWTON_TOL", "RESIDUAL_TOL", "MAX_TURN"]

NEWTON_TOL = 1e-11
"""Newton's corrector stops when its step and the residual are below this, relative to ``x_s``."""

MAX_TURN = 0.5
"""Largest angle [rad] between the predictor's tangent and the chord to the corrected point before
the step is halved (so the predictor cannot jump onto another part of the branch at a fold). The
chord, not the next tangent: a stop's kink makes the sampled Jacobian, and so the tangent, jump
where a time sample crosses the clearance."""

RESIDUAL_TOL = 1e-12
"""... or when the residual is below this, relative to ``x_s`` (a stop's kink can make Newton's step
alternate between two pieces of the sampled law while the residual is already at round-off)."""

_MAX_NEWTON = 12
_DOMEGA = 1e-7          # relative forward-difference step in omega


@dataclass(frozen=True, eq=False)
class Problem:
    """One harmonic-balance problem: the condensed linear part, the local laws and the AFT basis."""

    linear: Condensed
    laws: LocalLaws
    basis: Basis

    @property
    def size(self) -> int:
        return self.basis.size * self.linear.m

    def residual(self, X: np.ndarray, omega: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``R`` ((2H+1) m,) [m], ``dR/dX`` and ``dR/domega`` [m s/rad] at ``(X, omega)``."""
        F, gamma, _ = aft(self.laws, self.basis, X)
        assert gamma is not None
        h = _DOMEGA * omega
        lin = self.linear.at(omega, pair=omega + h)
        R = self.equations(X, F, omega)
        dw = (self.equations(X, F, omega + h) - R) / h
        J = lin.times(gamma)
        J[np.diag_indices_from(J)] += 1.0
        return R, J, dw

    def equations(self, X: np.ndarray, F: np.ndarray, omega: float) -> np.ndarray:
        """``R = X - U + G F`` [m] for the force coefficients ``F`` of ``X`` at ``omega`` [rad/s]."""
        lin = self.linear.at(omega)
        U = np.zeros((self.basis.harmonics + 1, self.linear.m), dtype=complex)
        U[1] = lin.U
        return X - to_real(U) + lin.apply(F)

    def start(self, omega: float) -> np.ndarray:
        """The linear solution at ``omega``: the first guess of Newton's method."""
        U = np.zeros((self.basis.harmonics + 1, self.linear.m), dtype=complex)
        U[1] = self.linear.at(omega).U
        return to_real(U)

    def solve(self, X: np.ndarray, omega: float, scale: float) -> tuple[np.ndarray, bool]:
        """Newton's method at fixed ``omega`` from ``X``, its steps halved while they do not reduce
        the residual; returns the solution and whether it converged."""
        last, dX, alpha = np.inf, np.zeros_like(X), 1.0
        for it in range(4 * _MAX_NEWTON):
            R, J, _ = self.residual(X, omega)
            size = float(np.linalg.norm(R))
            if it and size <= RESIDUAL_TOL * scale:
                return X, True
            if size > last and alpha > 1 / 64:
                alpha /= 2
                X = X - alpha * dX
                continue
            dX = np.linalg.solve(J, -R)
            X, last, alpha = X + dX, size, 1.0
            if np.linalg.norm(dX) <= NEWTON_TOL * scale:
                return X, True
        return X, False

    def first(self, omega: float, scale: float) -> tuple[np.ndarray, bool]:
        """The solution at ``omega`` from the linear one: Newton directly, else by pseudo-arclength
        continuation in the inputs' level ``lambda`` from 0 (where ``X = 0``) to 1, through the folds
        a strongly nonlinear response has in its amplitude."""
        X, ok = self.solve(self.start(omega), omega, scale)
        if ok:
            return X, True
        U = self.start(omega) / scale

        def in_level(w: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
            R, J, _ = self.residual(scale * w[:-1], omega)
            return R / scale + (1.0 - w[-1]) * U, J, -U

        v = np.zeros(X.size + 1)
        e = np.zeros(X.size + 1)
        e[-1] = 1.0
        R, J, dp = in_level(v)                       # type: ignore[misc]
        t, ds = _tangent(J, dp, e), 0.05
        for _ in range(400):
            step = _corrected(in_level, v, t, ds)
            if step is None:
                ds /= 2
                if ds < 1e-6:
                    break
                continue
            v_new, t, iters = step
            if v_new[-1] >= 1.0:
                frac = (1.0 - v[-1]) / (v_new[-1] - v[-1])
                return self.solve(scale * (v[:-1] + frac * (v_new[:-1] - v[:-1])), omega, scale)
            v, ds = v_new, min(ds * 1.5, 0.2) if iters <= 4 else ds
        return scale * v[:-1], False


@dataclass
class Branch:
    """Points along the branch: frequency [rad/s], coefficients, and the tangent's omega part."""

    omega: list[float] = field(default_factory=list)
    X: list[np.ndarray] = field(default_factory=list)
    path: list[float] = field(default_factory=list)      # omega of every continuation point
    slope: list[float] = field(default_factory=list)     # their d omega / d s (sign changes at folds)
    near: list[int] = field(default_factory=list)        # the last recorded point at each
    arc: list[float] = field(default_factory=list)       # their arclength in the scaled unknowns
    scale: float = 1.0                                   # w_s [rad/s]: omega = w_s * scaled omega
    steps: int = 0
    rejected: int = 0
    complete: bool = True


def _bordered(J: np.ndarray, dp: np.ndarray, t: np.ndarray) -> np.ndarray:
    """``[[J, dp], [t^T]]``: the Jacobian bordered by the parameter's column and the direction's row."""
    n = J.shape[0]
    A = np.empty((n + 1, n + 1))
    A[:n, :n] = J
    A[:n, n] = dp
    A[n] = t
    return A


def _tangent(J: np.ndarray, dw: np.ndarray, prev: np.ndarray) -> np.ndarray:
    rhs = np.zeros(J.shape[0] + 1)
    rhs[-1] = 1.0
    t = np.linalg.solve(_bordered(J, dw, prev), rhs)
    return t / np.linalg.norm(t)


def follow(problem: Problem, w0: float, w1: float, points: int, targets: Sequence[float] | None,
           max_steps: int) -> Branch:
    """Follow the branch from ``w0`` to ``w1`` [rad/s].

    ``targets`` None records every continuation point (the last one at ``w1`` exactly); else the
    branch's crossings of each target frequency [rad/s] (Newton at fixed frequency from the
    interpolated neighbours), every crossing, so a frequency with three solutions gives three points.
    """
    xs = max(float(np.max(np.abs(problem.start(w))) if problem.size else 0.0)
             for w in np.linspace(w0, w1, 41)) or 1.0
    ws = w1 - w0
    X, ok = problem.first(w0, xs)
    if not ok:
        raise AnalysisError(f"harmonic_balance: Newton's method did not converge at the first frequency "
                            f"{w0 / (2 * np.pi):.6g} Hz; start the range where the response is nearly linear")
    out = Branch()
    R, J, dw = problem.residual(X, w0)
    e = np.zeros(X.size + 1)
    e[-1] = 1.0
    t = _tangent(J, dw * ws / xs, e)
    targets_left = None if targets is None else sorted(targets)
    out.scale = ws
    _record(out, w0, X)
    _walk(out, w0, t[-1], 0.0)
    if targets_left is not None:
        targets_left = [f for f in targets_left if f > w0 * (1 + 1e-14)]
    def in_frequency(w: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
        if w[-1] <= 0:
            return None
        R, J, dw = problem.residual(xs * w[:-1], w[-1] * ws)
        return R / xs, J, dw * ws / xs

    ds0 = np.sqrt(2.0) / points
    ds, ds_min, ds_max = ds0, ds0 * 1e-4, 2 * ds0
    v = np.append(X / xs, w0 / ws)
    while out.steps < max_steps:
        out.steps += 1
        step = _corrected(in_frequency, v, t, ds)
        if step is None:
            out.rejected += 1
            ds /= 2
            if ds < ds_min:
                raise AnalysisError(f"harmonic_balance: continuation stalled near "
                                    f"{v[-1] * ws / (2 * np.pi):.6g} Hz (step below {ds_min:.1e})")
            continue
        v_new, t_new, iters = step
        chord = (v_new - v) / np.linalg.norm(v_new - v)
        if float(chord @ t) < np.cos(MAX_TURN) and ds > ds_min * 4:
            out.rejected += 1
            ds /= 2
            continue
        wa, wb = v[-1] * ws, v_new[-1] * ws
        if targets_left is not None:
            _crossings(problem, out, targets_left, v, v_new, wa, wb, xs, ws)
        elif wb >= w1:
            frac = (w1 - wa) / (wb - wa)
            Xe, ok = problem.solve(xs * (v[:-1] + frac * (v_new[:-1] - v[:-1])), w1, xs)
            _record(out, w1, Xe if ok else xs * v_new[:-1])
        else:
            _record(out, wb, xs * v_new[:-1])
        _walk(out, wb, t_new[-1], out.arc[-1] + float(np.linalg.norm(v_new - v)))
        v, t = v_new, t_new
        if wb >= w1 or wb < w0 - 0.05 * ws:
            return out
        ds = min(ds * 1.5, ds_max) if iters <= 4 else ds if iters <= 8 else ds / 2
    out.complete = False
    return out


def _record(out: Branch, omega: float, X: np.ndarray) -> None:
    out.omega.append(float(omega))
    out.X.append(X)


def _walk(out: Branch, omega: float, slope: float, arc: float) -> None:
    out.arc.append(arc)
    out.path.append(float(omega))
    out.slope.append(float(slope))
    out.near.append(len(out.omega) - 1)


def _crossings(problem: Problem, out: Branch, targets: list[float], v: np.ndarray, v_new: np.ndarray,
               wa: float, wb: float, xs: float, ws: float) -> None:
    """Record the branch's solution at every target frequency between ``wa`` and ``wb`` [rad/s]
    (either direction: a target on a part of the branch that runs backwards is recorded too)."""
    lo, hi = min(wa, wb), max(wa, wb)
    for f in targets:
        if lo < f <= hi:
            frac = (f - wa) / (wb - wa)
            X, ok = problem.solve(xs * (v[:-1] + frac * (v_new[:-1] - v[:-1])), f, xs)
            if not ok:
                raise AnalysisError(f"harmonic_balance: Newton's method did not converge at "
                                    f"{f / (2 * np.pi):.6g} Hz on the branch")
            _record(out, f, X)


def _corrected(fun: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray, np.ndarray] | None], v: np.ndarray,
               t: np.ndarray, ds: float) -> tuple[np.ndarray, np.ndarray, int] | None:
    """Predictor-corrector step of length ``ds`` on scaled unknowns ``v`` (the parameter last): the new
    point, its tangent and Newton's iterations (None when the corrector fails). ``fun(v)`` gives the
    scaled residual, its Jacobian in the unknowns and its derivative in the parameter (None where
    the parameter is out of range).

    Newton's steps are halved while they do not reduce the residual (a stop's kink makes the
    sampled equations piecewise smooth, and a full step can alternate between two pieces).
    """
    pred = v + ds * t
    w, small = pred.copy(), False
    last, dv, alpha = np.inf, np.zeros_like(v), 1.0
    for it in range(1, 2 * _MAX_NEWTON + 2):
        got = fun(w)
        if got is None:
            return None
        R, J, dp = got
        size = float(np.hypot(np.linalg.norm(R), t @ (w - pred)))
        if small or (it > 1 and np.linalg.norm(R) <= RESIDUAL_TOL):
            return w, _tangent(J, dp, t), it - 1
        if size > last and alpha > 1 / 16:          # no progress: go back and take half the step
            alpha /= 2
            w = w - alpha * dv
            continue
        b = -np.append(R, t @ (w - pred))
        try:
            dv = np.linalg.solve(_bordered(J, dp, t), b)
        except np.linalg.LinAlgError:
            return None
        w, last, alpha = w + dv, size, 1.0
        small = bool(np.linalg.norm(dv) <= NEWTON_TOL)
    return None
