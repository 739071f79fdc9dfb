"""The model file's ``[control]`` design, run by ``vibss control`` and the report's control section."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import ModelError
from ..results import Result, TextTable
from .designs import integral_force, skyhook, velocity_feedback
from .loop import ClosedLoop, close
from .plant import plant

__all__ = ["ControlStudy", "run_control"]


@dataclass(frozen=True, eq=False)
class ControlStudy(Result):
    """A closed loop with its passive and active transmissibility at the passive resonance peaks.

    Attributes
    ----------
    loop : ClosedLoop
        Poles, damping, margins.
    passive, active : FrequencyResponse
        Transmissibility of each performance output to each disturbance, same frequencies.
    """

    loop: ClosedLoop
    passive: Any
    active: Any
    name: str = "control"

    @property
    def output_labels(self) -> tuple[str, ...]:
        """The performance outputs."""
        return tuple(self.active.outputs)

    @property
    def input_labels(self) -> tuple[str, ...]:
        """The disturbances."""
        return tuple(self.active.inputs)

    def _item(self, i: int, j: int | None) -> np.ndarray:
        return self.active.response[i] if j is None else self.active.response[i, j]

    def reductions(self) -> list[dict[str, Any]]:
        """Per output, at its largest passive transmissibility (over the disturbances): frequency [Hz],
        passive and active |T| [-] and the reduction [dB]."""
        rows = []
        for i, y in enumerate(self.active.outputs):
            tp = np.abs(self.passive.response[i])
            j, k = np.unravel_index(int(np.argmax(tp)), tp.shape)
            ta = abs(self.active.response[i, j, k])
            rows.append({"output": y, "input": self.active.inputs[j], "frequency_hz": float(self.active.frequency_hz[k]),
                         "passive": float(tp[j, k]), "active": float(ta),
                         "reduction_db": float(20 * np.log10(tp[j, k] / ta))})
        return rows

    def summary(self) -> TextTable:
        """Transmissibility reduction at each output's passive peak."""
        rows = [(r["output"], r["input"], f"{r['frequency_hz']:.4g}", f"{r['passive']:.4g}", f"{r['active']:.4g}",
                 f"{r['reduction_db']:.1f}") for r in self.reductions()]
        return TextTable(("output", "disturbance", "passive peak [Hz]", "passive |T| [-]", "active |T| [-]",
                      "reduction [dB]"), rows, title=f"{self.loop.name}: transmissibility at the passive peaks")

    def report(self) -> str:
        """Design, poles, margins and reductions."""
        return f"{self.loop.controller.summary()}\n\n{self.loop.report()}\n\n{self.summary()}"

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: poles, margins, reductions, and the design parameters."""
        design = {k: v for k, v in getattr(self.loop.controller, "design", {}).items()
                  if isinstance(v, (str, int, float, dict, list))}
        return {"design": design, **self.loop.to_dict(), "reductions": self.reductions()}

    def plot(self, ax: Any = None) -> Any:
        """Passive and closed-loop transmissibility on one figure."""
        from ..plotting.control import plot_transmissibility

        return plot_transmissibility(self.passive, self.active, ax=ax, title=self.loop.name)


def run_control(model: Any, frequencies: Any = None) -> ControlStudy:
    """Design, close and analyse the model file's ``[control]`` loops.

    Parameters
    ----------
    model : Model
        With actuators, sensors and ``settings["control"]`` (:mod:`vibss.io.controlfile`).
    frequencies : array_like or None
        [Hz]; default 300 log-spaced points over a decade either side of the modes.

    Returns
    -------
    ControlStudy
    """
    spec = model.settings.get("control")
    if not spec:
        raise ModelError("the model has no [control] table (design, gain, disturbances, performance)")
    P = plant(model, spec["disturbances"], performance=spec["performance"], measurements=spec.get("measurements"))
    if spec["design"] == "skyhook":
        K = skyhook(P, spec["gain"])
    elif spec["design"] == "velocity_feedback":
        K = velocity_feedback(P, spec["gain"])
    else:
        K = integral_force(P, spec["gain"], leak_hz=spec.get("leak", 0.0))
    cl = close(P, K, name=f"{spec['design']} on {model.name}")
    if frequencies is None:
        from ..modal.api import modes

        f = modes(model).frequency_hz
        f = f[f > 0]
        lo, hi = (f.min() / 10, f.max() * 10) if f.size else (0.1, 1000.0)
        frequencies = np.geomspace(lo, hi, 300)
    passive, active = cl.transmissibility(spec["disturbances"], spec["performance"], frequencies)
    return ControlStudy(cl, passive, active)
