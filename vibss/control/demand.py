"""What a closed loop demands of its actuators (force) and its mounts (stroke) under a given environment.

A ground-motion PSD gives RMS values, ``sigma_y^2 = sum_j integral |H_yj(f)|^2 S_j(f) df`` (the inputs
uncorrelated; a log grid over each PSD's band, dense around every lightly damped closed-loop pole,
trapezoidal rule); a shock or any time function gives the peak of the time response (python-control's
``forced_response`` on the closed loop, a first-order hold of the sampled input). Every output of the
loop can be asked for: actuator commands (force), relative displacements (stroke), accelerations.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import ModelError
from ..linear.plant.names import control_name
from ..results import Result, Table
from .plant import vibss_name

__all__ = ["Demand", "demand"]


@dataclass(frozen=True, eq=False)
class Demand(Result):
    """RMS (random) or peak (transient) of closed-loop outputs under an environment.

    Attributes
    ----------
    outputs : tuple of str
        Output names (vibss spelling).
    units : tuple of str
        Their SI units.
    value : (p,) ndarray
        RMS or peak |value| per output, SI.
    statistic : str
        ``"RMS"`` or ``"peak"``.
    environment : str
        What drove it.
    """

    outputs: tuple[str, ...]
    units: tuple[str, ...]
    value: np.ndarray
    statistic: str
    environment: str
    name: str = "demand"

    @property
    def output_labels(self) -> tuple[str, ...]:
        """Output names."""
        return self.outputs

    def _item(self, i: int, j: int | None) -> float:
        return float(self.value[i])

    def summary(self) -> Table:
        """One row per output."""
        rows = [(y, u, f"{v:.4g}") for y, u, v in zip(self.outputs, self.units, self.value)]
        return Table(("output", "unit", f"{self.statistic}"), rows, title=f"{self.name}: {self.environment}")

    def report(self) -> str:
        """The table as text."""
        return str(self.summary())

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready values (SI)."""
        return {"statistic": self.statistic, "environment": self.environment,
                "outputs": {y: {"value": float(v), "unit": u} for y, u, v in zip(self.outputs, self.units, self.value)}}


def demand(loop: Any, environment: Mapping[str, Any], outputs: Sequence[str] | None = None,
           end: float | None = None, step: float | None = None, points: int = 4000) -> Demand:
    """RMS under PSDs, or peaks under time functions, of a closed loop's outputs.

    Parameters
    ----------
    loop : ClosedLoop
        From :func:`vibss.control.close`.
    environment : mapping
        ``{disturbance: PSD}`` (every value a :class:`vibss.random.PSD`, in the disturbance's SI
        unit squared per Hz) or ``{disturbance: time function}`` (``HalfSine(...)`` and the other
        :mod:`vibss.model.timefunctions`).
    outputs : sequence of str or None
        Outputs (default every output of the loop: plant outputs and actuator commands).
    end, step : float or None
        Time window and step [s] for time functions (default: the excitation's end plus five time
        constants of the slowest closed-loop pole; a twentieth of the fastest oscillating pole's
        period, at most 200,000 samples).
    points : int
        Log-grid points per PSD band.

    Returns
    -------
    Demand
    """
    sys = loop.system
    outs = [vibss_name(s) for s in sys.output_labels] if outputs is None else [str(s) for s in outputs]
    labels = list(sys.output_labels)
    io = []
    for y in outs:
        if control_name(y) not in labels:
            raise ModelError(f"outputs: {y!r} is not an output of the closed loop; they are "
                             f"{[vibss_name(s) for s in labels]}")
        io.append(labels.index(control_name(y)))
    ins = list(sys.input_labels)
    env = {control_name(str(k)): v for k, v in environment.items()}
    unknown = sorted(vibss_name(k) for k in set(env) - set(ins))
    if unknown or not env:
        raise ModelError(f"environment: {unknown or 'nothing'} given; the loop's disturbances are "
                         f"{[vibss_name(s) for s in ins]}")
    units = getattr(sys, "vibss_units", {}) or {}
    unit = tuple(units.get(y, "-") for y in outs)
    is_psd = [hasattr(v, "band") and callable(v) for v in env.values()]
    if all(is_psd):
        return _random(loop, env, outs, io, unit, points)
    if any(is_psd):
        raise ModelError("environment: give PSDs for every disturbance, or time functions for every one")
    return _transient(loop, env, outs, io, unit, end, step)


def _random(loop: Any, env: dict[str, Any], outs: list[str], io: list[int], unit: tuple[str, ...],
            points: int) -> Demand:
    from ..frequency.statespace_response import Evaluator

    sys = loop.system
    poles = loop.poles[(loop.poles.imag > 0)]
    total = np.zeros(len(outs))
    for name, psd in env.items():
        lo, hi = psd.band
        f = np.geomspace(max(lo, 1e-6), hi, points)
        near = [abs(p) / (2 * np.pi) * (1 + np.linspace(-4, 4, 81) * max(-p.real / abs(p), 1e-5))
                for p in poles]
        f = np.unique(np.concatenate([f, *near])) if near else f
        f = f[(f >= lo) & (f <= hi)]
        h = Evaluator(sys, outputs=io, inputs=[list(sys.input_labels).index(name)])(2 * np.pi * f)[:, 0, :]
        total += np.trapezoid(np.abs(h) ** 2 * psd(f)[None, :], f, axis=1)
    return Demand(tuple(outs), unit, np.sqrt(total), "RMS",
                  ", ".join(f"{vibss_name(k)}: {getattr(v, 'name', 'psd')}" for k, v in env.items()),
                  name=f"{loop.name}: random demand")


def _transient(loop: Any, env: dict[str, Any], outs: list[str], io: list[int], unit: tuple[str, ...],
               end: float | None, step: float | None) -> Demand:
    import control

    sys = loop.system
    poles = loop.poles
    stable = poles[poles.real < 0]
    if end is None:
        tail = 5.0 / float(np.min(-stable.real)) if stable.size else 1.0
        last = max((float(getattr(v, "end_time", np.inf)) for v in env.values()), default=0.0)
        end = (last if np.isfinite(last) else 0.0) + tail
    if step is None:
        osc = np.abs(poles[poles.imag > 0])
        step = (2 * np.pi / osc.max() / 20) if osc.size else end / 2000
        step = max(step, end / 200_000)
    if not (end > 0 and 0 < step <= end):
        raise ModelError(f"end, step: need 0 < step <= end [s], got end={end!r}, step={step!r}")
    t = np.arange(0.0, end + 0.5 * step, step)
    u = np.zeros((sys.ninputs, t.size))
    for name, fn in env.items():
        value = getattr(fn, "value", fn)
        u[list(sys.input_labels).index(name)] = np.asarray(value(t), dtype=float)
    r = control.forced_response(control.ss(sys.A, sys.B, sys.C[io], sys.D[io]), t, u)
    y = np.atleast_2d(np.asarray(r.outputs))
    return Demand(tuple(outs), unit, np.abs(y).max(axis=1), "peak",
                  ", ".join(f"{vibss_name(k)}: {type(v).__name__}" for k, v in env.items())
                  + f" (0 to {end:.3g} s, step {step:.3g} s)", name=f"{loop.name}: transient demand")
