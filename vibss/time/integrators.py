"""Classical fixed-step integrators of ``M q'' + C q' + K q = F f(t)`` on a force-input Plant.

These are the textbook structural-dynamics schemes that finite-element packages use. vibss's own
time response is the exact modal first-order hold (:mod:`vibss.time`); the schemes here exist so
the benchmarks (``benchmarks/bench_pareto.py``, ``bench_stability.py``) can measure them against it
and so that :mod:`vibss.stability` has something concrete to predict.

- :func:`newmark` — Newmark average acceleration (``beta = 1/4``, ``gamma = 1/2``, the trapezoidal
  rule): implicit, unconditionally stable, second order, no numerical damping; its only error is a
  period elongation of about ``(omega dt)^2 / 12`` per mode.
- :func:`central_difference` — explicit, second order, stable only for ``dt < 2 / omega_max``
  (undamped; damping lowers the limit slightly). Beyond it the response grows without bound.

Both sample the force at the step times (the force between steps is the scheme's own
interpolation: an edge between samples is smeared, see :func:`vibss.diagnostics.check_sampling`).

Both functions return outputs ``y = Oq q + Ov q' + Oa q'' + Pf f`` at every step. The wrappers
:func:`newmark_method` and :func:`central_difference_method` have the signature of
:data:`vibss.time.METHODS` entries (they take a :class:`vibss.time.SimulationJob`), so they can be
passed to ``simulate(..., method=newmark_method)`` or registered by name.

Examples
--------
>>> import numpy as np
>>> from vibss.linear.plant.plant import Plant
>>> z = np.zeros((1, 1)); one = np.ones((1, 1))
>>> p = Plant(("b.z",), one, z, 100 * one, z, ("f",), ("force",), one, z, z, z, z,
...           ("b.z",), ("m",), one, z, z, z, z, z, z)
>>> t = np.linspace(0.0, 1.0, 1001)
>>> y = newmark(p, t, np.ones((1001, 1)))          # step force 1 N on k = 100 N/m, m = 1 kg
>>> bool(abs(y[-1, 0] - (1 - np.cos(10.0)) / 100) < 1e-4)
True
"""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.linalg as sl

from ..errors import ModelError
from ..linear.solve.mass import mass_solver
from ..linear.eigen.undamped import generalized_eigvals
from ..linear.plant.plant import Plant

__all__ = ["newmark", "central_difference", "newmark_method", "central_difference_method",
           "critical_step", "frequency_error", "ERROR_CONSTANT"]

ERROR_CONSTANT = {"newmark": 1.0 / 12.0, "central_difference": 1.0 / 24.0}
"""Leading coefficient ``c`` of each scheme's relative frequency error ``c (w dt)^2`` (second order):
Newmark average acceleration lengthens every period by ``(w dt)^2 / 12``, central difference
shortens it by ``(w dt)^2 / 24``; neither changes the amplitude of an undamped mode."""


def frequency_error(scheme: str, omega_dt: Any) -> np.ndarray:
    """Exact relative frequency error [-] of an undamped mode integrated at ``w dt`` [rad per step].

    Newmark average acceleration turns ``w`` into ``W`` with ``tan(W dt / 2) = w dt / 2`` (so
    ``1 - W / w = 1 - 2 atan(w dt / 2) / (w dt)``, about ``(w dt)^2 / 12``); central difference into
    ``sin(W dt / 2) = w dt / 2`` (about ``(w dt)^2 / 24``; unstable, ``inf``, from ``w dt = 2``).

    Parameters
    ----------
    scheme : {"newmark", "central_difference"}
        The integrator.
    omega_dt : array_like
        ``w dt`` of each mode [rad].

    Returns
    -------
    ndarray
        ``|1 - W / w|`` (0 at ``w dt = 0``).

    Examples
    --------
    >>> float(frequency_error("newmark", 2 * np.pi / 1.6).round(3))      # 1.6 samples per period
    0.44
    """
    x = np.maximum(np.asarray(omega_dt, float), 1e-300)
    if scheme == "newmark":
        return np.asarray(1.0 - 2.0 * np.arctan(x / 2.0) / x)
    with np.errstate(invalid="ignore"):
        return np.asarray(np.where(x < 2.0, 2.0 * np.arcsin(np.minimum(x / 2.0, 1.0)) / x - 1.0, np.inf))


def _check(plant: Plant, t: np.ndarray, f: np.ndarray) -> tuple[float, np.ndarray]:
    """Validate a force-only plant, a uniform grid and the sampled forces; return (dt, f)."""
    bad = [name for name, kind in zip(plant.inputs, plant.kinds) if kind != "force"]
    if bad:
        raise ModelError(f"integrators: only force inputs are supported; inputs {bad} are prescribed "
                         f"motions (use vibss.time.simulate with method='modal')")
    t = np.asarray(t, float)
    if t.ndim != 1 or t.size < 2:
        raise ModelError(f"integrators: t: expected at least 2 sample times [s], got shape {t.shape}")
    dt = float(t[1] - t[0])
    if not (dt > 0 and np.allclose(np.diff(t), dt, rtol=1e-9, atol=0.0)):
        raise ModelError("integrators: t: the grid must be uniform and increasing")
    f = np.asarray(f, float)
    if f.ndim == 1:
        f = f[:, None]
    if f.shape != (t.size, len(plant.inputs)):
        raise ModelError(f"integrators: f: expected shape ({t.size}, {len(plant.inputs)}) "
                         f"(samples x inputs) [N, N m], got {f.shape}")
    return dt, f


def _outputs(plant: Plant, q: np.ndarray, v: np.ndarray, a: np.ndarray, f: np.ndarray) -> np.ndarray:
    y = q @ np.asarray(plant.Oq).T
    if np.any(plant.Ov):
        y += v @ np.asarray(plant.Ov).T
    if np.any(plant.Oa):
        y += a @ np.asarray(plant.Oa).T
    if np.any(plant.Pf):
        y += f @ np.asarray(plant.Pf).T
    return y


def _start(plant: Plant, q0: Any, v0: Any, g0: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    n = plant.n
    q = np.zeros(n) if q0 is None else np.asarray(q0, float).reshape(n)
    v = np.zeros(n) if v0 is None else np.asarray(v0, float).reshape(n)
    M, C, K = (np.asarray(x, float) for x in (plant.M, plant.C, plant.K))
    a = mass_solver(plant)(g0 - C @ v - K @ q)
    return q, v, a


def critical_step(plant: Plant) -> float:
    """Stability limit ``2 / omega_max`` [s] of the undamped central-difference scheme.

    Parameters
    ----------
    plant : Plant
        The plant (its M and K).

    Returns
    -------
    float
        ``2 / omega_max`` [s]; ``inf`` for a model without stiffness.
    """
    w2 = generalized_eigvals(plant.K, plant.M)
    wmax = float(np.sqrt(max(w2.max(), 0.0)))
    return 2.0 / wmax if wmax > 0 else np.inf


def newmark(plant: Plant, t: np.ndarray, f: np.ndarray, q0: Any = None, v0: Any = None,
            beta: float = 0.25, gamma: float = 0.5) -> np.ndarray:
    """Newmark integration (default: average acceleration, implicit, unconditionally stable).

    Parameters
    ----------
    plant : Plant
        Force-input plant (n DOFs, m force inputs, p outputs).
    t : (ns,) ndarray
        Uniform sample times from 0 [s]; the step is ``t[1] - t[0]``.
    f : (ns, m) array_like
        Input forces at the sample times [N, N m].
    q0, v0 : (n,) array_like or None
        Initial displacements [m, rad] and velocities [m/s, rad/s] (default zero).
    beta, gamma : float
        Newmark parameters (1/4, 1/2: average acceleration).

    Returns
    -------
    (ns, p) ndarray
        Outputs at the sample times.
    """
    dt, f = _check(plant, t, f)
    M, C, K = (np.asarray(x, float) for x in (plant.M, plant.C, plant.K))
    G = f @ np.asarray(plant.F, float).T                 # (ns, n) generalised forces
    q, v, a = _start(plant, q0, v0, G[0])
    keff = K + gamma / (beta * dt) * C + 1.0 / (beta * dt**2) * M
    cho = sl.cho_factor(keff)
    a0, a1, a2 = 1 / (beta * dt**2), 1 / (beta * dt), 1 / (2 * beta) - 1
    c0, c1, c2 = gamma / (beta * dt), gamma / beta - 1, dt * (gamma / (2 * beta) - 1)
    ns, n = len(t), plant.n
    Q, V, A = np.empty((ns, n)), np.empty((ns, n)), np.empty((ns, n))
    Q[0], V[0], A[0] = q, v, a
    for i in range(1, ns):
        rhs = G[i] + M @ (a0 * q + a1 * v + a2 * a) + C @ (c0 * q + c1 * v + c2 * a)
        qn = sl.cho_solve(cho, rhs, check_finite=False)
        an = a0 * (qn - q) - a1 * v - a2 * a
        v = v + dt * ((1 - gamma) * a + gamma * an)
        q, a = qn, an
        Q[i], V[i], A[i] = q, v, a
    return _outputs(plant, Q, V, A, f)


def central_difference(plant: Plant, t: np.ndarray, f: np.ndarray, q0: Any = None,
                       v0: Any = None) -> np.ndarray:
    """Explicit central-difference integration; stable only for ``dt < 2 / omega_max``.

    ``(M/dt^2 + C/(2 dt)) q[i+1] = g[i] - (K - 2 M/dt^2) q[i] - (M/dt^2 - C/(2 dt)) q[i-1]``,
    started with ``q[-1] = q0 - dt v0 + dt^2 a0 / 2``. Check the step first with
    :func:`vibss.diagnostics.check_central_difference`; beyond the limit the result grows like
    ``|lambda|^i`` with ``|lambda| > 1`` (overflow to inf is not caught here).

    Parameters
    ----------
    plant, t, f, q0, v0
        As :func:`newmark`.

    Returns
    -------
    (ns, p) ndarray
        Outputs at the sample times.
    """
    dt, f = _check(plant, t, f)
    M, C, K = (np.asarray(x, float) for x in (plant.M, plant.C, plant.K))
    G = f @ np.asarray(plant.F, float).T
    q, v, a = _start(plant, q0, v0, G[0])
    lhs = M / dt**2 + C / (2 * dt)
    cho = sl.cho_factor(lhs)
    k2 = K - 2 * M / dt**2
    m2 = M / dt**2 - C / (2 * dt)
    ns, n = len(t), plant.n
    Q = np.empty((ns + 2, n))                # q[-1], q[0], ..., q[ns]
    Q[0] = q - dt * v + dt**2 / 2 * a
    Q[1] = q
    with np.errstate(over="ignore", invalid="ignore"):
        for i in range(1, ns + 1):
            Q[i + 1] = sl.cho_solve(cho, G[i - 1] - k2 @ Q[i] - m2 @ Q[i - 1], check_finite=False)
        V = (Q[2:] - Q[:-2]) / (2 * dt)
        A = (Q[2:] - 2 * Q[1:-1] + Q[:-2]) / dt**2
        return _outputs(plant, Q[1:-1], V, A, f)


def _job_forces(job: Any) -> np.ndarray:
    t = job.time
    if not job.funcs:
        return np.zeros((len(t), 0))
    return np.column_stack([np.broadcast_to(fn(t), t.shape) for fn in job.funcs]).astype(float)


def newmark_method(job: Any) -> tuple[np.ndarray, str]:
    """:data:`vibss.time.METHODS`-style wrapper of :func:`newmark`.

    Parameters
    ----------
    job : vibss.time.SimulationJob
        Uses ``plant`` (force inputs only), ``time`` (uniform, the step), ``funcs`` (sampled at
        ``time``), ``q0``, ``v0``.

    Returns
    -------
    y : (ns, p) ndarray
        Outputs at ``job.time``.
    note : str
        How it ran.
    """
    y = newmark(job.plant, job.time, _job_forces(job), job.q0, job.v0)
    return y, f"Newmark average acceleration, fixed step {job.time[1] - job.time[0]:g} s, forces sampled"


def central_difference_method(job: Any) -> tuple[np.ndarray, str]:
    """:data:`vibss.time.METHODS`-style wrapper of :func:`central_difference`.

    Parameters
    ----------
    job : vibss.time.SimulationJob
        As :func:`newmark_method`. The step must be below ``2 / omega_max``
        (:func:`vibss.diagnostics.check_central_difference`).

    Returns
    -------
    y : (ns, p) ndarray
        Outputs at ``job.time``.
    note : str
        How it ran.
    """
    y = central_difference(job.plant, job.time, _job_forces(job), job.q0, job.v0)
    return y, f"explicit central difference, fixed step {job.time[1] - job.time[0]:g} s, forces sampled"
