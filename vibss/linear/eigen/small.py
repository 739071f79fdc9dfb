"""The small symmetric eigenproblems: one LAPACK call each, no vibss types.

Cluster rotations, principal axes of an inertia tensor or a 6x6 mount matrix, projected damping
blocks, Ritz pairs of a Krylov basis, batched Monte Carlo variants. They sit at the bottom of the
layers (the assembly factorises a mount's 6x6 matrix with them).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.linalg as sl

try:
    from numpy.linalg import _umath_linalg   # the LAPACK gufuncs behind numpy.linalg
    _gufuncs: Any = _umath_linalg
except ImportError:       # pragma: no cover - a NumPy that moved them: the public calls
    _gufuncs = None

__all__ = ["symmetric_eigen", "projected_eigen", "state_eigen", "state_eigenvalues", "inverse_cholesky",
           "eigh_small"]

_QUIET = {"invalid": "raise", "over": "ignore", "divide": "ignore", "under": "ignore"}
"""The error state :mod:`numpy.linalg` calls its gufuncs under, with a failure raised (not a warning)."""


def inverse_cholesky(m: np.ndarray) -> np.ndarray:
    """``L^-1`` with ``m = L L^T``, of a float64 matrix or a stack of them: ``np.linalg.inv(np.linalg.cholesky(m))``
    bit for bit (the same LAPACK gufuncs) without their Python wrappers, which cost a 6 x 6 mass block
    more than the factorisation; a matrix that is not positive definite goes to the public calls,
    which raise their ``LinAlgError``.

    Examples
    --------
    >>> li = inverse_cholesky(np.array([[4.0, 2.0], [2.0, 5.0]]))
    >>> (li @ np.array([[4.0, 2.0], [2.0, 5.0]]) @ li.T).round(12).tolist()
    [[1.0, 0.0], [0.0, 1.0]]
    """
    if _gufuncs is not None and isinstance(m, np.ndarray) and m.dtype == np.float64 and m.ndim >= 2:
        try:
            with np.errstate(**_QUIET):   # type: ignore[arg-type]
                out: np.ndarray = _gufuncs.inv(_gufuncs.cholesky_lo(m, signature="d->d"), signature="d->d")
            return out
        except (FloatingPointError, TypeError, ValueError):   # a failure, or a NumPy whose gufuncs changed
            pass
    return np.linalg.inv(np.linalg.cholesky(m))


def eigh_small(a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``np.linalg.eigh(a)`` (LAPACK ``syevd`` on the lower triangle) bit for bit without its Python
    wrapper, for the small symmetric problems the eigen path solves on every new model; a failure
    goes to the public call, which raises its ``LinAlgError``."""
    if _gufuncs is not None and isinstance(a, np.ndarray) and a.dtype == np.float64 and a.ndim >= 2:
        try:
            with np.errstate(**_QUIET):   # type: ignore[arg-type]
                w, v = _gufuncs.eigh_lo(a, signature="d->dd")
            return w, v
        except (FloatingPointError, TypeError, ValueError):   # a failure, or a NumPy whose gufuncs changed
            pass
    w, v = np.linalg.eigh(a)
    return w, v


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


def state_eigen(a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Eigenvalues [rad/s] and right eigenvectors of a real first-order state matrix (a closed loop,
    whose controller states leave no second-order structure), by ascending magnitude (LAPACK ``geev``)."""
    lam, v = np.linalg.eig(np.asarray(a, dtype=float))
    order = np.argsort(np.abs(lam), kind="stable")
    return lam[order], v[:, order]


def state_eigenvalues(a: np.ndarray) -> np.ndarray:
    """Eigenvalues [rad/s] of a real state matrix, or of a stack of them (``(..., n, n)``: one LAPACK
    ``geev`` per matrix without eigenvectors, batched variants of a closed loop), in LAPACK's order."""
    return np.linalg.eigvals(np.asarray(a, dtype=float))
