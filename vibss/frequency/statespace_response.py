"""Frequency response of any python-control state-space system, evaluated accurately.

python-control evaluates ``C (sI - A)^-1 B + D`` with SLICOT's TB05AD *without balancing*, which
loses digits on badly scaled realizations (``../shared/notes/python-control.md``, finding 2). Here
the realization is balanced first (``scipy.linalg.matrix_balance``) and then solved directly at
every frequency (batched LAPACK ``gesv``). Used for closed loops and other systems that are not a
vibss :class:`~vibss.linear.plant.Plant` (for a plant, :func:`vibss.frequency_response` is exact).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
import scipy.linalg as sl

__all__ = ["evaluate"]


def evaluate(system: Any, omega: Any, outputs: Sequence[int] | None = None,
             inputs: Sequence[int] | None = None, chunk: int = 64) -> np.ndarray:
    """``H(i w) = C (i w I - A)^-1 B + D`` of a continuous-time state space.

    Parameters
    ----------
    system : control.StateSpace
        The system (dt = 0).
    omega : (nf,) array_like
        Angular frequencies [rad/s].
    outputs, inputs : sequence of int or None
        Rows and columns wanted (default all).
    chunk : int
        Frequencies solved per batched call.

    Returns
    -------
    (p, m, nf) complex ndarray
    """
    w = np.atleast_1d(np.asarray(omega, dtype=float))
    A = np.asarray(system.A, dtype=float)
    B = np.asarray(system.B, dtype=float).reshape(A.shape[0], system.ninputs)
    C = np.asarray(system.C, dtype=float).reshape(system.noutputs, A.shape[0])
    D = np.asarray(system.D, dtype=float).reshape(system.noutputs, system.ninputs)
    if outputs is not None:
        C, D = C[list(outputs)], D[list(outputs)]
    if inputs is not None:
        B, D = B[:, list(inputs)], D[:, list(inputs)]
    n = A.shape[0]
    out = np.empty((C.shape[0], B.shape[1], w.size), dtype=complex)
    if n == 0:
        out[:] = D[:, :, None]
        return out
    _, (scale, _) = sl.matrix_balance(A, permute=False, separate=True)
    Ab = A / scale[:, None] * scale[None, :]
    Bb, Cb = B / scale[:, None], C * scale[None, :]
    eye = np.eye(n)
    for start in range(0, w.size, chunk):
        s = 1j * w[start:start + chunk]
        lhs = s[:, None, None] * eye[None] - Ab[None]
        x = np.linalg.solve(lhs, np.broadcast_to(Bb, (s.size, *Bb.shape)))
        out[:, :, start:start + s.size] = np.einsum("ij,fjk->ikf", Cb, x) + D[:, :, None]
    return out
