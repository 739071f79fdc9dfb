"""Named input and output signals of a study, and the :class:`~vibss.linear.plant.plant.Plant` they define.

Signal names (fixed; every analysis, result and the command line use them)
-------------------------------------------------------------------------
Inputs (``u``):

========================================  =====================================================
``<body>.fx`` ``.fy`` ``.fz``             force at the body's COG, global axes [N]
``<body>.mx`` ``.my`` ``.mz``             moment on the body, global axes [N m]
``<point>.fx`` ``.fy`` ``.fz``            force at a control point [N]
``<body|ground|support>.<dof>.disp``      prescribed displacement of a DOF [m, rad]
``<body|ground|support>.<dof>.vel``       prescribed velocity [m/s, rad/s]
``<body|ground|support>.<dof>.acc``       prescribed acceleration [m/s^2, rad/s^2]
``actuator.<name>.f`` / ``.m``            force [N] (moment [N m]) of an actuator: ``+f d`` on
                                          its body, ``-f d`` on its ``to`` side
========================================  =====================================================

``<dof>`` is one of ``x y z rx ry rz``. Ground DOFs are the rigid motion of ground about the global
origin (``ground.z.disp`` moves every ground attachment point in z; ``ground.rx.disp`` rotates
ground about the global X axis). A named support (:class:`vibss.model.mounts.Support`) is a ground
of its own: ``<support>.z.acc`` moves the ``to`` ends of the mounts with ``support=<support>`` and
nothing else (``ground.*`` moves the mounts on the rigid ground only). A prescribed body DOF leaves the unknowns: the plant's free DOFs
exclude it, and its motion drives the others through the coupling stiffness, damping and mass (the
handbook program's flags 2-4). An :class:`vibss.model.excitation.Excitation` is accepted as an input too
(named by its ``signal``); one with a ``direction`` gives one force column along that unit vector
(applied at ``at``, or the COG), or one ground translation along it.

Outputs (``y``):

========================================  =====================================================
``<body>.<dof>``                          displacement of a body DOF [m, rad]
``<body>.<dof>.vel`` / ``.acc``           its velocity / acceleration
``<point>.x|y|z`` (+ ``.vel``, ``.acc``)  motion of a control point, global axes
``mount.<name>.dx|dy|dz``                 mount deflection delta = d_body - d_to, global axes [m]
``mount.<name>.d1|d2|d3``                 the same in the mount's local (principal) axes
``mount.<name>.fx|fy|fz`` / ``.f1|f2|f3`` force the mount transmits into its ``to`` side,
                                          K delta + C delta' (+ i H delta in frequency) [N]
``mount.<name>.rx|ry|rz`` / ``.r1|r2|r3`` relative rotation theta_body - theta_to [rad]
``mount.<name>.mx|my|mz`` / ``.m1|m2|m3`` moment a 6x6 mount transmits into its ``to`` side,
                                          Kr theta + Cr theta' [N m]
``ground.fx|fy|fz|mx|my|mz``              total force [N] and moment about the global origin
                                          [N m] transmitted into ground by the mounts (those
                                          on the rigid ground, not on a support)
``<support>.fx|fy|fz|mx|my|mz``           the same into a support by its mounts
``<body>.into.fx|fy|fz|mx|my|mz``         total force [N] and moment about the body's COG
                                          [N m] transmitted into the body by the mounts whose
                                          ``to`` side it is (what rests on it); ``ground.into.*``
                                          is ``ground.*``. Both include the reactions of the
                                          actuators whose ``to`` side it is.
``sensor.<name>``                         a sensor's measurement (unit by its kind, see
                                          :mod:`vibss.model.actuation`)
========================================  =====================================================

The default outputs are the displacements of every body DOF. python-control forbids ``.`` in signal
names (it is its ``system.signal`` separator), so python-control objects carry the same names with
``.`` replaced by ``:`` (:func:`control_name`); the systems :func:`vibss.statespace` returns
(:class:`vibss.linear.statespace.NamedStateSpace`) accept either spelling when indexed.

Examples
--------
>>> from ... import Body, Model, Mount, MountType
>>> t = MountType("t", [1e4, 1e4, 1e4])
>>> m = Model([Body("b", 10.0, [1, 1, 1])], [Mount("m", t, "b")])
>>> p = build_plant(m, ["b.fz"], ["b.z", "mount.m.fz"])
>>> p.inputs, p.outputs, p.units
(('b.fz',), ('b.z', 'mount.m.fz'), ('m', 'N'))
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp

from .assemble import Assembly, assemble
from ...errors import ModelError, SignalError, did_you_mean
from ...model.geometry import point_transfer
from ..eigen.undamped import undamped
from ...model.actuation import resolve
from ...model.model import DOF_NAMES, GROUND, Model
from .branches import build_branches
from .plant import INPUT_KINDS, MountForm, Plant
from .memo import remembered

__all__ = ["build_plant", "control_name", "default_outputs", "INPUT_FORMS", "OUTPUT_FORMS"]

INPUT_FORMS = ("<body>.fx|fy|fz", "<body>.mx|my|mz", "<point>.fx|fy|fz",
               "<body|ground|support>.<x|y|z|rx|ry|rz>.disp|vel|acc", "actuator.<name>.f|m")
"""Valid input name forms (for messages)."""

OUTPUT_FORMS = ("<body>.<x|y|z|rx|ry|rz>[.vel|.acc]", "<point>.x|y|z[.vel|.acc]",
                "mount.<name>.dx|dy|dz|d1|d2|d3", "mount.<name>.fx|fy|fz|f1|f2|f3",
                "mount.<name>.rx|ry|rz|r1|r2|r3", "mount.<name>.mx|my|mz|m1|m2|m3",
                "<ground|support>.fx|fy|fz|mx|my|mz", "<body>.into.fx|fy|fz|mx|my|mz", "sensor.<name>")
"""Valid output name forms (for messages)."""

_MOTION = {"disp": "displacement", "vel": "velocity", "acc": "acceleration"}
_FORCE = {"fx": 0, "fy": 1, "fz": 2, "mx": 3, "my": 4, "mz": 5}
_DERIV = {"": 0, "vel": 1, "acc": 2}
_MOUNT = {"dx": ("d", "g", 0), "dy": ("d", "g", 1), "dz": ("d", "g", 2),
          "d1": ("d", "l", 0), "d2": ("d", "l", 1), "d3": ("d", "l", 2),
          "fx": ("f", "g", 0), "fy": ("f", "g", 1), "fz": ("f", "g", 2),
          "f1": ("f", "l", 0), "f2": ("f", "l", 1), "f3": ("f", "l", 2),
          "rx": ("r", "g", 0), "ry": ("r", "g", 1), "rz": ("r", "g", 2),
          "r1": ("r", "l", 0), "r2": ("r", "l", 1), "r3": ("r", "l", 2),
          "mx": ("m", "g", 0), "my": ("m", "g", 1), "mz": ("m", "g", 2),
          "m1": ("m", "l", 0), "m2": ("m", "l", 1), "m3": ("m", "l", 2)}


def control_name(name: str) -> str:
    """The python-control spelling of a vibss signal name (``.`` -> ``:``).

    Examples
    --------
    >>> control_name("mount.front.xz.f3")
    'mount:front:xz:f3'
    """
    return name.replace(".", ":")


def default_outputs(model: Model) -> tuple[str, ...]:
    """Displacement of every body DOF, ``'<body>.<dof>'`` in DOF order."""
    return tuple(f"{b}.{d}" for b in model.body_names for d in DOF_NAMES)


@dataclass(frozen=True)
class _Input:
    name: str
    kind: str
    force: np.ndarray | None = None      # (n,) generalised force, force inputs
    motion: np.ndarray | None = None     # (n + nz,) prescribed-coordinate direction, motion inputs


def _input_names(model: Model) -> list[str]:
    names = [f"{b}.{c}" for b in model.body_names for c in _FORCE]
    names += [f"{p.name}.{c}" for p in model.control_points for c in ("fx", "fy", "fz")]
    names += [f"{t}.{d}.{k}" for t in [*model.body_names, GROUND, *model.support_names]
              for d in DOF_NAMES for k in _MOTION]
    names += [a.signal for a in model.actuators]
    return names


def _output_names(model: Model) -> list[str]:
    names = [f"{b}.{d}{s}" for b in model.body_names for d in DOF_NAMES for s in ("", ".vel", ".acc")]
    names += [f"{p.name}.{d}{s}" for p in model.control_points for d in "xyz" for s in ("", ".vel", ".acc")]
    names += [f"mount.{m.name}.{c}" for m in model.mounts for c in _MOUNT]
    names += [f"{g}.{c}" for g in [GROUND, *model.support_names] for c in _FORCE]
    names += [f"{m}.into.{c}" for m in sorted({m.to for m in model.mounts}) for c in _FORCE]
    names += [s.signal for s in model.sensors]
    return names


def _bad_input(model: Model, name: Any, why: str = "") -> SignalError:
    return SignalError(f"inputs: unknown input signal {name!r}{why}; valid forms are "
                       f"{', '.join(INPUT_FORMS)}" + did_you_mean(name, _input_names(model)),
                       argument="inputs", received=name, expected=INPUT_FORMS)


def _bad_output(model: Model, name: Any, why: str = "") -> SignalError:
    return SignalError(f"outputs: unknown output signal {name!r}{why}; valid forms are "
                       f"{', '.join(OUTPUT_FORMS)}" + did_you_mean(name, _output_names(model)),
                       argument="outputs", received=name, expected=OUTPUT_FORMS)


def _point_force(asm: Assembly, body: str, r: np.ndarray, direction: np.ndarray) -> np.ndarray:
    f = np.zeros(asm.n)
    i = asm.model.body_index(body)
    f[6 * i:6 * i + 6] = point_transfer(r).T @ direction
    return f


def _grounds(model: Model) -> set[str]:
    """The ground nodes' names: ``ground`` and every support."""
    return {GROUND, *model.support_names}


def _node_index(model: Model, target: str) -> int:
    """Index of a body, the rigid ground (``n_bodies``) or a support (``n_bodies + 1 + s``) in the
    assembly's ``b_index``/``a_index`` numbering."""
    nb = len(model.bodies)
    if target == GROUND:
        return nb
    if target in model.support_names:
        return nb + 1 + model.support_names.index(target)
    return model.body_index(target)


def _motion_vector(asm: Assembly, target: str, dof_index: int) -> np.ndarray:
    v = np.zeros(asm.n + asm.nz)
    base = asm.ground_offset(target) if target in _grounds(asm.model) else 6 * asm.model.body_index(target)
    v[base + dof_index] = 1.0
    return v


def parse_input(asm: Assembly, item: Any) -> _Input:
    model = asm.model
    if not isinstance(item, str):
        return _parse_excitation(asm, item)
    bodies, points = set(model.body_names), {p.name: p for p in model.control_points}
    if item.startswith("actuator.") and (model.actuators or "actuator" not in points.keys() | bodies):
        return _actuator_input(asm, item)
    head, _, last = item.rpartition(".")
    if last in _MOTION:
        target, _, dof = head.rpartition(".")
        if dof not in DOF_NAMES:
            raise _bad_input(model, item, f" (DOF {dof!r} is not one of {list(DOF_NAMES)})")
        if target not in bodies and target not in _grounds(model):
            raise _bad_input(model, item, f" ({target!r} is neither a body nor 'ground' nor a support)")
        return _Input(item, _MOTION[last], motion=_motion_vector(asm, target, DOF_NAMES.index(dof)))
    if last in _FORCE:
        k = _FORCE[last]
        if head in bodies:
            f = np.zeros(asm.n)
            f[6 * model.body_index(head) + k] = 1.0
            return _Input(item, "force", force=f)
        if head in points and k < 3:
            p = points[head]
            return _Input(item, "force", force=_point_force(
                asm, p.body, model.point(p.body, p.at, p.frame), np.eye(3)[k]))
        if head in _grounds(model):
            raise _bad_input(model, item, f" (a force on {head!r} does nothing; prescribe its "
                                          f"motion, e.g. '{head}.z.disp')")
    raise _bad_input(model, item)


def actuator_wrench(model: Model, actuator: Any) -> tuple[str, str, np.ndarray, np.ndarray]:
    """Where an actuator acts: ``(body, to, point, w)`` with ``w`` (6,) the force and moment per
    unit input applied at ``point`` (global) [N/N, N m/N m]."""
    body, to, point, d = resolve(model, actuator)
    w = np.concatenate([d, np.zeros(3)]) if actuator.kind == "force" else np.concatenate([np.zeros(3), d])
    return body, to, point, w


def _actuator_input(asm: Assembly, item: str) -> _Input:
    model = asm.model
    head, _, comp = item[len("actuator."):].rpartition(".")
    found = {a.name: a for a in model.actuators}
    a = found.get(head)
    if a is None:
        raise _bad_input(model, item, f" (no actuator named {head!r}; actuators are {sorted(found)})")
    if item != a.signal:
        raise _bad_input(model, item, f" (actuator {head!r} is a {a.kind} actuator: its signal is "
                                      f"{a.signal!r})")
    body, to, point, w = actuator_wrench(model, a)
    f = np.zeros(asm.n)
    for side, sign in ((body, 1.0), (to, -1.0)):
        if side == GROUND:
            continue
        i = model.body_index(side)
        r = point - model.body(side).cog
        f[6 * i:6 * i + 3] += sign * w[:3]
        f[6 * i + 3:6 * i + 6] += sign * (np.cross(r, w[:3]) + w[3:])
    return _Input(item, "force", force=f)


def actuator_reactions(model: Model, inputs: Sequence[str], outputs: Sequence[str]) -> np.ndarray:
    """(p, m) feedthrough of actuator inputs into the ``ground.*`` and ``<body>.into.*`` outputs:
    the reaction ``-f d`` each actuator puts into its ``to`` side (moments about that side's
    reference point: the COG, or the global origin for ground); and into ``mount_force`` sensors of
    the mount an actuator acts in parallel with (a load cell under the pair carries both)."""
    out = np.zeros((len(outputs), len(inputs)))
    acts = {a.signal: a for a in model.actuators}
    cells = {s.signal: s for s in model.sensors if s.kind == "mount_force"}
    for j, u in enumerate(inputs):
        a = acts.get(u) if isinstance(u, str) else None
        if a is None:
            continue
        _, to, point, w = actuator_wrench(model, a)
        ref = np.zeros(3) if to == GROUND else model.body(to).cog
        wrench = -np.concatenate([w[:3], np.cross(point - ref, w[:3]) + w[3:]])
        for i, y in enumerate(outputs):
            cell = cells.get(y)
            if cell is not None and cell.mount == a.mount and a.kind == "force":
                m = next(x for x in model.mounts if x.name == cell.mount)
                d = m.orientation.matrix[:, cell.axis - 1] if cell.axis is not None else cell.direction
                out[i, j] = -float(d @ w[:3])      # a load cell under the mount carries its actuator too
                continue
            head, _, comp = y.rpartition(".")
            target = head[:-5] if head.endswith(".into") else head
            if target == to and comp in _FORCE and (head == GROUND or head.endswith(".into")):
                out[i, j] = wrench[_FORCE[comp]]
    return out


def _parse_excitation(asm: Assembly, exc: Any) -> _Input:
    model = asm.model
    try:
        kind, target, dof = exc.kind, exc.target, exc.dof
        direction, name = exc.direction, exc.signal
    except AttributeError:
        raise ModelError(f"inputs: expected a signal name or an Excitation, got {exc!r}") from None
    if kind not in INPUT_KINDS:
        raise ModelError(f"inputs: excitation {name!r}: kind {kind!r} is not one of {list(INPUT_KINDS)}")
    if target not in model.body_names and target not in _grounds(model):
        options = [*model.body_names, *model.support_names]
        raise ModelError(f"inputs: excitation {name!r}: unknown target {target!r}; bodies are "
                         f"{model.body_names}, or 'ground'"
                         + (f", or a support {model.support_names}" if model.supports else "")
                         + did_you_mean(target, options))
    if direction is not None:
        d = np.asarray(direction, dtype=float)
        d = d / np.linalg.norm(d)
    if kind == "force":
        if target in _grounds(model):
            raise ModelError(f"inputs: excitation {name!r}: a force on {target!r} does nothing")
        at = getattr(exc, "at", None)
        r = np.zeros(3) if at is None else model.point(target, at, getattr(exc, "frame", "body"))
        if dof is not None:
            k = DOF_NAMES.index(dof)
            if k >= 3:
                f = np.zeros(asm.n)
                f[6 * model.body_index(target) + k] = 1.0
                return _Input(name, kind, force=f)
            d = np.eye(3)[k]
        return _Input(name, kind, force=_point_force(asm, target, r, d))
    if dof is not None:
        return _Input(name, kind, motion=_motion_vector(asm, target, DOF_NAMES.index(dof)))
    axis = np.flatnonzero(np.abs(d) > 1e-12)
    if target in _grounds(model):
        v = np.zeros(asm.n + asm.nz)
        o = asm.ground_offset(target)
        v[o:o + 3] = d
        return _Input(name, kind, motion=v)
    if axis.size == 1:
        return _Input(name, kind, motion=_motion_vector(asm, target, int(axis[0])) * np.sign(d[axis[0]]))
    raise ModelError(f"inputs: excitation {name!r}: a prescribed {kind} of body {target!r} must drive "
                     f"one DOF (dof = 'x' ... 'rz'); a direction {d.tolist()} that mixes DOFs "
                     "cannot be prescribed (it would not remove a DOF)")


@dataclass
class _Rows:
    """Output rows over the full coordinate vector ``[q (n); q_ground (nz)]``."""

    d: np.ndarray   # displacement part
    v: np.ndarray   # velocity part
    a: np.ndarray   # acceleration part
    h: np.ndarray   # hysteretic part (times i)
    f: np.ndarray | None = None   # per unit force of each mount into its 'to' side (3 per mount)


def _mount_wrench(asm: Assembly, target: str) -> dict[str, np.ndarray]:
    """(6, n + nz) rows of the force and moment transmitted into ``target`` (a body, ground or a
    support) by the
    mounts whose ``to`` side it is.

    A mount's force into its ``to`` side is ``K delta + C delta' (+ i H delta)``, and a 6x6 mount's
    moment ``Kr theta + Cr theta'``. Moments are about the target's reference point: its COG (the
    global origin for ground). Keys ``"k"``, ``"c"``,
    ``"h"``: the displacement, velocity and hysteretic parts.
    """
    model = asm.model
    i = _node_index(model, target)
    b = asm.deflection_matrix()
    rows = {key: np.zeros((6, asm.n + asm.nz)) for key in ("k", "c", "h")}
    rows["f"] = np.zeros((6, 3 * len(model.mounts)))
    for p in np.flatnonzero(asm.a_index == i):
        lt = point_transfer(asm.r_a[p]).T                 # (6, 3): force at the point -> wrench
        bp = b[3 * p:3 * p + 3].toarray()
        for key, mat in (("k", asm.kp), ("c", asm.cp), ("h", asm.hp)):
            rows[key] += lt @ mat[p] @ bp
        rows["f"][:, 3 * p:3 * p + 3] = lt
        coupled = asm.has_coupling and (np.any(asm.kcp[p]) or np.any(asm.ccp[p]))
        if np.any(asm.krp[p]) or np.any(asm.crp[p]) or coupled:   # a 6x6 mount's own moment
            rp = asm.rotation_matrix()[3 * p:3 * p + 3].toarray()
            rows["k"][3:] += asm.krp[p] @ rp
            rows["c"][3:] += asm.crp[p] @ rp
            if coupled:                 # force kc theta at the point, moment kc^T delta
                for key, mat in (("k", asm.kcp), ("c", asm.ccp)):
                    rows[key] += lt @ mat[p] @ rp
                    rows[key][3:] += mat[p].T @ bp
    return rows


def output_row(asm: Assembly, name: Any, cache: dict) -> tuple[_Rows, str]:
    model = asm.model
    if not isinstance(name, str):
        raise ModelError(f"outputs: expected a signal name (str), got {name!r}")
    nf = asm.n + asm.nz
    zero = np.zeros(nf)
    bodies, points = set(model.body_names), {p.name: p for p in model.control_points}
    if name.startswith("sensor.") and (model.sensors or "sensor" not in points.keys() | bodies):
        return _sensor_row(asm, name)
    if name.startswith("mount."):
        head, _, comp = name[6:].rpartition(".")
        if comp not in _MOUNT:
            raise _bad_output(model, name, f" (component {comp!r} is not one of {list(_MOUNT)})")
        names = cache.setdefault("mounts", {m.name: i for i, m in enumerate(model.mounts)})
        if head not in names:
            raise _bad_output(model, name, f" (no mount named {head!r})")
        p = names[head]
        what, frame, k = _MOUNT[comp]
        b = asm.deflection_matrix()[3 * p:3 * p + 3].toarray()
        t = model.mounts[p].orientation.matrix
        axis = t[:, k] if frame == "l" else np.eye(3)[k]
        if what == "d":
            return _Rows(axis @ b, zero, zero, zero), "m"
        if what in ("r", "m"):
            rp = asm.rotation_matrix()[3 * p:3 * p + 3].toarray()
            if what == "r":
                return _Rows(axis @ rp, zero, zero, zero), "rad"
            mk, mc = axis @ asm.krp[p] @ rp, axis @ asm.crp[p] @ rp
            if asm.has_coupling:        # a full 6x6 matrix: the moment kc^T delta too
                mk, mc = mk + axis @ asm.kcp[p].T @ b, mc + axis @ asm.ccp[p].T @ b
            return _Rows(mk, mc, zero, zero), "N m"
        f = np.zeros(3 * len(model.mounts))
        f[3 * p:3 * p + 3] = axis
        fk, fc = axis @ asm.kp[p] @ b, axis @ asm.cp[p] @ b
        if asm.has_coupling:            # a full 6x6 matrix: the force kc theta too
            rp = asm.rotation_matrix()[3 * p:3 * p + 3].toarray()
            fk, fc = fk + axis @ asm.kcp[p] @ rp, fc + axis @ asm.ccp[p] @ rp
        return _Rows(fk, fc, zero, axis @ asm.hp[p] @ b, f), "N"
    head, _, comp = name.rpartition(".")
    target = head[:-5] if head.endswith(".into") else (head if head in _grounds(model) else None)
    if head.endswith(".into") and comp not in _FORCE:
        raise _bad_output(model, name, f" (component {comp!r} is not one of {list(_FORCE)})")
    if target is not None and comp in _FORCE:
        if target not in _grounds(model) and target not in bodies:
            what = "a control point, not a body" if target in points else "not a body"
            raise _bad_output(model, name, f" ({target!r} is {what})")
        if target not in _grounds(model) and not any(m.to == target for m in model.mounts):
            raise _bad_output(model, name, f" (no mount has {target!r} as its 'to' side: nothing "
                                           f"rests on it; see mount.<name>.f* for its own mounts)")
        k = _FORCE[comp]
        g = cache.get(("wrench", target))
        if g is None:
            g = cache[("wrench", target)] = _mount_wrench(asm, target)
        return _Rows(g["k"][k], g["c"][k], zero, g["h"][k], g["f"][k]), ("N" if k < 3 else "N m")
    base, _, suffix = name.rpartition(".")
    order = _DERIV.get(suffix)
    if order is None or order == 0:
        base, order = name, 0
    head, _, comp = base.rpartition(".")
    row = zero.copy()
    if head in bodies and comp in DOF_NAMES:
        k = DOF_NAMES.index(comp)
        row[6 * model.body_index(head) + k] = 1.0
        unit = "rad" if k >= 3 else "m"
    elif head in points and comp in ("x", "y", "z"):
        p = points[head]
        row[:asm.n] = asm.point_matrix(p.body, model.point(p.body, p.at, p.frame))["xyz".index(comp)]
        unit = "m"
    else:
        raise _bad_output(model, name)
    unit += ("", "/s", "/s^2")[order]
    parts = [zero, zero, zero]
    parts[order] = row
    return _Rows(parts[0], parts[1], parts[2], zero), unit


def _sensor_row(asm: Assembly, name: str) -> tuple[_Rows, str]:
    """Output rows of ``sensor.<name>`` over ``[q; q_ground]``."""
    model = asm.model
    found = {s.name: s for s in model.sensors}
    s = found.get(name[len("sensor."):])
    if s is None:
        raise _bad_output(model, name, f" (no sensor named {name[7:]!r}; sensors are {sorted(found)})")
    nf = asm.n + asm.nz
    zero = np.zeros(nf)
    if s.mount is not None:
        p = [m.name for m in model.mounts].index(s.mount)
        b = asm.deflection_matrix()[3 * p:3 * p + 3].toarray()
        t = model.mounts[p].orientation.matrix
        d = t[:, s.axis - 1] if s.axis is not None else s.direction
        if s.kind == "mount_force":
            fk, fc = d @ asm.kp[p] @ b, d @ asm.cp[p] @ b
            if asm.has_coupling:
                rp = asm.rotation_matrix()[3 * p:3 * p + 3].toarray()
                fk, fc = fk + d @ asm.kcp[p] @ rp, fc + d @ asm.ccp[p] @ rp
            return _Rows(fk, fc, zero, d @ asm.hp[p] @ b), s.unit
        row = d @ b
    else:
        body, to, point, d = resolve(model, s)
        row = zero.copy()
        row[:asm.n] = d @ asm.point_matrix(body, point - model.body(body).cog)
        if s.kind.startswith("relative"):
            if to == GROUND:
                row[asm.n:asm.n + 6] -= d @ point_transfer(point)
            else:
                row[:asm.n] -= d @ asm.point_matrix(to, point - model.body(to).cog)
    parts = [zero, zero, zero]
    parts[s.order] = row
    return _Rows(parts[0], parts[1], parts[2], zero), s.unit


def input_maps(asm: Assembly, parsed: Sequence[Any]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Generalised-force and prescribed-motion columns of parsed inputs, and the free DOFs.

    Parameters
    ----------
    asm : Assembly
        The assembled model.
    parsed : sequence
        Inputs parsed by :func:`parse_input` (each has ``force`` (n,) or ``motion`` (n + nz,)).

    Returns
    -------
    force : (n, m) ndarray
        Generalised force per unit force input.
    motion : (n + nz, m) ndarray
        Prescribed motion (body, ground and support DOFs) per unit motion input.
    free : (k,) int ndarray
        DOFs that are not prescribed (the unknowns).
    """
    n, m = asm.n, len(parsed)
    motion, force = np.zeros((n + asm.nz, m)), np.zeros((n, m))
    for j, p in enumerate(parsed):
        if p.force is not None:
            force[:, j] = p.force
        else:
            motion[:, j] = p.motion
    prescribed = np.flatnonzero(np.any(motion[:n] != 0, axis=1))
    free = np.setdiff1d(np.arange(n), prescribed)
    if free.size == 0:
        raise ModelError("inputs: every body DOF is prescribed; nothing is left to respond")
    return force, motion, free


def build_plant(model_or_assembly: Model | Assembly, inputs: Sequence[Any],
                outputs: Sequence[str] | None = None,
                modal_damping: float | Sequence[float] | None = None, sparse: bool = False) -> Plant:
    """The second-order plant of a study: free-DOF matrices plus the named input/output maps.

    Only the requested input columns and output rows are built.

    Parameters
    ----------
    model_or_assembly : Model or Assembly
        The system (a sparse assembly is densified unless ``sparse``).
    inputs : sequence of str or Excitation
        Input signals (see the module docstring), e.g. ``["engine.fz", "ground.z.acc"]``.
    outputs : sequence of str or None
        Output signals; default: the displacement of every body DOF.
    modal_damping : float, (n_free,) array_like or None
        Extra modal damping ratio(s) [-] of the free DOFs' undamped elastic modes (ascending
        frequency), added to C as ``M Phi diag(2 zeta w) Phi^T M``. It belongs to no mount, so
        mount and ground force outputs do not include it.
    sparse : bool
        Keep ``M, C, K, H`` as ``scipy.sparse`` CSR matrices (no dense n x n matrix): for large
        models, with ``frequency_response(plant, frequencies=..., method="sparse")`` or
        :func:`vibss.reduce`. Not with ``modal_damping``.

    Returns
    -------
    Plant

    Raises
    ------
    ModelError
        Unknown signal names (with the valid forms and a did-you-mean), duplicates, no inputs.

    Examples
    --------
    >>> from ... import Body, Model, Mount, MountType
    >>> t = MountType("t", [1e4, 1e4, 1e4])
    >>> m = Model([Body("b", 10.0, [1, 1, 1])], [Mount("m", t, "b")])
    >>> p = build_plant(m, ["ground.z.disp"], ["b.z"])
    >>> p.dofs[:3], p.kinds, float(p.Kz[2, 0])
    (('b.x', 'b.y', 'b.z'), ('displacement',), -10000.0)

    The plant of a small Model and signals named by strings is remembered
    (:mod:`vibss.linear.plant.memo`): the same model and signals give the same read-only Plant, with the
    modal basis and factorisations already cached on it.
    """
    if isinstance(model_or_assembly, Model) and modal_damping is None:
        key = _plant_key(inputs, outputs, sparse)
        if key is not None:
            return remembered(model_or_assembly, key,
                              lambda: _build_plant(model_or_assembly, inputs, outputs, None, sparse))
    return _build_plant(model_or_assembly, inputs, outputs, modal_damping, sparse)


def _plant_key(inputs: Any, outputs: Any, sparse: bool) -> tuple | None:
    """The memo key of a plant whose signals are all named by strings (None otherwise)."""
    names = [inputs] if isinstance(inputs, str) else inputs
    outs = [outputs] if isinstance(outputs, str) else outputs
    if not isinstance(names, (list, tuple)) or not all(isinstance(x, str) for x in names):
        return None
    if outs is not None and (not isinstance(outs, (list, tuple)) or not all(isinstance(x, str) for x in outs)):
        return None
    return ("plant", tuple(names), None if outs is None else tuple(outs), bool(sparse))


def _build_plant(model_or_assembly: Model | Assembly, inputs: Sequence[Any], outputs: Sequence[str] | None,
                 modal_damping: float | Sequence[float] | None, sparse: bool) -> Plant:
    asm = (model_or_assembly if isinstance(model_or_assembly, Assembly)
           else assemble(model_or_assembly, sparse=True if sparse else None))
    model = asm.model
    if sparse and modal_damping is not None:
        raise ModelError("modal_damping: needs the dense plant (sparse=False): it adds a full matrix to C")
    if isinstance(inputs, str) or not hasattr(inputs, "__iter__"):
        inputs = [inputs]
    parsed = [parse_input(asm, item) for item in inputs]
    if not parsed:
        raise ModelError("inputs: give at least one input signal, e.g. "
                         f"'{model.body_names[0]}.fz' or 'ground.z.disp'")
    outputs = default_outputs(model) if outputs is None else outputs
    if isinstance(outputs, str):
        outputs = [outputs]
    outputs = tuple(outputs)
    for what, names in (("inputs", [p.name for p in parsed]), ("outputs", outputs)):
        dup = sorted({x for x in names if names.count(x) > 1})
        if dup:
            raise ModelError(f"{what}: signal(s) {dup} given more than once")

    n, m = asm.n, len(parsed)
    mats = {key: sp.csr_matrix(getattr(asm, key)) if sparse else asm.dense(key) for key in ("M", "K", "C", "H")}
    coupling = {"K": asm.Kg, "C": asm.Cg, "H": asm.Hg}
    force, motion, free = input_maps(asm, parsed)

    def ff(a: Any) -> Any:
        return a[free][:, free].tocsr() if sparse else a[np.ix_(free, free)]

    def fz(key: str) -> np.ndarray:
        out = np.asarray(mats[key][free] @ motion[:n])
        if key in coupling:
            out = out + np.asarray(coupling[key][free] @ motion[n:])
        return out

    C = ff(mats["C"])
    if modal_damping is not None:
        C = C + _modal_damping(ff(mats["M"]), ff(mats["K"]), modal_damping, _columns(asm.stiffness_factor(), free))
    cache: dict = {}
    rows, units = zip(*(output_row(asm, name, cache) for name in outputs)) if outputs else ((), ())
    full = {key: np.array([getattr(r, key) for r in rows]).reshape(len(outputs), n + asm.nz)
            for key in ("d", "v", "a", "h")}
    o = {key: full[key][:, free] for key in full}
    pz = {key: full[key] @ motion for key in full}
    K, H, M = ff(mats["K"]), ff(mats["H"]), ff(mats["M"])
    extra_c = None if modal_damping is None else C - ff(mats["C"])
    return Plant(
        dofs=tuple(asm.dofs[i] for i in free),
        M=M, C=C, K=K, H=H,
        mounts=mount_form(asm, free, (K, C, H, M), extra_c),
        inputs=tuple(p.name for p in parsed), kinds=tuple(p.kind for p in parsed),
        F=force[free], Kz=fz("K"), Cz=fz("C"), Mz=fz("M"), Hz=fz("H"),
        outputs=outputs, units=tuple(units),
        Oq=o["d"], Ov=o["v"], Oa=o["a"], Pz=pz["d"], Pv=pz["v"], Pa=pz["a"],
        Pf=actuator_reactions(model, [p.name for p in parsed], outputs), name=model.name,
        Oh=o["h"], Ph=pz["h"], Kf=_columns(asm.stiffness_factor(), free),
        branches=build_branches(model, asm.deflection_matrix(), free, motion, np.array(
            [np.zeros(3 * len(model.mounts)) if r.f is None else r.f for r in rows]).reshape(
            len(outputs), 3 * len(model.mounts))) if any(t.has_branches for t in model.mount_types.values()) else None,
    )


def _columns(g: sp.csr_matrix, cols: np.ndarray) -> sp.csr_matrix:
    """``g[:, cols]`` as CSR with sorted indices (so no product sorts them in place later and the
    summation order, hence the last bits, never change between calls)."""
    out = g[:, cols].tocsr()
    out.sort_indices()
    return out




def mount_form(asm: Assembly, free: np.ndarray, source: tuple, extra_c: Any = None) -> MountForm | None:
    """The plant's ``K, C, H`` as a sum over its mounts (:class:`~vibss.linear.plant.plant.MountForm`).

    Parameters
    ----------
    asm : Assembly
        The assembled model.
    free : (n,) int ndarray
        Free body DOFs (indices into ``asm.dofs``).
    source : tuple
        The plant's ``(K, C, H, M)``.
    extra_c : (n, n) array_like or None
        Damping not from the mounts (modal damping).

    Returns
    -------
    MountForm or None
        None when no mount with a positive-definite stiffness touches a free DOF.
    """
    n_body = asm.n
    b = sp.csr_matrix(asm.deflection_matrix()[:, :n_body][:, free])
    q = len(asm.b_index)
    if q == 0:
        return None
    lam = np.linalg.eigvalsh(0.5 * (asm.kp + asm.kp.transpose(0, 2, 1)))          # (q, 3)
    rows = np.diff(b.indptr).reshape(q, 3).sum(axis=1)
    # positive definite beyond round-off: an inclined zero-stiffness axis leaves lam.min ~ eps lam.max
    # > 0, and its Z(s) is singular (issue 18's fuzzer: LinAlgError in the mounts' solve)
    apart = (lam.min(axis=1) > 1e3 * np.finfo(float).eps * lam.max(axis=1)) & (rows > 0)
    # the others with diagonal local matrices are kept apart per local axis, their stiff axes only:
    # assembled, a stiff axis rounds the zero axis beside it at its own level (issue 18's fuzzer:
    # a 2 g body free along such an axis lost 1.5e-8 of its FRF at 0.1 Hz)
    mounts = asm.model.mounts
    axial = ~apart & (rows > 0) & np.array([not m.type.coupled and bool(np.any(np.asarray(m.type.stiffness) > 0))
                                            for m in mounts], dtype=bool).reshape(q)
    if not apart.any() and not axial.any():
        return None
    idx = (3 * np.flatnonzero(apart)[:, None] + np.arange(3)).ravel()
    rest_mounts = ~apart & ~axial
    rest = (3 * np.flatnonzero(rest_mounts)[:, None] + np.arange(3)).ravel()
    br = b[rest]
    ax = _axes(mounts, b, np.flatnonzero(axial))

    def assembled(blocks: np.ndarray) -> sp.csr_matrix:
        if rest.size == 0:
            return sp.csr_matrix((free.size, free.size))
        return sp.csr_matrix(br.T @ sp.block_diag(list(blocks[rest_mounts])) @ br)

    def rotational(blocks: np.ndarray, coupling: np.ndarray | None = None) -> sp.csr_matrix:
        """6x6 mounts' rotational parts (and full matrices' coupling), assembled with the rest."""
        out = sp.csr_matrix((free.size, free.size))
        if not np.any(blocks) and (coupling is None or not np.any(coupling)):
            return out
        rr = sp.csr_matrix(asm.rotation_matrix()[:, :n_body][:, free])
        if np.any(blocks):
            out = sp.csr_matrix(rr.T @ sp.block_diag(list(blocks)) @ rr)
        if coupling is not None and np.any(coupling):
            x = sp.csr_matrix(b.T @ sp.block_diag(list(coupling)) @ rr)     # B^T kc R: both mounts' sides
            out = sp.csr_matrix(out + x + x.T)
        return out

    c_rest = assembled(asm.cp) + rotational(asm.crp, asm.ccp)
    if ax.c0.size:                                # the zero axes' dampers: one rank-1 term each
        c_rest = c_rest + sp.csr_matrix(ax.b0.T @ sp.diags(ax.c0) @ ax.b0)
    if extra_c is not None:
        c_rest = sp.csr_matrix(c_rest + sp.csr_matrix(extra_c))
    k_top = max(float(lam[apart].max()) if apart.any() else 0.0, float(ax.k.max()) if ax.k.size else 0.0)
    return MountForm(B=b[idx], kp=asm.kp[apart], cp=asm.cp[apart], hp=asm.hp[apart],
                     K=sp.csr_matrix(assembled(asm.kp) + rotational(asm.krp, asm.kcp)), C=sp.csr_matrix(c_rest),
                     H=assembled(asm.hp), source=source,
                     stiffness_ratio=k_top / _softest(lam[rows > 0]),
                     inertia_w2=_inertia_w2(asm, free, b[idx], lam[apart].max(axis=1), source[3], ax.b, ax.k),
                     Ba=ax.b, ka=ax.k, ca=ax.c, ha=ax.h)


@dataclass(frozen=True)
class _Axes:
    """Rows of the mounts kept apart per local axis: ``b`` (r, n) deflections along their stiff axes
    with stiffness ``k`` [N/m], damping ``c`` [N s/m] and hysteretic stiffness ``h`` [N/m]; ``b0``, ``c0``
    the zero-stiffness axes that have a damper."""

    b: sp.csr_matrix
    k: np.ndarray
    c: np.ndarray
    h: np.ndarray
    b0: sp.csr_matrix
    c0: np.ndarray


def _axes(mounts: Sequence[Any], b: sp.csr_matrix, which: np.ndarray) -> _Axes:
    """Each mount in ``which`` in its local axes (their matrices diagonal there): ``T^T B_p`` per axis."""
    n = b.shape[1]
    stiff: list[tuple[sp.csr_matrix, float, float, float]] = []
    zero: list[tuple[sp.csr_matrix, float]] = []
    for p in which:
        t = mounts[p].type
        local = sp.csr_matrix(mounts[p].orientation.matrix.T) @ b[3 * p:3 * p + 3]
        k, c = np.asarray(t.stiffness, dtype=float), np.asarray(t.damping, dtype=float)
        h = k * np.asarray(t.loss_factor, dtype=float)
        for a in range(3):
            if k[a] > 0:
                stiff.append((local[a], k[a], c[a], h[a]))
            elif c[a] > 0:
                zero.append((local[a], c[a]))

    def stack(parts: list) -> sp.csr_matrix:
        return sp.csr_matrix(sp.vstack([x[0] for x in parts])) if parts else sp.csr_matrix((0, n))
    return _Axes(b=stack(stiff), k=np.array([x[1] for x in stiff], dtype=float),
                 c=np.array([x[2] for x in stiff], dtype=float), h=np.array([x[3] for x in stiff], dtype=float),
                 b0=stack(zero), c0=np.array([x[1] for x in zero], dtype=float))


FREE_MOTION_CHECK_MAX = 150
"""Plants up to this many free DOFs are checked for free motions when their mounts' form is built
(larger ones keep ``inertia_w2 = 0``: the stiffness ratio alone chooses their form)."""


def _free_motion(asm: Assembly, free: np.ndarray) -> bool:
    """Whether the mounts leave a motion of the free DOFs unrestrained: the stiffness factor's
    smallest singular value at round-off of its largest (or fewer rows than DOFs)."""
    g = asm.stiffness_factor()[:, free].toarray()
    if g.shape[0] < g.shape[1]:
        return True
    sv = np.linalg.svd(g, compute_uv=False)
    return bool(sv[-1] <= g.shape[0] * np.finfo(float).eps * sv[0])


def _inertia_w2(asm: Assembly, free: np.ndarray, b: sp.csr_matrix, kmax: np.ndarray, mass: Any,
                b_axes: sp.csr_matrix | None = None, k_axes: np.ndarray | None = None) -> float:
    """:attr:`MountForm.inertia_w2` [rad^2/s^2]: ``max_p k_max,p lambda_max(B_p M^-1 B_p^T)`` over the
    mounts kept apart (``b``: their (3 q, n) deflection rows, ``kmax``: their largest principal
    stiffness [N/m]) when the mounts leave a motion free; 0 otherwise or above
    :data:`FREE_MOTION_CHECK_MAX` free DOFs.

    ``B_p M^-1 B_p^T`` [1/kg] is the compliance of the inertia a unit deflection of mount p moves
    (a moment of inertia counted at the mount's lever arm), so the value is units-independent: a
    frequency squared. A free motion is held by nothing but inertia, and the assembled ``K``'s
    round-off of its stiffest mounts swamps it at low frequencies: a 13 g body with no stiffness to
    ground, linked by 8e13 N/m to a free 4.6 t body, lost 1.6e-3 of its FRF at 1.9 Hz in the
    assembled form (issue 18's long run) while its stiffness ratio (3.7) chose that form."""
    if free.size == 0 or free.size > FREE_MOTION_CHECK_MAX or not _free_motion(asm, free):
        return 0.0
    m = mass.toarray() if sp.issparse(mass) else np.asarray(mass, dtype=float)
    bd = b.toarray()
    ba = np.zeros((0, free.size)) if b_axes is None else b_axes.toarray()
    try:
        x = np.linalg.solve(m, np.vstack([bd, ba]).T)                  # M^-1 [B; Ba]^T, (n, 3 q + r)
    except np.linalg.LinAlgError:
        return float(np.inf)
    q = kmax.size
    top = 0.0
    if q:
        comp = (bd @ x[:, :3 * q]).reshape(q, 3, q, 3)[np.arange(q), :, np.arange(q), :]     # (q, 3, 3) blocks
        lam = np.linalg.eigvalsh(0.5 * (comp + comp.transpose(0, 2, 1))).max(axis=1)
        top = float(np.max(kmax * np.maximum(lam, 0.0)))
    if ba.shape[0]:                                                      # per-axis rows: 1 x 1 blocks
        assert k_axes is not None
        top = max(top, float(np.max(k_axes * np.maximum(np.einsum("ij,ji->i", ba, x[:, 3 * q:]), 0.0))))
    return top


def _softest(lam: np.ndarray) -> float:
    """The smallest nonzero principal stiffness [N/m] of mounts (``lam``: (q, 3) eigenvalues of their
    ``kp``), zero axes (below round-off of their mount's largest) left out.

    The mounts' form pays off when the mounts kept apart are stiff *against any soft mount*, those
    with a zero axis (assembled with the rest) included: a 13 g body held by one single-axis
    4.6e5 N/m mount and linked by 8e13 N/m to a free 4.6 t body lost 5e-3 of its FRF in the
    assembled form while the links alone spanned a ratio of 3.7 (issue 18's long run)."""
    pos = lam[lam > 1e3 * np.finfo(float).eps * lam.max(axis=1, keepdims=True)]
    return float(pos.min()) if pos.size else float(lam.max())


def _modal_damping(M: np.ndarray, K: np.ndarray, zeta: float | Sequence[float], factor: Any = None) -> np.ndarray:
    spec = undamped(K, M, factor)
    w2, phi, rigid = spec.omega2, spec.phi, spec.rigid
    w = np.sqrt(w2)
    z = np.broadcast_to(np.asarray(zeta, dtype=float), w.shape) if np.ndim(zeta) == 0 else np.asarray(zeta, float)
    if z.shape != w.shape or np.any(z < 0) or not np.all(np.isfinite(z)):
        raise ModelError(f"modal_damping: expected a ratio >= 0 or {w.size} of them, got {zeta!r}")
    g = np.where(rigid, 0.0, 2.0 * z * w)
    mp = M @ phi
    c = (mp * g) @ mp.T
    c = 0.5 * (c + c.T)
    # entries at the round-off of the diagonal are zeros that the eigenvectors' last bits blurred
    d = np.sqrt(np.abs(np.diag(c)))
    c[np.abs(c) <= 4 * c.shape[0] * np.finfo(float).eps * np.outer(d, d)] = 0.0
    return c
