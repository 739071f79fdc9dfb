"""The modal method: exact first-order-hold recursion of decoupled modal blocks (real undamped modes
for classical damping, complex modes where non-proportional damping couples them)."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from ...linear.eigen.complex_modes import complex_modes
from ...linear.eigen.basis import projected_damping
from ...linear.eigen.small import symmetric_eigen
from ...linear.eigen.basis import damping_coupling, modal_basis, proportional
from ..phi import cs_blocks, foh_blocks
from ..recursion import LowRank, scan
from .grid import Grid, Kinematics, direct_terms
from ...threads import one_blas_thread
from .prepared import Prepared

__all__ = ["run_modal", "modal_outputs", "channels", "DEGREE", "CHUNK", "LOWRANK_CHUNK", "SEPARATION"]

DEGREE = {"force": 1, "displacement": 1, "velocity": 2, "acceleration": 3}
"""Polynomial degree (per interval) of the prescribed coordinate (or force) for a PWL input."""

CHUNK = 1024
"""Time steps per chunk of the modal recursion where the forcing of each step is formed first (steps
of several lengths, or input jumps, in the chunk)."""

LOWRANK_CHUNK = 16384
"""Time steps per chunk of the modal recursion where every step has one length and no jump: the
forcing is passed as its factors (:class:`~vibss.time.recursion.LowRank`), so a chunk keeps only
``sqrt(steps)`` states per mode."""


@dataclass(frozen=True, eq=False)
class _ModalSet:
    """A set of decoupled modal blocks with their input and output maps."""

    A: np.ndarray       # (nb, b, b)
    P: np.ndarray | None  # (nb, n) modal forcing per generalized force (into the last row)
    x0: np.ndarray      # (nb, b) initial state
    Y: np.ndarray       # (p, nb, b) output per state component (conjugate pairs weighted 2)
    Pc: np.ndarray | None = None   # (nb, 3m) forcing per input channel [f, z, z'] (added to P @ channels)
    mode: np.ndarray | None = None  # (nb,) the undamped mode each block belongs to (the one dominating its shape)


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
                  Ceta: np.ndarray, Cdeta: np.ndarray, wg: np.ndarray) -> _ModalSet:
    """Decoupled elastic modes ``eta'' + c eta' + w^2 eta = phi^T f`` as scalar complex modes.

    The block ``A = [[0, w], [-w, -c]]`` on ``x = [w eta; eta']`` has eigenvectors ``(w, lam)``:
    ``x = T z``, ``T = [[w, w], [lam1, lam2]]``, so ``z_k`` is driven by ``+-1 / (lam1 - lam2)``. An
    underdamped mode keeps ``lam1`` (``Im > 0``) with weight 2 (``x = 2 Re(t1 z1)``); an overdamped
    one keeps both real roots with weight 1. The forcing is formed per input channel (``wg``,
    :func:`channels`): ``phi^T wg`` (n x 3m) rather than the (N x n) map ``phi^T`` scaled (4-7 ms at
    600 DOF, most of this function).
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
    return _ModalSet(A=lam_.reshape(-1, 1, 1), P=None, Pc=np.concatenate(force)[:, None] * (phi.T @ wg)[idx],
                     x0=np.concatenate(z0)[:, None], Y=Y[:, :, None], mode=idx)


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
    coupled = np.zeros(w.size, bool) if proportional(plant, "C") is not None else \
        (damping_coupling(0.5 * (chat + chat.T)) > 0).any(axis=1)      # C = a M + b K: diagonal
    eta0, deta0 = phi.T @ (M @ q0), phi.T @ (M @ v0)
    s = np.where(w > 0, w, 1.0)
    Ceta, Cdeta = prep.Cp @ phi, prep.Cv @ phi
    wg = channels(prep)
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
                              x0=np.column_stack([s[block] * eta0[block], deta0[block]]), Y=Y,
                              mode=np.flatnonzero(block)))
    if diag.any():
        sm = _scalar_modes(w[diag], np.diag(chat)[diag], phi[:, diag], eta0[diag], deta0[diag],
                           Ceta[:, diag], Cdeta[:, diag], wg)
        scalar.append(dataclasses.replace(sm, mode=np.flatnonzero(diag)[sm.mode]))
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
        owner = np.flatnonzero(e)[np.argmax(np.abs(Vk[:ne] / se[:, None]), axis=0)]
        # the forcing per input channel, V^-1[:, velocity] Phi^T [F, -Kt, -Ct] (N/2 x 3m): the
        # (N/2 x n) map Phi^T itself is only ever applied to those 3m columns (an N^3/8 complex
        # GEMM saved, about 0.06 s at 600 DOF)
        scalar.append(_ModalSet(A=lam[keep].reshape(-1, 1, 1), P=None,
                                x0=z0, Y=Yw[:, :, None] * weight[None, :, None],
                                Pc=cm.velocity_rows()[keep] @ (phi[:, e].T @ wg), mode=owner))
        how = (f"non-proportional damping: {ne} coupled modes as complex modes (eig of the scaled "
               f"modal first-order form), {len(w) - ne} decoupled real modes")
    if scalar:
        sets.append(_ModalSet(A=np.concatenate([x.A for x in scalar]),
                              P=None,      # every scalar set forces through its channels (Pc)
                              x0=np.concatenate([x.x0 for x in scalar]), Y=np.concatenate([x.Y for x in scalar], axis=1),
                              Pc=np.concatenate([x.Pc for x in scalar]),
                              mode=np.concatenate([x.mode for x in scalar if x.mode is not None])))
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
    sets, how = _remembered_modal_sets(prep, q0, v0, float(grid.t[-1])) if modal_sets is None else modal_sets
    y = modal_outputs(prep, grid, kin, rows, sets, len(prep.plant.outputs))
    y += direct_terms(prep, kin, rows)
    return y, how


def modal_outputs(prep: Prepared, grid: Grid, kin: Kinematics, rows: np.ndarray, sets: list[_ModalSet],
                  width: int) -> np.ndarray:
    """(len(rows), width) the modal sets' outputs (their ``Y`` rows, ``width`` of them) at grid points
    ``rows``: the response without the direct terms (:func:`run_modal` adds those). A caller that
    gives each mode rows of its own in ``Y`` gets the modes' terms apart
    (:mod:`vibss.insight.time_split`)."""
    degree = max([DEGREE[k] for k in prep.kinds] + [1])
    # generalized forcing per input "channel": [F (force), -Kt (z), -Ct (z')]
    Wg = channels(prep)
    m = len(prep.kinds)
    ni = len(grid.h)
    coef = kin.coef
    y = np.zeros((len(rows), width))
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
    return y
