"""Ritz steps on the stiffness factor that sharpen ``eigh``'s low modes (:func:`~vibss.linear.eigen.undamped.undamped`).

- :func:`refine`: one step of subspace inverse iteration with ``K`` and the Ritz values of the
  subspace by a Jacobi SVD of ``G W`` (high relative accuracy): the modes ``eigh`` cannot
  certify, and the few a light resonance amplifies;
- :func:`gram_ritz`: the Ritz step alone, by ``eigh`` of ``(G Phi)^T (G Phi)`` on the span of the low
  shapes: it removes ``eigh``'s coupling between them (``eps w2_max``) down to ``eps`` times the top of
  the low modes, which narrows a need of hundreds of modes to the few :func:`refine` takes.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.linalg as sl
import scipy.sparse as sp
import scipy.sparse.linalg as spl

from .checks import (_EPS, _issparse, _factor_norms, _six_blocks, error_estimate, fast_matrix, rayleigh_estimate,
                     stiffness_solver)
from .jacobi import jacobi_svd
from .small import projected_eigen

__all__ = ["GRAM_RITZ", "gram_ritz", "refine"]


GRAM_RITZ = 200
"""A consumer's need of this many modes or more is narrowed by :func:`gram_ritz` before the
inverse iteration and Jacobi SVD of :func:`refine` (which cost ~4 s on 986 modes at 2,400 DOF)."""


def _mass_times(M: Any, blocks: np.ndarray | None = None) -> Any:
    """``v -> M v`` by the 6x6 mass blocks where ``M`` has them (``blocks`` when already found), else by
    ``M`` (CSR when mostly zeros)."""
    blocks = _six_blocks(M) if blocks is None else blocks
    mass = M if _issparse(M) or blocks is not None else fast_matrix(np.asarray(M, float))
    if blocks is not None:
        return lambda v: np.matmul(blocks, v.reshape(blocks.shape[0], 6, -1)).reshape(v.shape)
    return lambda v: np.asarray(mass @ v)


def gram_ritz(M: Any, factor: Any, checked: Any, w2: np.ndarray, phi: np.ndarray, est: np.ndarray, k: int,
              blocks: Any, orthonormal: bool = False) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, bool]:
    """Rayleigh-Ritz of the ``k`` lowest shapes on the stiffness factor: ``B^T B y = theta P y``,
    ``B = G Phi_k``, ``P = Phi_k^T M Phi_k``.

    ``eigh`` of the whole pencil leaves each pair of shapes coupled by up to ``eps w2_max``
    (``phi_i^T K phi_j``, its backward error), which a light resonance amplifies by ``1 / 2 zeta``.
    In the span of the ``k`` lowest shapes that coupling is what ``B^T B`` holds off its diagonal;
    the Ritz step removes it down to its own backward error, ``eps theta_max`` (the top of the low
    modes instead of the whole model's), and to the rounding of ``B`` itself (``eps`` times the
    shapes' cancellation on the factor, which the bounds' rounding term carries and no Ritz step on
    ``B`` removes). ``P`` keeps the step right where the shapes are not M-orthonormal (some refined
    already, beside ``eigh``'s); with ``orthonormal`` (``eigh``'s shapes alone) ``P = I`` is taken
    where the diagonal of ``P`` is within 100 ``eps`` of 1 (0.3 s less at 2,400 DOF), the coupling
    it leaves counted in ``level``. The coupling to the shapes above ``k`` stays at ``eps w2_max``: safe
    because ``k`` is the last mode the consumer flagged at that level, its reach included, so every
    pair across the boundary already met the consumer's tolerance
    (:func:`vibss.linear.eigen.basis._needs_refinement`). The values are the new shapes' Rayleigh
    quotients on the factor, with their bounds (as on the dense path). Cost: the products ``G Phi_k``
    and ``M Phi_k``, two ``k x k`` Gram matrices and the pencil's ``eigh``, one ``n x k x k`` product,
    and the bounds' products (``G phi``, ``|G| |phi|``, ``G^T G phi``): 0.6-0.9 s for 986-1,065 of
    2,400 modes, where the inverse iteration and Jacobi SVD of :func:`refine` take 2.4-3.8 s; the
    modes still in need (none to 80 on the 2,400-DOF chain, tree and random graph) go to :func:`refine`.

    Returns
    -------
    (w2, phi, est, level, ran)
        ``level`` [rad^2/s^2]: the size of each shape's coupling to the others in the low span,
        ``eps theta_max`` there and ``eps w2_max`` above it; ``ran`` False when the step failed (the
        input returned as it was).
    """
    level = np.full(w2.shape, _EPS * float(np.max(w2)))
    low = phi[:, :k]
    b = np.asarray(factor @ low)
    try:
        mlow = _mass_times(M, None if blocks is None else blocks[0])(low)
        # eigh's shapes are M-orthonormal to eps times the mass blocks' conditioning: measured (the
        # diagonal, n k), and the pencil's P formed only past 100 eps
        drift = float(np.max(np.abs(np.einsum("ij,ij->j", low, mlow) - 1.0))) if orthonormal else np.inf
        theta, y = sl.eigh(b.T @ b, None if drift <= 100 * _EPS else low.T @ mlow, check_finite=False)
    except (np.linalg.LinAlgError, ValueError):
        return w2, phi, est, level, False
    phi, w2, est = phi.copy(), w2.copy(), est.copy()
    phi[:, :k] = low @ y
    cols = slice(0, min(k + 1, w2.size))               # one more: the last one's gap is whole
    nrm = _factor_norms(checked, phi[:, cols])
    rho, e_head = rayleigh_estimate(phi[:, cols], M, None, checked, np.zeros(cols.stop, bool), norms=nrm,
                                    blocks=blocks)
    w2[:k], est[:k] = np.where(np.isfinite(rho[:k]), rho[:k], theta), e_head[:k]
    level[:k] = max(_EPS, drift if drift <= 100 * _EPS else 0.0) * float(np.max(theta))
    if np.any(np.diff(w2) < 0):               # a close pair reordered by the quotients: ascending again
        order = np.argsort(w2, kind="stable")
        w2, phi, est, level = w2[order], phi[:, order], est[order], level[order]
    return w2, phi, est, level, True


def refine(K: Any, M: Any, factor: Any, w2: np.ndarray, phi: np.ndarray, est: np.ndarray,
           need: np.ndarray, shift: float = 0.0, solve: Any = None,
           whole: bool = False, estimate: bool = True,
           factors: dict | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray, bool]:
    """Refine the modes flagged ``need`` (and all below them): inverse iteration, then Ritz.

    One step of subspace inverse iteration ``X = (K + shift M)^-1 M Phi_low``, the
    columns M-orthonormalised (scaled Cholesky QR, twice), then the Ritz values of the subspace from
    the *factor* by a Jacobi SVD of ``G W`` (high relative accuracy; ``W^T K W`` when no factor is
    known). A mode keeps its old value where the new estimate is not better. Returns
    ``(w2, phi, est, refined)``. With ``whole`` and not ``estimate`` every mode up to the last one
    flagged is replaced and no estimate is formed (the caller tests them: their ``est`` is inf).
    """
    low = np.arange(int(np.flatnonzero(need).max()) + 1)
    # the products by the 6x6 mass blocks where M has them (its CSR form, 3 ms at 600 DOF, unused then)
    mul = _mass_times(M)
    mphi = mul(phi[:, low])
    try:
        if shift and factors is not None and shift in factors:    # the sweeps' one shifted factorisation
            solve = factors[shift]
        elif solve is None or shift:
            kd = K.toarray() if _issparse(K) and K.shape[0] <= 2000 else K
            if shift:
                kd = kd + shift * (M if _issparse(M) == _issparse(kd) else
                                   sp.csr_matrix(M) if _issparse(kd) else M.toarray())
            solve = spl.splu(sp.csc_matrix(kd)).solve if _issparse(kd) else stiffness_solver(np.asarray(kd, float))
            if shift and factors is not None:
                factors[shift] = solve
        x = solve(mphi)
        for _ in range(2):                               # scaled Cholesky QR in the M inner product
            x = x / np.sqrt(np.einsum("ij,ij->j", x, mul(x)))[None, :]
            g = x.T @ mul(x)
            x = sl.solve_triangular(np.linalg.cholesky(0.5 * (g + g.T)), x.T, lower=True).T
        if factor is not None:
            b = np.asarray(sp.csr_matrix(factor) @ x) if _issparse(factor) else np.asarray(factor) @ x
            if b.shape[0] < b.shape[1]:
                b = np.vstack([b, np.zeros((b.shape[1] - b.shape[0], b.shape[1]))])
            sva, v, work = jacobi_svd(b)
            order = np.argsort(sva)
            lam, q = ((work[0] / work[1]) * sva[order]) ** 2, v[:, order]
        else:
            kx = np.asarray(K @ x)
            lam, q = projected_eigen(x.T @ kx, np.eye(x.shape[1]))
    except (np.linalg.LinAlgError, RuntimeError, ValueError):
        return w2, phi, est, False
    new_w2 = w2.copy()
    new_w2[low] = lam
    full_phi = phi.copy()
    full_phi[:, low] = x @ q
    top = min(int(low.max()) + 2, w2.size)      # the refined modes and one neighbour for the gap
    new_est = np.full(w2.shape, np.inf)
    if estimate or not whole:
        new_est[:top] = error_estimate(new_w2[:top], full_phi[:, :top], M, None if factor is not None else K,
                                       factor)
    better = np.zeros(w2.shape, bool)
    better[low] = need[low] & ~(new_est[low] > est[low])     # only the modes asked for; NaN / inf (rigid) not worse
    if whole:                  # the whole Ritz subspace or nothing: its vectors are one orthonormal set
        better[low] = True
    w2 = np.where(better, new_w2, w2)
    phi = np.where(better[None, :], full_phi, phi)
    est = np.where(better, new_est, est)
    return w2, phi, est, bool(better.any())
