"""The damping projected on the undamped modes, ``Phi^T C Phi`` and ``Phi^T H Phi``, computed once.

The frequency kernels (``modal``, ``complex_modal``), ``auto``'s choice (classical damping, the
complex-mode risk), the frequency grid's damping estimate and the modal state space all need the
projection of the same plant's damping on the same :class:`~vibss.linear.eigen.undamped.ModalBasis`.
:func:`projected_damping` computes it once per plant and basis and keeps it in the plant's cache
(the plant is frozen, so it never goes stale).
"""

from __future__ import annotations

from functools import partial
from typing import Any

import numpy as np
import scipy.linalg as sl
import scipy.sparse as sp

from .undamped import ModalBasis, fast_matrix
from ..plant.plant import Plant

__all__ = ["projected_damping", "damping_factors", "damping_rank"]


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
    >>> from ... import Body, Model, Mount, MountType
    >>> from .undamped import modal_basis
    >>> from ..plant.build import build_plant
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


def damping_factors(plant: Plant, basis: ModalBasis) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The damping as a low-rank product on the modes: ``Phi^T (C + i H / s) Phi = U (Zc + Zh / s) U^T``.

    Dampers live in mounts: with the plant's :class:`~vibss.linear.plant.plant.MountForm`, every mount
    with a viscous or hysteretic part contributes the three columns ``Phi^T B_p^T`` of its
    deflection map and its (3, 3) damping blocks, and the rest of ``C`` and ``H`` (mounts with a
    zero stiffness axis, rotational parts, added damping) the rows of the DOFs it touches, with its
    own block. Without a mount form the DOFs that ``C`` or ``H`` touch are used directly. No
    factorisation is made (no rank is guessed): the product is exact.

    Parameters
    ----------
    plant : Plant
        Its ``C`` and ``H`` (dense or scipy.sparse), and ``mounts`` when it matches the plant.
    basis : ModalBasis
        Undamped modes of the plant (columns ``phi``, n x k).

    Returns
    -------
    U : (k, r) ndarray
        The modes' deflections at the dampers [m, rad per unit modal coordinate].
    Zc : (r, r) ndarray
        Viscous damping of those deflections [N s/m] (block diagonal, symmetric).
    Zh : (r, r) ndarray
        Hysteretic stiffness [N/m] (block diagonal, symmetric; zeros when absent).

    Examples
    --------
    >>> from ... import Body, Model, Mount, MountType
    >>> from .undamped import modal_basis
    >>> from ..plant.build import build_plant
    >>> t = MountType("t", [1e3] * 3, [8.0] * 3)
    >>> m = Model([Body("b", 4.0, [1, 1, 1])], [Mount("m", t, "b"), Mount("n", MountType("u", [1e3] * 3), "b", at=[1, 0, 0])])
    >>> p = build_plant(m, ["b.fz"], ["b.z"])
    >>> u, zc, zh = damping_factors(p, modal_basis(p))
    >>> u.shape, bool(np.allclose(u @ zc @ u.T, projected_damping(p, modal_basis(p))[0]))   # one damped mount
    ((6, 3), True)
    """
    return plant.cached(f"damping factors {id(basis)}", partial(_factors, plant, basis))[1]


def _dense(mat: Any) -> np.ndarray:
    return mat.toarray() if sp.issparse(mat) else np.asarray(mat, dtype=float)


def _touched(mats: list[Any], n: int) -> np.ndarray:
    """Indices of the DOFs (rows) that any of ``mats`` touches."""
    hit = np.zeros(n, bool)
    for mat in mats:
        if sp.issparse(mat):
            coo = sp.coo_matrix(mat)
            hit[coo.row[coo.data != 0]] = True
        else:
            hit |= np.any(np.asarray(mat) != 0, axis=1)
    return np.flatnonzero(hit)


def _pieces(plant: Plant) -> tuple[Any, np.ndarray, np.ndarray, list[Any], np.ndarray]:
    """Where the damping sits: the plant's mount form (None when it does not match), its damped
    mounts, its per-axis mounts, the rest of ``C`` and ``H`` and the DOFs that rest touches."""
    form = plant.mounts
    if form is not None and form.matches(plant):
        damped = np.flatnonzero(np.any(form.cp != 0, axis=(1, 2)) | np.any(form.hp != 0, axis=(1, 2)))
        axes = np.flatnonzero((form.ca != 0) | (form.ha != 0))        # the mounts kept apart per axis
        rest = [form.C, form.H]
    else:
        form, damped, axes, rest = None, np.zeros(0, int), np.zeros(0, int), [plant.C, plant.H]
    return form, damped, axes, rest, _touched(rest, plant.n)


def damping_rank(plant: Plant) -> int:
    """The number of columns of :func:`damping_factors`' ``U`` (3 per damped mount, one per damped
    mount axis kept apart, one per DOF the rest of the damping touches), counted without forming
    it: ``auto`` costs the low-rank update by it (:mod:`vibss.frequency.methods`), and forming ``U``
    (a product with every mode) only to count its columns cost 0.08-0.10 s at 600 DOF.

    Parameters
    ----------
    plant : Plant

    Returns
    -------
    int
    """
    def count() -> int:
        _, damped, axes, _, idx = _pieces(plant)
        return 3 * damped.size + axes.size + idx.size

    return plant.cached("damping rank", count)


def _factors(plant: Plant, basis: ModalBasis) -> tuple[ModalBasis, tuple[np.ndarray, np.ndarray, np.ndarray]]:
    phi = basis.phi
    cols: list[np.ndarray] = []          # (k, r_i) blocks of U
    zc: list[np.ndarray] = []
    zh: list[np.ndarray] = []
    form, damped, axes, rest, idx = _pieces(plant)
    if form is not None:
        if damped.size:
            rows = (3 * damped[:, None] + np.arange(3)).ravel()
            cols.append(np.asarray(form.B[rows] @ phi).T)
            zc.append(sl.block_diag(*form.cp[damped]))
            zh.append(sl.block_diag(*form.hp[damped]))
        if axes.size:
            cols.append(np.asarray(form.Ba[axes] @ phi).T)
            zc.append(np.diag(form.ca[axes]))
            zh.append(np.diag(form.ha[axes]))
    if idx.size:
        cols.append(phi[idx].T)
        zc.append(_dense(rest[0])[np.ix_(idx, idx)])
        zh.append(_dense(rest[1])[np.ix_(idx, idx)])
    if not cols:
        k = phi.shape[1]
        out = (np.zeros((k, 0)), np.zeros((0, 0)), np.zeros((0, 0)))
    else:
        c, h = sl.block_diag(*zc), sl.block_diag(*zh)
        out = (np.hstack(cols), 0.5 * (c + c.T), 0.5 * (h + h.T))
    for a in out:
        a.setflags(write=False)
    return basis, out
