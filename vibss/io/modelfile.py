"""Model files (TOML or JSON) to and from :class:`~vibss.model.Model`, and the built-in examples.

The format is specified in ``docs/model-file.md`` (tables ``[model]``, ``[[body]]``,
``[[mount_type]]``, ``[[mount]]``, ``[[support]]``, ``[[control_point]]``, ``[[load]]``,
``[[excitation]]`` and ``[analysis]``). Numbers are converted to SI once, on load, from the units declared in
``[model] units`` (default SI, except angles: degrees). Every problem is reported as a
:class:`~vibss.errors.ModelFileError` whose message names the file, the entry (``mount[3]
('rear-left')`` is the third ``[[mount]]`` table, counting from 1), the key and what was expected;
unknown keys get a did-you-mean.

What the :class:`Model` has no field for is kept, in SI, in ``Model.settings``:
``"time"``, ``"frequency"`` and ``"harmonic_balance"`` (the ``[analysis]`` tables,
:mod:`vibss.io.harmonicfile`), ``"initial"`` (``{body: {"displacement":
[6], "velocity": [6]}}``) and ``"load_cases"`` (``{case: [load names]}``, when loads name a case).

Examples
--------
>>> model = load_example("prism")
>>> [m.name for m in model.mounts]
['corner', 'corner.xz', 'corner.yz', 'corner.xz.yz']
>>> loads_model(dumps_model(model)).mounts[3].at.tolist()
[-1.0, -2.0, 0.0]
"""

# Over 600 lines on purpose (issue 28): the reader and the writer of one file format: each table's
# keys are read and written here side by side, and the writer learns every number's unit by reading
# its own output back (io/fileunits.py), so splitting them would list each key twice.

from __future__ import annotations

import json
from collections.abc import Mapping, Sequence
from pathlib import Path
import warnings
from typing import Any, Union

import numpy as np

from .._validate import read_regular_file
from ..errors import ModelError, ModelFileError, VibssWarning, did_you_mean
from ..model.excitation import Excitation, amplitude_quantity, function_from_dict
from .filetable import MISSING, Entry, numbers, parse_text
from .designfile import read_design, read_study, write_tables
from .ordersfile import read_orders
from .harmonicfile import read_harmonic_balance
from .controlfile import read_control
from .environmentsfile import read_random, read_shock
from ..model.geometry import Orientation
from ..model.actuation import ACTUATOR_KINDS, SENSOR_KINDS, Actuator, Sensor
from ..model.model import (DOF_NAMES, GROUND, SYMMETRIES, Body, ControlPoint, Load, Model, Mount,
                    MountType, Support, symmetric)
from .tomlwriter import dumps_toml
from ..model.rheology import QUANTITIES as RHEOLOGY_QUANTITIES
from ..model.units import Units

__all__ = ["load_model", "loads_model", "dump_model", "dumps_model", "model_to_dict",
           "load_example", "example_names", "example_path"]

MAX_MODEL_FILE_BYTES = 16 * 2**20
"""Largest model file :func:`load_model` reads [bytes] (16 MiB)."""

EXAMPLES_DIR = Path(__file__).parent.parent / "examples"
"""Folder of the built-in example model files."""

_TABLES = ("model", "body", "mount_type", "mount", "support", "control_point", "load", "excitation", "analysis",
           "design", "study", "orders", "actuator", "sensor", "control", "shock", "random")


def _entries(data: Mapping[str, Any], table: str, source: str, units: Units) -> list[Entry]:
    items = data.get(table, [])
    if isinstance(items, Mapping):
        raise ModelFileError(f"{source}: {table}: expected [[{table}]] tables (an array of tables), "
                             f"got a single [{table}] table")
    if not isinstance(items, list):
        raise ModelFileError(f"{source}: {table}: expected [[{table}]] tables, got {items!r}")
    out = []
    for i, item in enumerate(items, start=1):
        name = item.get("name") if isinstance(item, Mapping) else None
        where = f"{source}: {table}[{i}]" + (f" ({name!r})" if isinstance(name, str) else "")
        if not isinstance(item, Mapping):
            raise ModelFileError(f"{where}: expected a table, got {item!r}")
        out.append(Entry(item, where, units))
    return out


def _wrap(entry: Entry, exc: ModelError) -> ModelFileError:
    """A constructor's ModelError located at ``entry`` (a ModelFileError is already located)."""
    if isinstance(exc, ModelFileError):
        return exc
    text = str(exc)
    return ModelFileError(text if text.startswith(entry.where) else f"{entry.where}: {text}")


# -- the tables ------------------------------------------------------------------------------------
def _body(e: Entry, i: int, initial: dict[str, Any]) -> Body:
    e.check_keys(("name", "mass", "inertia", "inertia_tensor", "principal_axes", "cog", "initial"),
                 ("mass",))
    name = e.string("name", f"body{i}")
    mass = e.array("mass", [(), (3,)], "mass", positive=True)
    if ("inertia" in e) == ("inertia_tensor" in e):
        raise e.fail("inertia", "give either inertia = [I1, I2, I3] (principal moments) or "
                     "inertia_tensor = [[Ixx, Ixy, Ixz], [Ixy, Iyy, Iyz], [Ixz, Iyz, Izz]]")
    if "inertia" in e:
        inertia = e.array("inertia", [(3,)], "inertia", positive=True)
        axes = e.orientation("principal_axes")
    else:
        if "principal_axes" in e:
            raise e.fail("principal_axes", "only applies to principal moments (inertia), not to "
                         "inertia_tensor, which is already in global axes")
        inertia, axes = e.array("inertia_tensor", [(3, 3)], "inertia"), None
    init = e.sub("initial")
    if init is not None:
        init.check_keys(("displacement", "velocity"))
        initial[name] = {
            "displacement": init.array("displacement", [(6,)], ["length"] * 3 + ["angle"] * 3,
                                       np.zeros(6)).tolist(),
            "velocity": init.array("velocity", [(6,)], ["velocity"] * 3 + ["angular_velocity"] * 3,
                                   np.zeros(6)).tolist()}
    try:
        return Body(name, float(mass) if mass.ndim == 0 else mass, inertia,
                    e.array("cog", [(3,)], "length", np.zeros(3)), axes)
    except ModelError as exc:
        raise _wrap(e, exc) from None


def _matrix6(e: Entry, key: str, kind: str) -> np.ndarray | None:
    """A 6x6 ``stiffness_matrix`` (``kind="stiffness"``) or ``damping_matrix`` in SI: the translation
    block in the file's stiffness (damping) unit, the rotation block in its rotational one, both
    coupling blocks in force/angle (force time/angle)."""
    if key not in e:
        return None
    raw = e.array(key, [(6, 6)], "dimensionless")
    unit = {q: e.units.factor(f"{q}_{kind}") for q in ("rotational", "coupling")}
    f = np.full((6, 6), unit["coupling"])
    f[:3, :3] = e.units.factor(kind)
    f[3:, 3:] = unit["rotational"]
    return np.asarray(raw * f)


def _mount_type(e: Entry) -> MountType:
    e.check_keys(("name", "stiffness", "damping", "loss_factor", "rheology", "rotational_stiffness",
                  "rotational_damping", "stiffness_matrix", "damping_matrix", "stops", "curve"),
                 ("name",) if "rheology" in e or "stiffness_matrix" in e or "curve" in e else ("name", "stiffness"))
    try:
        return MountType(e.string("name"),
                         e.array("stiffness", [(3,)], "stiffness", None, nonnegative=True),
                         e.array("damping", [(3,)], "damping", np.zeros(3), nonnegative=True),
                         e.array("loss_factor", [(), (3,)], "dimensionless", 0.0, nonnegative=True),
                         _rheology(e),
                         e.array("rotational_stiffness", [(3,)], "rotational_stiffness", np.zeros(3),
                                 nonnegative=True),
                         e.array("rotational_damping", [(3,)], "rotational_damping", np.zeros(3),
                                 nonnegative=True),
                         _matrix6(e, "stiffness_matrix", "stiffness"), _matrix6(e, "damping_matrix", "damping"),
                         stops=_stops(e), curve=_curve(e))
    except ModelError as exc:
        raise _wrap(e, exc) from None


def _stops(e: Entry) -> dict[str, Any] | None:
    """``stops = {z = {clearance = c or [c-, c+], stiffness = k}}`` (or ``z = [c, k]``) in SI: the
    clearance in the file's length unit, the stiffness in its stiffness unit; the model checks the rest."""
    table = e.table("stops")
    if table is None:
        return None
    out: dict[str, Any] = {}
    for axis, spec in table.items():
        if isinstance(spec, Mapping):
            clearance, stiffness = spec.get("clearance"), spec.get("stiffness")
            extra = sorted(set(spec) - {"clearance", "stiffness"})
            if extra:
                raise e.fail(f"stops.{axis}", f"unknown key(s) {extra}; expected clearance and stiffness")
        elif isinstance(spec, (list, tuple)) and len(spec) == 2:
            clearance, stiffness = spec
        else:
            raise e.fail(f"stops.{axis}", f"expected {{clearance = ..., stiffness = ...}}, got {spec!r}")
        c, k = numbers(clearance), numbers(stiffness)
        if c is None or k is None:
            raise e.fail(f"stops.{axis}", f"expected numbers, got clearance {clearance!r}, stiffness {stiffness!r}")
        out[axis] = (c * e.units.factor("length"), k * e.units.factor("stiffness"))
    return out


def _curve(e: Entry) -> dict[str, Any] | None:
    """``curve = {z = [[deflection, force], ...]}`` in SI (the file's length and force units)."""
    table = e.table("curve")
    if table is None:
        return None
    out: dict[str, Any] = {}
    for axis, pts in table.items():
        a = numbers(pts)
        if a is None or a.ndim != 2 or a.shape[1] != 2:
            raise e.fail(f"curve.{axis}", f"expected [[deflection, force], ...] pairs, got {pts!r}")
        out[axis] = a * np.array([e.units.factor("length"), e.units.factor("force")])
    return out


def _rheology(e: Entry) -> dict[str, Any] | None:
    """The ``rheology = {type = ..., ...}`` table in SI (stiffness keys in the file's stiffness unit,
    ``c`` in its damping unit, ``tau`` in its time unit, frequencies in Hz); the model checks the rest."""
    table = e.table("rheology")
    if table is None:
        return None
    out: dict[str, Any] = {}
    for key, value in table.items():
        quantity = RHEOLOGY_QUANTITIES.get(key)
        if key == "type" or quantity is None:       # unknown keys: the model names them
            out[key] = value
            continue
        a = numbers(value)
        if a is None:
            raise e.fail(f"rheology.{key}", f"expected numbers, got {value!r}")
        out[key] = a if quantity == "frequency" else a * e.units.factor(quantity)
    return out


def _reference(e: Entry, key: str, names: Sequence[str], default: Any = MISSING,
               ground: bool = False) -> str:
    value = e.string(key, default)
    if value not in names and not (ground and value == GROUND):
        options = list(names) + ([GROUND] if ground else [])
        raise e.fail(key, f"unknown body {value!r}; expected one of {options}"
                     + did_you_mean(value, options))
    return value


def _support(e: Entry, i: int) -> Support:
    e.check_keys(("name", "description"), ("name",))
    try:
        return Support(e.string("name"), e.string("description", ""))
    except ModelError as exc:
        raise _wrap(e, exc) from None


def _mounts(e: Entry, i: int, types: Mapping[str, MountType], bodies: Sequence[str],
            supports: Sequence[str] = ()) -> tuple[Mount, ...]:
    e.check_keys(("name", "type", "body", "to", "at", "frame", "orientation", "symmetry", "support"),
                 ("type", "body"))
    tname = e.string("type")
    if tname not in types:
        raise e.fail("type", f"unknown mount type {tname!r}; [[mount_type]] names are {list(types)}"
                     + did_you_mean(tname, types))
    symmetry = e.string("symmetry", "none", SYMMETRIES)
    support = e.string("support", None)
    if support is not None and support not in supports:
        raise e.fail("support", f"unknown support {support!r}; "
                     + (f"[[support]] names are {list(supports)}" if supports else "the file has no [[support]] table")
                     + did_you_mean(support, supports))
    try:
        mount = Mount(e.string("name", f"mount{i}"), types[tname], _reference(e, "body", bodies),
                      e.array("at", [(3,)], "length", np.zeros(3)),
                      _reference(e, "to", bodies, GROUND, ground=True),
                      e.orientation("orientation"), e.string("frame", "body", ("body", "global")), support)
        return symmetric(mount, symmetry)
    except ModelError as exc:
        raise _wrap(e, exc) from None


def _control_point(e: Entry, i: int, bodies: Sequence[str]) -> ControlPoint:
    e.check_keys(("name", "body", "at", "frame"), ("body", "at"))
    try:
        return ControlPoint(e.string("name", f"point{i}"), _reference(e, "body", bodies),
                            e.array("at", [(3,)], "length"), e.string("frame", "body", ("body", "global")))
    except ModelError as exc:
        raise _wrap(e, exc) from None


def _element_fields(e: Entry, bodies: Sequence[str], mounts: Sequence[str]) -> dict[str, Any]:
    """The placement keys shared by [[actuator]] and [[sensor]] (body, to, at, frame, direction,
    mount, axis), read and checked against the model's bodies and mounts."""
    out: dict[str, Any] = {}
    if "body" in e:
        out["body"] = _reference(e, "body", bodies)
    if "to" in e:
        out["to"] = _reference(e, "to", bodies, ground=True)
    if "at" in e:
        out["at"] = e.array("at", [(3,)], "length")
    out["frame"] = e.string("frame", "body", ("body", "global"))
    if "direction" in e:
        out["direction"] = e.array("direction", [(3,)], "dimensionless")
    if "mount" in e:
        mount = e.string("mount")
        if mount not in mounts:
            raise e.fail("mount", f"unknown mount {mount!r}; mounts are {list(mounts)}"
                         + did_you_mean(mount, mounts))
        out["mount"] = mount
    if "axis" in e:
        axis = e.number("axis")
        if axis not in (1, 2, 3):
            raise e.fail("axis", f"expected 1, 2 or 3 (the mount's local axes), got {axis!r}")
        out["axis"] = int(axis)
    return out


def _actuator(e: Entry, bodies: Sequence[str], mounts: Sequence[str]) -> Actuator:
    e.check_keys(("name", "body", "to", "at", "frame", "direction", "mount", "axis", "bandwidth", "kind"),
                 ("name",))
    fields = _element_fields(e, bodies, mounts)
    try:
        return Actuator(e.string("name"), kind=e.string("kind", "force", ACTUATOR_KINDS),
                        bandwidth=e.number("bandwidth", default=None), **fields)
    except ModelError as exc:
        raise _wrap(e, exc) from None


def _sensor(e: Entry, bodies: Sequence[str], mounts: Sequence[str]) -> Sensor:
    e.check_keys(("name", "kind", "body", "to", "at", "frame", "direction", "mount", "axis"),
                 ("name", "kind"))
    kind = e.string("kind", choices=tuple(SENSOR_KINDS))
    fields = _element_fields(e, bodies, mounts)
    try:
        return Sensor(e.string("name"), kind, **fields)
    except ModelError as exc:
        raise _wrap(e, exc) from None


def _load(e: Entry, i: int, bodies: Sequence[str], cases: dict[str, list[str]]) -> Load:
    e.check_keys(("name", "case", "body", "force", "moment", "at", "frame"), ("body",))
    name = e.string("name", f"load{i}")
    case = e.string("case", "")
    cases.setdefault(case or "default", []).append(name)
    try:
        return Load(name, _reference(e, "body", bodies), force=e.array("force", [(3,)], "force", np.zeros(3)),
                    moment=e.array("moment", [(3,)], "moment", np.zeros(3)),
                    at=e.array("at", [(3,)], "length", None), frame=e.string("frame", "body", ("body", "global")),
                    case=case)
    except ModelError as exc:
        raise _wrap(e, exc) from None


def _excitation(e: Entry, i: int, bodies: Sequence[str], base: Path | None) -> Excitation:
    e.check_keys(("name", "kind", "target", "dof", "direction", "at", "frame", "function"),
                 ("kind", "target", "function"))
    kind = e.string("kind", choices=("force", "displacement", "velocity", "acceleration"))
    dof = e.string("dof", None, DOF_NAMES)
    if (dof is None) == ("direction" not in e):
        raise e.fail("dof", f"give exactly one of dof (one of {list(DOF_NAMES)}) and direction "
                     "(a 3-vector)")
    units = e.units
    try:
        function = function_from_dict(
            e.data["function"], f"{e.where}: function",
            value_scale=units.factor(amplitude_quantity(kind, dof)),
            time_scale=units.factor("time"), angle_scale=units.factor("angle"), base=base)
        return Excitation(e.string("name", f"excitation{i}"), kind,
                          _reference(e, "target", bodies, ground=True), function, dof,
                          e.array("direction", [(3,)], "dimensionless", None),
                          e.array("at", [(3,)], "length", None),
                          e.string("frame", "body", ("body", "global")))
    except ModelError as exc:
        raise _wrap(e, exc) from None


def _analysis(e: Entry, excitations: Sequence[Excitation] = ()) -> dict[str, Any]:
    e.check_keys(("time", "frequency", "harmonic_balance"))
    out: dict[str, Any] = {}
    hb = e.sub("harmonic_balance")
    if hb is not None:
        out["harmonic_balance"] = read_harmonic_balance(hb, excitations)
    t = e.sub("time")
    if t is not None:
        t.check_keys(("end", "step", "record_from", "tolerance"))
        out["time"] = {k: v for k, v in (
            ("end", t.number("end", "time", None, positive=True)),
            ("step", t.number("step", "time", None, positive=True)),
            ("record_from", t.number("record_from", "time", None, nonnegative=True)),
            ("tolerance", t.number("tolerance", "dimensionless", None, positive=True))) if v is not None}
        end = out["time"].get("end")
        if end is not None and out["time"].get("step", 0.0) > end:
            raise t.fail("step", f"must not exceed end ({t.data['end']})")
        if end is not None and out["time"].get("record_from", 0.0) >= end:
            raise t.fail("record_from", f"must be before end ({t.data['end']})")
    f = e.sub("frequency")
    if f is not None:
        f.check_keys(("f1", "f2", "points", "spacing"))
        out["frequency"] = {k: v for k, v in (
            ("f1", f.number("f1", "dimensionless", None, nonnegative=True)),
            ("f2", f.number("f2", "dimensionless", None, positive=True)),
            ("spacing", f.string("spacing", None, ("linear", "log")))) if v is not None}
        if "points" in f:
            points = f.data["points"]
            if isinstance(points, bool) or not isinstance(points, int) or points < 2:
                raise f.fail("points", f"expected a whole number >= 2, got {points!r}")
            out["frequency"]["points"] = points
        fr = out["frequency"]
        if "f1" in fr and "f2" in fr and not fr["f2"] > fr["f1"]:
            raise f.fail("f2", f"must be greater than f1 ({fr['f1']} Hz), got {fr['f2']} Hz")
        if fr.get("spacing") == "log" and fr.get("f1", 1.0) <= 0:
            raise f.fail("f1", "log spacing needs f1 > 0")
    return out


def _build(data: Any, source: str, base: Path | None, default_name: str,
           probe: Units | None = None) -> Model:
    if not isinstance(data, Mapping):
        raise ModelFileError(f"{source}: expected tables ([model], [[body]], ...) at the top level")
    for key in data:
        if key not in _TABLES:
            raise ModelFileError(f"{source}: unknown table [{key}]; expected some of {list(_TABLES)}"
                                 + did_you_mean(key, _TABLES))
    head = data.get("model", {})
    if not isinstance(head, Mapping):
        raise ModelFileError(f"{source}: model: expected a [model] table, got {head!r}")
    m = Entry(head, f"{source}: [model]", Units())
    m.check_keys(("name", "units", "gravity"))
    try:
        units = Units.from_mapping(m.table("units"))
    except ModelFileError:
        raise                               # already located (file and table)
    except ModelError as exc:
        raise ModelFileError(f"{source}: [model]: {exc}") from None
    file_units = units
    if probe is not None:                   # fileunits: the same data read with the probe's units
        units = probe
    m = Entry(head, m.where, units)
    initial: dict[str, Any] = {}
    bodies = [_body(e, i, initial) for i, e in enumerate(_entries(data, "body", source, units), 1)]
    if not bodies:
        raise ModelFileError(f"{source}: body: no [[body]] table; a model needs at least one body")
    names = [b.name for b in bodies]
    types: dict[str, MountType] = {}
    for e in _entries(data, "mount_type", source, units):
        t = _mount_type(e)
        if t.name in types:
            raise e.fail("name", f"mount type {t.name!r} is defined twice")
        types[t.name] = t
    supports = [_support(e, i) for i, e in enumerate(_entries(data, "support", source, units), 1)]
    support_names = [s.name for s in supports]
    mounts = [m for i, e in enumerate(_entries(data, "mount", source, units), 1)
              for m in _mounts(e, i, types, names, support_names)]
    points = [_control_point(e, i, names)
              for i, e in enumerate(_entries(data, "control_point", source, units), 1)]
    mount_names = [m.name for m in mounts]
    actuators = [_actuator(e, names, mount_names) for e in _entries(data, "actuator", source, units)]
    sensors = [_sensor(e, names, mount_names) for e in _entries(data, "sensor", source, units)]
    cases: dict[str, list[str]] = {}
    loads = [_load(e, i, names, cases) for i, e in enumerate(_entries(data, "load", source, units), 1)]
    excitations = [_excitation(e, i, names + support_names, base)
                   for i, e in enumerate(_entries(data, "excitation", source, units), 1)]
    seen: set[str] = set()
    for i, x in enumerate(excitations, 1):
        if x.name in seen:
            raise ModelFileError(f"{source}: excitation[{i}] ({x.name!r}): name: used twice; "
                                 "names must be unique")
        seen.add(x.name)
    analysis = data.get("analysis", {})
    if not isinstance(analysis, Mapping):
        raise ModelFileError(f"{source}: analysis: expected an [analysis] table, got {analysis!r}")
    settings = _analysis(Entry(analysis, f"{source}: [analysis]", units), excitations)
    for key, reader in (("design", read_design), ("study", read_study), ("orders", read_orders),
                        ("control", read_control), ("shock", read_shock), ("random", read_random)):
        if key in data:
            if not isinstance(data[key], Mapping):
                raise ModelFileError(f"{source}: {key}: expected a [{key}] table, got {data[key]!r}")
            settings[key] = reader(Entry(data[key], f"{source}: [{key}]", units))
    if initial:
        settings["initial"] = initial
    if set(cases) - {"default"}:
        settings["load_cases"] = cases
    settings["units"] = {k: v for k, v in vars(file_units).items() if v is not None}
    gravity, name = _gravity(m, units), m.string("name", default_name)
    try:
        return Model(bodies, mounts, points, loads, gravity, name, excitations, settings, actuators, sensors,
                     supports)
    except ModelError as exc:
        raise ModelFileError(f"{source}: {exc}") from None


def _gravity(m: Entry, units: Units) -> np.ndarray | None:
    """``[model] gravity``: 3 numbers in the file's acceleration unit, or ``"standard"`` (9.80665 m/s^2
    along -z). Numbers that look like m/s^2 in a file whose lengths are not metres get a warning."""
    import warnings

    from ..errors import VibssWarning
    from ..model.units import STANDARD_GRAVITY

    value = m.data.get("gravity")
    if isinstance(value, str):
        if value != "standard":
            raise m.fail("gravity", f"expected 3 numbers (in the file's acceleration unit) or \"standard\", got {value!r}")
        return np.array([0.0, 0.0, -STANDARD_GRAVITY])
    g = m.array("gravity", [(3,)], "acceleration", None)
    if g is not None and units.acceleration is None and units.length != "m":
        raw = float(np.linalg.norm(g)) / units.factor("acceleration")
        if 9.0 < raw < 10.5:
            warnings.warn(f"{m.where}: gravity {raw:.4g} is read in {units.label('acceleration')} (the file's "
                          f"units): {float(np.linalg.norm(g)):.4g} m/s^2, {STANDARD_GRAVITY / float(np.linalg.norm(g)):.0f}x "
                          "less than standard gravity; write gravity = \"standard\" or give it in "
                          f"{units.label('acceleration')}", VibssWarning, stacklevel=2)
    return g


# -- public loading --------------------------------------------------------------------------------
def loads_model(text: str, fmt: str = "toml", source: str = "<string>",
                base: str | Path | None = None) -> Model:
    """Model from the text of a model file.

    Parameters
    ----------
    text : str
        The file's contents.
    fmt : {"toml", "json"}
        Its format.
    source : str
        Name used in error messages (the file name).
    base : str or Path or None
        Folder that relative file names inside the model (table data) are taken from.

    Returns
    -------
    Model
        In SI units; see the module docstring for ``Model.settings``.

    Raises
    ------
    ModelFileError
        Any problem, located by file, entry and key (syntax errors: by line).

    Examples
    --------
    >>> text = '''
    ... [[body]]
    ... name = "box"
    ... mass = 2.0
    ... inertia = [0.1, 0.1, 0.1]
    ... '''
    >>> loads_model(text).bodies[0].mass
    2.0
    """
    data = parse_text(text, fmt, source)    # bounded depth and digits, unique keys, BOM skipped
    stem = Path(source).stem if not source.startswith("<") else "model"
    return _build(data, source, None if base is None else Path(base), stem)


def load_model(path: str | Path) -> Model:
    """Read a model file (``.toml`` or ``.json``, by extension).

    Parameters
    ----------
    path : str or Path
        The file.

    Returns
    -------
    Model
        In SI units.

    Raises
    ------
    ModelFileError
        The file cannot be read or is not a valid model (the message says where and why).
    """
    path = Path(path)
    fmt = {".toml": "toml", ".json": "json"}.get(path.suffix.lower())
    if fmt is None:
        raise ModelFileError(f"{path}: unknown model file type {path.suffix!r}; expected .toml or .json")
    try:        # a regular file of bounded size (a FIFO or /dev/zero named *.toml would hang)
        raw = read_regular_file(path, MAX_MODEL_FILE_BYTES, "model file", str(path))
    except ModelError as exc:
        raise ModelFileError(str(exc), argument="model file", received=str(path)) from None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ModelFileError(f"{path}: not UTF-8 text ({exc.reason})") from None
    return loads_model(text, fmt, str(path), path.parent)


# -- writing ---------------------------------------------------------------------------------------
def _orientation_dict(o: Orientation) -> dict[str, Any] | None:
    return None if np.array_equal(o.matrix, np.eye(3)) else {"matrix": o.matrix.tolist()}


def _plain(value: Any) -> Any:
    return value.tolist() if isinstance(value, np.ndarray) else value


UnitsLike = Union[Units, Mapping[str, str], str, None]


def file_units(model: Model, units: UnitsLike = None) -> Units:
    """The units :func:`dumps_model` writes ``model`` in.

    Parameters
    ----------
    model : Model
        The model; a model read from a file remembers that file's units (``settings["units"]``).
    units : Units, mapping, "SI" or None
        None: the model's file units (SI for a model built in Python); ``"SI"``: m, kg, N, s, rad;
        a mapping as in a file's ``[model] units`` table (``{"length": "mm"}``; angles default to
        degrees, as in files).

    Examples
    --------
    >>> file_units(load_example("powertrain")).length
    'mm'
    >>> file_units(load_example("powertrain"), "SI").length
    'm'
    """
    if isinstance(units, Units):
        return units
    if isinstance(units, str):
        if units.upper() != "SI":
            raise ModelError(f"units: expected 'SI', a Units or a mapping like {{'length': 'mm'}}, got {units!r}")
        return Units()
    if units is None:
        units = (model.settings or {}).get("units")
        if units is None:
            return Units()
    return Units.from_mapping(units)


def model_to_dict(model: Model, units: UnitsLike = "SI") -> dict[str, Any]:
    """The model as model-file data, ready for TOML or JSON.

    Mounts are written one by one (symmetry already expanded) and orientations as matrices. In SI
    (the default) loading the result gives exactly the same matrices; in other units (see
    :func:`file_units`) each number is the shortest that reads back to the same SI value, which
    it does for all but a few (within one rounding, 1e-16 relative).

    Parameters
    ----------
    model : Model
        The model.
    units : Units, mapping, "SI" or None
        The units to write the numbers in (:func:`file_units`); None: the model's own file units.
    """
    target = file_units(model, units)
    data = _si_dict(model)
    if target == Units():
        return data
    from .fileunits import ProbeUnits, convert_tree
    try:
        probed = _si_dict(_build(data, "<units probe>", None, "model", probe=ProbeUnits()))
        out = convert_tree(data, probed, target)
    except ModelError as exc:       # a number the reader does not scale linearly: keep SI, say so
        warnings.warn(f"model {model.name!r}: written in SI, not in {_units_text(target)}: {exc}",
                      VibssWarning, stacklevel=2)
        return data
    out["model"]["units"] = {k: v for k, v in vars(target).items() if v is not None}
    return out


def _units_text(u: Units) -> str:
    return ", ".join(v for v in vars(u).values() if v is not None)


def _si_dict(model: Model) -> dict[str, Any]:
    settings = model.settings or {}
    head: dict[str, Any] = {"name": model.name, "units": {
        "length": "m", "mass": "kg", "force": "N", "angle": "rad", "time": "s"}}
    if model.gravity is not None:
        head["gravity"] = model.gravity.tolist()
    out: dict[str, Any] = {"model": head, "body": []}
    initial = settings.get("initial", {})
    for b in model.bodies:
        d: dict[str, Any] = {"name": b.name, "mass": _plain(b.mass)}
        if b.inertia.shape == (3,):
            d["inertia"] = b.inertia.tolist()
            if (axes := _orientation_dict(b.principal_axes)) is not None:
                d["principal_axes"] = axes
        else:
            d["inertia_tensor"] = b.inertia.tolist()
        d["cog"] = b.cog.tolist()
        if b.name in initial:
            d["initial"] = dict(initial[b.name])
        out["body"].append(d)
    out["mount_type"] = [{"name": t.name, "stiffness": t.stiffness.tolist(),
                          "damping": t.damping.tolist(), "loss_factor": t.loss_factor.tolist()}
                         | ({} if t.rheology is None else {"rheology": t.rheology.to_dict()})
                         | ({} if not t.rotational else {"rotational_stiffness": t.rotational_stiffness.tolist(),
                                                         "rotational_damping": t.rotational_damping.tolist()})
                         | {key: m.tolist() for key in ("stiffness_matrix", "damping_matrix")
                            if (m := getattr(t, key)) is not None}
                         | ({} if t.stops is None else {"stops": {ax: {"clearance": list(c), "stiffness": k}
                                                                  for ax, (c, k) in t.stops.items()}})
                         | ({} if t.curve is None else {"curve": {ax: a.tolist() for ax, a in t.curve.items()}})
                         for t in model.mount_types.values()]
    out["mount"] = []
    for m in model.mounts:
        d = {"name": m.name, "type": m.type.name, "body": m.body, "to": m.to, "at": m.at.tolist(),
             "frame": m.frame}
        if (o := _orientation_dict(m.orientation)) is not None:
            d["orientation"] = o
        if m.support is not None:
            d["support"] = m.support
        out["mount"].append(d)
    if model.supports:
        out["support"] = [{"name": s.name} | ({"description": s.description} if s.description else {})
                          for s in model.supports]
    out["control_point"] = [{"name": c.name, "body": c.body, "at": c.at.tolist(), "frame": c.frame}
                            for c in model.control_points]
    for key, items in (("actuator", model.actuators), ("sensor", model.sensors)):
        out[key] = [_element_dict(x) for x in items]
    out["load"] = []
    for ld in model.loads:
        d = {"name": ld.name, "body": ld.body, "force": ld.force.tolist(), "moment": ld.moment.tolist()}
        if ld.at is not None:
            d.update(at=ld.at.tolist(), frame=ld.frame)
        if ld.case:
            d["case"] = ld.case
        out["load"].append(d)
    out["excitation"] = []
    for x in model.excitations:
        d = {"name": x.name, "kind": x.kind, "target": x.target}
        d.update({"dof": x.dof} if x.dof is not None else {"direction": x.direction.tolist()})
        if x.at is not None:
            d.update(at=x.at.tolist(), frame=x.frame)
        f = x.function.to_dict()
        d["function"] = f["terms"] if f["type"] == "sum" else f
        out["excitation"].append(d)
    analysis = {k: dict(settings[k]) for k in ("time", "frequency", "harmonic_balance") if k in settings}
    if analysis:
        out["analysis"] = analysis
    out.update(write_tables(settings))
    return {k: v for k, v in out.items() if v != []}


def _element_dict(x: Actuator | Sensor) -> dict[str, Any]:
    """An [[actuator]] or [[sensor]] entry (only the keys that are set)."""
    if isinstance(x, Actuator) and x.dynamics is not None:
        raise ModelError(f"actuator {x.name!r}: its dynamics (a python-control system) cannot be "
                         "written to a model file; give a bandwidth [Hz] instead")
    if isinstance(x, Sensor) and x.noise is not None:
        raise ModelError(f"sensor {x.name!r}: its noise PSD is not written to model files yet; save the "
                         "model without it (dataclasses.replace(sensor, noise=None)) and give the noise in Python")
    d: dict[str, Any] = {"name": x.name}
    if isinstance(x, Sensor):
        d["kind"] = x.kind
    elif x.kind != "force":
        d["kind"] = x.kind
    for key in ("body", "to", "mount", "axis"):
        if getattr(x, key) is not None:
            d[key] = getattr(x, key)
    if x.mount is None:
        d.update(at=x.at.tolist(), frame=x.frame)
    if x.direction is not None:
        d["direction"] = x.direction.tolist()
    if isinstance(x, Actuator) and x.bandwidth is not None:
        d["bandwidth"] = x.bandwidth
    return d


def dumps_model(model: Model, fmt: str = "toml", units: UnitsLike = None) -> str:
    """The model as the text of a model file, in its own units (floats written exactly).

    Parameters
    ----------
    model : Model
        The model.
    fmt : {"toml", "json"}
        Output format.
    units : Units, mapping, "SI" or None
        None (default): the units of the file the model was read from (a model built in Python:
        SI); ``"SI"``; or a mapping like ``{"length": "mm"}`` (see :func:`file_units`). Comments
        of the original file are not kept.

    Returns
    -------
    str

    Examples
    --------
    >>> text = dumps_model(load_example("powertrain"))          # read in mm: written in mm
    >>> 'length = "mm"' in text
    True
    """
    if fmt not in ("toml", "json"):
        raise ModelError(f"unknown model file format {fmt!r}; expected 'toml' or 'json'")
    data = model_to_dict(model, units)
    if fmt == "json":
        return json.dumps(data, indent=2) + "\n"
    return dumps_toml(data, header="vibss model file, written by vibss.io.dumps_model (units: "
                                   f"{_units_text(Units.from_mapping(data['model']['units']))})")


def dump_model(model: Model, path: str | Path, units: UnitsLike = None) -> None:
    """Write the model to ``path`` (``.toml`` or ``.json``, by extension).

    Parameters
    ----------
    model : Model
        The model.
    path : str or Path
        The file to write.
    units : Units, mapping, "SI" or None
        As in :func:`dumps_model` (default: the model's own file units).
    """
    path = Path(path)
    fmt = {".toml": "toml", ".json": "json"}.get(path.suffix.lower())
    if fmt is None:
        raise ModelFileError(f"{path}: unknown model file type {path.suffix!r}; expected .toml or .json")
    path.write_text(dumps_model(model, fmt, units), encoding="utf-8")


# -- examples --------------------------------------------------------------------------------------
def example_names() -> list[str]:
    """Names of the built-in example models (``vibss example list``)."""
    return sorted(p.stem for p in EXAMPLES_DIR.glob("*.toml"))


def example_path(name: str) -> Path:
    """Path of the built-in example ``name`` (with or without ``.toml``).

    Raises
    ------
    ModelError
        Unknown name (the message lists the examples).
    """
    stem = name[:-5] if name.endswith(".toml") else name
    names = example_names()
    if stem not in names:
        raise ModelError(f"unknown example {name!r}; examples are {names}" + did_you_mean(stem, names))
    return EXAMPLES_DIR / f"{stem}.toml"


def load_example(name: str) -> Model:
    """Load the built-in example model ``name`` (see :func:`example_names`).

    Parameters
    ----------
    name : str
        Example name, e.g. ``"powertrain"`` (``vibss example list`` shows them all).

    Returns
    -------
    Model

    Examples
    --------
    >>> load_example("two_mass").n_dof
    12
    """
    return load_model(example_path(name))
