"""The ``[orders]`` table of a model file: rotating sources and the speed range of ``vibss orders``.

Read into ``Model.settings["orders"]`` in SI (rates in rpm stay rpm) and written back by
:func:`~vibss.io.modelfile.model_to_dict`. Lengths, forces, moments and angles are in the file's
units. Example (a file in mm and N)::

    [orders]
    rpm = [300.0, 6000.0]                  # speed range [rpm]
    points = 400                           # speeds in the range (default 400)
    outputs = ["powertrain.rx", "mount.engine.fz"]

    [[orders.unbalance]]
    name = "crank"
    body = "powertrain"
    mass = 0.005                           # kg
    radius = 50.0                          # mm
    axis = "x"                             # or [x, y, z]
    at = [0.0, 0.0, 480.0]                 # optional: a point of the unbalance plane (global)
    order = 1.0                            # optional
    phase = 0.0                            # optional, angle unit

    [[orders.force]]
    name = "2nd order torque"
    body = "powertrain"
    order = 2.0
    rpm = [300.0, 6000.0]                  # table speeds [rpm]
    moment = [[6.0e4, 0.0, 0.0], [6.0e4, 0.0, 0.0]]    # N mm per speed; or force = [...] [N]
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from ..errors import ModelFileError
from .filetable import Entry, numbers

__all__ = ["read_orders"]

_UNBALANCE = ("name", "body", "mass", "radius", "axis", "at", "order", "phase")
_FORCE = ("name", "body", "order", "rpm", "force", "moment", "phase")


def _list(e: Entry, key: str) -> list[Entry]:
    value = e.data.get(key, [])
    if isinstance(value, Mapping):
        value = [value]
    if not isinstance(value, list) or not all(isinstance(x, Mapping) for x in value):
        raise e.fail(key, f"expected [[orders.{key}]] tables, got {value!r}")
    return [Entry(x, f"{e.where}: {key}[{i}]" + (f" ({x['name']!r})" if isinstance(x.get("name"), str) else ""),
                  e.units) for i, x in enumerate(value, 1)]


def _axis(e: Entry) -> Any:
    value = e.data.get("axis", "x")
    if isinstance(value, str):
        if value not in ("x", "y", "z"):
            raise e.fail("axis", f"expected 'x', 'y', 'z' or 3 numbers, got {value!r}")
        return value
    return e.array("axis", [(3,)], "dimensionless").tolist()


def _rows(e: Entry, key: str, quantity: str, n: int) -> Any:
    return e.array(key, [(3,), (n, 3)], quantity).tolist() if key in e else None


def read_orders(e: Entry) -> dict[str, Any]:
    """The ``[orders]`` table as plain data in SI: ``rpm``, ``points``, ``outputs``, ``unbalance``
    and ``force`` lists of keyword dictionaries for :class:`vibss.orders.Unbalance` /
    :class:`vibss.orders.OrderForce`."""
    e.check_keys(("rpm", "points", "outputs", "unbalance", "force"))
    out: dict[str, Any] = {}
    if "rpm" in e:
        rpm = e.array("rpm", [(2,)], "dimensionless", positive=True).tolist()
        if not rpm[1] > rpm[0]:
            raise e.fail("rpm", f"expected [low, high] with low < high, got {e.data['rpm']!r}")
        out["rpm"] = rpm
    if "points" in e:
        p = e.data["points"]
        if isinstance(p, bool) or not isinstance(p, int) or p < 2:
            raise e.fail("points", f"expected a whole number >= 2, got {p!r}")
        out["points"] = p
    if "outputs" in e:
        o = e.data["outputs"]
        if not isinstance(o, list) or not o or not all(isinstance(x, str) and x for x in o):
            raise e.fail("outputs", f"expected a list of signal names, got {o!r}")
        out["outputs"] = list(o)
    unb = []
    for u in _list(e, "unbalance"):
        u.check_keys(_UNBALANCE, required=("name", "body", "mass", "radius"))
        d: dict[str, Any] = {"name": u.string("name"), "body": u.string("body"),
                             "mass": u.number("mass", "mass", positive=True),
                             "radius": u.number("radius", "length", positive=True), "axis": _axis(u)}
        if "at" in u:
            d["at"] = u.array("at", [(3,)], "length").tolist()
        if "order" in u:
            d["order"] = u.number("order", positive=True)
        if "phase" in u:
            d["phase"] = u.number("phase", "angle")
        unb.append(d)
    forces = []
    for f in _list(e, "force"):
        f.check_keys(_FORCE, required=("name", "body", "order", "rpm"))
        a = numbers(f.data["rpm"])
        n = 1 if a is None or a.ndim == 0 else a.shape[0]
        d = {"name": f.string("name"), "body": f.string("body"), "order": f.number("order", positive=True),
             "rpm": f.array("rpm", [(), (n,)], "dimensionless", positive=True).tolist()}
        if "force" not in f and "moment" not in f:
            raise f.fail(None, "give force, moment or both (amplitudes per global axis)")
        for key, q in (("force", "force"), ("moment", "moment")):
            rows = _rows(f, key, q, n)
            if rows is not None:
                d[key] = rows
        if "phase" in f:
            d["phase"] = f.array("phase", [(6,)], "angle").tolist()
        forces.append(d)
    if not unb and not forces:
        raise ModelFileError(f"{e.where}: no [[orders.unbalance]] or [[orders.force]] source")
    out["unbalance"], out["force"] = unb, forces
    return out
