"""The rigid motion a ground excitation leaves behind: a velocity or acceleration input whose
integral does not return to zero makes every absolute motion a drift (a half-sine acceleration
pulse leaves the ground moving at ``2 A T / pi``). Reports and the command line flag it."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = ["Drift", "ground_drifts", "DRIFT_SHARE"]


@dataclass(frozen=True)
class Drift:
    """The rigid motion a ground excitation leaves behind at the end of a record.

    Attributes
    ----------
    excitation : str
        The excitation's name.
    velocity : float
        The ground's velocity at the end [m/s, rad/s] (integral of an acceleration input).
    displacement : float
        The ground's displacement at the end [m, rad].
    unit : str
        ``"m"`` or ``"rad"``.
    """

    excitation: str
    velocity: float
    displacement: float
    unit: str = "m"

    def text(self) -> str:
        """``"record-x leaves the ground moving at 0.28 m/s, 0.26 m away by the end"``."""
        return (f"{self.excitation} leaves the ground moving at {self.velocity:.3g} {self.unit}/s, "
                f"{self.displacement:.3g} {self.unit} away by the end (absolute motions carry this drift)")


DRIFT_SHARE = 0.01
"""A ground excitation drifts when its velocity at the end exceeds this share of its largest (a
pulse pair of zero net velocity leaves an offset at rest: no drift)."""


def ground_drifts(excitations: Sequence[Any], t_end: float, samples: int = 20001) -> list[Drift]:
    """The velocity and acceleration excitations of a ground or support that leave it moving at
    ``t_end`` [s] faster than :data:`DRIFT_SHARE` of their largest velocity (a half-sine
    acceleration pulse: a constant velocity after it). Integrated by the trapezoidal rule on
    ``samples`` points (a note's accuracy)."""
    out = []
    t = np.linspace(0.0, float(t_end), int(samples))
    for e in excitations:
        if e.kind not in ("velocity", "acceleration") or getattr(e, "function", None) is None:
            continue
        x = np.asarray(e.function.value(t), float) * np.ones_like(t)
        v = x
        if e.kind == "acceleration":
            v = np.concatenate([[0.0], np.cumsum(0.5 * (x[1:] + x[:-1]) * np.diff(t))])
        d = np.concatenate([[0.0], np.cumsum(0.5 * (v[1:] + v[:-1]) * np.diff(t))])
        top = float(np.abs(v).max())
        if top > 0 and abs(v[-1]) > DRIFT_SHARE * top:
            unit = "rad" if str(getattr(e, "dof", "")).startswith("r") else "m"
            out.append(Drift(str(e.name), float(v[-1]), float(d[-1]), unit))
    return out
