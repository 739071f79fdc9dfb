"""Variants of a closed loop whose mount rates are off: the rate changes as an internal feedback.

A change ``dk`` of a mount's rate along its local axis ``j`` adds the force ``-dk d`` along that
axis, ``d`` the mount's deflection there. So the plant is extended once with a hidden ideal actuator
in parallel with the mount (``f``) and a hidden relative-displacement sensor across it (``d``), and
every variant is the nominal system with ``f = -Delta d``, ``Delta = diag(dk)`` (an LFT):

- frequency responses (loop transfers, transmissibility) of a variant are exact at any frequency:
  ``H_v = H_yu - H_yt Delta (I + H_tt Delta)^-1 H_tu`` from the nominal responses, an ``r x r`` solve
  per variant and frequency (``r`` the number of mount axes that change);
- poles: ``A_v = A - B_t Delta (I + D_tt Delta)^-1 C_t`` is a rank-``r`` change of the nominal closed
  loop. In the nominal closed loop's modal coordinates the ``states`` lowest poles are solved per
  variant (batched ``eigvals``); the poles above are held at their nominal values and their effect
  on the low ones kept as a static residual (``D_tt - C_h Lambda_h^-1 B_h``): exact when every
  pole is kept, and checked against a full eigen-solve of the worst variant afterwards.

Rates, rate ratios and tied rates change ``K`` this way; shifts and angles do not (they move the
lever arms): those take the per-variant rebuild (:func:`vibss.control.robust.robustness`,
``method="rebuild"``).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from typing import Any

import numpy as np

from ..design.parameters import _RATE, _RATIO, Parameter, ratio_axes
from ..errors import ControlDesignError
from ..frequency.statespace_kernels import diagonal_sum
from ..linear.eigen.small import state_eigen, state_eigenvalues
from ..model.actuation import Actuator, Sensor
from ..model.model import Model

__all__ = ["mount_rates", "Extended", "extend", "lft", "reduced_poles"]

HIDDEN = "robust_tolerance_"
"""Prefix of the hidden actuators and sensors that carry the rate changes."""


def mount_rates(model: Model, parameters: Sequence[Parameter], values: np.ndarray) -> np.ndarray:
    """(N, mounts, 3) principal rates [N/m] of every variant (as :func:`vibss.design.parameters.apply`).

    Parameters
    ----------
    model : Model
        The nominal model.
    parameters : sequence of Parameter
        Rate or rate-ratio parameters.
    values : (N, p) ndarray
        Their values per variant [N/m or -].
    """
    index = {m.name: i for i, m in enumerate(model.mounts)}
    nv = values.shape[0]
    rates = np.broadcast_to(np.array([m.type.stiffness for m in model.mounts], dtype=float),
                            (nv, len(model.mounts), 3)).copy()
    for i, p in enumerate(parameters):
        for mount, kind, factor in p.targets:
            if kind in _RATE:
                rates[:, index[mount], _RATE.index(kind)] = factor * values[:, i]
    for i, p in enumerate(parameters):            # ratios after rates: the denominator is final
        for mount, kind, factor in p.targets:
            if kind in _RATIO:
                num, den = ratio_axes(kind)
                rates[:, index[mount], num] = factor * values[:, i] * rates[:, index[mount], den]
    return rates


@dataclasses.dataclass(frozen=True)
class Extended:
    """The nominal plant and closed loop with the rate-change channels.

    Attributes
    ----------
    plant : GeneralizedPlant
        The plant with hidden actuators ``f`` and sensors ``d`` (one per changing mount axis).
    axes : tuple of (int, int)
        (mount index, local axis 0..2) of each channel.
    closed : tuple of ndarray
        ``(A, B, C, D)`` of the nominal closed loop on the extended plant (inputs: disturbances,
        then the ``f``; outputs: the plant's outputs then the commands).
    f_in, d_out : ndarray
        Indices of the ``f`` inputs and ``d`` outputs in the closed loop.
    """

    plant: Any
    axes: tuple[tuple[int, int], ...]
    closed: tuple[np.ndarray, ...]
    f_in: np.ndarray
    d_out: np.ndarray
    inputs: tuple[str, ...]
    outputs: tuple[str, ...]


def extend(plant: Any, controller: Any, axes: Sequence[tuple[int, int]]) -> Extended:
    """The plant rebuilt with a hidden actuator and sensor per changing mount axis, and the nominal
    loop closed on it (see the module docstring)."""
    return close_extended(extended_plant(plant, axes), controller, axes)


def extended_plant(plant: Any, axes: Sequence[tuple[int, int]]) -> Any:
    """The plant with a hidden ideal actuator (``actuator.robust_tolerance_<i>.u``) and relative
    displacement sensor (``sensor.robust_tolerance_<i>``) per mount axis; the plant itself when none."""
    from .plant import plant as build

    if not axes:
        return plant
    model = plant.model
    recipe = dict(plant.recipe)
    if recipe["measurements"] == "states":
        raise ControlDesignError("robustness: a state-feedback plant (measurements='states') has modal "
                                 "states that change with the mounts; measure sensors instead, or use "
                                 "method='rebuild'")
    acts, sens = [], []
    for i, (q, j) in enumerate(axes):
        m = model.mounts[q]
        acts.append(Actuator(f"{HIDDEN}{i}", mount=m.name, axis=j + 1))
        sens.append(Sensor(f"{HIDDEN}{i}", "relative_displacement", mount=m.name, axis=j + 1))
    ext = model.replace(actuators=[*model.actuators, *acts], sensors=[*model.sensors, *sens])
    y = recipe["measurements"] if recipe["measurements"] is not None else [s.signal for s in model.sensors]
    noise = recipe["noise"]
    if noise is not None and not isinstance(noise, dict):
        noise = {s: noise for s in y}
    return build(ext, recipe["disturbances"], [*recipe["actuators"], *[a.name for a in acts]],
                 recipe["performance"], [*y, *[s.signal for s in sens]], noise=noise, dofs=recipe["dofs"],
                 modal_damping=recipe["modal_damping"], ideal_actuators=recipe["ideal_actuators"],
                 name=recipe["name"] or model.name)


def close_extended(P: Any, controller: Any, axes: Sequence[tuple[int, int]]) -> Extended:
    """The loop ``u = K y`` closed on an :func:`extended_plant`, the channels located."""
    from .loop import _close

    A, B, C, D, ext_in, _, _ = _close(P, controller)
    ins = [P.input_labels[i] for i in ext_in]
    outs = list(P.output_labels) + list(controller.output_labels)
    f_in = np.array([ins.index(f"actuator:{HIDDEN}{i}:u") for i in range(len(axes))], dtype=int)
    d_out = np.array([outs.index(f"sensor:{HIDDEN}{i}") for i in range(len(axes))], dtype=int)
    return Extended(P, tuple(axes), (A, B, C, D), f_in, d_out, tuple(ins), tuple(outs))


def open_loop(ext: Extended, controller: Any, omega: np.ndarray) -> np.ndarray:
    """(ny + r, nu + r, nf) nominal plant responses from the commands and the channels' forces to the
    measurements and the channels' deflections (independent of the controller)."""
    from ..frequency.statespace_response import Evaluator
    from .loop import interconnect_indices

    P = ext.plant
    iy = interconnect_indices(P.output_labels, controller.input_labels, "controller inputs")
    iu = interconnect_indices(P.input_labels, controller.output_labels, "controller outputs")
    t_in = [P.input_labels.index(ext.inputs[i]) for i in ext.f_in]
    t_out = [P.output_labels.index(ext.outputs[i]) for i in ext.d_out]
    return Evaluator(P, outputs=[*iy, *t_out], inputs=[*iu, *t_in])(omega)


def lft(h: np.ndarray, delta: np.ndarray, rows: Sequence[int], cols: Sequence[int],
        t_out: Sequence[int], t_in: Sequence[int]) -> np.ndarray:
    """Responses of every variant: ``H_rc - H_rt Delta (I + H_tt Delta)^-1 H_tc``.

    Parameters
    ----------
    h : (p, m, nf) complex ndarray
        Nominal responses, the channels included.
    delta : (N, r) ndarray
        Rate changes per variant and channel [N/m].
    rows, cols : sequence of int
        Outputs and inputs wanted.
    t_out, t_in : sequence of int
        The deflection outputs ``d`` and force inputs ``f``.

    Returns
    -------
    (N, nf, len(rows), len(cols)) complex ndarray
    """
    hrc = np.moveaxis(h[np.ix_(rows, cols)], -1, 0)[None]          # (1, nf, a, b)
    hrt = np.moveaxis(h[np.ix_(rows, t_in)], -1, 0)[None]
    htc = np.moveaxis(h[np.ix_(t_out, cols)], -1, 0)[None]
    htt = np.moveaxis(h[np.ix_(t_out, t_in)], -1, 0)[None]           # (1, nf, r, r)
    r = len(t_in)
    dl = delta[:, None, None, :]                                     # (N, 1, 1, r): right-multiplies columns
    lhs = np.eye(r)[None, None] + htt * dl                           # I + H_tt Delta
    x = np.linalg.solve(lhs, np.broadcast_to(htc, lhs.shape[:2] + htc.shape[2:]))
    return hrc - (hrt * dl) @ x


def closed_modes(closed: tuple[np.ndarray, ...]) -> tuple[np.ndarray, np.ndarray]:
    """Eigenvalues [rad/s] and eigenvectors of the nominal closed loop, by ascending magnitude
    (:func:`vibss.linear.eigen.small.state_eigen`)."""
    return state_eigen(closed[0])


def _real_form(lam: np.ndarray, b: np.ndarray, c: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The diagonal modal system ``(lam, b, c)`` of a real system (conjugate pairs complete) in real
    coordinates: a pair ``a +- i w`` becomes ``[[a, -w], [w, a]]`` on ``(Re z, Im z)``."""
    k = lam.size
    A = np.zeros((k, k))
    B = np.zeros((k, b.shape[1]))
    C = np.zeros((c.shape[0], k))
    used = np.zeros(k, bool)
    tol = 1e-9 * max(np.abs(lam).max(initial=1.0), 1.0)
    for i in range(k):
        if used[i]:
            continue
        used[i] = True
        if abs(lam[i].imag) <= tol:
            A[i, i], B[i], C[:, i] = lam[i].real, b[i].real, c[:, i].real
            continue
        free = np.flatnonzero(~used)
        j = free[np.argmin(np.abs(lam[free] - np.conj(lam[i])))]
        used[j] = True
        m = lam[i] if lam[i].imag > 0 else lam[j]
        z = i if lam[i].imag > 0 else j
        A[i, i], A[i, j], A[j, i], A[j, j] = m.real, -m.imag, m.imag, m.real
        B[i], B[j] = b[z].real, b[z].imag
        C[:, i], C[:, j] = 2 * c[:, z].real, -2 * c[:, z].imag
    return A, B, C


HOLD = 1e-7
"""Largest first-order bound on the relative shift ``|d lam| / |lam|`` of a pole (also a bound on its
damping change, to first order) for which :func:`reduced_poles` holds a pole among the lowest ones at
its nominal value instead of solving it per variant: ``||B_j|| max_v ||Delta_v (I + D Delta_v)^-1||
||C_j|| / |lam_j|``, its modal input and output rows on the rate channels."""


def reduced_poles(closed: tuple[np.ndarray, ...], f_in: np.ndarray, d_out: np.ndarray, delta: np.ndarray,
                  states: int, chunk: int = 200,
                  modes: tuple[np.ndarray, np.ndarray] | None = None,
                  hold: float = 0.0) -> tuple[np.ndarray, np.ndarray, int]:
    """Closed-loop poles of every variant [rad/s] (see the module docstring).

    Parameters
    ----------
    closed : tuple of ndarray
        ``(A, B, C, D)`` of the nominal closed loop with the channels.
    f_in, d_out : ndarray
        Channel indices.
    delta : (N, r) ndarray
        Rate changes [N/m].
    states : int
        Poles solved per variant (the lowest by magnitude, a conjugate pair never split); the rest
        held at their nominal values.
    chunk : int
        Variants per batched eigen-solve.
    modes : (lam, V) or None
        :func:`closed_modes` of ``closed`` if known.
    hold : float
        The poles among the lowest ``states`` that the rate channels barely see, a first-order bound on
        their relative shift below ``hold`` (:data:`HOLD`), are held at their nominal values too (0:
        none), their coupling to the solved ones left out: the eigen-solve per variant shrinks to the
        poles the loops see (``kept`` counts the solved ones).

    Returns
    -------
    poles : (N, k) complex ndarray
        The solved poles of each variant.
    held : (n - k,) complex ndarray
        The nominal poles held.
    kept : int
        Number of poles solved per variant, ``k``.
    """
    A, B, C, D = closed
    lam, V = closed_modes(closed) if modes is None else modes
    k = min(int(states), len(lam))
    if 0 < k < len(lam) and abs(lam[k - 1].imag) > 0 and np.isclose(lam[k], np.conj(lam[k - 1])):
        k += 1                                      # keep the pair whole
    r = len(f_in)
    if r == 0:
        return np.broadcast_to(lam[:k], (delta.shape[0], k)).copy(), lam[k:], k
    Bt = np.linalg.solve(V, B[:, f_in])
    Ct = C[d_out] @ V
    Dtt = D[np.ix_(d_out, f_in)].astype(complex)
    if k < len(lam):
        hi = slice(k, None)
        Dtt = Dtt - (Ct[:, hi] / lam[hi]) @ Bt[hi]
    Dr = Dtt.real
    solve = np.ones(k, bool)
    if hold > 0:
        bound = shift_bound(lam[:k], Bt[:k], Ct[:, :k], Dr, delta)
        solve = bound > hold
        mate = np.argmin(np.abs(lam[:k][None, :] - np.conj(lam[:k])[:, None]), axis=1)   # each pole's conjugate
        solve |= solve[mate]                                                            # pairs stay whole
    L, Bl, Cl = _real_form(lam[:k][solve], Bt[:k][solve], Ct[:, :k][:, solve])
    ks = int(solve.sum())
    out = np.empty((delta.shape[0], ks), dtype=complex)
    for s in range(0, delta.shape[0], chunk):
        dv = delta[s:s + chunk]                                    # (c, r)
        inner = np.linalg.inv(np.eye(r)[None] + Dr[None] * dv[:, None, :])   # (I + D Delta)^-1
        av = L[None] - (Bl[None] * dv[:, None, :]) @ inner @ Cl[None]
        out[s:s + chunk] = state_eigenvalues(av)
    return out, np.concatenate([lam[:k][~solve], lam[k:]]), ks


def shift_bound(lam: np.ndarray, bt: np.ndarray, ct: np.ndarray, d: np.ndarray, delta: np.ndarray) -> np.ndarray:
    """(k,) first-order bound on each pole's relative shift over the variants, ``||B_j|| max_v
    ||Delta_v (I + D Delta_v)^-1||_2 ||C_j|| / |lam_j|`` (``d lam_j = -B_j Delta' C_j`` to first order)."""
    r = delta.shape[1]
    inner = np.linalg.inv(np.eye(r)[None] + d[None] * delta[:, None, :])
    dmax = float(np.linalg.norm(delta[:, :, None] * inner, ord=2, axis=(1, 2)).max(initial=0.0))
    mag = np.maximum(np.abs(lam), np.finfo(float).tiny)
    return np.linalg.norm(bt, axis=1) * dmax * np.linalg.norm(ct, axis=0) / mag


def peak_refined(mag: np.ndarray, omega: np.ndarray) -> np.ndarray:
    """(N,) peak of ``mag`` (N, nf) over a grid, refined by a parabola in ``w^2`` through ``1 / mag^2``
    at the three points around the largest sample (exact for a single-DOF resonance, whose
    ``1 / |H|^2 = ((k - m w^2)^2 + (c w)^2) / |N|^2`` is quadratic in ``w^2`` for a constant numerator;
    second order in the grid step otherwise)."""
    i = np.clip(np.argmax(mag, axis=1), 1, mag.shape[1] - 2)
    rows = np.arange(mag.shape[0])
    y = 1.0 / np.maximum(np.stack([mag[rows, i - 1], mag[rows, i], mag[rows, i + 1]], axis=1), 1e-300) ** 2
    x = np.stack([omega[i - 1], omega[i], omega[i + 1]], axis=1) ** 2
    # the parabola's minimum from divided differences
    d1 = (y[:, 1] - y[:, 0]) / (x[:, 1] - x[:, 0])
    d2 = ((y[:, 2] - y[:, 1]) / (x[:, 2] - x[:, 1]) - d1) / (x[:, 2] - x[:, 0])
    xm = 0.5 * (x[:, 0] + x[:, 1]) - d1 / np.where(d2 > 0, 2 * d2, np.inf)
    ym = y[:, 0] + d1 * (xm - x[:, 0]) + d2 * (xm - x[:, 0]) * (xm - x[:, 1])
    inside = (d2 > 0) & (xm > x[:, 0]) & (xm < x[:, 2]) & (ym > 0)
    out = mag.max(axis=1)
    return np.where(inside, np.maximum(out, 1.0 / np.sqrt(np.where(inside, ym, 1.0))), out)


def frequency_metrics(ext: Extended, controller: Any, delta: np.ndarray, omega: np.ndarray,
                      channel: tuple[int, int], chunk: int = 50, h: np.ndarray | None = None,
                      modes: tuple[np.ndarray, np.ndarray] | None = None) -> dict[str, np.ndarray]:
    """Disk margins and peak transmissibility of every variant, exact on the grid ``omega`` [rad/s].

    Returns ``{"disk_margin": (N,) smallest loop-at-a-time balanced disk margin, "loop_disk_margin":
    (N, nu), "mimo_disk_margin": (N,), "peak": (N,) peak |T| of the channel, "effort": (N,) peak |u / w|
    over the commands for the channel's disturbance}``; ``h`` the :func:`open_loop` responses and
    ``modes`` the :func:`closed_modes` of the nominal loop if known. Peaks over the grid are refined
    by :func:`peak_refined`.
    """
    from ..frequency.statespace_response import Evaluator

    ny, nu, r = controller.ninputs, controller.noutputs, len(ext.f_in)
    if h is None:
        h = open_loop(ext, controller, omega)
    kw = np.moveaxis(Evaluator(controller)(omega), -1, 0)                 # (nf, nu, ny)
    cmd = list(range(len(ext.outputs) - nu, len(ext.outputs)))
    rows, cols = [channel[1], *cmd, *ext.d_out], [channel[0], *ext.f_in]
    tw = _closed_response(ext.closed, rows, cols, modes)(omega)
    at = _closed_response(ext.closed, [channel[1], *ext.d_out], [channel[0], *ext.f_in], modes)
    nv, nf = delta.shape[0], omega.size
    loops = np.empty((nv, nu))
    mimo = np.empty(nv)
    peak = np.empty(nv)
    effort = np.empty(nv)
    for s in range(0, nv, chunk):
        dv = delta[s:s + chunk]
        c = dv.shape[0]
        g = _lft_or_nominal(h, dv, range(ny), range(nu), range(ny, ny + r), range(nu, nu + r))
        q = kw[None] @ g                                                # (c, nf, nu, nu)
        S = np.linalg.inv(np.eye(nu) - q)             # input sensitivity; S_ii = 1 / (1 + L_i), L_i
        d = np.abs(np.diagonal(S, axis1=-2, axis2=-1) - 0.5)   # loop i broken with the others closed
        for i in range(nu):
            loops[s:s + c, i] = 1.0 / peak_refined(d[:, :, i], omega)
        x = S - 0.5 * np.eye(nu)
        top = np.linalg.eigvalsh(np.conj(np.swapaxes(x, -1, -2)) @ x)[..., -1]
        mimo[s:s + c] = 1.0 / peak_refined(np.sqrt(np.maximum(top, 0.0)), omega)
        t = _lft_or_nominal(tw, dv, range(1 + nu), [0], range(1 + nu, 1 + nu + r), range(1, 1 + r))[:, :, :, 0]
        peak[s:s + c] = _peak_search(at, dv, np.abs(t[:, :, 0]), omega)
        effort[s:s + c] = np.abs(t[:, :, 1:]).max(axis=(1, 2))
    return {"disk_margin": loops.min(axis=1), "loop_disk_margin": loops, "mimo_disk_margin": mimo, "peak": peak,
            "effort": effort}


def _peak_search(at: Any, delta: np.ndarray, mag: np.ndarray, omega: np.ndarray, steps: int = 6) -> np.ndarray:
    """(N,) peak of ``|T|`` of each variant: its largest grid sample, then successive parabolic steps in
    ``w^2`` on ``1 / |T|^2`` with the response evaluated exactly at each new frequency (one per variant
    and step), kept inside the grid neighbours of the largest sample. ``at(w)`` is the nominal closed
    loop's (1 + r, 1 + r, len(w)) response of the channel and the rate channels."""
    n = mag.shape[0]
    i = np.clip(np.argmax(mag, axis=1), 1, mag.shape[1] - 2)
    rws = np.arange(n)
    x = np.stack([omega[i - 1], omega[i], omega[i + 1]], axis=1) ** 2
    y = 1.0 / np.maximum(np.stack([mag[rws, i - 1], mag[rws, i], mag[rws, i + 1]], axis=1), 1e-300) ** 2
    best = mag.max(axis=1)
    for _ in range(steps):
        d1 = (y[:, 1] - y[:, 0]) / (x[:, 1] - x[:, 0])
        d2 = ((y[:, 2] - y[:, 1]) / (x[:, 2] - x[:, 1]) - d1) / (x[:, 2] - x[:, 0])
        with np.errstate(divide="ignore", invalid="ignore"):
            xm = 0.5 * (x[:, 0] + x[:, 1]) - d1 / (2 * d2)
        ok = (d2 > 0) & np.isfinite(xm) & (xm > x[:, 0]) & (xm < x[:, 2]) & (np.abs(xm - x[:, 1]) > 1e-12 * x[:, 1])
        if not ok.any():
            break
        wm = np.sqrt(np.where(ok, xm, x[:, 1]))
        ym = 1.0 / np.maximum(np.abs(_response_at(at, delta, wm)), 1e-300) ** 2
        best = np.where(ok, np.maximum(best, 1.0 / np.sqrt(ym)), best)
        left = xm < x[:, 1]
        better = ym < y[:, 1]
        nx, ny = x.copy(), y.copy()
        for mask, a in ((left & better, (0, None, 1)), (left & ~better, (None, 1, 2)),
                        (~left & better, (1, None, 2)), (~left & ~better, (0, 1, None))):
            m = mask & ok
            for k, src in enumerate(a):
                nx[m, k] = xm[m] if src is None else x[m, src]
                ny[m, k] = ym[m] if src is None else y[m, src]
        x, y = nx, ny
    return best


def _response_at(at: Any, delta: np.ndarray, w: np.ndarray) -> np.ndarray:
    """(N,) ``T_v(i w_v)`` of the channel of each variant ``v`` at its own frequency."""
    h = at(w)                                                          # (1 + r, 1 + r, N)
    if delta.shape[1] == 0:
        return h[0, 0]
    hrc, hrt, htc, htt = h[0, 0], h[0, 1:].T, h[1:, 0].T, np.moveaxis(h[1:, 1:], -1, 0)
    r = delta.shape[1]
    x = np.linalg.solve(np.eye(r)[None] + htt * delta[:, None, :], htc[:, :, None])[:, :, 0]
    return hrc - np.einsum("nr,nr,nr->n", hrt, delta, x)


def _closed_response(closed: tuple[np.ndarray, ...], rows: Sequence[int], cols: Sequence[int],
                     modes: tuple[np.ndarray, np.ndarray] | None) -> Any:
    """``w -> (rows, cols, len(w))`` response of the closed loop [rad/s]: a diagonal sum over its modes
    when known (projected once), else the state-space evaluator."""
    from ..frequency.statespace_response import Evaluator

    A, B, C, D = closed
    if modes is None:
        import control

        return Evaluator(control.ss(A, B, C, D), outputs=list(rows), inputs=list(cols))
    lam, V = modes
    vb = np.linalg.solve(V, B[:, list(cols)])
    cv = C[list(rows)] @ V
    d = D[np.ix_(list(rows), list(cols))][:, :, None]
    diag = diagonal_sum(lam, cv, vb)

    def h(w: np.ndarray) -> np.ndarray:
        return diag(1j * np.asarray(w, dtype=float)) + d

    return h


def _lft_or_nominal(h: np.ndarray, delta: np.ndarray, rows: Any, cols: Any, t_out: Any, t_in: Any) -> np.ndarray:
    if delta.shape[1] == 0:
        nom = np.moveaxis(h[np.ix_(list(rows), list(cols))], -1, 0)
        return np.broadcast_to(nom[None], (delta.shape[0],) + nom.shape)
    return lft(h, delta, list(rows), list(cols), list(t_out), list(t_in))
