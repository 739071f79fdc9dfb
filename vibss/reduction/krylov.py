"""Input-driven rational Krylov (moment-matching) reduction for :mod:`vibss.reduction`.

The full system stays sparse: ``M, C, K, H`` as CSR matrices over the free DOFs (a
:class:`~vibss.linear.plant.plant.Plant` whose four matrices are ``scipy.sparse``, see :func:`sparse_plant`), the
input and output maps dense but thin (n x m, p x n). Nothing n x n is ever dense.

Basis
-----
A second-order (structure-preserving) Galerkin projection ``q = V eta`` with ``V`` M-orthonormal:

- **real shifts** ``sigma_j = w_j^2`` spread over the band ``[w1, w2]`` (``w_j`` evenly spaced; a
  band starting at 0 gets ``sigma = 0``, the static response, or a slightly negative shift when
  ``K`` is singular), each factorised once (banded ``dgbtrf`` or ``splu`` of ``K - sigma_j M``, :mod:`vibss.linear.project.krylov`);
- per shift a block Arnoldi sequence ``V_0 = (K - sigma M)^-1 B``, ``V_{k+1} = (K - sigma M)^-1 M V_k``
  for ``moments`` blocks, where ``B`` holds every forcing column (``F``, ``Kz``, ``Cz``, ``Mz``,
  ``Hz``) and, when the outputs are few (``<= TWO_SIDED_MAX`` rows), the output rows transposed
  (``Oq``, ``Ov``, ``Oa``, ``Oh``): both spans in one V keep the projection symmetric (Galerkin);
- each new block is M-orthogonalised against the basis and within itself (block Gram-Schmidt,
  twice), columns whose M-norm falls below ``DEFLATE_RTOL`` of their original one are deflated.

Error control (greedy)
----------------------
At check frequencies (the midpoints between neighbouring interpolation frequencies, i.e. where an
interpolation error is largest) the full response is computed exactly with one complex sparse LU
of ``K + iH + iwC - w^2 M`` per frequency, and compared with the reduced one: the relative error per
output (divided by the output's largest response over the band, see
:func:`vibss.reduction.result.relative_error`). Where it exceeds ``CHECK_SAFETY`` times the tolerance the
exact solutions at that frequency (state and, two-sided, adjoint; real and imaginary parts) join the
basis -- they cost nothing more, the factorisation is there -- which makes the reduced response
exact at that frequency, and the new midpoints are checked in the next round. It stops when every
fresh check is below ``CHECK_SAFETY x tol``; the estimate is the largest error of the final basis at
every check the basis was **not** built at (the last round's, and the earlier rounds' that passed:
the last round's sit only beside the frequencies just added).
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
import scipy.sparse as sp

from ..errors import AnalysisError
from ..model.model import Model
from ..linear.plant.plant import FIELD_ROLES, Plant
from ..linear.plant.build import build_plant
from ..linear.project.krylov import DEFLATE_RTOL, Basis as _Basis, exact_response, forcing_columns as _forcing, \
    observing_columns as _observing, project, shift_solver as _shift_lu
from .scope import LOW_END, low_end, peak_checks
from .prune import Removal, _components, _dof_names, _touched_rows, frf

__all__ = ["KrylovBasis", "krylov", "sparse_plant", "as_sparse", "prune_sparse", "exact_response",
           "N_SHIFTS", "MOMENTS", "CHECK_SAFETY", "MAX_ROUNDS", "TWO_SIDED_MAX", "DEFLATE_RTOL"]

N_SHIFTS = 3
"""Real shifts spread over the band at the start."""
MOMENTS = 2
"""Block Arnoldi moments per real shift at the start."""
CHECK_SAFETY = 0.5
"""The basis grows until the sampled error is below this fraction of the tolerance."""
MAX_ROUNDS = 8
"""Most enrichment rounds."""
TWO_SIDED_MAX = 12
"""Largest number of output rows (Oq, Ov, Oa, Oh together) whose adjoint blocks join the basis."""


@dataclass(frozen=True, eq=False)
class KrylovBasis:
    """Outcome of :func:`krylov`.

    Attributes
    ----------
    plant : Plant
        The reduced plant (DOFs ``krylov<k>``, ``M = I``, ``K = diag(w_k^2)``: Ritz coordinates).
    ritz_hz : (r,) ndarray
        Undamped natural frequencies of the reduced plant [Hz].
    shifts_hz : (ns,) ndarray
        Real shifts [Hz] (``sigma = (2 pi f)^2``; a negative entry stands for ``sigma < 0``).
    moments : int
        Block moments per real shift.
    interpolation_hz : (ni,) ndarray
        Frequencies [Hz] whose exact (complex) solutions joined the basis.
    check_hz : (nc,) ndarray
        Every check frequency [Hz] (exact sparse LU solves).
    estimate : float
        Largest relative error of the final basis at the checks it was not built at [-].
    history : tuple of (basis size, checks, largest error)
        Per round.
    timings : dict of str to float
        Wall time [s] of the factorisations, basis, projection and checks.
    two_sided : bool
        Whether the output (adjoint) blocks are in the basis.
    notes : tuple of str
        Caveats.
    """

    plant: Plant
    ritz_hz: np.ndarray
    shifts_hz: np.ndarray
    moments: int
    interpolation_hz: np.ndarray
    check_hz: np.ndarray
    estimate: float
    history: tuple[tuple[int, int, float], ...]
    timings: dict[str, float]
    two_sided: bool
    notes: tuple[str, ...]


# ------------------------------------------------------------------------ the full system, sparse

def sparse_plant(model: Model, inputs: Sequence[Any], outputs: Sequence[str]) -> Plant:
    """The scope's plant with ``M, C, K, H`` as scipy.sparse CSR matrices (no dense n x n).

    :func:`vibss.linear.plant.build.build_plant` with ``sparse=True``.

    Parameters
    ----------
    model : Model
        The system.
    inputs : sequence of str or Excitation
        Input signals.
    outputs : sequence of str
        Output signals.

    Returns
    -------
    Plant
        With sparse ``M, C, K, H`` (n x n) and dense maps.
    """
    return build_plant(model, inputs, outputs, sparse=True)


def as_sparse(p: Plant) -> Plant:
    """The plant with ``M, C, K, H`` as CSR matrices (a no-op when they already are)."""
    square = [k for k, role in FIELD_ROLES.items() if role == "dof x dof"]
    if all(sp.isspmatrix_csr(getattr(p, k)) for k in square if getattr(p, k) is not None):
        return p                # the very arrays: the plant's mounts' form (MountForm.matches) still holds
    return replace(p, **{k: sp.csr_matrix(getattr(p, k)) for k in square})


def prune_sparse(p: Plant) -> tuple[Plant, list[Removal]]:
    """Remove the connected components (graph of M, C, K, H) no input excites or no output sees.

    The sparse counterpart of :func:`vibss.reduction.prune.prune_dofs` (exact, zero initial
    conditions); entries count as couplings when nonzero.
    """
    pattern = abs(p.M) + abs(p.C) + abs(p.K) + abs(p.H)
    excited = _touched_rows([p.F, p.Kz, p.Cz, p.Mz, p.Hz], p.n)
    seen = _touched_rows([o.T for o in (p.Oq, p.Ov, p.Oa, p.Oh) if o is not None], p.n)
    keep, dropped = _components(sp.csr_matrix(pattern), excited, seen)
    if not dropped or not keep.any():
        return p, []
    removals: dict[str, list[str]] = {}
    for idx, why in dropped:
        removals.setdefault(why, []).extend(p.dofs[i] for i in idx)
    out = [Removal("dofs", tuple(_dof_names(names)), f"decoupled (coupling graph of M, C, K, H): {why}")
           for why, names in removals.items()]
    k = np.flatnonzero(keep)
    return p.restrict(k), out


def _midpoints(points: np.ndarray, lo: float, hi: float) -> np.ndarray:
    pts = np.unique(np.clip(points, lo, hi))
    mids = 0.5 * (pts[1:] + pts[:-1])
    if pts[0] > lo:
        mids = np.r_[lo, mids]
    if pts[-1] < hi:
        mids = np.r_[mids, hi]
    return mids


def _resonance_checks(red: Plant, row: np.ndarray, lo: float, hi: float, tol: float,
                      checked: np.ndarray) -> np.ndarray:
    """Checks [rad/s] on the peaks and flanks of the in-band Ritz resonances of significant modes
    (:func:`~vibss.reduction.scope.peak_checks`) not checked yet: a pole slightly off shows as a
    large error there, between the other checks. ``checked`` holds the checks so far that are
    not interpolation frequencies (where the error is zero by construction, whatever the pole).

    Significant: peak modal contribution ``|O t_k| |t_k^T B| / (w_k g_k)`` (``g_k = c_kk`` or
    ``h_kk / w_k``) above ``CHECK_SAFETY tol`` of the output's reference.
    """
    w2k = np.diag(red.K)
    wk = np.sqrt(np.maximum(w2k, 0.0))
    inb = (wk >= lo) & (wk <= hi)
    if not inb.any():
        return np.zeros(0)
    g = np.abs(np.diag(red.C)) + np.abs(np.diag(red.H)) / np.maximum(wk, 1e-300)
    b = np.abs(np.hstack([red.F, red.Kz, red.Cz, red.Mz, red.Hz])).max(axis=1)
    o = np.abs(np.stack([red.Oq, red.Ov * wk[None, :], red.Oa * wk[None, :]**2])).max(axis=0)
    contrib = (o * b[None, :] / np.maximum(wk * np.maximum(g, 1e-6 * wk), 1e-300)[None, :]) / row[:, None]
    sig = inb & (contrib.max(axis=0) > CHECK_SAFETY * tol)
    pts = peak_checks(wk[sig], g[sig], lo, hi)
    if checked.size == 0 or pts.size == 0:
        return pts
    half = np.min(np.maximum(0.5 * g[sig], 1e-6 * wk[sig]))
    near = np.min(np.abs(pts[:, None] - checked[None, :]), axis=1) <= 1e-3 * half
    return pts[~near]


UNDAMPED_OFFSET = 5e-8
"""Relative offset [-] of a check placed at an undamped Ritz resonance (a tenth of the 1e-6
half-power width assumed for undamped modes): exactly on it the reduced response is singular."""


def _off_undamped(red: Plant, wk: np.ndarray) -> np.ndarray:
    """``wk`` [rad/s], each undamped mode's (no C or H on its diagonal) moved up by
    ``UNDAMPED_OFFSET``, so no response is evaluated exactly on an undamped pole."""
    g = np.abs(np.diag(red.C)) + np.abs(np.diag(red.H))
    return np.where(g > 0, wk, wk * (1.0 + UNDAMPED_OFFSET))


def krylov(p: Plant, band: tuple[float, float], tol: float, n_shifts: int = N_SHIFTS,
           moments: int = MOMENTS, two_sided: bool | None = None, max_rounds: int = MAX_ROUNDS) -> KrylovBasis:
    """Rational block Krylov reduction of a sparse plant for the band ``(w1, w2)`` [rad/s].

    Parameters
    ----------
    p : Plant
        With sparse ``M, C, K, H`` (:func:`sparse_plant`, :func:`as_sparse`).
    band : (float, float)
        ``(w1, w2)`` [rad/s].
    tol : float
        Relative tolerance [-] (see the module docstring).
    n_shifts : int
        Real shifts at the start (>= 1).
    moments : int
        Block moments per real shift (>= 1).
    two_sided : bool or None
        Put the output (adjoint) blocks in the basis; default: when there are at most
        ``TWO_SIDED_MAX`` output rows.
    max_rounds : int
        Most enrichment rounds.

    Returns
    -------
    KrylovBasis

    Raises
    ------
    AnalysisError
        The inputs force nothing, a shift stays singular, or a factorisation, solve or small
        eigen-problem fails numerically (never a bare ``LinAlgError``).
    """
    try:
        return _krylov(p, band, tol, n_shifts, moments, two_sided, max_rounds)
    except (np.linalg.LinAlgError, FloatingPointError) as exc:
        raise AnalysisError(f"krylov: a linear-algebra step failed ({type(exc).__name__}: {exc}) while "
                            f"building the basis for the band {band[0] / (2 * np.pi):.4g} to "
                            f"{band[1] / (2 * np.pi):.4g} Hz; try method 'modal' or a wider tolerance") from exc


def _krylov(p: Plant, band: tuple[float, float], tol: float, n_shifts: int, moments: int,
            two_sided: bool | None, max_rounds: int) -> KrylovBasis:
    """:func:`krylov` itself (the wrapper turns numerical failures into an AnalysisError)."""
    t_start = time.perf_counter()
    timings = {"shift_lu_s": 0.0, "basis_s": 0.0, "project_s": 0.0, "check_s": 0.0}
    w1, w2 = float(band[0]), float(band[1])
    b = _forcing(p)
    if b.shape[1] == 0:
        raise AnalysisError("krylov: the inputs force no free DOF")
    o = _observing(p)
    if two_sided is None:
        two_sided = o.shape[1] <= TWO_SIDED_MAX
    block0 = np.hstack([b, o]) if two_sided else b
    ws = np.linspace(w1, w2, max(int(n_shifts), 1)) if n_shifts > 1 else np.array([0.5 * (w1 + w2)])
    basis, sigmas = _shifted_basis(p, ws, w2, block0, moments, timings)
    # check frequencies avoid 0 (a motion input of order > 0 diverges there)
    lo = w1 if w1 > 0 else w2 * LOW_END
    interp = np.clip(ws, lo, w2)
    checks = _midpoints(interp, lo, w2)
    seen = _Checks()
    added: list[float] = []
    notes: list[str] = []
    for rnd in range(max_rounds + 1):
        red, sols, err, row = _checked_round(p, basis, checks, bool(two_sided), seen, lo, w2, timings)
        estimate = float(err.max())
        seen.history.append((basis.V.shape[1], int(checks.size), estimate))
        done = np.array(seen.every)
        res = _resonance_checks(red, row, lo, w2, tol, done[~np.isin(done, np.asarray(added))])
        if (estimate <= CHECK_SAFETY * tol and res.size == 0) or rnd == max_rounds:
            break
        bad = _enriched(basis, sols, checks, err > CHECK_SAFETY * tol, added, timings)
        interp = np.r_[interp, checks[bad]]
        checks = _next_checks(np.unique(interp), checks[bad], res)
    estimate = max(estimate, _earlier_checks(red, seen, added, row, lo, w2))
    if estimate > tol:
        notes.append(f"the requested tolerance {tol:g} was not reached in {max_rounds} rounds "
                     f"(sampled error {estimate:.3g} with {basis.V.shape[1]} vectors)")
    timings["total_s"] = time.perf_counter() - t_start
    two_pi = 2 * np.pi
    return KrylovBasis(plant=red, ritz_hz=np.sqrt(np.maximum(np.diag(red.K), 0.0)) / two_pi,
                       shifts_hz=np.sign(sigmas) * np.sqrt(np.abs(sigmas)) / two_pi, moments=int(moments),
                       interpolation_hz=np.array(added) / two_pi, check_hz=np.array(seen.every) / two_pi,
                       estimate=estimate, history=tuple(seen.history), timings=timings,
                       two_sided=bool(two_sided), notes=tuple(notes))


def _shifted_basis(p: Plant, ws: np.ndarray, w2: float, block0: np.ndarray, moments: int,
                   timings: dict[str, float]) -> tuple[_Basis, list[float]]:
    """The M-orthonormal basis of ``moments`` moments of ``block0`` about each shift near ``ws``
    [rad/s], and the shifts ``sigma`` [rad^2/s^2] taken."""
    basis = _Basis(p.M)
    sigmas = []
    for w in ws:
        t0 = time.perf_counter()
        lu, sigma = _shift_lu(p, float(w), w2, banded=False)   # SuperLU, as its tolerances were set with
        t1 = time.perf_counter()
        timings["shift_lu_s"] += t1 - t0
        sigmas.append(sigma)
        blk = basis.add(lu(np.asarray(block0, float)))
        for _ in range(max(int(moments), 1) - 1):
            if blk.shape[1] == 0:
                break
            blk = basis.add(lu(np.asarray(p.M @ blk)))
        timings["basis_s"] += time.perf_counter() - t1
    return basis, sigmas


@dataclass
class _Checks:
    """The exact responses at the check frequencies of every round so far, and each round's
    (vectors, checks, sampled error)."""

    h: list[np.ndarray] = field(default_factory=list)
    w: list[np.ndarray] = field(default_factory=list)
    every: list[float] = field(default_factory=list)
    history: list[tuple[int, int, float]] = field(default_factory=list)


def _checked_round(p: Plant, basis: _Basis, checks: np.ndarray, two_sided: bool, seen: _Checks, lo: float,
                   w2: float, timings: dict[str, float]) -> tuple[Plant, list[Any], np.ndarray, np.ndarray]:
    """One round: the plant projected on the basis, the exact solutions at ``checks`` [rad/s], the
    error per check relative to each output's largest response, and that reference per output."""
    t0 = time.perf_counter()
    red = project(p, basis.V)
    t1 = time.perf_counter()
    timings["project_s"] += t1 - t0
    sols = [exact_response(p, 1j * w, adjoint=two_sided) for w in checks]
    hf = np.stack([y for y, _, _ in sols], axis=-1)
    hr = frf(red, 1j * checks)
    seen.h.append(hf)
    seen.w.append(checks)
    # reference per output: its largest response over the band (full at the checks so far,
    # reduced at its own in-band resonances)
    ritz = np.sqrt(np.maximum(np.diag(red.K), 0.0))
    start = _start(red, lo, w2)
    wr = _off_undamped(red, ritz)
    wr = wr[(wr >= start) & (wr <= w2)]
    peak = np.max([np.abs(h[..., w >= start]).max(axis=(1, 2), initial=0.0) for h, w in zip(seen.h, seen.w)],
                  axis=0)
    if wr.size:
        peak = np.maximum(peak, np.abs(frf(red, 1j * wr)).max(axis=(1, 2)))
    row = np.where(peak > 0, peak, max(float(peak.max()), 1e-300))
    err = np.where(checks >= start, (np.abs(hr - hf) / row[:, None, None]).max(axis=(0, 1)), 0.0)   # per check
    timings["check_s"] += time.perf_counter() - t1
    seen.every.extend(checks.tolist())
    return red, sols, err, row


def _enriched(basis: _Basis, sols: list[Any], checks: np.ndarray, bad: np.ndarray, added: list[float],
              timings: dict[str, float]) -> np.ndarray:
    """The exact solutions at the checks that missed (``bad``) added to the basis (real and
    imaginary parts, with the adjoint's); their frequencies appended to ``added``."""
    t2 = time.perf_counter()
    for (y, x, xa), w, flag in zip(sols, checks, bad):
        if flag:
            cols = [x] + ([xa] if xa is not None else [])
            z = np.hstack(cols)
            basis.add(np.hstack([z.real, z.imag]))
            added.append(float(w))
    timings["basis_s"] += time.perf_counter() - t2
    return bad


def _next_checks(pts: np.ndarray, just_added: np.ndarray, res: np.ndarray) -> np.ndarray:
    """New checks: midpoints of the intervals of ``pts`` that end at a frequency just added, and the
    resonances ``res`` still to check."""
    new = []
    for w in just_added:
        i = int(np.searchsorted(pts, w))
        if i > 0:
            new.append(0.5 * (pts[i - 1] + pts[i]))
        if i + 1 < pts.size:
            new.append(0.5 * (pts[i] + pts[i + 1]))
    return np.unique(np.r_[new, res]) if new else res


def _start(red: Plant, lo: float, w2: float) -> float:
    """Where the scope's measure starts [rad/s] (:func:`~vibss.reduction.scope.low_end`, with the
    reduced model's Ritz frequencies: its rigid-body modes are the full model's)."""
    band = (lo, w2) if lo > w2 * LOW_END else (0.0, w2)
    return low_end(band, np.sqrt(np.maximum(np.diag(red.K), 0.0)))


def _earlier_checks(red: Plant, seen: _Checks, added: list[float], row: np.ndarray, lo: float,
                    w2: float) -> float:
    """The earlier rounds' checks that were not added to the basis, against the final basis: a
    last round's checks sit only beside the frequencies just added and miss the rest of the band."""
    if len(seen.h) <= 1:
        return 0.0
    w_all, h_all = np.concatenate(seen.w[:-1]), np.concatenate(seen.h[:-1], axis=-1)
    keep = ~np.isin(w_all, np.asarray(added)) & (w_all >= _start(red, lo, w2))
    if not keep.any():
        return 0.0
    return float((np.abs(frf(red, 1j * w_all[keep]) - h_all[..., keep]) / row[:, None, None]).max())
