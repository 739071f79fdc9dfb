"""Time-response methods: the job they receive, the registry of :class:`TimeMethod` objects, the resolver.

Every method, built-in or a user's callable, has one signature: ``kernel(job) -> (y, note)`` with
``job`` a :class:`SimulationJob` and ``y`` the (ns, p) outputs at ``job.time``. Each
:data:`METHODS` entry carries the facts :func:`vibss.time.simulate` acts on (hits pulse edges,
force inputs only, uses ``solve_ivp``'s ``solver``, falls back to ...), so the driver never tests
a method's name.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from . import branched
from . import kernels as tm
from ..costs import constant, scale
from ..diagnostics import check_central_difference
from ..errors import AnalysisError, ModelError
from ..linear.plant.branches import require_none
from ..linear.plant.plant import Plant
from ..methods import SIMULATE_LARGE_DOFS, Check, Claim, Cost, Method, callable_name, resolve
from ..model.model import Model
from .integrators import (ERROR_CONSTANT, central_difference, central_difference_method, frequency_error, newmark,
                          newmark_method)
from .sampling import PEAK_TOLERANCE, fine_input, modal_amplitudes
from .kernels.laws import LocalLaws
from .nonlinear import run_nonlinear, step_limit, substeps

__all__ = ["SimulationJob", "NonlinearJob", "TimeMethod", "METHODS", "AUTO", "resolve_method", "stays_sparse", "settled",
           "CHECK_WINDOW", "FLOPS", "STEP_OVERHEAD"]


@dataclass(frozen=True)
class TimeMethod(Method):
    """A simulation method: ``kernel(job: SimulationJob) -> (y (ns, p), note)``.

    Attributes
    ----------
    hits_edges : bool
        Input breakpoints (pulse edges, table knots) are hit exactly (inserted into the grid or
        restarted at), so the sampling check only looks at aliasing.
    forces_only : bool
        Takes force inputs only (no prescribed motion).
    uses_solver : bool
        Integrates with ``solve_ivp``'s ``solver`` (explicit Runge-Kutta solvers are checked for
        stiffness).
    auto_reason : str
        Why ``auto`` picks it (empty: ``auto`` does not).
    checker : callable or None
        ``checker(job, y) -> Check``: its a-posteriori check, cheap next to the run (None: it
        claims exactness, or nothing).
    coster : callable or None
        ``coster(job) -> Cost``: its time and peak memory on the job (the memory guard reads it).
    nonlinear : bool
        Takes a model with nonlinear mounts (a :class:`NonlinearJob`); the others are linear only.
    """

    hits_edges: bool = False
    forces_only: bool = False
    uses_solver: bool = False
    auto_reason: str = ""
    checker: Callable[[Any, np.ndarray], Check] | None = None
    coster: Callable[[Any], Cost] | None = None
    nonlinear: bool = False


@dataclass(frozen=True, eq=False)
class SimulationJob:
    """Everything a method needs; what a user-supplied method callable receives.

    Attributes
    ----------
    plant : Plant
        The plant (n free DOFs, m inputs, p outputs).
    time : (ns,) ndarray
        Sample times ``k dt`` from 0 to ``t_end`` [s].
    funcs : tuple of callable
        The m input signals ``u_j(t)`` (vectorised, SI).
    breakpoints : (k,) ndarray
        Times where an input or its slope jumps [s].
    q0, v0 : (n,) ndarray
        Initial displacement and velocity of the free DOFs at ``t = 0-`` [m, rad, m/s, rad/s].
    rtol, atol : float, float or None
        Tolerances (``ivp``).
    solver : str
        ``solve_ivp`` method name (``ivp``).

    A method callable returns ``(y, note)``: y of shape (ns, p) at ``time``, and a text.
    """

    plant: Plant
    time: np.ndarray
    funcs: tuple[Callable[[np.ndarray], np.ndarray], ...]
    breakpoints: np.ndarray
    q0: np.ndarray
    v0: np.ndarray
    rtol: float = 1e-6
    atol: float | None = None
    solver: str = "Radau"
    sinusoids: tuple[tuple[Any, ...], ...] = ()
    exact_inputs: tuple[str, ...] = ()

    def sampled(self, grid: tm.Grid) -> tm.Kinematics:
        """Exact kinematics of the inputs on ``grid`` (right and left limits at its points): linear
        between the points once the inputs' sine/cosine pieces (``sinusoids``) are taken out, and
        those pieces exactly."""
        d = tm.nudge(grid.t, float(self.time[1] - self.time[0]))
        up, dn = grid.t + d, grid.t - d
        u_r = np.column_stack([np.broadcast_to(f(up), up.shape) for f in self.funcs]) if self.funcs \
            else np.zeros((len(up), 0))
        u_l = np.column_stack([np.broadcast_to(f(dn), dn.shape) for f in self.funcs]) if self.funcs \
            else np.zeros((len(up), 0))
        return tm.kinematics(grid, np.asarray(u_r, float), np.asarray(u_l, float), self.plant.kinds,
                             self.sinusoids or None, d)


@dataclass(frozen=True, eq=False)
class NonlinearJob(SimulationJob):
    """A :class:`SimulationJob` of a model with nonlinear mounts (:mod:`vibss.time.nonlinear`): its plant
    is the augmented linear part (the user's outputs, then each nonlinear axis's deflection and
    velocity; the user's inputs, then one force per axis).

    Attributes
    ----------
    laws : LocalLaws or None
        The nonlinear axes.
    user_outputs, user_inputs : int
        The user's outputs and inputs (the first rows and columns of the plant's).
    memo : dict
        What the run recorded: ``"run"`` (:class:`~vibss.time.kernels.contact.ContactRun`), ``"sub"``
        (internal steps per sample).
    """

    laws: LocalLaws | None = None
    user_outputs: int = 0
    user_inputs: int = 0
    memo: dict = field(default_factory=dict)


def _nonlinear_job(job: Any, name: str) -> NonlinearJob:
    if not isinstance(job, NonlinearJob) or job.laws is None:
        raise ModelError(f"simulate: method {name!r} simulates a Model (with nonlinear mounts or without), not a "
                         "Plant: pass the model, or use 'auto' or 'modal'", argument="method", received=name)
    return job


def _method_nonlinear(job: SimulationJob) -> tuple[np.ndarray, str]:
    nj = _nonlinear_job(job, "nonlinear_modal")
    sub = int(nj.memo.pop("next_sub", 0)) or substeps(nj, step_limit(nj, nj.rtol))
    y, note, run = _run_nonlinear(nj, sub)
    nj.memo.update(run=run, sub=sub)
    return y, note


def _run_nonlinear(nj: NonlinearJob, sub: int) -> tuple[np.ndarray, str, Any]:
    """``run_nonlinear`` kept per internal step count: a refined run's check takes the steps an earlier
    check already ran (1, 2 failed -> 4 checked against that 2)."""
    runs = nj.memo.setdefault("runs", {})
    if sub not in runs:
        runs[sub] = run_nonlinear(nj, sub)
    return runs[sub]


NONLINEAR_PEAK_FLOOR = 1e-4
"""A nonlinear axis's peak (an output's) is judged relative to at least this fraction of the largest
axis's (output's of its unit): one that a symmetry keeps at rest moves by round-off, 1e-11 of the largest
on a symmetric cabinet, and those 1e-13 m differed by 1e-5 of a 1e-6 floor between two step counts."""


def _check_nonlinear(job: Any, y: np.ndarray) -> Check:
    """The step-doubling estimate of a nonlinear run: the same run with half the internal steps per
    sample (twice as many when there is one), ``|y_h - y_2h| / 3`` relative to the peak, on the outputs
    and on the nonlinear axes' peak deflections: the factor of second order, not the ``/ 15`` of the
    fourth that smooth steps have. With every stop clearance and curve breakpoint located the steps
    are fourth order (the snubbed cabinet's 0.3 s shock, its vertical motion against 32 steps per
    sample: 4.6e-9, 2.9e-10, 1.8e-11, 1.1e-12 at 1, 2, 4, 8), where this factor overstates the error
    of a finer run fivefold; while breakpoints were stepped over the error fell as
    ``h^2`` and ``/ 15`` stated 7.8e-8 for 3.2e-7. A contact shorter than a step is such a case still."""
    nj = _nonlinear_job(job, "nonlinear_modal")
    sub, run = nj.memo["sub"], nj.memo["run"]
    other = sub // 2 if sub >= 2 else 2
    y2, _, run2 = _run_nonlinear(nj, other)
    factor = 1 / 3 if other < sub else 4 / 3       # second order (see the docstring)
    peak = np.abs(y).max(axis=0, initial=0.0)
    units = np.array(list(getattr(job.plant, "units", ())), dtype=object)
    if units.size != peak.size:            # an augmented plant: every output judged alike
        units = np.zeros(peak.size, dtype=object)
    for u in set(units.tolist()):          # an output symmetry keeps at rest: judged against its unit's largest
        same = units == u
        peak[same] = np.maximum(peak[same], NONLINEAR_PEAK_FLOOR * float(peak[same].max(initial=0.0)))
    peak = np.maximum(peak, 1e-300)
    out = float((np.abs(y - y2).max(axis=0, initial=0.0) / peak).max(initial=0.0)) * factor
    ext = np.maximum(np.abs(run.peak_hi), np.abs(run.peak_lo))
    dev = np.maximum(np.abs(run.peak_hi - run2.peak_hi), np.abs(run.peak_lo - run2.peak_lo))
    # each axis relative to its own excursion, floored at NONLINEAR_PEAK_FLOOR of the largest: an axis
    # that symmetry keeps at rest has round-off peaks (1e-20 m) whose ratio means nothing
    floor = NONLINEAR_PEAK_FLOOR * float(ext.max(initial=0.0))
    local = float((dev / np.maximum(ext, max(floor, 1e-300))).max(initial=0.0)) * factor
    where = (f"step doubling ({sub} and {other} internal steps per sample): outputs {out:.1e}, peak "
             f"deflections of the nonlinear axes {local:.1e}")
    error = max(out, local)
    if error > nj.rtol:       # the steps that meet rtol for a rerun: the steps' fourth order, an eighth of
        # rtol so that the next check, with its second-order factor (5x the error of a fourth-order run), passes
        grow = min(16.0, max(2.0, (error / (nj.rtol / 8)) ** 0.25))
        nj.memo["next_sub"] = int(np.ceil(sub * grow / 2) * 2)
    return Check(error, nj.rtol, where)


def _method_modal(job: SimulationJob) -> tuple[np.ndarray, str]:
    dt = job.time[1] - job.time[0]
    grid = tm.make_grid(len(job.time), dt, job.breakpoints)
    kin = job.sampled(grid)
    prep = tm.prepare(job.plant)
    sets = branched.modal_sets(prep, job.q0, job.v0) if job.plant.branches is not None else None
    y, how = tm.run_modal(prep, grid, kin, grid.samples, job.q0, job.v0, sets)
    extra = len(grid.t) - len(job.time)
    given = [u for u in job.plant.inputs]
    exact = [u for u in given if u in job.exact_inputs]
    sampled = [u for u in given if u not in job.exact_inputs]
    what = ("every input exact (piecewise linear, sine and cosine pieces)" if not sampled else
            f"exact for {exact} (piecewise linear, sine and cosine pieces); {sampled} linear between "
            "their samples" if exact else "the inputs linear between their samples")
    return y, f"exact modal FOH ({how}); {what}; {extra} breakpoints inserted into the grid"


def _method_forced_response(job: SimulationJob) -> tuple[np.ndarray, str]:
    dt = job.time[1] - job.time[0]
    grid = tm.make_grid(len(job.time), dt, np.array([]))
    t = job.time
    u = np.column_stack([np.broadcast_to(f(t), t.shape) for f in job.funcs]) if job.funcs \
        else np.zeros((len(t), 0))
    kin = tm.kinematics(grid, u, u, job.plant.kinds)
    return tm.run_forced_response(tm.prepare(job.plant), t, u, kin, job.q0, job.v0)


def _method_ivp(job: SimulationJob) -> tuple[np.ndarray, str]:
    return tm.run_ivp(tm.prepare(job.plant), list(job.funcs), job.breakpoints, job.time, job.q0,
                      job.v0, rtol=job.rtol, atol=job.atol, solver=job.solver)


def _method_central_difference(job: SimulationJob) -> tuple[np.ndarray, str]:
    finding = check_central_difference(job.plant.M, job.plant.K, float(job.time[1] - job.time[0]))
    if not finding.ok:
        raise AnalysisError(f"central_difference would blow up: {finding.message}")
    return central_difference_method(job)


CHECK_WINDOW = 512
"""Steps of the fixed-step integrators' step-halving check (the first ones, where a pulse acts)."""

FLOPS = constant("time.FLOPS", 1e9)
"""Floating-point operations per second of one core, for the time estimates [1/s]."""


def _forces(job: SimulationJob, t: np.ndarray) -> np.ndarray:
    return (np.column_stack([np.broadcast_to(f(t), t.shape) for f in job.funcs]).astype(float) if job.funcs
            else np.zeros((t.size, 0)))


def _highest_mode(job: SimulationJob, y: np.ndarray) -> tuple[float, float]:
    """The highest undamped mode [rad/s] that carries at least :data:`~vibss.time.sampling.PEAK_TOLERANCE`
    of an output's peak, and that share (0, 0: none)."""
    peak = np.abs(y).max(axis=0)
    inputs = [fine_input(f, job.time, job.breakpoints, p)
              for f, p in zip(job.funcs, job.sinusoids or [()] * len(job.funcs))]
    for f, amp in reversed(modal_amplitudes(job.plant, inputs, job.q0, job.v0)):
        share = float((np.minimum(amp, peak) / np.where(peak > 0, peak, 1.0)).max(initial=0.0))
        if share >= PEAK_TOLERANCE:
            return 2 * np.pi * f, share
    return 0.0, 0.0


def _halving(scheme: str) -> Callable[[Any, np.ndarray], Check]:
    """The check of a fixed-step integrator, relative to the outputs' peak: the same scheme at ``dt / 2``
    over the first :data:`CHECK_WINDOW` steps (``4/3 |y(dt) - y(dt/2)|`` estimates the error of ``y(dt)``
    for a second-order scheme), or, if larger, the phase the highest participating mode has drifted by
    the end of the record (its exact frequency error times ``w t_end``, times its share of the peak)."""
    integrate = newmark if scheme == "newmark" else central_difference

    def check(job: Any, y: np.ndarray) -> Check:
        t = job.time[:min(job.time.size, CHECK_WINDOW)]
        dt, t_end = float(t[1] - t[0]), float(job.time[-1])
        half = dt / 2 * np.arange(2 * t.size - 1)
        with np.errstate(all="ignore"):
            fine = integrate(job.plant, half, _forces(job, half), job.q0, job.v0)[::2]
        peak = np.maximum(np.abs(y).max(axis=0), np.abs(fine).max(axis=0))
        scale = np.where(peak > 0, peak, 1.0)
        halving = float(np.nan_to_num(4 / 3 * np.abs(y[:t.size] - fine) / scale, nan=np.inf).max(initial=0.0))
        w, share = _highest_mode(job, y)
        freq = float(frequency_error(scheme, w * dt)) if w > 0 else 0.0
        drift = share * min(2.0, freq * w * t_end)
        c = ERROR_CONSTANT[scheme]
        step = np.sqrt(PEAK_TOLERANCE / (c * w * max(t_end, 1.0 / w))) / w if w > 0 else np.inf
        where = (f"step halving over the first {t.size} steps: {halving:.1e}; highest participating mode "
                 f"{w / (2 * np.pi):.4g} Hz at {2 * np.pi / (w * dt) if w > 0 else np.inf:.3g} samples per "
                 f"period: frequency error {freq:.1e} (about {c:.3g} (w dt)^2), phase drift {drift:.1e} of "
                 f"the peak by {t_end:g} s; dt <= {step:.3g} s keeps it within {PEAK_TOLERANCE:.0%}")
        return Check(max(halving, drift), PEAK_TOLERANCE, where)

    return check


IVP_CHECK_SHARE = 8
"""The ``ivp`` check re-solves the first ``1 / IVP_CHECK_SHARE`` of the record (at least
:data:`IVP_CHECK_MIN` samples) at a tenth of the tolerances."""
IVP_CHECK_MIN = 32


def _tightened(job: Any, y: np.ndarray) -> Check:
    """The check of ``ivp``: the first part of the record again at ``rtol / 10`` and ``atol / 10``;
    ``|y - y_tight|`` estimates the error of ``y`` there (to about 10 %), relative to the outputs'
    peak. It sees the pulse a shock record starts with, not a phase drift that grows beyond the
    window (measured: 1.5e-7 in the window, 1.9e-7 over the record at rtol 1e-6; 0.14 and 0.28
    at rtol 0.1 with RK23). The claim scales with ``rtol``: the limit is ``rtol`` (1e-6 by default)."""
    ns = min(job.time.size, max(job.time.size // IVP_CHECK_SHARE, IVP_CHECK_MIN))
    t = job.time[:ns]
    edges = job.breakpoints[job.breakpoints < t[-1]]
    atol = None if job.atol is None else job.atol / 10
    fine, _ = tm.run_ivp(tm.prepare(job.plant), list(job.funcs), edges, t, job.q0, job.v0,
                         rtol=job.rtol / 10, atol=atol, solver=job.solver)
    peak = np.maximum(np.abs(y).max(axis=0), np.abs(fine).max(axis=0))
    scale = np.where(peak > 0, peak, 1.0)
    error = float(np.nan_to_num(np.abs(y[:ns] - fine) / scale, nan=np.inf).max(initial=0.0))
    return Check(error, float(job.rtol), f"the first {ns} samples ({t[-1]:.3g} s) again at rtol "
                                         f"{job.rtol / 10:.0e} ({job.solver}); a phase drift may grow beyond")


def _cost(kind: str) -> Callable[[Any], Cost]:
    """Time and peak memory of a method on a job, from its sizes: ``n`` DOFs, ``m`` inputs, ``p``
    outputs, ``ns`` samples (the modal path adds the inserted breakpoints; the state-space paths carry
    ``2 n`` states, one ``(2n)^2`` product a step; the integrators one factored solve a step and three
    ``(ns, n)`` histories; the step loops in Python cost :data:`STEP_OVERHEAD` each). Measured against
    one run at 120 and 600 DOF, 2,000 steps (docs/analyses/time.md): the run took 0.4-3.7x the estimate."""
    def cost(job: Any) -> Cost:
        found = _formula(job)
        return Cost(scale(f"time.{kind}") * found.seconds, found.bytes)

    def _formula(job: Any) -> Cost:
        n, m, p, ns = job.plant.n, len(job.plant.inputs), len(job.plant.outputs), job.time.size
        dense = 8.0 * (6 * n * n)
        if kind == "modal":
            ns = ns + job.breakpoints.size
            # no complex modes where C and H are zero or a M + b K; other damping costed as fully coupled
            eigen = float(n) ** 3 if _classical(job.plant) else n**3 + EIG_GENERAL * (2.0 * n) ** 3
            return Cost(0.01 + (eigen + ns * (4 * n * (m + 2) + 2 * n * p)) / FLOPS, dense + 8.0 * ns * (p + 2 * m))
        if kind == "nonlinear":
            r = job.laws.r if getattr(job, "laws", None) is not None else 0
            sub = max(1, int(getattr(job, "memo", {}).get("sub", 1)))
            steps = ns * sub
            return Cost(0.05 + (2 * n**3 + steps * (8 * n * (r + 1)) + ns * 2 * n * p) / FLOPS
                        + steps * 10 * STEP_OVERHEAD, dense + 8.0 * steps * 4 * r + 8.0 * ns * p)
        if kind == "state":
            return Cost((4 * n**3 + ns * (4 * n * n + 2 * n * (m + p))) / FLOPS + ns * STEP_OVERHEAD,
                        4 * dense + 8.0 * ns * (2 * n + m + p))
        return Cost((n**3 + ns * 2 * n * n) / FLOPS + ns * STEP_OVERHEAD, dense + 8.0 * ns * (3 * n + m + p))

    return cost


def _classical(plant: Any) -> bool:
    from ..linear.eigen.basis import classical_by_construction      # lazy: the command line's import time

    return classical_by_construction(plant)


EIG_GENERAL = constant("time.EIG_GENERAL", 1.2)
"""The modal path's ``eig`` of the ``2 n`` states (general damping: complex modes) per ``(2 n)^3``, in
units of the classical path's ``eigh`` per ``n^3``: the 600-DOF suite took 8-10x the classical time (the
mechanism chain over 0.4 s 30x: its 148 modes slower than the horizon each take a dense inverse
iteration, :func:`~vibss.linear.eigen.complex_modes.complex_modes`)."""


STEP_OVERHEAD = constant("time.STEP_OVERHEAD", 3e-5)
"""Interpreter time of one step of a loop over the steps [s] (measured: Newmark at 120 DOF)."""


EXACT = Claim(1e-9, exact=True, conditions="inputs piecewise linear, or sine and cosine pieces, between their "
                                           "breakpoints (outputs at the samples)")
METHODS: dict[str, TimeMethod] = {m.name: m for m in (
    TimeMethod("modal", _method_modal, exact=True, hits_edges=True, fallback="forced_response",
               internal_states=True, claim=EXACT, coster=_cost("modal"),
               auto_reason="exact for piecewise-linear inputs and sine/cosine pieces, and the fastest",
               summary="exact modal superposition of piecewise-linear inputs (breakpoints inserted)"),
    TimeMethod("forced_response", _method_forced_response, exact=True, internal_states=True,
               claim=Claim(1e-9, exact=True, conditions="inputs linear between the samples (first-order hold "
                                                        "on the sample grid)"), coster=_cost("state"),
               summary="control.forced_response of the exact realization on the sample grid"),
    TimeMethod("ivp", _method_ivp, hits_edges=True, uses_solver=True, coster=_cost("state"),
               checker=_tightened,
               claim=Claim(1e-6, conditions="rtol = 1e-6 (the default; the claim is rtol for another): the "
                                            "local error of every step within rtol and atol; checked on the "
                                            "first eighth of the record re-solved at rtol / 10"),
               summary="solve_ivp with variable steps to rtol/atol, restarted at every breakpoint"),
    TimeMethod("newmark", newmark_method, forces_only=True, checker=_halving("newmark"), coster=_cost("fixed"),
               claim=Claim(PEAK_TOLERANCE, conditions="the phase each participating mode drifts over the record, "
                                                      "w t_end (w dt)^2 / 12 (second order, no amplitude error), "
                                                      "stays below it"),
               summary="Newmark average acceleration (unconditionally stable, second order)"),
    TimeMethod("central_difference", _method_central_difference, forces_only=True,
               checker=_halving("central_difference"), coster=_cost("fixed"),
               claim=Claim(PEAK_TOLERANCE, conditions="dt < 2 / w_max (refused beyond) and every participating "
                                                      "mode has more than 25 samples per period: second order, "
                                                      "frequency error (w dt)^2 / 24"),
               summary="explicit central difference (refused beyond dt = 2 / w_max)"),
    TimeMethod("nonlinear_modal", _method_nonlinear, hits_edges=True, internal_states=True, nonlinear=True,
               checker=_check_nonlinear, coster=_cost("nonlinear"),
               claim=Claim(1e-6, conditions="rtol (1e-6 by default) relative on the outputs and the peak deflections "
                                            "of the nonlinear axes: the internal step keeps omega_c h within "
                                            "0.2 (rtol / 1e-6)^(1/4) (auto: shorter steps until the step-doubling check passes) of every stop's contact frequency"),
               auto_reason="a model with nonlinear mounts: the linear part exact in modes, the mount forces local, "
                           "stop contacts located",
               summary="exact modal propagation with the nonlinear mount forces as local cubic forces, stop "
                       "contacts located"),
)}
"""Simulation methods by name (``"auto"`` picks :data:`AUTO`), each with its contract (claim,
a-posteriori check, cost: docs/analyses/time.md). ``newmark`` (average acceleration, unconditionally
stable, second order) and ``central_difference`` (explicit; refused beyond ``dt = 2 / w_max``) take
force inputs only and are there for comparison (docs/performance.md); a named run that misses its
claim warns with the measured bound."""

AUTO = "modal"
"""The method ``"auto"`` runs (falling back as its :attr:`TimeMethod.fallback` says)."""


def _custom(fn: Callable[..., Any]) -> TimeMethod:
    return TimeMethod(callable_name(fn), fn, summary="user method")


def resolve_method(method: Any) -> tuple[TimeMethod, bool]:
    """The :class:`TimeMethod` for a name, ``"auto"``, a TimeMethod or a callable ``f(job)``, and
    whether it was ``"auto"``.

    Parameters
    ----------
    method : str, TimeMethod or callable

    Returns
    -------
    method : TimeMethod
    auto : bool

    Raises
    ------
    ModelError
        An unknown name (the valid ones listed, with a did-you-mean).
    """
    if isinstance(method, str) and method == "auto":
        return METHODS[AUTO], True
    return resolve(method, METHODS, where="simulate", custom=_custom, extra=["auto"]), False


def stays_sparse(model: Model, method: Any) -> bool:
    """Whether :func:`~vibss.time.api.simulate` keeps ``model`` sparse (:mod:`vibss.time.large`): above
    :data:`vibss.methods.SIMULATE_LARGE_DOFS` DOFs with ``method="auto"``, and no branch mounts."""
    return (isinstance(method, str) and method == "auto" and 6 * len(model.bodies) > SIMULATE_LARGE_DOFS
            and not any(t.has_branches for t in model.mount_types.values()))


def settled(plant: Plant, method: Any) -> tuple[TimeMethod, bool, str]:
    """The method :func:`~vibss.time.api.simulate` runs (``auto`` settled for frequency-dependent
    mounts: the structured modal path where :func:`vibss.time.branched.suits` says so, else
    ``forced_response``), whether ``auto`` chose it, and the note on the plant's Maxwell branches."""
    chosen, auto = resolve_method(method)
    if plant.branches is not None and auto:
        structured, why = branched.suits(plant)
        if structured:       # the exact modal FOH on modes plus branch states; forced_response if refused
            return chosen, auto, f"{plant.branches.note()}: {why}"
        return (METHODS["forced_response"], False,
                f"{plant.branches.note()}: forced_response of the state space with them ({why})")
    if plant.branches is not None:
        if not chosen.internal_states:
            require_none(plant, f"simulate: method {chosen.name!r}",
                         f"use one of {[k for k, v in METHODS.items() if v.internal_states]} or 'auto'")
        return chosen, auto, plant.branches.note()
    return chosen, auto, ""
