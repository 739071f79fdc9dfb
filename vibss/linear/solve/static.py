"""The static solve ``K x = f``: badly scaled stiffness kept exact, free motions named.

Systems up to :data:`FACTOR_MAX` DOFs are solved from the stiffness *factor* (``K = G^T G``, one row
per mount axis, :meth:`~vibss.linear.plant.assemble.Assembly.stiffness_factor`): a QR factorisation of G
with rows sorted by size and column pivoting is row-wise backward stable, so soft mounts beside
1e16 N/m links keep their digits (K formed in floats loses them: 1e16 * eps ~ 1 N/m). Otherwise the
stiffness matrix of the free DOFs is equilibrated (``D K D`` with ``D = diag(K)^-1/2``),
factorised (Cholesky for dense models, sparse LU for large ones) and its 1-norm condition number
estimated (:func:`scipy.sparse.linalg.onenormest` on the factorisation). A system that is not fully
restrained (a body not connected to ground, a direction no mount resists) has a singular K: the
solve finds the free motions (null space of the equilibrated K), and if the load pushes along one of
them raises :class:`~vibss.errors.AnalysisError` naming it ("body 'engine' is free to move in x").
A load orthogonal to every free motion is solved in the minimum-norm sense and the free motions
are listed with the solution.

:func:`static_solve` is the one static solve: :func:`vibss.static` and the design measures (sag,
torque response) call it, never ``np.linalg.solve(K, ...)``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.linalg as sl
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph
import scipy.sparse.linalg as spl

from ..plant.assemble import Assembly
from ..eigen.directions import align_cluster, describe_motion
from ..eigen.undamped import symmetric_eigen, undamped
from ..eigen.jacobi import jacobi_svd
from ...errors import AnalysisError

__all__ = ["static_solve", "StaticSolution", "SINGULAR_RCOND", "FACTOR_MAX", "NULL_DENSE_MAX", "FACTOR_RANK_RTOL"]

SINGULAR_RCOND = 1e-12
"""Equilibrated stiffness matrices with a smaller reciprocal condition number count as singular."""

FACTOR_MAX = 1200
"""Largest number of free DOFs solved from the stiffness factor (dense QR, O(r n^2))."""

NULL_DENSE_MAX = 600
"""Above this many free DOFs the free motions of a singular system are found by sparse
shift-invert (a few lowest eigenpairs), not by a dense eigendecomposition (a 1,000-body model took
76 s and 1.6 GB before naming its free motion)."""

FACTOR_RANK_RTOL = 1e-12
"""The factored solve is used when every pivot of R exceeds this times the first (else the
singular-system path names the free motions)."""


@dataclass(frozen=True)
class StaticSolution:
    """The solution of :func:`static_solve`.

    Attributes
    ----------
    x : (k,) or (k, m) ndarray
        Displacements of the free DOFs [m, rad] (one column per load column).
    free_motions : tuple of str
        The free motions of a system that is not fully restrained, described ("body 'engine' is free
        to move in x"); the load is orthogonal to them and ``x`` is the minimum-norm solution. Empty
        when the system is restrained.
    """

    x: np.ndarray
    free_motions: tuple[str, ...] = ()


def static_solve(a: Assembly, rhs: Any, free: Any = None, kff: Any = None) -> StaticSolution:
    """``K_ff x = rhs`` on the free DOFs of an assembly, exact on badly scaled stiffness.

    The other DOFs are held fixed (their prescribed part of the load is the caller's). See the
    module docstring for the method: the stiffness factor's pivoted QR up to :data:`FACTOR_MAX`
    free DOFs, else the equilibrated Cholesky (dense) or sparse LU with a condition estimate; on a
    singular system the free motions are found and named.

    Parameters
    ----------
    a : Assembly
        The assembled model (its stiffness factor and mounts).
    rhs : (k,) or (k, m) array_like
        Generalised load on the free DOFs [N, N m], one column per load case.
    free : (k,) int array_like or None
        Indices of the free DOFs into ``a.dofs`` (None: every DOF).
    kff : (k, k) ndarray or sparse matrix, optional
        ``K[free][:, free]``, when the caller has it (else taken from ``a.K``).

    Returns
    -------
    StaticSolution

    Raises
    ------
    AnalysisError
        The load pushes along a motion the mounts do not restrain (named in the message).

    Examples
    --------
    >>> from ... import Body, Model, Mount, MountType
    >>> from ..plant.assemble import assemble
    >>> m = Model([Body("b", 10.0, [1, 1, 1])], [Mount("m", MountType("t", [1e4, 1e4, 2e4]), "b")])
    >>> a = assemble(m)
    >>> f = np.zeros(6)
    >>> f[2] = -98.1
    >>> s = static_solve(a, f[:3], free=[0, 1, 2])
    >>> round(float(s.x[2]), 6), s.free_motions
    (-0.004905, ())
    """
    free = np.arange(a.n) if free is None else np.asarray(free, dtype=int)
    rhs = np.asarray(rhs, dtype=float)
    if kff is None:
        K = a.K
        kff = K[np.ix_(free, free)] if not sp.issparse(K) else K[free][:, free]
    x, notes = _solve(a, kff, rhs, free)
    return StaticSolution(x, notes)


def _solve(a: Assembly, kff: Any, rhs: np.ndarray, free: np.ndarray) -> tuple[np.ndarray, tuple[str, ...]]:
    """Solve the equilibrated system; on a singular one, name the free motions. ``rhs`` (k,) or
    (k, m): the scalings broadcast down its rows, so a single load takes the vector path's bits."""
    diag = np.asarray(kff.diagonal()).ravel()
    # a DOF whose stiffness is below eps^2 of the largest is unrestrained: a denormal 1e-323 N/m left
    # by round-off (issue 18's fuzzer) would otherwise scale the system by 1e161 and solve to 1e164 m
    live = diag > np.finfo(float).eps ** 2 * max(float(diag.max(initial=0.0)), np.finfo(float).tiny)
    d = 1.0 / np.sqrt(np.where(live, diag, 1.0))
    dr = d.reshape(-1, *([1] * (rhs.ndim - 1)))          # d down the rows of rhs
    if sp.issparse(kff):
        ks = sp.csc_matrix(sp.diags(d) @ kff @ sp.diags(d))
    else:
        ks = d[:, None] * kff * d[None, :]
    singular = bool(np.any(~live)) or _unconnected(a, free)
    factored = free.size <= FACTOR_MAX and len(a.model.mounts) > 0
    if not singular and factored:
        x = _factored_solve(a.stiffness_factor()[:, free], rhs)
        if x is not None:
            return x, ()
        # the factor's pivoted QR found it rank deficient: a free motion, whatever round-off left in K
        # (K's Cholesky can then succeed and return 1e164 m; issue 18's fuzzer)
        singular = True
    if not singular:
        try:
            solve = _factor(ks)
            norm = abs(ks).sum(axis=0).max()
            op = spl.LinearOperator(ks.shape, matvec=solve, rmatvec=solve, dtype=float)
            inv_norm = _onenormest(op) if ks.shape[0] > 4 else np.abs(np.linalg.inv(_dense(ks))).sum(0).max()
            singular = 1.0 / (norm * inv_norm) < SINGULAR_RCOND
        except (np.linalg.LinAlgError, RuntimeError):
            singular = True
        if not singular:
            return dr * solve(dr * rhs), ()
    # Singular: null space of the equilibrated matrix (dense up to NULL_DENSE_MAX DOFs, else sparse)
    if free.size > NULL_DENSE_MAX:
        v = _sparse_null(ks)
        w, null = np.zeros(v.shape[1]), np.ones(v.shape[1], dtype=bool)
    elif factored:
        # ks = (G D)^T (G D): its eigenpairs from the Jacobi SVD of the equilibrated factor, to high
        # relative accuracy (K's own eigenvalues can hide a free motion under round-off of 1e-10)
        gd = a.stiffness_factor()[:, free].toarray() * d[None, :]
        if gd.shape[0] < gd.shape[1]:
            gd = np.vstack([gd, np.zeros((gd.shape[1] - gd.shape[0], gd.shape[1]))])
        sva, vv, work = jacobi_svd(gd)
        order = np.argsort(sva)
        w, v = ((work[0] / work[1]) * sva[order]) ** 2, vv[:, order]
        null = w <= np.sqrt(SINGULAR_RCOND) * max(w.max(), np.finfo(float).tiny) * 1e-2
    else:
        w, v = symmetric_eigen(_dense(ks))
        null = w <= np.sqrt(SINGULAR_RCOND) * max(w.max(), np.finfo(float).tiny) * 1e-2
    basis = d[:, None] * v[:, null]                     # back to physical DOFs
    full = np.zeros((a.n, basis.shape[1]))
    full[free] = basis
    M = a.M                 # sparse on a sparse assembly (a dense copy cost 1.6 GB at 1,000 bodies)
    full = align_cluster(full / np.sqrt(np.einsum("ij,ij->j", full, M @ full)), M)
    full = full[:, np.argsort(np.argmax(np.abs(full), axis=0), kind="stable")]  # DOF order
    names = a.model.body_names
    described = [describe_motion(full[:, j], names) for j in range(full.shape[1])]
    size = np.linalg.norm(rhs) if rhs.ndim == 1 else np.linalg.norm(rhs, axis=0)   # per load column
    load_along = [j for j in range(full.shape[1])
                  if np.any(np.abs(full[free, j] @ rhs) > 1e-9 * size * np.linalg.norm(full[free, j]))]
    if load_along:
        raise AnalysisError("the mounts do not restrain the load: "
                            + "; ".join(described[j] for j in load_along)
                            + " (add mounts or stiffness in that direction, or prescribe it)")
    # minimum-norm solution on the restrained subspace (y = x / d orthogonal to the null vectors):
    # from the factor, with the constraints appended as rows, when the model is small enough
    if factored and null.any():
        g = a.stiffness_factor()[:, free].toarray()
        cons = (v[:, null] / d[:, None]).T
        weight = np.abs(g).max() / max(float(np.abs(cons).max()), np.finfo(float).tiny)
        x = _factored_solve(np.vstack([g, weight * cons]), rhs)
        if x is not None:
            return x, tuple(described)
    if free.size > NULL_DENSE_MAX:      # (ks + N N^T) y = d rhs: y is orthogonal to the null space N
        nn = v[:, null]
        y = spl.splu(sp.csc_matrix(ks + sp.csr_matrix(nn @ nn.T))).solve(dr * rhs)
        return dr * y, tuple(described)
    keep = ~null
    y = v[:, keep] @ ((v[:, keep].T @ (dr * rhs)) / w[keep].reshape(-1, *([1] * (rhs.ndim - 1))))
    return dr * y, tuple(described)


def _sparse_null(ks: Any) -> np.ndarray:
    """(n, k) orthonormal null vectors of the equilibrated singular ``ks``, sparse.

    Per connected component of its pattern (a body cut off, a DOF with no stiffness): a small
    component by dense eigen, a large one only when its sparse LU says it is singular, by
    shift-invert (the eigen module's path) for its lowest eigenpairs, enough to hold its null space.
    """
    ks = sp.csc_matrix(ks)
    n = ks.shape[0]
    _, labels = csgraph.connected_components(abs(ks) > 0, directed=False)
    top = float(abs(ks).sum(axis=0).max())              # >= the largest eigenvalue
    tol = np.sqrt(SINGULAR_RCOND) * top * 1e-2
    out = []
    for c in range(labels.max() + 1):
        idx = np.flatnonzero(labels == c)
        block = ks[idx][:, idx]
        if idx.size <= NULL_DENSE_MAX:
            w, v = symmetric_eigen(block.toarray())
        else:
            try:
                solve = _factor(block)
                op = spl.LinearOperator(block.shape, matvec=solve, rmatvec=solve, dtype=float)
                if 1.0 / (abs(block).sum(axis=0).max() * spl.onenormest(op)) >= SINGULAR_RCOND:
                    continue                            # regular: no free motion here
            except (np.linalg.LinAlgError, RuntimeError):
                pass
            k = 6
            while True:
                spectrum = undamped(block, sp.identity(idx.size, format="csc"), n_modes=min(k, idx.size - 2),
                                    method="shift-invert")
                w, v = spectrum.omega2, spectrum.phi
                if not (w <= tol).all() or k >= idx.size - 2:
                    break
                k *= 4
        for j in np.flatnonzero(w <= tol):
            full = np.zeros(n)
            full[idx] = v[:, j]
            out.append(full)
    return np.array(out).T.reshape(n, len(out))


def _onenormest(op: Any) -> float:
    """``scipy.sparse.linalg.onenormest`` with its random start vectors seeded: the same model gives
    the same verdict whatever the caller's random state (the estimate draws from numpy's global
    generator), and the caller's state is left as it was."""
    state = np.random.get_state()
    try:
        np.random.seed(0)
        return float(spl.onenormest(op))
    finally:
        np.random.set_state(state)


def _factored_solve(g: Any, rhs: np.ndarray) -> np.ndarray | None:
    """``x`` with ``G^T G x = rhs`` by QR of G (rows sorted by size, columns pivoted); None if G
    is rank deficient (a pivot below :data:`FACTOR_RANK_RTOL` of the first)."""
    gd = g.toarray() if sp.issparse(g) else np.asarray(g, float)
    if gd.shape[0] < gd.shape[1]:
        return None
    order = np.argsort(-np.abs(gd).max(axis=1), kind="stable")
    r, piv = sl.qr(gd[order], mode="r", pivoting=True, check_finite=False)
    r = r[:gd.shape[1]]
    d = np.abs(np.diag(r))
    if d.size == 0 or not d[-1] > FACTOR_RANK_RTOL * d[0]:
        return None
    y = sl.solve_triangular(r, rhs[piv], trans="T", check_finite=False)
    z = sl.solve_triangular(r, y, check_finite=False)
    x = np.empty_like(z)
    x[piv] = z
    return x


def _factor(ks: Any) -> Any:
    if sp.issparse(ks):
        lu = spl.splu(ks)
        return lu.solve
    c = sl.cho_factor(ks, check_finite=False)
    return lambda b: sl.cho_solve(c, b, check_finite=False)


def _dense(ks: Any) -> np.ndarray:
    return ks.toarray() if sp.issparse(ks) else np.asarray(ks)


def _unconnected(a: Assembly, free: np.ndarray) -> bool:
    """Whether some body has no path of mounts to ground (then all its DOFs are free)."""
    nb = len(a.model.bodies)
    if len(a.b_index) == 0:
        return True
    to = np.minimum(a.a_index, nb)        # every support is ground too
    g = sp.coo_matrix((np.ones(len(a.b_index)), (a.b_index, to)), shape=(nb + 1, nb + 1))
    _, labels = csgraph.connected_components(g, directed=False)
    return bool(np.any(labels[:nb] != labels[nb]))
