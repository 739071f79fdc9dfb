"""Model-file data from SI back into a file's own units (``dumps_model(model, units=...)``).

The reader is the one place that knows which quantity each number of a model file is (a stiffness,
a damping, an amplitude in g, a PSD level in g^2/Hz, a rheology's relaxation time ...). Rather than
list those a second time for the writer, the writer asks the reader: it reads the SI data once
more with :class:`ProbeUnits`, whose base units are the primes 2 (length), 3 (mass), 5 (force),
7 (time), 11 (angle) and 13 (acceleration when it has its own unit), and writes that model out
again. Each number then comes back multiplied by its quantity's factor, a product of those primes,
from which the powers of the base units follow exactly (:func:`powers_of`); dividing the SI number
by the same powers of the wanted units gives the number in those units (:func:`in_units`).

Examples
--------
>>> powers_of(5 / 2)                   # force / length: a stiffness
{'length': -1, 'force': 1}
>>> in_units(2.0e5, {'length': -1, 'force': 1}, Units(length="mm"))   # 2e5 N/m
200.0
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

from ..errors import ModelError
from ..model.units import BASE_UNITS, QUANTITIES, STANDARD_GRAVITY, Units

__all__ = ["ProbeUnits", "powers_of", "in_units", "convert_tree"]

PRIMES: dict[str, int] = {"length": 2, "mass": 3, "force": 5, "time": 7, "angle": 11, "acceleration": 13}
"""The probe's value of one unit of each base dimension (acceleration: its own unit, e.g. g)."""


@dataclass(frozen=True)
class ProbeUnits(Units):
    """Units whose base factors are distinct primes (see the module docstring); SI spellings."""

    def factor(self, quantity: str) -> float:
        if quantity == "acceleration":
            return float(PRIMES["acceleration"])
        f = Fraction(1)
        for dim, power in QUANTITIES[quantity].items():
            f *= Fraction(PRIMES[dim]) ** power
        return float(f)

    def label(self, quantity: str) -> str:
        return f"<{quantity}>"


def powers_of(ratio: float) -> dict[str, int]:
    """The base-unit powers whose probe factor is ``ratio`` (a product of powers of ``PRIMES``).

    Raises
    ------
    ModelError
        ``ratio`` is no such product (the number is not linear in the units).
    """
    if not ratio > 0:
        raise ModelError(f"probe ratio {ratio!r} is not positive")
    frac = Fraction(ratio).limit_denominator(10**12)
    if abs(float(frac) - ratio) > 1e-12 * ratio:
        raise ModelError(f"probe ratio {ratio!r} is not a ratio of small integers")
    out: dict[str, int] = {}
    num, den = frac.numerator, frac.denominator
    for dim, p in PRIMES.items():
        k = 0
        while num % p == 0:
            num //= p
            k += 1
        while den % p == 0:
            den //= p
            k -= 1
        if k:
            out[dim] = k
    if num != 1 or den != 1:
        raise ModelError(f"probe ratio {ratio!r} has a factor {num}/{den} that is no unit")
    return out


def _factor(powers: Mapping[str, int], units: Units) -> float:
    """SI value of one unit of the quantity with these powers, in ``units``."""
    f = 1.0
    for dim, k in powers.items():
        if dim == "acceleration":
            base = (STANDARD_GRAVITY if units.acceleration == "g"
                    else BASE_UNITS["length"][units.length] / BASE_UNITS["time"][units.time] ** 2)
        else:
            base = BASE_UNITS[dim][getattr(units, dim)]
        f *= base ** k
    return f


def in_units(si: float, powers: Mapping[str, int], units: Units) -> float:
    """``si`` written in ``units``: the shortest number that the reader turns back into ``si``.

    Of ``si / f``, ``si * (1/f)`` and their 15-digit roundings, the first whose reading
    (``value * f``, as the reader does it) gives ``si`` exactly, else the nearest of them.
    """
    if not powers or si == 0:
        return si
    f = _factor(powers, units)
    raw = [si / f, si * (1.0 / f)]
    candidates = sorted({float(f"{v:.15g}") for v in raw} | set(raw), key=lambda v: len(repr(v)))
    for v in candidates:
        if v * f == si:
            return v
    return min(candidates, key=lambda v: abs(v * f - si))


def convert_tree(si: Any, probe: Any, units: Units, where: str = "") -> Any:
    """``si`` (model-file data in SI) in ``units``, the powers of each number read off ``probe``
    (the same data read with :class:`ProbeUnits` and written again).

    Raises
    ------
    ModelError
        The two trees differ in shape, or a number is not linear in the units.
    """
    if isinstance(si, Mapping):
        if not isinstance(probe, Mapping) or set(si) != set(probe):
            raise ModelError(f"{where or 'model'}: the probe's keys differ")
        return {k: convert_tree(v, probe[k], units, f"{where}.{k}" if where else str(k)) for k, v in si.items()}
    if isinstance(si, list):
        if not isinstance(probe, list) or len(si) != len(probe):
            raise ModelError(f"{where}: the probe's list differs")
        return [convert_tree(a, b, units, f"{where}[{i}]") for i, (a, b) in enumerate(zip(si, probe))]
    if isinstance(si, bool) or not isinstance(si, (int, float)):
        return si
    if si == 0:
        return si
    if not isinstance(probe, (int, float)) or isinstance(probe, bool):
        raise ModelError(f"{where}: the probe has no number here")
    powers = powers_of(probe / si)
    return si if not powers else in_units(float(si), powers, units)
