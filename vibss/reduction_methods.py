"""Kernels of :mod:`vibss.reduction`: exact pruning, modal truncation with static correction.

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

Modal truncation
----------------
Keep every mode up to the band's top ``w2`` and as many above as the tolerance needs; the rest is
accounted for quasi-statically by the residual flexibility
``R = K_e^+ - Phi_k Omega_k^-2 Phi_k^T`` (elastic part; rigid-body modes are always kept):

- ``Pf += Oq R F`` (force inputs), ``Pz -= Oq R Kz`` (motion inputs, per prescribed coordinate).

Only the displacement-proportional part of the outputs (``Oq``: displacements, deflections, the
spring part of mount and ground forces) receives the correction, and only the stiffness part of
the forcing (``F``, ``Kz``). Velocity and acceleration parts of outputs (``Ov``, ``Oa``) and the
damping/mass coupling of motion inputs (``Cz``, ``Mz``) are not corrected; their truncation
error is in the estimate.

Error estimate (per channel i, j and frequency w)::

    |e_ij(w)| <= |z_j(w)| sum_{a,b=0..2} w^(a+b) sqrt(r(o_a,i)) sqrt(r(b_b,j)) G_ab(w)

with ``r(v) = v^T R v`` (via ``(R v)^T K (R v)``, free of cancellation), output terms
``o_0 = Oq, o_1 = Ov, o_2 = Oa``, input terms ``b_0 = F - Kz, b_1 = -Cz, b_2 = -Mz``,
``G_00 = sup_r |w^2 - i w g_r| / |w_r^2 - w^2 + i w g_r|`` (static correction applied) and
``G_ab = sup_r w_r^2 / |w_r^2 - w^2 + i w g_r|`` otherwise, the sup over the truncated modes:
those computed, then an assumed tail above them with ``g_r = eta w_r^2``, ``eta`` the largest
``g_r / w_r^2`` seen. It is a bound (Cauchy-Schwarz) for classical damping when all modes are
computed, and an estimate otherwise.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
import scipy.linalg as sl
import scipy.sparse as sp
import scipy.sparse.linalg as spl
from scipy.sparse.csgraph import connected_components

from .errors import AnalysisError
from .plant import Plant

__all__ = ["Removal", "sub_plant", "modal_plant", "prune_dofs", "prune_modes", "truncate",
           "Truncation", "frf", "ZERO_RTOL", "PART_RTOL", "DENSE_MAX"]

ZERO_RTOL = 1e-12
"""Coupling entries below this fraction of ``sqrt(|a_ii a_jj|)`` count as zero (round-off)."""

PART_RTOL = 1e-10
"""Modal participations below this fraction of their column's (row's) largest count as zero."""

DENSE_MAX = 1500
"""Largest number of DOFs for which every mode is computed densely (``eigh``)."""

N_CHECK = 24
"""Evenly spaced check frequencies over the band for the sampled error (plus 5 near its top)."""

CHECK_SAFETY = 0.5
"""Modes are added until the sampled error is below this fraction of the tolerance."""

SPARSE_MODES_MAX = 400
"""Most modes computed by the sparse eigensolver when searching for the tolerance."""

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
    """The plant restricted to the DOFs ``keep`` (indices), every map cut accordingly."""
    ix = np.ix_(keep, keep)
    return replace(p, dofs=tuple(p.dofs[i] for i in keep), M=p.M[ix], C=p.C[ix], K=p.K[ix], H=p.H[ix],
                   F=p.F[keep], Kz=p.Kz[keep], Cz=p.Cz[keep], Mz=p.Mz[keep], Hz=p.Hz[keep],
                   Oq=p.Oq[:, keep], Ov=p.Ov[:, keep], Oa=p.Oa[:, keep],
                   Oh=None if p.Oh is None else p.Oh[:, keep])


def modal_plant(p: Plant, phi: np.ndarray, omega2: np.ndarray, labels: tuple[str, ...],
                pf: np.ndarray | None = None, pz: np.ndarray | None = None) -> Plant:
    """Galerkin projection on M-orthonormal modes ``phi`` (n, k): ``M = I``, ``K = diag(omega2)``.

    ``pf`` and ``pz`` (p, m) are added to ``Pf`` and ``Pz`` (static correction).
    """
    t = phi.T
    return replace(p, dofs=labels, M=np.eye(phi.shape[1]), K=np.diag(omega2), C=t @ p.C @ phi,
                   H=t @ p.H @ phi, F=t @ p.F, Kz=t @ p.Kz, Cz=t @ p.Cz, Mz=t @ p.Mz, Hz=t @ p.Hz,
                   Oq=p.Oq @ phi, Ov=p.Ov @ phi, Oa=p.Oa @ phi,
                   Oh=None if p.Oh is None else p.Oh @ phi,
                   Pf=p.Pf if pf is None else p.Pf + pf, Pz=p.Pz if pz is None else p.Pz + pz)


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


def _eigh(p: Plant) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    w2, phi = sl.eigh(p.K, p.M, check_finite=False)
    top = max(float(np.abs(w2).max()), 1e-300)
    rigid = w2 <= 1e-10 * top
    return np.where(rigid, 0.0, w2), phi, rigid


def prune_modes(p: Plant) -> tuple[Plant, list[Removal], bool]:
    """Remove modes with zero input or output participation (exact); returns (plant, removals, modal?).

    The plant comes back in modal coordinates (DOFs ``mode<k>``) only when a mode was removed.
    """
    w2, phi, _ = _eigh(p)
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


# ------------------------------------------------------------------------------------ truncation

@dataclass(frozen=True, eq=False)
class Truncation:
    """Modal truncation outcome (see the module docstring)."""

    plant: Plant
    n_kept: int
    n_computed: int
    kept_hz: np.ndarray
    first_truncated_hz: float
    dropped_in_band: int
    estimate: float
    bound_kind: str
    classical: bool
    notes: tuple[str, ...]


class _Static:
    """Elastic static solves ``K_e^+ x`` (rigid modes deflated) and the K-norm."""

    def __init__(self, p: Plant, phi0: np.ndarray, sparse: bool, mats: dict):
        self.p, self.phi0 = p, phi0
        if sparse and phi0.shape[1] == 0:
            self.K = mats["K"]
            self.lu = spl.splu(sp.csc_matrix(self.K))
            self.solve = lambda b: self.lu.solve(np.asarray(b, float))
        else:
            self.K = p.K
            mp = p.M @ phi0
            cho = sl.cho_factor(p.K + mp @ mp.T)
            self.solve = lambda b: sl.cho_solve(cho, np.asarray(b, float))

    def flex(self, b: np.ndarray) -> np.ndarray:
        """``K_e^+ b`` for (n, c) b: the elastic static response."""
        if self.phi0.shape[1]:
            b = b - self.p.M @ (self.phi0 @ (self.phi0.T @ b))
        return self.solve(b)

    def knorm2(self, x: np.ndarray) -> np.ndarray:
        return np.einsum("ij,ij->j", x, self.K @ x)


def _lowest_modes(p: Plant, k: int, mats: dict) -> tuple[np.ndarray, np.ndarray]:
    if not mats or k >= p.n - 1:
        return sl.eigh(p.K, p.M, subset_by_index=[0, min(k, p.n) - 1], check_finite=False)
    Ks, Ms = mats["K"], mats["M"]
    d = Ks.diagonal() / Ms.diagonal()
    sigma = -1e-6 * float(np.median(d[d > 0])) if np.any(d > 0) else -1.0
    w2, phi = spl.eigsh(Ks, k=k, M=Ms, sigma=sigma, which="LM")
    o = np.argsort(w2)
    w2, phi = w2[o], phi[:, o]
    phi = phi / np.sqrt(np.einsum("ij,ij->j", phi, Ms @ phi))
    return w2, phi


def _gain_factors(w: np.ndarray, wr: np.ndarray, gr: np.ndarray, eta: float,
                  tail: bool, top: float | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(nf,) sup over truncated modes of the corrected (G00), uncorrected (G) and residual-vector
    (Gv = w^2 / |w_r^2 - w^2 + i w g_r|) factors."""
    wr_all, gr_all = wr, gr
    if tail:
        top = top if top is not None else (float(wr[-1]) if wr.size else 1.0)
        wt = top * np.logspace(0, 8, 161)
        wr_all, gr_all = np.concatenate([wr, wt]), np.concatenate([gr, eta * wt**2])
    W, Wr, Gr = w[:, None], wr_all[None, :], gr_all[None, :]
    den = np.abs(Wr**2 - W**2 + 1j * W * Gr)
    den = np.where(den > 0, den, np.inf)
    g00 = np.abs(W**2 - 1j * W * Gr) / den
    g = Wr**2 / den
    gv = W**2 / den
    return g00.max(axis=1), g.max(axis=1), gv.max(axis=1)


class _Modes:
    """The lowest ``nc`` modes of a plant, its projection on them and the static residuals."""

    def __init__(self, p: Plant, nc: int, mats: dict, static: "_Static | None", vecs: np.ndarray):
        self.p = p
        self.score = None
        ev, phi = _lowest_modes(p, nc, mats)
        scale = float(np.max(np.diag(p.K) / np.diag(p.M)))
        self.rigid = ev <= 1e-10 * max(scale, 1e-300)
        self.ev = np.where(self.rigid, 0.0, ev)
        self.phi = phi
        self.nc = phi.shape[1]
        self.static = static or _Static(p, phi[:, self.rigid], bool(mats), mats)
        self.x_full = self.static.flex(vecs)
        el = ~self.rigid
        self.inv = np.where(el, 1.0 / np.where(el, self.ev, 1.0), 0.0)
        self.c = phi.T @ vecs                                   # participations (nc, cols)
        resid = self.x_full - phi @ (self.c * self.inv[:, None])
        self.r_tail = np.maximum(self.static.knorm2(resid), 0.0)
        self.contrib = self.c**2 * self.inv[:, None]
        mul = (lambda a: mats[a] @ phi) if mats else (lambda a: getattr(p, a) @ phi)
        self.Cm = phi.T @ mul("C")
        self.Hm = phi.T @ mul("H") if np.any(p.H) else np.zeros((self.nc, self.nc))
        self.gam = np.diag(self.Cm).copy()
        self.proj = {k: phi.T @ getattr(p, k) for k in ("F", "Kz", "Cz", "Mz", "Hz")}
        self.proj.update({k: getattr(p, k) @ phi for k in ("Oq", "Ov", "Oa")})
        self.proj["Oh"] = None if p.Oh is None else p.Oh @ phi
        self.oq_x0 = p.Oq @ self.x_full[:, :p.F.shape[1]]
        off = np.abs(self.Cm - np.diag(self.gam))
        g = np.abs(self.gam)
        self.classical = bool(np.all(off <= 1e-8 * np.sqrt(np.outer(g, g)) + 1e-14 * (g.max() + 1e-300)))

    def rank(self, wgrid: np.ndarray, row: np.ndarray, m: int, q: int) -> int:
        """Reorder the modes by their importance to the scope; returns how many matter at all.

        Score of mode r: its largest contribution over the grid ``wgrid`` [rad/s] to any channel,
        beyond the static correction (``w^2 / (w_r^2 |w_r^2 - w^2 + i w g_r|)`` times the modal
        participations), relative to the output's peak ``row`` (q,). Rigid-body modes come first.
        Modes far from the inputs or outputs (localised elsewhere) then drop to the end.
        """
        W = wgrid[:, None]
        ev = np.maximum(self.ev, 1e-300)
        den = np.abs(ev[None, :] - W**2 + 1j * W * self.gam[None, :])
        f = W**2 / np.where(den > 0, den, 1e-300) / ev[None, :]                  # (nf, nc)
        ca = np.abs(self.c)
        b = sum(ca[:, i * m:(i + 1) * m] for i in range(3))                      # (nc, m)
        o = sum(ca[:, 3 * m + i * q:3 * m + (i + 1) * q] for i in range(3)) / np.maximum(row, 1e-300)
        wmax = float(wgrid.max())
        scale = max(1.0, wmax) ** 2
        score = f.max(axis=0) * o.max(axis=1) * b.max(axis=1) * scale
        score = np.where(self.rigid, np.inf, score)
        order = np.argsort(-score, kind="stable")
        self._permute(order)
        self.score = score[order]
        return int(np.sum(self.score > 0))

    def _permute(self, order: np.ndarray) -> None:
        for name in ("ev", "phi", "rigid", "inv", "c", "contrib", "gam"):
            a = getattr(self, name)
            setattr(self, name, a[:, order] if name == "phi" else a[order])
        self.Cm = self.Cm[np.ix_(order, order)]
        self.Hm = self.Hm[np.ix_(order, order)]
        for key in ("F", "Kz", "Cz", "Mz", "Hz"):
            self.proj[key] = self.proj[key][order]
        for key in ("Oq", "Ov", "Oa"):
            self.proj[key] = self.proj[key][:, order]
        if self.proj["Oh"] is not None:
            self.proj["Oh"] = self.proj["Oh"][:, order]

    def plant(self, k: int) -> Plant:
        """Kept modes 1..k plus the static correction of ``b0 = F - Kz`` on ``Oq``."""
        p, pr = self.p, self.proj
        m = p.F.shape[1]
        corr = self.oq_x0 - pr["Oq"][:, :k] @ (self.c[:k, :m] * self.inv[:k, None])
        force = np.array([kind == "force" for kind in p.kinds])
        cut = lambda a: None if a is None else a[:k]  # noqa: E731
        return replace(p, dofs=tuple(f"mode{i + 1}" for i in range(k)), M=np.eye(k),
                       K=np.diag(self.ev[:k]), C=self.Cm[:k, :k], H=self.Hm[:k, :k],
                       F=pr["F"][:k], Kz=pr["Kz"][:k], Cz=pr["Cz"][:k], Mz=pr["Mz"][:k], Hz=pr["Hz"][:k],
                       Oq=pr["Oq"][:, :k], Ov=pr["Ov"][:, :k], Oa=pr["Oa"][:, :k],
                       Oh=None if pr["Oh"] is None else pr["Oh"][:, :k],
                       Pf=p.Pf + np.where(force[None, :], corr, 0.0),
                       Pz=p.Pz + np.where(force[None, :], 0.0, corr))


def _estimate(md: _Modes, k: int, wgrid: np.ndarray, zf: np.ndarray, peak: np.ndarray, m: int, q: int,
              tail: bool, residual: str = "static") -> float:
    """Largest estimated relative error over channels and the grid with k modes kept.

    Computed truncated modes enter one by one (triangle inequality, exact per-mode factors); the
    modes above the computed ones through their residual flexibility (Cauchy-Schwarz) and the
    worst factor of an assumed tail (see the module docstring).
    """
    ev = md.ev
    W = wgrid[:, None]
    wr2, gr = ev[k:], md.gam[k:]
    den = np.abs(wr2[None, :] - W**2 + 1j * W * gr[None, :])
    den = np.where(den > 0, den, np.inf)
    inv = 1.0 / np.maximum(wr2, 1e-300)[None, :]
    f_static = np.abs(W**2 - 1j * W * gr[None, :]) / den * inv      # corrected (a = b = 0)
    f_plain = 1.0 / den                                              # not corrected
    f_vec = W**2 / den * inv                                         # residual vectors
    ca = np.abs(md.c[k:])                                            # (nr, cols)
    B = [ca[:, i * m:(i + 1) * m] for i in range(3)]
    O = [ca[:, 3 * m + i * q:3 * m + (i + 1) * q] for i in range(3)]
    sq = np.sqrt(md.r_tail)
    sb = [sq[i * m:(i + 1) * m] for i in range(3)]
    so = [sq[3 * m + i * q:3 * m + (i + 1) * q] for i in range(3)]
    if tail:
        top = float(np.sqrt(ev.max()))
        eta = float(np.max(gr / np.maximum(wr2, 1e-300))) if gr.size else 0.0
        g00, g, gv = _gain_factors(wgrid, np.zeros(0), np.zeros(0), eta, tail=True, top=top)
    est = np.zeros((wgrid.size, q, m))
    for a in range(3):
        for b in range(3):
            if residual == "vectors":
                f, gt = f_vec, (gv if tail else None)
            elif a == b == 0:
                f, gt = f_static, (g00 if tail else None)
            else:
                f, gt = f_plain * wr2[None, :], (g if tail else None)
                f = f * inv
            term = np.einsum("fr,ri,rj->fij", f, O[a], B[b])
            if tail:
                term = term + gt[:, None, None] * so[a][None, :, None] * sb[b][None, None, :]
            est += term * (wgrid ** (a + b))[:, None, None]
    est = (est * zf[:, None, :]).max(axis=0)
    row = peak.max(axis=1, keepdims=True)
    floor = np.where(row > 0, row, max(float(peak.max()), 1e-300))
    return float((est / floor).max())


def _ritz_plant(md: _Modes, k: int, mats: dict) -> Plant:
    """Kept modes 1..k plus the residual static vectors of every forcing term as extra DOFs.

    ``V = [Phi_k, Q]``, Q an M-orthonormal basis of ``R [F - Kz, Cz, Mz]`` (the truncated modes'
    static response), and the plant projected on V (Galerkin): the static response is exact and
    the truncated part keeps its damping, mass and kinematics (all output types corrected).
    """
    p = md.p
    m = p.F.shape[1]
    x = md.x_full[:, :3 * m]
    resid = x - md.phi[:, :k] @ (md.c[:k, :3 * m] * md.inv[:k, None])
    keep = np.linalg.norm(resid, axis=0) > 1e-10 * np.linalg.norm(x, axis=0)
    resid = resid[:, keep]
    if resid.shape[1] == 0 or k >= p.n:
        return replace(md.plant(k), Pf=p.Pf, Pz=p.Pz)
    mul = (lambda a, v: mats[a] @ v) if mats else (lambda a, v: getattr(p, a) @ v)
    # M-orthonormal basis of the residual vectors, orthogonal to the kept modes (twice, for round-off)
    for _ in range(2):
        resid = resid - md.phi[:, :k] @ (md.phi[:, :k].T @ mul("M", resid))
    g = resid.T @ mul("M", resid)
    lam, u = np.linalg.eigh(0.5 * (g + g.T))
    ok = lam > 1e-12 * lam.max()
    q = resid @ (u[:, ok] / np.sqrt(lam[ok]))
    kq = q.T @ mul("K", q)
    w2q, uq = np.linalg.eigh(0.5 * (kq + kq.T))        # diagonalise the residual block
    q = q @ uq
    v = np.hstack([md.phi[:, :k], q])
    nq = q.shape[1]
    pr = md.plant(k)
    kk = np.diag(np.r_[md.ev[:k], w2q])
    cq = v.T @ mul("C", v)
    hq = v.T @ mul("H", v) if np.any(p.H) else np.zeros((k + nq, k + nq))
    labels = pr.dofs + tuple(f"residual{i + 1}" for i in range(nq))
    return replace(p, dofs=labels, M=np.eye(k + nq), K=kk, C=0.5 * (cq + cq.T), H=0.5 * (hq + hq.T),
                   F=v.T @ p.F, Kz=v.T @ p.Kz, Cz=v.T @ p.Cz, Mz=v.T @ p.Mz, Hz=v.T @ p.Hz,
                   Oq=p.Oq @ v, Ov=p.Ov @ v, Oa=p.Oa @ v, Oh=None if p.Oh is None else p.Oh @ v)


def truncate(p: Plant, band: tuple[float, float], tol: float, grid: np.ndarray,
             max_modes: int | None = None, residual: str = "vectors") -> Truncation:
    """Modal truncation of ``p`` for the band ``(w1, w2)`` [rad/s] to relative accuracy ``tol``.

    ``grid`` (nf,) [rad/s] is where the estimate is evaluated (resonances in the band are added).
    ``residual``: ``"static"`` (feedthrough) or ``"vectors"`` (residual vectors as extra DOFs).
    """
    if residual not in ("static", "vectors"):
        raise ValueError(f"residual: expected 'static' or 'vectors', got {residual!r}")
    build = (lambda md, k: md.plant(k)) if residual == "static" else (lambda md, k: _ritz_plant(md, k, mats))
    n = p.n
    mats = {k: sp.csr_matrix(getattr(p, k)) for k in ("M", "C", "K", "H")} if n > DENSE_MAX else {}
    w2b = band[1]
    notes: list[str] = []
    m, q = p.F.shape[1], p.Oq.shape[0]
    vecs = np.hstack([p.F - p.Kz, -p.Cz, -p.Mz, p.Oq.T, p.Ov.T, p.Oa.T])
    nc = n if not mats else min(n - 2, 40)
    md = _Modes(p, nc, mats, None, vecs)
    while mats and md.ev[-1] <= 1.5 * w2b**2 and md.nc < n - 2:
        md = _Modes(p, min(n - 2, 2 * md.nc), mats, md.static, vecs)
    # exact response of the full plant at check frequencies: the band's top region and beside
    # the in-band resonances (sparse LU per frequency when large)
    w_lo = max(float(np.min(grid)), 1e-300)
    res = np.sqrt(md.ev[(md.ev > 0) & (md.ev <= w2b**2)])
    side = np.r_[res * (1 - 2e-4), res * (1 + 2e-4), res * (1 - 2e-3), res * (1 + 2e-3)]
    wc = np.unique(np.r_[np.linspace(w_lo, w2b, N_CHECK), np.linspace(0.9 * w2b, w2b, 5),
                         side[(side >= w_lo) & (side <= w2b)]])
    h_ref = frf(p, 1j * wc)
    row = np.abs(h_ref).max(axis=(1, 2))
    best, history = None, []
    while True:
        ev = md.ev
        res = np.sqrt(ev[(ev > 0) & (ev <= w2b**2)])
        md.rank(np.unique(np.r_[wc, res]), row, m, q)
        k_min = max(int(np.sum(md.rigid)), 1)
        best = None
        last = md.nc + (1 if md.nc == n else 0)
        steps = np.unique(np.r_[np.arange(8), np.round(8 * 1.25 ** np.arange(40))]).astype(int)
        for k in sorted({int(k_min + s) for s in steps if k_min + s < last} | {last - 1}):
            plant_k = build(md, k)
            err = np.abs(frf(plant_k, 1j * wc) - h_ref).max(axis=(1, 2))
            worst = float((err / np.where(row > 0, row, max(float(row.max()), 1e-300))).max())
            if best is None or worst < best[1]:
                best = (k, worst, plant_k)
            if worst <= CHECK_SAFETY * tol or (max_modes is not None and k >= max_modes) or k == n:
                best = (k, worst, plant_k)
                break
        history.append(best[1] if best else np.inf)
        done = best is not None and (best[1] <= CHECK_SAFETY * tol or best[0] == n
                                     or (max_modes is not None and best[0] >= max_modes))
        stalled = len(history) >= 2 and history[-1] > 0.9 * history[-2]
        if done or stalled or not mats or md.nc >= min(n - 2, SPARSE_MODES_MAX):
            break
        md = _Modes(p, min(n - 2, SPARSE_MODES_MAX, 2 * md.nc), mats, md.static, vecs)
    if best is None:   # every mode lies in or below the band
        best = (md.nc, 0.0, build(md, md.nc))
        notes.append("every mode lies in or below the band: nothing truncated")
    k, worst, plant_k = best
    if worst > tol:
        notes.append(f"the requested tolerance {tol:g} was not reached (estimate {worst:.3g} with "
                     f"{k} modes): damping, velocity or acceleration terms limit the static correction")
    kind = (f"sampled: exact error at {wc.size} check frequencies over the band (evenly spaced, its "
            f"top, beside each resonance in it), relative per output; modes added in order of their "
            f"contribution to the scope until below {CHECK_SAFETY:g} x tolerance")
    if k < n:
        ev = md.ev
        inband = np.sqrt(ev[(ev > band[0]**2) & (ev <= w2b**2)])
        side = np.concatenate([inband * (1 - 2e-4), inband * (1 + 2e-4)])
        wg = np.unique(np.r_[np.asarray(grid, float), side[(side > 0) & (side <= w2b)]])
        with np.errstate(divide="ignore"):
            zf = np.abs(np.where(p.order[None, :] > 0, wg[:, None] ** (-np.maximum(p.order, 0))[None, :], 1.0))
        peak = np.abs(frf(plant_k, 1j * wg)).max(axis=2)
        bound = _estimate(md, k, wg, zf, peak, m, q, md.nc < n, residual)
        what = ("bound (classical damping, all modes known)" if md.classical and md.nc >= n
                else "estimate")
        notes.append(f"a-priori {what} from modal participations (triangle inequality over the "
                     f"truncated modes; conservative for transfer between distant points): {bound:.3g}")
    if np.any(p.H):
        notes.append("hysteretic damping is projected on the kept modes; the estimate does not include it")
    fr = np.sqrt(md.ev) / (2 * np.pi)
    return Truncation(plant=plant_k, n_kept=k, n_computed=md.nc, kept_hz=np.sort(fr[:k]),
                      first_truncated_hz=float(fr[k:].min()) if k < fr.size else float("inf"),
                      dropped_in_band=int(np.sum(md.ev[k:] <= w2b**2)),
                      estimate=worst, bound_kind=kind, classical=md.classical, notes=tuple(notes))


# ------------------------------------------------------------------------------- evaluation

def frf(p: Plant, s: np.ndarray) -> np.ndarray:
    """Exact response ``Y(s)`` (p, m, nf) of a plant at Laplace points ``s`` (sparse LU when large).

    ``(K + iH + sC + s^2 M) X = F - (Kz + iHz + s Cz + s^2 Mz) Z``, ``Y = O(s) X + P(s) Z + Pf``,
    ``Z = diag(s^-order)``.
    """
    s = np.atleast_1d(np.asarray(s, complex))
    order = p.order
    with np.errstate(divide="ignore", invalid="ignore"):
        zf = np.where(order[None, :] > 0, s[:, None] ** (-np.maximum(order, 0))[None, :], 1.0)
    oh = 0.0 if p.Oh is None else p.Oh
    ph = 0.0 if p.Ph is None else p.Ph
    out = np.empty((s.size, p.Oq.shape[0], p.F.shape[1]), complex)
    large = p.n > DENSE_MAX
    if large:
        mats = [sp.csc_matrix(a) for a in (p.K, p.H, p.C, p.M)]
    for i, si in enumerate(s):
        rhs = p.F - (p.Kz + 1j * p.Hz + si * p.Cz + si**2 * p.Mz) * zf[i][None, :]
        if large:
            a = (mats[0] + 1j * mats[1] + si * mats[2] + si**2 * mats[3]).tocsc()
            x = spl.splu(a).solve(np.asarray(rhs, complex))
        else:
            x = np.linalg.solve(p.K + 1j * p.H + si * p.C + si**2 * p.M, rhs)
        obs = p.Oq + 1j * oh + si * p.Ov + si**2 * p.Oa
        pz = p.Pz + 1j * ph + si * p.Pv + si**2 * p.Pa
        out[i] = obs @ x + pz * zf[i][None, :] + p.Pf
    return np.moveaxis(out, 0, -1)


def check_reducible(p: Plant) -> None:
    """Raise AnalysisError when the plant cannot be truncated (no DOF left)."""
    if p.n == 0:
        raise AnalysisError("the plant has no free DOF left to reduce")
