"""Kernels of :mod:`vibss.reduction`: exact pruning and the exact response used to check reductions.

Pruning
-------
``prune_dofs``: connected components of the DOF coupling graph (the pattern of M, C, K, H, an entry
counting when ``|a_ij| > ZERO_RTOL sqrt(|a_ii a_jj|)``); a component that no input excites (F, Kz,
Cz, Mz, Hz) or no output sees (Oq, Ov, Oa, Oh) is removed: its contribution to every output is
zero for zero initial conditions.

``prune_modes``: the same on the undamped modes (M = I, K = diagonal; the graph is that of
``Phi^T C Phi`` and ``Phi^T H Phi``). Repeated frequencies are first rotated within their cluster
so that the inputs excite as few of them as possible (SVD of the cluster's participations). A
component whose modal participation is zero to round-off (``PART_RTOL``) on the input or output
side is removed.

Modal truncation lives in :mod:`vibss.reduction.truncation`.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from ..linear.eigen.undamped import undamped
from ..linear.plant.plant import Plant
from ..linear.solve.exact import response

__all__ = ["Removal", "sub_plant", "modal_plant", "prune_dofs", "prune_modes", "frf", "ZERO_RTOL",
           "PART_RTOL", "DENSE_MAX"]

ZERO_RTOL = 1e-12
"""Coupling entries below this fraction of ``sqrt(|a_ii a_jj|)`` count as zero (round-off)."""

PART_RTOL = 1e-10
"""Modal participations below this fraction of their column's (row's) largest count as zero."""

DENSE_MAX = 1500
"""Largest number of DOFs for which every mode is computed densely (``eigh``)."""




CLUSTER_RTOL = 1e-8
"""Relative gap below which natural frequencies are treated as repeated."""


@dataclass(frozen=True)
class Removal:
    """What was removed and why.

    Attributes
    ----------
    what : str
        ``"dofs"`` or ``"modes"``.
    names : tuple of str
        Bodies (``'b2 (all 6 DOF)'``), DOFs (``'prism.x'``) or modes (``'mode 3 (12.3 Hz)'``).
    reason : str
        Why it does not affect the scope's outputs.
    exact : bool
        Whether the removal is exact (to round-off).
    """

    what: str
    names: tuple[str, ...]
    reason: str
    exact: bool = True


def _input_side(p: Plant) -> list[np.ndarray]:
    return [a for a in (p.F, p.Kz, p.Cz, p.Mz, p.Hz) if a is not None]


def _output_side(p: Plant) -> list[np.ndarray]:
    return [a for a in (p.Oq, p.Ov, p.Oa, p.Oh) if a is not None]


def sub_plant(p: Plant, keep: np.ndarray) -> Plant:
    """The plant restricted to the DOFs ``keep`` (indices): :meth:`Plant.restrict`."""
    return p.restrict(keep)


def modal_plant(p: Plant, phi: np.ndarray, omega2: np.ndarray, labels: tuple[str, ...],
                pf: np.ndarray | None = None, pz: np.ndarray | None = None) -> Plant:
    """Galerkin projection on M-orthonormal modes ``phi`` (n, k): ``M = I``, ``K = diag(omega2)``.

    ``pf`` and ``pz`` (p, m) are added to ``Pf`` and ``Pz`` (static correction).
    """
    t = phi.T
    modal = p.project(phi, labels, M=np.eye(phi.shape[1]), K=np.diag(omega2), C=t @ p.C @ phi,
                      H=t @ p.H @ phi)
    return replace(modal, Pf=p.Pf if pf is None else p.Pf + pf, Pz=p.Pz if pz is None else p.Pz + pz)


def _pattern(mats: list[np.ndarray]) -> sp.csr_matrix:
    n = mats[0].shape[0]
    rows, cols = [], []
    for a in mats:
        if not np.any(a):
            continue
        d = np.sqrt(np.abs(np.diag(a)))
        i, j = np.nonzero(a)
        big = np.abs(a[i, j]) > ZERO_RTOL * d[i] * d[j] + 1e-300
        rows.append(i[big])
        cols.append(j[big])
    i = np.concatenate(rows) if rows else np.zeros(0, int)
    j = np.concatenate(cols) if cols else np.zeros(0, int)
    return sp.csr_matrix((np.ones(i.size), (i, j)), shape=(n, n))


def _touched_rows(mats: list[np.ndarray], n: int) -> np.ndarray:
    """(n,) bool: rows with an entry above PART_RTOL of its column's largest."""
    hit = np.zeros(n, bool)
    for a in mats:
        a = np.abs(a)
        if a.size == 0:
            continue
        top = a.max(axis=0, keepdims=True)
        hit |= np.any((a > PART_RTOL * top) & (top > 0), axis=1)
    return hit


def _components(pattern: sp.csr_matrix, excited: np.ndarray, seen: np.ndarray) -> tuple[np.ndarray, list[tuple[np.ndarray, str]]]:
    ncomp, label = connected_components(pattern, directed=False)
    keep = np.zeros(label.size, bool)
    dropped = []
    for c in range(ncomp):
        idx = np.flatnonzero(label == c)
        ex, ob = bool(excited[idx].any()), bool(seen[idx].any())
        if ex and ob:
            keep[idx] = True
        else:
            why = ("neither excited by an input nor seen by an output" if not (ex or ob) else
                   "not excited by any input" if not ex else "not seen by any output")
            dropped.append((idx, why))
    return keep, dropped


def _dof_names(dofs: list[str]) -> list[str]:
    by_body: dict[str, list[str]] = {}
    for d in dofs:
        body, _, comp = d.rpartition(".")
        by_body.setdefault(body, []).append(comp)
    out = []
    for body, comps in by_body.items():
        out.append(f"{body} (all 6 DOF)" if len(comps) == 6 else ", ".join(f"{body}.{c}" for c in comps))
    return out


def prune_dofs(p: Plant) -> tuple[Plant, list[Removal]]:
    """Remove DOF groups that the inputs cannot excite or the outputs cannot see (exact)."""
    pattern = _pattern([p.M, p.C, p.K, p.H])
    excited = _touched_rows(_input_side(p), p.n)
    seen = _touched_rows([o.T for o in _output_side(p)], p.n)
    keep, dropped = _components(pattern, excited, seen)
    if not dropped:
        return p, []
    if not keep.any():
        keep[:] = True   # nothing responds: keep the plant as is (its outputs are feedthrough only)
        return p, [Removal("dofs", (), "no DOF is both excited and seen: the outputs are pure feedthrough; "
                                      "nothing removed")]
    removals: dict[str, list[str]] = {}
    for idx, why in dropped:
        removals.setdefault(why, []).extend(p.dofs[i] for i in idx)
    out = [Removal("dofs", tuple(_dof_names(names)), f"decoupled (coupling graph of M, C, K, H): {why}")
           for why, names in removals.items()]
    return sub_plant(p, np.flatnonzero(keep)), out


def _clusters(w2: np.ndarray) -> list[np.ndarray]:
    scale = max(float(np.abs(w2).max()), 1e-300)
    edges = np.flatnonzero(np.diff(w2) > CLUSTER_RTOL * np.maximum(np.abs(w2[1:]), 1e-3 * scale)) + 1
    return [c for c in np.split(np.arange(w2.size), edges) if c.size > 1]


def _rotate_clusters(phi: np.ndarray, w2: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Rotate each repeated-frequency cluster so the inputs ``b`` (n, m) excite its first vectors."""
    phi = phi.copy()
    for c in _clusters(w2):
        u, _, _ = np.linalg.svd(phi[:, c].T @ b, full_matrices=True)
        phi[:, c] = phi[:, c] @ u
    return phi


def mode_labels(freq_hz: np.ndarray, index: np.ndarray) -> tuple[str, ...]:
    """``'mode<k>'`` labels (k from 1 in ascending frequency of the plant analysed)."""
    return tuple(f"mode{int(i) + 1}" for i in index)


def _undamped(p: Plant) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    spec = undamped(p.K, p.M, p.Kf)
    return spec.omega2, spec.phi, spec.rigid


def prune_modes(p: Plant) -> tuple[Plant, list[Removal], bool]:
    """Remove modes with zero input or output participation (exact); returns (plant, removals, modal?).

    The plant comes back in modal coordinates (DOFs ``mode<k>``) only when a mode was removed.
    """
    w2, phi, _ = _undamped(p)
    forcing = np.hstack(_input_side(p))
    phi = _rotate_clusters(phi, w2, forcing)
    t = phi.T
    cm, hm = t @ p.C @ phi, t @ p.H @ phi
    pattern = _pattern([np.eye(p.n), cm, hm])
    excited = _touched_rows([t @ a for a in _input_side(p)], p.n)
    seen = _touched_rows([(o @ phi).T for o in _output_side(p)], p.n)
    keep, dropped = _components(pattern, excited, seen)
    if not dropped or not keep.any():
        return p, [], False
    f = np.sqrt(w2) / (2 * np.pi)
    removals: dict[str, list[str]] = {}
    for idx, why in dropped:
        removals.setdefault(why, []).extend(f"mode {i + 1} ({f[i]:.4g} Hz)" for i in idx)
    out = [Removal("modes", tuple(v), f"zero modal participation: {k}") for k, v in removals.items()]
    kept = np.flatnonzero(keep)
    return modal_plant(p, phi[:, kept], w2[kept], mode_labels(f, kept)), out, True


# ------------------------------------------------------------------------------- evaluation

def frf(p: Plant, s: np.ndarray) -> np.ndarray:
    """Exact response ``Y(s)`` (p, m, nf) of a plant at Laplace points ``s``: the one exact solve,
    :func:`vibss.linear.solve.exact.response` (dense batched LU for small dense plants, banded or SuperLU
    for large or scipy.sparse ones; the 0 Hz limit at ``s = 0``; ``inf`` only where an exactly
    singular resonance is seen and driven)."""
    return response(p, np.atleast_1d(np.asarray(s, complex)))
