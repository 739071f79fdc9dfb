"""Modal truncation of a :class:`~vibss.linear.plant.plant.Plant` for :mod:`vibss.reduction`.

Kept modes and the residual correction
--------------------------------------
Modes (mass-normalised, ``eigh`` or shift-invert ``eigsh``) are kept; the truncated ones are
accounted for through their static response, the residual flexibility
``R = K_e^+ - Phi_k Omega_k^-2 Phi_k^T`` (elastic part; rigid-body modes are always kept), in one of
two ways:

``residual="vectors"``
    ``R [F - Kz, Cz, Mz]`` (M-orthonormalised, orthogonal to the kept modes) is appended to the
    basis as DOFs ``residual<k>`` and the plant is projected on it (Galerkin): the static response
    is exact and the truncated part keeps its damping, mass and kinematics, so every output type
    is corrected.
``residual="static"``
    ``Pf += Oq R F`` (force inputs), ``Pz -= Oq R Kz`` (motion inputs, per prescribed coordinate):
    only the displacement-proportional output terms (``Oq``: displacements, deflections, the spring
    part of mount and ground forces) under the stiffness forcing (``F``, ``Kz``) are corrected;
    ``Ov``, ``Oa``, ``Cz``, ``Mz`` terms are not.

Choice of modes
---------------
The modes are ranked by their largest contribution to the scope beyond the residual correction
(modes localised away from the inputs and outputs fall to the end, even inside the band) and added
until the exact error at check frequencies (evenly spaced over the band, its top, beside each
in-band resonance) is below ``CHECK_SAFETY`` times the tolerance. Large sparse plants get their
lowest modes from shift-invert ``eigsh`` (doubling up to ``SPARSE_MODES_MAX``) and their exact
check responses from a sparse LU per frequency.

A-priori figure (reported in the notes)
---------------------------------------
Per channel, the truncated modes computed enter one by one (triangle inequality) with the factor
``|w^2 - i w g_r| / (w_r^2 |w_r^2 - w^2 + i w g_r|)`` (static correction) or
``w^2 / (w_r^2 |...|)`` (residual vectors, an estimate) times their participations; modes beyond the
computed ones through ``sqrt(r(o)) sqrt(r(b))`` with ``r(v) = (R v)^T K (R v)`` (Cauchy-Schwarz) and
an assumed tail damped like the highest computed modes. A bound for classical damping with static
correction when all modes are computed; conservative by orders of magnitude for transfer between
distant points, hence not used to choose the modes.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
import scipy.linalg as sl
import scipy.sparse as sp
import scipy.sparse.linalg as spl

from .._validate import choice
from ..linear.eigen.undamped import undamped
from ..linear.eigen.small import symmetric_eigen
from ..linear.plant.plant import Plant
from .prune import DENSE_MAX, frf
from .scope import Scope, peak_checks

__all__ = ["truncate", "Truncation", "N_CHECK", "CHECK_SAFETY", "SPARSE_MODES_MAX"]

N_CHECK = 24
"""Evenly spaced check frequencies over the band for the sampled error (plus 5 near its top)."""
CHECK_SAFETY = 0.5
"""Modes are added until the sampled error is below this fraction of the tolerance."""
SPARSE_MODES_MAX = 400
"""Most modes computed by the sparse eigensolver when searching for the tolerance."""



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


def _lowest_modes(p: Plant, k: int, mats: dict) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The lowest ``k`` modes: ``w2`` [rad^2/s^2], shapes, and the eigen path's rigid flags (its
    test on the stiffness factor: a 5 mHz mode of a body 1e6 times lighter than its neighbour is
    elastic, though 1e-10 of the largest ``K_ii / M_ii``)."""
    if not mats or k >= p.n - 1:
        spec = undamped(p.K, p.M, p.Kf, n_modes=min(k, p.n))
    else:
        spec = undamped(mats["K"], mats["M"], p.Kf, n_modes=k, method="shift-invert")
    return spec.omega2, spec.phi, np.asarray(spec.rigid, bool)


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
        self.score: np.ndarray | None = None
        ev, phi, self.rigid = _lowest_modes(p, nc, mats)
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
        cm = phi.T @ mul("C")
        hm = phi.T @ mul("H") if np.any(p.H) else np.zeros((self.nc, self.nc))
        self.gam = np.diag(cm).copy()
        # half-power bandwidth [rad/s] of each mode: viscous plus hysteretic (h / w)
        self.width = np.abs(self.gam) + np.abs(np.diag(hm)) / np.sqrt(np.maximum(self.ev, 1e-300))
        # the plant on all nc modes; plant(k) restricts it to the first k (after _permute's order)
        self.modal = p.project(phi, tuple(f"mode{i + 1}" for i in range(self.nc)), M=np.eye(self.nc),
                               K=np.diag(self.ev), C=cm, H=hm)
        self.oq_x0 = p.Oq @ self.x_full[:, :p.F.shape[1]]
        off = np.abs(cm - np.diag(self.gam))
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
        # rigid modes (mechanism modes of zero-stiffness links included) rank first anyway: their
        # ev = 0 is not divided by (as 1e-300 the product below overflowed, and warned)
        ev = np.where(self.rigid, 1.0, np.maximum(self.ev, 1e-300))
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
        for name in ("ev", "phi", "rigid", "inv", "c", "contrib", "gam", "width"):
            a = getattr(self, name)
            setattr(self, name, a[:, order] if name == "phi" else a[order])
        self.modal = self.modal.restrict(order)

    def plant(self, k: int) -> Plant:
        """Kept modes 1..k plus the static correction of ``b0 = F - Kz`` on ``Oq``."""
        p = self.p
        m = p.F.shape[1]
        corr = self.oq_x0 - self.modal.Oq[:, :k] @ (self.c[:k, :m] * self.inv[:k, None])
        force = np.array([kind == "force" for kind in p.kinds])
        return replace(self.modal.restrict(np.arange(k)), dofs=tuple(f"mode{i + 1}" for i in range(k)),
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
                assert gt is not None  # set with the tail
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
    lam, u = symmetric_eigen(g)
    ok = lam > 1e-12 * lam.max()
    q = resid @ (u[:, ok] / np.sqrt(lam[ok]))
    kq = q.T @ mul("K", q)
    w2q, uq = symmetric_eigen(kq)        # diagonalise the residual block
    q = q @ uq
    v = np.hstack([md.phi[:, :k], q])
    nq = q.shape[1]
    cq = v.T @ mul("C", v)
    hq = v.T @ mul("H", v) if np.any(p.H) else np.zeros((k + nq, k + nq))
    labels = tuple(f"mode{i + 1}" for i in range(k)) + tuple(f"residual{i + 1}" for i in range(nq))
    return p.project(v, labels, M=np.eye(k + nq), K=np.diag(np.r_[md.ev[:k], w2q]), C=0.5 * (cq + cq.T),
                     H=0.5 * (hq + hq.T))


def _first_passing(ks: list[int], build: object, md: _Modes, wc: np.ndarray, h_ref: np.ndarray,
                   row: np.ndarray, goal: float) -> tuple[int, float, Plant]:
    """The first candidate of ``ks`` (kept modes, ascending) whose error at the checks ``wc`` meets
    ``goal``, else the last one; found by galloping (candidates 1, 2, 4, 8 ... of the list) and then
    bisection between the last miss and the first pass, since more modes make a smaller error. A
    chain with mechanism modes (zero-stiffness links) needs nearly every mode: each of its 23
    candidates solved at 304 checks took 8 s at 300 DOF one after the other, minutes at 500 DOF."""
    seen: dict[int, tuple[int, float, Plant]] = {}

    def at(i: int) -> tuple[int, float, Plant]:
        if i not in seen:
            plant_k = build(md, ks[i])                    # type: ignore[operator]
            err = np.abs(frf(plant_k, 1j * wc) - h_ref).max(axis=(1, 2))
            seen[i] = (ks[i], float((err / np.where(row > 0, row, max(float(row.max()), 1e-300))).max()), plant_k)
        return seen[i]

    last = len(ks) - 1
    lo, hi, step = -1, 0, 1
    while at(hi)[1] > goal:                               # gallop
        if hi == last:
            return at(hi)
        lo, hi, step = hi, min(last, hi + step), 2 * step
    while hi - lo > 1:                                    # bisect: the first pass in (lo, hi]
        mid = (lo + hi) // 2
        lo, hi = (lo, mid) if at(mid)[1] <= goal else (mid, hi)
    return at(hi)


def truncate(p: Plant, scope: Scope, n_grid: int = 200, max_modes: int | None = None,
             residual: str = "vectors") -> Truncation:
    """Modal truncation of ``p`` for the scope's band to its relative accuracy.

    The a-priori estimate is evaluated on ``n_grid`` frequencies from :meth:`Scope.low_end` to the
    band's top (resonances in the band added); the sampled error on the check frequencies.
    ``residual``: ``"static"`` (feedthrough) or ``"vectors"`` (residual vectors as extra DOFs).
    """
    band, tol = scope.band_rad, scope.tolerance
    choice(residual, "residual", ("static", "vectors"))
    mats: dict[str, sp.csr_matrix]
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
    w_lo = scope.low_end(np.sqrt(np.maximum(md.ev, 0.0)))
    grid = np.linspace(w_lo, w2b, int(n_grid))
    inb = (md.ev > 0) & (md.ev <= w2b**2)
    res = np.sqrt(md.ev[inb])
    side = np.r_[res * (1 - 2e-4), res * (1 + 2e-4), res * (1 - 2e-3), res * (1 + 2e-3)]
    wc = np.unique(np.r_[np.linspace(w_lo, w2b, N_CHECK), np.linspace(0.9 * w2b, w2b, 5),
                         side[(side >= w_lo) & (side <= w2b)], peak_checks(res, md.width[inb], w_lo, w2b)])
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
        ks = sorted({int(k_min + s) for s in steps if k_min + s < last} | {last - 1})
        if max_modes is not None:                       # nothing past the first candidate >= max_modes
            ks = ks[:next((i + 1 for i, k in enumerate(ks) if k >= max_modes), len(ks))]
        best = _first_passing(ks, build, md, wc, h_ref, row, CHECK_SAFETY * tol) if ks else None
        history.append(best[1] if best else np.inf)
        done = best is not None and (best[1] <= CHECK_SAFETY * tol or best[0] == n
                                     or (max_modes is not None and best[0] >= max_modes))
        if done or not mats or md.nc >= min(n - 2, SPARSE_MODES_MAX):
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
