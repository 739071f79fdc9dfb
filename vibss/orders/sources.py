"""Excitation by rotating machinery: a rotating unbalance and engine-order forces and moments, each a
harmonic of the shaft speed whose amplitude follows the speed.

Every source acts on one body and gives, at shaft speed ``rpm``, a complex amplitude (phasor) of
the six generalised forces at the body's COG (global axes: ``fx fy fz`` [N], ``mx my mz`` [N m])
at the frequency ``order * rpm / 60`` [Hz]; the physical load is ``Re(F e^{i w t})``.

- :class:`Unbalance`: mass ``m`` [kg] at radius ``e`` [m] turning about ``axis`` through ``at``:
  ``F = m e W^2 (u - i v) e^{i phase}`` with ``W = 2 pi rpm / 60`` [rad/s] and ``(u, v, axis)`` a
  right-handed frame, so the force points along ``u`` at ``t = 0`` and turns towards ``v``
  (positive rotation about ``axis``); its moment about the COG is ``(at - cog) x F``.
- :class:`OrderForce`: an engine order (or any harmonic of the shaft speed): force [N] and/or
  moment [N m] amplitudes per global axis against speed, from a table (interpolated log-log
  between positive amplitudes, so a force growing with speed squared is followed exactly; linearly
  where a column has zeros; refused outside the table), with a phase per axis [rad].
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import _validate as v
from .._deprecated import module_aliases
from ..errors import ArgumentError, ModelError, did_you_mean
from ..model.geometry import skew
from ..model.model import Model

__all__ = ["Unbalance", "OrderForce", "Source", "generalized_forces", "sources_from_settings"]

_AXES = {"x": np.eye(3)[0], "y": np.eye(3)[1], "z": np.eye(3)[2]}


def _axis(value: Any, who: str) -> np.ndarray:
    if isinstance(value, str):
        if value not in _AXES:
            raise ArgumentError(f"{who}: axis: expected 'x', 'y', 'z' or a 3-vector, got {value!r}"
                                + did_you_mean(value, _AXES), argument="axis", received=value)
        return _AXES[value].copy()
    a = v.array(value, "axis", (3,), who=who)
    n = float(np.linalg.norm(a))
    if n == 0.0:
        raise ArgumentError(f"{who}: axis: must not be the zero vector", argument="axis", received=value)
    return a / n


def _name(value: Any, argument: str, who: str) -> None:
    if not isinstance(value, str) or not value:
        raise ArgumentError(f"{who}: {argument}: expected a non-empty string, got {value!r}",
                            argument=argument, received=value)


def _body(model: Model, name: str, who: str) -> Any:
    names = [b.name for b in model.bodies]
    if name not in names:
        raise ModelError(f"{who}: body: unknown body {name!r}{did_you_mean(name, names)}; bodies are {names}")
    return model.bodies[names.index(name)]


@dataclass(frozen=True)
class Unbalance:
    """A rotating unbalance on a body.

    Parameters
    ----------
    name : str
        Label.
    body : str
        Body the shaft runs in.
    mass : float
        Unbalance mass [kg] (> 0).
    radius : float
        Its radius [m] (> 0); ``mass * radius`` is the unbalance [kg m].
    axis : {"x", "y", "z"} or (3,) array_like
        Shaft axis, global; the shaft turns positively about it.
    at : (3,) array_like or None
        A point of the unbalance plane on the shaft axis, global coordinates [m]; None: the COG.
    order : float
        Harmonic of the shaft speed (1 for an unbalance of the shaft itself; 2 for a balancer shaft
        at twice crank speed).
    phase : float
        Angle of the unbalance from ``u`` at ``t = 0`` [rad].
    """

    name: str
    body: str
    mass: float
    radius: float
    axis: Any = "x"
    at: Any = None
    order: float = 1.0
    phase: float = 0.0
    _axis: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        who = f"unbalance {self.name!r}"
        _name(self.name, "name", "unbalance")
        _name(self.body, "body", who)
        object.__setattr__(self, "mass", v.number(self.mass, "mass", who=who, minimum=0.0, strict=True, unit="kg"))
        object.__setattr__(self, "radius", v.number(self.radius, "radius", who=who, minimum=0.0, strict=True, unit="m"))
        object.__setattr__(self, "order", v.number(self.order, "order", who=who, minimum=0.0, strict=True))
        object.__setattr__(self, "phase", v.number(self.phase, "phase", who=who, unit="rad"))
        object.__setattr__(self, "_axis", _axis(self.axis, who))
        if self.at is not None:
            object.__setattr__(self, "at", v.array(self.at, "at", (3,), who=who))

    def phasors(self, model: Model, rpm: np.ndarray) -> np.ndarray:
        """(6, n) complex generalised force at the COG [N, N m] at each shaft speed [rpm]."""
        body = _body(model, self.body, f"unbalance {self.name!r}")
        e = self._axis
        u = np.cross(e, [0.0, 0.0, 1.0]) if abs(e[2]) < 0.9 else np.cross(e, [1.0, 0.0, 0.0])
        u /= np.linalg.norm(u)
        w = np.cross(e, u)                                  # (u, w, e) right-handed
        om = 2.0 * np.pi * self.order * np.asarray(rpm, float) / 60.0
        f = np.outer((u - 1j * w) * np.exp(1j * self.phase), self.mass * self.radius * om ** 2)
        r = (np.zeros(3) if self.at is None else self.at - body.cog)
        return np.vstack([f, skew(r) @ f])


@dataclass(frozen=True)
class OrderForce:
    """Forces and moments at a harmonic of the shaft speed, with amplitudes against speed.

    Parameters
    ----------
    name : str
        Label (e.g. ``"2nd order torque"``).
    body : str
        Body they act on (at its COG).
    order : float
        Harmonic of the shaft speed (2 for the second engine order of a four-cylinder engine).
    rpm : (k,) array_like
        Shaft speeds of the table [rpm], increasing (one value: the same amplitude at every speed).
    force : (k, 3) array_like or None
        Force amplitude per global axis at each speed [N].
    moment : (k, 3) array_like or None
        Moment amplitude per global axis at each speed [N m] (e.g. the crank-axis torque).
    phase : (6,) array_like or None
        Phase of each of ``fx fy fz mx my mz`` [rad]; None: all in phase.
    """

    name: str
    body: str
    order: float
    rpm: Any
    force: Any = None
    moment: Any = None
    phase: Any = None

    def __post_init__(self) -> None:
        who = f"order force {self.name!r}"
        _name(self.name, "name", "order force")
        _name(self.body, "body", who)
        object.__setattr__(self, "order", v.number(self.order, "order", who=who, minimum=0.0, strict=True))
        rpm = np.atleast_1d(v.array(self.rpm, "rpm", None, who=who))
        if rpm.ndim != 1:
            raise ArgumentError(f"{who}: rpm: expected a speed or a list of speeds, got {self.rpm!r}",
                                argument="rpm", received=self.rpm)
        if np.any(rpm <= 0) or np.any(np.diff(rpm) <= 0):
            raise ArgumentError(f"{who}: rpm: speeds must be positive and increasing, got {rpm.tolist()}",
                                argument="rpm", received=self.rpm)
        object.__setattr__(self, "rpm", rpm)
        if self.force is None and self.moment is None:
            raise ArgumentError(f"{who}: give force=, moment= or both", argument="force")
        for key in ("force", "moment"):
            value = getattr(self, key)
            if value is not None:
                a = v.array(value, key, None, who=who)
                if a.shape not in ((3,), (rpm.size, 3)):
                    raise ArgumentError(f"{who}: {key}: expected 3 amplitudes or one row of 3 per speed "
                                        f"({rpm.size} x 3), got shape {a.shape}", argument=key, received=value)
                object.__setattr__(self, key, np.broadcast_to(a, (rpm.size, 3)).copy())
        phase = np.zeros(6) if self.phase is None else v.array(self.phase, "phase", (6,), who=who)
        object.__setattr__(self, "phase", phase)

    def phasors(self, model: Model, rpm: np.ndarray) -> np.ndarray:
        """(6, n) complex generalised force at the COG [N, N m] at each shaft speed [rpm]."""
        who = f"order force {self.name!r}"
        _body(model, self.body, who)
        rpm = np.asarray(rpm, float)
        if self.rpm.size > 1 and (rpm.min() < self.rpm[0] * (1 - 1e-12) or rpm.max() > self.rpm[-1] * (1 + 1e-12)):
            raise ArgumentError(f"{who}: speeds {rpm.min():g} ... {rpm.max():g} rpm leave the table's "
                                f"{self.rpm[0]:g} ... {self.rpm[-1]:g} rpm", argument="rpm")
        table = np.hstack([np.zeros((self.rpm.size, 3)) if self.force is None else self.force,
                           np.zeros((self.rpm.size, 3)) if self.moment is None else self.moment])
        amp = np.array([_interp(rpm, self.rpm, table[:, j]) for j in range(6)])
        return amp * np.exp(1j * self.phase)[:, None]


def _interp(x: np.ndarray, xp: np.ndarray, fp: np.ndarray) -> np.ndarray:
    """Table lookup: log-log between positive amplitudes (exact for power laws such as an inertia
    force growing with speed squared), linear where the column has zeros or signs."""
    if xp.size == 1:
        return np.full(x.size, fp[0])
    if np.all(fp > 0):
        return np.exp(np.interp(np.log(x), np.log(xp), np.log(fp)))
    return np.interp(x, xp, fp)


Source = Unbalance | OrderForce


def generalized_forces(model: Model, sources: Sequence[Source], rpm: np.ndarray) -> dict[tuple[str, float], np.ndarray]:
    """Phasors grouped by (body, order): ``{(body, order): (6, n) complex}`` [N, N m]."""
    out: dict[tuple[str, float], np.ndarray] = {}
    for s in sources:
        key = (s.body, float(s.order))
        out[key] = out.get(key, 0.0) + s.phasors(model, rpm)
    return out



def sources_from_settings(model: Model) -> list[Source]:
    """The sources of a model file's ``[orders]`` table (``model.settings["orders"]``); [] if none."""
    spec = (model.settings or {}).get("orders", {})
    return ([Unbalance(**d) for d in spec.get("unbalance", [])]
            + [OrderForce(**d) for d in spec.get("force", [])])


__getattr__ = module_aliases("vibss.orders.sources", {
    "generalised_forces": ("vibss.orders.sources.generalized_forces", lambda: generalized_forces)})
