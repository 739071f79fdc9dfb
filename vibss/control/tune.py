"""Fixed-structure tuning of decentralised isolator loops against goals (systune's question, small).

``tune(plant, structure, goals)`` tunes one loop law per actuator (a static gain such as skyhook
damping, a PID or a lead-lag) so that every goal holds, then spends as little actuator effort as it
can:

1. minimise the sum of squared relative violations (Nelder-Mead in the logarithms of the
   parameters, which keeps them positive and scales them alike);
2. with every goal met, minimise the effort (the peak command per unit disturbance) with the goals as
   inequality constraints (SLSQP);
3. verify the result with :func:`vibss.control.close` (its own poles and margins) and report which
   goals are met.

Goals are ``(metric, "<=" or ">=", value)`` or ``(metric, op, value, (disturbance, output))``:

====================  =======================================================================
metric                what is compared (the worst over the tolerance set)
====================  =======================================================================
peak_transmissibility peak ``|T|`` of the channel [output unit / disturbance unit]
disk_margin           smallest loop-at-a-time balanced disk margin [-]
mimo_disk_margin      MIMO balanced disk margin (lower bound) [-]
damping               smallest closed-loop damping ratio [-]
effort                peak ``|u / w|`` over the commands for the channel's disturbance
====================  =======================================================================

With ``tolerances`` every goal must hold on the nominal plant and on the corners of the tolerance
box (rates only; the rate changes as an internal feedback, :mod:`vibss.control.variants`).
"""

from __future__ import annotations


from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validate import choice, integer
from ..design.parameters import current_values, parameters_of
from ..errors import ArgumentError, ControlDesignError, VibssError
from ..linear.eigen.small import state_eigenvalues
from ..methods import Check
from ..results import Result, TextTable, jsonable
from .designs import _ALL_KINDS, _sign, pairs as find_pairs
from .loop import ClosedLoop, Controller, controller
from .plant import vibss_name
from .variants import close_extended, extended_plant, frequency_metrics, mount_rates, open_loop, reduced_poles

__all__ = ["tune", "Tuning", "Goal", "STRUCTURES", "METRICS"]

STRUCTURES: dict[str, tuple[tuple[str, ...], tuple[str, ...]]] = {
    "skyhook": (("gain",), ("velocity",)),
    "velocity_feedback": (("gain",), ("relative_velocity",)),
    "gain": (("gain",), _ALL_KINDS),
    "pi": (("kp", "ki"), _ALL_KINDS),
    "pd": (("kp", "kd"), _ALL_KINDS),
    "pid": (("kp", "ki", "kd"), _ALL_KINDS),
    "lead_lag": (("gain", "zero_hz", "pole_hz"), _ALL_KINDS),
}
"""Loop laws: their parameters per loop and the measurement kinds they pair with."""

METRICS = ("peak_transmissibility", "disk_margin", "mimo_disk_margin", "damping", "effort")
"""Goal metrics."""

_KEY = {"peak_transmissibility": "peak", "disk_margin": "disk_margin", "mimo_disk_margin": "mimo_disk_margin",
        "damping": "damping", "effort": "effort"}


@dataclass(frozen=True)
class Goal:
    """One goal: ``metric op value`` (``channel`` for transmissibility and effort).

    Attributes
    ----------
    metric : str
        One of :data:`METRICS`.
    op : {"<=", ">="}
    value : float
        The bound (SI; [-] for margins and damping).
    channel : tuple of str or None
        (disturbance, output); None: the plant's first of each.
    """

    metric: str
    op: str
    value: float
    channel: tuple[str, str] | None = None

    @classmethod
    def coerce(cls, g: Any) -> Goal:
        """A Goal from a Goal or a tuple ``(metric, op, value[, channel])``."""
        if isinstance(g, Goal):
            return g
        if not isinstance(g, (tuple, list)) or len(g) not in (3, 4):
            raise ArgumentError(f"tune: goals: expected (metric, '<=' or '>=', value[, (disturbance, output)]), "
                                f"got {g!r}", argument="goals", received=g)
        metric = choice(g[0], "goals (metric)", METRICS, who="tune")
        op = choice(g[1], "goals (op)", ("<=", ">="), who="tune")
        try:
            value = float(g[2])
        except (TypeError, ValueError):
            value = np.nan
        if not np.isfinite(value):
            raise ArgumentError(f"tune: goals: {metric}: the bound must be a finite number, got {g[2]!r}",
                                argument="goals", received=g)
        ch = None
        if len(g) == 4 and g[3] is not None:
            if isinstance(g[3], str) or len(g[3]) != 2:
                raise ArgumentError(f"tune: goals: {metric}: channel must be (disturbance, output), got {g[3]!r}",
                                    argument="goals", received=g)
            ch = (vibss_name(str(g[3][0])), vibss_name(str(g[3][1])))
        return cls(metric, op, value, ch)

    def text(self) -> str:
        """``"peak_transmissibility <= 2 (ground.z.vel -> b.z.vel)"``."""
        return f"{self.metric} {self.op} {self.value:.4g}" + (f" ({self.channel[0]} -> {self.channel[1]})"
                                                              if self.channel else "")

    def excess(self, v: float) -> float:
        """Relative amount by which ``v`` misses the bound (negative: met with room) [-]."""
        scale = max(abs(self.value), 1e-12)
        return (v - self.value) / scale if self.op == "<=" else (self.value - v) / scale


@dataclass(frozen=True, eq=False)
class Tuning(Result):
    """A tuned controller, verified.

    Attributes
    ----------
    controller : Controller
        The tuned ``u = K y``.
    closed : ClosedLoop
        :func:`vibss.control.close` of it (poles, margins) on the nominal plant.
    structure : str
        The loop law.
    parameters : dict of str to float
        Tuned parameters per loop (``"<actuator>.<name>"``; gains in command per measurement unit,
        ``*_hz`` in Hz).
    goals : tuple of Goal
    achieved : (g,) ndarray
        Each goal's metric, worst over the tolerance set.
    met : (g,) bool ndarray
    effort : float
        Peak command per unit disturbance (worst over the set).
    variants : int
        Plants the goals were held on (1: the nominal only).
    nfev : int
        Closed loops evaluated.
    check : Check
        The verification: this tuning's nominal damping and disk margin against :func:`close`'s.
    note : str
    """

    controller: Controller
    closed: ClosedLoop
    structure: str
    parameters: dict[str, float]
    goals: tuple[Goal, ...]
    achieved: np.ndarray
    met: np.ndarray
    effort: float
    variants: int
    nfev: int
    check: Check
    note: str = ""
    method: str = "nelder-mead + slsqp"

    @property
    def all_met(self) -> bool:
        """Every goal met."""
        return bool(self.met.all())

    @property
    def output_labels(self) -> tuple[str, ...]:
        """The goals' metrics."""
        return tuple(g.metric for g in self.goals)

    def _item(self, i: int, j: int | None) -> float:
        return float(self.achieved[i])

    @property
    def table(self) -> TextTable:
        """One row per goal: bound, achieved (worst over the set), met."""
        rows = [[g.text(), f"{a:.4g}", "yes" if m else "NO"] for g, a, m in zip(self.goals, self.achieved, self.met)]
        rows.append(["effort (minimised)", f"{self.effort:.4g}", "-"])
        return TextTable(["goal", "achieved", "met"], rows,
                         title=f"tune ({self.structure}, {self.variants} plant(s)): "
                               + ("every goal met" if self.all_met else f"{int((~self.met).sum())} goal(s) missed"))

    def summary(self) -> TextTable:
        """The :attr:`table`."""
        return self.table

    def report(self) -> str:
        """Goals, parameters, verification."""
        pars = "\n".join(f"  {k} = {v:.6g}" for k, v in self.parameters.items())
        return "\n\n".join([self.table.render(), f"parameters:\n{pars}", f"verified with close(): {self.check.text()}",
                            self.note])

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready goals, parameters and verification."""
        return jsonable({"structure": self.structure, "parameters": self.parameters,
                         "goals": [{"goal": g.text(), "achieved": a, "met": bool(m)}
                                   for g, a, m in zip(self.goals, self.achieved, self.met)],
                         "effort": self.effort, "variants": self.variants, "nfev": self.nfev,
                         "check": self.check.text(), "note": self.note})


def _loop_law(name: str, v: np.ndarray, tau: float) -> Any:
    """SISO ``k(s)`` of one loop (positive; the feedback sign is applied by the caller)."""
    import control

    if name in ("skyhook", "velocity_feedback", "gain"):
        return control.ss([], [], [], [[v[0]]])
    if name == "lead_lag":
        wz, wp = 2 * np.pi * v[1], 2 * np.pi * v[2]
        return control.ss(control.tf([v[0] / wz, v[0]], [1 / wp, 1.0]))
    kp = v[0]
    ki = v[1] if name in ("pi", "pid") else 0.0
    kd = v[-1] if name in ("pd", "pid") else 0.0
    c = control.ss(control.tf([kp], [1.0]))
    if ki:
        c = control.parallel(c, control.ss(control.tf([ki], [1.0, 0.0])))
    if kd:
        c = control.parallel(c, control.ss(control.tf([kd, 0.0], [tau, 1.0])))
    return c


def build_controller(plant: Any, structure: str, pr: Sequence[tuple[str, str]], values: np.ndarray,
                     tau: float = 1e-3) -> Controller:
    """The decentralised controller ``u_i = -k_i(s) y_i`` of ``structure`` with parameter rows ``values``."""
    import control

    parts = [-_sign(plant, lab, y) * _loop_law(structure, v, tau) for (lab, y), v in zip(pr, values)]
    sys = control.append(*parts) if len(parts) > 1 else parts[0]
    names = STRUCTURES[structure][0]
    return controller(sys.A, sys.B, sys.C, sys.D, [vibss_name(y) for _, y in pr], [vibss_name(u) for u, _ in pr],
                      {"design": f"tuned {structure}",
                       **{n: [float(v[k]) for v in values] for k, n in enumerate(names)},
                       "pairs": {vibss_name(u): vibss_name(y) for u, y in pr}}, name=f"tuned_{structure}")


def _start(plant: Any, pr: Sequence[tuple[str, str]], structure: str, omega: np.ndarray, h: np.ndarray) -> np.ndarray:
    """Starting parameters per loop: loop gain 1 where the loop's own plant response peaks."""
    out = []
    for i in range(len(pr)):
        g = np.abs(h[i, i])
        k = int(np.argmax(g))
        gain, w = 1.0 / max(g[k], 1e-300), omega[k]
        row = {"gain": gain, "kp": gain, "ki": gain * w / 10, "kd": gain / w,
               "zero_hz": w / (2 * np.pi) / 3, "pole_hz": w / (2 * np.pi) * 3}
        out.append([row[n] for n in STRUCTURES[structure][0]])
    return np.array(out, dtype=float)


class _Problem:
    """The closed loops of one tuning: metrics of a parameter vector over the plant set, cached."""

    def __init__(self, plant: Any, structure: str, pr: list[tuple[str, str]], goals: tuple[Goal, ...],
                 tolerances: Mapping[Any, float] | None, states: int, tau: float) -> None:
        from .robust import _axes, _corners, default_grid

        self.plant, self.structure, self.pr, self.goals, self.states, self.tau = plant, structure, pr, goals, states, tau
        model = plant.model
        if tolerances:
            params = parameters_of(model, list(tolerances))
            if not all(p.is_rate for p in params):
                raise ControlDesignError("tune: tolerances: rates and rate ratios only (shifts and angles move "
                                         "the mounts; check them with robustness(method='rebuild'))")
            tol = np.array([float(v) for v in tolerances.values()])
            nominal = current_values(model, params)
            k = len(params)
            which = np.arange(k) if k <= 5 else np.arange(k)[:0]
            values = np.vstack([nominal[None], _corners(params, nominal, tol, which)]) if which.size else \
                np.vstack([nominal[None]] + [nominal + np.where(np.arange(k) == i, s * tol * nominal, 0.0)
                                             for i in range(k) for s in (-1.0, 1.0)])
            self.axes = _axes(model, params)
            r0 = np.array([m.type.stiffness for m in model.mounts], dtype=float)
            rates = mount_rates(model, params, values)
            q = np.array([a[0] for a in self.axes], dtype=int)
            j = np.array([a[1] for a in self.axes], dtype=int)
            self.delta = rates[:, q, j] - r0[q, j]
        else:
            self.axes, self.delta = [], np.zeros((1, 0))
        self.P = extended_plant(plant, self.axes)
        self.omega = default_grid(state_eigenvalues(plant.A), 800)
        self.channels = list(dict.fromkeys(g.channel for g in goals)) or [None]
        if None not in self.channels:
            self.channels.append(None)              # the effort objective's channel
        self.h: np.ndarray | None = None
        self.cache: dict[bytes, dict[Any, Any]] = {}
        self.nfev = 0

    def values(self, x: np.ndarray) -> np.ndarray:
        return (10.0 ** np.asarray(x, dtype=float)).reshape(len(self.pr), -1)

    def controller(self, x: np.ndarray) -> Controller:
        return build_controller(self.plant, self.structure, self.pr, self.values(x), self.tau)

    def metrics(self, x: np.ndarray) -> dict[Any, Any]:
        """Worst metric over the set per (metric, channel), ``unstable`` the largest pole real part."""
        from .robust import _channel, _pole_metrics

        key = np.asarray(x, dtype=float).tobytes()
        if key in self.cache:
            return self.cache[key]
        self.nfev += 1
        K = self.controller(x)
        ext = close_extended(self.P, K, self.axes)
        poles, held, _ = reduced_poles(ext.closed, ext.f_in, ext.d_out, self.delta, self.states)
        allp = np.concatenate([poles, np.broadcast_to(held, (poles.shape[0], held.size))], axis=1)
        mag = np.maximum(np.abs(allp), 1.0)
        out: dict[Any, Any] = {"unstable": float((allp.real / mag).max())}
        stable, zeta = _pole_metrics(poles, held)
        out["damping"] = float(zeta.min())
        if not stable.all():
            self.cache[key] = out
            return out
        if self.h is None:
            self.h = open_loop(ext, K, self.omega)
        for ch in self.channels:
            names, idx = _channel(self.plant, ext, ch)
            fm = frequency_metrics(ext, K, self.delta, self.omega, idx, h=self.h)
            for metric, k in _KEY.items():
                if metric == "damping":
                    continue
                worst = fm[k].max() if metric in ("peak_transmissibility", "effort") else fm[k].min()
                out[(metric, ch)] = float(worst)
            out[("names", ch)] = names
        self.cache[key] = out
        return out

    def value(self, g: Goal, m: dict[Any, Any]) -> float:
        return float(m["damping"] if g.metric == "damping" else m[(g.metric, g.channel)])

    def excesses(self, x: np.ndarray) -> np.ndarray:
        m = self.metrics(x)
        if m["unstable"] > 1e-9:
            return np.full(len(self.goals), 1e3 * (1.0 + m["unstable"]))
        return np.array([g.excess(self.value(g, m)) for g in self.goals])

    def violation(self, x: np.ndarray) -> float:
        e = self.excesses(x)
        return float(np.sum(np.maximum(e, 0.0) ** 2))

    def effort(self, x: np.ndarray) -> float:
        m = self.metrics(x)
        return float(m.get(("effort", None), np.inf))


def tune(plant: Any, structure: str, goals: Sequence[Any], *, tolerances: Mapping[Any, float] | None = None,
         pairs: Mapping[str, str] | None = None, start: Any = None, tau: float = 1e-3, states: int = 120,
         maxiter: int = 400) -> Tuning:
    """Tune one loop law per actuator so that the goals hold, with the least effort.

    Parameters
    ----------
    plant : GeneralizedPlant
        From :func:`vibss.control.plant`.
    structure : str
        One of :data:`STRUCTURES` (``"skyhook"``, ``"velocity_feedback"``, ``"gain"``, ``"pi"``,
        ``"pd"``, ``"pid"``, ``"lead_lag"``): ``u_i = -k_i(s) y_i`` per loop; PID
        ``kp + ki / s + kd s / (tau s + 1)``; lead-lag ``gain (s / wz + 1) / (s / wp + 1)``.
    goals : sequence of tuple or Goal
        ``(metric, "<=" or ">=", value[, (disturbance, output)])``, metrics :data:`METRICS`.
    tolerances : mapping or None
        ``{"<mount>.k3": 0.2, ...}`` (rates, relative): every goal must hold on the corners of the
        box too (up to 5 rates; beyond, each rate at its two ends alone).
    pairs : mapping or None
        ``{actuator: measurement}``; default: each actuator's collocated sensor of the law's kind.
    start : (loops, k) array_like or None
        Starting parameters (default: loop gain 1 at each loop's own resonance).
    tau : float
        Derivative filter time constant of PID/PD [s].
    states : int
        Closed-loop poles solved per variant (see :func:`vibss.control.robustness`).
    maxiter : int
        Iterations of each optimizer.

    Returns
    -------
    Tuning
        With the controller, its :func:`~vibss.control.close` and which goals are met.

    Examples
    --------
    >>> import vibss.control as vc   # doctest: +SKIP
    >>> t = vc.tune(P, "skyhook", [("peak_transmissibility", "<=", 2.0, ("ground.z.vel", "b.z.vel"))])  # doctest: +SKIP
    """
    from scipy.optimize import minimize

    from .loop import close

    structure = choice(structure, "structure", STRUCTURES, who="tune")
    if not hasattr(plant, "recipe"):
        raise ArgumentError("tune: plant: expected a vibss.control.plant(...)", argument="plant")
    gl = tuple(Goal.coerce(g) for g in goals)
    if not gl:
        raise ArgumentError("tune: goals: give at least one goal", argument="goals")
    if not tau > 0:
        raise ArgumentError(f"tune: tau: expected a time constant > 0 [s], got {tau!r}", argument="tau", received=tau)
    maxiter = integer(maxiter, "maxiter", who="tune")
    pr = find_pairs(plant, STRUCTURES[structure][1], pairs)
    prob = _Problem(plant, structure, pr, gl, tolerances, integer(states, "states", who="tune"), tau)
    nk = len(STRUCTURES[structure][0])
    if start is None:
        k0 = build_controller(plant, structure, pr, np.ones((len(pr), nk)), tau)
        h0 = open_loop(close_extended(prob.P, k0, prob.axes), k0, prob.omega)
        x0 = np.log10(_start(plant, pr, structure, prob.omega, h0)).ravel()
    else:
        s0 = np.asarray(start, dtype=float).reshape(len(pr), nk)
        if not np.all(np.isfinite(s0)) or np.any(s0 <= 0):
            raise ArgumentError("tune: start: expected parameters > 0", argument="start", received=start)
        x0 = np.log10(s0).ravel()
    best = {"x": x0, "v": prob.violation(x0)}

    def stop_when_met(xk: np.ndarray) -> None:       # stop phase 1 as soon as every goal holds
        v = prob.violation(xk)
        if v < best["v"]:
            best.update(x=np.array(xk), v=v)
        if v == 0.0:
            raise _GoalsMet("every goal holds")

    res1 = minimize(prob.violation, x0, method="Nelder-Mead", callback=stop_when_met,
                    options={"maxiter": maxiter * len(x0), "xatol": 1e-6, "fatol": 1e-14})
    x = res1.x if prob.violation(res1.x) <= best["v"] else best["x"]
    note = f"phase 1 (Nelder-Mead on the violations): {prob.violation(x):.3g} left"
    if prob.violation(x) == 0.0:
        x = _least_effort(prob, x, maxiter)
        note += "; phase 2 (SLSQP, least effort with the goals as constraints)"
    K = prob.controller(x)
    m = prob.metrics(x)
    achieved = np.array([prob.value(g, m) if m["unstable"] <= 1e-9 else np.nan for g in gl])
    met = np.array([g.excess(a) <= 1e-6 if np.isfinite(a) else False for g, a in zip(gl, achieved)])
    cl = close(plant, K, allow_unstable=True)
    chk = _verify(prob, x, cl)
    names = STRUCTURES[structure][0]
    vals = prob.values(x)
    params = {f"{vibss_name(u).split('.')[1]}.{n}": float(vals[i, k]) for i, (u, _) in enumerate(pr)
              for k, n in enumerate(names)}
    return Tuning(controller=K, closed=cl, structure=structure, parameters=params, goals=gl, achieved=achieved,
                  met=met, effort=prob.effort(x), variants=prob.delta.shape[0], nfev=prob.nfev, check=chk,
                  note=note + f"; metrics on {prob.omega.size} frequencies (peaks refined by a parabola)")


class _GoalsMet(VibssError, StopIteration):
    """Ends phase 1 from its callback (scipy stops a minimiser on a StopIteration from the callback)."""


def _least_effort(prob: _Problem, x: np.ndarray, maxiter: int) -> np.ndarray:
    """SLSQP from a feasible ``x``: minimise log effort with every goal's excess <= 0."""
    from scipy.optimize import minimize

    e0 = prob.effort(x)
    cons = [{"type": "ineq", "fun": (lambda z, i=i: -prob.excesses(z)[i])} for i in range(len(prob.goals))]
    res = minimize(lambda z: np.log(max(prob.effort(z), 1e-300) / e0), x, method="SLSQP", constraints=cons,
                   options={"maxiter": maxiter, "ftol": 1e-12}, bounds=[(xi - 4, xi + 4) for xi in x])
    ok = np.all(prob.excesses(res.x) <= 1e-6)
    return res.x if ok and prob.effort(res.x) <= e0 * (1 + 1e-12) else x


def _verify(prob: _Problem, x: np.ndarray, cl: ClosedLoop) -> Check:
    """This tuning's nominal damping against close()'s poles (both exact), and stability."""
    from .robust import _pole_metrics

    ext = close_extended(prob.P, prob.controller(x), prob.axes)
    poles, held, _ = reduced_poles(ext.closed, ext.f_in, ext.d_out, np.zeros((1, len(prob.axes))), prob.states)
    _, zeta = _pole_metrics(poles, held)
    mags = np.abs(cl.poles)
    z_cl = float(np.min(np.where(mags > 0, -cl.poles.real / np.where(mags > 0, mags, 1.0), 1.0)))
    err = abs(float(zeta[0]) - z_cl) / max(abs(z_cl), 1e-3)
    return Check(err, 1e-3, f"nominal damping {float(zeta[0]):.6g} against close()'s {z_cl:.6g}")



