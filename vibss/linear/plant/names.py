"""The names of a study's input and output signals: their grammar, and each name's input column or output row.

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
``<body>.<dof>.rel``                      its displacement relative to the rigid ground at the
                                          body's centre of gravity [m, rad]
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
>>> from .build import build_plant
>>> t = MountType("t", [1e4, 1e4, 1e4])
>>> m = Model([Body("b", 10.0, [1, 1, 1])], [Mount("m", t, "b")])
>>> p = build_plant(m, ["b.fz"], ["b.z", "mount.m.fz"])
>>> p.inputs, p.outputs, p.units
(('b.fz',), ('b.z', 'mount.m.fz'), ('m', 'N'))

The plant itself is built by :func:`vibss.linear.plant.build.build_plant`; the mounts' form of its
stiffness and damping by :func:`vibss.linear.plant.mountform.mount_form`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from .assemble import Assembly
from ...errors import ModelError, SignalError, did_you_mean
from ...model.geometry import point_transfer
from ...model.actuation import resolve
from ...model.model import DOF_NAMES, GROUND, Model
from .plant import INPUT_KINDS

__all__ = ["default_outputs", "INPUT_FORMS", "OUTPUT_FORMS", "parse_input", "output_row",
           "actuator_wrench", "actuator_reactions"]

INPUT_FORMS = ("<body>.fx|fy|fz", "<body>.mx|my|mz", "<point>.fx|fy|fz",
               "<body|ground|support>.<x|y|z|rx|ry|rz>.disp|vel|acc", "actuator.<name>.f|m")
"""Valid input name forms (for messages)."""

OUTPUT_FORMS = ("<body>.<x|y|z|rx|ry|rz>[.vel|.acc|.rel]", "<point>.x|y|z[.vel|.acc]",
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
    if suffix == "rel":
        return _relative_row(asm, name, base)
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


def _relative_row(asm: Assembly, name: str, base: str) -> tuple[_Rows, str]:
    """``<body>.<dof>.rel``: the body DOF minus the rigid ground's motion at the body's centre of
    gravity (a translation minus the ground point's translation there, a rotation minus the
    ground's rotation) [m, rad]."""
    model = asm.model
    head, _, comp = base.rpartition(".")
    if head not in model.body_names or comp not in DOF_NAMES:
        raise _bad_output(model, name, " (relative motion is <body>.<x|y|z|rx|ry|rz>.rel)")
    k = DOF_NAMES.index(comp)
    row = np.zeros(asm.n + asm.nz)
    row[6 * model.body_index(head) + k] = 1.0
    g = asm.ground_offset(GROUND)
    row[g:g + 6] -= point_transfer(model.body(head).cog)[k] if k < 3 else np.eye(6)[k]
    zero = np.zeros_like(row)
    return _Rows(row, zero, zero, zero), ("rad" if k >= 3 else "m")


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
