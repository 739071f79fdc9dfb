"""The Jacobi SVD of the factored eigenproblem: every undamped frequency to high relative accuracy.

With the stiffness factor ``G`` (``K = G^T G``) and ``M = L L^T``, the squared singular values of
``A = G L^-T`` are the ``w^2`` of ``K phi = w^2 M phi``. LAPACK ``gejsv`` gets each of them with a
relative error of about ``eps kappa(B)``, ``A = D1 B D2``: graded rows (stiff links beside soft
mounts) and graded columns (grams beside tonnes) cost nothing. :func:`vibss.linear.eigen.undamped.undamped`
chooses this path for small models and for the modes ``eigh`` cannot certify.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.linalg as sl
import scipy.sparse as sp
from scipy.linalg import lapack

from .checks import _inverse_cholesky

__all__ = ["jacobi_svd", "TALL", "SMALL_PRODUCTS"]


def _jacobi(factor: Any, M: Any) -> tuple[np.ndarray, np.ndarray, float]:
    """All modes as singular values of ``A = G L^-T`` by LAPACK ``gejsv`` (joba 'G', row pivoting).

    ``gejsv`` pre-conditions by a QR factorisation with row sorting and column pivoting and then
    runs one-sided Jacobi, so each singular value has a *relative* error of about
    ``eps * kappa(B)`` where ``A = D1 B D2`` with diagonal D1, D2: graded rows (stiff links beside
    soft mounts) and graded columns (grams beside tonnes) cost nothing. Returns ``(w2, phi, bound)``
    with the ascending ``w2 = sigma^2``, mass-normalised ``phi = L^-T V`` and the relative error
    bound of every sigma (inf when LAPACK could not estimate the condition number).
    """
    li = _inverse_cholesky(M)
    if li is None:
        md = M.toarray() if sp.issparse(M) else np.asarray(M, float)
        li = np.linalg.inv(np.linalg.cholesky(md))
    n = li.shape[0]
    small = sp.issparse(factor) and sp.issparse(li) and n <= SMALL_PRODUCTS
    if small:
        a = _sparse_order_product(factor.toarray(), li.toarray())
    else:
        a = np.asarray((sp.csr_matrix(factor) @ sp.csr_matrix(li).T).toarray()) if sp.issparse(factor) \
            else np.asarray(factor, float) @ np.asarray(li.toarray() if sp.issparse(li) else li).T
    live = np.flatnonzero(np.any(a != 0, axis=0))    # a DOF no mount resists is exactly rigid
    v = np.zeros((n, n))
    sigma = np.zeros(n)
    sconda = 0.0
    if live.size:
        b = a[:, live]
        if b.shape[0] < live.size:                   # gejsv needs m >= n: zero rows change nothing
            b = np.vstack([b, np.zeros((live.size - b.shape[0], live.size))])
        sva, vl, work = jacobi_svd(b)
        sigma[:live.size] = (work[0] / work[1]) * sva
        v[live, :live.size] = vl
        sconda = float(work[2])
        rank = int(np.count_nonzero(sigma[:live.size] > live.size * np.finfo(float).eps * sigma[0]))
        if sconda <= 0 and 0 < rank < live.size:
            # rank deficient (rigid modes): LAPACK estimates no condition number; take it for
            # the elastic part, A restricted to the span of the elastic right singular vectors
            c = b @ vl[:, :rank]
            sconda = float(jacobi_svd(c, vectors=False)[2][2])
    dead = np.setdiff1d(np.arange(n), live)
    v[dead, live.size + np.arange(dead.size)] = 1.0
    order = np.argsort(sigma, kind="stable")
    bound = n * np.finfo(float).eps * sconda if sconda > 0 else (0.0 if not live.size else np.inf)
    vo = v[:, order]
    phi = _sparse_order_product(li.toarray().T, vo.T) if small else np.asarray(li.T @ vo)
    return sigma[order] ** 2, phi, bound


SMALL_PRODUCTS = 150
"""Up to this many DOFs, :func:`_jacobi` forms its two products with :func:`_sparse_order_product`."""


def _sparse_order_product(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """``x @ y.T`` summed as scipy.sparse sums it (``x`` CSR times ``y^T``, or a CSC ``x`` times a
    dense ``y^T``): each entry from zero, over the inner index in ascending order, one rounding per
    product and per addition (no fused multiply-add, no blocking). Structural zeros only add exact
    zeros, so a small model's eigen path gets the sparse products' digits bit for bit without
    their bookkeeping; the Jacobi SVD's accuracy on graded models depends on those digits."""
    out = np.zeros((x.shape[0], y.shape[0]))
    # Only the rows where x[:, k] is a stored nonzero take a term (as in scipy, which multiplies
    # stored entries only): adding a structural zero's product would add +-0, which leaves every
    # sum as it is (the sums start at +0 and never become -0), so the digits are the same; the work
    # is nnz(x) rows of y instead of n^2 per inner index (16 of 29 ms of the Jacobi path at 150 DOF)
    yt = np.ascontiguousarray(y.T)
    for k in range(x.shape[1]):
        rows = np.flatnonzero(x[:, k])
        if rows.size == x.shape[0]:
            out += x[:, k, None] * yt[k]
        elif rows.size:
            out[rows] += x[rows, k, None] * yt[k]
    return out


def _jacobi_floor(w2: np.ndarray) -> float:
    """The Jacobi SVD's absolute round-off floor of ``||G phi||`` [rad/s]: ``n eps sigma_max``.

    The computed right singular vector ``v`` of a zero singular value of ``A = G L^-T`` satisfies
    ``||A v|| <~ n eps ||A||`` (backward stability), and ``||G phi|| = ||A v||`` for the
    mass-normalised ``phi = L^-T v``; ``||A|| = sigma_max = omega_max``. A rigid mode whose shape
    touches the mounts only through that leakage (issue 18's fourth long run: ``||G phi|| = 9.9e-14``
    rad/s beside ``omega_max = 4.1e7`` rad/s, its per-mode ratio 1.5e-4) fails the relative test and
    the lever-arm floor, but not this one. An elastic mode is called rigid only below
    ``n eps omega_max`` (8e-15 of the top frequency at 36 DOFs, 3e-14 at :data:`JACOBI_MAX`), under
    the 1e-12 that separates frequencies of plausible mounts and masses (1e-2 ... 1e10 rad/s).
    """
    return float(w2.size * np.finfo(float).eps * np.sqrt(max(float(np.max(w2, initial=0.0)), 0.0)))


TALL = 2000
"""Rows above which :func:`jacobi_svd` does the row-sorted, column-pivoted QR itself (``gejsv``'s
own preprocessing, but through LAPACK's blocked ``geqp3``: 0.09 s instead of 0.84 s on 100,000 x 20)."""


def jacobi_svd(b: np.ndarray, vectors: bool = True) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Singular values and right singular vectors of ``b`` (m >= n) to high relative accuracy: the
    one Jacobi SVD of the eigen path (all modes, and the Ritz values of a refinement).

    LAPACK ``gejsv`` (joba 'G', row sorting and pivoting): each singular value has a relative error
    of about ``eps kappa(B)``, ``b = D1 B D2`` with diagonal D1, D2. For a tall ``b`` (more than
    :data:`TALL` rows and 4 n) its first step -- rows sorted by decreasing norm, a QR factorization
    with column pivoting ``b[:, p] = Q R`` (row-wise backward stable on row-sorted matrices, Cox and
    Higham) -- is done here by ``geqp3`` and ``gejsv`` runs on the n x n factor R: the singular
    values, and the columns' norms that scale the condition estimate, are R's; ``V = P V_R``.

    Parameters
    ----------
    b : (m, n) ndarray
    vectors : bool
        Compute ``V`` (else an empty array is returned for it).

    Returns
    -------
    sva : (n,) ndarray
        Singular values divided by ``work[0] / work[1]`` (descending, as LAPACK returns them).
    v : (n, n) ndarray
        Right singular vectors (columns).
    work : ndarray
        ``gejsv``'s work array: ``work[0] / work[1]`` scales ``sva``; ``work[2]`` estimates the
        scaled condition number (0 when it could not).
    """
    m, n = b.shape
    jobv = 0 if vectors else 3
    if m > max(TALL, 4 * n):
        rows = np.argsort(-np.einsum("ij,ij->i", b, b), kind="stable")
        r, piv = sl.qr(b[rows], mode="r", pivoting=True)
        sva, _, vr, work, _, info = lapack.dgejsv(np.ascontiguousarray(r[:n]), joba=3, jobu=3, jobv=jobv,
                                                  jobr=1, jobp=1)
        v = np.empty_like(vr)
        if vectors:
            v[piv] = vr
    else:
        sva, _, v, work, _, info = lapack.dgejsv(b, joba=3, jobu=3, jobv=jobv, jobr=1, jobp=1)
    if info != 0:
        raise np.linalg.LinAlgError(f"gejsv returned info={info}")
    return sva, v, work
