"""The one eigen path: undamped modes ``K phi = w^2 M phi`` and their error bounds.

Every consumer (the modes table, damped modes, FRFs, state space, modal time responses, pruning,
truncation, Krylov checks, diagnostics) takes its undamped modes from here.

- :func:`undamped`: the one entry every consumer calls: modes, rigid flags and a per-mode error
  bound. With the stiffness *factor* ``G`` (``K = G^T G``, :meth:`Assembly.stiffness_factor`) a
  small model is solved by a Jacobi SVD of ``G L^-T`` (``M = L L^T``; :mod:`vibss.linear.eigen.jacobi`),
  which gives every frequency to high *relative* accuracy even where K formed in floats has lost the
  soft mounts beside stiff links; a large one by ``eigh`` with an a-posteriori test that refines only
  the modes that need it;
- :func:`generalized_eigh`: all modes or the lowest ``n_modes`` (block Cholesky of M, LAPACK
  ``syevd``/``syevr``); :data:`METHODS` names the dense and sparse shift-invert solvers;
- :func:`rigid_mask`: the one test of which computed modes are rigid-body modes, and
  :func:`error_estimate`: relative error bound of each frequency (Kato-Temple on the factored
  residual, and the Jacobi SVD's own bound), both from :mod:`vibss.linear.eigen.checks`;
- :func:`~vibss.linear.eigen.small.symmetric_eigen`, :func:`~vibss.linear.eigen.small.projected_eigen` (in :mod:`.small`): the small symmetric problems (cluster rotations,
  principal axes, projected Ritz problems) so that every eigen solve lives in this module.

The modal basis of a plant, its projected damping and the classical-damping test are in
:mod:`vibss.linear.eigen.basis`.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.linalg as sl
import scipy.sparse as sp
import scipy.sparse.linalg as spl

from ..._validate import choice
from ...results import ReadOnly
from ...errors import ModelError
from ...threads import dense_threads
from .checks import (_EPS, _issparse, RIGID_RTOL, ROUNDOFF_LEVERS, _as_factor, _factor_norms, _inverse_cholesky,
                     _trace_norm, error_estimate, fast_matrix, mass_blocks, rayleigh_estimate, rigid_mask,
                     stiffness_solver)
from .csr import csr_of
from .small import eigh_small
from .jacobi import SMALL_PRODUCTS, _jacobi, _jacobi_floor
from .ritz import GRAM_RITZ, gram_ritz, refine

__all__ = ["generalized_eigh", "rigid_mask", "METHODS",
           "RIGID_RTOL", "fast_matrix", "stiffness_solver", "Solver", "Spectrum",
           "undamped", "error_estimate", "JACOBI_MAX",
           "generalized_eigvals"]

Solver = Callable[[Any, Any, "int | None"], "tuple[np.ndarray, np.ndarray]"]

JACOBI_MAX = 150
"""Largest number of DOFs solved by the Jacobi SVD of the factored problem by default (it costs
about 8 times ``eigh``: ~5 ms at 150 DOF, ~0.8 s at 600 DOF); larger models use ``eigh`` with
a-posteriori refinement."""

JACOBI_FALLBACK = 1500
"""Above :data:`JACOBI_MAX` and up to this many DOFs, the ``eigh`` path falls back to the Jacobi SVD
when refinement leaves a mode whose error estimate exceeds :data:`FREQ_RTOL`."""

DENSE_CHECKS = 30
"""Up to this many DOFs the eigen path's checks (rigid test, error bound) read the stiffness factor
as a dense array; the Jacobi SVD and the refinement keep the sparse one (their digits)."""

FREQ_RTOL = 1e-10
"""Target relative accuracy of every elastic frequency; modes whose estimate exceeds it (times the
resonance amplification 1 / 2 zeta in :func:`modal_basis`) are refined."""

def generalized_eigh(K: Any, M: Any, n_modes: int | None = None,
                     blocks: tuple[np.ndarray, np.ndarray] | None = None) -> tuple[np.ndarray, np.ndarray]:
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
    blocks : tuple, optional
        :func:`~vibss.linear.eigen.checks.mass_blocks` of a dense ``M``, when already computed.

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
    K = K.toarray() if _issparse(K) else np.asarray(K, float)
    subset = None if n_modes is None or n_modes >= K.shape[0] else [0, n_modes - 1]
    # a small sparse M is read densely, so a model's dense and sparse assemblies take one route
    if blocks is None:
        blocks = mass_blocks(M.toarray() if _issparse(M) and K.shape[0] <= SMALL_PRODUCTS else M)
    if blocks is not None:
        # rigid bodies: L^-1 per 6x6 mass block, applied as one batched product (the sparse L^-1
        # costs three CSR products with n columns, about 10 ms at 600 DOF)
        lib = blocks[1]
        nb, n = lib.shape[0], K.shape[0]
        half = np.matmul(lib, K.reshape(nb, 6, n)).reshape(n, n)           # L^-1 K
        a = np.matmul(lib, half.T.reshape(nb, 6, n)).reshape(n, n)          # L^-1 K L^-T
        a = 0.5 * (a + a.T)
        if subset is None and n <= SMALL_PRODUCTS:
            w2, u = eigh_small(a)           # LAPACK syevd as scipy's driver "evd", without the wrappers (10 us)
        else:
            with dense_threads(n):
                w2, u = sl.eigh(a, subset_by_index=subset, driver="evd" if subset is None else "evr",
                                check_finite=False)
        k = u.shape[1]
        phi = np.matmul(np.swapaxes(lib, 1, 2), u.reshape(nb, 6, k)).reshape(n, k)   # L^-T u
        return w2, phi
    li = _inverse_cholesky(M)
    if li is None:
        M = M.toarray() if _issparse(M) else M
        with dense_threads(K.shape[0]):
            return sl.eigh(K, M, subset_by_index=subset, check_finite=False)
    a = li @ (li @ K).T                     # L^-1 K L^-T (K symmetric)
    a = 0.5 * (a + a.T)
    with dense_threads(a.shape[0]):
        w2, u = sl.eigh(a, subset_by_index=subset, driver="evd" if subset is None else "evr",
                        check_finite=False)
    return w2, np.asarray(li.T @ u)


def generalized_eigvals(K: Any, M: Any) -> np.ndarray:
    """(n,) eigenvalues ``w^2`` [rad^2/s^2] of ``K phi = w^2 M phi``, ascending, without vectors.

    For a bound that needs only the spectrum's extent (the stable step of an explicit integrator).
    """
    K = K.toarray() if _issparse(K) else np.asarray(K, float)
    li = _inverse_cholesky(M)
    if li is None:
        return sl.eigh(K, M.toarray() if _issparse(M) else M, eigvals_only=True, check_finite=False)
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
        ``"+ritz"`` when a Ritz step on the factor narrowed a consumer's need (:func:`~vibss.linear.eigen.ritz.gram_ritz`),
        ``"+refined"`` when modes were refined, and ``" (the Jacobi SVD bounded its modes no closer)"``
        when the Jacobi fallback ran and the refined modes were kept.
    """

    omega2: np.ndarray
    phi: np.ndarray
    rigid: np.ndarray
    error: np.ndarray
    method: str


# Over 80 code lines on purpose: the one eigen path's decision in one place: the route
# (Jacobi, dense, shift-invert, a user's solver), the rigid-mode test, the error bounds and the
# refinement must be read together to see what each mode's bound means (issue 28: at most 3
# functions over 80 lines).
def undamped(K: Any, M: Any, factor: Any = None, n_modes: int | None = None,
             method: "str | Solver" = "auto",
             also: "Callable[[np.ndarray, np.ndarray, np.ndarray, np.ndarray | None], np.ndarray] | None" = None,
             solve: "Callable[[np.ndarray], np.ndarray] | None" = None) -> Spectrum:
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
        ``also(w2, phi, error, level) -> (k,) bool``: modes a consumer needs more accurate than
        :data:`FREQ_RTOL` (e.g. amplified at a light resonance, :func:`modal_basis`); ``level``
        [rad^2/s^2] is the size of each shape's coupling to the others (``phi_i^T K phi_j``; None:
        ``eigh``'s ``eps w2_max``; after the Ritz step, the low modes' among themselves). On the
        ``eigh`` path without rigid modes they (and every mode below them) are refined in the same sweep as the modes this function refines for itself; a
        need of :data:`GRAM_RITZ` modes or more is narrowed first by a Ritz step on the factor
        (:func:`~vibss.linear.eigen.ritz.gram_ritz`), which leaves only the low modes' own coupling.
    solve : callable, optional
        ``b -> K^-1 b``, the caller's factorisation of ``K`` (a plant's cached one, shared with its
        static solves); the refinement without a shift uses it instead of factorising ``K`` again.

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
    small_auto = False
    # the checks' products on a tiny model's factor as a dense array: the same bounds (each with its
    # own rounding term) without scipy.sparse's bookkeeping, about 17 CSR objects a call
    checked = factor.toarray() if _issparse(factor) and n <= DENSE_CHECKS else factor
    if factor is not None and not _issparse(factor) and n <= DENSE_CHECKS:
        # a tiny dense factor (an assembly's, without its CSR): the Jacobi SVD and the refinement
        # take its CSR, built only if they run, so their products keep scipy.sparse's digits
        factor = _LazyCSR(checked)
    if callable(method):
        name = getattr(method, "__name__", "custom")
    elif method == "auto":
        if _issparse(K) and n_modes is not None and n_modes < n // 10 and n > JACOBI_MAX:
            name = "shift-invert"
        elif factor is not None and n <= JACOBI_MAX:
            # eigh first; the Jacobi SVD only where the cheap bound says eigh is not accurate
            # enough (a mode that may be rigid, or one refinement cannot certify): 150 DOF, 6 ms
            # against 13 ms for the Jacobi SVD of every model
            name, small_auto = "dense", True
        else:
            name = "dense"
    else:       # a name: one of the solvers, or an ArgumentError with did-you-mean
        name = str(choice(method, "method", ["auto", "jacobi", *METHODS], who="modes"))
    if name == "jacobi" and factor is None:
        name = "dense"
    bound = np.inf
    floor = 0.0
    blocks = None
    kept = ""                # said when the Jacobi fallback ran and eigh's refined modes were kept
    if name == "jacobi":
        w2, phi, bound = _jacobi(_csr(factor), M)
        floor = _jacobi_floor(w2)
    else:
        solver = method if callable(method) else METHODS[name]
        guard = n_modes
        if n_modes is not None and name == "dense":   # a guard band: Ritz on k modes alone converges
            guard = min(n, max(2 * n_modes, n_modes + 12))  # slowly for the top ones (shift-invert's
            #                                                 modes are already inverse iterates)
        if name == "dense" and not callable(method) and not _issparse(M):
            blocks = mass_blocks(M)          # once, for the solve and the bounds
            w2, phi = generalized_eigh(K, M, guard, blocks)
        else:
            w2, phi = solver(K, M, guard)
        w2, phi = np.asarray(w2, float), np.asarray(phi, float)
        # eigh's null vectors have ||A phi||^2 ~ eps w2_max: the floor is sqrt(eps) of the top.
        # Shift-invert's lowest modes are the dominant ones of (K - sigma M)^-1 M, computed to
        # relative accuracy: no such floor (at 60,000 DOF it flagged 2 Hz modes as doubtful and
        # refined all 20 for 2.6 s of a 7.6 s eigsh, to the same frequencies within 2.4e-13)
        floor = 0.0 if name == "shift-invert" and not callable(method) else \
            math.sqrt(10 * n * _EPS) * _trace_norm(M, K, checked)
    norms = None if factor is None else _factor_norms(checked, phi)
    rigid = rigid_mask(phi, K, checked, floor, norms)
    if name == "dense" and not callable(method) and factor is not None:
        # the shapes' Rayleigh quotients on the factor: second order in eigh's shape error (eigh's
        # values carry its absolute eps w2_max: 1e-12 relative on the tree's lowest modes)
        rho, est = rayleigh_estimate(phi, M, None, checked, rigid, norms=norms, blocks=blocks)
        w2 = np.where(rigid | ~np.isfinite(rho), w2, rho)
        if np.any(np.diff(w2) < 0):            # a close pair reordered (by up to eps w2_max): ascending again
            order = np.argsort(w2, kind="stable")
            w2, phi, rigid, est = w2[order], phi[:, order], rigid[order], est[order]
            norms = None if norms is None else (norms[0][:, order], norms[1][order], norms[2][order])
    else:
        est = error_estimate(w2, phi, M, None if factor is not None else K, checked, rigid, norms=norms,
                             blocks=blocks)
    if bound != np.inf:                      # the Jacobi SVD's own bound (eigh has none: min(est, inf) is est)
        est = np.minimum(est, bound + _data_rounding(norms))
    any_rigid = bool(np.count_nonzero(rigid))
    if small_auto and (any_rigid or np.count_nonzero(~np.isfinite(est[~rigid]))):
        # eigh cannot tell a rigid mode from one below sqrt(eps) of the top, nor bound a mode in a
        # cluster (no gap: an infinite bound): the Jacobi SVD decides, as it always did. Modes with
        # a finite bound over FREQ_RTOL are refined below, and go to the Jacobi SVD if they stay so
        w2, phi, rigid, est = _jacobi_checked(_csr(factor), M, K, checked)
        name = "jacobi"
    if name in ("dense", "shift-invert") and not callable(method):
        # eigh cannot tell a rigid mode from one below sqrt(eps) of the top: refine every mode up to
        # the last doubtful one (shifted, so rigid modes are allowed), then test on the factor alone
        any_rigid = bool(np.count_nonzero(rigid))
        need = rigid | (est > FREQ_RTOL)
        asked = also is not None and name == "dense" and not any_rigid

        def consumer(w2: np.ndarray, phi: np.ndarray, est: np.ndarray, fresh: bool = False) -> tuple:
            # the consumer's need against eigh's absolute error; a large one narrowed first by a
            # Ritz step on the factor, which leaves only the low modes' own coupling (gram_ritz)
            nonlocal name
            assert also is not None
            extra = np.asarray(also(w2, phi, est, None), bool)       # at eigh's own coupling
            k = int(np.flatnonzero(extra).max()) + 1 if extra.any() else 0
            if k >= GRAM_RITZ and factor is not None:
                w2, phi, est, level, ran = gram_ritz(M, _csr(factor), checked, w2, phi, est, k, blocks,
                                                     orthonormal=fresh)
                if ran:
                    name += "+ritz"
                    extra = np.asarray(also(w2, phi, est, level), bool)
            return w2, phi, est, extra
        if also is not None and asked:
            w2, phi, est, extra = consumer(w2, phi, est, fresh=True)      # eigh's shapes, none refined
            need = need | extra
        if np.count_nonzero(need) and (factor is not None or not any_rigid):
            above = w2[~rigid]
            shift = 0.0
            if np.any(rigid):                  # shifted, so that rigid modes are allowed
                kd_, md_ = (np.abs(np.asarray(x.diagonal() if _issparse(x) else np.diag(x), float)) for x in (K, M))
                ratio = kd_[md_ > 0] / md_[md_ > 0]
                shift = 1e-3 * float(above.min()) if above.size and above.min() > 0 else \
                    1e-6 * float(np.median(ratio[ratio > 0])) if np.any(ratio > 0) else 1.0
            refined = False
            factors: dict = {}                 # the shifted factorisation, made once for every sweep
            for sweep in range(3):             # a few sweeps of subspace inverse iteration
                w2, phi, est, ok = refine(K, M, _csr(factor), w2, phi, est, need, shift, solve, whole=True,
                                          estimate=factor is None, factors=factors)   # with a factor: tested below
                if not ok:
                    break
                refined = True
                if factor is not None:
                    # the refined modes and the one above them (its gap changed) are tested again; the
                    # others are unchanged, and were not rigid even with the floor
                    head = min(int(np.flatnonzero(need).max()) + 2, w2.size)
                    cols = slice(0, min(head + 1, w2.size))     # one more: the last one's gap is whole
                    nrm = _factor_norms(checked, phi[:, cols])
                    rig = rigid_mask(phi[:, cols], K, checked, norms=nrm)
                    e_head = error_estimate(w2[cols], phi[:, cols], M, None, checked, rig, norms=nrm)
                    rigid, est = rigid.copy(), est.copy()
                    rigid[:head], est[:head] = rig[:head], e_head[:head]
                need = ~rigid & (est > FREQ_RTOL)
                if also is not None and not asked and name == "dense" and sweep < 2 and not np.any(rigid):
                    # modes flagged rigid at first turned out elastic: the consumer's need joins the
                    # next sweep (the soft tower: one refinement fewer, 16 ms of its 0.16 s)
                    w2, phi, est, extra = consumer(w2, phi, est)
                    need, asked = need | extra, True
                if not np.any(need):
                    break
            name += "+refined" if refined else ""
        if factor is not None and n <= JACOBI_FALLBACK and np.count_nonzero(~rigid & ~(est <= FREQ_RTOL)) \
                and _jacobi_may_certify(checked, phi, ~rigid & ~(est <= FREQ_RTOL), est):
            # eigh and its refinement cannot certify some mode (a strongly graded model): the Jacobi
            # SVD can, at ~8x the cost of eigh; kept unless its bounds are the wider ones
            jw2, jphi, jrigid, jest = _jacobi_checked(_csr(factor), M, K, checked)
            k = w2.size                               # eigh's modes (a guard band with n_modes)
            if not np.array_equal(jrigid[:k], rigid) or \
                    np.nanmax(jest[:k], initial=0.0) <= np.nanmax(est, initial=0.0):
                w2, phi, rigid, est = jw2, jphi, jrigid, jest
                name = "jacobi (eigh could not certify every mode)"
            else:
                kept = " (the Jacobi SVD bounded its modes no closer)"
        if also is not None and not asked and name.startswith("dense") and not np.any(rigid):
            # modes flagged rigid at first turned out elastic: the consumer's need, asked now
            w2, phi, est, extra = consumer(w2, phi, est)
            if np.any(extra):
                extra = np.arange(w2.size) <= np.flatnonzero(extra).max()
                w2, phi, est, ok = refine(K, M, _csr(factor), w2, phi, est, extra, solve=solve, whole=True)
                name += "+refined" if ok and "+refined" not in name else ""
    w2 = np.where(rigid, 0.0, np.maximum(w2, 0.0))
    if n_modes is not None and n_modes < w2.size:
        w2, phi, rigid, est = w2[:n_modes], phi[:, :n_modes], rigid[:n_modes], est[:n_modes]
    return Spectrum(w2, phi, rigid, est, name + kept)


class _LazyCSR:
    """A tiny dense stiffness factor whose CSR form (:func:`~vibss.linear.eigen.csr.csr_of`) is
    built on first use: the eigh path reads the dense array only (a CSR costs ~15 us on 6 DOFs)."""

    def __init__(self, dense: np.ndarray) -> None:
        self.dense = dense
        self._csr: Any = None

    def csr(self) -> Any:
        if self._csr is None:
            self._csr = csr_of(self.dense)
        return self._csr


def _csr(factor: Any) -> Any:
    """The factor the Jacobi SVD and the refinement take: a :class:`_LazyCSR`'s CSR, else itself."""
    return factor.csr() if isinstance(factor, _LazyCSR) else factor


def _jacobi_checked(factor: Any, M: Any, K: Any, checked: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray,
                                                                       np.ndarray]:
    """The Jacobi SVD's modes with their rigid test and error bounds: ``(w2, phi, rigid, est)``."""
    w2, phi, bound = _jacobi(factor, M)
    norms = _factor_norms(checked, phi)
    rigid = rigid_mask(phi, K, checked, _jacobi_floor(w2), norms)
    est = np.minimum(error_estimate(w2, phi, M, None, checked, rigid, norms=norms), bound + _data_rounding(norms))
    return w2, phi, rigid, est


def _jacobi_may_certify(factor: Any, phi: np.ndarray, uncertified: np.ndarray, est: np.ndarray) -> bool:
    """Whether the Jacobi SVD could bring any of the ``uncertified`` modes within :data:`FREQ_RTOL`.

    Its estimate of a mode is ``min(residual estimate, gejsv's bound + data rounding)``
    (:func:`_jacobi_checked`); the residual estimate carries the rounding of ``||G phi||``,
    ``(per_row + 2) eps c`` (:func:`~vibss.linear.eigen.checks.error_estimate`), and the data rounding
    ``ROUNDOFF_LEVERS eps c`` (:func:`_data_rounding`), with ``c = || |G| |phi| || / ||G phi||`` the
    mode's cancellation on the factor, a property of its shape. So ``floor = min(per_row + 2,
    ROUNDOFF_LEVERS) eps c`` bounds any solver's estimate from below. The Jacobi SVD is worth its ~10x
    ``eigh`` only for a mode whose floor is within the tolerance and whose refined estimate
    ``est`` stalled more than :data:`JACOBI_GAIN` times above that floor (a graded model, where
    ``gejsv``'s scaling invariance certifies what the refinement cannot). Where the refinement
    already sits near the floor, ``gejsv``'s own bound ``eps kappa(B)`` was the wider one on every
    model measured: the 600-DOF soft tower (its two lowest modes, 0.4 mHz, cancel by 3e5 on the
    factor: 2e-8 against the refinement's 8e-10, for 0.43 s of a 0.68 s eigen-analysis) and the
    600-DOF mechanism chain (4e-7 against ~1e-10 on its first elastic mode).
    """
    idx = np.flatnonzero(uncertified)
    _, num, den = _factor_norms(factor, phi[:, idx])
    per_row = int(np.diff(factor.indptr).max(initial=1)) if _issparse(factor) else factor.shape[1]
    with np.errstate(divide="ignore", invalid="ignore"):
        floor = min(per_row + 2, ROUNDOFF_LEVERS) * _EPS * den / num
    return bool(np.any(~(floor > FREQ_RTOL) & ~(est[idx] <= JACOBI_GAIN * floor)))


JACOBI_GAIN = 10.0
"""The Jacobi fallback runs for a mode whose refined estimate stalled more than this many times above
the least any solver's estimate can be (:func:`_jacobi_may_certify`)."""


def _data_rounding(norms: tuple | None) -> np.ndarray | float:
    """Relative error of each frequency that the stiffness factor's own rounding leaves [-].

    The Jacobi SVD's bound holds for the factor ``G`` as stored; ``G``'s lever arms are differences
    of positions and carry their round-off (:data:`~vibss.linear.eigen.checks.ROUNDOFF_LEVERS` eps of
    each entry), which moves ``w = ||G phi||`` by up to ``ROUNDOFF_LEVERS eps || |G| |phi| || /
    ||G phi||``. The contract campaign (tests/robustness/test_contract_campaign.py) found a 0.03 Hz
    mode of a body on two parallel mounts 4.9e-15 off its 60-digit value under a Jacobi bound of
    1.3e-15; with this term the bound is 2.1e-13. 0 without the norms (no factor: no Jacobi bound).
    """
    if norms is None:
        return 0.0
    _, num, den = norms
    with np.errstate(divide="ignore", invalid="ignore"):
        out = ROUNDOFF_LEVERS * _EPS * den / num
    return np.where(np.isfinite(out), out, np.inf)
