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

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any, cast
import warnings

import numpy as np
import scipy.sparse as sp
import numpy.typing as npt

from .._validate import choice, name_index, number, vector
from ..errors import AnalysisError, ArgumentError, DefectiveModesError, ModelError, VibssWarning
from ..results import ReadOnly, Result, TextTable as Table, jsonable, require_pandas
from .branched import suits as branch_path
from .methods import METHODS, SimulationJob, TimeMethod, resolve_method
from ..model.model import DOF_NAMES, Model
from ..model.timefunctions import TimeFunction
from ..linear.plant.branches import require_none
from ..linear.plant.hysteresis import dropped_hysteresis
from ..linear.plant.plant import Plant
from ..linear.plant.signals import build_plant
from ..linear.solve.exact import without_hysteresis
from .large import Projected, WARN_ERROR, projected_plant
from ..studies import causal_loss_fit, steady_sweeps, transient_excitations
from ..diagnostics import check_excitations, check_explicit_rk

EXPLICIT_RK = ("RK23", "RK45", "DOP853")


__all__ = ["simulate", "TimeResponse", "PeakTable", "SimulationJob", "TimeMethod", "METHODS"]

SignalInput = Callable[[np.ndarray], np.ndarray] | npt.ArrayLike


@dataclass(frozen=True, eq=False)
class PeakTable(ReadOnly):
    """Peak (largest magnitude) value, its time, and RMS of each output.

    Attributes
    ----------
    outputs : tuple of str
        Output names (p).
    units : tuple of str
        SI unit per output.
    value : (p,) ndarray
        Signed value at the peak of ``|y|``.
    time : (p,) ndarray
        Time of the peak [s].
    rms : (p,) ndarray
        Root mean square over the recorded samples.
    """

    outputs: tuple[str, ...]
    units: tuple[str, ...]
    value: np.ndarray
    time: np.ndarray
    rms: np.ndarray

    def to_pandas(self) -> Any:
        """DataFrame indexed by output, columns peak, time, rms, unit."""
        pd = require_pandas()

        return pd.DataFrame({"peak": self.value, "time": self.time, "rms": self.rms,
                             "unit": self.units}, index=list(self.outputs))


@dataclass(frozen=True, eq=False)
class TimeResponse(Result):
    """A simulated time response.

    Follows the result protocol (:mod:`vibss.results`): ``r['b.z']`` is the (ns,) samples of one
    output; ``r.control`` is the python-control ``TimeResponseData``; ``output_labels`` /
    ``input_labels`` are python-control's names of ``output_names`` / ``input_names``.

    Attributes
    ----------
    time : (ns,) ndarray
        Sample times [s] (from ``record_from``).
    outputs : (p, ns) ndarray
        Output values (SI, unit per output in ``units``).
    output_names : tuple of str
        Output signal names, e.g. ``'engine.z'``, ``'sensor.x'``, ``'mount.front.fz'``.
    units : tuple of str
        SI unit per output.
    inputs : (m, ns) ndarray
        Input signals at the samples.
    input_names : tuple of str
        Input signal names, e.g. ``'engine.fz'``, ``'ground.z.acc'``.
    method : str
        The method that ran.
    note : str
        How it ran (and, for ``auto``, why).
    name : str
        System name.
    """

    time: np.ndarray
    outputs: np.ndarray
    output_names: tuple[str, ...]
    units: tuple[str, ...]
    inputs: np.ndarray
    input_names: tuple[str, ...]
    method: str
    note: str
    name: str = "vibss"

    @property
    def output_labels(self) -> tuple[str, ...]:
        """Output signal names (python-control's name; ``output_names`` is the same)."""
        return self.output_names

    @property
    def input_labels(self) -> tuple[str, ...]:
        """Input signal names (python-control's name; ``input_names`` is the same)."""
        return self.input_names

    def _item(self, i: int, j: int | None) -> np.ndarray:
        if j is not None:
            raise ArgumentError(f"TimeResponse[{self.output_names[i]!r}, {self.input_names[j]!r}]: a time "
                                "response is the sum over its inputs; index by output only",
                                argument="key", received=(self.output_names[i], self.input_names[j]))
        return self.outputs[i]

    @property
    def control(self) -> Any:
        """The same response as a python-control :class:`control.TimeResponseData`."""
        from control import TimeResponseData

        return TimeResponseData(
            self.time, self.outputs, None, self.inputs if self.inputs.size else None,
            output_labels=list(self.output_names),
            input_labels=list(self.input_names) if self.inputs.size else None, sysname=self.name)

    data = control
    """Old name of :attr:`control`."""

    def output(self, name: str) -> np.ndarray:
        """(ns,) samples of output ``name``."""
        return self.outputs[name_index(name, self.output_names, "output", who="TimeResponse.output")]

    def peaks(self) -> PeakTable:
        """Peak value (largest magnitude, signed), its time, and RMS of every output."""
        if self.time.size == 0:
            z = np.zeros(len(self.output_names))
            return PeakTable(self.output_names, self.units, z, z, z)
        i = np.argmax(np.abs(self.outputs), axis=1)
        rows = np.arange(len(i))
        return PeakTable(self.output_names, self.units, self.outputs[rows, i], self.time[i],
                         np.sqrt(np.mean(self.outputs**2, axis=1)))

    def in_g(self) -> TimeResponse:
        """The same response with translational accelerations (outputs in m/s^2) in g
        (standard gravity, 9.80665 m/s^2): for tables and figures of shock studies."""
        from ..model.units import STANDARD_GRAVITY

        acc = np.array([u == "m/s^2" for u in self.units])
        if not acc.any():
            return self
        outputs = np.where(acc[:, None], self.outputs / STANDARD_GRAVITY, self.outputs)
        return replace(self, outputs=outputs, units=tuple("g" if a else u for a, u in zip(acc, self.units)))

    def negligible(self, rel: float = 1e-9) -> tuple[str, ...]:
        """Outputs whose peak is below ``rel`` times the largest peak of their unit (rad counted
        with m, rad/s^2 with m/s^2: rotations of a body of about 1 m): channels the model's symmetry
        leaves at zero, up to rounding (1e-17 m beside a 0.7 m stroke)."""
        return _negligible(self.peaks(), rel)

    def report(self) -> str:
        """Text table: peak value and its time, and RMS, per output (channels left at zero by the
        model's symmetry, :meth:`negligible`, counted below the table rather than listed)."""
        pk = self.peaks()
        width = max([len(n) for n in self.output_names] + [6])
        lines = [f"Time response of {self.name}: {self.time.size} samples"
                 + (f", {self.time[0]:g} .. {self.time[-1]:g} s" if self.time.size else ""),
                 f"method: {self.method} ({self.note})", "",
                 f"{'output':<{width}}  {'peak':>13}  {'at [s]':>10}  {'RMS':>12}  unit"]
        quiet = set(_negligible(pk))
        for n, u, v, t, r in zip(self.output_names, self.units, pk.value, pk.time, pk.rms):
            if n not in quiet:
                lines.append(f"{n:<{width}}  {v:>13.5e}  {t:>10.5f}  {r:>12.5e}  {u}")
        if quiet:
            lines.append(f"({len(quiet)} output{'s' if len(quiet) > 1 else ''} below 1e-9 of the largest of "
                         f"their unit not listed: {', '.join(n for n in self.output_names if n in quiet)})")
        return "\n".join(lines)

    def summary(self) -> Table:
        """Peak value, its time and RMS of every output but the :meth:`negligible` ones."""
        pk = self.peaks()
        quiet = set(_negligible(pk))
        rows = [[n, f"{v:.5e}", f"{t:.5f}", f"{r:.5e}", u]
                for n, u, v, t, r in zip(self.output_names, self.units, pk.value, pk.time, pk.rms) if n not in quiet]
        return Table(["output", "peak", "at [s]", "RMS", "unit"], rows, title=f"method {self.method}"
                     + (f"; {len(quiet)} outputs below 1e-9 of the largest of their unit not listed" if quiet else ""))

    def to_dict(self) -> dict[str, Any]:
        """The spec's JSON: ``{"time": [...], "outputs": {name: [...]}}`` plus units and method."""
        return jsonable({"time": self.time,
                         "outputs": {n: row for n, row in zip(self.output_names, self.outputs)},
                         "units": dict(zip(self.output_names, self.units)),
                         "method": self.method, "note": self.note})

    def to_pandas(self) -> Any:
        """DataFrame with a ``time`` column, one column per output and one per input."""
        pd = require_pandas()

        cols = {"time": self.time}
        cols.update({n: row for n, row in zip(self.output_names, self.outputs)})
        cols.update({n: row for n, row in zip(self.input_names, self.inputs)})
        return pd.DataFrame(cols)

    def plot(self, outputs: Sequence[str] | None = None, by: str = "body", ax: Any = None,
             inputs: bool | None = None) -> Any:
        """Plot outputs against time, peaks marked: :func:`vibss.plotting.plot_time_response`.

        Parameters
        ----------
        outputs : sequence of str or None
            Outputs to draw (default all).
        by : {"body", "all"}
            One axes per body (the name before the first dot) or all in one axes.
        ax : Axes, sequence of Axes or None
            Axes to draw in (one per group); default: a new figure.
        inputs : bool or None
            Draw the inputs on top (default: for prescribed ground motion, in a new figure).

        Returns
        -------
        matplotlib.figure.Figure
        """
        from ..plotting import plot_time_response

        return plot_time_response(self, outputs, by, ax, inputs)


# ----------------------------------------------------------------------------------------------

def _six(body: str, what: str, vec: Any) -> np.ndarray:
    """6 finite numbers (x y z rx ry rz) of one body's initial displacement or velocity."""
    return vector(vec, 6, what, who=f"simulate: initial[{body!r}]", strict=False,
                  what="6 finite numbers (x y z rx ry rz)")


def _initial(plant: Plant, initial: Any, model: Model | None) -> tuple[np.ndarray, np.ndarray]:
    """Initial free-DOF displacement and velocity from per-body data.

    ``initial`` maps a body name to ``{"displacement": [6], "velocity": [6]}`` (either key may be
    left out: zero); anything else (a bare list, a number, an unknown body or key) is refused.
    """
    q0, v0 = np.zeros(plant.n), np.zeros(plant.n)
    if initial is None and model is not None:
        initial = (model.settings or {}).get("initial")
    if initial is None or (isinstance(initial, Mapping) and not initial):
        return q0, v0
    if not isinstance(initial, Mapping):
        raise ModelError(f"simulate: initial: expected {{body: {{'displacement': [6], 'velocity': "
                         f"[6]}}}}, got {initial!r}")
    index = {d: i for i, d in enumerate(plant.dofs)}
    bodies = set(model.body_names) if model is not None else {d.rsplit(".", 1)[0] for d in plant.dofs}
    for body, data in initial.items():
        if body not in bodies:
            raise ModelError(f"simulate: initial: unknown body {body!r}; bodies are {sorted(bodies)}")
        if not isinstance(data, Mapping):
            raise ModelError(f"simulate: initial[{body!r}]: expected {{'displacement': [6 numbers], "
                             f"'velocity': [6 numbers]}} (either key optional), got {data!r}")
        unknown = set(data) - {"displacement", "velocity"}
        if unknown:
            raise ModelError(f"simulate: initial[{body!r}]: unknown key(s) {sorted(map(str, unknown))}; "
                             "expected 'displacement' and/or 'velocity'")
        for target, what in ((q0, "displacement"), (v0, "velocity")):
            if data.get(what) is None:
                continue
            a = _six(body, what, data[what])
            for d, val in zip(DOF_NAMES, a):
                label = f"{body}.{d}"
                if label in index:
                    target[index[label]] = val
                elif val != 0.0:
                    raise ModelError(f"simulate: initial[{body!r}]: {what}: {label!r} is not a free "
                                     f"DOF (it is prescribed by an input)")
    return q0, v0


def _exact_terms(fn: TimeFunction) -> bool:
    """Whether the exact modal path integrates ``fn`` exactly: piecewise linear, or linear once its
    sine/cosine pieces are removed (every term of a sum)."""
    from ..model.timefunctions import Sum, _linear

    if isinstance(fn, Sum):
        return all(_exact_terms(f) for f in fn.terms)
    return _linear(fn) or bool(fn.sinusoids)


def _as_function(value: Any, ts: np.ndarray, name: str) -> tuple[Callable[[np.ndarray], np.ndarray], tuple[float, ...]]:
    if hasattr(value, "value") and hasattr(value, "breakpoints"):
        return value.value, tuple(value.breakpoints)
    if callable(value):
        return value, ()
    a = np.asarray(value, float)
    if a.shape != ts.shape or not np.all(np.isfinite(a)):
        raise ModelError(f"simulate: inputs[{name!r}]: expected a callable u(t) or {ts.size} finite "
                         f"samples (one per dt from 0 to t_end), got shape {a.shape}")
    return cast("Callable[[np.ndarray], np.ndarray]", lambda t, a=a: np.interp(t, ts, a)), ()


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
        The system; a Model is turned into a Plant by :func:`vibss.linear.plant.signals.build_plant`.
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
        Per body ``{"displacement": [6], "velocity": [6]}`` [m, rad, m/s, rad/s] at ``t = 0-``
        (either key may be left out). Default: the model's bodies' ``initial``. With no
        excitations and no inputs, the free vibration from these initial conditions is simulated
        (the result then has no inputs).
    method : {"auto", "modal", "forced_response", "ivp", "newmark", "central_difference"}, TimeMethod or callable
        See the module docstring and :data:`METHODS`; a callable ``f(job) -> (y, note)`` gets the
        :class:`SimulationJob` the built-ins get.
        A :class:`~vibss.errors.VibssWarning` says when the sampling smears a pulse or aliases a
        sweep for the method chosen, or when an explicit ``solver`` meets a stiff model.
    rtol, atol : float, float or None
        Tolerances of ``ivp`` (atol default: 1e-12 of the initial state, or 1e-15).
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
        Bad argument (the message names it), more than :data:`MAX_SAMPLES` samples, or nothing
        driving the response (no excitation, input or initial condition).
    AnalysisError
        A method cannot answer (e.g. solve_ivp failed), or an output needs the second derivative
        of a displacement input (impulsive: prescribe the motion as an acceleration input).

    Warns
    -----
    VibssWarning
        Mounts with a loss factor: it has no causal time-domain form and is left out (named in the
        warning and in ``note``; :func:`vibss.linear.plant.hysteresis.dropped_hysteresis`).
    """
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
    rtol, atol, solver = _tolerances(rtol, atol, solver)
    ns = int(samples)
    ts = dt * np.arange(ns)
    model = model_or_plant if isinstance(model_or_plant, Model) else None
    hysteresis = choice(hysteresis, "hysteresis", ("drop", "causal"), who="simulate")
    causal_note = ""
    if hysteresis == "causal" and model is not None:
        fit = causal_loss_fit(model)
        causal_note, model = fit.note, fit.model
        model_or_plant = model
    hidden = False
    truncated: Projected | None = None
    skipped: tuple[Any, ...] = ()
    if excitations is None and model is not None and inputs is None:
        # the model's time-domain excitations; steady sweeps are frequency studies (vibss.studies)
        excitations, skipped = transient_excitations(model), steady_sweeps(model)
    excitations = list(excitations or [])
    signals: dict[str, list[tuple[Callable[[np.ndarray], np.ndarray], tuple[float, ...]]]] = {}
    sources: dict[str, Any] = {}
    pieces: dict[str, list[Any]] = {}      # sine/cosine pieces per signal (exact in the modal path)
    exact: dict[str, bool] = {}            # whether every term of a signal is linear once they are removed
    for e in excitations:
        sig = getattr(e, "signal", None)
        if sig is None:
            raise ModelError(f"simulate: excitations: expected Excitation objects, got {e!r}")
        signals.setdefault(sig, []).append((e.function.value, tuple(e.function.breakpoints)))
        sources.setdefault(sig, e)
        pieces.setdefault(sig, []).extend(e.function.sinusoids)
        exact[sig] = exact.get(sig, True) and _exact_terms(e.function)
    for name, value in (inputs or {}).items():
        signals.setdefault(name, []).append(_as_function(value, ts, name))
        sources.setdefault(name, name)
        fn = value if isinstance(value, TimeFunction) else getattr(value, "__self__", None)
        fn = fn if isinstance(fn, TimeFunction) and (fn is value or value == fn.value) else None
        pieces.setdefault(name, []).extend(fn.sinusoids if fn is not None else ())
        exact[name] = exact.get(name, True) and fn is not None and _exact_terms(fn)
    if isinstance(model_or_plant, Plant):
        plant = model_or_plant
        if sp.issparse(plant.K):
            raise AnalysisError("simulate: the plant has sparse matrices (build_plant(..., sparse=True)); "
                                "simulate a dense plant, or reduce a large model first (vibss.reduce)")
        unknown = [s for s in signals if s not in plant.inputs]
        if unknown:
            raise ModelError(f"simulate: input(s) {unknown} are not inputs of the plant; its inputs are "
                             f"{list(plant.inputs)}")
        if outputs is not None and tuple(outputs) != plant.outputs:
            plant = _select_outputs(plant, outputs)
    elif model is not None:
        if _stays_sparse(model, method):
            truncated = _truncated(model, list(sources.values()), outputs, initial, signals, ts, dt)
            plant = truncated.plant
        elif sources:
            plant = build_plant(model, list(sources.values()), outputs)
        else:
            # free vibration from initial conditions: a zero force input, internal and not reported
            plant = build_plant(model, [f"{model.body_names[0]}.fx"], outputs)
            hidden = True
    else:
        raise ModelError(f"simulate: model_or_plant: expected a Model or a Plant, got {model_or_plant!r}")
    funcs = []
    bps: list[float] = []
    for name in plant.inputs:
        terms = signals.get(name, [])
        bps.extend(b for _, bb in terms for b in bb)
        funcs.append(_sum(terms))
    q0, v0 = _initial(plant, initial, model)
    if hidden and not (np.any(q0) or np.any(v0)):
        raise ModelError("simulate: nothing drives the response: no excitations, no inputs and no "
                         "nonzero initial conditions (initial={body: {'displacement': [6], "
                         "'velocity': [6]}})")
    _check_derivatives(plant)
    left_out = dropped_hysteresis(model if model is not None else plant, "simulate")
    if left_out:                         # said once here; the kernels then see no hysteretic part
        plant = without_hysteresis(plant)
    job = SimulationJob(plant=plant, time=ts, funcs=tuple(funcs), breakpoints=np.array(bps, float),
                        q0=q0, v0=v0, rtol=float(rtol), atol=atol, solver=solver,
                        sinusoids=tuple(tuple(pieces.get(u, ())) for u in plant.inputs),
                        exact_inputs=tuple(u for u in plant.inputs if exact.get(u, u not in signals)))
    chosen, auto = resolve_method(method)
    if plant.branches is not None and auto:
        structured, why = branch_path(plant)
        if structured:       # the exact modal FOH on modes plus branch states; forced_response if refused
            branch_note = f"{plant.branches.note()}: {why}"
        else:
            chosen, auto = METHODS["forced_response"], False
            branch_note = f"{plant.branches.note()}: forced_response of the state space with them ({why})"
    elif plant.branches is not None:
        branch_note = plant.branches.note()
        if not chosen.internal_states:
            require_none(plant, f"simulate: method {chosen.name!r}",
                         f"use one of {[k for k, v in METHODS.items() if v.internal_states]} or 'auto'")
    else:
        branch_note = ""
    motions = [u for u, kind in zip(plant.inputs, plant.kinds) if kind != "force"]
    if chosen.forces_only and motions:
        raise ModelError(f"simulate: method {chosen.name!r} takes only force inputs; inputs {motions} "
                         "are prescribed motions (use method='modal')")
    for finding in check_excitations(excitations, dt, inserts_breakpoints=chosen.hits_edges):
        finding.warn(stacklevel=3)
    if chosen.uses_solver and solver in EXPLICIT_RK:
        check_explicit_rk(plant.M, plant.K, t_end, rtol=rtol, solver=solver, C=plant.C).warn(stacklevel=3)
    try:
        y, note = chosen.kernel(job)
    except DefectiveModesError as exc:
        if not auto or chosen.fallback is None:
            others = [n for n, m in METHODS.items() if m is not chosen and not (m.forces_only and motions)
                      and (m.internal_states or plant.branches is None)]
            raise DefectiveModesError(f"simulate: method {chosen.name!r} refused: {exc}; use one of the "
                                      f"methods simulate accepts: {others} (or 'auto')", argument="method",
                                      received=chosen.name, expected=others) from None
        refused, chosen = chosen, METHODS[chosen.fallback]
        y, note = chosen.kernel(job)
        note = f"{refused.name} refused ({exc}); {chosen.name}: " + note
    name = chosen.name
    y = np.asarray(y, float)
    if y.shape != (ns, len(plant.outputs)):
        raise AnalysisError(f"simulate: method {name!r} returned shape {y.shape}, expected {(ns, len(plant.outputs))}")
    if auto:
        note = f"auto -> {name}: " + (f"{chosen.auto_reason}; " if chosen.auto_reason else "") + note
    if truncated is not None:
        note = f"{_truncation_note(truncated, y)}; " + note
    keep = ts >= record_from - 1e-9 * dt
    shown = [] if hidden else funcs
    u = np.array([np.broadcast_to(f(ts[keep]), (int(keep.sum()),)) for f in shown]).reshape(len(shown), int(keep.sum()))
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
    return TimeResponse(time=ts[keep], outputs=y[keep].T.copy(), output_names=tuple(plant.outputs),
                        units=tuple(plant.units), inputs=u,
                        input_names=() if hidden else tuple(plant.inputs),
                        method=name, note=note, name=plant.name)


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


def _sum(terms: list[tuple[Callable[[np.ndarray], np.ndarray], tuple[float, ...]]]) -> Callable[[np.ndarray], np.ndarray]:
    if not terms:
        return lambda t: np.zeros(np.shape(t))
    if len(terms) == 1:
        return terms[0][0]
    fns = [f for f, _ in terms]
    return cast("Callable[[np.ndarray], np.ndarray]", lambda t: sum(np.asarray(f(t), float) for f in fns))


LARGE_DOFS = 6000
"""Above this many DOFs ``simulate(model, method="auto")`` keeps the model sparse and projects it on
a subspace built for its inputs and outputs, with an error estimate (:mod:`vibss.time.large`); at or
below it every mode is computed densely and the answer is exact (65–196 s at 6,000 DOF, by the load
on the machine). Twice the frequency response's threshold (:data:`vibss.frequency.api.LARGE_DOFS`)."""


def _stays_sparse(model: Model, method: Any) -> bool:
    """Whether :func:`simulate` keeps ``model`` sparse (:mod:`vibss.time.large`): above
    :data:`LARGE_DOFS` DOFs with ``method="auto"``, and no branch mounts."""
    return (isinstance(method, str) and method == "auto" and 6 * len(model.bodies) > LARGE_DOFS
            and not any(t.has_branches for t in model.mount_types.values()))


def _truncated(model: Model, sources: list[Any], outputs: Sequence[str] | None, initial: Any,
               signals: Mapping[str, Any], ts: np.ndarray, dt: float) -> Projected:
    """The large model's sparse plant projected on a subspace built for its channels (:mod:`vibss.time.large`)."""
    if not sources:
        raise AnalysisError(f"simulate: a free vibration of {6 * len(model.bodies)} DOFs (above "
                            f"{LARGE_DOFS}) from initial conditions alone: the large-model path needs an "
                            "input to build its subspace; give method='modal' (every mode, dense) instead")
    full = build_plant(model, sources, outputs, sparse=True)
    q0, v0 = _initial(full, initial, model)
    if np.any(q0) or np.any(v0):
        raise AnalysisError(f"simulate: initial: nonzero initial conditions on a model of {full.n} DOFs "
                            f"(above {LARGE_DOFS}, kept sparse and projected) do not map to the "
                            "reduced coordinates exactly; give method='modal' (every mode, dense) instead")
    samples = np.array([np.broadcast_to(_sum(signals.get(u, []))(ts), ts.shape) for u in full.inputs])
    return projected_plant(full, samples.reshape(len(full.inputs), ts.size), dt)


def _truncation_note(tr: Projected, y: np.ndarray) -> str:
    """What the large-model path kept and its error estimate; warns above
    :data:`~vibss.time.large.WARN_ERROR`."""
    worst = float(tr.estimate(y).max(initial=0.0))
    text = (f"{tr.describe()}; estimated error {worst:.2g} of each output's peak ((1/pi) int |dH| |U| dw "
            "with |dH| from the checks: an estimate from sampled checks, not a bound)")
    if not worst <= WARN_ERROR:
        warnings.warn(VibssWarning(f"simulate: {text}: above {WARN_ERROR:g} (method='modal' computes every "
                                   "mode, dense)"), stacklevel=3)
    return text


def _select_outputs(plant: Plant, outputs: Sequence[str]) -> Plant:
    for o in outputs:
        if o not in plant.outputs:
            raise ModelError(f"simulate: outputs: {o!r} is not an output of the plant; outputs are "
                             f"{list(plant.outputs)}")
    return plant.select(outputs=list(outputs))


def _negligible(pk: PeakTable, rel: float = 1e-9) -> tuple[str, ...]:
    """:meth:`TimeResponse.negligible` from a peak table already computed."""
    family = [u.replace("rad", "m") for u in pk.units]
    largest: dict[str, float] = {}
    for u, v in zip(family, pk.value):
        largest[u] = max(largest.get(u, 0.0), abs(float(v)))
    return tuple(n for n, u, v in zip(pk.outputs, family, pk.value) if not abs(v) > rel * largest[u])
