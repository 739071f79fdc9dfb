"""The ``[design]`` and ``[study]`` tables of a model file: what ``vibss design`` and ``vibss study``
run when the file says so.

Both are read into ``Model.settings`` (``"design"`` and ``"study"``), in SI, and written back by
:func:`~vibss.io.modelfile.model_to_dict`. Parameter names are ``"<mount>.<kind>"`` as in
:mod:`vibss.design.parameters`; their values are in the file's units of the kind: rates in its
stiffness unit, shifts in its length unit, angles in its angle unit, rate ratios plain numbers.

Example (a file in mm, N and degrees)::

    [design]
    purity = 0.9                  # every rigid-body mode at least 90 % pure
    frame = "tra"                 # energy split along the torque-roll axis
    windows = [6.0, 18.0]         # Hz, every mode; or { z = [8, 14], rx = [6, 12] }
    modes = ["rx", "z"]           # modes whose mean purity is maximised (default: all)
    max_sag = 3.0                 # mm, vertical sag of the COG under weight
    samples = 10000               # Monte Carlo variants for the tolerance study
    beta = 2.0                    # optional: keep the windows 2 sigma inside under the tolerances
    [design.variables]            # bounds of each design variable
    "engine.k3" = [150.0, 400.0]  # N/mm
    "engine.k1/k3" = [0.2, 0.6]   # -
    "engine.rx" = [-20.0, 20.0]   # deg
    # several mounts tied: (mount, kind, factor) targets, the value is factor x the variable
    "engine pair spread" = { bounds = [-30.0, 30.0], targets = [["engine", "y", 1], ["engine.xz", "y", -1]] }
    [design.catalogue]            # optional discrete rates
    "engine.k3" = [200.0, 250.0, 300.0]
    [design.tolerances]           # relative for rates and ratios, absolute for shifts and angles
    "engine.k3" = 0.15

    [study]
    analysis = "modes"            # or "certificate"
    [study.grid]                  # every combination (or [study.table]: one variant per row)
    "engine.k3" = [200.0, 250.0, 300.0]
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from .filetable import Entry, numbers

__all__ = ["DESIGN_KEYS", "STUDY_KEYS", "read_design", "read_study", "kind_quantity", "write_tables"]

DESIGN_KEYS = ("purity", "frame", "axis", "windows", "modes", "max_sag", "method", "starts",
               "samples", "sampling", "beta", "variables", "catalogue", "tolerances")
STUDY_KEYS = ("analysis", "grid", "table")
_FRAMES = ("global", "tra", "principal")
_AXES = ("x", "y", "z")
_DOFS = ("x", "y", "z", "rx", "ry", "rz")


def kind_quantity(name: str) -> str:
    """The file quantity of a parameter ``"<mount>.<kind>"`` (``"stiffness"``, ``"length"``,
    ``"angle"`` or ``"dimensionless"``); ``"dimensionless"`` for names that are not parameters."""
    kind = name.rsplit(".", 1)[-1]
    if "/" in kind:
        return "dimensionless"
    return {"k1": "stiffness", "k2": "stiffness", "k3": "stiffness", "x": "length", "y": "length",
            "z": "length", "rx": "angle", "ry": "angle", "rz": "angle"}.get(kind, "dimensionless")


def _columns(e: Entry, shape: tuple[int, ...] | None, *, relative: bool = False) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for name in e.data:
        value = numbers(e.data[name])
        q = kind_quantity(name)
        if relative and q in ("stiffness", "dimensionless"):
            q = "dimensionless"                   # a relative tolerance
        if shape is None:                         # any 1-D list of values
            if value is None or value.ndim != 1 or not value.size:
                raise e.fail(name, f"expected a list of numbers [{e.units.label(q)}], got {e.data[name]!r}")
            out[name] = e.array(name, [value.shape], q).tolist()
        else:
            out[name] = e.array(name, [shape], q).tolist()
    return out


def _tied(e: Entry) -> dict[str, Any]:
    """A tied variable ``{bounds = [lo, hi], targets = [[mount, kind, factor], ...]}``."""
    e.check_keys(("bounds", "targets"), required=("bounds", "targets"))
    targets = e.data["targets"]
    kinds = {"k1", "k2", "k3", "x", "y", "z", "rx", "ry", "rz", "k1/k3", "k2/k3", "k1/k2", "k2/k1", "k3/k1", "k3/k2"}
    if not (isinstance(targets, list) and targets and all(
            isinstance(t, list) and len(t) == 3 and isinstance(t[0], str) and t[1] in kinds
            and isinstance(t[2], (int, float)) and not isinstance(t[2], bool) for t in targets)):
        raise e.fail("targets", f"expected a list of [mount, kind, factor] with kind one of {sorted(kinds)}, "
                     f"got {targets!r}")
    quantities = {kind_quantity(f"m.{t[1]}") for t in targets}
    if len(quantities) != 1:
        raise e.fail("targets", f"mixes quantities {sorted(quantities)}; tie kinds of one unit")
    bounds = e.array("bounds", [(2,)], quantities.pop()).tolist()
    return {"bounds": bounds, "targets": [[t[0], t[1], float(t[2])] for t in targets]}


def read_design(e: Entry) -> dict[str, Any]:
    """The ``[design]`` table as keyword arguments of :func:`vibss.design.optimize` /
    :func:`~vibss.design.certificate` / :func:`~vibss.design.monte_carlo` (SI)."""
    e.check_keys(DESIGN_KEYS)
    out: dict[str, Any] = {}
    if "purity" in e:
        out["purity"] = e.number("purity")
        if not 0.0 < out["purity"] <= 1.0:
            raise e.fail("purity", f"expected a fraction in (0, 1], got {e.data['purity']!r}")
    for key, choices in (("frame", _FRAMES), ("axis", _AXES), ("method", ("SLSQP", "trust-constr", "global")),
                         ("sampling", ("random", "lhs", "sobol"))):
        if key in e:
            out[key] = e.string(key, choices=choices)
    if "windows" in e:
        w = e.data["windows"]
        if isinstance(w, Mapping):
            sub = Entry(w, f"{e.where}: windows", e.units)
            sub.check_keys(_DOFS)
            out["windows"] = {d: sub.array(d, [(2,)], "dimensionless", nonnegative=True).tolist() for d in w}
        else:
            out["windows"] = e.array("windows", [(2,)], "dimensionless", nonnegative=True).tolist()
    if "modes" in e:
        modes = e.data["modes"]
        if not isinstance(modes, list) or not modes or not all(
                (isinstance(m, int) and not isinstance(m, bool) and m >= 1) or m in _DOFS for m in modes):
            raise e.fail("modes", f"expected a list of mode numbers (1, 2 ...) or DOF names {list(_DOFS)}, "
                         f"got {modes!r}")
        out["modes"] = list(modes)
    if "beta" in e:
        out["beta"] = e.number("beta", nonnegative=True)
        if "tolerances" not in e or "windows" not in e:
            raise e.fail("beta", "a reliability-based optimisation needs windows and [design.tolerances]")
    if "max_sag" in e:
        out["max_sag"] = e.number("max_sag", "length", positive=True)
    for key in ("starts", "samples"):
        if key in e:
            v = e.data[key]
            if isinstance(v, bool) or not isinstance(v, int) or v < 1:
                raise e.fail(key, f"expected a whole number >= 1, got {v!r}")
            out[key] = v
    for key, shape in (("variables", (2,)), ("catalogue", None), ("tolerances", ())):
        part = e.sub(key)
        if part is not None:
            tied = {k: v for k, v in part.data.items() if isinstance(v, Mapping)} if key == "variables" else {}
            plain = Entry({k: v for k, v in part.data.items() if k not in tied}, part.where, part.units)
            read = _columns(plain, shape, relative=key == "tolerances")
            for name, value in tied.items():
                read[name] = _tied(Entry(value, f"{part.where}: {name!r}", e.units))
            out[key] = {k: read[k] for k in part.data}            # the file's order
    for name, (lo, hi) in ((k, v if isinstance(v, list) else v["bounds"]) for k, v in out.get("variables", {}).items()):
        if not lo < hi:
            raise e.fail("variables", f"{name!r}: expected [lower, upper] with lower < upper, got "
                         f"{e.data['variables'][name]!r}")
    for name in out.get("catalogue", {}):
        if name not in out.get("variables", {}):
            raise e.fail("catalogue", f"{name!r} is not in [design.variables]; catalogue values need bounds there")
    tied_names = {k for k, v in out.get("variables", {}).items() if isinstance(v, dict)}
    for name in out.get("tolerances", {}):
        if name in tied_names:
            continue
        kind = name.rsplit(".", 1)[-1]
        if "." not in name or kind_quantity(name) == "dimensionless" and "/" not in kind:
            raise e.fail("tolerances", f"{name!r}: expected '<mount>.<kind>' or the name of a tied "
                         "variable in [design.variables]")
    return out


def read_study(e: Entry) -> dict[str, Any]:
    """The ``[study]`` table: ``analysis`` and ``grid`` or ``table`` (values in SI)."""
    e.check_keys(STUDY_KEYS)
    out: dict[str, Any] = {"analysis": e.string("analysis", "modes", ("modes", "certificate"))}
    if ("grid" in e) == ("table" in e):
        raise e.fail(None, "give exactly one of [study.grid] (every combination) and [study.table] "
                     "(one variant per row)")
    key = "grid" if "grid" in e else "table"
    sub = e.sub(key) or Entry({}, f"{e.where}: {key}", e.units)
    if not sub.data:
        raise e.fail(key, "is empty; give at least one parameter and its values")
    out[key] = _columns(sub, None)
    if key == "table" and len({len(v) for v in out[key].values()}) != 1:
        raise e.fail("table", "every column must have the same length, got "
                     f"{ {k: len(v) for k, v in out[key].items()} }")
    return out


def write_tables(settings: Mapping[str, Any]) -> dict[str, Any]:
    """``[design]`` / ``[study]`` / ``[orders]`` / ``[control]`` data for a model file written in SI
    (angles in rad)."""
    out: dict[str, Any] = {}
    for key in ("design", "study", "orders", "control", "shock", "random"):
        if key in settings:
            out[key] = {k: (dict(v) if isinstance(v, Mapping) else v) for k, v in settings[key].items()}
    return out
