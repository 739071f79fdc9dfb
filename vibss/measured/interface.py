"""The source's blocks for the coupling (:mod:`vibss.measured.coupling`) from its plant, keeping
the blocked dynamic stiffness at the interface in its structure.

The source's plant (inputs ``u`` then the supports' motions ``z``, outputs ``y`` then the forces
``g`` into the supports) answers ``Y = O(s) X + P(s) Z(s) + sum_tau g_tau(s) (O_tau X + P_tau Z)``
(:func:`vibss.linear.solve.exact.observe`), with ``X`` the DOF solutions (:func:`~vibss.linear.solve.exact.states`).
Its interface block is therefore ``H_gz = O_g X_z + P_gz(s)``: rank at most the source's DOFs plus
each mount's own dynamic stiffness (block-diagonal, sparse). Forming ``I - Y_B H_gz`` from the two
parts costs ``n^2`` per source DOF instead of the ``n^3`` of a dense product, and nothing ``n x n``
is ever evaluated by the source's solve: at 600 interface DOFs that leaves the coupling's one LU.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ..linear.plant.branches import groups
from ..linear.plant.plant import Plant
from ..linear.plant.terms import plant_terms
from ..linear.solve.exact import output_map, states, zfactor

__all__ = ["Blocks", "blocks"]


@dataclass(frozen=True)
class Blocks:
    """One block of frequencies of the source's response, split at the interface (``p`` outputs,
    ``m`` inputs, ``n`` interface DOFs; per frequency first).

    Attributes
    ----------
    hy : (nf, p, m + n) complex ndarray
        Outputs per input and per interface motion.
    hgu : (nf, n, m) complex ndarray
        Interface forces per input (the blocked forces).
    low : (nf, n, d) and (nf, d, n) complex ndarrays
        ``O_g`` and ``X_z``: the part of ``H_gz`` through the source's ``d`` DOFs.
    direct : list of ((nf,) complex ndarray, scipy.sparse matrix)
        ``(c(s), P)``: the mounts' own part of ``H_gz``, ``sum c(s) P``; empty when ``diagonal`` holds it.
    diagonal : (nf, points, k, k) complex ndarray or None
        The same part as blocks on the diagonal, one a point (``k`` DOFs a point), when it has that
        shape (a mount's force depends on its own end's motion only).
    """

    hy: np.ndarray
    hgu: np.ndarray
    low: tuple[np.ndarray, np.ndarray]
    direct: list[tuple[np.ndarray, sp.csr_matrix]]
    diagonal: np.ndarray | None = None

    def gz_times(self, z: np.ndarray) -> np.ndarray:
        """``H_gz @ z`` for (nf, n, k) ``z``."""
        out = self.low[0] @ (self.low[1] @ z)
        for c, p in self.direct:
            out += c[:, None, None] * _sparse_left(p, z)
        if self.diagonal is not None:
            nf, pts, k, _ = self.diagonal.shape
            zz = z.reshape(nf, pts, k, -1)
            out += (self.diagonal @ zz).reshape(z.shape)
        return out

    def operator(self, yb: np.ndarray) -> np.ndarray:
        """(nf, n, n) ``I - Y_B H_gz`` for (nf, n, n) ``Y_B``."""
        a = (yb @ self.low[0]) @ self.low[1]
        for c, p in self.direct:
            a += c[:, None, None] * _sparse_right(yb, p)
        if self.diagonal is not None:
            nf, pts, k, _ = self.diagonal.shape
            yp = np.swapaxes(yb.reshape(nf, -1, pts, k), 1, 2)             # (nf, points, rows, k)
            a += np.swapaxes(yp @ self.diagonal, 1, 2).reshape(a.shape)
        np.negative(a, out=a)
        a += np.eye(a.shape[1])[None]
        return a


def _sparse_left(p: sp.csr_matrix, z: np.ndarray) -> np.ndarray:
    """``P @ z`` for every frequency of (nf, n, k) ``z``."""
    nf, n, k = z.shape
    return np.moveaxis((p @ np.moveaxis(z, 0, 1).reshape(n, nf * k)).reshape(-1, nf, k), 1, 0)


def _sparse_right(y: np.ndarray, p: sp.csr_matrix) -> np.ndarray:
    """``y @ P`` for every frequency of (nf, r, n) ``y``."""
    nf, r, n = y.shape
    return (p.T.tocsr() @ y.reshape(nf * r, n).T).T.reshape(nf, r, -1)


def blocks(plant: Plant, s: np.ndarray, p: int, m: int, skews: np.ndarray | None) -> Blocks:
    """The source's blocks at the Laplace values ``s`` (plant: inputs ``u`` then ``z``, outputs ``y``
    then ``g``; ``skews`` the points' ``S(p)`` when the interface has rotations, see
    :func:`vibss.measured.coupling.to_points`)."""
    from .coupling import to_points

    x, _ = states(plant, s)                                          # (nf, d, m + n)
    zf = zfactor(s, plant.order)                                     # (nf, m + n)
    o = np.stack([output_map(plant, complex(si)) for si in s])       # (nf, p + n, d)
    terms = plant_terms(plant)
    pieces = [(np.ones_like(s), terms.p0), (s, plant.Pv), (s**2, plant.Pa)]
    pieces += [(g.factor(s), g.Pz) for g in groups(plant)]
    pieces = [(c, np.asarray(q)) for c, q in pieces if np.any(q)]
    hy = o[:, :p] @ x
    hgu = o[:, p:] @ x[:, :, :m]
    for c, q in pieces:
        hy += c[:, None, None] * q[None, :p] * zf[:, None, :]
        hgu += c[:, None, None] * q[None, p:, :m] * zf[:, None, :m]
    if np.any(plant.Pf):                                             # force inputs' direct feedthrough
        hy += plant.Pf[None, :p]
        hgu += plant.Pf[None, p:, :m]
        pf = np.asarray(plant.Pf)[p:, m:]
        if np.any(pf):
            pieces.append((np.ones_like(s) / zf[:, m], pf))
    og, xz = np.array(o[:, p:]), x[:, :, m:] * zf[:, None, m:]
    direct = []
    for c, q in pieces:
        block = np.array(q[p:, m:], dtype=complex)
        if skews is not None:
            to_points(block, skews, slice(None), slice(None))
        direct.append((c * zf[:, m], block))                         # displacement inputs: zf = 1
    k = 6 if skews is not None else 3
    diagonal = _diagonal(direct, k)
    if skews is not None:
        to_points(hy, skews, None, slice(m, None))
        to_points(hgu, skews, slice(None), None)
        to_points(og, skews, slice(None), None)
        to_points(xz, skews, None, slice(None))
    if diagonal is not None:
        return Blocks(hy, hgu, (og, xz), [], diagonal)
    return Blocks(hy, hgu, (og, xz), [(c, sp.csr_matrix(q)) for c, q in direct])


def _diagonal(direct: list[tuple[np.ndarray, np.ndarray]], k: int) -> np.ndarray | None:
    """``sum c(s) P`` as (nf, points, k, k) diagonal blocks, or None when a ``P`` has entries off them."""
    if not direct:
        return None
    n = direct[0][1].shape[0]
    pts = n // k
    idx = np.arange(pts)
    out = np.zeros((direct[0][0].size, pts, k, k), dtype=complex)
    for c, q in direct:
        blocks4 = q.reshape(pts, k, pts, k)
        diag = blocks4[idx, :, idx, :]                                   # (points, k, k)
        if np.count_nonzero(q) != np.count_nonzero(diag):
            return None
        out += c[:, None, None, None] * diag[None]
    return out
