"""Time response: shocks, forces, prescribed motions and initial conditions.

:func:`simulate` runs a linear simulation of a model (or a :class:`~vibss.linear.plant.plant.Plant`) from
``t = 0`` and returns a :class:`TimeResponse` sampled every ``dt`` from ``record_from`` on.
Methods are chosen by name through :data:`METHODS` (a callable is accepted too):

``"modal"`` (the fast path, and ``"auto"``)
    Exact modal superposition of piecewise-linear (PWL) inputs: real undamped modes (the one eigen path) for
    classical damping (2x2 blocks, exact also for rigid-body modes, omega = 0); complex modes of the
    scaled modal first-order form for the modes that non-proportional damping couples. Each mode is
    discretised exactly for polynomial forcing (first-order hold, and the exact polynomial
    kinematics of velocity and acceleration inputs); only the outputs are stored. Frequency-dependent
    mounts' Maxwell branches join the modes as states (:mod:`vibss.time.branched`): ``auto`` takes
    this for a few of them and falls back to ``forced_response`` when most mounts have them or the
    structured eigen-solve cannot certify its roots (the note says why).
    **Edges:** the inputs' breakpoints (pulse edges, table knots) are inserted into the simulation
    grid, so a pulse edge between two samples is hit exactly and jumps are kept as jumps.
``"forced_response"`` (the reference)
    python-control's :func:`control.forced_response` of the exact z-only realization (no
    differentiated inputs), on the uniform sample grid. **Edges:** the input is the PWL
    interpolant of its samples, so an edge between samples is smeared over one step.
``"nonlinear_modal"`` (``"auto"`` on a model with stops or curves)
    The linear part exact in its modes (as ``"modal"``), each nonlinear mount axis's force beyond its
    linear rate a local force, cubic in time over each internal step and implicit at the few local
    coordinates; every stop contact located (:mod:`vibss.time.nonlinear`). It starts from the
    operating point (:func:`vibss.operating_point`: gravity and static loads, stops and curves
    included) and its outputs are the motion from there (the linear methods leave gravity out: the
    motion from the static state). The result's ``contacts`` lists the stops hit.
``"ivp"``
    :func:`scipy.integrate.solve_ivp` with variable steps to the tolerance ``rtol`` / ``atol``
    (``solver`` = ``"Radau"``, ``"DOP853"``, ``"LSODA"`` ...), of the same realization. **Edges:**
    the integration restarts at every breakpoint, so edges are hit exactly; between breakpoints
    the inputs are evaluated exactly (not interpolated).

Conventions: initial conditions are the state at ``t = 0-``, prescribed coordinates start at rest
at zero (an input nonzero at ``t = 0`` is a jump at ``t = 0``); where an input jumps or kinks at a
sample, outputs take the right-hand limit.

Examples
--------
>>> from vibss import Body, Model, Mount, MountType
>>> from vibss.model.excitation import Excitation, Step
>>> m = Model([Body("b", 2.0, [1, 1, 1])], [Mount("m", MountType("t", [800.0] * 3), "b")])
>>> step = Excitation("s", "force", "b", Step(10.0), dof="z")
>>> r = simulate(m, [step], outputs=["b.z"], t_end=0.5, dt=1e-3)
>>> round(float(r.peaks().value[0]), 6)      # 2 F / k, undamped
0.025
"""

from __future__ import annotations

import dataclasses
import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, cast

import numpy as np
import scipy.sparse as sp

from .._validate import choice, number
from ..errors import AnalysisError, ArgumentError, DefectiveModesError, ModelError, VibssWarning
from .drift import implausible_motions
from .inputs import SignalInput, as_function, exact_terms, initial_state, summed
from .methods import METHODS, NonlinearJob, SimulationJob, TimeMethod, resolve_method, settled, stays_sparse
from .nonlinear import contact_table, nonlinear_job
from ..nonlinear.kernels import nonlinear_mounts
from ..methods import Check, Cost, Method, decide
from ..model.model import Model
from ..model.timefunctions import TimeFunction
from ..linear.plant.hysteresis import dropped_hysteresis
from ..linear.plant.plant import Plant
from ..linear.plant.build import build_plant
from ..linear.solve.exact import without_hysteresis
from .sampling import PEAK_TOLERANCE, InputProbe, fine_input, output_sampling, probe_input
from .large import Projected, projected_model, truncation_note
from .result import PeakTable, TimeResponse
from ..studies import causal_loss_fit, steady_sweeps, transient_excitations
from ..diagnostics import check_excitations, check_explicit_rk

EXPLICIT_RK = ("RK23", "RK45", "DOP853")


__all__ = ["simulate", "TimeResponse", "PeakTable", "SimulationJob", "TimeMethod", "METHODS"]

Terms = list[tuple[Callable[[np.ndarray], np.ndarray], tuple[float, ...]]]


def simulate(model_or_plant: Model | Plant, excitations: Sequence[Any] | None = None, *,
             inputs: Mapping[str, SignalInput] | None = None, outputs: Sequence[str] | None = None,
             t_end: float, dt: float, record_from: float = 0.0, initial: Any = None,
             method: str | Callable[[SimulationJob], tuple[np.ndarray, str]] = "auto",
             rtol: float = 1e-6, atol: float | None = None, solver: str = "Radau",
             hysteresis: str = "drop") -> TimeResponse:
    """Simulate the time response from ``t = 0`` to ``t_end``.

    Parameters
    ----------
    model_or_plant : Model or Plant
        The system; a Model is turned into a Plant by :func:`vibss.linear.plant.build.build_plant`.
    excitations : sequence of Excitation or None
        Excitations (several on one signal add up). Default: the model's time-domain ones
        (:func:`vibss.studies.transient_excitations`; its steady sweeps are skipped, as the
        command line and the report do, and named in ``note``), unless ``inputs`` given. The
        window and step the command line and the report use: :func:`vibss.studies.time_window`.
    inputs : mapping of str to callable or (ns,) array_like, or None
        More input signals by name (``'engine.fz'``, ``'ground.z.acc'`` ...): a function ``u(t)``
        [SI] or samples at ``k dt`` (ns = round(t_end / dt) + 1).
    outputs : sequence of str or None
        Output signal names (default: every body DOF's displacement).
    t_end : float
        End time [s].
    dt : float
        Sample interval [s].
    record_from : float
        First recorded time [s] (the simulation still starts at 0).
    initial : mapping or None
        Per body ``{"displacement": [6], "velocity": [6]}`` [m, rad, m/s, rad/s] at ``t = 0-`` (from
        the operating point on a model with nonlinear mounts)
        (either key may be left out). Default: the model's bodies' ``initial``. With no
        excitations and no inputs, the free vibration from these initial conditions is simulated
        (the result then has no inputs).
    method : {"auto", "modal", "forced_response", "ivp", "newmark", "central_difference", "nonlinear_modal"}, TimeMethod or callable
        See the module docstring and :data:`METHODS`; a callable ``f(job) -> (y, note)`` gets the
        :class:`SimulationJob` the built-ins get.
        A :class:`~vibss.errors.VibssWarning` says when the sampling smears a pulse or aliases a
        sweep for the method chosen, or when an explicit ``solver`` meets a stiff model.
    rtol, atol : float, float or None
        Tolerances of ``ivp`` (atol default: 1e-12 of the initial state, or 1e-15); ``rtol`` is also
        the accuracy ``nonlinear_modal`` is held to (relative, on the outputs and the peak deflections
        of the nonlinear axes).
    solver : str
        ``solve_ivp`` method of ``ivp`` (``"Radau"``, ``"DOP853"``, ``"LSODA"``, ...).

    hysteresis : {"drop", "causal"}
        Mounts with a constant loss factor (a Model only): ``"drop"`` leaves the loss out, with a
        warning naming the mounts (it has no causal time-domain form); ``"causal"`` simulates
        :func:`vibss.studies.causal_loss` of the model instead: each loss as a passive Maxwell ladder
        fitted over the model's frequency band, its fit error stated in ``note``.
    Returns
    -------
    TimeResponse

    Raises
    ------
    ModelError
        Bad argument (the message names it), more than :data:`MAX_SAMPLES` samples, nothing
        driving the response (no excitation, input or initial condition), or a linear method named
        for a model with nonlinear mounts (the message names the mounts and the methods that work).
    AnalysisError
        A method cannot answer (e.g. solve_ivp failed), or an output needs the second derivative
        of a displacement input (impulsive: prescribe the motion as an acceleration input).

    Warns
    -----
    VibssWarning
        Mounts with a loss factor: it has no causal time-domain form and is left out (named in the
        warning and in ``note``; :func:`vibss.linear.plant.hysteresis.dropped_hysteresis`).
        A sampled input (a plain callable) that departs from the line between its samples, naming
        it and the step that resolves it; outputs stored coarser than the periods that carry the
        response, with the expected peak error and the step that bounds it to 1 %
        (:mod:`vibss.time.sampling`); a named method that misses its claim
        (:attr:`TimeMethod.claim`), with the measured bound (also in ``note``).
    """
    dt, t_end, record_from, ts = _window(dt, t_end, record_from)
    rtol, atol, solver = _tolerances(rtol, atol, solver)
    model = model_or_plant if isinstance(model_or_plant, Model) else None
    hysteresis = choice(hysteresis, "hysteresis", ("drop", "causal"), who="simulate")
    causal_note = ""
    if hysteresis == "causal" and model is not None:
        fit = causal_loss_fit(model)
        causal_note, model = fit.note, fit.model
        model_or_plant = model
    skipped: tuple[Any, ...] = ()
    if excitations is None and model is not None and inputs is None:
        # the model's time-domain excitations; steady sweeps are frequency studies (vibss.studies)
        excitations, skipped = transient_excitations(model), steady_sweeps(model)
    excitations = list(excitations or [])
    sig = _signals(excitations, inputs, ts)
    for text in implausible_motions(excitations, t_end):      # both paths, linear and nonlinear
        warnings.warn(f"simulate: {text}", VibssWarning, stacklevel=2)
    if model is not None and (nonlinear_mounts(model) or getattr(method, "nonlinear", False)
                              or (isinstance(method, str) and getattr(METHODS.get(method), "nonlinear", False))):
        return _nonlinear(model, excitations, sig, outputs, initial, method, ts, record_from, rtol, atol, solver,
                          prefix=dict(causal_note=causal_note, branch_note="", skipped=skipped))
    plant, truncated, hidden = _plant(model_or_plant, model, sig, outputs, initial, method, ts, dt)
    job, funcs, left_out = _job(plant, model, sig, initial, hidden, ts, rtol, atol, solver)
    plant = job.plant
    chosen, auto, branch_note = settled(plant, method)
    motions = [u for u, kind in zip(plant.inputs, plant.kinds) if kind != "force"]
    if chosen.forces_only and motions:
        raise ModelError(f"simulate: method {chosen.name!r} takes only force inputs; inputs {motions} "
                         "are prescribed motions (use method='modal')")
    for finding in check_excitations(excitations, dt, inserts_breakpoints=chosen.hits_edges):
        finding.warn(stacklevel=3)
    if chosen.uses_solver and solver in EXPLICIT_RK:
        check_explicit_rk(plant.M, plant.K, t_end, rtol=rtol, solver=solver, C=plant.C).warn(stacklevel=3)
    probes = _probes(job, sig, chosen)
    for probe in probes:
        if not probe.ok and not chosen.uses_solver:      # solve_ivp evaluates the inputs themselves
            warnings.warn(probe.message(dt, "" if chosen.hits_edges else chosen.name), VibssWarning, stacklevel=2)
    y, note, chosen = _run(job, chosen, auto, motions)
    note = _sampling_note(note, job, chosen, probes, y)
    if auto:
        note = f"auto -> {chosen.name}: " + (f"{chosen.auto_reason}; " if chosen.auto_reason else "") + note
    if truncated is not None:
        note = f"{truncation_note(truncated, y)}; " + note
    keep = ts >= record_from - 1e-9 * dt
    shown = [] if hidden else funcs
    u = np.array([np.broadcast_to(f(ts[keep]), (int(keep.sum()),)) for f in shown]).reshape(len(shown), int(keep.sum()))
    note = _prefixed(note, hidden=hidden, left_out=left_out, causal_note=causal_note, branch_note=branch_note,
                     skipped=skipped)
    return TimeResponse(time=ts[keep], outputs=y[keep].T.copy(), output_names=tuple(plant.outputs),
                        units=tuple(plant.units), inputs=u,
                        input_names=() if hidden else tuple(plant.inputs),
                        method=chosen.name, note=note, name=plant.name)


def _nonlinear(model: Model, excitations: list[Any], sig: _Signals, outputs: Sequence[str] | None, initial: Any,
               method: Any, ts: np.ndarray, record_from: float, rtol: float, atol: float | None, solver: str,
               prefix: dict[str, Any]) -> TimeResponse:
    """:func:`simulate` of a model with nonlinear mounts (:mod:`vibss.time.nonlinear`): from the operating
    point, by ``nonlinear_modal`` (``auto``) or a named method that takes nonlinear models."""
    chosen, auto = resolve_method(method)
    if auto:
        chosen = METHODS[NONLINEAR_AUTO]
    if not chosen.nonlinear:
        names = [m.name for m in model.mounts if getattr(m.type, "nonlinear", False)]
        fits = [k for k, v in METHODS.items() if v.nonlinear]
        raise ModelError(f"simulate: method {chosen.name!r} is linear, and mounts {names} have stops or "
                         f"force-deflection curves: use method='auto' or one of {fits} (or simulate the tangent "
                         "model at the operating point, vibss.operating_point(model).tangent)",
                         argument="method", received=chosen.name, expected=fits)
    dt = float(ts[1] - ts[0])
    hidden = not sig.sources
    plant, laws, p, m = nonlinear_job(model, list(sig.sources.values()), outputs, hidden)
    left_out = dropped_hysteresis(model, "simulate", stacklevel=4)
    if left_out:
        basis = plant._cache.get("modal basis")
        plant = without_hysteresis(plant)
        if basis is not None:
            plant._cache["modal basis"] = basis             # the same M, K and C
    funcs = [summed(sig.terms.get(name, [])) for name in plant.inputs[:m]]
    bps = [b for name in plant.inputs[:m] for _, bb in sig.terms.get(name, []) for b in bb]
    q0, v0 = initial_state(plant, initial, model)
    if hidden and not (np.any(q0) or np.any(v0)):
        raise ModelError("simulate: nothing drives the response: no excitations, no inputs and no nonzero "
                         "initial conditions (initial={body: {'displacement': [6], 'velocity': [6]}})")
    for finding in check_excitations(excitations, dt, inserts_breakpoints=True):
        finding.warn(stacklevel=4)
    job = NonlinearJob(plant=plant, time=ts, funcs=tuple(funcs), breakpoints=np.array(bps, float), q0=q0, v0=v0,
                       rtol=float(rtol), atol=atol, solver=solver,
                       sinusoids=tuple(tuple(sig.pieces.get(u, ())) for u in plant.inputs[:m]),
                       exact_inputs=tuple(u for u in plant.inputs[:m] if sig.exact.get(u, u not in sig.terms)),
                       laws=laws, user_outputs=p, user_inputs=m)

    def cost(meth: Method) -> Cost | None:
        coster = getattr(meth, "coster", None)
        return coster(job) if coster is not None else None

    def check(meth: Method, answer: tuple[np.ndarray, str]) -> Check | None:
        checker = getattr(meth, "checker", None)
        return checker(job, answer[0]) if checker is not None else None

    # auto: rerun with the steps the failed check asks for (up to REFINEMENTS times) until it passes
    order = [chosen] + ([dataclasses.replace(chosen) for _ in range(REFINEMENTS)] if auto else [])
    d = decide(order, lambda meth: meth.kernel(job), where="simulate", auto=auto, check=check, cost=cost)
    y, note = d.answer
    y = np.asarray(y, float)
    if d.check is not None:
        note = f"{note}; {d.check.text()}"
    if len(d.attempts) > 1:
        note = "; ".join(a.text() for a in d.attempts[:-1]) + f"; the step refined {len(d.attempts) - 1} time(s): " + note
    note = "from the operating point (static equilibrium, stops and curves included); " + note
    if auto:
        note = f"auto -> {chosen.name}: {chosen.auto_reason}; " + note
    note = _prefixed(note, hidden=hidden, left_out=left_out, **prefix)
    keep = ts >= record_from - 1e-9 * dt
    shown = [] if hidden else funcs
    u = np.array([np.broadcast_to(f(ts[keep]), (int(keep.sum()),)) for f in shown]).reshape(len(shown), int(keep.sum()))
    recorded = job.memo.get("run")
    return TimeResponse(time=ts[keep], outputs=y[keep].T.copy(), output_names=tuple(plant.outputs[:p]),
                        units=tuple(plant.units[:p]), inputs=u,
                        input_names=() if hidden else tuple(plant.inputs[:m]), method=chosen.name, note=note,
                        name=plant.name, contacts=None if recorded is None or not laws.r else contact_table(laws, recorded))


NONLINEAR_AUTO = "nonlinear_modal"
"""The method ``"auto"`` runs on a model with nonlinear mounts."""

REFINEMENTS = 3
"""Times ``auto`` reruns the nonlinear method with shorter internal steps (those its failed check
estimates to meet ``rtol``) before it gives up (a named ``nonlinear_modal`` runs once and warns)."""


def _probes(job: SimulationJob, sig: _Signals, chosen: TimeMethod) -> list[InputProbe]:
    """Each sampled input probed between the samples of the method's grid
    (:func:`vibss.time.sampling.probe_input`): a plain callable or a time function not linear between
    its breakpoints for a method that hits the edges (modal, ivp); every input but data for the others,
    which sample time functions too."""
    bps = job.breakpoints if chosen.hits_edges else ()
    probed = ((lambda name: sig.sampled.get(name, False)) if chosen.hits_edges else   # the rest is exact
              (lambda name: name in sig.terms and not sig.data.get(name, False)))     # all sampled but data
    return [probe_input(name, fn, job.time, bps) for name, fn in zip(job.plant.inputs, job.funcs) if probed(name)]


def _sampling_note(note: str, job: SimulationJob, chosen: TimeMethod, probes: list[InputProbe],
                   y: np.ndarray) -> str:
    """The note with what the sampling loses: inputs departing from the line between their samples,
    and peaks of the outputs between samples (warned here, :func:`vibss.time.sampling.output_sampling`)."""
    dt = float(job.time[1] - job.time[0])
    for p in probes:
        if not p.ok and not chosen.uses_solver:
            note += f"; input {p.name!r} departs up to {p.departure:.0%} from the line between its samples"
    own = {p.name: p.omega for p in probes}
    inputs, freq = [], []
    for name, fn, pieces in zip(job.plant.inputs, job.funcs, job.sinusoids or [()] * len(job.funcs)):
        inputs.append(fine_input(fn, job.time, job.breakpoints, pieces))
        freq.append(max([own.get(name, 0.0), *(float(s.omega) for s in pieces)]))
    est = output_sampling(job.plant, job.time, inputs, freq, y, job.q0, job.v0)
    if not est.ok:
        warnings.warn(est.message(dt), VibssWarning, stacklevel=3)
        note += (f"; peaks between samples may read up to {est.error:.1%} low ({est.frequency:.4g} Hz in "
                 f"{est.output!r}; dt <= {est.step:.3g} s bounds it to {PEAK_TOLERANCE:.0%})")
    return note


def _window(dt: Any, t_end: Any, record_from: Any) -> tuple[float, float, float, np.ndarray]:
    """Checked ``dt``, ``t_end`` and ``record_from`` [s], and the sample times ``k dt`` from 0 to
    ``t_end`` (at most :data:`MAX_SAMPLES` of them)."""
    secs = "a number of seconds"
    dt = number(dt, "dt", who="simulate", minimum=0.0, strict=True, what=secs, must="a positive time step [s]")
    t_end = number(t_end, "t_end", who="simulate", minimum=dt, what=secs, must=f"at least dt = {dt:g} s")
    record_from = number(record_from, "record_from", who="simulate", minimum=0.0, what=secs,
                         must=f"in [0, t_end = {t_end:g}] s")
    if record_from > t_end:
        raise ArgumentError(f"simulate: record_from: must lie in [0, t_end = {t_end:g}] s, got {record_from!r}",
                            argument="record_from", received=record_from, expected=f"0 .. {t_end:g} s")
    samples = np.floor(t_end / dt + 1e-9) + 1
    if samples > MAX_SAMPLES:
        raise ModelError(f"simulate: t_end / dt: {t_end:g} s every {dt:g} s is {samples:.3g} samples, "
                         f"more than {MAX_SAMPLES:.0e}; use a larger dt or a shorter t_end")
    return dt, t_end, record_from, dt * np.arange(int(samples))


@dataclass
class _Signals:
    """The input signals of a simulation by name: their terms ``(u(t), breakpoints)``, the source
    each was named by (an Excitation or the name), their sine/cosine pieces (exact in the modal
    path), whether every term is linear once those are removed, whether some term is sampled even
    by the modal path (a plain callable, a sweep), and whether every term is data (samples)."""

    terms: dict[str, Terms]
    sources: dict[str, Any]
    pieces: dict[str, list[Any]]
    exact: dict[str, bool]
    sampled: dict[str, bool]
    data: dict[str, bool]


def _signals(excitations: Sequence[Any], inputs: Mapping[str, SignalInput] | None, ts: np.ndarray) -> _Signals:
    """The excitations and the named ``inputs`` gathered per signal (several on one signal add up)."""
    sig = _Signals({}, {}, {}, {}, {}, {})
    for e in excitations:
        name = getattr(e, "signal", None)
        if name is None:
            raise ModelError(f"simulate: excitations: expected Excitation objects, got {e!r}")
        sig.terms.setdefault(name, []).append((e.function.value, tuple(e.function.breakpoints)))
        sig.sources.setdefault(name, e)
        sig.pieces.setdefault(name, []).extend(e.function.sinusoids)
        sig.exact[name] = sig.exact.get(name, True) and exact_terms(e.function)
        sig.sampled[name] = sig.sampled.get(name, False) or not exact_terms(e.function)
        sig.data[name] = False
    for name, value in (inputs or {}).items():
        sig.terms.setdefault(name, []).append(as_function(value, ts, name))
        sig.sources.setdefault(name, name)
        fn = value if isinstance(value, TimeFunction) else getattr(value, "__self__", None)
        fn = fn if isinstance(fn, TimeFunction) and (fn is value or value == fn.value) else None
        sig.pieces.setdefault(name, []).extend(fn.sinusoids if fn is not None else ())
        sig.exact[name] = sig.exact.get(name, True) and fn is not None and exact_terms(fn)
        samples = not callable(value) and not isinstance(value, TimeFunction)    # data: linear between samples
        sig.sampled[name] = sig.sampled.get(name, False) or not (samples or (fn is not None and exact_terms(fn)))
        sig.data[name] = sig.data.get(name, True) and samples
    return sig


def _plant(model_or_plant: Model | Plant, model: Model | None, sig: _Signals, outputs: Sequence[str] | None,
           initial: Any, method: Any, ts: np.ndarray, dt: float) -> tuple[Plant, Projected | None, bool]:
    """The plant simulated, the large model's projection (or None) and whether its one input is a
    hidden zero force (a free vibration from initial conditions)."""
    if isinstance(model_or_plant, Plant):
        plant = model_or_plant
        if sp.issparse(plant.K):
            raise AnalysisError("simulate: the plant has sparse matrices (build_plant(..., sparse=True)); "
                                "simulate a dense plant, or reduce a large model first (vibss.reduce)")
        unknown = [s for s in sig.terms if s not in plant.inputs]
        if unknown:
            raise ModelError(f"simulate: input(s) {unknown} are not inputs of the plant; its inputs are "
                             f"{list(plant.inputs)}")
        if outputs is not None and tuple(outputs) != plant.outputs:
            plant = _select_outputs(plant, outputs)
        return plant, None, False
    if model is None:
        raise ModelError(f"simulate: model_or_plant: expected a Model or a Plant, got {model_or_plant!r}")
    if stays_sparse(model, method):
        truncated = projected_model(model, list(sig.sources.values()), outputs, initial, sig.terms, ts, dt)
        return truncated.plant, truncated, False
    if sig.sources:
        return build_plant(model, list(sig.sources.values()), outputs), None, False
    # free vibration from initial conditions: a zero force input, internal and not reported
    return build_plant(model, [f"{model.body_names[0]}.fx"], outputs), None, True


def _job(plant: Plant, model: Model | None, sig: _Signals, initial: Any, hidden: bool, ts: np.ndarray,
         rtol: float, atol: float | None, solver: str) -> tuple[SimulationJob, list[Any], str]:
    """The job every method gets, the input functions in the plant's order, and the note on a
    hysteretic damping left out (the job's plant then has none)."""
    funcs = []
    bps: list[float] = []
    for name in plant.inputs:
        terms = sig.terms.get(name, [])
        bps.extend(b for _, bb in terms for b in bb)
        funcs.append(summed(terms))
    q0, v0 = initial_state(plant, initial, model)
    if hidden and not (np.any(q0) or np.any(v0)):
        raise ModelError("simulate: nothing drives the response: no excitations, no inputs and no "
                         "nonzero initial conditions (initial={body: {'displacement': [6], "
                         "'velocity': [6]}})")
    _check_derivatives(plant)
    left_out = dropped_hysteresis(model if model is not None else plant, "simulate", stacklevel=4)  # via _job
    if left_out:                         # said once here; the kernels then see no hysteretic part
        plant = without_hysteresis(plant)
    job = SimulationJob(plant=plant, time=ts, funcs=tuple(funcs), breakpoints=np.array(bps, float),
                        q0=q0, v0=v0, rtol=float(rtol), atol=atol, solver=solver,
                        sinusoids=tuple(tuple(sig.pieces.get(u, ())) for u in plant.inputs),
                        exact_inputs=tuple(u for u in plant.inputs if sig.exact.get(u, u not in sig.terms)))
    return job, funcs, left_out


def _run(job: SimulationJob, chosen: TimeMethod, auto: bool,
         motions: Sequence[str]) -> tuple[np.ndarray, str, TimeMethod]:
    """The method's samples ``(ns, p)``, its note and the method that answered, settled by the one
    decider (:func:`vibss.methods.decide`): ``auto`` falls back (:attr:`TimeMethod.fallback`) when its
    pick refuses the modes or fails its check; a named method is guarded, run and checked (a miss
    warns with the measured bound, which the note carries)."""
    plant = job.plant
    order = [chosen] + ([METHODS[chosen.fallback]] if auto and chosen.fallback else [])
    others = [m for m in METHODS.values() if m is not chosen and not (m.forces_only and motions)
              and (m.internal_states or plant.branches is None)
              and not getattr(m, "nonlinear", False)]          # a nonlinear method takes a Model, not this job

    def run(method: Method) -> tuple[np.ndarray, str]:
        y, note = method.kernel(job)
        y = np.asarray(y, float)
        if y.shape != (job.time.size, len(plant.outputs)):
            raise AnalysisError(f"simulate: method {method.name!r} returned shape {y.shape}, expected "
                                f"{(job.time.size, len(plant.outputs))}")
        return y, str(note)

    def check(method: Method, answer: tuple[np.ndarray, str]) -> Check | None:
        checker = getattr(method, "checker", None)
        return checker(job, answer[0]) if checker is not None else None

    def cost(method: Method) -> Cost | None:
        coster = getattr(method, "coster", None)
        return coster(job) if coster is not None else None

    try:
        d = decide(order, run, where="simulate", auto=auto, check=check, cost=cost,
                   refusals=(DefectiveModesError,), others=others)
    except DefectiveModesError as exc:
        names = [m.name for m in others]
        raise DefectiveModesError(f"simulate: method {chosen.name!r} refused: {exc}; use one of the "
                                  f"methods simulate accepts: {names} (or 'auto')", argument="method",
                                  received=chosen.name, expected=names) from None
    y, note = d.answer
    if len(d.attempts) > 1:           # "modal refused (...); forced_response: ..." (what auto tried first)
        note = "; ".join(a.text() for a in d.attempts[:-1]) + f"; {d.method.name}: " + note
    if d.check is not None:
        note = f"{note}; {d.check.text()}"
    return y, note, cast(TimeMethod, d.method)


def _prefixed(note: str, *, hidden: bool, left_out: str, causal_note: str, branch_note: str,
              skipped: tuple[Any, ...]) -> str:
    """The method's note after what the driver did before it ran (innermost last)."""
    if hidden:
        note = "free vibration from the initial conditions; " + note
    if left_out:
        note = f"{left_out}; " + note
    if causal_note:
        note = f"{causal_note}; " + note
    if branch_note:
        note = f"{branch_note}; " + note
    if skipped:
        note = (f"skipped steady sweep(s) {[e.name for e in skipped]} (sweep_time = 0: frequency "
                "studies only); " + note)
    return note


MAX_SAMPLES = 5e7
"""Most samples ``t_end / dt + 1`` that :func:`simulate` accepts (each output row is stored)."""

SOLVERS = ("RK23", "RK45", "DOP853", "Radau", "BDF", "LSODA")
"""``solve_ivp`` methods accepted as ``solver``."""


def _tolerances(rtol: Any, atol: Any, solver: Any) -> tuple[float, float | None, str]:
    """Checked ``rtol`` (> 0), ``atol`` (None or >= 0) and ``solver`` (a solve_ivp method)."""
    r = number(rtol, "rtol", who="simulate", minimum=0.0, strict=True, what="a positive relative tolerance")
    a = None if atol is None else number(atol, "atol", who="simulate", minimum=0.0,
                                         what="None or an absolute tolerance >= 0")
    choice(solver, "solver", SOLVERS, who="simulate", expected=f"one of {list(SOLVERS)}")
    return r, a, str(solver)


def _check_derivatives(plant: Plant) -> None:
    """Refuse an output that needs the second derivative of a prescribed displacement.

    A piecewise-linear displacement has an impulsive second derivative (a delta at every kink), so
    such an output (the acceleration of the prescribed DOF itself, or of a body mass-coupled to it)
    cannot be sampled; its first derivative (piecewise constant) and the second derivative of a
    velocity input are representable and are kept.
    """
    disp = [j for j, k in enumerate(plant.kinds) if k == "displacement"]
    if not disp:
        return
    M = np.asarray(plant.M, float)
    Mz = np.asarray(plant.Mz, float)[:, disp]
    Oa = np.asarray(plant.Oa, float)
    try:
        G = np.linalg.solve(M, Mz) if plant.n else np.zeros((0, len(disp)))
    except np.linalg.LinAlgError:
        return   # the methods refuse a singular mass matrix themselves
    d2 = np.asarray(plant.Pa, float)[:, disp] - Oa @ G
    scale = np.abs(np.asarray(plant.Pa, float)[:, disp]) + np.abs(Oa) @ np.abs(G)
    bad = (np.abs(d2) > 1e-8 * scale) & (scale > 0)
    if np.any(bad):
        i, jj = map(int, np.argwhere(bad)[0])
        u = plant.inputs[disp[jj]]
        acc = u[:-len(".disp")] + ".acc" if u.endswith(".disp") else "an acceleration input"
        raise AnalysisError(
            f"simulate: output {plant.outputs[i]!r} depends on the second derivative of input {u!r} "
            f"(displacement), which is impulsive for a piecewise-linear displacement (a delta at "
            f"every kink). Prescribe the same motion as an acceleration input ({acc}), or drop "
            f"the output")


def _select_outputs(plant: Plant, outputs: Sequence[str]) -> Plant:
    for o in outputs:
        if o not in plant.outputs:
            raise ModelError(f"simulate: outputs: {o!r} is not an output of the plant; outputs are "
                             f"{list(plant.outputs)}")
    return plant.select(outputs=list(outputs))
