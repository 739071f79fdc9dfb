"""The ``woodbury`` frequency kernel: undamped modes plus the dampers and mount branches as a low-rank update.

In the undamped modes (``Phi^T M Phi = I``, ``Phi^T K Phi = Omega^2``) the dynamic stiffness is

    A(s) = D(s) + U Z(s) U^T,    D(s) = Omega^2 + s^2 (diagonal),    Z(s) = s Zc + i Zh  (r x r)

where ``U`` (k x r) holds the modes' deflections at the dampers and ``Zc``, ``Zh`` their viscous and
hysteretic blocks (:func:`vibss.linear.eigen.basis.damping_factors`): the damping of any model,
classical or not, has rank ``r <= 3 x`` (damped mounts). Classical damping (``Phi^T C Phi`` and
``Phi^T H Phi`` diagonal) stays in ``D(s) = Omega^2 + s Gamma + i Eta + s^2`` instead. The Maxwell
branches of frequency-dependent mounts (:mod:`vibss.linear.plant.branches`) join ``U`` with their
deflections ``Phi^T B_i^T`` and ``Z_ii(s) = k_i g_i(s)``, ``g_i = P_i / (1 + P_i)``,
``P_i = mu_i s^2 + tau_i s``; their terms in the inputs and outputs carry ``g(s)`` too. With
``y = U^T x`` the update's deflections, ``A x = P`` is the bordered system

    D x + U Z y = P,    U^T x - y = 0.

Eliminating ``x`` through ``D^-1`` (the Woodbury identity) would divide by ``omega_k^2 - omega^2``
next to every undamped resonance and lose the digits that the damping then restores. So only the
*far* modes are eliminated, those with ``|D_k(s)| > NEAR |Z-part of A_kk|`` (their ``1 / D_k`` is
bounded by the damping), and the *near* ones stay unknowns with ``y``: per frequency one LU with
partial pivoting of order ``q + r`` (q near modes),

    [ D_N      U_N Z            ] [x_N]   [ P_N              ]
    [ -U_N^T   I + U_F^T D_F^-1 U_F Z ] [ y ] = [ U_F^T D_F^-1 P_F ],

and the outputs ``L x = L_N x_N + L_F D_F^-1 P_F - (L_F D_F^-1 U_F) Z y``. The sums over the far
modes are GEMMs over all frequencies at once. Cost per frequency ``O(k r (p + m + r) + (q + r)^3)``
besides the modal basis: well below the complex modes' ``eig`` of the 2k-state matrix when few
mounts are damped; when every mount is (r > k), ``complex_modal`` or ``sparse`` is cheaper and
``auto`` takes them (:func:`vibss.frequency.methods.choose`).

Exact: the same equations as :func:`vibss.linear.solve.exact.response` on the certified modal basis, no
eigenvalues of the damped system, no truncation; a frequency where the bordered matrix is singular
(an undamped mode exactly at resonance) is answered by the exact solve.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..linear.plant.branches import groups
from ..linear.eigen.basis import ModalBasis, damping_coupling, modal_basis
from ..linear.plant.plant import Plant
from ..linear.eigen.basis import damping_factors, projected_damping
from ..linear.solve.exact import response, zfactor
from .terms import elastic_static, feedthrough, mass_solve, terms

__all__ = ["woodbury", "NEAR", "near_modes", "CHUNK"]

CHUNK = 64
"""Frequencies per batched LU of the bordered systems (each padded to its chunk's most near modes)."""

NEAR = 10.0
"""A mode is kept as an unknown (near) at ``s`` when ``|D_k(s)| <= NEAR |(U Z(s) U^T)_kk|``."""


def near_modes(omega2: np.ndarray, diag: np.ndarray, zdiag: np.ndarray) -> np.ndarray:
    """(nf, k) mask of the modes solved with the update at each ``s`` (see :data:`NEAR`).

    Parameters
    ----------
    omega2 : (k,) ndarray
        Squared natural frequencies [rad^2/s^2].
    diag : (nf, k) complex ndarray
        The diagonal part ``D(s)`` of the modal dynamic stiffness [rad^2/s^2].
    zdiag : (nf, k) ndarray
        ``|diag(U Z(s) U^T)|``: what the low-rank part adds to each mode [rad^2/s^2].

    Returns
    -------
    (nf, k) bool ndarray
    """
    return np.abs(diag) <= NEAR * zdiag


def _weighted(w: tuple[np.ndarray, np.ndarray], left: np.ndarray, right: np.ndarray) -> np.ndarray:
    """``sum_k w[f, k] left[:, k] right[k, :]`` for every f, ``w`` given as its real and imaginary
    parts (nf, k): (nf, a, b) by GEMMs."""
    a, b = left.shape[0], right.shape[1]
    pair = (left.T[:, :, None] * right[:, None, :]).reshape(left.shape[1], a * b)
    out = w[0] @ pair + 1j * (w[1] @ pair)
    return out.reshape(w[0].shape[0], a, b)


def _weighted_gram(w: tuple[np.ndarray, np.ndarray], u: np.ndarray) -> np.ndarray:
    """``U^T diag(w[f]) U`` for every f (nf, r, r), symmetric: the upper triangle by GEMMs."""
    r = u.shape[1]
    i, j = np.triu_indices(r)
    pair = u[:, i] * u[:, j]
    half = w[0] @ pair + 1j * (w[1] @ pair)
    out = np.empty((w[0].shape[0], r, r), complex)
    out[:, i, j] = half
    out[:, j, i] = half
    return out


def _update(plant: Plant, basis: ModalBasis, s: np.ndarray) -> tuple[np.ndarray, np.ndarray, Any, np.ndarray]:
    """The modal dynamic stiffness as ``D(s) + U Z(s) U^T`` (module docstring).

    Returns ``D`` (nf, k), ``U`` (k, r), ``Z`` as a function of frequency indices -> (len, r, r), and
    ``|diag(U Z(s) U^T)|`` (nf, k). Classical damping (``Phi^T C Phi`` and ``Phi^T H Phi`` diagonal)
    stays in ``D``; other damping joins ``U`` as its mounts' deflections
    (:func:`vibss.linear.eigen.basis.damping_factors`); every Maxwell branch of a frequency-dependent
    mount adds its deflection ``Phi^T B_i^T`` with ``k_i g_i(s)`` (:meth:`Branches.dynamic`).
    """
    omega2 = basis.omega2
    k = omega2.size
    projected = projected_damping(plant, basis)
    classical = not any(np.any(damping_coupling(g) > 0) for g in projected if np.any(g))
    d = omega2[None, :] + (s**2)[:, None]
    if classical:
        d = d + s[:, None] * np.diag(projected[0])[None, :]
        if np.any(projected[1]):
            d = d + 1j * np.diag(projected[1])[None, :]
        ud, zc, zh = np.zeros((k, 0)), np.zeros((0, 0)), np.zeros((0, 0))
    else:
        ud, zc, zh = damping_factors(plant, basis)
    rd = ud.shape[1]
    hyst = bool(np.any(zh))
    zdiag = np.zeros(d.shape)
    if rd:
        diag_c = np.einsum("kr,rs,ks->k", ud, zc, ud)
        diag_h = np.einsum("kr,rs,ks->k", ud, zh, ud) if hyst else np.zeros(k)
        zdiag = s[:, None] * diag_c[None, :] + 1j * diag_h[None, :]
    br = plant.branches
    if br is None:
        ub, kg = np.zeros((k, 0)), np.zeros((s.size, 0))
    else:
        ub = basis.phi.T @ br.B.T                                       # (k, r_b)
        kg = br.dynamic(s)                                              # (nf, r_b) k_i g_i(s)
        zdiag = zdiag + kg @ (ub * ub).T
    u = np.hstack([ud, ub])
    r = u.shape[1]

    def zmat(idx: np.ndarray) -> np.ndarray:
        z = np.zeros((idx.size, r, r), complex)
        if rd:
            z[:, :rd, :rd] = s[idx, None, None] * zc[None] + (1j * zh[None] if hyst else 0.0)
        j = np.arange(rd, r)
        z[:, j, j] = kg[idx]
        return z

    return d, u, zmat, np.abs(zdiag)


def _factors(plant: Plant, s: np.ndarray) -> tuple[list, list, np.ndarray]:
    """The output and right-hand-side terms with their factors per frequency: [((nf,), (P, n))] and
    [((nf,), (n, M), scaled by Z)], the plant's powers of ``s`` and its branch groups' ``g(s)``."""
    outs, rhs, order = terms(plant)
    fo = [(s**a, oa) for a, oa in outs]
    fr = [(s**b, rb, scaled) for b, rb, scaled in rhs]
    for g in groups(plant):
        gs = g.factor(s)
        if np.any(g.Oq):
            fo.append((gs, g.Oq))
        if np.any(g.Kz):
            fr.append((-gs, g.Kz, True))
    return fo, fr, order


def woodbury(plant: Plant, s: np.ndarray, basis: ModalBasis | None = None) -> np.ndarray:
    """Undamped modes with the dampers and branches as a low-rank update, bordered solve per
    frequency; (p, m, nf).

    Any viscous and hysteretic damping (classical or not) and frequency-dependent mounts; exact
    (see the module docstring).

    Parameters
    ----------
    plant : Plant
        Dense plant.
    s : (nf,) complex array_like
        Laplace points ``i w`` [rad/s], ``w > 0``.
    basis : ModalBasis or None
        The plant's undamped modes (computed if None).

    Returns
    -------
    (p, m, nf) complex ndarray
    """
    s = np.asarray(s, dtype=complex)
    basis = basis or modal_basis(plant)
    phi = basis.phi
    d, u, zmat, zdiag = _update(plant, basis, s)
    k, r = u.shape
    outs, rhs, order = _factors(plant, s)
    p, m, nf = len(plant.outputs), len(plant.inputs), s.size
    zf = zfactor(s, order)
    left = np.vstack([oa @ phi for _, oa in outs]) if outs else np.zeros((0, k))          # (P, k)
    right = np.hstack([phi.T @ rb for _, rb, _ in rhs]) if rhs else np.zeros((k, 0))     # (k, M)
    mm = right.shape[1]
    near = near_modes(basis.omega2, d, zdiag) if r else np.zeros((nf, k), bool)
    with np.errstate(divide="ignore", invalid="ignore"):
        w = np.where(near, 0.0, 1.0 / np.where(near, 1.0, d))
    bad = ~np.all(np.isfinite(w), axis=1)
    w_split = (np.ascontiguousarray(w.real), np.ascontiguousarray(w.imag))
    yfull = _uncoupled(plant, s, basis, near, d, w, w_split, left, right, outs, rhs)
    if r:
        g2 = _weighted(w_split, u.T, right)                              # U_F^T D_F^-1 P_F
        g3 = _weighted_gram(w_split, u)                                  # U_F^T D_F^-1 U_F
        eye = np.eye(r)
        for run in np.array_split(np.arange(nf), max(1, nf // CHUNK)):
            # one batched LU per chunk of frequencies, its near sets padded to the longest
            z = zmat(run)                                                # (nr, r, r)
            count = near[run].sum(axis=1)
            q = int(count.max())
            slot = np.arange(q)[None, :] < count[:, None]                # (nr, q) real slots
            nn = np.zeros((run.size, q), int)
            nn[slot] = np.nonzero(near[run])[1]
            un = np.where(slot[:, :, None], u[nn], 0.0)                  # (nr, q, r)
            big = np.zeros((run.size, q + r, q + r), complex)
            big[:, np.arange(q), np.arange(q)] = np.where(slot, np.take_along_axis(d[run], nn, axis=1), 1.0)
            big[:, :q, q:] = un @ z
            big[:, q:, :q] = -un.transpose(0, 2, 1)
            big[:, q:, q:] = eye + g3[run] @ z
            rb = np.zeros((run.size, q + r, mm), complex)
            rb[:, :q] = np.where(slot[:, :, None], right[nn], 0.0)
            rb[:, q:] = g2[run]
            try:
                sol = np.linalg.solve(big, rb)
            except np.linalg.LinAlgError:
                bad[run] = True
                continue
            zy = z @ sol[:, q:]                                           # (nr, r, M)
            # - L_F D_F^-1 U_F Z y, through the chunk's (k, nr M) modal forces (no (nf, P, r) sums)
            uz = (u @ zy.transpose(1, 0, 2).reshape(r, -1)).reshape(k, run.size, mm) * w[run].T[:, :, None]
            yfull[run] -= (left @ uz.reshape(k, -1)).reshape(-1, run.size, mm).transpose(1, 0, 2)
            if q:
                ln = np.where(slot[:, None, :], left[:, nn].transpose(1, 0, 2), 0.0)   # (nr, P, q)
                yfull[run] += ln @ sol[:, :q]
    bad |= ~np.all(np.isfinite(yfull), axis=(1, 2))
    # assemble Y = sum_ab f_a(s) f_b(s) (O_a ...) (... R_b) Z(s)
    out = np.zeros((nf, p, m), complex)
    i = 0
    for fa, _ in outs:
        j = 0
        for fb, _, scaled in rhs:
            fac = (fa * fb)[:, None] * (zf if scaled else np.ones((1, m)))
            out += yfull[:, i:i + p, j:j + m] * fac[:, None, :]
            j += m
        i += p
    out += feedthrough(plant, s, zf)
    for g in groups(plant):                                              # branch forces seen directly
        if np.any(g.Pz):
            out += g.factor(s)[:, None, None] * g.Pz[None] * zf[:, None, :]
    if bad.any():                                                        # singular: the exact solve
        out[bad] = np.moveaxis(response(plant, s[bad]), -1, 0)
    return np.moveaxis(out, 0, -1)


def _uncoupled(plant: Plant, s: np.ndarray, basis: ModalBasis, near: np.ndarray, d: np.ndarray, w: np.ndarray,
               w_split: tuple[np.ndarray, np.ndarray], left: np.ndarray, right: np.ndarray,
               outs: list, rhs: list) -> np.ndarray:
    """(nf, P, M) the part of ``L x`` that does not pass through the update, ``L_F D_F^-1 P_F``, or
    the same sum in the mode-acceleration form ``O K^-1 R - L_F ((D - Omega^2) / Omega^2) D_F^-1 P_F - L_N Omega_N^-2 P_N``
    or the mass-residual form ``O M^-1 R / s^2 - L_F ((D - s^2) / s^2) D_F^-1 P_F - L_N P_N / s^2``
    (the near modes' ``x_N`` and the coupling ``-L_F D_F^-1 U_F Z y`` are common to all three), per
    frequency whichever sums the smallest terms. The plain sum loses digits below the modes, where
    the high modes' static terms cancel, and far above them; the static part is exact
    (:func:`vibss.frequency.terms.elastic_static`, in the mounts' forces on stiff models)."""
    plain = _weighted(w_split, left, right)
    if not outs or not rhs:
        return plain
    scale = np.linalg.norm(left, axis=0) * np.linalg.norm(right, axis=1)
    cost = np.abs(w) @ scale
    forms = []                  # (constant (P, M), its factor per frequency, weights)
    rigid = bool(basis.rigid.any())
    if not rigid:               # no static part with rigid modes (K singular)
        try:
            st = np.hstack([elastic_static(plant, rb) for _, rb, _ in rhs])
            inv2 = 1.0 / basis.omega2
            forms.append((np.vstack([oa @ st for _, oa in outs]), np.ones(s.size),
                          np.where(near, -inv2[None, :], -(d - basis.omega2[None, :]) * w * inv2[None, :])))
        except (np.linalg.LinAlgError, ValueError, RuntimeError):
            pass
    try:
        ms = np.hstack([mass_solve(plant, rb) for _, rb, _ in rhs])
        inv_s2 = 1.0 / s**2
        forms.append((np.vstack([oa @ ms for _, oa in outs]), inv_s2,
                      np.where(near, -inv_s2[:, None], -(d - (s**2)[:, None]) * w * inv_s2[:, None])))
    except (np.linalg.LinAlgError, ValueError, RuntimeError):
        pass
    costs = [cost] + [np.abs(wf) @ scale + np.abs(fac) * np.linalg.norm(c0) for c0, fac, wf in forms]
    if rigid and forms:         # the mass form not below the elastic modes: there the rigid modes' 1 / s^2
        low = basis.omega[~basis.rigid].min(initial=np.inf)      # cancel in it (hanging chain: 1.9e-8
        costs[-1] = np.where(np.abs(s) > low, costs[-1], np.inf)  # at 0.3 omega_1, chosen by the cost)
    pick = np.argmin(np.stack(costs), axis=0)
    for which, (c0, fac, wf) in enumerate(forms, start=1):
        rows = pick == which
        if rows.any():
            sub = wf[rows]
            plain[rows] = fac[rows, None, None] * c0[None] + _weighted(
                (np.ascontiguousarray(sub.real), np.ascontiguousarray(sub.imag)), left, right)
    return plain
