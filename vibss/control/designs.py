"""Decentralised isolator loops: skyhook, direct velocity feedback, integral force feedback, PID.

Each design pairs every actuator of a :func:`vibss.control.plant` with one measurement and returns a
named :class:`~vibss.control.loop.Controller` ``u = K y`` (negative feedback: ``u_i = -g_i ... y_i``):

========================  =========================  ===============================================
design                    measurement kind           law per loop
========================  =========================  ===============================================
:func:`skyhook`           absolute ``velocity``      ``u = -c v`` (a damper to an inertial "sky")
:func:`velocity_feedback` ``relative_velocity``      ``u = -c v_rel`` (an active damper across a mount)
:func:`integral_force`    ``mount_force``            ``u = g / (s + w_l) F`` (integral force feedback;
                                                     ``F`` the force into the base, actuator included)
:func:`pid`               any                        ``u = -(kp + ki / s + kd s / (tau s + 1)) y``
========================  =========================  ===============================================

Pairs are found automatically when each actuator has exactly one measurement of the right kind at
the same point along the same line (collocated), or given as ``{actuator: measurement}``.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from ..errors import ControlDesignError, ModelError
from ..linear.plant.names import control_name
from ..model.actuation import resolve
from .loop import Controller, controller
from .plant import vibss_name

__all__ = ["skyhook", "velocity_feedback", "integral_force", "pid", "pairs"]


def _sensor(plant: Any, label: str) -> Any:
    name = vibss_name(label)
    if not name.startswith("sensor."):
        return None
    return {s.name: s for s in plant.model.sensors}.get(name[len("sensor."):])


def _actuator(plant: Any, label: str) -> Any:
    name = vibss_name(label)[len("actuator."):].rsplit(".", 1)[0]
    return {a.name: a for a in plant.actuator_elements}[name]


def _where(model: Any, e: Any) -> tuple[np.ndarray, np.ndarray]:
    if getattr(e, "kind", "") == "mount_force":
        m = {x.name: x for x in model.mounts}[e.mount]
        d = m.orientation.matrix[:, e.axis - 1] if e.axis is not None else e.direction
        return model.mount_point(m), np.asarray(d)
    _, _, point, d = resolve(model, e)
    return point, d


def pairs(plant: Any, kinds: Sequence[str], given: Mapping[str, str] | None = None) -> list[tuple[str, str]]:
    """``(command, measurement)`` label pairs of a plant, one per actuator (python-control spelling).

    Parameters
    ----------
    plant : GeneralizedPlant
        From :func:`vibss.control.plant`.
    kinds : sequence of str
        Sensor kinds a measurement may have (:data:`vibss.model.actuation.SENSOR_KINDS`).
    given : mapping or None
        ``{actuator name or command: measurement}``; default: the collocated sensor of each actuator.

    Raises
    ------
    ControlDesignError
        An actuator without (or with several) collocated measurements of the right kind.
    """
    if not hasattr(plant, "groups") or not hasattr(plant, "model"):
        raise ModelError("plant: expected a vibss.control.plant(...) (it knows the actuators and sensors)")
    out = []
    ys = plant.groups["y"]
    for lab in plant.groups["u"]:
        a = _actuator(plant, lab)
        if given is not None:
            key = next((k for k in (a.name, vibss_name(lab), lab) if k in given), None)
            if key is None:
                raise ModelError(f"pairs: no measurement given for actuator {a.name!r}")
            y = control_name(str(given[key]))
            if y not in ys:
                raise ModelError(f"pairs: {vibss_name(y)!r} (for actuator {a.name!r}) is not a measurement "
                                 f"of the plant; measurements are {[vibss_name(s) for s in ys]}")
            s = _sensor(plant, y)
            if s is not None and s.kind not in kinds:
                raise ControlDesignError(f"pairs: sensor {s.name!r} measures {s.kind}; this design needs "
                                         f"{' or '.join(kinds)}")
            out.append((lab, y))
            continue
        pa, da = _where(plant.model, a)
        found = []
        for y in ys:
            s = _sensor(plant, y)
            if s is None or s.kind not in kinds:
                continue
            ps, ds = _where(plant.model, s)
            if np.allclose(ps, pa, atol=1e-9) and abs(abs(float(ds @ da)) - 1.0) < 1e-9:
                found.append((y, float(np.sign(ds @ da))))
        if len(found) != 1:
            what = "no" if not found else f"{len(found)}"
            raise ControlDesignError(f"actuator {a.name!r}: {what} collocated {' or '.join(kinds)} sensors "
                                     "(same point, same line) among the measurements; pair them with "
                                     "pairs={actuator: measurement}")
        out.append((lab, found[0][0]))
    return out


_find_pairs = pairs


def _gains(plant: Any, gains: Any, what: str, unit: str) -> np.ndarray:
    labs = plant.groups["u"]
    if isinstance(gains, Mapping):
        g = []
        for lab in labs:
            a = _actuator(plant, lab)
            key = next((k for k in (a.name, vibss_name(lab), lab) if k in gains), None)
            if key is None:
                raise ModelError(f"{what}: no gain for actuator {a.name!r}; give one per actuator")
            g.append(gains[key])
        out = np.array(g, dtype=float)
    else:
        out = np.broadcast_to(np.asarray(gains, dtype=float), (len(labs),)).copy()
    if not np.all(np.isfinite(out)) or np.any(out < 0):
        raise ModelError(f"{what}: expected gains >= 0 [{unit}], got {gains!r}")
    return out


def _sign(plant: Any, lab: str, y: str) -> float:
    """+1 when the measurement's positive direction is the actuator's, -1 when opposite."""
    s = _sensor(plant, y)
    if s is None:
        return 1.0
    a = _actuator(plant, lab)
    return float(np.sign(_where(plant.model, s)[1] @ _where(plant.model, a)[1]) or 1.0)


def _static(plant: Any, gains: Any, kinds: Sequence[str], given: Any, design: str, unit: str) -> Controller:
    pr = _find_pairs(plant, kinds, given)
    g = _gains(plant, gains, "gains", unit)
    ins = list(dict.fromkeys(y for _, y in pr))
    D = np.zeros((len(pr), len(ins)))
    for i, (lab, y) in enumerate(pr):
        D[i, ins.index(y)] = -g[i] * _sign(plant, lab, y)
    return controller(np.zeros((0, 0)), np.zeros((0, len(ins))), np.zeros((len(pr), 0)), D,
                      [vibss_name(y) for y in ins], [vibss_name(u) for u, _ in pr],
                      {"design": design, "gains [" + unit + "]": dict(zip([vibss_name(u) for u, _ in pr], g.tolist())),
                       "pairs": {vibss_name(u): vibss_name(y) for u, y in pr}}, name=design)


def skyhook(plant: Any, gains: float | Mapping[str, float], pairs: Mapping[str, str] | None = None) -> Controller:
    """Skyhook damping: each actuator pushes against its collocated absolute velocity, ``u = -c v``.

    Parameters
    ----------
    plant : GeneralizedPlant
        With absolute ``velocity`` sensors among its measurements.
    gains : float or mapping
        Damping ``c`` [N s/m] (one for all, or per actuator).
    pairs : mapping or None
        ``{actuator: measurement}``; default: the collocated velocity sensor of each actuator.

    Returns
    -------
    Controller
        Static gains; with ideal collocated actuators the loop cannot go unstable.
    """
    return _static(plant, gains, ("velocity",), pairs, "skyhook", "N s/m")


def velocity_feedback(plant: Any, gains: float | Mapping[str, float],
                      pairs: Mapping[str, str] | None = None) -> Controller:
    """Direct velocity feedback across mounts: ``u = -c v_rel`` (an active viscous damper).

    Parameters
    ----------
    plant : GeneralizedPlant
        With ``relative_velocity`` sensors.
    gains : float or mapping
        Damping ``c`` [N s/m].
    pairs : mapping or None
        As :func:`skyhook`.
    """
    return _static(plant, gains, ("relative_velocity",), pairs, "velocity feedback", "N s/m")


def integral_force(plant: Any, gains: float | Mapping[str, float], leak_hz: float = 0.0,
                   pairs: Mapping[str, str] | None = None) -> Controller:
    """Integral force feedback: ``u = g / (s + w_l) F`` on the force the collocated mount and its
    actuator transmit into the base (``F = k delta + c delta' - u``: ``u`` then acts like a damper
    to an inertial point, ``-g m v`` for a single mass).

    Parameters
    ----------
    plant : GeneralizedPlant
        With ``mount_force`` sensors.
    gains : float or mapping
        ``g`` [rad/s] (one for all, or per actuator).
    leak_hz : float
        Corner frequency of the leaky integrator [Hz] (0: a pure integrator).
    pairs : mapping or None
        As :func:`skyhook`.
    """
    if not np.isfinite(leak_hz) or leak_hz < 0:
        raise ModelError(f"leak_hz: expected a frequency >= 0 [Hz], got {leak_hz!r}")
    pr = _find_pairs(plant, ("mount_force",), pairs)
    g = _gains(plant, gains, "gains", "rad/s")
    ins = list(dict.fromkeys(y for _, y in pr))
    n = len(pr)
    wl = 2 * np.pi * leak_hz
    B = np.zeros((n, len(ins)))
    for i, (lab, y) in enumerate(pr):
        B[i, ins.index(y)] = _sign(plant, lab, y)
    return controller(-wl * np.eye(n), B, np.diag(g), np.zeros((n, len(ins))),
                      [vibss_name(y) for y in ins], [vibss_name(u) for u, _ in pr],
                      {"design": "integral force feedback", "gains [rad/s]": g.tolist(), "leak [Hz]": leak_hz,
                       "pairs": {vibss_name(u): vibss_name(y) for u, y in pr}}, name="integral_force",
                      states=[f"{vibss_name(u)}:integral".replace(".", ":") for u, _ in pr])


def pid(plant: Any, pairs: Mapping[str, str], kp: Any = 0.0, ki: Any = 0.0, kd: Any = 0.0,
        tau: float = 1e-3) -> Controller:
    """Decentralised PID loops ``u = -(kp + ki / s + kd s / (tau s + 1)) y``.

    Parameters
    ----------
    plant : GeneralizedPlant
    pairs : mapping
        ``{actuator: measurement}`` (any measurement kind).
    kp, ki, kd : float or mapping
        Gains per actuator (units: command per measurement unit, per s, times s).
    tau : float
        Derivative filter time constant [s].
    """
    pr = _find_pairs(plant, _ALL_KINDS, pairs)
    gp, gi, gd = (_gains(plant, v, name, "-") for v, name in ((kp, "kp"), (ki, "ki"), (kd, "kd")))
    if not tau > 0:
        raise ModelError(f"tau: expected a time constant > 0 [s], got {tau!r}")
    import control

    parts = []
    for i, (lab, y) in enumerate(pr):
        c = control.ss(control.tf([gp[i]], [1.0]))
        if gi[i]:
            c = control.parallel(c, control.ss(control.tf([gi[i]], [1.0, 0.0])))
        if gd[i]:
            c = control.parallel(c, control.ss(control.tf([gd[i], 0.0], [tau, 1.0])))
        parts.append(-_sign(plant, lab, y) * c)
    sys = control.append(*parts)
    ins = [vibss_name(y) for _, y in pr]
    if len(set(ins)) != len(ins):
        raise ModelError("pairs: two actuators share a measurement; pid pairs one measurement per actuator")
    return controller(sys.A, sys.B, sys.C, sys.D, ins, [vibss_name(u) for u, _ in pr],
                      {"design": "pid", "kp": gp.tolist(), "ki": gi.tolist(), "kd": gd.tolist(), "tau [s]": tau,
                       "pairs": {vibss_name(u): vibss_name(y) for u, y in pr}}, name="pid")


_ALL_KINDS = ("displacement", "velocity", "acceleration", "relative_displacement", "relative_velocity",
              "mount_force")
