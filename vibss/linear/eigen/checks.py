"""Checks of computed undamped modes on the stiffness factor: the rigid-mode test and error bounds.

The factor ``G`` of ``K = G^T G`` (one row per mount principal axis,
:meth:`vibss.linear.plant.assemble.Assembly.stiffness_factor`) keeps every mount's stiffness apart, so
products with it do not cancel soft mounts against stiff links the way K formed in floats does.

- :func:`rigid_mask`: the one test of which computed modes are rigid-body modes;
- :func:`error_estimate`: a relative error bound of each computed frequency (Kato-Temple);
- block-diagonal mass helpers shared with :mod:`vibss.linear.eigen.undamped`.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import scipy.linalg as sl
import scipy.sparse as sp
import scipy.sparse.linalg as spl
from scipy.sparse.csgraph import connected_components

from ..solve.mass import mass_solver
from .small import inverse_cholesky

__all__ = ["rigid_mask", "error_estimate", "rayleigh_estimate", "mass_blocks", "RIGID_RTOL", "ROUNDOFF_LEVERS", "fast_matrix", "stiffness_solver"]

RIGID_RTOL = 1e-10
"""A mode is rigid when its stiffness cancels to round-off (see :func:`rigid_mask`):
``|G phi| <= RIGID_RTOL |G| |phi|`` with the stiffness factor G (``K = G^T G``), or
``phi^T K phi <= RIGID_RTOL^2 phi^T |K| phi``-like on K alone (the energy ratio is the square)."""

ROUNDOFF_LEVERS = 10.0
"""A mode whose ``||G phi||`` is below this many eps of :func:`_reach` (its motion times the
largest lever arms of the mounts it touches) is rigid, whatever the per-mode ratio says: the lever
arms are differences of positions and carry their round-off (eps |position|), so such a mode's
stiffness is round-off of the model's own data. Found by issue 18's fuzzer: a rotation about an axis
through every mount up to 1e-15 m (both norms of the ratio test ~1e-13) was printed as a 0 Hz elastic
mode; the 60-digit reference has w^2 = 1.5e-54 there. An elastic mode has ``||G phi||`` above this
unless its lever arms are below ~1e-14 of the mounts' own."""

def _issparse(x: Any) -> bool:
    """:func:`scipy.sparse.issparse`, an array answered first (scipy's class check costs about a
    microsecond, and a 6-DOF model's eigen path asks it some twenty times)."""
    return not isinstance(x, np.ndarray) and sp.issparse(x)


_EPS = float(np.finfo(float).eps)
"""The unit round-off of float64 [-] (``np.finfo`` costs a microsecond a call on small models)."""

_BLOCK_MAX = 12
"""Largest diagonal block of M that :func:`generalized_eigh` factorises on its own."""


_DENSE_PATTERN = 150
"""A dense mass matrix up to this size is read by NumPy indexing in :func:`_inverse_cholesky`."""


def _inverse_cholesky(M: Any) -> Any:
    """Sparse ``L^-1`` with ``M = L L^T``, block by block (M block-diagonal), or None.

    Rigid bodies have 6x6 mass blocks with no coupling between bodies, so ``M`` splits into small
    diagonal blocks (the connected components of its pattern); each is factorised on its own.
    None when a block is larger than :data:`_BLOCK_MAX` or not positive definite.
    """
    dense = not _issparse(M) and np.shape(M)[0] <= _DENSE_PATTERN
    Ms = np.asarray(M, float) if dense else sp.csr_matrix(M)
    n = Ms.shape[0]
    # a small dense M: the same components from its dense pattern, the blocks read by NumPy indexing
    # (the same numbers, without scipy.sparse's bookkeeping on a 6 x 6 problem)
    labels = _components(Ms != 0) if dense else connected_components(Ms != 0, directed=False)[1]
    if n == 0 or np.bincount(labels).max() > _BLOCK_MAX:
        return None
    rows, cols, vals = [], [], []
    sizes = np.bincount(labels)
    order = np.argsort(labels, kind="stable")          # DOFs grouped by block, blocks in label order
    starts = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    for size in np.unique(sizes):                      # all blocks of one size at once
        first = starts[sizes == size]
        idx = order[first[:, None] + np.arange(size)[None, :]]            # (blocks, size)
        r = np.broadcast_to(idx[:, :, None], idx.shape + (size,))
        c = np.broadcast_to(idx[:, None, :], idx.shape + (size,))
        blocks = (Ms[r, c] if dense else np.asarray(Ms[r.ravel(), c.ravel()]).reshape(r.shape)).astype(float)
        try:
            inv = inverse_cholesky(blocks)
        except np.linalg.LinAlgError:
            return None
        rows.append(r.ravel())
        cols.append(c.ravel())
        vals.append(inv.ravel())
    return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n))


def _components(pattern: np.ndarray) -> np.ndarray:
    """Connected components of a small symmetric dense pattern: each DOF's label is the smallest
    index it connects to, numbered 0, 1, ... in that order (the blocks, and their DOFs in ascending
    order, are those of ``scipy.sparse.csgraph.connected_components``)."""
    n = pattern.shape[0]
    linked = pattern | pattern.T
    labels = np.arange(n)
    while True:
        new = np.minimum(labels, np.where(linked, labels[None, :], n).min(axis=1, initial=n))
        if np.array_equal(new, labels):
            return np.unique(labels, return_inverse=True)[1].reshape(n)     # numbered 0, 1, ...
        labels = new


def _as_factor(factor: Any) -> Any:
    """A sparse factor with sorted indices, copied if needed: products never sort the caller's
    matrix in place (which would change the summation order, hence the last bits, between calls)."""
    if _issparse(factor):
        if sp.isspmatrix_csr(factor) and factor.has_sorted_indices:
            return factor           # nothing will sort it: no copy (a new CSR object costs ~15 us)
        g = sp.csr_matrix(factor)
        return g if g.has_sorted_indices else g.sorted_indices()
    return np.asarray(factor, float)


def _factor_norms(factor: Any, phi: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``G phi``, ``||G phi||`` and ``|| |G| |phi| ||`` per column (G sparse or dense)."""
    g = sp.csr_matrix(factor) if _issparse(factor) else np.asarray(factor, float)
    gphi = np.asarray(g @ phi)
    absg = abs(g) if _issparse(g) else np.abs(g)
    agp = np.asarray(absg @ np.abs(phi))
    return gphi, np.sqrt(np.einsum("ij,ij->j", gphi, gphi)), np.sqrt(np.einsum("ij,ij->j", agp, agp))


def rigid_mask(shapes: np.ndarray, K: Any = None, factor: Any = None, floor: float = 0.0,
               norms: tuple | None = None) -> np.ndarray:
    """Which computed modes are rigid-body (zero-frequency) modes: the one test.

    A mode is rigid when its stiffness cancels to round-off: ``||X phi|| <= RIGID_RTOL ||X| |phi||
    + ROUNDOFF_LEVERS eps reach(X, phi) + floor`` (:func:`_reach`, :data:`ROUNDOFF_LEVERS`;
    ``floor``: the eigen-solver's backward error, ``n eps omega_max`` for the Jacobi SVD) with X the
    stiffness factor G (``K = G^T G``; preferred) or K itself. For a true null
    vector the left side is round-off (~1e-16 of the right); an elastic mode stores stiffness energy
    (a 0.005 Hz suspension mode beside 1e6 N/m links: ~1e-5; six isolation modes beside 1e16 N/m
    links, on the factor: ~1e-6). The test looks at each mode alone, so it does not depend on how
    many modes were computed, and both sides scale alike with the units.

    Parameters
    ----------
    shapes : (n, k) ndarray
        Mass-normalised shapes.
    K : (n, n) array_like or sparse, optional
        Stiffness matrix (used when no factor is given).
    factor : (r, n) array_like or sparse, optional
        Stiffness factor G with ``K = G^T G``.
    floor : float
        Absolute round-off floor of ``||X phi||`` (the backward error of the eigen-solver).
    norms : tuple, optional
        ``(G phi, ||G phi||, || |G| |phi| ||)`` when already computed (``_factor_norms``).

    Returns
    -------
    (k,) bool ndarray
    """
    if factor is not None:
        _, num, den = _factor_norms(factor, shapes) if norms is None else norms
        x: Any = _as_factor(factor)
    else:
        x = sp.csr_matrix(K) if _issparse(K) else np.asarray(K, float)
        num = np.linalg.norm(np.asarray(x @ shapes), axis=0)
        den = np.linalg.norm(np.asarray(abs(x) @ np.abs(shapes)), axis=0)
    lever = ROUNDOFF_LEVERS * _EPS
    # _reach(x, phi) <= ||rows|| ||phi||: only a mode under that ceiling needs its reach (a product
    # with the whole factor's pattern); for the others the test is decided without it
    ceiling = RIGID_RTOL * den + 2 * lever * _row_sums_norm(x) * np.sqrt(np.einsum("ij,ij->j", shapes, shapes)) + floor
    rigid = np.zeros(num.shape, bool)
    maybe = np.flatnonzero(~(num > ceiling))
    if maybe.size:
        rigid[maybe] = num[maybe] <= RIGID_RTOL * den[maybe] + lever * _reach(x, shapes[:, maybe]) + floor
    return rigid


def _row_sums_norm(x: Any) -> float:
    """``||rows||`` with ``rows_q = sum_i |X_qi|`` (the bound of :func:`_reach` per unit shape)."""
    rows = np.asarray(abs(x).sum(axis=1)).ravel() if _issparse(x) else np.abs(np.asarray(x, float)).sum(axis=1)
    return math.sqrt(float(rows @ rows))       # np.linalg.norm of a vector: sqrt(x . x), without its wrapper


def _reach(x: Any, shapes: np.ndarray) -> np.ndarray:
    """Per mode, ``||rho||`` with ``rho_q = (sum_i |X_qi|) ||phi_(supp q)||``: what each row of X
    (a mount axis) would see if the mode's largest motion among the DOFs that row touches went
    through its largest lever arm. The scale of the round-off of ``X phi`` that lever arms computed
    from positions leave (:data:`ROUNDOFF_LEVERS`)."""
    if _issparse(x):
        a = abs(sp.csr_matrix(x))
        pattern = a.copy()
        pattern.data[:] = 1.0
        rows = np.asarray(a.sum(axis=1)).ravel()
    else:
        a = np.abs(np.asarray(x, float))
        pattern = (a > 0).astype(float)
        rows = a.sum(axis=1)
    local = np.sqrt(np.asarray(pattern @ (shapes * shapes)))           # (r, k)
    return np.linalg.norm(rows[:, None] * local, axis=0)


def _trace_norm(M: Any, K: Any = None, factor: Any = None) -> float:
    """``||L^-1 K L^-T||_F``-like scale ``sqrt(trace(M^-1 K))``: an upper bound of ``sqrt(w2_max)``."""
    md = M.diagonal() if _issparse(M) else np.asarray(M, float).diagonal()
    if factor is not None:
        g: Any = _as_factor(factor)
        col = np.asarray(g.multiply(g).sum(axis=0)).ravel() if _issparse(g) else np.add.reduce(g * g, axis=0)
    else:
        col = np.abs(K.diagonal() if _issparse(K) else np.asarray(K, float).diagonal())
    # (np.sum and np.sqrt as their ufuncs: the same sums and rounding, without the Python wrappers)
    return math.sqrt(float(np.add.reduce(col / np.where(md > 0, md, 1.0))) * 10)


def mass_blocks(M: Any) -> tuple[np.ndarray, np.ndarray] | None:
    """``(blocks, inverse)`` of a dense M that is block diagonal with 6x6 blocks: its (n/6, 6, 6)
    blocks and their inverse Cholesky factors ``L^-1`` (``M_b = L L^T``), computed once for the
    eigen solve and its bounds; None for any other M (raises for a block that is not positive
    definite)."""
    blocks = _six_blocks(M)
    return None if blocks is None else (blocks, inverse_cholesky(blocks))


def _six_blocks(M: Any) -> np.ndarray | None:
    """(n/6, 6, 6) diagonal blocks of M when M is block diagonal with 6x6 blocks, else None."""
    if _issparse(M) or M.shape[0] % 6 or M.shape[0] == 0:
        return None
    m = np.asarray(M, float)
    nb = m.shape[0] // 6
    if nb == 1:
        return m.reshape(1, 6, 6)            # one body: its mass matrix is its block
    blocks = m.reshape(nb, 6, nb, 6)[np.arange(nb), :, np.arange(nb), :]
    if np.count_nonzero(blocks) != np.count_nonzero(m):
        return None
    return blocks


def error_estimate(w2: np.ndarray, phi: np.ndarray, M: Any, K: Any = None, factor: Any = None,
                   rigid: np.ndarray | None = None, li: Any = None, norms: tuple | None = None,
                   blocks: tuple[np.ndarray, np.ndarray | None] | None = None) -> np.ndarray:
    """Relative error bound of each computed natural frequency ``sqrt(w2)`` (see :func:`_bound`)."""
    return _bound(w2, phi, M, K, factor, rigid, li, norms, blocks)[0]


def rayleigh_estimate(phi: np.ndarray, M: Any, K: Any = None, factor: Any = None,
                      rigid: np.ndarray | None = None, norms: tuple | None = None,
                      blocks: tuple[np.ndarray, np.ndarray | None] | None = None
                      ) -> tuple[np.ndarray, np.ndarray]:
    """``(rho, est)``: the Rayleigh quotients of the shapes [rad^2/s^2] and the bound of their
    frequencies (:func:`_bound` with ``w2 = rho``).

    To first order the quotient is bounded no wider than the eigenvalue the shape came with (the
    bound of a computed ``w2`` is the quotient's plus ``|w2 - rho|``; the gaps here are to the
    neighbours' quotients), and on the factor it is accurate to second order in the shape's error,
    where ``eigh``'s own value carries its absolute error ``eps w2_max`` (``eps w2_max / w2``
    relatively on a low mode). The shape itself keeps its first-order error."""
    est, rho = _bound(None, phi, M, K, factor, rigid, None, norms, blocks)
    return rho, est


def _bound(w2: np.ndarray | None, phi: np.ndarray, M: Any, K: Any = None, factor: Any = None,
           rigid: np.ndarray | None = None, li: Any = None, norms: tuple | None = None,
           blocks: tuple[np.ndarray, np.ndarray | None] | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Relative error bound of each computed natural frequency ``sqrt(w2)``, and the Rayleigh quotients.

    Residual-based (Kato-Temple): with the Rayleigh quotient ``rho = ||G phi||^2 / phi^T M phi``
    (on the factor: no cancellation against stiff links), the residual ``r = G^T G phi - rho M phi``
    in the ``M^-1`` norm ``e`` and the gap ``d`` from ``rho`` to the other computed eigenvalues,
    an eigenvalue lies within ``min(e, e^2 / d)`` of ``rho``. The estimate of ``|w - w_true| / w`` is
    ``(|w2 - rho| + min(e, e^2 / d)) / (2 rho)`` plus the round-off of ``rho`` itself
    (``k eps / c`` with ``c = ||G phi|| / || |G| |phi| ||``), and never below ``4 sqrt(n) eps``.
    Rigid modes get NaN (their 0 is exact).

    Parameters
    ----------
    w2 : (k,) ndarray or None
        Computed eigenvalues [rad^2/s^2] (None: the shapes' Rayleigh quotients).
    phi : (n, k) ndarray
        Their shapes.
    M : (n, n) array_like or sparse
        Mass matrix.
    K, factor : optional
        Stiffness matrix, or its factor G (``K = G^T G``; preferred).
    rigid : (k,) bool ndarray, optional
        Rigid-body modes (estimate NaN).
    li : sparse matrix, optional
        ``L^-1`` with ``M = L L^T`` when already known.
    norms : tuple, optional
        ``(G phi, ||G phi||, || |G| |phi| ||)`` when already computed.
    blocks : tuple, optional
        :func:`mass_blocks` of ``M`` when already computed (a dense M).

    Returns
    -------
    est : (k,) ndarray
        Relative error bound of each frequency [-] (``w2`` None: of the quotients').
    rho : (k,) ndarray
        Rayleigh quotients ``phi^T K phi / phi^T M phi`` [rad^2/s^2].
    """
    eps = _EPS
    if blocks is None:
        six = _six_blocks(M)
        blocks = None if six is None else (six, None)
    if blocks is not None:
        mphi = np.matmul(blocks[0], phi.reshape(blocks[0].shape[0], 6, -1)).reshape(phi.shape)
    else:
        mphi = np.asarray((sp.csr_matrix(M) if _issparse(M) else fast_matrix(np.asarray(M, float))) @ phi)
    norm2 = np.einsum("ij,ij->j", phi, mphi)
    # one error state for the whole bound (a 6-DOF model's bound is a few dozen 6-vector steps, and
    # entering np.errstate costs as much as several of them): 0 / 0 and x / 0 give NaN and inf,
    # which the bound turns into inf below
    with np.errstate(divide="ignore", invalid="ignore"):
        if factor is not None:
            g: Any = _as_factor(factor)
            gphi, num, den = _factor_norms(g, phi) if norms is None else norms
            kphi = np.asarray(g.T @ gphi)
            per_row = np.diff(g.indptr).max(initial=1) if _issparse(g) else g.shape[1]
            rho = num ** 2 / norm2
            rounding = (per_row + 2) * eps * den / num
        else:
            k: Any = sp.csr_matrix(K) if _issparse(K) else np.asarray(K, float)
            kphi = np.asarray(k @ phi)
            per_row = np.diff(k.indptr).max(initial=1) if _issparse(k) else k.shape[1]
            rho = np.einsum("ij,ij->j", phi, kphi) / norm2
            absk = abs(k) if _issparse(k) else np.abs(k)
            rounding = (per_row + 2) * eps * np.einsum("ij,ij->j", np.abs(phi), np.asarray(absk @ np.abs(phi))) \
                / np.abs(rho) / norm2
        r = kphi - rho[None, :] * mphi
        if blocks is not None:                   # rigid bodies: 6x6 mass blocks on the diagonal
            inverse = blocks[1] if blocks[1] is not None else inverse_cholesky(blocks[0])
            y = np.matmul(inverse, r.reshape(blocks[0].shape[0], 6, -1))
            e = np.sqrt(np.einsum("bij,bij->j", y, y))
        elif (li := _inverse_cholesky(M) if li is None else li) is not None:
            e = np.linalg.norm(np.asarray(li @ r), axis=0)
        else:
            md = M.toarray() if _issparse(M) else np.asarray(M, float)
            e = np.sqrt(np.abs(np.einsum("ij,ij->j", r, mass_solver(md)(r))))
        e = e / np.sqrt(norm2)
        lam = rho if w2 is None else np.asarray(w2, float)
        gap = np.full(lam.shape, np.inf)
        if lam.size > 1:                       # ascending: the nearest others are the neighbours
            gap[1:] = np.abs(rho[1:] - lam[:-1])
            gap[:-1] = np.minimum(gap[:-1], np.abs(rho[:-1] - lam[1:]))
        shift = np.minimum(e, e * e / gap)
        est = (np.abs(lam - rho) + shift) / (2 * np.abs(rho)) + rounding
    # floor: the round-off of any eigen-solver's answer (and of the reference it is checked against)
    est = np.maximum(est, 4 * math.sqrt(phi.shape[0]) * eps)
    est[~np.isfinite(est)] = np.inf
    if rigid is not None:
        est[np.asarray(rigid, bool)] = np.nan
    return est, rho


def fast_matrix(a: np.ndarray) -> Any:
    """``a`` as CSR when it is mostly zeros (a mass matrix: 6x6 blocks), for cheap products."""
    return sp.csr_matrix(a) if np.count_nonzero(a) < 0.05 * a.size else a


def stiffness_solver(k: np.ndarray) -> Any:
    """``b -> k^-1 b`` by sparse LU when ``k`` is mostly zeros, else dense LU (raises if singular)."""
    if np.count_nonzero(k) < 0.05 * k.size:
        lu = spl.splu(sp.csc_matrix(k))
        return lambda b: lu.solve(np.asarray(b, dtype=lu.U.dtype) if np.isrealobj(b) else b)
    fac = sl.lu_factor(k, check_finite=False)
    if np.any(np.diag(fac[0]) == 0):
        raise np.linalg.LinAlgError("singular stiffness")
    return lambda b: sl.lu_solve(fac, b, check_finite=False)
