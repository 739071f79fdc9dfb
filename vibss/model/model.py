"""The model: frozen, validated bodies, control points, loads and the Model (mount types and mounts
in :mod:`vibss.model.mounts`, re-exported here).

Everything is SI (m, kg, N, s, rad). Objects are frozen dataclasses, normalised and validated on
construction; "editing" returns a copy (:func:`dataclasses.replace`). Every error is a
:class:`~vibss.errors.ModelError` naming the entity and the field.

Examples
--------
>>> from vibss import Body, MountType, Mount, Model, symmetric
>>> body = Body("prism", mass=1000.0, inertia=[10.0, 20.0, 30.0])
>>> rubber = MountType("rubber", stiffness=[1e4, 2e4, 3e4])
>>> mounts = symmetric(Mount("m", rubber, body="prism", at=[1.0, 2.0, 0.0]), "double")
>>> model = Model([body], mounts)
>>> [m.name for m in model.mounts]
['m', 'm.xz', 'm.yz', 'm.xz.yz']
"""

from __future__ import annotations

import copy
import dataclasses
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import numpy.typing as npt

from .._validate import is_numeric
from .limits import check_range
from .._deprecated import renamed_attribute
from ..errors import ArgumentError, ModelError, did_you_mean
from ._common import (DOF_NAMES, GROUND, _frame, _freeze, _name, _orientation, _point_name,
                      _signal_safe, _vec)
from .geometry import Orientation
from .actuation import Actuator, Sensor
from .mounts import SYMMETRIES, Mount, MountType, Support, symmetric  # re-exported: vibss.model.model keeps every name

__all__ = [
    "GROUND",
    "DOF_NAMES",
    "Body",
    "MountType",
    "Mount",
    "Support",
    "ControlPoint",
    "Load",
    "Model",
    "symmetric",
    "Actuator",
    "Sensor",
]

@dataclass(frozen=True, eq=False)
class Body:
    """A rigid body.

    Parameters
    ----------
    name : str
        Unique name.
    mass : float or (3,) array_like
        Mass [kg], or a directional ("effective") mass (mx, my, mz) [kg].
    inertia : (3,) or (3, 3) array_like
        Principal moments (I1, I2, I3) [kg m^2] about the COG, oriented by ``principal_axes``;
        or the full inertia tensor J about the COG in global axes [kg m^2]. The tensor's
        off-diagonal entries are minus the products of inertia (Jxy = -integral of x y dm).
    cog : (3,) array_like
        Centre of gravity in global coordinates [m].
    principal_axes : Orientation, (3, 3) array_like or None
        Orientation of the principal axes (columns = axes 1, 2, 3 in global coordinates); only
        with principal moments. Default: along the global axes.

    Attributes
    ----------
    masses : (3,) ndarray
        Mass per translation direction [kg] (three equal values for a scalar mass).
    tensor : (3, 3) ndarray
        Inertia tensor about the COG in global axes [kg m^2].
    """

    name: str
    mass: Any
    inertia: Any
    cog: Any = (0.0, 0.0, 0.0)
    principal_axes: Any = None
    masses: np.ndarray = field(init=False, repr=False)
    tensor: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        _name(self.name, "body")
        who = f"body {self.name!r}"
        _point_name(self.name, who)
        if self.name == "mount":
            raise ModelError(f"{who}: the name 'mount' is reserved ('mount.<name>.fz' are mount signals)")
        m = np.array(self.mass, dtype=float) if is_numeric(self.mass) else None
        if m is None or m.shape not in ((), (3,)):
            raise ModelError(f"{who}: mass: expected a number or 3 numbers [kg], got {self.mass!r}")
        if not np.all(np.isfinite(m)):
            raise ModelError(f"{who}: mass must be finite, got {m.tolist()}")
        if np.any(m <= 0):
            raise ModelError(f"{who}: mass must be positive, got {m.tolist()} kg")
        masses = np.full(3, float(m)) if m.shape == () else m
        object.__setattr__(self, "mass", float(m) if m.shape == () else _freeze(m.copy()))
        object.__setattr__(self, "masses", _freeze(masses.copy()))
        check_range(masses, "mass", who, "mass", "kg")
        object.__setattr__(self, "cog", _vec(self.cog, 3, who, "cog"))
        check_range(self.cog, "length", who, "cog", "m")

        inertia = np.array(self.inertia, dtype=float) if is_numeric(self.inertia) else None
        if inertia is None or inertia.shape not in ((3,), (3, 3)):
            raise ModelError(
                f"{who}: inertia: expected 3 principal moments or a 3x3 tensor [kg m^2], "
                f"got {self.inertia!r}"
            )
        if not np.all(np.isfinite(inertia)):
            raise ModelError(f"{who}: inertia must be finite, got {inertia.tolist()}")
        if inertia.shape == (3,):
            axes = _orientation(self.principal_axes, who, "principal_axes")
            object.__setattr__(self, "principal_axes", axes)
            moments = inertia
            tensor = axes.matrix @ np.diag(moments) @ axes.matrix.T
            tensor = 0.5 * (tensor + tensor.T)  # exactly symmetric despite rounding
        else:
            if self.principal_axes is not None:
                raise ModelError(
                    f"{who}: principal_axes only applies to principal moments, not to a full "
                    "inertia tensor (which is already in global axes)"
                )
            if not np.allclose(inertia, inertia.T, rtol=1e-9, atol=1e-12 * np.abs(inertia).max()):
                raise ModelError(f"{who}: inertia tensor must be symmetric, got {inertia.tolist()}")
            tensor = 0.5 * (inertia + inertia.T)
            moments = np.linalg.eigvalsh(tensor)
        _check_moments(moments, who)
        check_range(moments, "inertia", who, "inertia (principal moments)", "kg m^2")
        object.__setattr__(self, "inertia", _freeze(inertia))
        object.__setattr__(self, "tensor", _freeze(tensor))

    @property
    def mass_matrix(self) -> np.ndarray:
        """6x6 mass matrix diag(mx, my, mz) + J [kg, kg m^2]."""
        out = np.zeros((6, 6))
        out[:3, :3] = np.diag(self.masses)
        out[3:, 3:] = self.tensor
        return out

    @property
    def total_mass(self) -> float:
        """Mass used for weight and reports [kg]: the scalar mass, or the mean directional mass."""
        return float(np.mean(self.masses))

    def moved(self, offset: npt.ArrayLike) -> Body:
        """Copy of the body translated by ``offset`` [m]."""
        return dataclasses.replace(self, cog=self.cog + np.asarray(offset, float))



def _check_moments(moments: np.ndarray, who: str) -> None:
    scale = max(float(np.abs(moments).max()), 1e-300)
    if np.any(moments <= 1e-12 * scale):
        raise ModelError(
            f"{who}: inertia is not positive definite (principal moments {moments.tolist()} "
            "kg m^2); every principal moment must be positive"
        )
    a, b, c = np.sort(moments)
    if a + b < c * (1 - 1e-9):
        raise ModelError(
            f"{who}: inertia is physically impossible: principal moments {moments.tolist()} "
            f"break the triangle inequality ({a:.6g} + {b:.6g} < {c:.6g}); no mass "
            "distribution has them"
        )


@dataclass(frozen=True, eq=False)
class ControlPoint:
    """A named point on a body whose motion is reported.

    Parameters
    ----------
    name : str
        Unique name.
    body : str
        The body the point belongs to.
    at : (3,) array_like
        Position [m], relative to the body's COG (``frame="body"``) or global (``"global"``).
    frame : {"body", "global"}
        How ``at`` is measured.
    """

    name: str
    body: str
    at: Any
    frame: str = "body"

    def __post_init__(self) -> None:
        who = f"control point {self.name!r}"
        if not isinstance(self.name, str) or not self.name:
            raise ModelError(f"control point: name must be a non-empty string, got {self.name!r}")
        _point_name(_signal_safe(self.name, who), who)
        if not isinstance(self.body, str):
            raise ModelError(f"{who}: body must be a body name, got {self.body!r}")
        object.__setattr__(self, "at", _vec(self.at, 3, who, "at"))
        check_range(self.at, "length", who, "at", "m")
        object.__setattr__(self, "frame", _frame(self.frame, who))


_LOAD_FIELDS = ("name", "body", "force", "moment", "at", "frame", "case")
_LOAD_OLD_ORDER = ("body", "force", "moment", "at", "frame", "name", "case")
_LOAD_DEFAULTS: dict[str, Any] = {"name": "", "force": (0.0, 0.0, 0.0), "moment": (0.0, 0.0, 0.0), "at": None,
                                  "frame": "body", "case": ""}


@dataclass(frozen=True, eq=False, init=False)
class Load:
    """A static force and moment on a body: ``Load(name, body, force=..., moment=..., at=...)``, name
    first as for :class:`Body` and :class:`Mount` (and as ``[[load]]`` tables in model files).

    The old order ``Load(body, force, ..., name=...)`` still works with a ``DeprecationWarning``
    naming the new spelling; it is recognised unambiguously: without ``body=``, a second positional
    argument that is not a string (a force) or a single positional argument is the old order.

    Parameters
    ----------
    name : str
        Label for reports ("" allowed).
    body : str
        The loaded body.
    force : (3,) array_like
        Force in global axes [N].
    moment : (3,) array_like
        Moment in global axes [N m].
    at : (3,) array_like or None
        Point of application of ``force`` [m] (frame as ``frame``); None: the COG.
    frame : {"body", "global"}
        How ``at`` is measured.
    case : str
        Load case. Unnamed loads (``""``) always apply; a named case is one alternative set of
        loads added to them (:func:`vibss.static`'s ``case``).

    Examples
    --------
    >>> Load("pump", "frame", force=[0.0, 0.0, -120.0]).body
    'frame'
    """

    name: str
    body: str
    force: Any
    moment: Any
    at: Any
    frame: str
    case: str

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        unknown = sorted(set(kwargs) - set(_LOAD_FIELDS))
        if unknown:
            raise ArgumentError(f"Load: unknown argument(s) {unknown}; Load takes {list(_LOAD_FIELDS)}",
                                argument=unknown[0], received=kwargs[unknown[0]], expected=_LOAD_FIELDS)
        if len(args) > len(_LOAD_FIELDS):
            raise ArgumentError(f"Load: at most {len(_LOAD_FIELDS)} positional arguments "
                                f"({', '.join(_LOAD_FIELDS)}), got {len(args)}", argument="args",
                                received=len(args), expected=len(_LOAD_FIELDS))
        old = bool(args) and "body" not in kwargs and not (len(args) >= 2 and isinstance(args[1], str))
        values = dict(zip(_LOAD_OLD_ORDER if old else _LOAD_FIELDS, args))
        twice = sorted(set(values) & set(kwargs))
        if twice:
            raise ArgumentError(f"Load: {twice[0]} given twice (by position and by keyword)",
                                argument=twice[0], received=kwargs[twice[0]], expected="one value")
        values.update(kwargs)
        if "body" not in values:
            raise ModelError("load: body: missing; give Load(name, body, force=[fx, fy, fz] [N])")
        if old:
            import warnings

            warnings.warn(f"Load(body, force, ..., name=...) is deprecated: the name comes first, as for "
                          f"Body and Mount: Load({values.get('name', '')!r}, {values['body']!r}, force=...)",
                          DeprecationWarning, stacklevel=2)
        for key in _LOAD_FIELDS:
            object.__setattr__(self, key, values.get(key, _LOAD_DEFAULTS.get(key)))
        self.__post_init__()

    def __post_init__(self) -> None:
        if not isinstance(self.body, str):
            raise ModelError(f"load {self.name!r}: body must be a body name, got {self.body!r}")
        if not isinstance(self.name, str):
            raise ModelError(f"load: name must be a string, got {self.name!r}")
        who = f"load {self.name or 'on ' + repr(self.body)}"
        object.__setattr__(self, "force", _vec(self.force, 3, who, "force"))
        object.__setattr__(self, "moment", _vec(self.moment, 3, who, "moment"))
        if self.at is not None:
            object.__setattr__(self, "at", _vec(self.at, 3, who, "at"))
            check_range(self.at, "length", who, "at", "m")
        check_range(self.at, "length", who, "at", "m")
        object.__setattr__(self, "frame", _frame(self.frame, who))
        if not isinstance(self.case, str):
            raise ModelError(f"{who}: case must be a string (a load case name), got {self.case!r}")
        if self.case == "self-weight":
            raise ModelError(f"{who}: case 'self-weight' is reserved (static(..., case='self-weight') is "
                             "gravity alone); name the case otherwise")


def _load_signature() -> Any:
    import inspect

    P = inspect.Parameter
    params = [P("self", P.POSITIONAL_OR_KEYWORD), P("name", P.POSITIONAL_OR_KEYWORD, annotation="str"),
              P("body", P.POSITIONAL_OR_KEYWORD, annotation="str")]
    params += [P(k, P.POSITIONAL_OR_KEYWORD, default=_LOAD_DEFAULTS[k], annotation=a)
               for k, a in (("force", "Any"), ("moment", "Any"), ("at", "Any"), ("frame", "str"), ("case", "str"))]
    return inspect.Signature(params, return_annotation="None")


Load.__init__.__signature__ = _load_signature()  # type: ignore[attr-defined]  # the documented order


@dataclass(frozen=True, eq=False)
class Model:
    """A system of rigid bodies joined to each other and to ground by mounts.

    Parameters
    ----------
    bodies : sequence of Body
        The bodies; their order fixes the DOF order (6 per body: x y z rx ry rz).
    mounts : sequence of Mount
        The mounts (expand symmetric patterns with :func:`symmetric` first).
    control_points : sequence of ControlPoint
        Points whose motion is reported.
    loads : sequence of Load
        Static loads.
    gravity : (3,) array_like or None
        Gravitational acceleration [m/s^2] (e.g. ``(0, 0, -9.81)``) adding self-weight to the
        static loads, or None.
    name : str
        Title for reports.
    excitations : sequence
        Excitations for frequency and time studies (:class:`vibss.model.excitation.Excitation`).
    settings : mapping
        Default study settings read from a model file's ``[analysis]`` table.
    actuators : sequence of Actuator
        Force or moment pairs (input signals ``actuator.<name>.f``; :mod:`vibss.model.actuation`).
    sensors : sequence of Sensor
        Named measurements (output signals ``sensor.<name>``).
    supports : sequence of Support
        Named ground points moved on their own (multi-support excitation): a mount with
        ``support=<name>`` stands on it instead of the rigid ``ground``.
    """

    bodies: Sequence[Body]
    mounts: Sequence[Mount] = ()
    control_points: Sequence[ControlPoint] = ()
    loads: Sequence[Load] = ()
    gravity: Any = None
    name: str = "model"
    excitations: Sequence[Any] = ()
    settings: Any = None
    actuators: Sequence[Actuator] = ()
    sensors: Sequence[Sensor] = ()
    supports: Sequence[Support] = ()

    def __post_init__(self) -> None:
        for key, cls in (("bodies", Body), ("mounts", Mount),
                         ("control_points", ControlPoint), ("loads", Load),
                         ("actuators", Actuator), ("sensors", Sensor), ("supports", Support)):
            value = getattr(self, key)
            if isinstance(value, (str, bytes, cls)) or not isinstance(value, Iterable):
                raise ModelError(f"model: {key}: expected a sequence of {cls.__name__}, got {value!r}")
            items = tuple(value)
            for i, item in enumerate(items):
                if not isinstance(item, cls):
                    raise ModelError(f"model: {key}[{i}] must be a {cls.__name__}, got {item!r}")
            object.__setattr__(self, key, items)
        if not self.bodies:
            raise ModelError("model: needs at least one body")
        if isinstance(self.excitations, (str, bytes)) or not isinstance(self.excitations, Iterable):
            raise ModelError(f"model: excitations: expected a sequence of Excitation, got {self.excitations!r}")
        object.__setattr__(self, "excitations", tuple(self.excitations))
        _unique([b.name for b in self.bodies], "body")
        _unique([m.name for m in self.mounts], "mount")
        _unique([c.name for c in self.control_points], "control point")
        reserved = {b.name for b in self.bodies} | {GROUND, "mount"}
        for c in self.control_points:
            if c.name in reserved:
                raise ModelError(f"control point {c.name!r}: the name is taken by a body (or reserved: "
                                 f"'ground', 'mount'); signals like '{c.name}.x' would be ambiguous")
        names = {b.name for b in self.bodies}
        _unique([s.name for s in self.supports], "support")
        taken = names | {c.name for c in self.control_points}
        supports = {s.name for s in self.supports}
        for s in self.supports:
            if s.name in taken:
                raise ModelError(f"support {s.name!r}: the name is taken by a body or control point; "
                                 f"signals like '{s.name}.z.acc' would be ambiguous")
        for m in self.mounts:
            if m.support is not None and m.support not in supports:
                raise ModelError(f"mount {m.name!r}: support: unknown support {m.support!r}; "
                                 + (f"supports are {sorted(supports)}" if supports else
                                    "the model has no supports (add Support(...) to Model(supports=...))")
                                 + did_you_mean(m.support, supports))
            for key in ("body", "to"):
                target = getattr(m, key)
                if target != GROUND and target not in names:
                    raise ModelError(f"mount {m.name!r}: {key}: unknown body {target!r}; "
                                     f"bodies are {sorted(names)}" + did_you_mean(target, names))
        types: dict[str, MountType] = {}
        for m in self.mounts:
            if types.setdefault(m.type.name, m.type) is not m.type and not _same_type(types[m.type.name], m.type):
                raise ModelError(f"mount {m.name!r}: a different mount type is already named {m.type.name!r}")
        for c in self.control_points:
            if c.body not in names:
                raise ModelError(f"control point {c.name!r}: unknown body {c.body!r}"
                                 + did_you_mean(c.body, names))
        for ld in self.loads:
            if ld.body not in names:
                raise ModelError(f"load {ld.name or ''}: unknown body {ld.body!r}" + did_you_mean(ld.body, names))
        elements: tuple[tuple[str, Sequence[Any]], ...] = (("actuator", self.actuators), ("sensor", self.sensors))
        for what, group in elements:
            if group and what in names | {c.name for c in self.control_points}:
                raise ModelError(f"model: a body or control point is named {what!r} and the model has "
                                 f"{what}s: signals '{what}.<name>' would be ambiguous; rename it")
        _check_elements(self.actuators, "actuator", names, {m.name for m in self.mounts})
        _check_elements(self.sensors, "sensor", names, {m.name for m in self.mounts})
        if self.gravity is not None:
            object.__setattr__(self, "gravity", _vec(self.gravity, 3, "model", "gravity"))
        if self.settings is not None and not isinstance(self.settings, Mapping):
            raise ModelError(f"model: settings: expected a mapping, got {self.settings!r}")
        object.__setattr__(self, "settings", copy.deepcopy(dict(self.settings or {})))  # not shared

    # -- lookups ---------------------------------------------------------------------------
    @property
    def n_dof(self) -> int:
        """Number of DOFs (6 per body)."""
        return 6 * len(self.bodies)

    @property
    def body_names(self) -> list[str]:
        """Body names in DOF order."""
        return [b.name for b in self.bodies]

    @property
    def support_names(self) -> list[str]:
        """Support names in order (their six ground DOFs follow the rigid ground's)."""
        return [s.name for s in self.supports]

    def ground_node(self, mount: Mount) -> int:
        """Which ground node a mount's ``to`` end is on: 0 the rigid ground, 1 + s support s,
        -1 a body."""
        if mount.to != GROUND:
            return -1
        return 0 if mount.support is None else 1 + self.support_names.index(mount.support)

    @property
    def mount_types(self) -> dict[str, MountType]:
        """The mount types used, by name."""
        return {m.type.name: m.type for m in self.mounts}

    def body(self, name: str) -> Body:
        """The body called ``name``."""
        for b in self.bodies:
            if b.name == name:
                return b
        raise ModelError(f"unknown body {name!r}; bodies are {self.body_names}"
                         + did_you_mean(name, self.body_names))

    def body_index(self, name: str) -> int:
        """Position of body ``name`` in DOF order (``-1`` for ground)."""
        if name == GROUND:
            return -1
        return self.body_names.index(self.body(name).name)

    def point(self, body: str, at: npt.ArrayLike, frame: str = "body") -> np.ndarray:
        """Position of a point relative to ``body``'s COG [m] (global axes)."""
        at = np.asarray(at, dtype=float)
        return at if frame == "body" else at - self.body(body).cog

    def mount_point(self, mount: Mount) -> np.ndarray:
        """Global coordinates of a mount's attachment point [m]."""
        return mount.at + self.body(mount.body).cog if mount.frame == "body" else mount.at

    @property
    def load_cases(self) -> list[str]:
        """Names of the load cases, in order of first use (unnamed loads always apply)."""
        return list(dict.fromkeys(ld.case for ld in self.loads if ld.case))

    @property
    def total_mass(self) -> float:
        """Sum of the bodies' masses [kg]."""
        return float(sum(b.total_mass for b in self.bodies))

    @property
    def center_of_gravity(self) -> np.ndarray:
        """Mass-weighted center of gravity of all bodies [m]."""
        # the bodies' total_mass (the mean directional mass) in one array operation: 10,000 calls of
        # np.mean took 0.6 s of a 1.4 s modes(n_modes=20) on a 10,000-body model
        m = np.add.reduce(np.array([b.masses for b in self.bodies], dtype=float).reshape(-1, 3), axis=1) / 3  # the mean
        g = np.array([b.cog for b in self.bodies])
        return m @ g / np.add.reduce(m)

    centre_of_gravity = renamed_attribute("centre_of_gravity", "center_of_gravity", "Model")

    def _repr_html_(self) -> str:
        """The model in a notebook: its bodies and its mounts as two escaped HTML tables [kg, m, N/m]."""
        import html

        from ..results import TextTable

        bodies = TextTable(["body", "mass [kg]", "COG [m]", "inertia [kg m^2]"],
                           [[b.name, f"{b.mass:.6g}", ", ".join(f"{x:.4g}" for x in b.cog),
                             ", ".join(f"{x:.4g}" for x in np.ravel(b.inertia))] for b in self.bodies])
        mounts = TextTable(["mount", "type", "body", "to", "at [m]", "stiffness [N/m]", "nonlinear"],
                           [[m.name, m.type.name, m.body, m.to, ", ".join(f"{x:.4g}" for x in m.at),
                             ", ".join(f"{k:.4g}" for k in m.type.stiffness),
                             "stops/curve" if getattr(m.type, "nonlinear", False) else ""] for m in self.mounts])
        head = (f"Model {self.name!r}: {len(self.bodies)} bodies, {len(self.mounts)} mounts, "
                f"{6 * len(self.bodies)} DOFs, total mass {self.total_mass:.6g} kg")
        return f"<div><strong>{html.escape(head)}</strong>{bodies.to_html()}{mounts.to_html()}</div>"

    # -- copies ----------------------------------------------------------------------------
    def replace(self, **changes: Any) -> Model:
        """Copy with fields replaced (see :func:`dataclasses.replace`).

        Parameters
        ----------
        **changes
            New values of Model fields, e.g. ``mounts=[...]``; validated like the constructor's.
        """
        return dataclasses.replace(self, **changes)

    def transformed(self, rotation: npt.ArrayLike | None = None,
                    offset: npt.ArrayLike = (0.0, 0.0, 0.0)) -> Model:
        """Copy of the whole model rotated by ``rotation`` (3x3) then shifted by ``offset`` [m].

        Frequencies do not change; shapes and deflections rotate with the model. Gravity, loads
        and directional masses are rotated only where that is meaningful: directional masses
        must be isotropic to be rotated.
        """
        q = np.eye(3) if rotation is None else Orientation.coerce(rotation).matrix
        off = np.asarray(offset, dtype=float)
        if rotation is not None and (self.excitations or self.settings.get("initial")):
            raise ModelError("transformed: the model has excitations or initial conditions, which are "
                             "given along global axes and are not rotated; rotate a model without them "
                             "and add them in the new axes")
        bodies = []
        for b in self.bodies:
            if not np.allclose(b.masses, b.masses[0]):
                raise ModelError(f"body {b.name!r}: a directional mass cannot be rotated")
            bodies.append(Body(b.name, b.mass, q @ b.tensor @ q.T, q @ b.cog + off))
        mounts = [dataclasses.replace(
            m, at=q @ m.at + (off if m.frame == "global" else 0.0),
            orientation=Orientation(q @ m.orientation.matrix)) for m in self.mounts]
        cps = [dataclasses.replace(c, at=q @ c.at + (off if c.frame == "global" else 0.0))
               for c in self.control_points]
        loads = [dataclasses.replace(
            ld, force=q @ ld.force, moment=q @ ld.moment,
            at=None if ld.at is None else q @ ld.at + (off if ld.frame == "global" else 0.0))
            for ld in self.loads]
        gravity = None if self.gravity is None else q @ self.gravity
        parts: dict[str, Any] = {key: [dataclasses.replace(
            e, at=q @ e.at + (off if e.frame == "global" else 0.0),
            direction=None if e.direction is None else q @ e.direction) for e in getattr(self, key)]
            for key in ("actuators", "sensors")}
        return dataclasses.replace(self, bodies=bodies, mounts=mounts, control_points=cps,
                                   loads=loads, gravity=gravity, **parts)


def _check_elements(items: Sequence[Any], what: str, bodies: set[str], mounts: set[str]) -> None:
    """Actuators or sensors: unique names, and bodies, ``to`` sides and mounts that exist."""
    _unique([e.name for e in items], what)
    for e in items:
        who = f"{what} {e.name!r}"
        if e.mount is not None and e.mount not in mounts:
            raise ModelError(f"{who}: mount: unknown mount {e.mount!r}" + did_you_mean(e.mount, mounts))
        if e.body is not None and e.body not in bodies:
            raise ModelError(f"{who}: body: unknown body {e.body!r}; bodies are {sorted(bodies)}"
                             + did_you_mean(e.body, bodies))
        to = getattr(e, "to", None)
        if to is not None and to != GROUND and to not in bodies:
            raise ModelError(f"{who}: to: unknown body {to!r}; expected 'ground' or one of "
                             f"{sorted(bodies)}" + did_you_mean(to, bodies))
        if to is not None and to == e.body:
            raise ModelError(f"{who}: body and to are both {to!r}; an element between a body and "
                             "itself does nothing")


def _same_type(a: MountType, b: MountType) -> bool:
    rheology = [None if t.rheology is None else t.rheology.to_dict() for t in (a, b)]
    return rheology[0] == rheology[1] and all(np.array_equal(a.local_matrix(k), b.local_matrix(k))
                                              for k in ("stiffness", "damping")) and all(np.array_equal(getattr(a, k), getattr(b, k))
                                              for k in ("stiffness", "damping", "loss_factor",
                                                        "rotational_stiffness", "rotational_damping"))


def _unique(names: Iterable[str], what: str) -> None:
    seen: set[str] = set()
    for n in names:
        if n in seen:
            raise ModelError(f"{what} name {n!r} is used twice; names must be unique")
        seen.add(n)


