"""Frequency response of any python-control state-space system, evaluated accurately.

python-control evaluates ``C (sI - A)^-1 B + D`` with SLICOT's TB05AD *without balancing*, which
loses digits on badly scaled realizations (``../shared/notes/python-control.md``, finding 2). Here
the realization is balanced first (``scipy.linalg.matrix_balance``) and then solved directly at
every frequency (batched LAPACK ``gesv``). Above 150 states the system is diagonalised once instead
(``C V (sI - Lambda)^-1 V^-1 B``: O(n p m) per frequency) when its eigenvectors are well conditioned
(``cond(V) < 1e8``), else solved directly: the registry
:data:`vibss.frequency.methods.STATESPACE_METHODS` and its choice
:func:`~vibss.frequency.methods.choose_statespace`, on the kernels of
:mod:`vibss.frequency.statespace_kernels`. Used for closed loops and other systems that are not a
vibss :class:`~vibss.linear.plant.plant.Plant` (for a plant, :func:`vibss.frequency_response` is exact).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from .methods import StateSpaceMethod, choose_statespace

__all__ = ["evaluate", "Evaluator"]


class Evaluator:
    """``H(i w)`` of one system at any frequencies, with its factorisation done once.

    Parameters
    ----------
    system : control.StateSpace
        Continuous time.
    outputs, inputs : sequence of int or None
        Rows and columns wanted (default all).
    """

    def __init__(self, system: Any, outputs: Sequence[int] | None = None,
                 inputs: Sequence[int] | None = None) -> None:
        A = np.asarray(system.A, dtype=float)
        n = A.shape[0]
        B = np.asarray(system.B, dtype=float).reshape(n, system.ninputs)
        C = np.asarray(system.C, dtype=float).reshape(system.noutputs, n)
        D = np.asarray(system.D, dtype=float).reshape(system.noutputs, system.ninputs)
        if outputs is not None:
            C, D = C[list(outputs)], D[list(outputs)]
        if inputs is not None:
            B, D = B[:, list(inputs)], D[:, list(inputs)]
        self.D = D
        self.n = n
        # the evaluator (None for a static gain) and the response h(s) without D
        self.method: StateSpaceMethod | None = None
        self._h: Callable[[np.ndarray], np.ndarray] | None = None
        if n:
            self.method, self._h = choose_statespace(A, B, C)

    def __call__(self, omega: Any, chunk: int = 64) -> np.ndarray:
        """(p, m, nf) complex response at ``omega`` [rad/s]."""
        w = np.atleast_1d(np.asarray(omega, dtype=float))
        D = self.D
        out = np.empty((D.shape[0], D.shape[1], w.size), dtype=complex)
        if self.n == 0:
            out[:] = D[:, :, None]
            return out
        assert self._h is not None
        for start in range(0, w.size, chunk):
            s = 1j * w[start:start + chunk]
            out[:, :, start:start + s.size] = self._h(s) + D[:, :, None]
        return out


def evaluate(system: Any, omega: Any, outputs: Sequence[int] | None = None,
             inputs: Sequence[int] | None = None) -> np.ndarray:
    """``H(i w) = C (i w I - A)^-1 B + D`` of a continuous-time state space.

    Parameters
    ----------
    system : control.StateSpace
        The system (dt = 0).
    omega : (nf,) array_like
        Angular frequencies [rad/s].
    outputs, inputs : sequence of int or None
        Rows and columns wanted (default all).

    Returns
    -------
    (p, m, nf) complex ndarray
    """
    return Evaluator(system, outputs, inputs)(omega)
