"""``[analysis] harmonic_balance``: the steady periodic response a model file asks for.

Read into ``Model.settings["harmonic_balance"]`` in SI and written back by
:func:`~vibss.io.modelfile.model_to_dict` (in the file's units). The report's "Harmonic balance"
section and ``vibss frf --harmonic-balance`` run :func:`vibss.harmonic_balance` with it. Example (a
file in mm, kg, N)::

    [analysis]
    harmonic_balance = { inputs = { "ground.z.acc" = 2000.0 }, outputs = ["mount.foot.d3"],
                         f1 = 5.0, f2 = 40.0, harmonics = 7, points = 200 }

``inputs`` maps an input signal (``cabinet.fz``, ``ground.z.acc`` ...) or an ``[[excitation]]``'s
name (its signal, as it drives the plant) to the sine amplitude in the file's unit of that signal
(force, moment, length, angle, velocity or acceleration; ``g`` where the file's acceleration is in
g). ``f1``, ``f2``: the frequency range [Hz]; ``harmonics``: the highest harmonic kept (default 5);
``points``: continuation steps over the range (default 200); ``outputs``: output signals (default
every body DOF's displacement).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from ..model.excitation import Excitation, amplitude_quantity
from .filetable import Entry

__all__ = ["read_harmonic_balance", "harmonic_balance_arguments", "KEYS", "input_quantity"]

KEYS = ("inputs", "outputs", "f1", "f2", "harmonics", "points")
"""Keys of the ``harmonic_balance`` table."""

_MOTION = {"disp": "displacement", "vel": "velocity", "acc": "acceleration"}
_DOFS = ("x", "y", "z", "rx", "ry", "rz")


def input_quantity(name: str, excitations: Sequence[Excitation] = ()) -> str | None:
    """The quantity (:data:`vibss.model.units.QUANTITIES`) of an input's amplitude, from an
    excitation of that name or the signal grammar; None when the name is neither.

    Examples
    --------
    >>> input_quantity("engine.fz"), input_quantity("ground.rx.acc"), input_quantity("engine")
    ('force', 'angular_acceleration', None)
    """
    for x in excitations:
        if x.name == name:
            return amplitude_quantity(x.kind, x.dof)
    parts = name.split(".")
    if len(parts) >= 2 and parts[-1] in ("fx", "fy", "fz", "f"):
        return "force"
    if len(parts) >= 2 and parts[-1] in ("mx", "my", "mz", "m"):
        return "moment"
    if len(parts) >= 3 and parts[-1] in _MOTION and parts[-2] in _DOFS:
        return amplitude_quantity(_MOTION[parts[-1]], parts[-2])
    return None


def _whole(e: Entry, key: str, default: int, least: int) -> int:
    value = e.data.get(key, default)
    if isinstance(value, bool) or not isinstance(value, int) or value < least:
        raise e.fail(key, f"expected a whole number >= {least}, got {value!r}")
    return value


def read_harmonic_balance(e: Entry, excitations: Sequence[Excitation] = ()) -> dict[str, Any]:
    """The ``harmonic_balance`` table as plain data in SI: ``inputs`` (name to amplitude), ``f1``,
    ``f2`` [Hz], ``harmonics``, ``points`` and, when given, ``outputs``.

    Raises
    ------
    ModelFileError
        An unknown or missing key, an input that is neither a signal nor an excitation, an
        amplitude that is not a finite number, ``f2 <= f1``, a count that is not a whole number.
    """
    e.check_keys(KEYS, ("inputs", "f1", "f2"))
    raw = e.data["inputs"]
    if not isinstance(raw, Mapping) or not raw:
        raise e.fail("inputs", "expected a table of input signal (or excitation name) to amplitude, e.g. "
                     f"{{ \"ground.z.acc\" = 2000.0 }}, got {raw!r}")
    inputs: dict[str, float] = {}
    table = Entry(raw, f"{e.where}: inputs", e.units)
    for name in raw:
        quantity = input_quantity(str(name), excitations)
        if quantity is None:
            raise table.fail(name, "neither an input signal (<body>.fz, <body>.mx, ground.z.acc, "
                             "<body>.x.disp ...) nor an [[excitation]]'s name "
                             f"{[x.name for x in excitations]}")
        inputs[str(name)] = table.number(name, quantity)
    out: dict[str, Any] = {"inputs": inputs, "f1": e.number("f1", positive=True),
                           "f2": e.number("f2", positive=True)}
    if not out["f2"] > out["f1"]:
        raise e.fail("f2", f"must be greater than f1 ({out['f1']} Hz), got {out['f2']} Hz")
    out["harmonics"] = _whole(e, "harmonics", 5, 1)
    out["points"] = _whole(e, "points", 200, 2)
    if "outputs" in e:
        outs = e.data["outputs"]
        if not isinstance(outs, list) or not outs or not all(isinstance(o, str) and o for o in outs):
            raise e.fail("outputs", f"expected a list of output signal names, got {outs!r}")
        out["outputs"] = list(outs)
    return out


def harmonic_balance_arguments(spec: Mapping[str, Any], excitations: Sequence[Excitation] = ()) -> dict[str, Any]:
    """Keyword arguments of :func:`vibss.harmonic_balance` from the table read by
    :func:`read_harmonic_balance` (an excitation's name becomes its plant input signal)."""
    signal = {x.name: x.signal for x in excitations}
    return {"inputs": {signal.get(k, k): v for k, v in spec["inputs"].items()},
            "outputs": spec.get("outputs"), "frequencies": (spec["f1"], spec["f2"]),
            "harmonics": spec["harmonics"], "points": spec["points"]}
