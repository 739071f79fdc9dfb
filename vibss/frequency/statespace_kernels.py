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

__all__ = ["MODAL_COND_MAX", "modal", "balanced"]

Response = Callable[[np.ndarray], np.ndarray]

MODAL_COND_MAX = 1e8
"""Largest condition number of the eigenvectors ``V`` for which :func:`modal` diagonalises: above
it ``V^-1`` loses the digits the balanced solve keeps."""


def modal(A: np.ndarray, B: np.ndarray, C: np.ndarray) -> Response | None:
    """Diagonalised once: ``C V (sI - Lambda)^-1 V^-1 B`` (O(n p m) per frequency); None where the
    eigenvectors are ill conditioned (``cond(V) >=`` :data:`MODAL_COND_MAX`)."""
    lam, V = eigenpairs(A)
    if not np.linalg.cond(V) < MODAL_COND_MAX:
        return None
    left, right = C @ V, np.linalg.solve(V, B)

    def h(s: np.ndarray) -> np.ndarray:
        g = 1.0 / (s[None, :] - lam[:, None])
        return np.einsum("in,nf,nk->ikf", left, g, right)
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
