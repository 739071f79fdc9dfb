"""Pieces of a projection basis for large sparse plants: an M-orthonormal basis grown block by block,
shift-invert solves, the exact response at one point (with its adjoint) and the Galerkin projection
in Ritz coordinates.

Shared by the Krylov reduction (:mod:`vibss.reduction.krylov`) and the channel subspace of the
large-model frequency and time responses (:mod:`vibss.linear.project.subspace`). Nothing n x n is dense.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import cast

import numpy as np
import scipy.sparse as sp
from scipy.linalg.lapack import dgbtrf, dgbtrs

from ...errors import AnalysisError
from ..solve.banded import Structure, structure
from ..eigen.small import projected_eigen, symmetric_eigen
from ..plant.plant import Plant
from ..solve.exact import SingularMatrixError, forcing, lu_solver, observe, output_map, states, zfactor

__all__ = ["Basis", "exact_response", "forcing_columns", "observing_columns", "shift_solver", "project",
           "DEFLATE_RTOL"]

DEFLATE_RTOL = 1e-9
"""A new column is dropped when its M-norm after orthogonalisation is below this fraction of its
M-norm before."""


def exact_response(p: Plant, s: complex, adjoint: bool = False) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """Exact response of a sparse plant at one Laplace point ``s`` [rad/s] (the one exact solve,
    :func:`vibss.linear.solve.exact.states`, on the sparse structure: banded LU or SuperLU).

    Parameters
    ----------
    p : Plant
        With sparse ``M, C, K, H`` (:func:`sparse_plant`, :func:`as_sparse`).
    s : complex
        Laplace point (``i w``).
    adjoint : bool
        Also solve ``A(s)^T x = O(s)^T`` (the output side, same solve: A is symmetric).

    Returns
    -------
    y : (p, m) complex ndarray
        Outputs per unit input.
    x : (n, m) complex ndarray
        DOF response.
    xa : (n, p) complex ndarray or None
        Adjoint solutions (``adjoint``).
    """
    sv = np.array([s], dtype=complex)
    zf = zfactor(sv, p.order)
    rhs = forcing(p, sv, zf)[0]
    m = rhs.shape[1]
    obs = output_map(p, complex(s))
    if adjoint:
        rhs = np.hstack([rhs, obs.T])
    xs, bad = states(p, sv, rhs=rhs, backend="sparse")
    if bad[0]:
        raise AnalysisError(f"krylov: K + iH + sC + s^2 M is singular at s = {s:.6g} rad/s")
    x = xs[0, :, :m]
    y = observe(p, sv, x[None], zf)[0]
    return y, x, (xs[0, :, m:] if adjoint else None)


class Basis:
    """An M-orthonormal basis grown block by block (block Gram-Schmidt twice, with deflation).

    The columns live in one Fortran-ordered array grown by doubling, so adding a block neither
    copies the basis nor hands BLAS a strided view.
    """

    def __init__(self, M: sp.csr_matrix):
        self.M = M
        self._v = np.zeros((M.shape[0], 0), order="F")
        self._mv = np.zeros((M.shape[0], 0), order="F")
        self.r = 0

    @property
    def V(self) -> np.ndarray:
        """(n, r) the basis so far (a view)."""
        return self._v[:, :self.r]

    @property
    def MV(self) -> np.ndarray:
        """(n, r) ``M V`` (a view)."""
        return self._mv[:, :self.r]

    def add(self, w: np.ndarray) -> np.ndarray:
        """Add the columns of ``w`` (n, k); returns the new M-orthonormal columns (n, k' <= k)."""
        w = np.asarray(w, float)
        if w.size == 0:
            return w.reshape(w.shape[0], 0)
        norm0 = np.sqrt(np.maximum(np.einsum("ij,ij->j", w, self.M @ w), 0.0))
        keep = norm0 > 0
        w = w[:, keep] / norm0[keep]
        for rnd in range(2):
            if self.r:
                w = w - self.V @ (self.MV.T @ w)
            g = w.T @ (self.M @ w)
            lam, u = symmetric_eigen(g)
            floor = DEFLATE_RTOL**2 if rnd == 0 else 1e-12 * float(lam.max(initial=0.0))
            ok = lam > floor
            w = w @ (u[:, ok] / np.sqrt(lam[ok]))
            if w.shape[1] == 0:
                return w
        mw = np.asarray(self.M @ w)
        k = w.shape[1]
        if self.r + k > self._v.shape[1]:
            cap = max(2 * self._v.shape[1], self.r + k, 16)
            for name in ("_v", "_mv"):
                grown = np.empty((self._v.shape[0], cap), order="F")
                grown[:, :self.r] = getattr(self, name)[:, :self.r]
                setattr(self, name, grown)
        self._v[:, self.r:self.r + k] = w
        self._mv[:, self.r:self.r + k] = mw
        self.r += k
        return w

    def add_sequence(self, solve: Callable[[np.ndarray], np.ndarray], block: np.ndarray, moments: int) -> slice:
        """Add the block Krylov sequence ``S B, S M S B, ...`` (``moments`` blocks, ``S = solve``).

        Each block is M-orthonormalised against the ones before it of the same sequence only (a
        small basis); the sequence joins this basis in two passes, its last block apart. Returns the
        columns that last block became (a basis without them is the same sequence one moment shorter:
        comparing the two shows where the sequence has not converged).
        """
        local = Basis(self.M)
        blk = local.add(np.asarray(solve(np.asarray(block, float)), float))
        before = local.r
        for _ in range(max(int(moments), 1) - 1):
            if blk.shape[1] == 0:
                break
            before = local.r
            blk = local.add(np.asarray(solve(np.asarray(self.M @ blk)), float))
        if moments > 1 and local.r > before:
            self.add(local.V[:, :before])
            start = self.r
            self.add(local.V[:, before:])
            return slice(start, self.r)
        self.add(local.V)
        return slice(self.r, self.r)


def forcing_columns(p: Plant) -> np.ndarray:
    """(n, k) every nonzero forcing column of the plant (``F, Kz, Cz, Mz, Hz``)."""
    b = np.hstack([p.F, p.Kz, p.Cz, p.Mz, p.Hz])
    return b[:, np.any(b != 0, axis=0)]


def observing_columns(p: Plant) -> np.ndarray:
    """(n, k) every nonzero output row of the plant, transposed (``Oq, Ov, Oa, Oh``)."""
    o = np.vstack([a for a in (p.Oq, p.Ov, p.Oa, p.Oh) if a is not None]).T
    return o[:, np.any(o != 0, axis=0)]


def shift_solver(p: Plant, w: float, w2: float, banded: bool = True) -> tuple[Callable[[np.ndarray], np.ndarray], float]:
    """LU of ``K - sigma M`` at ``sigma = w^2`` (nudged when singular); returns (solve, sigma).

    Banded LU (``dgbtrf``) on the plant's banded ordering (:func:`vibss.linear.solve.banded.structure`)
    when it bands, ``banded`` is true and ``sigma > 0``; else SuperLU (:func:`vibss.linear.solve.exact.lu_solver`): a static
    shift's ``K`` may be singular to round-off, which SuperLU's pivoting reports as exactly singular
    (the shift is then nudged below zero) where the banded LU answered with a basis too poor for the
    reduction's tolerance (measured: 8.4e-9 against 1e-9 in tests/reduction/test_reduction.py).
    """
    st = p.cached("band structure", lambda: structure(p)) if banded else None
    sigma = w * w
    for k in range(4):
        try:
            if st is not None and st.banded and sigma > 0:
                return _band_solver(st, sigma), sigma
            return lu_solver(cast("sp.spmatrix", sp.csr_matrix(p.K) - sigma * sp.csr_matrix(p.M)).tocsc()), sigma
        except SingularMatrixError:
            sigma = sigma * (1 + 1e-3 * (k + 1)) if sigma > 0 else -((1e-2 * (k + 1) * w2) ** 2)
    raise AnalysisError(f"krylov: K - sigma M is singular near sigma = {w * w:.6g} (rad/s)^2")


def _band_solver(st: Structure, sigma: float) -> Callable[[np.ndarray], np.ndarray]:
    """``b -> (K - sigma M)^-1 b`` by one real banded LU in the structure's ordering."""
    band, perm = st.band, st.perm
    inv = np.argsort(perm)
    n = perm.size
    ab = np.zeros((3 * band + 1, n), order="F")
    ab[band:] = st.parts["K"] - sigma * st.parts["M"]
    lu, piv, info = dgbtrf(ab, band, band, overwrite_ab=1)
    if info > 0:
        raise SingularMatrixError(f"K - sigma M is exactly singular at sigma = {sigma:.6g} (rad/s)^2")

    def solve(b: np.ndarray) -> np.ndarray:
        b = np.asarray(b)
        if np.iscomplexobj(b):
            return solve(b.real) + 1j * solve(b.imag)
        x, _ = dgbtrs(lu, band, band, np.asfortranarray(b[perm].reshape(n, -1)), piv)
        return x[inv].reshape(b.shape)
    return solve


def project(p: Plant, V: np.ndarray) -> Plant:
    """Galerkin projection of a sparse plant on M-orthonormal ``V`` (n, r), in Ritz coordinates.

    ``M_r = I``, ``K_r = diag(w_k^2)`` (eigenvectors ``T`` of ``V^T K V``), ``C_r, H_r = T^T V^T (C, H) V T``,
    force maps ``T^T V^T F ...``, output maps ``O V T``. Feedthrough terms are kept.
    """
    def sym(a: sp.csr_matrix) -> np.ndarray:
        g = V.T @ (a @ V)
        return 0.5 * (g + g.T)

    mr = sym(p.M)
    if p.Kf is not None:              # (Kf V)^T (Kf V): no cancellation of penalty rates against soft ones
        kv = np.asarray(p.Kf @ V)
        kr = kv.T @ kv
    else:
        kr = sym(p.K)
    w2, t = projected_eigen(kr, mr)
    vt = V @ t
    top = max(float(np.abs(w2).max(initial=0.0)), 1e-300)
    w2 = np.where(np.abs(w2) <= 1e-12 * top, 0.0, w2)
    r = V.shape[1]
    return p.project(vt, tuple(f"krylov{k + 1}" for k in range(r)), M=np.eye(r), K=np.diag(w2))
