"""The ``[control]`` table of a model file: the active isolation design ``vibss control`` runs.

Read into ``Model.settings["control"]`` (SI) and written back by the model writer. Example::

    [control]
    design = "skyhook"             # skyhook | velocity_feedback | integral_force
    gain = 1200.0                  # per loop: N s/m (skyhook, velocity_feedback) or rad/s (integral_force)
    leak = 0.1                     # integral_force only: leaky-integrator corner [Hz]
    disturbances = ["ground.z.vel"]
    performance = ["table.z.vel"]  # outputs whose transmissibility is reported
    measurements = ["sensor.fl.z.geo", ...]   # optional: default every sensor
"""

from __future__ import annotations

from typing import Any

from .filetable import Entry

__all__ = ["read_control", "CONTROL_DESIGNS"]

CONTROL_DESIGNS = ("skyhook", "velocity_feedback", "integral_force")
"""Designs a model file can ask for."""


def _names(e: Entry, key: str, required: bool) -> list[str] | None:
    if key not in e:
        if required:
            raise e.fail(key, f"expected a list of signal names, e.g. {key} = [\"ground.z.vel\"]")
        return None
    value = e.data[key]
    if not isinstance(value, list) or not value or not all(isinstance(x, str) for x in value):
        raise e.fail(key, f"expected a non-empty list of signal names, got {value!r}")
    return list(value)


def read_control(e: Entry) -> dict[str, Any]:
    """``[control]`` as a dict (see the module docstring); every bad key named."""
    e.check_keys(("design", "gain", "leak", "disturbances", "performance", "measurements"),
                 ("design", "gain", "disturbances", "performance"))
    out: dict[str, Any] = {"design": e.string("design", choices=CONTROL_DESIGNS),
                           "gain": e.number("gain", nonnegative=True),
                           "disturbances": _names(e, "disturbances", True),
                           "performance": _names(e, "performance", True)}
    if "leak" in e:
        if out["design"] != "integral_force":
            raise e.fail("leak", "only applies to design = \"integral_force\"")
        out["leak"] = e.number("leak", nonnegative=True)
    measurements = _names(e, "measurements", False)
    if measurements is not None:
        out["measurements"] = measurements
    return out
