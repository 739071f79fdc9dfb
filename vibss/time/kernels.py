"""Numerical methods of the time response (:mod:`vibss.time`): input kinematics, modal exact-FOH
recursion, the z-only state-space realization, and the ``forced_response`` / ``solve_ivp`` paths.

Formulation shared by every method
----------------------------------
The plant (:class:`vibss.linear.plant.plant.Plant`) is ``M q'' + C q' + K q = F f - (Kz z + Cz z' + Mz z'')``
with outputs ``y = Oq q + Ov q' + Oa q'' + Pz z + Pv z' + Pa z'' + Pf f``. The mass coupling to the
prescribed coordinates is removed by the substitution ``p = q + G z`` with ``G = M^-1 Mz``:

    M p'' + C p' + K p = F f - Kt z - Ct z',   Kt = Kz - K G,  Ct = Cz - C G,

so that no input is ever differentiated twice. The outputs become

    y = Cp p + Cv p' + D0 z + D1 z' + D2 z'' + Df f,
    Cp = Oq - Oa M^-1 K,  Cv = Ov - Oa M^-1 C,
    D0 = Pz - Cp G - Oa M^-1 Kz,  D1 = Pv - Cv G - Oa M^-1 Cz,  D2 = Pa - Oa M^-1 Mz,
    Df = Pf + Oa M^-1 F.

Initial conditions are the state at ``t = 0-``, with every prescribed coordinate at rest at zero;
an input that is nonzero at ``t = 0`` acts as a jump at ``t = 0``. A jump of a prescribed
*displacement* through a damper is an impulse (``p'`` jumps by ``-M^-1 Ct dz``); the modal method
applies it exactly, and in the z-only realization (``xi = p' + M^-1 Ct z``) the state does not jump
at all. At a sample time where an input jumps or kinks, outputs take the right-hand limit (the
left-hand limit at the last sample).
"""

from __future__ import annotations

from collections.abc import Callable
import contextlib
import dataclasses
import threading
from collections.abc import Iterator
from dataclasses import dataclass, fields
from typing import Any, cast

import numpy as np
import scipy.linalg as sl
from threadpoolctl import ThreadpoolController

from ..linear.eigen.complex_modes import complex_modes
from ..errors import AnalysisError
from ..linear.eigen.undamped import damping_coupling, modal_basis, symmetric_eigen
from ..linear.eigen.checks import _six_blocks
from ..linear.plant.branches import mechanical, require_none
from ..linear.plant.plant import Plant
from ..linear.eigen.projection import projected_damping
from .phi import cs_blocks, foh_blocks
from .recursion import LowRank, scan

__all__ = ["Prepared", "Grid", "Kinematics", "prepare", "make_grid", "nudge", "kinematics",
           "run_modal", "run_forced_response", "run_ivp", "realization"]

DEGREE = {"force": 1, "displacement": 1, "velocity": 2, "acceleration": 3}
"""Polynomial degree (per interval) of the prescribed coordinate (or force) for a PWL input."""

CHUNK = 1024
"""Time steps per chunk of the modal recursion where the forcing of each step is formed first (steps
of several lengths, or input jumps, in the chunk)."""

LOWRANK_CHUNK = 16384
"""Time steps per chunk of the modal recursion where every step has one length and no jump: the
forcing is passed as its factors (:class:`~vibss.time.recursion.LowRank`), so a chunk keeps only
``sqrt(steps)`` states per mode."""

_BLAS_LOCK = threading.Lock()
_blas_users = 0
_blas_limiter: Any = None
_blas_controller: Any = None


def _controller() -> Any:
    """The process's BLAS thread pools, found once: ``threadpool_limits`` scans the loaded libraries
    on every call (about 2 ms, most of a 1,000-step run of a small model)."""
    global _blas_controller
    if _blas_controller is None:
        _blas_controller = ThreadpoolController()
    return _blas_controller


@contextlib.contextmanager
def one_blas_thread() -> Iterator[None]:
    """BLAS on one thread for the many small products of a time run, safe from several threads.

    ``threadpoolctl.threadpool_limits`` changes a process-wide setting and restores what it saw on
    entry: two threads entering and leaving in turn left the process on one BLAS thread for good
    (issue 18: 8 threads of ``simulate`` once, and every later analysis in the process ran
    single-threaded). Here the first user sets the limit and the last one restores it. While any
    time run holds it, BLAS runs on one thread in every thread of the process.
    """
    global _blas_users, _blas_limiter
    with _BLAS_LOCK:
        if _blas_users == 0:
            # what threadpoolctl's limit(limits=1) does, without its report of every library (about
            # 45 us, 3 % of a small model's run): each pool not on one thread is set to one, and put back
            _blas_limiter = [(lib, lib.num_threads) for lib in _controller().lib_controllers]
            for lib, threads in _blas_limiter:
                if threads != 1:
                    lib.set_num_threads(1)
        _blas_users += 1
    try:
        yield
    finally:
        with _BLAS_LOCK:
            _blas_users -= 1
            if _blas_users == 0:
                for lib, threads in _blas_limiter:
                    if threads != 1:
                        lib.set_num_threads(threads)
                _blas_limiter = None


@dataclass(frozen=True, eq=False)
class Prepared:
    """Plant after the substitution ``p = q + G z`` (see the module docstring); SI, n DOFs, m inputs."""

    plant: Plant
    G: np.ndarray     # (n, m)
    Kt: np.ndarray    # (n, m)
    Ct: np.ndarray    # (n, m)
    Cp: np.ndarray    # (p, n)
    Cv: np.ndarray    # (p, n)
    D0: np.ndarray    # (p, m) per z
    D1: np.ndarray    # (p, m) per z'
    D2: np.ndarray    # (p, m) per z''
    Df: np.ndarray    # (p, m) per f
    force: np.ndarray  # (m,) bool
    kinds: tuple[str, ...]


def prepare(plant: Plant) -> Prepared:
    """Substituted matrices of ``plant`` (see the module docstring); computed once per plant (the
    plant is frozen), its arrays read-only."""
    return cast(Prepared, plant.cached("prepared", lambda: _prepare(plant)))


def _prepare(plant: Plant) -> Prepared:
    M = np.asarray(plant.M, float)
    blocks = _six_blocks(M) if M.shape[0] > 150 else None
    if blocks is not None:       # rigid bodies: M^-1 by the 6x6 blocks' Cholesky factors
        lib = np.linalg.inv(np.linalg.cholesky(blocks))
        lit = np.ascontiguousarray(np.swapaxes(lib, 1, 2))
        inv = lambda X: np.matmul(lit, np.matmul(lib, np.asarray(X, float).reshape(lib.shape[0], 6, -1))  # noqa: E731
                                  ).reshape(np.shape(X))
    else:
        cho = sl.cho_factor(M)
        inv = lambda X: sl.cho_solve(cho, np.asarray(X, float))  # noqa: E731
    motion = np.array([k != "force" for k in plant.kinds])
    G = inv(plant.Mz) * motion
    K, C = np.asarray(plant.K, float), np.asarray(plant.C, float)
    Kt = plant.Kz - K @ G
    Ct = plant.Cz - C @ G
    Oa = np.asarray(plant.Oa, float)
    has_oa = bool(np.any(Oa))
    OaMi = inv(Oa.T).T if has_oa else np.zeros_like(Oa)
    Cp = plant.Oq - OaMi @ K
    Cv = plant.Ov - OaMi @ C
    out = Prepared(
        plant=plant, G=G, Kt=Kt, Ct=Ct, Cp=Cp, Cv=Cv,
        D0=plant.Pz - Cp @ G - OaMi @ plant.Kz,
        D1=plant.Pv - Cv @ G - OaMi @ plant.Cz,
        D2=plant.Pa - OaMi @ plant.Mz,
        Df=plant.Pf + OaMi @ plant.F,
        force=~motion, kinds=tuple(plant.kinds))
    for f in fields(out):
        value = getattr(out, f.name)
        if isinstance(value, np.ndarray):
            value.flags.writeable = False
    return out


@dataclass(frozen=True, eq=False)
class Grid:
    """Simulation grid: the sample grid ``k dt`` merged with the inputs' breakpoints.

    Attributes
    ----------
    t : (ng,) ndarray
        Grid times [s], from 0 to the last sample.
    h : (ng - 1,) ndarray
        Step lengths [s].
    hkey : (ng - 1,) int ndarray
        Index of each step into ``steps`` (the distinct step lengths).
    steps : (nh,) ndarray
        Distinct step lengths [s].
    samples : (ns,) int ndarray
        Grid index of every sample ``k dt``.
    """

    t: np.ndarray
    h: np.ndarray
    hkey: np.ndarray
    steps: np.ndarray
    samples: np.ndarray


def nudge(t: np.ndarray, dt: float) -> np.ndarray:
    """(len(t),) offsets [s] at which inputs are evaluated for their right/left limits at ``t``.

    A few ulps are not enough: a function's own rounding (e.g. ``(t - start) / duration < 1``)
    can put its edge a few ulps away from its breakpoint; 1e-10 dt is far below any step.
    """
    return np.maximum(1e-10 * dt, 64 * np.spacing(np.abs(np.asarray(t, float)) + dt))


def make_grid(n_samples: int, dt: float, breakpoints: np.ndarray) -> Grid:
    """Grid of ``n_samples`` samples ``k dt`` plus the breakpoints strictly inside [s]."""
    ts = dt * np.arange(n_samples)
    t_last = ts[-1]
    bp = np.unique(np.asarray(breakpoints, float))
    bp = bp[(bp > 0) & (bp < t_last)]
    if bp.size:
        k = np.rint(bp / dt)
        bp = bp[np.abs(bp - k * dt) > 1e-9 * dt]  # on a sample already
    if bp.size:
        t = np.union1d(ts, bp)
        samples = np.searchsorted(t, ts)
    else:                   # the samples alone (increasing, so union1d would give them back)
        t, samples = ts, np.arange(n_samples)
    h = np.diff(t)
    # full sample steps are exactly dt (``diff(k dt)`` jitters by a few 1e-13 dt: before, that made a
    # second and third step "length" of dt (1 +- 1e-12) and half the steps irregular for the
    # recursion); split steps are at least 1e-9 dt away from dt and grouped to 1e-12 dt
    rel = np.rint(h / dt * 1e12).astype(np.int64)
    rel[np.abs(rel - 10**12) < 1000] = 10**12
    keys, hkey = np.unique(rel, return_inverse=True)
    steps = keys * (dt / 1e12)
    steps[keys == 10**12] = dt
    return Grid(t=t, h=h, hkey=hkey.reshape(-1), steps=steps, samples=samples)


@dataclass(frozen=True, eq=False)
class Kinematics:
    """Piecewise-polynomial input kinematics on a grid.

    Attributes
    ----------
    coef : (ng - 1, 4, m) ndarray
        Taylor coefficients of the prescribed coordinate ``z`` (or of the force ``f``) at the start
        of each interval: ``z(t_i + tau) = sum_k coef[i, k] tau^k / k!``.
    jump : (ng - 1, m) ndarray
        Jump of a displacement input at the start of each interval (impulse through ``Ct``).
    z, z1, z2, f : (ng, m) ndarray
        z, z', z'' of motion inputs and f of force inputs at the grid points (right-hand limits;
        left-hand at the last point).
    u : (ng, m) ndarray
        The input signals themselves at the grid points (same convention).
    osc : tuple of (float, ndarray)
        Sine/cosine parts: ``(omega, amp)`` with ``amp`` (ng - 1, 2, m) the amplitudes of
        ``cos(omega tau)`` and ``sin(omega tau)`` in ``z`` (or ``f``) on each interval, ``tau`` from its
        start [rad/s; unit of z or f]. ``coef`` holds the rest.
    """

    coef: np.ndarray
    jump: np.ndarray
    z: np.ndarray
    z1: np.ndarray
    z2: np.ndarray
    f: np.ndarray
    u: np.ndarray
    osc: tuple[tuple[float, np.ndarray], ...] = ()


def kinematics(grid: Grid, u_right: np.ndarray, u_left: np.ndarray, kinds: tuple[str, ...],
               sinusoids: tuple[tuple[Any, ...], ...] | None = None,
               offsets: np.ndarray | None = None) -> Kinematics:
    """Exact kinematics of inputs that are piecewise linear once their sine/cosine pieces are removed.

    Parameters
    ----------
    grid : Grid
    u_right, u_left : (ng, m) ndarray
        Right- and left-hand values of each input at the grid points (``u_left[0]`` is ignored:
        inputs are zero before ``t = 0``).
    kinds : tuple of str
        Input kind per column.
    sinusoids : tuple (one per input) of tuples of Sinusoid, optional
        Sine/cosine pieces of each input (:attr:`vibss.model.timefunctions.TimeFunction.sinusoids`):
        taken out of the samples and carried exactly (:attr:`Kinematics.osc`). A piece whose window
        does not start on the grid at ``t >= 0`` is left in the samples.
    offsets : (ng,) ndarray, optional
        The offsets [s] at which ``u_right`` / ``u_left`` were evaluated (:func:`nudge`); needed
        with ``sinusoids``.
    """
    if not sinusoids or not any(sinusoids):
        return _pwl_kinematics(grid, u_right, u_left, kinds)
    t = grid.t
    tol = 1e-9 * float(np.min(grid.h)) if grid.h.size else 0.0
    off = np.zeros_like(t) if offsets is None else np.asarray(offsets, float)
    u_right, u_left = np.array(u_right, float), np.array(u_left, float)
    kept: list[tuple[int, Any]] = []
    for j, pieces in enumerate(sinusoids):
        for p in pieces:
            on_grid = lambda x: not np.isfinite(x) or x >= t[-1] or bool(np.min(np.abs(t - x)) <= tol)  # noqa: E731
            if p.t0 < 0 or not on_grid(p.t0) or not on_grid(p.t1) or not p.omega > 0:
                continue
            u_right[:, j] -= p.value(t + off)
            u_left[:, j] -= p.value(t - off)
            kept.append((j, p))
    kin = _pwl_kinematics(grid, u_right, u_left, kinds)
    osc: dict[float, np.ndarray] = {}
    for j, p in kept:
        _add_sinusoid(kin, osc, grid, tol, j, kinds[j], p)
    return dataclasses.replace(kin, osc=tuple(osc.items()))


def _add_sinusoid(kin: Kinematics, osc: dict[float, np.ndarray], grid: Grid, tol: float, j: int, kind: str,
                  p: Any) -> None:
    """Add one sine/cosine piece of input ``j`` to the kinematics in place (see :func:`kinematics`).

    In window time ``tau = t - t0`` the piece ``u = a cos(w tau) + b sin(w tau)`` makes the coordinate
    ``z = c0 + c1 tau + Ac cos(w tau) + As sin(w tau)`` (a force or displacement: ``z = u``; a
    velocity: ``z`` its integral from 0; an acceleration: its double integral); after the window
    ``z`` goes on as the polynomial it left with.
    """
    w, a, b = float(p.omega), float(p.a), float(p.b)
    if kind in ("force", "displacement"):
        ac, as_, c0, c1 = a, b, 0.0, 0.0
    elif kind == "velocity":
        ac, as_, c0, c1 = -b / w, a / w, b / w, 0.0
    else:
        ac, as_, c0, c1 = -a / w ** 2, -b / w ** 2, a / w ** 2, b / w

    def z(tau: np.ndarray) -> np.ndarray:
        return c0 + c1 * tau + ac * np.cos(w * tau) + as_ * np.sin(w * tau)

    def z1(tau: np.ndarray) -> np.ndarray:
        return c1 + w * (as_ * np.cos(w * tau) - ac * np.sin(w * tau))

    def z2(tau: np.ndarray) -> np.ndarray:
        return -w * w * (ac * np.cos(w * tau) + as_ * np.sin(w * tau))

    t = grid.t
    t0, t1 = float(p.t0), float(p.t1)
    span = t1 - t0
    ti = t[:-1]
    inside = (ti >= t0 - tol) & (ti < t1 - tol)
    after = ti >= t1 - tol
    tau = np.maximum(ti - t0, 0.0)
    amp = osc.setdefault(w, np.zeros((len(ti), 2, kin.coef.shape[2])))
    ci, si = np.cos(w * tau[inside]), np.sin(w * tau[inside])
    amp[inside, 0, j] += ac * ci + as_ * si
    amp[inside, 1, j] += as_ * ci - ac * si
    kin.coef[inside, 0, j] += c0 + c1 * tau[inside]
    kin.coef[inside, 1, j] += c1
    end_z = end_v = 0.0
    if np.isfinite(t1) and kind in ("velocity", "acceleration"):
        end_z = float(z(np.array(span)))
        end_v = float(z1(np.array(span))) if kind == "acceleration" else 0.0
        kin.coef[after, 0, j] += end_z + end_v * (ti[after] - t1)
        kin.coef[after, 1, j] += end_v
    # values at the grid points: right-hand limits, the left-hand one at the last point
    right = np.concatenate([(ti >= t0 - tol) & (ti < t1 - tol), [t[-1] > t0 + tol and t[-1] <= t1 + tol]])
    post = np.concatenate([after, [t[-1] > t1 + tol]])
    tp = np.clip(t - t0, 0.0, span if np.isfinite(span) else None)
    piece = np.where(right, a * np.cos(w * tp) + b * np.sin(w * tp), 0.0)
    kin.u[:, j] += piece
    if kind == "force":
        kin.f[:, j] += piece
    elif kind == "displacement":
        kin.z[:, j] += piece
        kin.z1[:, j] += np.where(right, z1(tp), 0.0)
        starts = np.flatnonzero(np.abs(ti - t0) <= tol)
        kin.jump[starts, j] += a                                  # the piece's own edges (impulses)
        ends = np.flatnonzero(np.abs(ti - t1) <= tol)
        kin.jump[ends, j] -= a * np.cos(w * span) + b * np.sin(w * span)
    else:
        kin.z[:, j] += np.where(right, z(tp), np.where(post, end_z + end_v * (t - t1), 0.0))
        kin.z1[:, j] += np.where(right, z1(tp), np.where(post, end_v, 0.0))
        kin.z2[:, j] += np.where(right, z2(tp), 0.0)


def _pwl_kinematics(grid: Grid, u_right: np.ndarray, u_left: np.ndarray, kinds: tuple[str, ...]) -> Kinematics:
    """Exact kinematics of piecewise-linear inputs (see :func:`kinematics`)."""
    h = grid.h[:, None]
    ng, m = u_right.shape
    us, ue = u_right[:-1], u_left[1:]
    s = (ue - us) / h
    left = u_left.copy()
    left[0] = 0.0
    coef = np.zeros((ng - 1, 4, m))
    jump = np.zeros((ng - 1, m))
    z = np.zeros((ng, m))
    z1 = np.zeros((ng, m))
    z2 = np.zeros((ng, m))
    f = np.zeros((ng, m))
    # values at grid points: right limits, left at the last point
    ur = u_right.copy()
    ur[-1] = u_left[-1]
    sr = np.vstack([s, s[-1:]])
    for j, kind in enumerate(kinds):
        if kind in ("force", "displacement"):
            coef[:, 0, j], coef[:, 1, j] = us[:, j], s[:, j]
            if kind == "force":
                f[:, j] = ur[:, j]
            else:
                jump[:, j] = (u_right[:-1, j] - left[:-1, j])
                z[:, j], z1[:, j] = ur[:, j], sr[:, j]
        elif kind == "velocity":
            Z = np.concatenate([[0.0], np.cumsum(h[:, 0] * (us[:, j] + ue[:, j]) / 2)])
            coef[:, 0, j], coef[:, 1, j], coef[:, 2, j] = Z[:-1], us[:, j], s[:, j]
            z[:, j], z1[:, j], z2[:, j] = Z, ur[:, j], sr[:, j]
        else:  # acceleration
            hh = h[:, 0]
            V = np.concatenate([[0.0], np.cumsum(hh * (us[:, j] + ue[:, j]) / 2)])
            Z = np.concatenate([[0.0], np.cumsum(hh * V[:-1] + hh**2 * (2 * us[:, j] + ue[:, j]) / 6)])
            coef[:, :, j] = np.column_stack([Z[:-1], V[:-1], us[:, j], s[:, j]])
            z[:, j], z1[:, j], z2[:, j] = Z, V, ur[:, j]
    return Kinematics(coef=coef, jump=jump, z=z, z1=z1, z2=z2, f=f, u=ur)


def direct_terms(prep: Prepared, kin: Kinematics, rows: np.ndarray) -> np.ndarray:
    """(ns, p) output terms of the inputs themselves at grid points ``rows``."""
    return (kin.z[rows] @ prep.D0.T + kin.z1[rows] @ prep.D1.T + kin.z2[rows] @ prep.D2.T
            + kin.f[rows] @ prep.Df.T)


# --------------------------------------------------------------------------------------------
# modal method
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True, eq=False)
class _ModalSet:
    """A set of decoupled modal blocks with their input and output maps."""

    A: np.ndarray       # (nb, b, b)
    P: np.ndarray | None  # (nb, n) modal forcing per generalized force (into the last row)
    x0: np.ndarray      # (nb, b) initial state
    Y: np.ndarray       # (p, nb, b) output per state component (conjugate pairs weighted 2)
    Pc: np.ndarray | None = None   # (nb, 3m) forcing per input channel [f, z, z'] (added to P @ channels)


SEPARATION = 1e-2
"""Smallest ``|lam1 - lam2| / |lam|`` of a decoupled mode's two eigenvalues for which it is simulated
as a complex (scalar) mode; closer (critically damped within about 5e-5) and rigid modes keep the
real 2x2 block, which is exact for a Jordan block."""


def _diagonalisable(w: np.ndarray, c: np.ndarray, rigid: np.ndarray) -> np.ndarray:
    """(n,) bool: elastic modes whose 2x2 block has well-separated eigenvalues (``w`` [rad/s],
    ``c = 2 zeta w`` [1/s])."""
    root = np.sqrt(np.abs((c / 2 - w) * (c / 2 + w)))
    return ~rigid & (w > 0) & (2 * root >= SEPARATION * np.maximum(w, c))


def _scalar_modes(w: np.ndarray, c: np.ndarray, phi: np.ndarray, eta0: np.ndarray, deta0: np.ndarray,
                  Ceta: np.ndarray, Cdeta: np.ndarray) -> _ModalSet:
    """Decoupled elastic modes ``eta'' + c eta' + w^2 eta = phi^T f`` as scalar complex modes.

    The block ``A = [[0, w], [-w, -c]]`` on ``x = [w eta; eta']`` has eigenvectors ``(w, lam)``:
    ``x = T z``, ``T = [[w, w], [lam1, lam2]]``, so ``z_k`` is driven by ``+-1 / (lam1 - lam2)``. An
    underdamped mode keeps ``lam1`` (``Im > 0``) with weight 2 (``x = 2 Re(t1 z1)``); an overdamped
    one keeps both real roots with weight 1.
    """
    disc = (c / 2 - w) * (c / 2 + w)
    root = np.sqrt(disc.astype(complex))
    root = np.where(root.imag < 0, -root, root)
    l1, l2 = -c / 2 + root, -c / 2 - root
    over = disc > 0
    lam, force, z0, wt, src = [], [], [], [], []
    for la, lb, sel in ((l1, l2, np.ones(w.size, bool)), (l2, l1, over)):
        dl = la - lb
        lam.append(la[sel])
        force.append(1.0 / dl[sel])
        z0.append(((deta0 - lb * eta0) / dl)[sel])          # the row of T^-1 applied to x0
        wt.append(np.where(over[sel], 1.0, 2.0))
        src.append(np.flatnonzero(sel))
    idx = np.concatenate(src)
    lam_ = np.concatenate(lam)
    Y = (Ceta[:, idx] + Cdeta[:, idx] * lam_) * np.concatenate(wt)      # Y T: x_a = w z, x_b = lam z
    return _ModalSet(A=lam_.reshape(-1, 1, 1), P=np.concatenate(force)[:, None] * phi[:, idx].T,
                     x0=np.concatenate(z0)[:, None], Y=Y[:, :, None])


def _modal_sets(prep: Prepared, q0: np.ndarray, v0: np.ndarray,
                horizon: float = np.inf) -> tuple[list[_ModalSet], str]:
    plant = prep.plant
    M = np.asarray(plant.M, float)
    mb = modal_basis(plant)
    w2, phi, rigid = mb.omega2, mb.phi, mb.rigid
    chat = projected_damping(plant, mb)[0]          # Phi^T C Phi, shared with the other consumers
    if rigid.any():
        # rotate the rigid subspace so that its damping block is diagonal: undamped combinations of
        # rigid modes then decouple as exact double integrators instead of 2x2 Jordan blocks at 0
        rid = np.flatnonzero(rigid)
        _, q = symmetric_eigen(chat[np.ix_(rid, rid)])
        phi, chat = phi.copy(), chat.copy()
        phi[:, rid] = phi[:, rid] @ q
        chat[rid, :] = q.T @ chat[rid, :]
        chat[:, rid] = chat[:, rid] @ q
    w = np.sqrt(w2)
    coupled = (damping_coupling(0.5 * (chat + chat.T)) > 0).any(axis=1)
    eta0, deta0 = phi.T @ (M @ q0), phi.T @ (M @ v0)
    s = np.where(w > 0, w, 1.0)
    Ceta, Cdeta = prep.Cp @ phi, prep.Cv @ phi
    sets: list[_ModalSet] = []
    scalar: list[_ModalSet] = []
    d = ~coupled
    diag = _diagonalisable(w, np.diag(chat), rigid) & d
    block = d & ~diag
    if block.any():        # rigid and nearly critically damped modes: exact real 2x2 blocks
        A = np.zeros((int(block.sum()), 2, 2))
        A[:, 0, 1] = s[block]
        A[:, 1, 0] = -w2[block] / s[block]
        A[:, 1, 1] = -np.diag(chat)[block]
        Y = np.stack([Ceta[:, block] / s[block], Cdeta[:, block]], axis=-1)
        sets.append(_ModalSet(A=A, P=phi[:, block].T,
                              x0=np.column_stack([s[block] * eta0[block], deta0[block]]), Y=Y))
    if diag.any():
        scalar.append(_scalar_modes(w[diag], np.diag(chat)[diag], phi[:, diag], eta0[diag], deta0[diag],
                                    Ceta[:, diag], Cdeta[:, diag]))
    how = "classical damping: real undamped modes"
    if coupled.any():
        e = coupled
        ne = int(e.sum())
        se = s[e]
        cm = complex_modes(se, np.arange(ne), w2[e], chat[np.ix_(e, e)], horizon=horizon)
        lam, V = cm.lam, cm.vectors
        keep = lam.imag >= 0
        z0 = cm.solve(np.concatenate([se * eta0[e], deta0[e]])[:, None])[keep]
        Vk = V[:, keep]
        Yw = Ceta[:, e] @ (Vk[:ne] / se[:, None]) + Cdeta[:, e] @ Vk[ne:]
        weight = np.where(lam[keep].imag > 0, 2.0, 1.0)
        # the forcing per input channel, V^-1[:, velocity] Phi^T [F, -Kt, -Ct] (N/2 x 3m): the
        # (N/2 x n) map Phi^T itself is only ever applied to those 3m columns (an N^3/8 complex
        # GEMM saved, about 0.06 s at 600 DOF)
        scalar.append(_ModalSet(A=lam[keep].reshape(-1, 1, 1), P=None,
                                x0=z0, Y=Yw[:, :, None] * weight[None, :, None],
                                Pc=cm.velocity_rows()[keep] @ (phi[:, e].T @ channels(prep))))
        how = (f"non-proportional damping: {ne} coupled modes as complex modes (eig of the scaled "
               f"modal first-order form), {len(w) - ne} decoupled real modes")
    if len(scalar) > 1:     # decoupled and coupled scalar modes in one set: their channel maps
        wg = channels(prep)
        scalar = [x if x.P is None else dataclasses.replace(x, P=None, Pc=x.P @ wg) for x in scalar]
    if scalar:
        sets.append(_ModalSet(A=np.concatenate([x.A for x in scalar]),
                              P=None if scalar[0].P is None else np.concatenate([x.P for x in scalar]),
                              x0=np.concatenate([x.x0 for x in scalar]), Y=np.concatenate([x.Y for x in scalar], axis=1),
                              Pc=None if scalar[0].Pc is None else np.concatenate([x.Pc for x in scalar])))
    return sets, how


def _remembered_modal_sets(prep: Prepared, q0: np.ndarray, v0: np.ndarray,
                           horizon: float) -> tuple[list[_ModalSet], str]:
    """:func:`_modal_sets`, kept on the plant for the next run with the same initial state and
    horizon (one slot: a loop simulating one plant again and again, e.g. a controller design, skips
    the complex-mode ``eig`` and the modal maps). The sets depend only on the plant (frozen), the
    initial state and the horizon; their arrays are made read-only."""
    key = (float(horizon), np.asarray(q0, float).tobytes(), np.asarray(v0, float).tobytes())
    slot = prep.plant._cache.get("modal sets")
    if slot is not None and slot[0] == key:
        return slot[1]
    sets, how = _modal_sets(prep, q0, v0, horizon)
    for ms in sets:
        for a in (ms.A, ms.P, ms.x0, ms.Y, ms.Pc):
            if a is not None:
                a.flags.writeable = False
    prep.plant._cache["modal sets"] = (key, (sets, how))
    return sets, how


def _drive(hk: np.ndarray, start: int, Va: np.ndarray, fold: np.ndarray, cs: list, jumps: np.ndarray,
           J: np.ndarray, jfold: np.ndarray, hkey: np.ndarray, cplx: bool, b: int, nb: int) -> np.ndarray:
    """The forcing of steps ``start .. start + len(hk)`` (keys ``hk``) as a (steps, b, nb) array."""
    stop = start + len(hk)
    keys = np.unique(hk)
    if len(keys) == 1:
        drive = Va[start:stop] @ fold[keys[0]]
        for Vo, fo, _ in cs:
            drive += Vo[start:stop] @ fo[keys[0]]
    else:
        drive = np.empty((stop - start, fold.shape[2]))
        for key in keys:
            idx = np.flatnonzero(hk == key)
            drive[idx] = Va[start + idx] @ fold[key]
            for Vo, fo, _ in cs:
                drive[idx] += Vo[start + idx] @ fo[key]
    for i in jumps[(jumps >= start) & (jumps < stop)]:
        drive[i - start] += J[i] @ jfold[hkey[i]]
    if cplx:
        drive = drive.view(complex)
    return drive.reshape(stop - start, b, nb)


def _real_view(a: np.ndarray) -> np.ndarray:
    """A complex array's last axis as interleaved real and imaginary parts (real arrays as they are)."""
    return np.ascontiguousarray(a).view(float) if np.iscomplexobj(a) else a


def channels(prep: Prepared) -> np.ndarray:
    """(n, 3m) generalized force per input channel ``[f, z, z']``: ``[F (forces), -Kt, -Ct]``."""
    return np.hstack([prep.plant.F * prep.force, -prep.Kt, -prep.Ct])


def run_modal(prep: Prepared, grid: Grid, kin: Kinematics, rows: np.ndarray,
              q0: np.ndarray, v0: np.ndarray,
              modal_sets: tuple[list[_ModalSet], str] | None = None) -> tuple[np.ndarray, str]:
    """Exact modal first-order-hold simulation.

    ``modal_sets`` (the decoupled modes and a text) replaces the plant's own: the modes plus the
    branch states of frequency-dependent mounts (:mod:`vibss.time.branched`).

    Returns
    -------
    y : (len(rows), p) ndarray
        Outputs at grid points ``rows`` (sorted).
    how : str
        What was done (for the result's record).
    """
    plant = prep.plant
    degree = max([DEGREE[k] for k in prep.kinds] + [1])
    sets, how = _remembered_modal_sets(prep, q0, v0, float(grid.t[-1])) if modal_sets is None else modal_sets
    # generalized forcing per input "channel": [F (force), -Kt (z), -Ct (z')]
    Wg = channels(prep)
    m = len(prep.kinds)
    ni = len(grid.h)
    coef = kin.coef
    y = np.zeros((len(rows), len(plant.outputs)))
    want = np.zeros(len(grid.t), bool)
    want[rows] = True
    out_pos = np.cumsum(want) - 1
    # channel values per Taylor order k: [f_k, z_k, z_{k+1}] (zero-padded), one row per interval
    pad = np.concatenate([coef, np.zeros((ni, 1, m))], axis=1)
    V = np.concatenate([np.concatenate([pad[:, k], pad[:, k], pad[:, k + 1]], axis=1)
                        for k in range(degree + 1)], axis=1)           # (ni, (degree+1) 3m)
    J = np.concatenate([np.zeros((ni, 2 * m)), kin.jump], axis=1)       # (ni, 3m)
    # sine/cosine parts per frequency: channel amplitudes [f, z, z'] of cos and sin (ni, 2, 3m)
    osc = [(w, np.concatenate([amp, amp, np.stack([w * amp[:, 1], -w * amp[:, 0]], axis=1)], axis=2))
           for w, amp in kin.osc]
    jumps = np.flatnonzero(np.any(kin.jump != 0, axis=1))
    nh = len(grid.steps)
    with one_blas_thread():
        for ms in sets:
            E, gam = foh_blocks(ms.A, grid.steps, degree)
            nb, b = ms.A.shape[0], ms.A.shape[1]
            PW = np.zeros((ms.A.shape[0], Wg.shape[1]), np.result_type(ms.A, Wg))    # (nb, 3m)
            if ms.P is not None:
                PW = PW + ms.P @ Wg
            if ms.Pc is not None:
                PW = PW + ms.Pc
            active = np.flatnonzero(np.any(PW != 0, axis=0))
            Va = V.reshape(ni, degree + 1, 3 * m)[:, :, active].reshape(ni, -1)
            # per step length: drive = Va[i] @ fold[h] (the FOH coefficients folded into the map),
            # columns component-major (b, nb) as the recursion takes them
            # complex maps as interleaved real ones: Va is real, so one real GEMM makes re and im
            foldc = np.einsum("mc,hkmb->hkcbm", PW[:, active], gam).reshape(nh, -1, b * nb)
            fold = _real_view(foldc)
            jfold = _real_view(np.einsum("mc,hmb->hcbm", PW, E[:, :, :, b - 1]).reshape(nh, 3 * m, b * nb))
            cs = []
            for w, Vo in osc:
                g2 = cs_blocks(ms.A, grid.steps, w)                           # (nh, 2, nb, b)
                fo = np.einsum("mc,hpmb->hpcbm", PW[:, active], g2).reshape(nh, -1, b * nb)
                cs.append((Vo[:, :, active].reshape(ni, -1), _real_view(fo), fo))
            x = np.ascontiguousarray(ms.x0.T)
            if want[0]:
                y[0] += np.real(np.einsum("pnb,nb->p", ms.Y, ms.x0))
            Yt = np.ascontiguousarray(np.moveaxis(ms.Y, 2, 1))               # (p, b, nb)
            cplx = np.iscomplexobj(E)
            start = 0
            while start < ni:
                stop = min(start + LOWRANK_CHUNK, ni)
                hk = grid.hkey[start:stop]
                if np.all(hk == hk[0]) and not np.any((jumps >= start) & (jumps < stop)):
                    # one step length, no jump: the forcing as its factors, formed inside the scan
                    lr = LowRank(np.hstack([Va[start:stop]] + [c[0][start:stop] for c in cs]),
                                 np.concatenate([foldc[hk[0]]] + [c[2][hk[0]] for c in cs]).reshape(-1, b, nb))
                    ys, x = scan(E, hk, x, lr, Yt)
                else:
                    stop = min(start + CHUNK, ni)
                    hk = grid.hkey[start:stop]
                    ys, x = scan(E, hk, x, _drive(hk, start, Va, fold, cs, jumps, J, jfold, grid.hkey, cplx, b, nb), Yt)
                sel = want[start + 1:stop + 1]
                if sel.any():
                    y[out_pos[start + 1:stop + 1][sel]] += ys[sel]
                start = stop
    y += direct_terms(prep, kin, rows)
    return y, how


# --------------------------------------------------------------------------------------------
# z-only realization: forced_response and solve_ivp
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True, eq=False)
class Realization:
    """First-order form ``x' = A x + B u``, ``y = C x + D u + D1p z' + D2p z''`` (see :func:`realization`).

    ``x = [p; xi; z_vel; z_acc; v_acc]`` with ``xi = p' + M^-1 Ct z``. ``post1`` / ``post2`` (p, m)
    multiply the z' of displacement inputs and the z'' of velocity inputs, which the realization
    does not carry (they are evaluated from the input directly).
    """

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    post1: np.ndarray
    post2: np.ndarray
    states: tuple[str, ...]


def realization(prep: Prepared) -> Realization:
    """The exact z-only realization of the substituted plant (no differentiated inputs)."""
    plant = prep.plant
    n, m = plant.F.shape
    kinds = prep.kinds
    iv = [j for j, k in enumerate(kinds) if k == "velocity"]
    ia = [j for j, k in enumerate(kinds) if k == "acceleration"]
    nv, na = len(iv), len(ia)
    ns = 2 * n + nv + 2 * na
    # z = Zx x + Zu u ; z' = Z1x x + Z1u u (for velocity/acceleration kinds)
    Zx, Zu = np.zeros((m, ns)), np.zeros((m, m))
    Z1x, Z1u = np.zeros((m, ns)), np.zeros((m, m))
    for j, k in enumerate(kinds):
        if k == "displacement":
            Zu[j, j] = 1.0
        elif k == "velocity":
            Zx[j, 2 * n + iv.index(j)] = 1.0
            Z1u[j, j] = 1.0
        elif k == "acceleration":
            a = ia.index(j)
            Zx[j, 2 * n + nv + a] = 1.0
            Z1x[j, 2 * n + nv + na + a] = 1.0
    M = np.asarray(plant.M, float)
    cho = sl.cho_factor(M)
    MiK = sl.cho_solve(cho, plant.K)
    MiC = sl.cho_solve(cho, plant.C)
    MiCt = sl.cho_solve(cho, prep.Ct)
    MiF = sl.cho_solve(cho, plant.F * prep.force)
    MiKt = sl.cho_solve(cho, prep.Kt)
    A = np.zeros((ns, ns))
    B = np.zeros((ns, m))
    P, X = slice(0, n), slice(n, 2 * n)
    # p' = xi - M^-1 Ct z
    A[P, X] = np.eye(n)
    A[P] -= MiCt @ Zx
    B[P] -= MiCt @ Zu
    # xi' = -M^-1 K p - M^-1 C (xi - M^-1 Ct z) + M^-1 F f - M^-1 Kt z
    A[X, P] = -MiK
    A[X, X] = -MiC
    zc = MiC @ MiCt - MiKt
    A[X] += zc @ Zx
    B[X] += zc @ Zu + MiF
    for a, j in enumerate(iv):
        B[2 * n + a, j] = 1.0
    for a, j in enumerate(ia):
        A[2 * n + nv + a, 2 * n + nv + na + a] = 1.0
        B[2 * n + nv + na + a, j] = 1.0
    # y = Cp p + Cv (xi - M^-1 Ct z) + D0 z + D1 z' + D2 z'' + Df f
    C = np.zeros((len(plant.outputs), ns))
    C[:, P] = prep.Cp
    C[:, X] = prep.Cv
    zy = prep.D0 - prep.Cv @ MiCt
    C += zy @ Zx + prep.D1 @ Z1x
    D = zy @ Zu + prep.D1 @ Z1u + prep.Df * prep.force
    disp = np.array([k == "displacement" for k in kinds])
    acc = np.array([k == "acceleration" for k in kinds])
    vel = np.array([k == "velocity" for k in kinds])
    D += prep.D2 * acc
    post1 = prep.D1 * disp
    post2 = prep.D2 * vel
    states = (tuple(f"{d}.p" for d in plant.dofs) + tuple(f"{d}.xi" for d in plant.dofs)
              + tuple(f"{plant.inputs[j]}.z" for j in iv) + tuple(f"{plant.inputs[j]}.z" for j in ia)
              + tuple(f"{plant.inputs[j]}.v" for j in ia))
    return Realization(A=A, B=B, C=C, D=D, post1=post1, post2=post2, states=states)


def run_forced_response(prep: Prepared, t: np.ndarray, u: np.ndarray, kin: Kinematics,
                        q0: np.ndarray, v0: np.ndarray) -> tuple[np.ndarray, str]:
    """python-control ``forced_response`` on the uniform grid ``t`` [s]; (ns, p) outputs and a note.

    The system is :func:`vibss.linear.statespace.statespace` (modal realization) of the plant. Where that
    refuses an output that needs an input's derivative, the local z-only realization is used and
    the derivative term is added from the inputs' piecewise-linear slopes.
    """
    import control

    from ..linear.statespace import statespace

    plant = prep.plant
    n = plant.n
    try:
        sys = statespace(plant)
    except AnalysisError as exc:
        require_none(plant, "simulate: the local z-only realization", f"here: {exc}")
        r = realization(prep)
        sys = control.ss(r.A, r.B, r.C, r.D)
        x0 = np.zeros(r.A.shape[0])
        x0[:n], x0[n:2 * n] = q0, v0
        post = kin.z1 @ r.post1.T + kin.z2 @ r.post2.T
        note = f"python-control forced_response of the local z-only realization ({exc})"
    else:
        mb = modal_basis(plant if plant.branches is None else mechanical(plant))   # statespace's basis
        M = np.asarray(plant.M, float)
        x0 = np.zeros(sys.nstates)
        x0[:n] = mb.scale * (mb.phi.T @ (M @ q0))
        x0[n:2 * n] = mb.phi.T @ (M @ v0)
        if plant.branches is not None:   # branches relaxed at the initial deflection (no force in them)
            x0[2 * n:2 * n + plant.branches.r] = plant.branches.B @ q0   # fluid-track rates (last) at rest
        post = 0.0
        note = "python-control forced_response of vibss.statespace (modal realization), FOH of the samples"
    with one_blas_thread():
        res = control.forced_response(sys, timepts=t, inputs=u.T, initial_state=x0)
    y = np.asarray(res.outputs).reshape(len(plant.outputs), -1).T
    return y + post, note


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
