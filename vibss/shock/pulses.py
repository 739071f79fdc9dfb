"""Standard shock pulses (IEC 60068-2-27, MIL-STD-810 516) as vibss time functions.

Amplitudes are given in g (standard gravity ``G``, :data:`vibss.model.units.STANDARD_GRAVITY`) and
returned in m/s^2, so the time function can drive a base-acceleration input of :func:`vibss.simulate`
directly. The duration has no default: a specification always states it.
"""

from __future__ import annotations

from .. import _validate as v
from ..errors import ArgumentError
from ..model.timefunctions import HalfSine, Haversine, Sawtooth, Table
from ..model.units import G


def _args(amplitude_g: float, duration: float, start: float, who: str) -> tuple[float, float, float]:
    a = v.number(amplitude_g, "amplitude_g", who=who)
    d = v.number(duration, "duration", who=who, minimum=0.0)
    if d <= 0.0:
        raise ArgumentError(f"{who}: duration must be > 0 s, got {d}", argument="duration", received=d)
    s = v.number(start, "start", who=who)
    return a * G, d, s


def half_sine(amplitude_g: float, duration: float, *, start: float = 0.0) -> HalfSine:
    """Half-sine pulse of peak ``amplitude_g`` [g] lasting ``duration`` [s], in m/s^2.

    Examples
    --------
    >>> round(float(half_sine(50.0, 0.011).value(0.0055)), 3)
    490.332
    """
    a, d, s = _args(amplitude_g, duration, start, "half_sine")
    return HalfSine(amplitude=a, start=s, duration=d)


def haversine(amplitude_g: float, duration: float, *, start: float = 0.0) -> Haversine:
    """Haversine pulse of peak ``amplitude_g`` [g] lasting ``duration`` [s], in m/s^2."""
    a, d, s = _args(amplitude_g, duration, start, "haversine")
    return Haversine(amplitude=a, start=s, duration=d)


def sawtooth(amplitude_g: float, duration: float, *, start: float = 0.0) -> Sawtooth:
    """Terminal-peak saw-tooth: linear rise to ``amplitude_g`` [g] at ``duration`` [s], then zero."""
    a, d, s = _args(amplitude_g, duration, start, "sawtooth")
    return Sawtooth(amplitude=a, start=s, duration=d)


def trapezoid(amplitude_g: float, duration: float, rise: float, *, start: float = 0.0) -> Table:
    """Trapezoid of plateau ``amplitude_g`` [g], total ``duration`` [s] and equal rise/fall ``rise`` [s].

    Returned as a piecewise-linear :class:`~vibss.model.timefunctions.Table` (exact on the modal
    time path, which is exact for piecewise-linear inputs).
    """
    a, d, s = _args(amplitude_g, duration, start, "trapezoid")
    r = v.number(rise, "rise", who="trapezoid", minimum=0.0)
    if not 0.0 < r <= 0.5 * d:
        raise ArgumentError(f"trapezoid: rise must be in (0, duration/2], got {r}", argument="rise",
                              received=r)
    return Table([s, s + r, s + d - r, s + d], [0.0, a, a, 0.0])


__all__ = ["G", "half_sine", "haversine", "sawtooth", "trapezoid"]
