"""The damping projected on the undamped modes, ``Phi^T C Phi`` and ``Phi^T H Phi``, computed once.

The frequency kernels (``modal``, ``complex_modal``), ``auto``'s choice (classical damping, the
complex-mode risk), the frequency grid's damping estimate and the modal state space all need the
projection of the same plant's damping on the same :class:`~vibss.linear.eigen.ModalBasis`.
:func:`projected_damping` computes it once per plant and basis and keeps it in the plant's cache
(the plant is frozen, so it never goes stale).
"""

from __future__ import annotations

from functools import partial

import numpy as np

from .eigen import ModalBasis, fast_matrix
from .plant import Plant

__all__ = ["projected_damping"]


def projected_damping(plant: Plant, basis: ModalBasis) -> tuple[np.ndarray, np.ndarray]:
    """``Phi^T C Phi`` and ``Phi^T H Phi`` on the modes ``basis.phi`` (zeros when absent), cached.

    Parameters
    ----------
    plant : Plant
        Its ``C`` and ``H`` (dense or scipy.sparse) are projected.
    basis : ModalBasis
        Undamped modes of the plant (columns ``phi``, n x k).

    Returns
    -------
    gamma, eta : (k, k) ndarray
        Projected viscous [1/s] and hysteretic [1/s^2] damping, symmetrised, read-only (copy
        before changing them). The same objects for the same plant and basis.

    Examples
    --------
    >>> from vibss import Body, Model, Mount, MountType
    >>> from vibss.linear.eigen import modal_basis
    >>> from vibss.linear.signals import build_plant
    >>> m = Model([Body("b", 4.0, [1, 1, 1])], [Mount("m", MountType("t", [1e3] * 3, [8.0] * 3), "b")])
    >>> p = build_plant(m, ["b.fz"], ["b.z"])
    >>> b = modal_basis(p)
    >>> g, h = projected_damping(p, b)
    >>> round(float(g[-1, -1]), 12), projected_damping(p, b)[0] is g      # c / m for a z mode
    (2.0, True)
    """
    # the basis is kept in the cached value, so its id cannot be reused while the entry lives
    return plant.cached(f"projected damping {id(basis)}", partial(_project, plant, basis))[1]


def _project(plant: Plant, basis: ModalBasis) -> tuple[ModalBasis, tuple[np.ndarray, np.ndarray]]:
    phi = basis.phi
    k = phi.shape[1]
    out = []
    for key in ("C", "H"):
        mat = getattr(plant, key)
        if np.any(mat) if isinstance(mat, np.ndarray) else bool(mat.count_nonzero()):
            g = phi.T @ (plant.cached(f"sparse {key}", partial(fast_matrix, mat)) @ phi)
            g = 0.5 * (g + g.T)
        else:
            g = np.zeros((k, k))
        g.setflags(write=False)
        out.append(g)
    return basis, (out[0], out[1])
