"""A projection subspace built for a few channels at given frequencies, checked by exact solves.

For a large sparse plant and a few inputs and outputs, the response at many frequencies is the
response of a small Galerkin projection ``q = V a`` when ``V`` holds the input and output vectors
pushed through the dynamic stiffness near those frequencies (a block, rational Krylov space):

1. **Shifts.** :data:`N_SHIFTS` real shifts ``sigma_j = w_j^2`` at frequencies ``w_j`` spread over
   the requested ones (evenly by index), each one sparse or banded factorisation of
   ``K - sigma_j M`` (:func:`vibss.linear.project.krylov.shift_solver`); per shift :data:`MOMENTS` blocks
   ``(K - sigma M)^-1 [B, O^T]``, ``(K - sigma M)^-1 M V_k`` (``B`` every forcing column, ``O`` every
   output row: both sides in one basis keep the projection symmetric, so the error is second order
   in the basis' error). The basis is M-orthonormal (:class:`vibss.linear.project.krylov.Basis`) and the plant
   projected on it (its ``V^T X V`` grown with the basis), then turned to Ritz coordinates:
   ``M``, ``C``, ``H``, ``K`` and every input and output map, so dampers and loss factors are
   carried by the same projection.
2. **Checks.** Between neighbouring interpolation frequencies (shifts and frequencies already added),
   where an interpolation error is largest, the requested frequency nearest the midpoint (and each
   end of the list; with dampers or loss factors the shift frequencies too, which a real shift
   does not interpolate) is solved exactly (:func:`vibss.linear.project.krylov.exact_response`: the one exact
   solve, banded or sparse LU) and compared with the projected response. The error of a channel
   is ``|H_r - H|`` over the channel's peak ``max |H_r|`` over every requested frequency (times a
   weight per input and frequency when one is given: the time path weighs by the input spectrum).
   Beside them, where the projected response moves when the basis grows (the first basis against
   itself without each shift's last moment; then each round against the one before), at the local
   maxima of that change above the tolerance (the largest :data:`MOVED_MAX` per round): a pole that
   has not converged shows there.
3. **Greedy.** A check above the tolerance becomes an interpolation point: its exact solution and
   adjoint solution (real and imaginary parts: a complex shift, the factorisation is already
   done) join the basis, and the two new midpoints beside it are checked in the next round. It
   stops when every check is below the tolerance, re-evaluated with the final basis; the stated
   error is the largest over every check. A frequency already added that fails again means the
   projection itself loses the answer (the assembled ``K`` of a badly scaled model carries its
   stiffest mount's round-off into ``V^T K V``): not converged, and the caller falls back. Sampled: between checks the error is not measured.
   With a ``budget`` it also stops, not converged, before a round that would take its time past
   that many of its own exact solves (the frequency response: as many as it has frequencies), its
   exact solves kept for the caller.

Nothing n x n is formed densely; memory is ``n (basis + checks (m + p))`` complex numbers.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ...errors import AnalysisError, ArgumentError
from ..eigen.small import projected_eigen
from .krylov import Basis, exact_response, forcing_columns, observing_columns, shift_solver
from ..plant.plant import Plant
from ..solve.exact import forcing, observe, response, zfactor

__all__ = ["Subspace", "channel_subspace", "reduced_response", "N_SHIFTS", "MOMENTS", "MAX_ROUNDS", "TOLERANCE", "TWO_SIDED_MAX", "CHECK_SAFETY", "MOVED_MAX"]

N_SHIFTS = 8
"""Real shifts spread over the requested frequencies at the start."""
MOMENTS = 6
"""Block moments per real shift."""
MAX_ROUNDS = 12
"""Most greedy rounds (each adds the failed checks and checks the new midpoints)."""
TOLERANCE = 1e-8
"""Default relative error per channel, against the channel's peak over the requested frequencies."""
CHECK_SAFETY = 0.1
"""A check passes when its error is below this fraction of the tolerance (the error between checks
is not measured: the margin is for it)."""
MOVED_MAX = 10
"""Most checks per round placed where the projected response moved (each is one exact solve)."""
TWO_SIDED_MAX = 12
"""Most output rows whose vectors (and adjoint solutions) join the basis; more outputs: the input
side only."""


@dataclass(frozen=True, eq=False)
class Subspace:
    """Outcome of :func:`channel_subspace`.

    Attributes
    ----------
    plant : Plant
        The projected plant (Ritz coordinates ``krylov<k>``, ``M = I``, ``K`` diagonal).
    response : (p, m, nf) complex ndarray
        Its response at the requested frequencies, in their order.
    shifts_hz : (ns,) ndarray
        Real shifts [Hz].
    added_hz : (na,) ndarray
        Check frequencies [Hz] whose exact solutions joined the basis.
    check_hz : (nc,) ndarray
        Every check frequency [Hz] (exact solves), sorted.
    check_error : (p, m, nc) ndarray
        ``|H_r - H|`` at the checks with the final basis, unweighted [output unit per input unit].
    error : float
        Largest relative error over the checks with the final basis (see the module docstring) [-].
    worst_hz : float
        Where it was [Hz].
    converged : bool
        Every check within the tolerance.
    tol : float
        The tolerance asked [-].
    seconds : float
        Wall time [s].
    check_omega : (nc,) ndarray
        The check frequencies [rad/s], as given (exactly: a caller finds its own frequencies among them).
    check_response : (p, m, nc) complex ndarray
        The exact response there [output unit per input unit].
    stopped : str
        Why it stopped before its checks passed within its ``budget`` (empty otherwise).
    """

    plant: Plant
    response: np.ndarray
    shifts_hz: np.ndarray
    added_hz: np.ndarray
    check_hz: np.ndarray
    check_error: np.ndarray
    error: float
    worst_hz: float
    converged: bool
    tol: float
    seconds: float
    check_omega: np.ndarray
    check_response: np.ndarray
    stopped: str = ""

    def completed(self, s: np.ndarray, solve: Callable[[np.ndarray], np.ndarray]) -> tuple[np.ndarray, int]:
        """The response at ``s`` from its exact solves where it made them, ``solve`` elsewhere.

        Parameters
        ----------
        s : (nf,) complex ndarray
            Laplace points [rad/s]; a point ``i w`` at one of its checks is answered from that solve.
        solve : callable
            ``solve(s_rest) -> (p, m, k)``: the exact response at the other points.

        Returns
        -------
        h : (p, m, nf) complex ndarray
        solved : int
            How many points ``solve`` answered.
        """
        s = np.asarray(s, dtype=complex)
        at = np.searchsorted(self.check_omega, s.imag).clip(0, max(self.check_omega.size - 1, 0))
        kept = np.zeros(s.size, dtype=bool)
        if self.check_omega.size:
            kept = (self.check_omega[at] == s.imag) & (s.real == 0)
        h = np.empty(self.check_response.shape[:2] + (s.size,), dtype=complex)
        h[:, :, kept] = self.check_response[:, :, at[kept]]
        if not kept.all():
            h[:, :, ~kept] = solve(s[~kept])
        return h, int(np.sum(~kept))

    def describe(self) -> str:
        """Basis size, shifts, checked error and where it was checked, in words."""
        f = self.check_hz
        where = f"{f.size} exact solves from {f.min():.4g} to {f.max():.4g} Hz" if f.size else "no checks"
        shifts = ", ".join(f"{x:.4g}" for x in self.shifts_hz)
        return (f"channel subspace of {self.plant.n} vectors (real shifts at {shifts} Hz, "
                f"{self.added_hz.size} checked frequencies added); checked error {self.error:.2g} of each "
                f"channel's peak (largest at {self.worst_hz:.4g} Hz; {where} between the interpolation "
                f"points, tolerance {self.tol:g}; sampled, not bounded, between checks)"
                + (f"; {self.stopped}" if self.stopped else ""))


class _Galerkin:
    """``V^T X V`` of ``M, C, K, H`` kept up to date as the basis grows: only the new columns are
    multiplied (``X V_new`` and ``V^T X V_new``), so a round costs ``n r k``, not ``n r^2``."""

    def __init__(self, plant: Plant, basis: Basis):
        self.plant, self.basis = plant, basis
        self.keys = ["M", "K"] + [k for k in ("C", "H") if _nonzero(getattr(plant, k))]
        self.g = {k: np.zeros((0, 0)) for k in self.keys}

    def plant_now(self) -> Plant:
        """The plant projected on the basis as it is (its own coordinates, no rotation)."""
        v = self.basis.V
        r0, r = self.g["M"].shape[0], v.shape[1]
        if r > r0:
            new = v[:, r0:]
            for k in self.keys:
                xn = self.basis.MV[:, r0:] if k == "M" else getattr(self.plant, k) @ new
                top = v.T @ xn                                   # (r, r - r0): V^T X V_new
                g = np.zeros((r, r))
                g[:r0, :r0] = self.g[k]
                g[:, r0:] = top
                g[r0:, :r0] = top[:r0].T
                self.g[k] = 0.5 * (g + g.T)
        return self._ritz(np.arange(r))

    def without(self, drop: list[slice]) -> Plant:
        """The plant projected on the basis without the columns ``drop`` (after :meth:`plant_now`):
        the Galerkin matrices sliced, only the input and output maps projected anew."""
        keep = np.setdiff1d(np.arange(self.basis.r), np.concatenate(
            [np.arange(d.start, d.stop) for d in drop] + [np.zeros(0, int)]))
        return self._ritz(keep)

    def _ritz(self, keep: np.ndarray) -> Plant:
        """The plant projected on the basis columns ``keep``, in Ritz coordinates (``M = I``, ``K``
        diagonal: the eigenvectors ``T`` of the projected pair, so ``V T`` is the basis used)."""
        g = {k: self.g[k][np.ix_(keep, keep)] for k in self.keys}
        w2, t = projected_eigen(g["K"], g["M"])
        top = max(float(np.abs(w2).max(initial=0.0)), 1e-300)
        w2 = np.where(np.abs(w2) <= 1e-12 * top, 0.0, w2)
        r = t.shape[1]
        known = {k: t.T @ g[k] @ t for k in ("C", "H") if k in g}
        known.update({k: np.zeros((r, r)) for k in ("C", "H") if k not in g})
        return self.plant.project(self.basis.V[:, keep] @ t, tuple(f"krylov{k + 1}" for k in range(r)),
                                  M=np.eye(r), K=np.diag(w2), **known)


def reduced_response(red: Plant, s: np.ndarray) -> np.ndarray:
    """(p, m, nf) response of a plant in Ritz coordinates (``M = I``, ``K`` diagonal) at ``s``:
    without ``C`` and ``H`` the dynamic stiffness is diagonal and each frequency costs ``r (m + p)``
    (the same :func:`~vibss.linear.solve.exact.forcing` and :func:`~vibss.linear.solve.exact.observe` as the exact
    solve); with them, the exact solve of the small dense plant."""
    if np.any(red.C) or np.any(red.H) or red.branches is not None:
        return response(red, s)
    zf = zfactor(s, red.order)
    with np.errstate(divide="ignore", invalid="ignore"):
        x = forcing(red, s, zf) / (np.diag(red.K)[None, :] + (s * s)[:, None])[:, :, None]
    return np.moveaxis(observe(red, s, x, zf), 0, -1)


def _nonzero(a: object) -> bool:
    """Whether a dense or sparse matrix has a nonzero entry."""
    count = getattr(a, "count_nonzero", None)
    return bool(count()) if count is not None and not isinstance(a, np.ndarray) else bool(np.any(np.asarray(a)))


def _moved(hr: np.ndarray, prev: np.ndarray, scale: np.ndarray, tol: float) -> np.ndarray:
    """Indices of the :data:`MOVED_MAX` largest local maxima of ``|hr - prev|`` (relative per
    channel, weighted) above ``CHECK_SAFETY tol``: where the vectors added last changed the projected response, the previous
    basis was wrong there, and so may the new one be."""
    peak = np.abs(hr * scale).max(axis=2, keepdims=True)
    d = (np.abs(hr - prev) * scale / np.where(peak > 0, peak, 1.0)).max(axis=(0, 1))
    if d.size < 3:
        return np.flatnonzero(d > CHECK_SAFETY * tol)
    inner = np.flatnonzero((d[1:-1] >= d[:-2]) & (d[1:-1] >= d[2:])) + 1
    ends = [i for i in (0, d.size - 1) if d[i] >= d[1 if i == 0 else -2]]
    cand = np.r_[inner, ends].astype(int)
    cand = cand[d[cand] > CHECK_SAFETY * tol]
    return cand[np.argsort(d[cand])[::-1][:MOVED_MAX]]


def _midpoints(interp: set[int], nf: int) -> set[int]:
    """Indices of the requested frequencies nearest the midpoints between interpolation indices,
    and the ends of the list when they are not interpolation points."""
    pts = sorted(interp)
    out = {0, nf - 1} - interp
    out |= {(a + b) // 2 for a, b in zip(pts[:-1], pts[1:]) if b - a >= 2}
    return out


# Over 80 code lines on purpose: one adaptive loop (shifts added where the exact check fails, basis
# grown, re-checked): its state is the loop's, and split it reads as a protocol between pieces that
# only it calls (issue 28: at most 3 functions over 80 lines).
def channel_subspace(plant: Plant, omega: np.ndarray, tol: float = TOLERANCE, weight: np.ndarray | None = None,
                     n_shifts: int = N_SHIFTS, moments: int = MOMENTS, max_rounds: int | None = None,
                     budget: float | None = None) -> Subspace:
    """A projection of ``plant`` whose response at ``omega`` is checked against exact solves.

    Parameters
    ----------
    plant : Plant
        Sparse (or dense) ``M, C, K, H``; no frequency-dependent mounts (their branches are not projected).
    omega : (nf,) array_like
        Frequencies [rad/s], > 0, where the response is wanted (any order, repeats allowed).
    tol : float
        Relative error per channel against its peak [-] (module docstring).
    weight : (m, nf) array_like or None
        Non-negative weight per input and frequency (e.g. ``|U(w)|``) applied to the error and the peak.
    n_shifts, moments : int
        Real shifts at the start and block moments per shift.
    max_rounds : int or None
        Most greedy rounds (None: :data:`MAX_ROUNDS`).
    budget : float or None
        Stop (not converged, ``stopped`` says why) before a round that would take the time spent past
        this many of its own exact solves (> 0): their measured mean time, the round's projected
        response estimated by the last one's times the growth of ``r^2`` (damped; ``r`` the basis
        size: its dense solves per frequency grew as 3.7x for 1.78x more vectors on a lossy grid,
        nearer ``r^2`` than ``r^3`` at these sizes; ``r`` undamped). The frequency response passes the
        number of frequencies, so that a projection that cannot win (its basis near the plant's size,
        its damped projected solve dense a frequency) costs about what the exact solve at every
        frequency would, and the rest of that again, not 5-20x it (a 200-body lossy grid over 1-50 Hz:
        656 vectors for 1,200 DOF, 9.2 s against 1.7 s). A clock, not a formula: the cost constants
        were 3x off on the projected response; near the budget, the round it stops at can differ
        between runs (the answer meets the tolerance either way). The first round is not checked.
        None: no limit.

    Returns
    -------
    Subspace
        ``converged`` False when ``max_rounds`` or the ``budget`` were not enough (the caller decides).

    Raises
    ------
    AnalysisError
        The plant has frequency-dependent mounts, the inputs force nothing, a frequency is not
        positive and finite, or a shift stays singular.

    Examples
    --------
    >>> from ... import Body, Model, Mount, MountType
    >>> from ..plant.build import build_plant
    >>> t = MountType("t", [1e5, 2e5, 3e5])
    >>> bodies = [Body(f"b{i}", 10.0 + i, [1, 1, 1], cog=[i, 0, 0]) for i in range(20)]
    >>> mounts = [Mount(f"g{i}", t, f"b{i}", at=[i, 0.1, -0.2]) for i in range(20)]
    >>> mounts += [Mount(f"m{i}", t, f"b{i}", to=f"b{i - 1}", at=[i - 0.5, 0.1, 0.2]) for i in range(1, 20)]
    >>> p = build_plant(Model(bodies, mounts), ["b0.fz"], ["b0.z", "b1.z"], sparse=True)
    >>> sub = channel_subspace(p, 2 * np.pi * np.linspace(1.0, 30.0, 200))
    >>> sub.converged, sub.error < 1e-8, sub.plant.n < p.n
    (True, True, True)
    """
    t_start = time.perf_counter()
    max_rounds = MAX_ROUNDS if max_rounds is None else max_rounds
    if budget is not None and not (np.isfinite(budget) and budget > 0):
        raise ArgumentError(f"subspace: budget must be a positive number of exact solves, got {budget!r}",
                            argument="budget", received=budget)
    if plant.branches is not None:
        raise AnalysisError(f"subspace: the frequency-dependent mounts {list(plant.branches.mounts)} are not "
                            "projected; use the exact per-frequency solve (method 'sparse')")
    w_in = np.asarray(omega, dtype=float).ravel()
    if w_in.size == 0 or not np.all(np.isfinite(w_in)) or np.any(w_in <= 0):
        raise AnalysisError(f"subspace: frequencies must be finite and > 0 rad/s, got {w_in.size} values "
                            f"from {w_in.min(initial=np.inf):.4g} to {w_in.max(initial=-np.inf):.4g}")
    w, back = np.unique(w_in, return_inverse=True)
    nf = w.size
    b = forcing_columns(plant)
    if b.shape[1] == 0:
        raise AnalysisError(f"subspace: the inputs {list(plant.inputs)} force no DOF")
    o = observing_columns(plant)
    two_sided = o.shape[1] <= TWO_SIDED_MAX
    block0 = np.hstack([b, o]) if two_sided else b
    wt = None
    if weight is not None:                  # the weight of each unique frequency (its first occurrence)
        first = np.zeros(nf, dtype=int)
        first[back[::-1]] = np.arange(w_in.size)[::-1]
        wt = np.abs(np.asarray(weight, dtype=float).reshape(len(plant.inputs), w_in.size))[:, first]
    basis = Basis(plant.M)
    at = np.unique(np.round(np.linspace(0, nf - 1, max(1, min(int(n_shifts), nf)))).astype(int))
    sigmas = []
    last: list[slice] = []
    for i in at:
        solve, sigma = shift_solver(plant, float(w[i]), float(w[-1]))
        sigmas.append(sigma)
        last.append(basis.add_sequence(solve, block0, moments))
    interp = {int(i) for i in at}
    added: set[int] = set()
    exact: dict[int, np.ndarray] = {}
    sols: dict[int, np.ndarray] = {}
    new = _midpoints(interp, nf)
    damped = any(_nonzero(getattr(plant, k)) for k in ("C", "H"))
    if not new or damped:
        new |= interp       # a real shift interpolates only the undamped response; and never no check at all
    converged = False
    stopped = ""
    s = 1j * w
    hr_prev = None
    galerkin = _Galerkin(plant, basis)
    solve_times: list[float] = []
    projected = (0.0, 1)                        # the last round's projected response: seconds, basis size
    for rnd in range(max(int(max_rounds), 0) + 1):
        if rnd and budget is not None and solve_times:
            spent = time.perf_counter() - t_start
            allowed = float(budget) * float(np.mean(solve_times))
            ahead = projected[0] * ((basis.r / projected[1]) ** 2 if damped else basis.r / projected[1])
            if spent + ahead > allowed:
                stopped = (f"stopped before round {rnd + 1}, past its budget: {spent:.2g} s spent ({len(exact)} exact "
                           f"solves, {rnd} projected response(s)) and {ahead:.2g} s estimated for the next at "
                           f"{basis.r} vectors, against {allowed:.2g} s for the exact solve at {budget:g} "
                           f"frequencies ({float(np.mean(solve_times)):.2g} s each, measured)")
                break
        t_round = time.perf_counter()
        red = galerkin.plant_now()
        in_red = sorted(added)                  # the frequencies whose solutions ``red`` holds
        hr = reduced_response(red, s)                             # (p, m, nf)
        projected = (time.perf_counter() - t_round, max(red.n, 1))
        scale = np.ones((1,) + hr.shape[1:]) if wt is None else wt[None]
        if hr_prev is None:                     # the first basis against itself one moment shorter
            hr_prev = reduced_response(galerkin.without(last), s)
        # where the last vectors moved the answer, the smaller basis was wrong: check there too
        new |= set(_moved(hr, hr_prev, scale, tol)) - set(exact)
        hr_prev = hr
        for i in sorted(new - set(exact)):
            t_solve = time.perf_counter()
            y, x, xa = exact_response(plant, complex(s[i]), adjoint=two_sided)
            solve_times.append(time.perf_counter() - t_solve)
            exact[i] = y
            sols[i] = np.hstack([x, xa]) if xa is not None else x
        idx = np.array(sorted(exact), dtype=int)
        hf = np.stack([exact[i] for i in idx], axis=-1) if idx.size else np.zeros(hr.shape[:2] + (0,), complex)
        peak = np.abs(hr * scale).max(axis=2)
        if idx.size:
            peak = np.maximum(peak, np.abs(hf * scale[:, :, idx]).max(axis=2))
        peak = np.where(peak > 0, peak, max(float(peak.max(initial=0.0)), np.finfo(float).tiny))
        diff = np.abs(hr[:, :, idx] - hf)
        rel = (diff * scale[:, :, idx] / peak[:, :, None]).max(axis=(0, 1)) if idx.size else np.zeros(0)
        bad = [int(i) for i, e in zip(idx, rel) if not e <= CHECK_SAFETY * tol]
        if not bad:
            converged = True
            break
        if rnd == max_rounds or added.intersection(bad):
            break       # an added frequency failing again: the projection itself is off (round-off), not the basis
        for i in bad:
            z = sols.pop(i, None)
            if z is None:
                y, x, xa = exact_response(plant, complex(s[i]), adjoint=two_sided)
                z = np.hstack([x, xa]) if xa is not None else x
            basis.add(np.hstack([z.real, z.imag]))
            added.add(i)
        interp |= set(bad)
        new = _midpoints(interp, nf) - set(exact)
    k = int(np.argmax(rel)) if rel.size else 0
    two_pi = 2 * np.pi
    return Subspace(plant=red, response=hr[:, :, back], shifts_hz=np.sqrt(np.abs(sigmas)) / two_pi,
                    added_hz=w[in_red] / two_pi, check_hz=w[idx] / two_pi, check_error=diff,
                    error=float(rel.max(initial=0.0)), worst_hz=float(w[idx[k]] / two_pi) if idx.size else 0.0,
                    converged=converged, tol=float(tol), seconds=time.perf_counter() - t_start,
                    check_omega=w[idx], check_response=hf, stopped=stopped)
