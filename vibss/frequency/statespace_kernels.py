"""Kernels of the state-space evaluator (:class:`vibss.frequency.statespace_response.Evaluator`): two
ways to evaluate ``C (sI - A)^-1 B`` of a python-control state space at many frequencies, each
factorising once. Their registry and the choice between them: :data:`vibss.frequency.methods.STATESPACE_METHODS`.

Every kernel has one signature: ``kernel(A, B, C) -> h`` with ``h(s)`` the (p, m, k) response at
the Laplace points ``s`` (no feedthrough ``D``), or None where it refuses the system.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import scipy.linalg as sl

from ..linear.eigen.complex_modes import eigenpairs

__all__ = ["MODAL_COND_MAX", "modal", "balanced", "condition_1", "diagonal_sum"]

Response = Callable[[np.ndarray], np.ndarray]

MODAL_COND_MAX = 1e8
"""Largest condition number of the eigenvectors ``V`` for which :func:`modal` diagonalises: above
it ``V^-1`` loses the digits the balanced solve keeps."""


def modal(A: np.ndarray, B: np.ndarray, C: np.ndarray) -> Response | None:
    """Diagonalised once: ``C V (sI - Lambda)^-1 V^-1 B`` (O(n p m) per frequency); None where the
    eigenvectors are ill conditioned (``cond(V) >=`` :data:`MODAL_COND_MAX`)."""
    lam, V = eigenpairs(A)
    if not condition_1(V) < MODAL_COND_MAX:
        return None
    left, right = C @ V, np.linalg.solve(V, B)
    return diagonal_sum(lam, left, right)


def condition_1(V: np.ndarray) -> float:
    """The 1-norm condition number of ``V``, estimated from its LU factors (LAPACK ``gecon``, O(n^2)
    after the O(n^3 / 3) factorisation; within a factor n of the 2-norm ``np.linalg.cond``, whose
    SVD costs about 20 times the factorisation at 1,200 states)."""
    a = np.asarray(V, dtype=complex)
    lu, _ = sl.lu_factor(a, check_finite=False)
    gecon = sl.get_lapack_funcs("gecon", (lu,))
    rcond, info = gecon(lu, float(np.abs(a).sum(axis=0).max()), norm="1")
    return float(np.inf) if info != 0 or rcond <= 0 else 1.0 / float(rcond)


def diagonal_sum(lam: np.ndarray, left: np.ndarray, right: np.ndarray) -> Response:
    """``s -> (p, m, k)`` ``left (sI - Lambda)^-1 right`` of a diagonal system, as one batched matrix
    product per call (``(left * g) @ right``: a BLAS GEMM, where a three-operand ``einsum`` loops)."""
    def h(s: np.ndarray) -> np.ndarray:
        g = 1.0 / (s[:, None] - lam[None, :])                    # (k, n)
        return np.moveaxis((left[None] * g[:, None, :]) @ right, 0, -1)
    return h


def balanced(A: np.ndarray, B: np.ndarray, C: np.ndarray) -> Response:
    """Balanced (``scipy.linalg.matrix_balance``, no permutation), then solved directly at every
    frequency (batched LAPACK ``gesv``)."""
    n = A.shape[0]
    _, (scale, _) = sl.matrix_balance(A, permute=False, separate=True)
    Ab = A / scale[:, None] * scale[None, :]
    Bb, Cb = B / scale[:, None], C * scale[None, :]

    def h(s: np.ndarray) -> np.ndarray:
        lhs = s[:, None, None] * np.eye(n)[None] - Ab[None]
        x = np.linalg.solve(lhs, np.broadcast_to(Bb, (s.size, *Bb.shape)))
        return np.einsum("ij,fjk->ikf", Cb, x)
    return h
