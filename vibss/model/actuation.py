"""Actuators and sensors: the control elements of a model (frozen, validated like the rest).

An :class:`Actuator` is a force (or moment) pair: ``+f d`` on its body at a point and ``-f d`` on
its ``to`` side (another body at the same global point, or ground), along a unit direction ``d``;
either given directly or taken from a mount (``mount`` + local ``axis``: in parallel with it). Its
input signal is ``actuator.<name>.f`` [N] (``.m`` [N m] for a moment actuator). An optional
first-order ``bandwidth`` [Hz] (or any SISO python-control ``dynamics``) sits between the
command and the force in the control plants of :mod:`vibss.control`; the ``.f`` signal itself is
the force.

A :class:`Sensor` is a named output ``sensor.<name>``: the absolute displacement [m], velocity [m/s]
or acceleration [m/s^2] of a point along a direction (geophone, accelerometer); the relative
displacement or velocity across a mount (``mount`` + ``axis``) or between a point and the same
global point of ``to`` (a body or ground; stroke sensors); or the force through a mount along an
axis or direction [N] (a load cell under the mount: the force the mount, and every actuator acting in
parallel with it, transmit into its ``to`` side).

Examples
--------
>>> a = Actuator("lift", body="table", direction=[0, 0, 1], at=[0.1, 0.0, 0.0])
>>> s = Sensor("geo", "velocity", body="table", direction=[0, 0, 1])
>>> a.signal, s.signal, s.unit
('actuator.lift.f', 'sensor.geo', 'm/s')
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validate import is_numeric
from ..errors import ModelError
from ._common import GROUND, _frame, _signal_safe, _vec, unit_direction

__all__ = ["Actuator", "Sensor", "SENSOR_KINDS", "ACTUATOR_KINDS", "noise_psd"]

ACTUATOR_KINDS = ("force", "moment")
"""What an actuator applies."""

SENSOR_KINDS = {
    "displacement": ("m", 0), "velocity": ("m/s", 1), "acceleration": ("m/s^2", 2),
    "relative_displacement": ("m", 0), "relative_velocity": ("m/s", 1), "mount_force": ("N", 0),
}
"""Sensor kinds: their SI unit and the time-derivative order of what they measure."""


def _element_name(value: Any, who: str) -> str:
    if not isinstance(value, str) or not value.strip():
        raise ModelError(f"{who}: name must be a non-empty string, got {value!r}")
    return _signal_safe(value, f"{who} {value!r}")


def _axis(value: Any, who: str) -> int | None:
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or int(value) not in (1, 2, 3):
        raise ModelError(f"{who}: axis must be 1, 2 or 3 (a local axis of the mount), got {value!r}")
    return int(value)


def _direction(value: Any, who: str) -> np.ndarray | None:
    if value is None:
        return None
    d = _vec(value, 3, who, "direction")
    out = unit_direction(d)
    if out is None:
        raise ModelError(f"{who}: direction must be a nonzero vector, got {d.tolist()}")
    return out


@dataclass(frozen=True, eq=False)
class Actuator:
    """A force or moment pair between a body and ground or another body.

    Parameters
    ----------
    name : str
        Unique name; the input signal is ``actuator.<name>.f`` (``.m`` for a moment).
    body : str or None
        The body the actuator pushes (``+f d``). With ``mount``: the mount's body (may be omitted).
    to : str or None
        ``"ground"`` (default) or the body that takes the reaction ``-f d`` at the same global point.
        With ``mount``: the mount's ``to`` side.
    at : (3,) array_like
        Point of action [m], relative to the body's COG (``frame="body"``) or global. With
        ``mount``: the mount's point.
    frame : {"body", "global"}
        How ``at`` is measured.
    direction : (3,) array_like or None
        Line of action in global axes (normalised); or use ``mount`` and ``axis``.
    mount : str or None
        Act in parallel with this mount, along its local ``axis``.
    axis : {1, 2, 3} or None
        Local axis of ``mount``.
    bandwidth : float or None
        First-order actuator bandwidth [Hz]: force = command / (1 + s / (2 pi bandwidth)) in the
        control plants; None: ideal (force = command).
    kind : {"force", "moment"}
        A force along ``direction``, or a moment about it [N m].
    dynamics : python-control LTI system or None
        Any SISO transfer from command to force (Python only; instead of ``bandwidth``).
    """

    name: str
    body: str | None = None
    to: str | None = None
    at: Any = (0.0, 0.0, 0.0)
    frame: str = "body"
    direction: Any = None
    mount: str | None = None
    axis: int | None = None
    bandwidth: float | None = None
    kind: str = "force"
    dynamics: Any = None

    def __post_init__(self) -> None:
        who = f"actuator {self.name!r}"
        _element_name(self.name, "actuator")
        if self.kind not in ACTUATOR_KINDS:
            raise ModelError(f"{who}: kind must be one of {list(ACTUATOR_KINDS)}, got {self.kind!r}")
        object.__setattr__(self, "at", _vec(self.at, 3, who, "at"))
        object.__setattr__(self, "frame", _frame(self.frame, who))
        object.__setattr__(self, "axis", _axis(self.axis, who))
        object.__setattr__(self, "direction", _direction(self.direction, who))
        _placement(self, who, needs_body=True)
        if self.bandwidth is not None:
            if not is_numeric(self.bandwidth) or not np.isfinite(self.bandwidth) or self.bandwidth <= 0:
                raise ModelError(f"{who}: bandwidth must be a frequency > 0 [Hz], got {self.bandwidth!r}")
            object.__setattr__(self, "bandwidth", float(self.bandwidth))
        if self.dynamics is not None:
            if self.bandwidth is not None:
                raise ModelError(f"{who}: give bandwidth or dynamics, not both")
            if getattr(self.dynamics, "ninputs", None) != 1 or getattr(self.dynamics, "noutputs", None) != 1:
                raise ModelError(f"{who}: dynamics must be a SISO python-control system (command -> "
                                 f"force), got {self.dynamics!r}")

    @property
    def signal(self) -> str:
        """The input signal: ``actuator.<name>.f`` (force [N]) or ``.m`` (moment [N m])."""
        return f"actuator.{self.name}.{'f' if self.kind == 'force' else 'm'}"

    @property
    def command(self) -> str:
        """The command signal of the control plants, ``actuator.<name>.u`` [N or N m]."""
        return f"actuator.{self.name}.u"


@dataclass(frozen=True, eq=False)
class Sensor:
    """A named measurement ``sensor.<name>`` (see the module docstring for the kinds).

    Parameters
    ----------
    name : str
        Unique name; the output signal is ``sensor.<name>``.
    kind : str
        One of :data:`SENSOR_KINDS`.
    body : str or None
        The body the sensor sits on (absolute and relative kinds without ``mount``).
    at : (3,) array_like
        Point [m] (frame as ``frame``).
    frame : {"body", "global"}
        How ``at`` is measured.
    direction : (3,) array_like or None
        Sensing direction in global axes (normalised); or ``mount`` + ``axis``.
    to : str or None
        Relative kinds: ``"ground"`` or the body whose motion at the same global point is
        subtracted.
    mount : str or None
        Relative kinds: measure across this mount (its deflection ``body side - to side``);
        ``mount_force``: the force through it.
    axis : {1, 2, 3} or None
        Local axis of ``mount``.
    noise : float, callable, (frequency_hz, level) pair or None
        The measurement noise's one-sided PSD [unit^2/Hz, the sensor's unit]: a constant (white),
        a function of frequency [Hz] (a :class:`vibss.random.PSD` is one), or a table of levels
        at frequencies joined log-log (:meth:`noise_psd`); used by
        :meth:`vibss.control.ClosedLoop.noise_budget`. None: a noiseless sensor.
    """

    name: str
    kind: str
    body: str | None = None
    at: Any = (0.0, 0.0, 0.0)
    frame: str = "body"
    direction: Any = None
    to: str | None = None
    mount: str | None = None
    axis: int | None = None
    noise: Any = None

    def __post_init__(self) -> None:
        who = f"sensor {self.name!r}"
        object.__setattr__(self, "noise", _noise(self.noise, who))
        _element_name(self.name, "sensor")
        if self.kind not in SENSOR_KINDS:
            raise ModelError(f"{who}: kind must be one of {list(SENSOR_KINDS)}, got {self.kind!r}")
        object.__setattr__(self, "at", _vec(self.at, 3, who, "at"))
        object.__setattr__(self, "frame", _frame(self.frame, who))
        object.__setattr__(self, "axis", _axis(self.axis, who))
        object.__setattr__(self, "direction", _direction(self.direction, who))
        if self.kind in ("displacement", "velocity", "acceleration"):
            if self.mount is not None or self.to is not None:
                raise ModelError(f"{who}: an absolute {self.kind} sensor takes body, at and direction "
                                 "(not mount or to); use kind 'relative_...' for motion across a mount")
            if self.body is None or self.direction is None:
                raise ModelError(f"{who}: an absolute {self.kind} sensor needs body and direction")
        elif self.kind == "mount_force":
            if self.mount is None:
                raise ModelError(f"{who}: a mount_force sensor needs mount (and axis or direction)")
            if (self.axis is None) == (self.direction is None):
                raise ModelError(f"{who}: give the force component by axis (1, 2, 3: the mount's local "
                                 "axes) or by direction (global), one of them")
            if self.body is not None or self.to is not None:
                raise ModelError(f"{who}: a mount_force sensor takes mount and axis/direction, not body or to")
        else:
            _placement(self, who, needs_body=True)

    @property
    def signal(self) -> str:
        """The output signal, ``sensor.<name>``."""
        return f"sensor.{self.name}"

    @property
    def unit(self) -> str:
        """SI unit of the measurement."""
        return SENSOR_KINDS[self.kind][0]

    @property
    def order(self) -> int:
        """Time-derivative order of the measured motion (0 for forces and displacements)."""
        return SENSOR_KINDS[self.kind][1]

    def noise_psd(self, frequency_hz: Any) -> np.ndarray:
        """The noise PSD at ``frequency_hz`` [Hz] in [unit^2/Hz] (zeros for a noiseless sensor)."""
        return noise_psd(self.noise, frequency_hz)


def _noise(value: Any, who: str) -> Any:
    """A sensor's noise: None, a constant >= 0, a callable, or a (frequency_hz, level) table."""
    if value is None or callable(value):
        return value
    if is_numeric(value) and np.ndim(value) == 0:
        if not np.isfinite(value) or value < 0:
            raise ModelError(f"{who}: noise: a constant PSD must be finite and >= 0 [unit^2/Hz], got {value!r}")
        return float(value)
    try:
        f, lev = (np.asarray(x, dtype=float).ravel() for x in value)
    except (TypeError, ValueError):
        f = lev = np.zeros(0)
    if (f.size < 2 or f.shape != lev.shape or not np.all(np.isfinite(f)) or not np.all(np.isfinite(lev))
            or np.any(f <= 0) or np.any(np.diff(f) <= 0) or np.any(lev <= 0)):
        raise ModelError(f"{who}: noise: expected a PSD [unit^2/Hz]: a constant, a function of frequency [Hz], "
                         "or (frequency_hz, level) with at least 2 increasing frequencies > 0 and levels > 0, "
                         f"got {value!r}")
    f.setflags(write=False)
    lev.setflags(write=False)
    return (f, lev)


def noise_psd(spec: Any, frequency_hz: Any) -> np.ndarray:
    """A noise PSD spec (as :class:`Sensor`'s ``noise``) at ``frequency_hz`` [Hz]: a table is
    joined log-log and held flat beyond its ends."""
    f = np.asarray(frequency_hz, dtype=float)
    if spec is None:
        return np.zeros_like(f)
    if callable(spec):
        return np.broadcast_to(np.asarray(spec(f), dtype=float), f.shape).copy()
    if isinstance(spec, float):
        return np.full_like(f, spec)
    ft, lev = spec
    x = np.log(np.clip(f, ft[0], ft[-1]))
    return np.exp(np.interp(x, np.log(ft), np.log(lev)))


def _placement(e: Any, who: str, needs_body: bool) -> None:
    """Check a two-sided element: either a mount + axis, or body, to and a direction."""
    if e.mount is not None:
        if not isinstance(e.mount, str):
            raise ModelError(f"{who}: mount must be a mount name, got {e.mount!r}")
        if e.axis is None and e.direction is None:
            raise ModelError(f"{who}: with mount {e.mount!r}, give axis = 1, 2 or 3 (its local axes) "
                             "or a direction")
        if e.axis is not None and e.direction is not None:
            raise ModelError(f"{who}: give axis or direction, not both")
        return
    if e.axis is not None:
        raise ModelError(f"{who}: axis = {e.axis} needs mount (the mount whose local axis it is)")
    if needs_body and (not isinstance(e.body, str) or not e.body):
        raise ModelError(f"{who}: needs body (or mount and axis), got body={e.body!r}")
    if e.direction is None:
        raise ModelError(f"{who}: needs a direction (global axes), or mount and axis")
    if e.to is not None and not isinstance(e.to, str):
        raise ModelError(f"{who}: to must be 'ground' or a body name, got {e.to!r}")


def resolve(model: Any, e: Actuator | Sensor) -> tuple[str, str, np.ndarray, np.ndarray]:
    """Where a two-sided element acts: ``(body, to, point, direction)``.

    Parameters
    ----------
    model : Model
        The model holding it.
    e : Actuator or Sensor
        A mount-based or explicit element.

    Returns
    -------
    body, to : str
        The two sides (``to`` may be ``"ground"``).
    point : (3,) ndarray
        Global point of action [m].
    direction : (3,) ndarray
        Unit direction in global axes.
    """
    if e.mount is not None:
        m = {x.name: x for x in model.mounts}[e.mount]
        d = m.orientation.matrix[:, e.axis - 1] if e.axis is not None else e.direction
        return m.body, m.to, model.mount_point(m), np.asarray(d, dtype=float)
    body = str(e.body)
    to = GROUND if e.to is None else e.to
    point = model.point(body, e.at, e.frame) + model.body(body).cog
    return body, to, point, np.asarray(e.direction, dtype=float)
