"""The one eigen path: undamped modes ``K phi = w^2 M phi``, the rigid-mode test, the modal basis.

Every consumer (the modes table, damped modes, FRFs, state space, modal time responses, pruning,
truncation, Krylov checks, diagnostics) takes its undamped modes from here.

- :func:`undamped`: the one entry every consumer calls: modes, rigid flags and a per-mode error
  bound. With the stiffness *factor* ``G`` (``K = G^T G``, :meth:`Assembly.stiffness_factor`) a
  small model is solved by a Jacobi SVD of ``G L^-T`` (``M = L L^T``; LAPACK ``gejsv``), which
  gives every frequency to high *relative* accuracy even where K formed in floats has lost the soft
  mounts beside stiff links; a large one by ``eigh`` with an a-posteriori test that refines only the
  modes that need it;
- :func:`generalized_eigh`: all modes or the lowest ``n_modes`` (block Cholesky of M, LAPACK
  ``syevd``/``syevr``); :data:`METHODS` names the dense, Jacobi and sparse shift-invert solvers;
- :func:`rigid_mask`: the one test of which computed modes are rigid-body modes;
- :func:`error_estimate`: relative error bound of each frequency (Kato-Temple on the factored
  residual, and the Jacobi SVD's own bound);
- :func:`symmetric_eigen`, :func:`projected_eigen`: the small symmetric problems (cluster rotations,
  principal axes, projected Ritz problems) so that every eigen solve lives in this module;
- :func:`modal_basis`: the mass-normalised basis of a :class:`~vibss.linear.plant.plant.Plant`, with
  low modes refined to relative accuracy where a light damping would amplify their error;
- :func:`damping_coupling`: the one test of classical damping on a projected damping matrix.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import partial
from typing import Any, cast

import numpy as np
import scipy.linalg as sl
import scipy.sparse as sp
import scipy.sparse.linalg as spl
from scipy.linalg import lapack

from ..._validate import choice
from ...results import ReadOnly
from ...errors import ModelError
from .checks import (RIGID_RTOL, _as_factor, _factor_norms, _inverse_cholesky, _six_blocks, _trace_norm,
                           error_estimate, fast_matrix, rigid_mask, stiffness_solver)
from ..plant.plant import Plant

__all__ = ["generalized_eigh", "rigid_mask", "damping_coupling", "modal_basis", "ModalBasis", "METHODS",
           "RIGID_RTOL", "CLASSICAL_RTOL", "fast_matrix", "stiffness_solver", "Solver", "Spectrum",
           "undamped", "error_estimate", "symmetric_eigen", "projected_eigen", "JACOBI_MAX",
           "generalized_eigvals"]

Solver = Callable[[Any, Any, "int | None"], "tuple[np.ndarray, np.ndarray]"]

JACOBI_MAX = 150
"""Largest number of DOFs solved by the Jacobi SVD of the factored problem by default (it costs
about 8 times ``eigh``: ~5 ms at 150 DOF, ~0.8 s at 600 DOF); larger models use ``eigh`` with
a-posteriori refinement."""

JACOBI_FALLBACK = 1500
"""Above :data:`JACOBI_MAX` and up to this many DOFs, the ``eigh`` path falls back to the Jacobi SVD
when refinement leaves a mode whose error estimate exceeds :data:`FREQ_RTOL`."""

FREQ_RTOL = 1e-10
"""Target relative accuracy of every elastic frequency; modes whose estimate exceeds it (times the
resonance amplification 1 / 2 zeta in :func:`modal_basis`) are refined."""

def generalized_eigh(K: Any, M: Any, n_modes: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """``K phi = w^2 M phi`` (all modes, or the lowest ``n_modes``), ``phi^T M phi = I``.

    A block-diagonal ``M`` (rigid bodies) is factorised per block, and the standard problem
    ``L^-1 K L^-T`` is solved by LAPACK's divide and conquer (``syevd``; ``syevr`` for a subset):
    the same steps as :func:`scipy.linalg.eigh` ``(K, M)`` (``sygvd``) without its O(n^3)
    dense reduction to standard form, about 35 % faster at 600 DOF. Other mass matrices go to
    :func:`scipy.linalg.eigh` ``(K, M)``.

    Parameters
    ----------
    K, M : (n, n) array_like or sparse matrix
        Stiffness [N/m] and mass [kg] matrices (symmetric; M positive definite).
    n_modes : int or None
        Number of lowest modes (None: all).

    Returns
    -------
    w2 : (k,) ndarray
        Eigenvalues ``omega^2`` [rad^2/s^2], ascending.
    phi : (n, k) ndarray
        Mass-normalised mode shapes.

    Examples
    --------
    >>> K = np.array([[2.0, -1.0], [-1.0, 2.0]]) * 100
    >>> w2, phi = generalized_eigh(K, np.diag([1.0, 2.0]))
    >>> bool(np.allclose(w2, sl.eigh(K, np.diag([1.0, 2.0]), eigvals_only=True)))
    True
    """
    K = K.toarray() if sp.issparse(K) else np.asarray(K, float)
    subset = None if n_modes is None or n_modes >= K.shape[0] else [0, n_modes - 1]
    blocks = _six_blocks(M) if K.shape[0] > SMALL_PRODUCTS else None
    if blocks is not None:
        # rigid bodies: L^-1 per 6x6 mass block, applied as one batched product (the sparse L^-1
        # costs three CSR products with n columns, about 10 ms at 600 DOF)
        lib = np.linalg.inv(np.linalg.cholesky(blocks))
        nb, n = blocks.shape[0], K.shape[0]
        half = np.matmul(lib, K.reshape(nb, 6, n)).reshape(n, n)           # L^-1 K
        a = np.matmul(lib, half.T.reshape(nb, 6, n)).reshape(n, n)          # L^-1 K L^-T
        a = 0.5 * (a + a.T)
        w2, u = sl.eigh(a, subset_by_index=subset, driver="evd" if subset is None else "evr",
                        check_finite=False)
        k = u.shape[1]
        phi = np.matmul(np.swapaxes(lib, 1, 2), u.reshape(nb, 6, k)).reshape(n, k)   # L^-T u
        return w2, phi
    li = _inverse_cholesky(M)
    if li is None:
        M = M.toarray() if sp.issparse(M) else M
        return sl.eigh(K, M, subset_by_index=subset, check_finite=False)
    a = li @ (li @ K).T                     # L^-1 K L^-T (K symmetric)
    a = 0.5 * (a + a.T)
    w2, u = sl.eigh(a, subset_by_index=subset, driver="evd" if subset is None else "evr",
                    check_finite=False)
    return w2, np.asarray(li.T @ u)


def generalized_eigvals(K: Any, M: Any) -> np.ndarray:
    """(n,) eigenvalues ``w^2`` [rad^2/s^2] of ``K phi = w^2 M phi``, ascending, without vectors.

    For a bound that needs only the spectrum's extent (the stable step of an explicit integrator).
    """
    K = K.toarray() if sp.issparse(K) else np.asarray(K, float)
    li = _inverse_cholesky(M)
    if li is None:
        return sl.eigh(K, M.toarray() if sp.issparse(M) else M, eigvals_only=True, check_finite=False)
    a = li @ (li @ K).T
    return sl.eigh(0.5 * (a + a.T), eigvals_only=True, check_finite=False)


def _dense(K: Any, M: Any, n_modes: int | None) -> tuple[np.ndarray, np.ndarray]:
    return generalized_eigh(K, M, n_modes)


def _shift_invert(K: Any, M: Any, n_modes: int | None) -> tuple[np.ndarray, np.ndarray]:
    n = K.shape[0]
    if n_modes is None or n_modes >= n - 1:
        raise ModelError("method 'shift-invert' needs n_modes smaller than the number of DOFs - 1; "
                         "use method='dense' for all modes")
    K = sp.csc_matrix(K)
    M = sp.csc_matrix(M)
    # A small negative shift keeps K - sigma M positive definite even with rigid-body modes.
    scale = np.median(K.diagonal()[K.diagonal() > 0] / M.diagonal()[K.diagonal() > 0]) if K.nnz else 1.0
    sigma = -1e-6 * scale
    # a fixed starting vector: ARPACK's own is random, so two runs could differ in the last digits
    # (and a greedy reduction built on them in its basis size)
    v0 = np.random.default_rng(0).standard_normal(n)
    w2, v = spl.eigsh(K, k=n_modes, M=M, sigma=sigma, which="LM", v0=v0)
    order = np.argsort(w2)
    return w2[order], v[:, order]


METHODS: dict[str, Solver] = {"dense": _dense, "shift-invert": _shift_invert}


CLASSICAL_RTOL = 1e-10
"""Damping is classical when every off-diagonal of Phi^T C Phi is below this times sqrt(g_ii g_jj)."""


def damping_coupling(projected: np.ndarray) -> np.ndarray:
    """How far each off-diagonal of a projected damping matrix exceeds the classical bound.

    The one test of classical damping that damped modes, frequency and time responses share: modes
    i and j are coupled when ``|g_ij| > CLASSICAL_RTOL * sqrt(|g_ii g_jj|) + 64 eps max|g_kk|``
    (the second term is the round-off of ``Phi^T C Phi`` itself).

    Parameters
    ----------
    projected : (k, k) ndarray
        ``Phi^T C Phi`` (or ``Phi^T H Phi``) with mass-normalised shapes.

    Returns
    -------
    (k, k) ndarray
        Off-diagonal magnitude minus its bound: positive where modes are coupled (diagonal negative).
    """
    d = np.abs(np.diag(projected))
    off = np.abs(projected - np.diag(np.diag(projected)))
    bound = CLASSICAL_RTOL * np.sqrt(np.outer(d, d)) + 64 * np.finfo(float).eps * d.max(initial=0.0)
    return off - bound - np.diag(np.ones_like(d))


def symmetric_eigen(a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Eigenvalues (ascending) and orthonormal eigenvectors of a small symmetric matrix, or of a
    stack of them (``(..., k, k)``: one LAPACK call for every matrix, e.g. 100,000 Monte Carlo
    variants of a 6-DOF layout).

    The one call for the small problems (cluster rotations, principal axes of an inertia tensor,
    projected damping blocks, batched variants); ``a`` is symmetrised first.

    Examples
    --------
    >>> w, v = symmetric_eigen(np.array([[2.0, 1.0], [1.0, 2.0]]))
    >>> w.round(12).tolist()
    [1.0, 3.0]
    """
    a = np.asarray(a)
    return np.linalg.eigh(0.5 * (a + np.swapaxes(a, -1, -2)))


def projected_eigen(kr: np.ndarray, mr: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``kr t = w2 mr t`` for a small projected (Ritz, Krylov) pair, ``t^T mr t = I``.

    Parameters
    ----------
    kr, mr : (k, k) ndarray
        Projected stiffness and (positive definite) mass; symmetrised first.
    """
    return sl.eigh(0.5 * (kr + kr.T), 0.5 * (mr + mr.T), check_finite=False)


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
    for k in range(x.shape[1]):
        out = out + x[:, k, None] * y[None, :, k]
    return out


@dataclass(frozen=True, eq=False)
class Spectrum(ReadOnly):
    """Undamped modes from :func:`undamped`.

    Attributes
    ----------
    omega2 : (k,) ndarray
        Squared natural frequencies [rad^2/s^2], ascending; exactly 0 for rigid-body modes.
    phi : (n, k) ndarray
        Mass-normalised shapes.
    rigid : (k,) bool ndarray
        Rigid-body modes.
    error : (k,) ndarray
        Relative error bound of each frequency (NaN for rigid modes: their 0 is exact).
    method : str
        Solver used (``"jacobi"``, ``"dense"``, ``"shift-invert"`` or a callable's name), with
        ``"+refined"`` when modes were refined.
    """

    omega2: np.ndarray
    phi: np.ndarray
    rigid: np.ndarray
    error: np.ndarray
    method: str


def undamped(K: Any, M: Any, factor: Any = None, n_modes: int | None = None,
             method: "str | Solver" = "auto",
             also: "Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray] | None" = None) -> Spectrum:
    """The one undamped eigen solve ``K phi = w^2 M phi``: modes, rigid flags and error bounds.

    Parameters
    ----------
    K, M : (n, n) array_like or sparse matrix
        Stiffness [N/m ...] and mass [kg ...] matrices.
    factor : (r, n) array_like or sparse, optional
        Stiffness factor G with ``K = G^T G`` (:meth:`vibss.linear.plant.assemble.Assembly.stiffness_factor`).
        With it the frequencies are exact to high relative accuracy on badly scaled models.
    n_modes : int or None
        Number of lowest modes (None: all). The rigid test does not depend on it.
    method : {"auto", "jacobi", "dense", "shift-invert"} or callable
        ``"auto"``: Jacobi SVD of the factored problem up to :data:`JACOBI_MAX` DOFs, dense
        ``eigh`` (refined where its estimate exceeds :data:`FREQ_RTOL`) above; shift-invert for a
        sparse model when fewer than a tenth of the modes are asked for. A callable
        ``f(K, M, n_modes) -> (w2, phi)`` is used as given (its modes are still tested and estimated).
    also : callable, optional
        ``also(w2, phi, error) -> (k,) bool``: modes a consumer needs more accurate than
        :data:`FREQ_RTOL` (e.g. amplified at a light resonance, :func:`modal_basis`). On the
        ``eigh`` path without rigid modes they (and every mode below them) are refined in the same
        sweep as the modes this function refines for itself.

    Returns
    -------
    Spectrum

    Examples
    --------
    >>> K = np.array([[2.0, -1.0], [-1.0, 1.0]]) * 100
    >>> s = undamped(K, np.eye(2), factor=np.array([[10.0, 0.0], [-10.0, 10.0]]))
    >>> bool(np.allclose(s.omega2, np.linalg.eigvalsh(K))), bool(s.error.max() < 1e-12)
    (True, True)
    """
    n = K.shape[0]
    factor = None if factor is None else _as_factor(factor)
    if factor is not None and (factor.ndim != 2 or factor.shape[1] != n):
        raise ModelError(f"factor: the stiffness factor has shape {factor.shape}, K has {n} DOFs; a plant "
                         "restricted or projected must carry Kf[:, dofs] (or Kf @ V), or None")
    if n == 0:
        return Spectrum(np.zeros(0), np.zeros((0, 0)), np.zeros(0, bool), np.zeros(0), "dense")
    if callable(method):
        name = getattr(method, "__name__", "custom")
    elif method == "auto":
        if sp.issparse(K) and n_modes is not None and n_modes < n // 10 and n > JACOBI_MAX:
            name = "shift-invert"
        elif factor is not None and n <= JACOBI_MAX:
            name = "jacobi"
        else:
            name = "dense"
    else:       # a name: one of the solvers, or an ArgumentError with did-you-mean
        name = str(choice(method, "method", ["auto", "jacobi", *METHODS], who="modes"))
    if name == "jacobi" and factor is None:
        name = "dense"
    bound = np.inf
    floor = 0.0
    if name == "jacobi":
        w2, phi, bound = _jacobi(factor, M)
        floor = _jacobi_floor(w2)
    else:
        solver = method if callable(method) else METHODS[name]
        guard = n_modes
        if n_modes is not None and name == "dense":   # a guard band: Ritz on k modes alone converges
            guard = min(n, max(2 * n_modes, n_modes + 12))  # slowly for the top ones (shift-invert's
            #                                                 modes are already inverse iterates)
        w2, phi = solver(K, M, guard)
        w2, phi = np.asarray(w2, float), np.asarray(phi, float)
        # eigh's null vectors have ||A phi||^2 ~ eps w2_max: the floor is sqrt(eps) of the top.
        # Shift-invert's lowest modes are the dominant ones of (K - sigma M)^-1 M, computed to
        # relative accuracy: no such floor (at 60,000 DOF it flagged 2 Hz modes as doubtful and
        # refined all 20 for 2.6 s of a 7.6 s eigsh, to the same frequencies within 2.4e-13)
        floor = 0.0 if name == "shift-invert" and not callable(method) else \
            np.sqrt(10 * n * np.finfo(float).eps) * _trace_norm(M, K, factor)
    norms = None if factor is None else _factor_norms(factor, phi)
    rigid = rigid_mask(phi, K, factor, floor, norms)
    est = error_estimate(w2, phi, M, None if factor is not None else K, factor, rigid, norms=norms)
    est = np.minimum(est, bound)
    if name in ("dense", "shift-invert") and not callable(method):
        # eigh cannot tell a rigid mode from one below sqrt(eps) of the top: refine every mode up to
        # the last doubtful one (shifted, so rigid modes are allowed), then test on the factor alone
        need = rigid | (est > FREQ_RTOL)
        asked = also is not None and name == "dense" and not np.any(rigid)
        if also is not None and asked:
            need = need | np.asarray(also(w2, phi, est), bool)
        if np.any(need) and (factor is not None or not np.any(rigid)):
            above = w2[~rigid]
            shift = 0.0
            if np.any(rigid):                  # shifted, so that rigid modes are allowed
                kd_, md_ = (np.abs(np.asarray(x.diagonal() if sp.issparse(x) else np.diag(x), float)) for x in (K, M))
                ratio = kd_[md_ > 0] / md_[md_ > 0]
                shift = 1e-3 * float(above.min()) if above.size and above.min() > 0 else \
                    1e-6 * float(np.median(ratio[ratio > 0])) if np.any(ratio > 0) else 1.0
            refined = False
            for _ in range(3):                 # a few sweeps of subspace inverse iteration
                w2, phi, est, ok = _refine(K, M, factor, w2, phi, est, need, shift, whole=True,
                                           estimate=factor is None)   # with a factor: tested below
                if not ok:
                    break
                refined = True
                if factor is not None:
                    # the refined modes and the one above them (its gap changed) are tested again; the
                    # others are unchanged, and were not rigid even with the floor
                    head = min(int(np.flatnonzero(need).max()) + 2, w2.size)
                    cols = slice(0, min(head + 1, w2.size))     # one more: the last one's gap is whole
                    nrm = _factor_norms(factor, phi[:, cols])
                    rig = rigid_mask(phi[:, cols], K, factor, norms=nrm)
                    e_head = error_estimate(w2[cols], phi[:, cols], M, None, factor, rig, norms=nrm)
                    rigid, est = rigid.copy(), est.copy()
                    rigid[:head], est[:head] = rig[:head], e_head[:head]
                need = ~rigid & (est > FREQ_RTOL)
                if not np.any(need):
                    break
            name += "+refined" if refined else ""
        if factor is not None and n <= JACOBI_FALLBACK and np.any(~rigid & ~(est <= FREQ_RTOL)):
            # eigh and its refinement cannot certify some mode (a strongly graded model): the Jacobi
            # SVD can, at ~8x the cost of eigh
            w2, phi, bound = _jacobi(factor, M)
            rigid = rigid_mask(phi, K, factor, _jacobi_floor(w2))
            est = np.minimum(error_estimate(w2, phi, M, None, factor, rigid), bound)
            name = "jacobi (eigh could not certify every mode)"
        if also is not None and not asked and name.startswith("dense") and not np.any(rigid):
            # modes flagged rigid at first turned out elastic: the consumer's need, asked now
            extra = np.asarray(also(w2, phi, est), bool)
            if np.any(extra):
                extra = np.arange(w2.size) <= np.flatnonzero(extra).max()
                w2, phi, est, ok = _refine(K, M, factor, w2, phi, est, extra, whole=True)
                name += "+refined" if ok and not name.endswith("+refined") else ""
    w2 = np.where(rigid, 0.0, np.maximum(w2, 0.0))
    if n_modes is not None and n_modes < w2.size:
        w2, phi, rigid, est = w2[:n_modes], phi[:, :n_modes], rigid[:n_modes], est[:n_modes]
    return Spectrum(w2, phi, rigid, est, name)


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


def _refine(K: Any, M: Any, factor: Any, w2: np.ndarray, phi: np.ndarray, est: np.ndarray,
            need: np.ndarray, shift: float = 0.0, solve: Any = None,
            whole: bool = False, estimate: bool = True) -> tuple[np.ndarray, np.ndarray, np.ndarray, bool]:
    """Refine the modes flagged ``need`` (and all below them): inverse iteration, then Ritz.

    One step of subspace inverse iteration ``X = (K + shift M)^-1 M Phi_low``, the
    columns M-orthonormalised (scaled Cholesky QR, twice), then the Ritz values of the subspace from
    the *factor* by a Jacobi SVD of ``G W`` (high relative accuracy; ``W^T K W`` when no factor is
    known). A mode keeps its old value where the new estimate is not better. Returns
    ``(w2, phi, est, refined)``. With ``whole`` and not ``estimate`` every mode up to the last one
    flagged is replaced and no estimate is formed (the caller tests them: their ``est`` is inf).
    """
    low = np.arange(int(np.flatnonzero(need).max()) + 1)
    mass = M if sp.issparse(M) else fast_matrix(np.asarray(M, float))
    blocks = _six_blocks(M)
    mul = (lambda v: np.matmul(blocks, v.reshape(blocks.shape[0], 6, -1)).reshape(v.shape)) \
        if blocks is not None else (lambda v: np.asarray(mass @ v))
    mphi = mul(phi[:, low])
    try:
        kd = K.toarray() if sp.issparse(K) and K.shape[0] <= 2000 else K
        if shift:
            kd = kd + shift * (mass.toarray() if sp.issparse(mass) and not sp.issparse(kd) else mass)
        if solve is None or shift:
            solve = spl.splu(sp.csc_matrix(kd)).solve if sp.issparse(kd) else stiffness_solver(np.asarray(kd, float))
        x = solve(mphi)
        for _ in range(2):                               # scaled Cholesky QR in the M inner product
            x = x / np.sqrt(np.einsum("ij,ij->j", x, mul(x)))[None, :]
            g = x.T @ mul(x)
            x = sl.solve_triangular(np.linalg.cholesky(0.5 * (g + g.T)), x.T, lower=True).T
        if factor is not None:
            b = np.asarray(sp.csr_matrix(factor) @ x) if sp.issparse(factor) else np.asarray(factor) @ x
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


@dataclass(frozen=True, eq=False)
class ModalBasis(ReadOnly):
    """Undamped modes of a plant's free DOFs.

    Attributes
    ----------
    omega2 : (n,) ndarray
        Squared natural frequencies [rad^2/s^2], ascending; exactly 0 for rigid-body modes.
    phi : (n, n) ndarray
        Mass-normalised mode shapes (columns), ``phi.T @ M @ phi = I``.
    rigid : (n,) bool ndarray
        Rigid-body (zero-frequency) modes.
    scale : (n,) ndarray
        State scaling S [rad/s]: omega, or the lowest elastic omega for rigid modes.
    error : (n,) ndarray or None
        Relative error bound of each frequency (NaN for rigid modes), see :func:`error_estimate`.
    method : str
        Eigen-solver used (see :func:`undamped`).
    """

    omega2: np.ndarray
    phi: np.ndarray
    rigid: np.ndarray
    scale: np.ndarray
    error: np.ndarray | None = None
    method: str = ""

    @property
    def omega(self) -> np.ndarray:
        """(n,) natural frequencies [rad/s]."""
        return np.sqrt(self.omega2)


def modal_basis(plant: Plant) -> ModalBasis:
    """Mass-normalised undamped modes of the free DOFs (:func:`undamped` on the plant).

    Uses the plant's stiffness factor ``Kf`` when it has one (exact on badly scaled models). On the
    ``eigh`` path (large models) a mode is also refined when its error estimate, amplified at its
    resonance by ``1 / 2 zeta`` (from the diagonal of ``Phi^T C Phi`` and ``Phi^T H Phi``), would
    exceed :data:`REFINE_TOL` in the FRF.

    Parameters
    ----------
    plant : Plant

    Returns
    -------
    ModalBasis
        Computed once per plant (the plant is frozen; repeated FRF calls on it share it).
    """
    return cast(ModalBasis, plant.cached("modal basis", lambda: _modal_basis(plant)))


def _modal_basis(plant: Plant) -> ModalBasis:
    # the modes a light resonance would amplify are refined in undamped's own sweep (one inverse
    # iteration, one Ritz step for both needs)
    spec = undamped(plant.K, plant.M, plant.Kf, also=partial(_needs_refinement, plant))
    w2, phi, rigid, est, method = spec.omega2, spec.phi, spec.rigid, spec.error, spec.method
    elastic = np.sqrt(w2[~rigid & (w2 > 0)])
    floor = float(elastic.min()) if elastic.size else 1.0
    # a zero w2 the rigid test did not flag (issue 18's fuzzer: a free motion whose stiffness norms
    # are both round-off) must not divide the realization by zero
    scale = np.where(rigid | ~(w2 > 0), floor, np.sqrt(np.maximum(w2, 0.0)))
    return ModalBasis(w2, phi, rigid, scale, est, method)


REFINE_TOL = 1e-10
"""Refine a low mode when its predicted relative FRF error at resonance exceeds this."""


def _needs_refinement(plant: Plant, w2: np.ndarray, phi: np.ndarray, est: np.ndarray) -> np.ndarray:
    """Modes whose error estimate, amplified at their resonance, would exceed :data:`REFINE_TOL`.

    At resonance a damping ratio zeta_r amplifies a relative frequency error by 1 / (2 zeta_r);
    zeta_r comes from the diagonal of Phi^T C Phi (and eta_r / 2 from Phi^T H Phi).
    """
    w2c = np.maximum(w2, np.finfo(float).tiny)
    zeta = np.full(w2.shape, 1e-6)
    for key, hyst in (("C", False), ("H", True)):
        mat = getattr(plant, key)
        if np.any(mat):
            sparse_mat = plant.cached(f"sparse {key}", partial(fast_matrix, mat))
            g = np.einsum("ij,ij->j", phi, sparse_mat @ phi)
            zeta = np.maximum(zeta, g / (2 * w2c) if hyst else g / (2 * np.sqrt(w2c)))
    shape = np.finfo(float).eps * float(np.max(w2)) / w2c
    return np.maximum(np.nan_to_num(est, nan=0.0), shape) / (2 * np.minimum(zeta, 0.5)) > REFINE_TOL
