"""Time functions of excitations: pulses, steps, ramps, sines, sweeps, tables and their sums.

Each is a frozen dataclass with

- ``value(t)``: the value at times ``t`` [s] (vectorised, SI, in the unit of what it drives);
- ``breakpoints``: times [s] where the value or its slope jumps (pulse edges, table knots), so
  that an integrator can land on them;
- ``end_time``: the time [s] after which the value is identically zero or constant (``inf`` if
  never).

They are chosen by name through :data:`FUNCTIONS` (the model file's ``type`` key); plain data is
turned into them by :func:`vibss.model.excitation.function_from_dict`. They add up: ``f + g`` is a
:class:`Sum`.

Examples
--------
>>> pulse = HalfSine(amplitude=1000.0, start=0.01, duration=0.02)
>>> float(pulse.value(0.02))                 # the peak, at start + duration / 2
1000.0
>>> pulse.breakpoints
(0.01, 0.03)
>>> (Step(1.0, start=0.5) + Ramp(2.0)).value([0.25, 1.0]).tolist()
[0.5, 3.0]
"""

# Over 600 lines on purpose (issue 28): the catalogue of time functions, one small frozen class each
# (pulses, steps, ramps, sines, sweeps, tables, sums) with the shared base; a module per function
# would scatter the one registry that files and excitations read.

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np
import numpy.typing as npt

from ..errors import AnalysisError, ModelError

__all__ = [
    "TimeFunction", "Step", "Rectangular", "HalfSine", "Haversine", "Triangle", "Sawtooth",
    "Ramp", "Sine", "SineSweep", "Table", "Sum", "FUNCTIONS", "Sinusoid",
]


@dataclass(frozen=True)
class Sinusoid:
    """An additive sine/cosine piece of a time function: ``a cos(w (t - t0)) + b sin(w (t - t0))``
    on ``[t0, t1)``, zero outside.

    A function that declares its pieces (:attr:`TimeFunction.sinusoids`) is piecewise linear once
    they are subtracted (its breakpoints include every ``t0`` and finite ``t1``); the exact modal
    time path (:func:`vibss.time.kernels.modal.run_modal`) then integrates it exactly at any step.

    Attributes
    ----------
    t0, t1 : float
        Window [s] (``t1`` may be ``inf``).
    omega : float
        Angular frequency [rad/s], > 0.
    a, b : float
        Cosine and sine amplitudes [unit of the function].
    """

    t0: float
    t1: float
    omega: float
    a: float
    b: float

    def value(self, t: npt.ArrayLike) -> np.ndarray:
        """The piece at times ``t`` [s] (zero outside its window)."""
        t = np.asarray(t, dtype=float)
        tau = t - self.t0
        inside = (t >= self.t0) & (t < self.t1)
        return np.where(inside, self.a * np.cos(self.omega * tau) + self.b * np.sin(self.omega * tau), 0.0)


def _check_number(value: Any, kind: str, key: str, *, positive: bool = False,
                  nonnegative: bool = False, allow_inf: bool = False) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)):
        raise ModelError(f"{kind} function: {key}: expected a number, got {value!r}")
    v = float(value)
    if math.isnan(v) or (math.isinf(v) and not allow_inf):
        raise ModelError(f"{kind} function: {key}: must be finite, got {v}")
    if positive and not v > 0:
        raise ModelError(f"{kind} function: {key}: must be > 0, got {v}")
    if nonnegative and not v >= 0:
        raise ModelError(f"{kind} function: {key}: must be >= 0, got {v}")
    return v


@dataclass(frozen=True)
class TimeFunction:
    """Base of the time functions: see the module docstring for the protocol."""

    type: ClassVar[str] = ""
    #: Role of each parameter, for unit conversion on load: "value" (the excitation's unit),
    #: "time" [s], "rate" (value per second), "frequency" [Hz], "angle" [rad], "text", "data".
    roles: ClassVar[dict[str, str]] = {}
    #: Parameter names in files that differ from the attribute names (``{"time": "times"}``).
    aliases: ClassVar[dict[str, str]] = {}

    def value(self, t: npt.ArrayLike) -> np.ndarray:
        """Value at times ``t`` [s], in the SI unit of what the function drives."""
        raise NotImplementedError

    def _num(self, key: str, **checks: bool) -> float:
        """Validate parameter ``key`` as a number (see ``_check_number``) and store it as float."""
        v = _check_number(getattr(self, key), self.type, key, **checks)
        object.__setattr__(self, key, v)
        return v

    def _window(self) -> None:
        """Validate ``start`` and ``end`` [s] (``end`` may be ``inf``; it must follow ``start``)."""
        start = self._num("start")
        end = self._num("end", allow_inf=True)
        if end <= start:
            raise ModelError(f"{self.type} function: end: must be after start ({start}), got {end}")

    @property
    def breakpoints(self) -> tuple[float, ...]:
        """Sorted times [s] where the value or its slope jumps."""
        return ()

    @property
    def sinusoids(self) -> tuple[Sinusoid, ...]:
        """Sine/cosine pieces; the function minus them is piecewise linear between its breakpoints
        (empty: the function is integrated from its samples, linear between them)."""
        return ()

    @property
    def end_time(self) -> float:
        """Time [s] after which the value is identically zero or constant (``inf``: never)."""
        return math.inf

    @property
    def steady_state(self) -> bool:
        """Whether this is a frequency-domain (steady-state) excitation with no time history."""
        return False

    def to_dict(self) -> dict[str, Any]:
        """Plain data (SI) that :func:`function_from_dict` turns back into this function."""
        out: dict[str, Any] = {"type": self.type}
        defaults = {f.name: f.default for f in dataclasses.fields(self)}
        for key in self.roles:
            name = self.aliases.get(key, key)
            v = getattr(self, name)
            if isinstance(v, np.ndarray):
                out[key] = v.tolist()
            elif defaults[name] is dataclasses.MISSING or v != defaults[name]:
                out[key] = v
        return out

    def __add__(self, other: TimeFunction) -> Sum:
        if not isinstance(other, TimeFunction):
            return NotImplemented
        left = self.terms if isinstance(self, Sum) else (self,)
        right = other.terms if isinstance(other, Sum) else (other,)
        return Sum(left + right)


def _linear(f: TimeFunction) -> bool:
    """Whether ``f`` is piecewise linear between its breakpoints (a sum of such terms is too)."""
    return isinstance(f, (Step, Rectangular, Triangle, Sawtooth, Ramp, Table)) or (
        isinstance(f, Sum) and all(_linear(t) for t in f.terms))


def _edges(*times: float) -> tuple[float, ...]:
    return tuple(sorted({t for t in times if math.isfinite(t)}))


@dataclass(frozen=True)
class Step(TimeFunction):
    """Constant ``amplitude`` from ``start`` until ``end`` (the handbook program's type 1).

    Parameters
    ----------
    amplitude : float
        Value while on [unit of the excitation].
    start : float
        Switch-on time [s].
    end : float
        Switch-off time [s]; ``inf`` (default): stays on.
    """

    type: ClassVar[str] = "step"
    roles: ClassVar[dict[str, str]] = {"amplitude": "value", "start": "time", "end": "time"}
    amplitude: float
    start: float = 0.0
    end: float = math.inf

    def __post_init__(self) -> None:
        self._num("amplitude")
        self._window()

    def value(self, t: npt.ArrayLike) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        return np.where((t >= self.start) & (t < self.end), float(self.amplitude), 0.0)

    @property
    def breakpoints(self) -> tuple[float, ...]:
        return _edges(self.start, self.end)

    @property
    def end_time(self) -> float:
        return self.end if math.isfinite(self.end) else self.start


@dataclass(frozen=True)
class _Pulse(TimeFunction):
    """A pulse of ``amplitude`` lasting ``duration`` from ``start``; zero before and after."""

    roles: ClassVar[dict[str, str]] = {"amplitude": "value", "start": "time", "duration": "time"}
    amplitude: float
    start: float = 0.0
    duration: float = math.nan      # required: a pulse without a stated length is refused

    def __post_init__(self) -> None:
        self._num("amplitude")
        self._num("start")
        d = self.duration
        if isinstance(d, float) and math.isnan(d):
            raise ModelError(f"{self.type} function: duration: missing (required: the pulse's length [s], "
                             "e.g. 0.011 for an 11 ms shock; there is no default)")
        self._num("duration", positive=True)

    def _shape(self, u: np.ndarray) -> np.ndarray:
        """Pulse shape on ``0 <= u < 1`` (u = fraction of the duration), peak 1."""
        raise NotImplementedError

    def value(self, t: npt.ArrayLike) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        inside = (t >= self.start) & (t < self.end_time)  # the edges exactly as in breakpoints
        u = np.clip((t - self.start) / self.duration, 0.0, 1.0)
        return np.where(inside, self.amplitude * self._shape(u), 0.0)

    @property
    def breakpoints(self) -> tuple[float, ...]:
        return _edges(self.start, self.start + self.duration)

    @property
    def end_time(self) -> float:
        return self.start + self.duration


class Rectangular(_Pulse):
    """Rectangular pulse: ``amplitude`` on ``[start, start + duration)``.

    Parameters
    ----------
    amplitude : float
        Height [unit of the excitation].
    start : float
        Start [s].
    duration : float
        Length [s], > 0.
    """

    type: ClassVar[str] = "rectangular"

    def _shape(self, u: np.ndarray) -> np.ndarray:
        return np.ones_like(u)


class HalfSine(_Pulse):
    """Half-sine pulse ``A sin(pi (t - start) / duration)``; area ``2 A duration / pi``.

    Parameters as :class:`Rectangular`.
    """

    type: ClassVar[str] = "half_sine"

    def _shape(self, u: np.ndarray) -> np.ndarray:
        return np.sin(np.pi * u)

    @property
    def sinusoids(self) -> tuple[Sinusoid, ...]:
        return (Sinusoid(self.start, self.start + self.duration, math.pi / self.duration, 0.0, self.amplitude),)


class Haversine(_Pulse):
    """Haversine pulse ``A sin^2(pi (t - start) / duration)`` (smooth edges); area ``A duration / 2``.

    Parameters as :class:`Rectangular`.
    """

    type: ClassVar[str] = "haversine"

    def _shape(self, u: np.ndarray) -> np.ndarray:
        return np.sin(np.pi * u) ** 2

    @property
    def sinusoids(self) -> tuple[Sinusoid, ...]:
        # A sin^2(pi u) = A/2 - A/2 cos(2 pi u): the constant is the piecewise-linear rest
        return (Sinusoid(self.start, self.start + self.duration, 2 * math.pi / self.duration,
                         -0.5 * self.amplitude, 0.0),)


class Triangle(_Pulse):
    """Symmetric triangular pulse peaking at ``start + duration / 2``; area ``A duration / 2``.

    Parameters as :class:`Rectangular`.
    """

    type: ClassVar[str] = "triangle"

    def _shape(self, u: np.ndarray) -> np.ndarray:
        return 1.0 - np.abs(2.0 * u - 1.0)

    @property
    def breakpoints(self) -> tuple[float, ...]:
        return _edges(self.start, self.start + 0.5 * self.duration, self.start + self.duration)


class Sawtooth(_Pulse):
    """Terminal-peak sawtooth: rises linearly to ``A`` at ``start + duration``, then drops to 0.

    Parameters as :class:`Rectangular`.
    """

    type: ClassVar[str] = "sawtooth"

    def _shape(self, u: np.ndarray) -> np.ndarray:
        return u


@dataclass(frozen=True)
class Ramp(TimeFunction):
    """``slope (t - start)`` from ``start``, held at its final value after ``end``.

    Parameters
    ----------
    slope : float
        Rate [unit of the excitation per s].
    start : float
        Start [s].
    end : float
        End of the rise [s]; ``inf`` (default): rises for ever.
    """

    type: ClassVar[str] = "ramp"
    roles: ClassVar[dict[str, str]] = {"slope": "rate", "start": "time", "end": "time"}
    slope: float
    start: float = 0.0
    end: float = math.inf

    def __post_init__(self) -> None:
        self._num("slope")
        self._window()

    def value(self, t: npt.ArrayLike) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        return self.slope * (np.clip(t, self.start, self.end) - self.start)

    @property
    def breakpoints(self) -> tuple[float, ...]:
        return _edges(self.start, self.end)

    @property
    def end_time(self) -> float:
        return self.end


@dataclass(frozen=True)
class Sine(TimeFunction):
    """``A sin(2 pi f (t - start) + phase)`` on ``[start, end)``, zero outside.

    Parameters
    ----------
    amplitude : float
        Amplitude [unit of the excitation].
    frequency : float
        Frequency [Hz], >= 0.
    phase : float
        Phase at ``start`` [rad] (model files: the file's angle unit, degrees by default).
    start, end : float
        On interval [s]; ``end`` defaults to ``inf``.
    """

    type: ClassVar[str] = "sine"
    roles: ClassVar[dict[str, str]] = {"amplitude": "value", "frequency": "frequency",
                                       "phase": "angle", "start": "time", "end": "time"}
    amplitude: float
    frequency: float
    phase: float = 0.0
    start: float = 0.0
    end: float = math.inf

    def __post_init__(self) -> None:
        self._num("amplitude")
        self._num("frequency", nonnegative=True)
        self._num("phase")
        self._window()

    def value(self, t: npt.ArrayLike) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        s = self.amplitude * np.sin(2 * np.pi * self.frequency * (t - self.start) + self.phase)
        return np.where((t >= self.start) & (t < self.end), s, 0.0)

    @property
    def breakpoints(self) -> tuple[float, ...]:
        return _edges(self.start, self.end)

    @property
    def sinusoids(self) -> tuple[Sinusoid, ...]:
        if self.frequency <= 0:
            return ()                                   # a constant A sin(phase): linear already
        return (Sinusoid(self.start, self.end, 2 * math.pi * self.frequency,
                         self.amplitude * math.sin(self.phase), self.amplitude * math.cos(self.phase)),)

    @property
    def end_time(self) -> float:
        return self.end


@dataclass(frozen=True)
class SineSweep(TimeFunction):
    """Swept sine from ``f1`` to ``f2``, amplitude linear in frequency from ``a1`` to ``a2``.

    ``value(t) = a(f(t)) sin(phi(t))`` for ``start <= t < start + sweep_time``, zero outside, with the
    instantaneous frequency ``f(t) = phi'(t) / 2 pi`` linear (``law="linear"``) or exponential
    (``"log"``) in time and the phase integrated exactly (``phi(start) = 0``). ``sweep_time = 0``
    is the infinitely slow sweep of the handbook's program: a steady state at every frequency,
    used by frequency analyses through :meth:`amplitude_at`; it has no time history.

    Parameters
    ----------
    f1, f2 : float
        First and last frequency [Hz], >= 0 (> 0 for the log law).
    a1, a2 : float
        Amplitude at ``f1`` and at ``f2`` [unit of the excitation].
    sweep_time : float
        Duration [s], >= 0.
    law : {"linear", "log"}
        How the frequency moves with time.
    start : float
        Start time [s].

    Examples
    --------
    >>> s = SineSweep(f1=10.0, f2=20.0, a1=1.0, a2=3.0, sweep_time=2.0)
    >>> float(s.frequency_at(1.0)), float(s.amplitude_at(15.0))
    (15.0, 2.0)
    """

    type: ClassVar[str] = "sine_sweep"
    roles: ClassVar[dict[str, str]] = {"f1": "frequency", "f2": "frequency", "a1": "value",
                                       "a2": "value", "sweep_time": "time", "law": "text",
                                       "start": "time"}
    f1: float
    f2: float
    a1: float
    a2: float
    sweep_time: float = 0.0
    law: str = "linear"
    start: float = 0.0

    def __post_init__(self) -> None:
        for key in ("f1", "f2"):
            self._num(key, nonnegative=True)
        for key in ("a1", "a2", "start"):
            self._num(key)
        self._num("sweep_time", nonnegative=True)
        if self.law not in ("linear", "log"):
            raise ModelError(f"sine_sweep function: law: expected 'linear' or 'log', got {self.law!r}")
        if self.law == "log" and not (self.f1 > 0 and self.f2 > 0):
            raise ModelError(f"sine_sweep function: f1, f2: a log sweep needs frequencies > 0, "
                             f"got f1 = {self.f1}, f2 = {self.f2}")

    @property
    def steady_state(self) -> bool:
        """Whether this is the infinitely slow sweep (``sweep_time == 0``)."""
        return self.sweep_time == 0.0

    def _transient(self) -> None:
        if self.steady_state:
            raise AnalysisError(
                "sine_sweep function with sweep_time = 0 is a steady state (frequency-domain) "
                "excitation and has no time history; give sweep_time > 0 for a time study")

    def frequency_at(self, t: npt.ArrayLike) -> np.ndarray:
        """Instantaneous frequency [Hz] at times ``t`` [s] (held at f1 / f2 outside the sweep)."""
        self._transient()
        u = np.clip((np.asarray(t, dtype=float) - self.start) / self.sweep_time, 0.0, 1.0)
        if self.law == "log":
            return self.f1 * (self.f2 / self.f1) ** u
        return self.f1 + (self.f2 - self.f1) * u

    def phase_at(self, t: npt.ArrayLike) -> np.ndarray:
        """Phase ``phi(t)`` [rad], the exact integral of ``2 pi f`` from ``start`` (clipped to the sweep)."""
        self._transient()
        T = self.sweep_time
        tau = np.clip(np.asarray(t, dtype=float) - self.start, 0.0, T)
        if self.law == "log" and self.f1 != self.f2:
            lnr = math.log(self.f2 / self.f1)
            return 2 * np.pi * self.f1 * T / lnr * np.expm1(lnr * tau / T)
        return 2 * np.pi * (self.f1 * tau + 0.5 * (self.f2 - self.f1) * tau**2 / T)

    def amplitude_at(self, f_hz: npt.ArrayLike) -> np.ndarray:
        """Amplitude [unit of the excitation] at frequency ``f_hz`` [Hz]; zero outside [f1, f2]."""
        f = np.asarray(f_hz, dtype=float)
        lo, hi = min(self.f1, self.f2), max(self.f1, self.f2)
        tol = 1e-9 * max(hi, 1e-300)
        inside = (f >= lo - tol) & (f <= hi + tol)
        if self.f1 == self.f2:
            return np.where(inside, float(self.a1), 0.0)
        a = self.a1 + (self.a2 - self.a1) * (f - self.f1) / (self.f2 - self.f1)
        return np.where(inside, a, 0.0)

    def value(self, t: npt.ArrayLike) -> np.ndarray:
        self._transient()
        t = np.asarray(t, dtype=float)
        on = (t >= self.start) & (t < self.start + self.sweep_time)
        s = self.amplitude_at(self.frequency_at(t)) * np.sin(self.phase_at(t))
        return np.where(on, s, 0.0)

    @property
    def breakpoints(self) -> tuple[float, ...]:
        return () if self.steady_state else _edges(self.start, self.start + self.sweep_time)

    @property
    def end_time(self) -> float:
        return math.inf if self.steady_state else self.start + self.sweep_time


@dataclass(frozen=True, eq=False, init=False)
class Table(TimeFunction):
    """Tabulated values, linearly interpolated: ``Table(time=[...], value=[...])``, spelled as in model
    files (``time = [...]``, ``value = [...]``).

    Parameters
    ----------
    time : (k,) array_like
        Strictly increasing times [s], k >= 2 (first positional argument; ``times=`` is accepted too,
        and the attribute is ``times``).
    value : (k,) array_like
        Values [unit of the excitation] (second positional argument; ``values=`` is accepted too, and
        the attribute is ``values``: ``value(t)`` is the method that interpolates).
    extrapolate : {"zero", "hold"}
        Outside the table: zero (default), or hold the first / last value.
    source : str
        File the table was read from (reports only).

    Examples
    --------
    >>> Table(time=[0.0, 1.0, 2.0], value=[0.0, 10.0, 0.0]).value([0.5, 1.5, 3.0]).tolist()
    [5.0, 5.0, 0.0]
    >>> Table([0.0, 1.0], [0.0, 2.0]).values.tolist()
    [0.0, 2.0]
    """

    type: ClassVar[str] = "table"
    roles: ClassVar[dict[str, str]] = {"time": "time", "value": "value", "extrapolate": "text"}
    aliases: ClassVar[dict[str, str]] = {"time": "times", "value": "values"}
    times: Any
    values: Any
    extrapolate: str = "zero"
    source: str = field(default="", compare=False)

    def __init__(self, time: Any = None, value: Any = None, extrapolate: str = "zero", source: str = "", *,
                 times: Any = None, values: Any = None) -> None:
        for key, a, b in (("time", time, times), ("value", value, values)):
            if a is not None and b is not None:
                raise ModelError(f"table function: {key}: given twice (as {key} and {key}s); give one")
            if a is None and b is None:
                raise ModelError(f"table function: {key}: missing; give Table(time=[...], value=[...])")
        object.__setattr__(self, "times", times if time is None else time)
        object.__setattr__(self, "values", values if value is None else value)
        object.__setattr__(self, "extrapolate", extrapolate)
        object.__setattr__(self, "source", source)
        self.__post_init__()

    def __post_init__(self) -> None:
        for key, name in self.aliases.items():
            try:
                a = np.array(getattr(self, name), dtype=float)
            except (TypeError, ValueError):
                raise ModelError(f"table function: {key}: expected a list of numbers") from None
            if a.ndim != 1 or a.size < 2:
                raise ModelError(f"table function: {key}: expected a list of at least 2 numbers, "
                                 f"got shape {a.shape}")
            if not np.all(np.isfinite(a)):
                raise ModelError(f"table function: {key}: values must be finite")
            a.setflags(write=False)
            object.__setattr__(self, name, a)
        if self.times.size != self.values.size:
            raise ModelError(f"table function: time, value: lengths differ "
                             f"({self.times.size} and {self.values.size})")
        bad = np.flatnonzero(np.diff(self.times) <= 0)
        if bad.size:
            i = int(bad[0])
            raise ModelError(f"table function: time: must be strictly increasing; entry {i + 2} "
                             f"({self.times[i + 1]}) does not follow entry {i + 1} ({self.times[i]})")
        if self.extrapolate not in ("zero", "hold"):
            raise ModelError(f"table function: extrapolate: expected 'zero' or 'hold', "
                             f"got {self.extrapolate!r}")

    def value(self, t: npt.ArrayLike) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        if self.extrapolate == "hold":
            return np.interp(t, self.times, self.values)
        return np.interp(t, self.times, self.values, left=0.0, right=0.0)

    @property
    def breakpoints(self) -> tuple[float, ...]:
        return tuple(self.times.tolist())

    @property
    def end_time(self) -> float:
        return float(self.times[-1])


@dataclass(frozen=True)
class Sum(TimeFunction):
    """The sum of several time functions (model files: ``function = [{...}, {...}]``).

    Parameters
    ----------
    terms : sequence of TimeFunction
        The functions added, at least one.
    """

    type: ClassVar[str] = "sum"
    roles: ClassVar[dict[str, str]] = {"terms": "data"}
    terms: tuple[TimeFunction, ...]

    def __post_init__(self) -> None:
        terms = tuple(self.terms)
        if not terms or not all(isinstance(f, TimeFunction) for f in terms):
            raise ModelError(f"sum function: terms: expected one or more time functions, got {self.terms!r}")
        object.__setattr__(self, "terms", terms)

    def value(self, t: npt.ArrayLike) -> np.ndarray:
        return sum((f.value(t) for f in self.terms[1:]), start=self.terms[0].value(t))

    @property
    def breakpoints(self) -> tuple[float, ...]:
        return tuple(sorted({b for f in self.terms for b in f.breakpoints}))

    @property
    def sinusoids(self) -> tuple[Sinusoid, ...]:
        """The terms' pieces, when every term is linear once its own are subtracted (else none)."""
        if any(not f.sinusoids and not _linear(f) for f in self.terms):
            return ()
        return tuple(p for f in self.terms for p in f.sinusoids)

    @property
    def end_time(self) -> float:
        return max(f.end_time for f in self.terms)

    @property
    def steady_state(self) -> bool:
        return all(f.steady_state for f in self.terms)

    def to_dict(self) -> dict[str, Any]:
        return {"type": self.type, "terms": [f.to_dict() for f in self.terms]}


FUNCTIONS: dict[str, type[TimeFunction]] = {
    cls.type: cls for cls in (Step, Rectangular, HalfSine, Haversine, Triangle, Sawtooth, Ramp,
                              Sine, SineSweep, Table, Sum)
}
"""Time function classes by their model-file ``type`` name."""
