"""The mounts summed over the DOFs, for :func:`vibss.linear.plant.assemble.assemble`: where each mount
acts, its matrices in global axes, the COO pattern of its four 6x6 blocks, the mass, and K, C, H
summed by scipy's own kernels (their order of summation is part of the answer: a dense assembly
gives the sparse one's digits bit for bit).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp

try:
    from scipy.sparse import _sparsetools          # scipy's own COO/CSR kernels (see _coo_dense)
except ImportError:       # pragma: no cover - a scipy that moved them
    _sparsetools = None

from ...errors import ModelError
from ...model.geometry import point_transfer
from ...model.model import Model

__all__: list[str] = []


@dataclass(slots=True)      # private and never changed: a plain __init__ (built on every assembly)
class _MountPoints:
    """Where each mount acts: ``b_index``/``a_index`` its two nodes (bodies, then the rigid ground
    and each support), ``r_b``/``r_a`` (nm, 3) its point from each node's reference point [m], ``t``
    (nm, 3, 3) its local axes; ``n`` body DOFs and ``nz`` ground DOFs."""

    b_index: np.ndarray
    a_index: np.ndarray
    r_b: np.ndarray
    r_a: np.ndarray
    t: np.ndarray
    n: int
    nz: int


def _mount_points(model: Model) -> _MountPoints:
    nb = len(model.bodies)
    n = 6 * nb
    names = {b.name: i for i, b in enumerate(model.bodies)}
    ng = 1 + len(model.supports)                    # ground nodes: the rigid ground, then each support
    nz = 6 * ng
    cogs = np.zeros((nb + ng, 3))                   # the bodies' COGs, then ground's (the origin)
    cogs[:nb] = [b.cog for b in model.bodies]
    nm = len(model.mounts)
    # each mount read once: its two nodes, whether its point is in body axes, the point and the axes
    ends, at, t = [], [], []
    for m in model.mounts:
        ends.append((names[m.body], names[m.to] if m.to in names else nb + model.ground_node(m), m.frame == "body"))
        at.append(m.at)
        t.append(m.orientation.matrix)
    e = np.array(ends, dtype=int).reshape(nm, 3)
    b_index, a_index = e[:, 0].copy(), e[:, 1].copy()
    cog_b = cogs[b_index]
    p = np.array(at, dtype=float).reshape(nm, 3) + np.where(e[:, 2, None] == 1, cog_b, 0.0)
    r_b, r_a = p - cog_b, p - cogs[a_index]
    return _MountPoints(b_index, a_index, r_b, r_a, np.array(t, dtype=float).reshape(nm, 3, 3), n, nz)


@dataclass(slots=True)      # private and never changed: a plain __init__ (built on every assembly)
class _MountMatrices:
    """Every mount's 3x3 matrices in global axes, (nm, 3, 3) each: translational stiffness ``kp``
    [N/m], damping ``cp`` [N s/m], hysteretic stiffness ``hp`` [N/m]; rotational ``krp`` [N m/rad],
    ``crp`` [N m s/rad]; the coupling blocks ``kcp``, ``ccp`` of full 6x6 matrices."""

    kp: np.ndarray
    cp: np.ndarray
    hp: np.ndarray
    krp: np.ndarray
    crp: np.ndarray
    kcp: np.ndarray
    ccp: np.ndarray
    k: np.ndarray | None = None
    kr: np.ndarray | None = None


_RATES = ("stiffness", "damping", "rotational_stiffness", "rotational_damping")
"""The mount types' principal rates that :func:`_mount_matrices` turns into global axes."""


def _mount_matrices(model: Model, t: np.ndarray) -> _MountMatrices:
    nm = len(model.mounts)
    # every principal rate of every mount type read in one pass (once per type: mounts share them),
    # turned in one einsum: (nm, 5, 3, 3) for k, c, eta k, kr, cr (the same products and sums per
    # entry as one einsum per rate)
    index: dict[int, int] = {}
    types: list[Any] = []
    which: list[int] = []
    for m in model.mounts:
        i = index.get(id(m.type))
        if i is None:
            i = index[id(m.type)] = len(types)
            types.append(m.type)
        which.append(i)
    rates = np.array([[getattr(mt, key) for key in _RATES] + [mt.loss_factor] for mt in types],
                     dtype=float).reshape(len(types), 5, 3)
    d = rates[which]                            # (nm, 5, 3): each mount's type's rows (a copy)
    d[:, 4] = d[:, 0] * d[:, 4]                 # eta k: the same product per entry, for every mount at once
    turned = np.einsum("pij,pqj,pkj->qpik", t, d, t)
    kp, cp, krp, crp, hp = (np.ascontiguousarray(x) for x in turned)
    kcp, ccp = np.zeros((nm, 3, 3)), np.zeros((nm, 3, 3))
    full = [mt.stiffness_matrix is not None or mt.damping_matrix is not None for mt in types]
    for im, m in enumerate(model.mounts):    # full 6x6 matrices: their blocks turned into global axes
        if not full[which[im]]:
            continue
        for kind, (tt, rr, tr) in (("stiffness", (kp, krp, kcp)), ("damping", (cp, crp, ccp))):
            if getattr(m.type, f"{kind}_matrix") is None:
                continue
            k6 = m.type.local_matrix(kind)
            if not np.any(k6 - np.diag(np.diag(k6))):
                continue                     # diagonal: the rates' own (bit-identical) path above
            tm = t[im]
            tt[im], rr[im], tr[im] = tm @ k6[:3, :3] @ tm.T, tm @ k6[3:, 3:] @ tm.T, tm @ k6[:3, 3:] @ tm.T
    return _MountMatrices(kp, cp, hp, krp, crp, kcp, ccp, d[:, 0], d[:, 2])


@dataclass(slots=True)      # private and never changed: a plain __init__ (built on every assembly)
class _BlockPattern:
    """The COO pattern of the four 6x6 blocks of every mount, shared by K, C and H: ``rows``,
    ``cols`` into ``[q; q_ground]``; ``lb``, ``la`` (nm, 3, 6) the point transfers from each node
    (:func:`_rotation_rows`: the relative rotation ``theta_body - theta_to``)."""

    rows: np.ndarray
    cols: np.ndarray
    lb: np.ndarray
    la: np.ndarray
    n: int
    nz: int
    sides: tuple[int, ...]


_INT32_MAX = 2 ** 31 - 1
"""``np.iinfo(np.int32).max`` (``np.iinfo`` costs microseconds a call on a small model)."""
_SIX = np.arange(6)
_ROW_SIDES, _COL_SIDES = np.array([0, 1, 0, 1]), np.array([0, 1, 1, 0])
"""The four blocks (b, b), (a, a), (b, a), (a, b) of a mount: the side of their rows and columns."""


def _block_pattern(at: _MountPoints) -> _BlockPattern:
    nm = at.b_index.size
    both = point_transfer(np.concatenate([at.r_b, at.r_a]).reshape(2, nm, 3))   # L(r_b), L(r_a)
    # int32 as scipy's kernels take them (an index type chosen by the size, as scipy chooses it)
    dtype = np.int32 if 6 * (at.n + at.nz) < _INT32_MAX else np.int64
    ends = (6 * np.concatenate([at.b_index, at.a_index]).reshape(2, nm, 1) + _SIX).astype(dtype)
    # the four blocks (b, b), (a, a), (b, a), (a, b) of every mount, row-major 6 x 6 each
    # every mount to ground: the blocks (a, a) and (a, b) fill ground rows alone, which no matrix
    # reads (K, C, H are the body rows: their entries, and so their sums, are the same without them)
    sides = (0, 2) if not np.count_nonzero(at.a_index < at.n // 6) else (0, 1, 2, 3)
    rows, cols = np.empty((len(sides), nm, 6, 6), dtype), np.empty((len(sides), nm, 6, 6), dtype)
    rows[...] = ends[_ROW_SIDES[list(sides)], :, :, None]     # along each block's rows
    cols[...] = ends[_COL_SIDES[list(sides)], :, None, :]     # along each block's columns
    return _BlockPattern(rows.ravel(), cols.ravel(), both[0], both[1], at.n, at.nz, sides)


def _rotation_rows(nm: int) -> np.ndarray:
    """(nm, 3, 6) the relative rotation ``theta_body - theta_to`` of each mount from its 6 DOFs."""
    rot = np.zeros((nm, 3, 6))
    rot[:, :, 3:] = np.eye(3)
    return rot


def _values(model: Model, pat: _BlockPattern, kmat: np.ndarray, rotational: list, coupling: list) -> np.ndarray:
    """(q, s nm 36) COO values of the mounts' 6x6 blocks ``pat.sides`` (of (b, b), (a, a), (b, a),
    (a, b)) for each of ``q`` matrices: ``kmat`` (q, nm, 3, 3) their translational parts,
    ``rotational`` and ``coupling`` each matrix's 6x6 parts or None (the same products and sums as
    one matrix at a time)."""
    lb, la, sides = pat.lb, pat.la, pat.sides
    lbt, lat = lb.transpose(0, 2, 1), la.transpose(0, 2, 1)
    kb, ka = kmat @ lb, kmat @ la                       # (q, nm, 3, 6) each
    q = kmat.shape[0]
    with np.errstate(over="ignore", invalid="ignore"):
        blocks = {0: lambda: lbt @ kb, 1: lambda: lat @ ka, 2: lambda: -(lbt @ ka), 3: lambda: -(lat @ kb)}
        vals = np.concatenate([blocks[side]().reshape(q, -1) for side in sides], axis=1)
        for i, (rotational_i, coupling_i) in enumerate(zip(rotational, coupling)):
            if rotational_i is None and coupling_i is None:
                continue
            rot = _rotation_rows(lb.shape[0])
            if rotational_i is not None:                # 6x6 mounts: the same blocks
                rr = (rot.transpose(0, 2, 1) @ rotational_i @ rot).ravel()
                vals[i] = vals[i] + np.concatenate([(rr, rr, -rr, -rr)[side] for side in sides])
            if coupling_i is not None:                  # delta^T kc theta + theta^T kc^T delta
                cr = coupling_i @ rot                   # (nm, 3, 6)
                bb, aa = lbt @ cr, lat @ cr
                bbt, aat = bb.transpose(0, 2, 1), aa.transpose(0, 2, 1)
                terms = (bb + bbt, aa + aat, -(bb + aat), -(aa + bbt))
                vals[i] = vals[i] + np.concatenate([terms[side].ravel() for side in sides])
    if np.count_nonzero(np.isfinite(vals)) != vals.size:
        nm = lb.shape[0]
        bad = int(np.flatnonzero((~np.isfinite(vals.reshape(q, len(sides), nm, 36))).any(axis=(0, 1, 3)))[0])
        raise ModelError(f"mount {model.mounts[bad].name!r}: its stiffness or damping about the COG "
                         "overflows (an extreme value or position); check its point and type")
    return vals


def _coo_dense(vals: np.ndarray, rows: np.ndarray, cols: np.ndarray, nrow: int, ncol: int) -> Any:
    """``csr_matrix((vals, (rows, cols))).toarray()`` by scipy's own kernels in scipy's own order
    (COO to CSR, the row sort where the rows are unsorted, the duplicates summed, the dense copy),
    without the sparse objects' construction and checks (about 0.1 ms of a 6-DOF model's 1 ms):
    the same sums bit for bit (the order in which duplicates are added is part of the answer).
    Falls back to the public path if the kernels are not where this scipy keeps them."""
    st = _sparsetools
    if st is None:            # pragma: no cover - a scipy that moved them
        return sp.csr_matrix((vals, (rows, cols)), shape=(nrow, ncol)).toarray()
    nnz = vals.size
    idx = np.int32 if max(nnz, nrow, ncol) < _INT32_MAX else np.int64
    indptr, indices, data = np.empty(nrow + 1, idx), np.empty(nnz, idx), np.empty(nnz)
    st.coo_tocsr(nrow, ncol, nnz, rows.astype(idx, copy=False), cols.astype(idx, copy=False),
                 np.ascontiguousarray(vals, float),
                 indptr, indices, data)
    if not st.csr_has_canonical_format(nrow, indptr, indices):
        if not st.csr_has_sorted_indices(nrow, indptr, indices):
            st.csr_sort_indices(nrow, indptr, indices, data)
        st.csr_sum_duplicates(nrow, ncol, indptr, indices, data)
    out = np.zeros((nrow, ncol))
    st.csr_todense(nrow, ncol, indptr, indices, data, out)
    return out


def _mass(model: Model, sparse: bool) -> np.ndarray | sp.csr_matrix:
    if sparse:
        return sp.block_diag([b.mass_matrix for b in model.bodies], format="csr")
    if len(model.bodies) == 1:
        return model.bodies[0].mass_matrix          # a new array: the body's block is the matrix
    n = 6 * len(model.bodies)
    mass = np.zeros((n, n))                         # the same numbers, no sparse bookkeeping
    for i, b in enumerate(model.bodies):
        mass[6 * i:6 * i + 6, 6 * i:6 * i + 6] = b.mass_matrix
    return mass


def _summed(model: Model, pat: _BlockPattern, mm: _MountMatrices, sparse: bool,
            keys: tuple[str, ...] = ("K", "C", "H")) -> tuple[dict[str, Any], dict[str, np.ndarray]]:
    """``keys`` of K, C and H of the body DOFs, and each one's (n, nz) coupling to ground, by name.

    The COO triplets are summed by scipy (its order of summation is part of the answer); on a
    dense assembly every nonzero matrix goes through scipy's kernels in one call, its rows stacked
    below the others' (each row's entries, hence its sums, exactly as for that matrix alone)."""
    n, nz = pat.n, pat.nz
    every = {"K": (mm.kp, mm.krp, mm.kcp), "C": (mm.cp, mm.crp, mm.ccp), "H": (mm.hp, None, None)}
    parts = {key: every[key] for key in keys}
    # which parts are there (count_nonzero: .any()'s answer, NaN counted, without its Python wrapper)
    present = {key: tuple(None if x is None or not np.count_nonzero(x) else x for x in part)
               for key, part in parts.items()}
    live = [key for key, part in present.items() if key == "K" or any(x is not None for x in part)]
    mats: dict[str, Any] = {}
    couplings: dict[str, np.ndarray] = {}
    for key in parts:
        if key not in live:                     # no dampers / no hysteresis: zeros
            mats[key] = sp.csr_matrix((n, n)) if sparse else np.zeros((n, n))
            couplings[key] = np.zeros((n, nz))
    if not live:
        return mats, couplings
    kmat = parts[live[0]][0][None] if len(live) == 1 else np.array([parts[key][0] for key in live])
    vals = _values(model, pat, kmat,
                   [present[key][1] for key in live], [present[key][2] for key in live])
    size = n + nz
    if not sparse:
        q = len(live)
        rows = pat.rows if q == 1 else (pat.rows[None, :] + size * np.arange(q)[:, None]).ravel()
        cols = pat.cols if q == 1 else np.concatenate([pat.cols] * q)
        full = _coo_dense(vals.ravel(), rows, cols, q * size, size).reshape(q, size, size)
        for i, key in enumerate(live):
            # one sum per entry, zeros as the sparse path leaves them: bit for bit its matrix
            body = full[i, :n, :n]
            mats[key], couplings[key] = 0.5 * (body + body.T) + 0.0, full[i, :n, n:].copy()
        return {key: mats[key] for key in parts}, {key: couplings[key] for key in parts}
    for i, key in enumerate(live):
        f = sp.csr_matrix((vals[i], (pat.rows, pat.cols)), shape=(size, size))
        body_part = f[:n, :n]
        body_part = 0.5 * (body_part + body_part.T)  # exact symmetry despite summation order
        mats[key], couplings[key] = body_part.tocsr(), f[:n, n:].toarray()
    return {key: mats[key] for key in parts}, {key: couplings[key] for key in parts}
