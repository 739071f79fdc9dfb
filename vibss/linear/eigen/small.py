"""The small symmetric eigenproblems: one LAPACK call each, no vibss types.

Cluster rotations, principal axes of an inertia tensor or a 6x6 mount matrix, projected damping
blocks, Ritz pairs of a Krylov basis, batched Monte Carlo variants. They sit at the bottom of the
layers (the assembly factorises a mount's 6x6 matrix with them).
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sl

__all__ = ["symmetric_eigen", "projected_eigen", "state_eigen", "state_eigenvalues"]


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
