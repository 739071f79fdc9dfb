"""The ``[shock]`` and ``[random]`` tables of a model file: the environments ``vibss srs`` and
``vibss random`` run (and the report's environment section).

Read into ``Model.settings["shock"]`` / ``["random"]`` in SI and written back by the model writer.
Levels are in the file's acceleration unit (``units = { acceleration = "g" }`` for g and g^2/Hz)::

    [shock]
    excitation = "drop-shock"            # a transient [[excitation]] of the file (the input)
    outputs = ["item.z.acc"]             # responses whose SRS is taken (default: the input's only)
    band = [5.0, 2000.0]                 # SRS natural frequencies [Hz]
    points = 60
    q = 10.0
    spec = { frequency = [5.0, 100.0, 2000.0], level = [5.0, 80.0, 80.0], lower_db = -3.0, upper_db = 6.0 }

    [random]
    input = "ground.z.acc"               # a ground-motion or force input signal
    psd = { frequency = [20.0, 80.0, 350.0, 2000.0], level = [0.01, 0.04, 0.04, 0.007] }
    outputs = ["item.z.acc", "mount.m.dz"]
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .filetable import Entry

__all__ = ["read_shock", "read_random"]


def _names(e: Entry, key: str) -> list[str] | None:
    if key not in e:
        return None
    value = e.data[key]
    if not isinstance(value, list) or not value or not all(isinstance(x, str) for x in value):
        raise e.fail(key, f"expected a non-empty list of signal names, got {value!r}")
    return list(value)


def _table(e: Entry, key: str, quantity: str, squared: bool, extra: tuple[str, ...] = ()) -> dict[str, Any] | None:
    sub = e.sub(key)
    if sub is None:
        return None
    sub.check_keys(("frequency", "level", *extra), ("frequency", "level"))
    raw = sub.data.get("frequency")
    n = len(raw) if isinstance(raw, list) else -1
    f = sub.array("frequency", [(max(n, 2),)], "dimensionless", positive=True)
    lv = sub.array("level", [(f.size,)], "dimensionless", nonnegative=True)
    if f.size < 2 or np.any(np.diff(f) <= 0):
        raise sub.fail("frequency", f"expected >= 2 increasing frequencies [Hz], got {f.tolist()}")
    factor = e.units.factor(quantity)
    out = {"frequency": f.tolist(), "level": (lv * (factor * factor if squared else factor)).tolist()}
    for k in extra:
        if k in sub:
            out[k] = sub.number(k)
    return out


def read_shock(e: Entry) -> dict[str, Any]:
    """``[shock]`` in SI (spec levels in m/s^2)."""
    e.check_keys(("excitation", "outputs", "band", "points", "q", "spec"), ("excitation",))
    out: dict[str, Any] = {"excitation": e.string("excitation")}
    if (outputs := _names(e, "outputs")) is not None:
        out["outputs"] = outputs
    if "band" in e:
        band = e.array("band", [(2,)], "dimensionless", positive=True)
        if not band[0] < band[1]:
            raise e.fail("band", f"expected [low, high] with low < high [Hz], got {band.tolist()}")
        out["band"] = band.tolist()
    if "points" in e:
        p = e.number("points")
        if p != int(p) or p < 2:
            raise e.fail("points", f"expected an integer >= 2, got {p!r}")
        out["points"] = int(p)
    if "q" in e:
        q = e.number("q")
        if not q > 0.5:
            raise e.fail("q", f"expected a quality factor > 0.5, got {q!r}")
        out["q"] = q
    spec = _table(e, "spec", "acceleration", False, ("lower_db", "upper_db"))
    if spec is not None:
        out["spec"] = spec
    return out


def read_random(e: Entry) -> dict[str, Any]:
    """``[random]`` in SI (PSD levels in (m/s^2)^2/Hz for accelerations, N^2/Hz for forces)."""
    e.check_keys(("input", "psd", "outputs"), ("input", "psd"))
    signal = e.string("input")
    last = signal.rsplit(".", 1)[-1]
    quantity = {"acc": "acceleration", "vel": "velocity", "disp": "length"}.get(last, "force")
    out: dict[str, Any] = {"input": signal, "psd": _table(e, "psd", quantity, True)}
    if (outputs := _names(e, "outputs")) is not None:
        out["outputs"] = outputs
    return out
