"""The simulation grid (samples merged with the inputs' breakpoints) and the inputs' exact
kinematics on it (piecewise polynomial, plus sine/cosine pieces)."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

import numpy as np

from .prepared import Prepared

__all__ = ["Grid", "Kinematics", "make_grid", "nudge", "kinematics", "direct_terms"]


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
