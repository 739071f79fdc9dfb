"""The ``woodbury`` frequency kernel: undamped modes plus the dampers as a low-rank update.

In the undamped modes (``Phi^T M Phi = I``, ``Phi^T K Phi = Omega^2``) the dynamic stiffness is

    A(s) = D(s) + U Z(s) U^T,    D(s) = Omega^2 + s^2 (diagonal),    Z(s) = s Zc + i Zh  (r x r)

where ``U`` (k x r) holds the modes' deflections at the dampers and ``Zc``, ``Zh`` their viscous and
hysteretic blocks (:func:`vibss.linear.projection.damping_factors`): the damping of any model,
classical or not, has rank ``r <= 3 x`` (damped mounts). With ``y = U^T x`` the damper
deflections, ``A x = P`` is the bordered system

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

Exact: the same equations as :func:`vibss.linear.solve.response` on the certified modal basis, no
eigenvalues of the damped system, no truncation; a frequency where the bordered matrix is singular
(an undamped mode exactly at resonance) is answered by the exact solve.
"""

from __future__ import annotations

import numpy as np

from ..linear.eigen import ModalBasis, modal_basis
from ..linear.plant import Plant
from ..linear.projection import damping_factors
from ..linear.solve import response, zfactor
from .terms import elastic_static, feedthrough, mass_solve, terms

__all__ = ["woodbury", "NEAR", "near_modes", "CHUNK"]

CHUNK = 64
"""Frequencies per batched LU of the bordered systems (each padded to its chunk's most near modes)."""

NEAR = 10.0
"""A mode is kept as an unknown (near) at ``s`` when ``|omega_k^2 + s^2| <= NEAR |s gamma_kk + i eta_kk|``."""


def near_modes(basis: ModalBasis, diag_c: np.ndarray, diag_h: np.ndarray, s: np.ndarray) -> np.ndarray:
    """(nf, k) mask of the modes solved with the dampers at each ``s`` (see :data:`NEAR`).

    Parameters
    ----------
    basis : ModalBasis
        Undamped modes.
    diag_c, diag_h : (k,) ndarray
        Diagonals of ``Phi^T C Phi`` [1/s] and ``Phi^T H Phi`` [1/s^2].
    s : (nf,) complex ndarray
        Laplace points [rad/s].

    Returns
    -------
    (nf, k) bool ndarray
    """
    d = np.abs(basis.omega2[None, :] + (s**2)[:, None])
    z = np.abs(s[:, None] * diag_c[None, :] + 1j * diag_h[None, :])
    return d <= NEAR * z


def _weighted(w: tuple[np.ndarray, np.ndarray], left: np.ndarray, right: np.ndarray) -> np.ndarray:
    """``sum_k w[f, k] left[:, k] right[k, :]`` for every f, ``w`` given as its real and imaginary
    parts (nf, k): (nf, a, b) by GEMMs."""
    a, b = left.shape[0], right.shape[1]
    pair = (left.T[:, :, None] * right[:, None, :]).reshape(left.shape[1], a * b)
    out = w[0] @ pair + 1j * (w[1] @ pair)
    return out.reshape(w[0].shape[0], a, b)


def _times(a: np.ndarray, z: np.ndarray) -> np.ndarray:
    """``a[f] @ z`` for a stack ``a`` (nf, i, r) and one symmetric ``z`` (r, r), as one GEMM."""
    return (a.reshape(-1, a.shape[-1]) @ z).reshape(a.shape[:-1] + (z.shape[1],))


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


def woodbury(plant: Plant, s: np.ndarray, basis: ModalBasis | None = None) -> np.ndarray:
    """Undamped modes with the dampers as a low-rank update, bordered solve per frequency; (p, m, nf).

    Any viscous and hysteretic damping (classical or not); exact (see the module docstring).

    Parameters
    ----------
    plant : Plant
        Dense plant without frequency-dependent mounts.
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
    u, zc, zh = damping_factors(plant, basis)
    k, r = u.shape
    outs, rhs, order = terms(plant)
    p, m, nf = len(plant.outputs), len(plant.inputs), s.size
    zf = zfactor(s, order)
    left = np.vstack([oa @ phi for _, oa in outs]) if outs else np.zeros((0, k))          # (P, k)
    right = np.hstack([phi.T @ rb for _, rb, _ in rhs]) if rhs else np.zeros((k, 0))     # (k, M)
    mm = right.shape[1]
    hyst = bool(np.any(zh))
    diag_c = np.einsum("kr,rs,ks->k", u, zc, u) if r else np.zeros(k)
    diag_h = np.einsum("kr,rs,ks->k", u, zh, u) if r and hyst else np.zeros(k)
    near = near_modes(basis, diag_c, diag_h, s) if r else np.zeros((nf, k), bool)
    d = basis.omega2[None, :] + (s**2)[:, None]
    with np.errstate(divide="ignore", invalid="ignore"):
        w = np.where(near, 0.0, 1.0 / np.where(near, 1.0, d))
    bad = ~np.all(np.isfinite(w), axis=1)
    w_split = (np.ascontiguousarray(w.real), np.ascontiguousarray(w.imag))
    yfull = _uncoupled(plant, s, basis, near, w, w_split, left, right, outs, rhs)
    if r:
        g2 = _weighted(w_split, u.T, right)                              # U_F^T D_F^-1 P_F
        g3 = _weighted_gram(w_split, u)                                  # U_F^T D_F^-1 U_F
        g3z = s[:, None, None] * _times(g3, zc) + (1j * _times(g3, zh) if hyst else 0.0)
        eye = np.eye(r)
        for run in np.array_split(np.arange(nf), max(1, nf // CHUNK)):
            # one batched LU per chunk of frequencies, its near sets padded to the longest
            count = near[run].sum(axis=1)
            q = int(count.max())
            slot = np.arange(q)[None, :] < count[:, None]                # (nr, q) real slots
            nn = np.zeros((run.size, q), int)
            nn[slot] = np.nonzero(near[run])[1]
            un = np.where(slot[:, :, None], u[nn], 0.0)                  # (nr, q, r)
            big = np.zeros((run.size, q + r, q + r), complex)
            big[:, np.arange(q), np.arange(q)] = np.where(slot, np.take_along_axis(d[run], nn, axis=1), 1.0)
            big[:, :q, q:] = s[run, None, None] * _times(un, zc) + (1j * _times(un, zh) if hyst else 0.0)
            big[:, q:, :q] = -un.transpose(0, 2, 1)
            big[:, q:, q:] = eye + g3z[run]
            rb = np.zeros((run.size, q + r, mm), complex)
            rb[:, :q] = np.where(slot[:, :, None], right[nn], 0.0)
            rb[:, q:] = g2[run]
            try:
                sol = np.linalg.solve(big, rb)
            except np.linalg.LinAlgError:
                bad[run] = True
                continue
            y = sol[:, q:]
            yt = np.ascontiguousarray(y.transpose(0, 2, 1))                  # (nr, M, r): Z y = (y^T Z)^T
            zy = (s[run, None, None] * _times(yt, zc) + (1j * _times(yt, zh) if hyst else 0.0)).transpose(0, 2, 1)
            # - L_F D_F^-1 U_F Z y, through the chunk's (k, nr M) modal forces (no (nf, P, r) sums)
            uz = (u @ zy.transpose(1, 0, 2).reshape(r, -1)).reshape(k, run.size, mm) * w[run].T[:, :, None]
            yfull[run] -= (left @ uz.reshape(k, -1)).reshape(-1, run.size, mm).transpose(1, 0, 2)
            if q:
                ln = np.where(slot[:, None, :], left[:, nn].transpose(1, 0, 2), 0.0)   # (nr, P, q)
                yfull[run] += ln @ sol[:, :q]
    bad |= ~np.all(np.isfinite(yfull), axis=(1, 2))
    # assemble Y = sum_ab s^(a+b) (O_a ...) (... R_b) Z(s)
    out = np.zeros((nf, p, m), complex)
    i = 0
    for a, _ in outs:
        j = 0
        for b_, _, scaled in rhs:
            fac = s[:, None] ** (a + b_) * (zf if scaled else np.ones((1, m)))
            out += yfull[:, i:i + p, j:j + m] * fac[:, None, :]
            j += m
        i += p
    out += feedthrough(plant, s, zf)
    if bad.any():                                                        # singular: the exact solve
        out[bad] = np.moveaxis(response(plant, s[bad]), -1, 0)
    return np.moveaxis(out, 0, -1)


def _uncoupled(plant: Plant, s: np.ndarray, basis: ModalBasis, near: np.ndarray, w: np.ndarray,
               w_split: tuple[np.ndarray, np.ndarray], left: np.ndarray, right: np.ndarray,
               outs: list, rhs: list) -> np.ndarray:
    """(nf, P, M) the part of ``L x`` that does not pass through the dampers, ``L_F D_F^-1 P_F``, or
    the same sum in the mode-acceleration form ``O K^-1 R - L_F (s^2 / omega^2) D_F^-1 P_F - L_N Omega_N^-2 P_N``
    or the mass-residual form ``O M^-1 R / s^2 - L_F (omega^2 / s^2) D_F^-1 P_F - L_N P_N / s^2``
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
                          np.where(near, -inv2[None, :], -(s**2)[:, None] * w * inv2[None, :])))
        except (np.linalg.LinAlgError, ValueError, RuntimeError):
            pass
    try:
        ms = np.hstack([mass_solve(plant, rb) for _, rb, _ in rhs])
        inv_s2 = 1.0 / s**2
        forms.append((np.vstack([oa @ ms for _, oa in outs]), inv_s2,
                      np.where(near, -inv_s2[:, None], -basis.omega2[None, :] * w * inv_s2[:, None])))
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
