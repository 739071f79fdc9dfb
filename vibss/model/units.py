"""Units of model files and their conversion to SI.

The library works in SI (m, kg, N, s, rad). A model file may declare other units for its numbers
(``[model] units = { length = "mm" }``); they are converted once, on load, with the factors here.
Derived quantities follow from the five base units: a file in mm gives stiffness in N/mm, damping
in N s/mm, inertia in kg mm^2, moments in N mm and accelerations in mm/s^2. Frequencies are always
in Hz, whatever the time unit.

Examples
--------
>>> u = Units(length="mm")
>>> u.factor("stiffness")        # 1 N/mm = 1000 N/m
1000.0
>>> u.label("damping")
'N s/mm'
>>> float(Units(angle="deg").to_si(180.0, "angle"))
3.141592653589793
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from ..errors import ModelError

__all__ = ["BASE_UNITS", "QUANTITIES", "Units", "STANDARD_GRAVITY", "G", "times_s", "input_unit", "ratio_unit"]

BASE_UNITS: dict[str, dict[str, float]] = {
    "length": {"m": 1.0, "cm": 0.01, "mm": 0.001, "in": 0.0254, "ft": 0.3048},
    "mass": {"kg": 1.0, "g": 0.001, "t": 1000.0, "lb": 0.45359237},
    "force": {"N": 1.0, "kN": 1000.0, "lbf": 4.4482216152605},
    "angle": {"rad": 1.0, "deg": math.pi / 180.0},
    "time": {"s": 1.0, "ms": 0.001},
}
"""SI value of one unit, per base dimension (exact definitions: 1 in = 0.0254 m, 1 lb = 0.45359237 kg)."""

QUANTITIES: dict[str, dict[str, int]] = {
    "length": {"length": 1},
    "mass": {"mass": 1},
    "force": {"force": 1},
    "angle": {"angle": 1},
    "time": {"time": 1},
    "stiffness": {"force": 1, "length": -1},
    "damping": {"force": 1, "time": 1, "length": -1},
    "inertia": {"mass": 1, "length": 2},
    "moment": {"force": 1, "length": 1},
    "rotational_stiffness": {"force": 1, "length": 1, "angle": -1},
    "rotational_damping": {"force": 1, "length": 1, "time": 1, "angle": -1},
    "coupling_stiffness": {"force": 1, "angle": -1},
    "coupling_damping": {"force": 1, "time": 1, "angle": -1},
    "velocity": {"length": 1, "time": -1},
    "acceleration": {"length": 1, "time": -2},
    "angular_velocity": {"angle": 1, "time": -1},
    "angular_acceleration": {"angle": 1, "time": -2},
    "force_rate": {"force": 1, "time": -1},
    "moment_rate": {"force": 1, "length": 1, "time": -1},
    "dimensionless": {},
}
"""Each quantity as powers of the base dimensions."""

STANDARD_GRAVITY = 9.80665
"""Standard gravity [m/s^2]: the ``g`` acceleration unit (``units = { acceleration = "g" }``), the
``g`` of shock and random specifications, and the default gravity of the design measures. Written
here once; everything else imports it."""

G = STANDARD_GRAVITY
"""Standard gravity [m/s^2] by its short name (``vibss.shock.G``, ``vibss.random.G``)."""

_ORDER = ("force", "mass", "length", "angle", "time")  # how labels are written: N s/mm


@dataclass(frozen=True)
class Units:
    """The units a model file's numbers are written in.

    Parameters
    ----------
    length : {"m", "cm", "mm", "in", "ft"}
    mass : {"kg", "g", "t", "lb"}
    force : {"N", "kN", "lbf"}
    angle : {"rad", "deg"}
        Default rad here (SI); model files default to deg (see :meth:`from_mapping`).
    time : {"s", "ms"}
    acceleration : {"g"} or None
        Unit of accelerations (excitation amplitudes, ``gravity``): ``"g"`` = 9.80665 m/s^2
        (standard gravity); None: length/time^2 of the units above.
    """

    length: str = "m"
    mass: str = "kg"
    force: str = "N"
    angle: str = "rad"
    time: str = "s"
    acceleration: str | None = None

    def __post_init__(self) -> None:
        if self.acceleration not in (None, "g"):
            raise ModelError(f"units: acceleration: unknown unit {self.acceleration!r}; expected \"g\" "
                             "(standard gravity, 9.80665 m/s^2) or leave it out (length/time^2)")
        for dim, table in BASE_UNITS.items():
            unit = getattr(self, dim)
            if not isinstance(unit, str) or unit not in table:
                raise ModelError(
                    f"units: {dim}: unknown unit {unit!r}; expected one of {list(table)}"
                    + (_did_you_mean(unit, table) if isinstance(unit, str) else "")
                )

    @classmethod
    def from_mapping(cls, data: Any, angle: str = "deg") -> Units:
        """Units from a model file's ``units`` table.

        Parameters
        ----------
        data : mapping or None
            ``{"length": "mm", ...}``; missing entries are SI, except ``angle``.
        angle : str
            Angle unit when ``data`` gives none (files: degrees).

        Examples
        --------
        >>> Units.from_mapping({"length": "mm"})
        Units(length='mm', mass='kg', force='N', angle='deg', time='s', acceleration=None)
        """
        if data is None:
            data = {}
        if not isinstance(data, Mapping):
            raise ModelError(f"units: expected a table like {{ length = \"mm\" }}, got {data!r}")
        for key in data:
            if key not in BASE_UNITS and key != "acceleration":
                raise ModelError(f"units: unknown key {key!r}; expected some of {list(BASE_UNITS)}"
                                 + _did_you_mean(key, BASE_UNITS))
        return cls(**{"angle": angle, **dict(data)})

    def factor(self, quantity: str) -> float:
        """SI value of one file unit of ``quantity`` (e.g. ``"stiffness"``: 1000.0 for N/mm)."""
        if quantity == "acceleration" and self.acceleration == "g":
            return STANDARD_GRAVITY
        f = 1.0
        for dim, power in _powers(quantity).items():
            f *= BASE_UNITS[dim][getattr(self, dim)] ** power
        return f

    def to_si(self, value: npt.ArrayLike, quantity: str) -> np.ndarray:
        """``value`` (in these units) converted to SI, as a float array."""
        return np.asarray(value, dtype=float) * self.factor(quantity)

    def label(self, quantity: str) -> str:
        """Unit symbol of ``quantity`` in these units, e.g. ``'N/mm'`` (``'-'`` if dimensionless)."""
        if quantity == "acceleration" and self.acceleration == "g":
            return "g"
        powers = _powers(quantity)
        num = [_sym(getattr(self, d), p) for d in _ORDER if (p := powers.get(d, 0)) > 0]
        den = [_sym(getattr(self, d), -p) for d in _ORDER if (p := powers.get(d, 0)) < 0]
        text = " ".join(num) or ("1" if den else "-")
        return text + ("/" + " ".join(den) if den else "")


def _powers(quantity: str) -> dict[str, int]:
    try:
        return QUANTITIES[quantity]
    except KeyError:
        raise ModelError(f"unknown quantity {quantity!r}; expected one of {list(QUANTITIES)}"
                         + _did_you_mean(quantity, QUANTITIES)) from None


def _sym(unit: str, power: int) -> str:
    return unit if power == 1 else f"{unit}^{power}"


def _did_you_mean(name: Any, options: Any) -> str:
    lower = {str(o).lower(): str(o) for o in options}  # unit symbols: case matters, typos of it too
    close = difflib.get_close_matches(str(name).lower(), list(lower), n=1)
    return f" (did you mean {lower[close[0]]!r}?)" if close else ""


# -- the unit algebra of signals and their ratios ---------------------------------------------------


def times_s(unit: str, k: int) -> str:
    """``unit`` times ``s^-k``: a displacement unit's velocity (k = 1) or acceleration (k = 2) unit.

    Examples
    --------
    >>> times_s("m", 2), times_s("m/s", 1), times_s("N", 1), times_s("rad/s^2", -2)
    ('m/s^2', 'm/s^2', 'N/s', 'rad')
    """
    base, power = unit, 0
    for p in (3, 2, 1):
        tail = "/s" if p == 1 else f"/s^{p}"
        if unit.endswith(tail):
            base, power = unit[:-len(tail)], p
            break
    power += k
    if power == 0:
        return base
    if power < 0:
        return f"{base} s" if power == -1 else f"{base} s^{-power}"
    return f"{base}/s" if power == 1 else f"{base}/s^{power}"


def input_unit(name: str, kind: str) -> str:
    """SI unit of an input signal from its name and kind (``"force"``, ``"displacement"`` ...).

    Examples
    --------
    >>> input_unit("engine.fz", "force"), input_unit("engine.my", "force"), input_unit("ground.rx.acc", "acceleration")
    ('N', 'N m', 'rad/s^2')
    """
    if kind == "force":
        last = name.rsplit(".", 1)[-1]
        return "N m" if last in ("mx", "my", "mz", "m") else "N"
    parts = name.split(".")
    dof = parts[-2] if len(parts) >= 2 else ""
    base = "rad" if dof.startswith("r") and dof in ("rx", "ry", "rz") else "m"
    return times_s(base, {"displacement": 0, "velocity": 1, "acceleration": 2}.get(kind, 0))


def ratio_unit(numerator: str, denominator: str) -> str:
    """The unit of ``numerator / denominator``, parenthesised where needed: ``m/N``,
    ``(m/s^2)/(m/s^2)``, ``N/(N m)``.

    Examples
    --------
    >>> ratio_unit("m", "N"), ratio_unit("m/s^2", "m/s^2"), ratio_unit("N", "N m")
    ('m/N', '(m/s^2)/(m/s^2)', 'N/(N m)')
    """
    def wrap(u: str) -> str:
        return f"({u})" if ("/" in u or " " in u) else u

    return f"{wrap(numerator)}/{wrap(denominator)}"
