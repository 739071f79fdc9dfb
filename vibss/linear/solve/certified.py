"""Complex-mode solutions of a small plant's dynamic stiffness, certified at every frequency.

The dense exact solve (:func:`vibss.linear.solve.backends._dense`) factorises ``A(iw) = K + iH + iwC - w^2 M``
once per frequency: 200 LUs of a 12 x 12 complex matrix are most of a small model's frequency
response. For a small plant the eigen-decomposition of its 2n-state first-order form is cheaper than
a handful of those LUs and is kept on the (frozen) plant, and then every frequency's solution is a
few GEMMs:

    x(w) = L diag(1 / (iw - lam)) R b(w),      L = Phi S^-1 V_1,   R = (V^-1)_2 Phi^T,

on the undamped modal basis ``Phi`` (mass-normalised, ``S = omega``) and the eigenvectors ``V`` of
``[[0, S], [-(Omega^2 + i Phi^T H Phi) S^-1, -Phi^T C Phi]]`` (:func:`~vibss.linear.eigen.complex_modes.eigenpairs`).
A modal sum is not backward stable by itself (its error grows with the eigenvectors' condition and
with cancellation between modes), so it is not trusted: one step of iterative refinement with the
same modal inverse, ``x <- x + L diag(1/(iw - lam)) R (b - A(iw) x)``, and then at **every
frequency** the normwise backward error

    eta(w) = ||b - A(iw) x||_2 / (||A(iw)||_F ||x||_2 + ||b||_2)

(residual by GEMMs with ``K, C, M, H``; ``||A(iw)||_F`` exactly from six inner products of them, a
polynomial in ``w``) is compared with :data:`CERTIFY_TOL` ``= n eps``, the order of the a-priori
bound of LU with partial pivoting (``gamma_3n`` times its growth; LU's realised ``eta`` on the small
benchmark models is below ``eps``, and so is that of the refined modal solution). A frequency whose
``eta`` misses, or is not finite, is solved by the LU (the caller's, :func:`vibss.linear.solve.backends._dense`).
So every answer is the exact solution of ``(A(iw) + dA) x = b + db`` with ``||dA|| <= eta ||A||``
and ``||db|| <= eta ||b||``, ``eta`` of order ``n eps``: the residual is formed in double precision,
and its own rounding (about ``(n + 1) eps (||A|| ||x|| + ||b||)``) is of the threshold's size, so the
check bounds ``eta`` by about ``2 n eps``, not ``n eps`` (the tests recompute it in long double:
at most 1.07 eps on the benchmark models). That is the order of LU's own a-priori bound: as good
as the LU's in the backward sense, frequency by frequency.

It applies only where the assembled dense LU would be used (the caller is that back-end; the
mounts' form of badly scaled models is not touched), on the imaginary axis, to plants of
:data:`CERTIFY_MIN_DOFS` to :data:`CERTIFY_MAX_DOFS` DOFs without frequency-dependent mounts, asked for at least
:data:`CERTIFY_MIN_FREQUENCIES` frequencies; not where the eigenvectors are nearly dependent
(``cond(V) > COND_MAX``: undamped rigid-body modes are Jordan blocks), where it would fail
everywhere, and not on a plant without mass-normalised modes (a first-order plant, ``M = 0``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as sl

from ...errors import VibssError
from ...results import ReadOnly
from ..eigen.complex_modes import COND_MAX, eigenpairs, factor_vectors
from ..eigen.basis import modal_basis
from ..plant.plant import Plant
from ..eigen.basis import projected_damping

__all__ = ["CERTIFY_MAX_DOFS", "CERTIFY_MIN_DOFS", "CERTIFY_MIN_FREQUENCIES", "CERTIFY_TOL", "ModalInverse", "modal_inverse",
           "applies", "certified_states"]

CERTIFY_MAX_DOFS = 30
"""Largest plant (DOFs; 60 states) whose exact solve tries the certified complex-mode solutions."""

CERTIFY_MIN_DOFS = 12
"""Smallest plant that tries them. At 6 DOF (one body) the batched LU of 200 frequencies is as fast as
the modal sums (0.35 ms a call either way, measured) and the eig is a new model's extra cost (+0.5 ms);
at 12 DOF the call halves (0.88 -> 0.45 ms) and a new model costs the same."""

CERTIFY_MIN_FREQUENCIES = 16
"""Fewest frequencies for which they are tried (a handful of LUs costs less than the check)."""

CERTIFY_TOL = 1.0
"""The accepted backward error in units of ``n eps`` (``n`` the plant's DOFs)."""

_MAX_ELEMENTS = 2**20
"""Largest ``n nf m`` solved this way at once (16 MiB per complex (n, nf m) array); above it the LU."""


@dataclass(frozen=True, eq=False)
class ModalInverse(ReadOnly):
    """``A(s)^-1 = L diag(1 / (s - lam)) R`` of a small plant, and what its residual check needs.

    Attributes
    ----------
    lam : (N,) complex ndarray
        Eigenvalues of the first-order modal form [1/s], ``N = 2 n``.
    left : (n, N) complex ndarray
        ``L = Phi S^-1 V_1``: DOF displacements [m, rad] of the modal states.
    right : (N, n) complex ndarray
        ``R = (V^-1)[:, n:] Phi^T``: modal states driven by generalised forces [N, N m].
    terms : (k n, n) ndarray
        ``Re(K + iH)``, ``M``, ``C`` (and ``H``) stacked, for the residual in one real GEMM.
    norms : (6,) ndarray
        ``<Kr, Kr>, <Kr, M>, <M, M>, <C, C>, <H, H>, <H, C>`` (Frobenius inner products): ``||A(iw)||_F^2``
        ``= <Kr,Kr> - 2 w^2 <Kr,M> + w^4 <M,M> + <H,H> + 2 w <H,C> + w^2 <C,C>``.
    """

    lam: np.ndarray
    left: np.ndarray
    right: np.ndarray
    terms: np.ndarray
    norms: np.ndarray


def _make(plant: Plant, k0: np.ndarray, c: np.ndarray, m: np.ndarray) -> ModalInverse | None:
    try:
        basis = modal_basis(plant)
    except (np.linalg.LinAlgError, VibssError):     # no mass-normalised modes (a first-order plant, M = 0)
        return None
    if basis.phi.shape != (plant.n, plant.n):
        return None
    gam, hys = projected_damping(plant, basis)
    n, sc = plant.n, basis.scale
    hyst = np.iscomplexobj(k0)
    a = np.zeros((2 * n, 2 * n), dtype=complex if hyst else float)
    a[np.arange(n), n + np.arange(n)] = sc
    a[n + np.arange(n), np.arange(n)] = -basis.omega2 / sc
    if hyst:
        a[n:, :n] -= 1j * hys / sc[None, :]
    a[n:, n:] = -gam
    lam, v = eigenpairs(a)
    if not (np.all(np.isfinite(lam)) and np.all(np.isfinite(v))):
        return None
    lu, rcond = factor_vectors(v)
    if not rcond > 1.0 / COND_MAX:          # nearly dependent eigenvectors: the sums would fail everywhere
        return None
    sel = np.zeros((2 * n, n))
    sel[n:] = np.eye(n)
    right = sl.lu_solve(lu, sel, check_finite=False) @ basis.phi.T
    left = basis.phi @ (v[:n] / sc[:, None])
    kr, h = k0.real, (k0.imag if hyst else None)
    stack = [kr, m, c] + ([h] if h is not None else [])
    terms = np.ascontiguousarray(np.vstack(stack), dtype=float)
    hh = float(np.vdot(h, h)) if h is not None else 0.0
    hc = float(np.vdot(h, c)) if h is not None else 0.0
    norms = np.array([np.vdot(kr, kr), np.vdot(kr, m), np.vdot(m, m), np.vdot(c, c), hh, hc], dtype=float)
    kept = []
    for arr in (lam, left, right, terms, norms):      # read-only views of read-only arrays: for good
        arr.flags.writeable = False
        kept.append(arr.view())
    return ModalInverse(*kept)


def modal_inverse(plant: Plant, k0: np.ndarray, c: np.ndarray, m: np.ndarray) -> ModalInverse | None:
    """The plant's :class:`ModalInverse`, computed once and kept in its cache; None where the
    eigenvectors are nearly dependent (``cond(V) > COND_MAX``).

    Parameters
    ----------
    plant : Plant
        Dense plant without frequency-dependent mounts.
    k0, c, m : (n, n) ndarray
        Its dense ``K + iH`` [N/m], ``C`` [N s/m] and ``M`` [kg].

    Returns
    -------
    ModalInverse or None
    """
    return plant.cached("certified modal inverse", lambda: _make(plant, k0, c, m))


def applies(plant: Plant, s: np.ndarray) -> bool:
    """Whether the exact solve of ``plant`` at ``s`` tries the certified complex-mode solutions: a
    dense plant of :data:`CERTIFY_MIN_DOFS` to :data:`CERTIFY_MAX_DOFS` DOFs without
    frequency-dependent mounts, at least :data:`CERTIFY_MIN_FREQUENCIES` points, all on the
    imaginary axis (``s = i w``)."""
    return (plant.branches is None and CERTIFY_MIN_DOFS <= plant.n <= CERTIFY_MAX_DOFS
            and s.size >= CERTIFY_MIN_FREQUENCIES and not np.any(s.real))


def _apply(inv: ModalInverse, pole: np.ndarray, r: np.ndarray) -> np.ndarray:
    """``L diag(pole) R r`` for ``r`` (n, nf, m); returns (n, nf, m) complex."""
    n, nf, m = r.shape
    z = (inv.right @ r.reshape(n, nf * m)).reshape(-1, nf, m)
    z *= pole.T[:, :, None]
    return (inv.left @ z.reshape(-1, nf * m)).reshape(n, nf, m)


def _residual(inv: ModalInverse, w: np.ndarray, b: np.ndarray, x: np.ndarray) -> np.ndarray:
    """``b - A(iw) x`` for ``x`` (n, nf, m) C-contiguous; returns (n, nf, m) complex."""
    n, nf, m = x.shape
    t = (inv.terms @ x.reshape(n, nf * m).view(float)).view(complex).reshape(-1, n, nf, m)
    wc = w[None, :, None]
    ax = t[0] - (wc * wc) * t[1] + 1j * (wc * t[2])
    if t.shape[0] > 3:
        ax += 1j * t[3]
    return b - ax


def certified_states(plant: Plant, s: np.ndarray, rhs: np.ndarray, k0: np.ndarray, c: np.ndarray,
                     m: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """Solutions of ``A(s) x = rhs`` by the plant's complex modes, and where they are certified.

    Parameters
    ----------
    plant : Plant
        A plant for which :func:`applies` holds.
    s : (nf,) complex ndarray
        Laplace values ``i w`` [rad/s].
    rhs : (nf, n, m) complex ndarray
        Right-hand sides [N, N m] (a read-only broadcast view when they do not change with ``s``).
    k0, c, m : (n, n) ndarray
        The plant's dense ``K + iH`` [N/m], ``C`` [N s/m] and ``M`` [kg].

    Returns
    -------
    (x, ok) or None
        ``x`` (nf, n, m) complex, a writeable view; ``ok`` (nf,) bool: the frequencies whose
        backward error is at most :data:`CERTIFY_TOL` ``n eps`` for every right-hand side (the
        others are to be solved by LU). None where the eigenvectors are nearly dependent, or the
        problem is larger than ``n nf m = 2^20``.
    """
    nf, n, nr = rhs.shape
    if n * nf * nr > _MAX_ELEMENTS:
        return None
    inv = modal_inverse(plant, k0, c, m)
    if inv is None:
        return None
    w = s.imag
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        pole = 1.0 / (s[:, None] - inv.lam[None, :])                 # (nf, N)
        if rhs.strides[0] == 0:                  # the same right-hand side at every s: R b once
            b = np.broadcast_to(rhs[0][:, None, :], (n, nf, nr))
            b_norm = np.broadcast_to(np.linalg.norm(rhs[0], axis=0), (nf, nr))
            z = (inv.right @ rhs[0])[:, None, :] * pole.T[:, :, None]
            x = (inv.left @ z.reshape(-1, nf * nr)).reshape(n, nf, nr)
        else:
            b = np.ascontiguousarray(rhs.transpose(1, 0, 2))
            b_norm = _column_norms(b)
            x = _apply(inv, pole, b)
        x += _apply(inv, pole, _residual(inv, w, b, x))             # one step of refinement
        w2 = w * w
        kk, km, mm, cc, hh, hc = inv.norms
        a_norm = np.sqrt(np.maximum(kk - 2 * w2 * km + w2 * w2 * mm + hh + 2 * w * hc + w2 * cc, 0.0))
        eta = _column_norms(_residual(inv, w, b, x)) / (a_norm[:, None] * _column_norms(x) + b_norm)
    ok = np.all(eta <= CERTIFY_TOL * n * np.finfo(float).eps, axis=1)
    return x.transpose(1, 0, 2), ok


def _column_norms(v: np.ndarray) -> np.ndarray:
    """``||v[:, j, k]||_2`` of a complex (n, nf, m) array; returns (nf, m)."""
    f = v.view(float) if v.flags.c_contiguous else np.ascontiguousarray(v).view(float)
    sq = np.einsum("ijk,ijk->jk", f, f)
    return np.sqrt(sq.reshape(v.shape[1], v.shape[2], 2).sum(axis=2))
