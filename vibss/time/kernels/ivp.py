"""The ``ivp`` method: ``scipy.integrate.solve_ivp`` of the z-only realization, restarted at every
breakpoint of the inputs."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, cast

import numpy as np

from ...errors import AnalysisError
from .grid import nudge
from .prepared import Prepared
from .realization import realization

__all__ = ["run_ivp"]


def run_ivp(prep: Prepared, funcs: list[Callable[[np.ndarray], np.ndarray]], edges: np.ndarray,
            ts: np.ndarray, q0: np.ndarray, v0: np.ndarray, *, rtol: float, atol: float | None,
            solver: str) -> tuple[np.ndarray, str]:
    """``scipy.integrate.solve_ivp`` piece by piece between ``edges`` [s].

    Parameters
    ----------
    funcs : list of callable
        The input signals ``u_j(t)`` (vectorised).
    edges : (k,) ndarray
        Breakpoints inside the run; the integration restarts on each.
    ts : (ns,) ndarray
        Sample times [s] (0 .. t_end).
    """
    from scipy.integrate import solve_ivp

    r = realization(prep)
    plant = prep.plant
    n = plant.n
    ns = r.A.shape[0]
    dt = ts[1] - ts[0]
    x = np.zeros(ns)
    x[:n], x[n:2 * n] = q0, v0
    scale = max(np.abs(x).max(), 1e-300)
    atol_ = atol if atol is not None else 1e-12 * scale if np.any(x) else 1e-15

    u_of_t = cast("list[Callable[[float | np.ndarray], np.ndarray]]", funcs)  # u(t) takes a scalar t too

    def inputs(t: float | np.ndarray) -> np.ndarray:
        return np.array([np.asarray(fn(t), float) for fn in u_of_t])

    cuts = np.concatenate([[0.0], np.sort(edges[(edges > 0) & (edges < ts[-1])]), [ts[-1]]])
    X = np.zeros((len(ts), ns))
    X[0] = x
    A, B = r.A, r.B
    # rigid bodies: M is block-diagonal (6 x 6 per body) and K, C follow the mounts' connectivity, so
    # A = [[0, I], [-M^-1 K, -M^-1 C]] is sparse; a sparse Jacobian lets Radau/BDF factorise it with
    # SuperLU instead of dense LU of the whole state
    jac: Any = A
    if ns > 60 and np.count_nonzero(A) < 0.2 * A.size:
        import scipy.sparse as sps

        jac = sps.csc_matrix(A)
    nfev = 0
    for a, b in zip(cuts[:-1], cuts[1:]):
        lo, hi = a + nudge(a, dt), b - nudge(b, dt)

        def rhs(t: float, x: np.ndarray, lo: float = lo, hi: float = hi) -> np.ndarray:
            return A @ x + B @ inputs(min(max(t, lo), hi))

        inside = np.flatnonzero((ts > a) & (ts <= b))
        t_eval = ts[inside] if inside.size and ts[inside[-1]] == b else np.append(ts[inside], b)
        sol = solve_ivp(rhs, (a, b), x, method=solver, t_eval=t_eval, rtol=rtol, atol=atol_,
                        **({"jac": jac if solver != "LSODA" else A} if solver in ("Radau", "BDF", "LSODA") else {}))
        if not sol.success:
            raise AnalysisError(f"solve_ivp ({solver}) failed on [{a:g}, {b:g}] s: {sol.message}")
        nfev += sol.nfev
        X[inside] = sol.y.T[:inside.size]
        x = sol.y[:, -1]
    # inputs and their one-sided derivatives at the samples (right limits, left at the end)
    tr = ts + nudge(ts, dt)
    tr[-1] = ts[-1] - nudge(ts[-1], dt)
    U = inputs(tr).T
    y = X @ r.C.T + U @ r.D.T
    if np.any(r.post1) or np.any(r.post2):
        dU = _derivative(inputs, tr, ts)
        y += dU @ (r.post1 + r.post2).T
    return y, f"scipy solve_ivp ({solver}, rtol={rtol:g}, atol={atol_:g}), {len(cuts) - 1} pieces, {nfev} evaluations"


def _derivative(inputs: Callable[[Any], np.ndarray], tr: np.ndarray, ts: np.ndarray) -> np.ndarray:
    """(ns, m) one-sided second-order finite-difference derivative of the inputs."""
    span = max(ts[-1], 1e-300)
    d = 1e-6 * span
    sign = np.where(np.arange(len(tr)) == len(tr) - 1, -1.0, 1.0)
    u0 = inputs(tr).T
    u1 = inputs(tr + sign * d).T
    u2 = inputs(tr + 2 * sign * d).T
    return (-3 * u0 + 4 * u1 - u2) / (2 * d) * sign[:, None]
