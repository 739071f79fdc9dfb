"""The rigid motion a ground excitation leaves behind: a velocity or acceleration input whose
integral does not return to zero makes every absolute motion a drift (a half-sine acceleration
pulse leaves the ground moving at ``2 A T / pi``). Reports and the command line flag it."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = ["Drift", "ground_drifts", "DRIFT_SHARE", "implausible_motions", "VELOCITY_LIMIT"]


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
    for e, t, v, d in _kinematics(excitations, t_end, samples):
        top = float(np.abs(v).max())
        if top > 0 and abs(v[-1]) > DRIFT_SHARE * top:
            out.append(Drift(str(e.name), float(v[-1]), float(d[-1]), _unit(e)))
    return out


VELOCITY_LIMIT = 100.0
"""[m/s] A prescribed motion faster than this is implausible for a body on mounts (a free fall
from 510 m; a 30 g pulse meant to last 11 ms but given as 11 s reaches 2,000 m/s)."""


def implausible_motions(excitations: Sequence[Any], t_end: float, samples: int = 20001) -> list[str]:
    """One-line warnings for velocity and acceleration excitations whose velocity exceeds
    :data:`VELOCITY_LIMIT` within ``t_end`` [s] (translations only): a duration in s where ms was
    meant, or an acceleration in mm/s^2 given as m/s^2."""
    out = []
    for e, t, v, _ in _kinematics(excitations, t_end, samples):
        top = int(np.argmax(np.abs(v)))
        if _unit(e) == "m" and abs(v[top]) > VELOCITY_LIMIT:
            out.append(f"excitation {e.name!r}: the ground or body it moves reaches {abs(v[top]):.3g} m/s by "
                       f"t = {t[top]:.3g} s, over the {VELOCITY_LIMIT:g} m/s any mount meets: a duration in s "
                       "where ms was meant, or a unit off by 1000?")
    return out


def _unit(e: Any) -> str:
    return "rad" if str(getattr(e, "dof", "")).startswith("r") else "m"


def _kinematics(excitations: Sequence[Any], t_end: float, samples: int) -> list[tuple[Any, np.ndarray, np.ndarray, np.ndarray]]:
    """Per velocity or acceleration excitation: the times [s], its velocity and displacement
    (trapezoidal rule on ``samples`` points from 0 to ``t_end``)."""
    out = []
    t = np.linspace(0.0, float(t_end), int(samples))
    for e in excitations:
        if getattr(e, "kind", None) not in ("velocity", "acceleration") or getattr(e, "function", None) is None:
            continue
        x = np.asarray(e.function.value(t), float) * np.ones_like(t)
        v = x
        if e.kind == "acceleration":
            v = np.concatenate([[0.0], np.cumsum(0.5 * (x[1:] + x[:-1]) * np.diff(t))])
        d = np.concatenate([[0.0], np.cumsum(0.5 * (v[1:] + v[:-1]) * np.diff(t))])
        out.append((e, t, v, d))
    return out
