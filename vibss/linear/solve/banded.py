"""Sparse structure of a plant's dynamic stiffness ``K + iH + sC + s^2 M`` for per-frequency solves.

Rigid bodies joined by mounts couple only the 6 DOFs of the bodies a mount joins, so the dynamic
stiffness is block-sparse. A reverse Cuthill-McKee ordering
(:func:`scipy.sparse.csgraph.reverse_cuthill_mckee`) of the coupling graph makes it *banded* for
chains and other locally connected layouts; LAPACK's banded LU with partial pivoting (``zgbsv``,
as stable as the dense LU it replaces) then costs O(n b^2) per frequency instead of O(n^3).
Layouts that do not band well (half-bandwidth above :data:`BAND_MAX`) are factorised by SuperLU
(:func:`scipy.sparse.linalg.splu`, fill-reducing COLAMD ordering) instead.

The cost constants below were measured on the project's 2-core VM (one BLAS thread,
``benchmarks/bench_frf.py``; read from vibss/data/costs.json, :mod:`vibss.costs`, where
benchmarks/bench_costs.py re-measures them); they only steer the automatic choice of an FRF method.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spl
from scipy.sparse.csgraph import reverse_cuthill_mckee

from ...costs import constant, scale
from ..plant.branches import groups
from ..plant.plant import Plant

__all__ = ["Structure", "structure", "BAND_MAX", "seconds_floor", "elimination", "superlu_seconds"]

BAND_MAX = 48
"""Largest half-bandwidth solved as a band; wider patterns go to SuperLU."""

_T_FREQ = constant("solve.T_FREQ", 3e-5)      # fixed cost per frequency [s] (Python, the right-hand side)
_K_BUILD = constant("solve.K_BUILD", 3.5e-9)   # [s] per band entry assembled (n (2 b + 1) per matrix)
_K_BAND = constant("solve.K_BAND", 2.5e-9)     # [s] per n b^2 of the banded LU
_K_SUPERLU = constant("solve.K_SUPERLU", 5.9e-8)  # [s] per nonzero of L + U of a SuperLU factorisation and solve
_K_SUPERLU_FLOP = constant("solve.K_SUPERLU_FLOP", 4.8e-10)  # [s] per multiply-add of its elimination


@dataclass(frozen=True, eq=False)
class Structure:
    """Ordering and storage of a plant's dynamic stiffness for per-frequency solves.

    Attributes
    ----------
    perm : (n,) int ndarray
        Ordering of the DOFs (row/column ``i`` of the band is DOF ``perm[i]``): the reverse
        Cuthill-McKee one, or the plant's own where that has the narrower band.
    band : int
        Half-bandwidth after the ordering (``|i - j| <= band`` for every coupling).
    banded : bool
        Whether the band is narrow enough for the banded LU (``band <= BAND_MAX``).
    parts : dict of str to ndarray or scipy.sparse matrix
        ``"K"``, ``"C"``, ``"M"``, ``"H"`` (only the nonzero ones) and ``"G0"``, ``"G1"`` ... (the
        frequency-dependent mounts' :func:`~vibss.linear.plant.branches.groups`): LAPACK band storage of the
        reordered matrix, shape ``(2 band + 1, n)``, when ``banded``; else CSC matrices in the
        original order.
    seconds_per_frequency : float
        Estimated cost of one solve [s] (for choosing a method; not a measurement).
    fill : int
        Nonzeros of ``L + U`` of the trial SuperLU factorisation (0 when ``banded``: none is made).
    flops : float
        Multiply-adds of that factorisation's elimination, ``sum_k`` (column k of L below the pivot)
        x (row k of U right of it) (0 when ``banded``).
    """

    perm: np.ndarray
    band: int
    banded: bool
    parts: dict
    seconds_per_frequency: float
    fill: int = 0
    flops: float = 0.0


def _bandwidth(pattern: sp.csr_matrix, order: np.ndarray) -> int:
    """Half-bandwidth of ``pattern`` with rows and columns in ``order``."""
    q = pattern[order][:, order].tocoo()
    return int(np.abs(q.row - q.col).max()) if q.nnz else 0


def _gb_layout(a: sp.spmatrix, perm: np.ndarray, band: int) -> np.ndarray:
    """``a[perm][:, perm]`` as LAPACK band storage: entry (i, j) at row ``band + i - j``, column j.

    ``gbsv`` wants ``band`` more rows on top (room for the fill of pivoting); the solver adds them.
    """
    q = sp.csr_matrix(a)[perm][:, perm].tocoo()
    q.eliminate_zeros()                   # stored zeros lie outside the pattern the band came from
    out = np.zeros((2 * band + 1, a.shape[0]))
    out[band + q.row - q.col, q.col] = q.data
    return out


def _dense_structure(raw: dict, n: int) -> Structure | None:
    """:func:`structure` of a dense plant when it bands: the same ordering, band and band storage (the
    stored values themselves, placed by index), without the sparse copies, slices and COO forms
    (150 DOF: 0.6 ms against 2.7 ms). None when it does not band (the sparse route factorises it)."""
    mats = {key: np.asarray(a, dtype=float) for key, a in raw.items()}
    mats = {key: a for key, a in mats.items() if key == "K" or key.startswith("G") or np.count_nonzero(a)}
    hit = np.zeros((n, n), dtype=bool)
    for a in mats.values():
        hit |= a != 0
    rows, cols = np.nonzero(hit)
    pattern = sp.csr_matrix((np.ones(rows.size), (rows, cols)), shape=(n, n))
    best = None
    for i, order in enumerate((np.arange(n), reverse_cuthill_mckee(pattern, symmetric_mode=True).astype(int))):
        inv = np.empty(n, dtype=int)
        inv[order] = np.arange(n)
        width = int(np.abs(inv[rows] - inv[cols]).max()) if rows.size else 0
        if best is None or (width, i) < best[:2]:
            best = (width, i, order, inv)
    assert best is not None
    band, _, perm, inv = best
    if band > BAND_MAX:
        return None
    parts = {}
    for key, a in mats.items():
        r, c = np.nonzero(a)
        out = np.zeros((2 * band + 1, n))
        out[band + inv[r] - inv[c], inv[c]] = a[r, c]
        parts[key] = out
    cost = scale("solve.banded") * (_T_FREQ + _K_BUILD * n * (2 * band + 1) * len(parts)
                                    + _K_BAND * n * max(band, 1) ** 2)
    return Structure(perm, band, True, parts, cost)


def seconds_floor(n: int) -> float:
    """The least one sparse solve of ``n`` DOFs can cost [s] (a half-bandwidth of 1), by the same
    constants as :attr:`Structure.seconds_per_frequency`: a method cheaper than ``nf`` times this
    needs no :func:`structure` to be chosen over the sparse solve."""
    return _T_FREQ + _K_BAND * n


def structure(plant: Plant) -> Structure:
    """Order and store ``K, C, M, H`` of a plant for per-frequency solves (see the module docstring).

    Parameters
    ----------
    plant : Plant
        Dense or sparse ``M, C, K, H``.

    Returns
    -------
    Structure

    Examples
    --------
    A chain of three bodies on mounts couples each body to its neighbours only:

    >>> from ... import Body, Model, Mount, MountType
    >>> from ..plant.build import build_plant
    >>> t = MountType("t", [1e5, 1e5, 1e5], [10.0, 10.0, 10.0])
    >>> bodies = [Body(f"b{i}", 10.0, [1, 1, 1], cog=[i, 0, 0]) for i in range(3)]
    >>> mounts = [Mount("g", t, "b0", at=[0.2, 0.1, -0.3])] + [
    ...     Mount(f"m{i}", t, f"b{i}", to=f"b{i - 1}", at=[-0.5, 0.1, -0.2]) for i in (1, 2)]
    >>> st = structure(build_plant(Model(bodies, mounts), ["b2.fz"], ["b0.z"]))
    >>> st.band, st.banded, st.parts["K"].shape   # neighbours' DOFs 6 + 5 apart; 2 band + 1 rows
    (11, True, (23, 18))
    """
    n = plant.n
    raw = {key: getattr(plant, key) for key in ("K", "C", "M", "H")}
    raw.update({f"G{j}": g.K for j, g in enumerate(groups(plant))})   # branches
    if not any(sp.issparse(a) for a in raw.values()):
        dense = _dense_structure(raw, n)        # a dense plant: its pattern and band read by NumPy
        if dense is not None:
            return dense
    mats = {key: sp.csr_matrix(a) for key, a in raw.items()}
    mats = {key: a for key, a in mats.items() if a.count_nonzero() or key in ("K",) or key.startswith("G")}
    pattern = sum(abs(a) for a in mats.values())
    pattern = sp.csr_matrix(pattern)
    band, perm = min((_bandwidth(pattern, order), i, order) for i, order in enumerate(
        (np.arange(n), reverse_cuthill_mckee(pattern, symmetric_mode=True).astype(int))))[::2]
    if band <= BAND_MAX:
        parts = {key: _gb_layout(a, perm, band) for key, a in mats.items()}
        cost = scale("solve.banded") * (_T_FREQ + _K_BUILD * n * (2 * band + 1) * len(parts)
                                        + _K_BAND * n * max(band, 1) ** 2)
        return Structure(perm, band, True, parts, cost)
    csc = {key: a.tocsc() for key, a in mats.items()}
    # the fill of L + U from a trial factorisation of a diagonally dominant matrix of this pattern
    trial = sp.csc_matrix(pattern + sp.diags(np.asarray(abs(pattern).sum(axis=1)).ravel() + 1.0))
    fill, flops = elimination(spl.splu(trial))
    # fill and flops: 0.75-1.71x measured / estimated on the random graph, lattice, tree and tower at
    # 150-2,400 DOF (fill alone, the model before: up to 4x under on the 2,400-DOF random graph,
    # whose fill is near dense and whose flops grow as fill^1.5; nnz(L + U)^2 / n, before that: 4x
    # over at 60,000 DOF)
    cost = scale("solve.superlu") * superlu_seconds(fill, flops)
    return Structure(perm, band, False, csc, cost, fill, flops)


def elimination(lu: Any) -> tuple[int, float]:
    """Nonzeros of ``L + U`` and multiply-adds of a SuperLU factorisation (:func:`scipy.sparse.linalg.splu`):
    pivot k updates (column k of L below it) x (row k of U right of it). A trial factorisation of a
    diagonally dominant matrix with the plant's pattern keeps the solve's ordering and pivots."""
    fill = int(lu.L.nnz + lu.U.nnz)
    below = np.diff(sp.csc_matrix(lu.L).indptr).astype(float) - 1     # SuperLU's int32 indices: the sum
    right = np.diff(sp.csr_matrix(lu.U).indptr).astype(float) - 1     # in floats (n^3 / 3 passes 2^31)
    return fill, float(np.dot(below, right))


def superlu_seconds(fill: float, flops: float) -> float:
    """Unscaled seconds of one SuperLU factorisation and solve with ``fill`` nonzeros in ``L + U`` and
    ``flops`` multiply-adds (:class:`Structure`), by the constants of ``vibss/data/costs.json``."""
    return _T_FREQ + _K_SUPERLU * fill + _K_SUPERLU_FLOP * flops
