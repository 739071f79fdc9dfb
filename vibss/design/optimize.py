"""Optimization of a mount layout with the exact gradients of :mod:`vibss.design.sensitivity`.

The design variables (:class:`~vibss.design.parameters.Parameter`: rates [N/m] absolute, shifts [m]
and angles [rad] from the given model) are scaled to ``[0, 1]`` inside their bounds. The objective
maximizes the mean purity (largest KE fraction, full M, in the chosen frame) of the selected modes;
constraints keep each mode's frequency in its window and, optionally, each selected mode's purity
above a target and the sag under weight below a limit. An optimizer of :data:`vibss.design.methods.METHODS`
(scipy's SLSQP or trust-constr, or a global search first) runs from the given layout and from
``starts - 1`` Latin-hypercube points; the best feasible result wins.

The steps, each a function: :func:`_design_variables` (parameters and bounds),
:func:`_catalogue` (discrete rates), :func:`_problem` (objective and constraints on the unit box),
:func:`_search` (the optimizer from every start), :func:`_snap_to_catalogue` (catalogue values, then
the rest again).

The purity is a maximum over coordinates, so it is smooth only while the dominant coordinate of a
mode stays the same; the exact gradient is that of the dominant entry.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, ClassVar

import numpy as np
from scipy.stats import qmc

from .._validate import array, choice, integer
from .._deprecated import module_aliases
from ..errors import AnalysisError, ArgumentError, VibssError, did_you_mean
from ..io.modelfile import dump_model
from ..model.model import DOF_NAMES, Model
from ..results import Result, TextTable, jsonable, require_pandas
from .certificate import Certificate, certificate, windows_for
from .methods import METHODS, Optimizer, Problem, differential_evolution, penalized, resolve_method
from .parameters import Parameter, apply, current_values, parameters_of
from .sensitivity import Sensitivity, evaluate

__all__ = ["Optimization", "optimize", "METHODS", "GRADIENTS", "benchmark_case"]

GRADIENTS = ("exact", "finite-difference")


@dataclass(frozen=True, eq=False)
class Optimization(Result):
    """An optimized layout, with the certificates before and after.

    Attributes
    ----------
    model : Model
        The optimized model.
    base : Model
        The model optimized from.
    variables : tuple of str
        Design variable names.
    units : tuple of str
        Their units.
    bounds : (p, 2) ndarray
        Their bounds.
    x0 : (p,) ndarray
        Initial values.
    x : (p,) ndarray
        Optimized values.
    objective : float
        Mean purity of the selected modes at the optimum [-].
    before, after : Certificate
        Certificates of the base and the optimized layout.
    success : bool
        The optimizer converged to a feasible point.
    message : str
        The optimizer's message.
    evaluations : int
        Modal evaluations (each gives values and gradients).
    starts : int
        Starting points tried.
    method : str
        The optimizer (``SLSQP``, ``trust-constr``, ``differential evolution + SLSQP`` ...), with the
        gradient kind.
    note : str
        What was optimized.
    reliability : Reliability or None
        For a reliability-based optimization (``tolerances=``): margins, their iterations and the
        Monte Carlo check of the deterministic and the reliable optimum.
    """

    signal_kind: ClassVar[str] = "variable"

    model: Model
    base: Model
    variables: tuple[str, ...]
    units: tuple[str, ...]
    bounds: np.ndarray
    x0: np.ndarray
    x: np.ndarray
    objective: float
    before: Certificate
    after: Certificate
    success: bool
    message: str
    evaluations: int
    starts: int
    method: str
    note: str = ""
    reliability: Any = None

    @property
    def output_labels(self) -> tuple[str, ...]:
        """The design variables: ``opt['engine.k3']`` is its optimized value."""
        return self.variables

    def _item(self, i: int, j: int | None) -> float:
        return float(self.x[i])

    def summary(self) -> TextTable:
        """Design variables: bounds, initial and optimized values."""
        rows = [[v, u, f"{lo:.4g}", f"{hi:.4g}", f"{a:.5g}", f"{b:.5g}"]
                for v, u, (lo, hi), a, b in zip(self.variables, self.units, self.bounds, self.x0, self.x)]
        return TextTable(["variable", "unit", "lower", "upper", "before", "after"], rows,
                     title="Design variables (shifts and angles from the base layout)")

    def comparison(self) -> TextTable:
        """Per mode: frequency and purity before and after."""
        b, a = self.before, self.after
        rows = [[f"{k + 1}", f"{b.frequency_hz[k]:.3f}", f"{100 * b.purity[k]:.1f} {b.dominant[k]}",
                 f"{a.frequency_hz[k]:.3f}", f"{100 * a.purity[k]:.1f} {a.dominant[k]}",
                 "yes" if a.in_window[k] else "NO"] for k in range(len(a.purity))]
        return TextTable(["mode", "f before [Hz]", "purity before [%]", "f after [Hz]", "purity after [%]",
                      "in window"], rows, title=f"Before and after ({a.frame_name} frame)")

    def report(self) -> str:
        """Text: verdict, variables, before/after table and both certificates' verdicts."""
        head = (f"Optimised layout of {self.base.name!r}: {'converged' if self.success else 'NOT converged'} "
                f"({self.message}); mean purity {self.objective:.4f}; {self.evaluations} evaluations, "
                f"{self.starts} start(s), {self.method}")
        return "\n\n".join([head, self.summary().render(), self.comparison().render(),
                            "before: " + self.before.report().split("\n", 1)[0],
                            "after:  " + self.after.report().split("\n", 1)[0], self.note]
                           + ([self.reliability.table().render()] if self.reliability is not None else []))

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready variables, objective and both certificates."""
        return jsonable({"model": self.base.name, "variables": list(self.variables), "units": list(self.units),
                         "bounds": self.bounds, "x0": self.x0, "x": self.x, "objective": self.objective,
                         "success": self.success, "message": self.message, "evaluations": self.evaluations,
                         "starts": self.starts, "before": self.before.to_dict(), "after": self.after.to_dict(),
                         "method": self.method, "note": self.note,
                         "reliability": None if self.reliability is None else {
                             "beta": self.reliability.beta, "iterations": self.reliability.iterations,
                             "margins": self.reliability.margins,
                             "probability_deterministic": self.reliability.deterministic.probability,
                             "probability": self.reliability.reliable.probability}})

    def to_pandas(self) -> Any:
        """DataFrame: one row per design variable."""
        pd = require_pandas()
        df = pd.DataFrame({"unit": list(self.units), "lower": self.bounds[:, 0], "upper": self.bounds[:, 1],
                           "before": self.x0, "after": self.x}, index=pd.Index(list(self.variables), name="variable"))
        df.attrs["units"] = {"by row": dict(zip(self.variables, self.units))}     # each variable in its own unit
        return df

    def plot(self, ax: Any = None, **kwargs: Any) -> Any:
        """Purity per mode before and after: :func:`vibss.plotting.design.plot_optimization`.

        Parameters
        ----------
        ax : Axes or None
            Draw into existing axes; default: a new figure.
        **kwargs
            Passed to :func:`vibss.plotting.design.plot_optimization`.

        Returns
        -------
        matplotlib.figure.Figure
        """
        from ..plotting.design import plot_optimization

        return plot_optimization(self, ax=ax, **kwargs)

    def write(self, path: str | Path) -> None:
        """Write the optimized model as a model file (``.toml`` or ``.json``).

        Parameters
        ----------
        path : str or Path
            The file.
        """
        dump_model(self.model, path)


def _select(modes: Any, k: int) -> Any:
    """Mode selector: None (all), 1-based numbers, or DOF names (x ... rz) of the dominant coordinate."""
    if modes is None:
        return None
    items = [modes] if isinstance(modes, (str, int)) else list(modes)
    for m in items:
        if isinstance(m, str) and m not in DOF_NAMES or not isinstance(m, str) and not 1 <= int(m) <= k:
            raise ArgumentError(f"optimize: modes: expected mode numbers 1 ... {k} or directions "
                                f"{list(DOF_NAMES)}, got {m!r}", argument="modes", received=modes)
    return items


def _chosen(items: Any, sens: Sensitivity) -> np.ndarray:
    k = len(sens.frequency_hz)
    if items is None:
        return np.arange(k)
    dom = [DOF_NAMES[j % 6] for j in np.argmax(sens.ke_matrix, axis=1)]
    rows = {int(m) - 1 for m in items if not isinstance(m, str)}
    rows |= {i for i, d in enumerate(dom) if d in {m for m in items if isinstance(m, str)}}
    return np.array(sorted(rows), dtype=int)


def optimize(model: Model, variables: Mapping[Any, Any], *, modes: Any = None, purity: float | None = None,
             windows: Any = None, max_sag: float | None = None, frame: Any = "global", axis: Any = "x",
             body: str | None = None, method: Any = "SLSQP", gradient: str = "exact", starts: int = 1,
             seed: int | None = 0, maxiter: int = 200,
             catalogue: Mapping[Any, Any] | None = None, tolerances: Mapping[Any, float] | None = None,
             beta: float = 2.0, samples: int = 10_000, margins: Mapping[str, Any] | None = None) -> Optimization:
    """Optimize a mount layout for decoupling within frequency windows, with exact gradients.

    Parameters
    ----------
    model : Model
        The layout to start from (shifts and angles are measured from it).
    variables : mapping of str or Parameter to (2,) array_like
        Design variable (``"<mount>.<kind>"`` or a tied :class:`~vibss.design.parameters.Parameter`)
        to its bounds ``(lower, upper)``: rates [N/m] (positive), shifts [m], angles [rad].
    modes : sequence of int or str, or None
        Modes whose mean purity is maximized: 1-based numbers, or DOF names (``"rx"``: modes whose
        dominant coordinate is a roll); None: all.
    purity : float or None
        Constraint: every selected mode at least this pure [-]; None: none.
    windows : (2,) array_like, mapping or None
        Frequency windows [Hz] as constraints (as :func:`~vibss.design.certificate`, directions from
        the base layout's modes).
    max_sag : float or None
        Constraint: vertical sag of the COG under weight at most this [m]; None: none.
    frame : {"global", "tra", "principal"} or (3, 3) array_like
        Axes of the KE fractions.
    axis : {"x", "y", "z"} or (3,) array_like
        Crank axis (for ``frame="tra"``).
    body : str or None
        Body whose inertia defines the frame (None: the only or first body).
    method : {"SLSQP", "trust-constr", "global"}, Optimizer or callable
        An optimizer of :data:`vibss.design.methods.METHODS`; ``"global"``:
        :func:`scipy.optimize.differential_evolution` on the objective with a quadratic penalty for
        the constraints (seeded, ``15 x p`` members, the given layout among them), then SLSQP with
        the exact gradients from its best point. A callable has the registry's kernel signature.
    gradient : {"exact", "finite-difference"}
        Exact gradients, or scipy's finite differences (for comparison).
    starts : int
        Starting points: the given layout plus ``starts - 1`` Latin-hypercube points.
    seed : int or None
        Seed of the extra starting points.
    maxiter : int
        Iterations per start.
    catalogue : mapping of str or Parameter to sequence of float, or None
        Discrete choices for some variables (catalogue rates [N/m]): after the continuous optimum,
        each takes the better of its two neighbouring catalogue values (greedily, one after the
        other) and the remaining variables are optimized again.
    tolerances : mapping or None
        Reliability-based optimization: parameter (``"<mount>.<kind>"`` or tied) to its production
        tolerance, uniform ``±tol`` (relative for rates and ratios, absolute [m, rad] otherwise).
        The window and purity constraints then hold with a margin of ``beta`` standard deviations,
        the deviations from the exact sensitivities at the optimum (first-order second-moment),
        shifted and re-optimized until the margins settle (sequential optimization and reliability
        assessment); a Monte Carlo study of ``samples`` variants checks the result
        (:attr:`Optimization.reliability`). Needs ``purity`` or ``windows``.
    beta : float
        Reliability index of the margins (2: about 98 % of variants per constraint if normal).
    samples : int
        Variants of the Monte Carlo check.
    margins : mapping or None
        Constraint margins per mode (used by the reliability loop): ``"lower"``, ``"upper"`` [Hz]
        and ``"purity"`` [-], arrays over the modes; None: none.

    Returns
    -------
    Optimization

    Examples
    --------
    >>> import vibss
    >>> pt = vibss.load_example("powertrain")
    >>> opt = optimize(pt, {"torque-strut.k1": (5e4, 2e5), "gearbox.k3": (1e5, 3e5)}, modes=[3, 6])
    >>> bool(opt.after.purity[[2, 5]].mean() > opt.before.purity[[2, 5]].mean())
    True
    """
    who = "optimize"
    if tolerances is not None:
        from .reliability import reliable_optimize

        return reliable_optimize(model, variables, tolerances, beta=beta, samples=samples, modes=modes,
                                 purity=purity, windows=windows, max_sag=max_sag, frame=frame, axis=axis,
                                 body=body, method=method, gradient=gradient, starts=starts, seed=seed,
                                 maxiter=maxiter, catalogue=catalogue)
    params, bounds = _design_variables(model, variables, who)
    optimizer = resolve_method(method)
    gradient = choice(gradient, "gradient", GRADIENTS, who=who)
    starts = integer(starts, "starts", who=who)
    maxiter = integer(maxiter, "maxiter", who=who)
    x0 = current_values(model, params)
    cat = _catalogue(catalogue, [p.name for p in params], bounds, who)
    before = certificate(model, body, purity=0.9 if purity is None else purity, windows=windows, frame=frame, axis=axis)
    items = _select(modes, len(before.frequency_hz))
    problem, evaluations = _problem(model, params, bounds, before, items, windows, purity, max_sag, margins,
                                    body, frame, axis, exact=gradient == "exact", who=who)
    lo, span = bounds[:, 0], bounds[:, 1] - bounds[:, 0]
    z_start = [np.clip((x0 - lo) / span, 0.0, 1.0)]
    label = optimizer.label or optimizer.name
    if optimizer.global_search:
        z_start = [differential_evolution(problem, z_start[0], seed, maxiter)]
    if starts > 1:
        z_start += list(qmc.LatinHypercube(len(params), seed=seed).random(starts - 1))
    best = _search(optimizer, problem, z_start, [(0.0, 1.0)] * len(params), maxiter, who)
    if cat:
        best = _snap_to_catalogue(optimizer, problem, best, cat, lo, span, maxiter, who)
        label += " with catalogue rates"
    (feasible, _), r = best
    x = lo + span * np.clip(r.x, 0.0, 1.0)
    optimum = apply(model, params, x)
    after = certificate(optimum, body, purity=0.9 if purity is None else purity, windows=windows, frame=frame, axis=axis)
    return Optimization(model=optimum, base=model, variables=tuple(p.name for p in params),
                        units=tuple(p.unit for p in params), bounds=bounds, x0=x0, x=x,
                        objective=-float(r.fun), before=before, after=after,
                        success=bool(r.success) and feasible, message=str(r.message),
                        evaluations=evaluations[0], starts=len(z_start), method=f"{label}, {gradient} gradients",
                        note=f"maximised the mean purity of modes {items or 'all'} in the {before.frame_name} frame")


def _design_variables(model: Model, variables: Mapping[Any, Any], who: str) -> tuple[tuple[Parameter, ...], np.ndarray]:
    """The validated parameters and their ``(p, 2)`` bounds [N/m, m, rad]."""
    if not isinstance(variables, Mapping) or not variables:
        raise ArgumentError(f"{who}: variables: expected a mapping of parameter to (lower, upper), got "
                            f"{variables!r}", argument="variables", received=variables)
    params = parameters_of(model, list(variables))
    bounds = np.array([array(b, f"variables[{getattr(k, 'name', k)!r}]", (2,), who=who)
                       for k, b in variables.items()])
    for p, (lo, hi) in zip(params, bounds):
        if not lo < hi or (p.is_rate and lo <= 0):
            raise ArgumentError(f"{who}: variables[{p.name!r}]: bounds must satisfy lower < upper "
                                f"(rates: 0 < lower), got {[lo, hi]}", argument="variables", received=[lo, hi])
    return params, bounds


def _catalogue(catalogue: Mapping[Any, Any] | None, names: list[str], bounds: np.ndarray,
               who: str) -> dict[int, np.ndarray]:
    """Variable index to its sorted catalogue values inside its bounds."""
    cat: dict[int, np.ndarray] = {}
    for key, values in (catalogue or {}).items():
        name = key.name if isinstance(key, Parameter) else str(key)
        if name not in names:
            raise ArgumentError(f"{who}: catalogue: {name!r} is not a design variable; variables are {names}"
                                + did_you_mean(name, names), argument="catalogue", received=name)
        i = names.index(name)
        v = np.sort(array(values, f"catalogue[{name!r}]", (None,), who=who))
        v = v[(v >= bounds[i, 0]) & (v <= bounds[i, 1])]
        if not v.size:
            raise ArgumentError(f"{who}: catalogue[{name!r}]: no value inside the bounds {bounds[i].tolist()}",
                                argument="catalogue", received=values)
        cat[i] = v
    return cat


def _problem(model: Model, params: tuple[Parameter, ...], bounds: np.ndarray, before: Certificate, items: Any,
             windows: Any, purity: float | None, max_sag: float | None, margins: Mapping[str, Any] | None,
             body: str | None, frame: Any, axis: Any, *, exact: bool, who: str) -> tuple[Problem, list[int]]:
    """The objective (minus the mean purity of the chosen modes) and the window, purity and sag
    constraints on the unit box, with their exact gradients (or scipy's finite differences); and
    the count of modal evaluations, updated as the optimizer runs."""
    k = len(before.frequency_hz)
    dirs = [DOF_NAMES[j % 6] for j in np.argmax(before.ke_matrix, axis=1)]
    win = windows_for(windows, dirs, who)
    lo, span = bounds[:, 0], bounds[:, 1] - bounds[:, 0]
    cache: dict[bytes, Sensitivity] = {}
    count = [0]

    def at(z: np.ndarray) -> Sensitivity:
        key = np.asarray(z, float).tobytes()
        if key not in cache:
            if len(cache) > 64:
                cache.clear()
            count[0] += 1
            cache[key] = evaluate(model, params, lo + span * z, body=body, frame=frame, axis=axis)
        return cache[key]

    def fun(z: np.ndarray) -> float:
        s = at(z)
        return -float(np.mean(s.purity[_chosen(items, s)]))

    def jac(z: np.ndarray) -> np.ndarray:
        s = at(z)
        return -np.mean(s.d_purity[_chosen(items, s)], axis=0) * span

    cons_f, cons_j = [], []
    lower_w, upper_w = np.isfinite(win[:, 0]) & (win[:, 0] > 0), np.isfinite(win[:, 1])
    m_lo, m_hi, m_p = (np.zeros(k) + np.asarray((margins or {}).get(key, 0.0), dtype=float)
                       for key in ("lower", "upper", "purity"))
    if lower_w.any() or upper_w.any():
        cons_f.append(lambda z: np.concatenate([(at(z).frequency_hz - win[:, 0] - m_lo)[lower_w],
                                                (win[:, 1] - at(z).frequency_hz - m_hi)[upper_w]]))
        cons_j.append(lambda z: np.vstack([at(z).d_frequency[lower_w], -at(z).d_frequency[upper_w]]) * span)
    if purity is not None:
        cons_f.append(lambda z: (at(z).purity - m_p)[_chosen(items, at(z))] - purity)
        cons_j.append(lambda z: at(z).d_purity[_chosen(items, at(z))] * span)
    if max_sag is not None:
        zi = 6 * model.body_index(before.body) + 2
        cons_f.append(lambda z: np.atleast_1d(max_sag + at(z).sag[zi]))        # sag[z] is negative
        cons_j.append(lambda z: at(z).d_sag[zi][None, :] * span)
    fd = "2-point"
    return Problem(fun, jac if exact else fd, cons_f, cons_j if exact else [fd] * len(cons_j)), count


def _search(optimizer: Optimizer, problem: Problem, starts_z: list[np.ndarray], bounds: list[tuple[float, float]],
            maxiter: int, who: str) -> Any:
    """The optimizer from every start: the best ``((feasible, -objective), result)``, feasible first."""
    best = None
    for z in starts_z:
        try:
            r = optimizer(problem, z, bounds, maxiter)
        except VibssError:      # a start in a degenerate corner (repeated modes): try the next
            continue
        feasible = all(np.all(f(r.x) >= -1e-6) for f in problem.constraints)
        score = (feasible, -r.fun)
        if best is None or score > best[0]:
            best = (score, r)
    if best is None:
        raise AnalysisError(f"{who}: every start failed (repeated frequencies or an unrestrained layout)",
                            argument="variables")
    return best


def _snap_to_catalogue(optimizer: Optimizer, problem: Problem, best: Any, cat: dict[int, np.ndarray],
                       lo: np.ndarray, span: np.ndarray, maxiter: int, who: str) -> Any:
    """Each catalogue variable takes the better of its two neighbouring catalogue values (greedily,
    one after the other, by the penalized objective); the other variables are optimized again."""
    zc = np.clip(best[1].x, 0.0, 1.0)
    for i, values in cat.items():
        vz = (values - lo[i]) / span[i]
        below, above = vz[vz <= zc[i]], vz[vz >= zc[i]]
        options = ([below.max()] if below.size else []) + ([above.min()] if above.size else [])
        trial = []
        for c in options:
            z = zc.copy()
            z[i] = c
            trial.append(penalized(problem, z))
        zc[i] = options[int(np.argmin(trial))]
    return _search(optimizer, problem, [zc], [(zc[i], zc[i]) if i in cat else (0.0, 1.0) for i in range(len(zc))],
                   maxiter, who)


def benchmark_case() -> tuple[Model, dict[Any, tuple[float, float]], dict[str, Any]]:
    """The powertrain with 15 design variables (rates of each mount pair, positions, the V angle):
    the model, the variables with bounds and the keyword arguments of :func:`optimize`."""
    from ..io.modelfile import load_example

    model = load_example("powertrain")
    rates = {m.name: m.type.stiffness for m in model.mounts}
    var: dict[Any, tuple[float, float]] = {}
    for j in range(3):
        var[Parameter(f"engine pair k{j + 1}", [("engine", f"k{j + 1}", 1.0), ("engine.xz", f"k{j + 1}", 1.0)])] = \
            (0.5 * rates["engine"][j], 2.0 * rates["engine"][j])
        var[f"gearbox.k{j + 1}"] = (0.5 * rates["gearbox"][j], 2.0 * rates["gearbox"][j])
        var[f"torque-strut.k{j + 1}"] = (0.5 * rates["torque-strut"][j], 2.0 * rates["torque-strut"][j])
    var[Parameter("engine pair height", [("engine", "z", 1.0), ("engine.xz", "z", 1.0)])] = (-0.03, 0.03)
    var[Parameter("engine pair spread", [("engine", "y", 1.0), ("engine.xz", "y", -1.0)])] = (-0.03, 0.03)
    var[Parameter("engine V angle", [("engine", "rx", 1.0), ("engine.xz", "rx", -1.0)])] = (-0.35, 0.35)
    var["gearbox.x"] = (-0.03, 0.03)
    var["gearbox.z"] = (-0.03, 0.03)
    var["torque-strut.z"] = (-0.03, 0.03)
    return model, var, {"frame": "tra", "windows": (5.0, 26.7 / np.sqrt(2))}


__getattr__ = module_aliases(__name__, {
    "Optimisation": ("vibss.design.optimize.Optimization", lambda: Optimization),
    "optimise": ("vibss.design.optimize.optimize", lambda: optimize)})
