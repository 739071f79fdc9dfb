"""The scene of a study: which inputs, which outputs, which frequencies, and how accurately.

A :class:`Scope` says what a reduced model must reproduce (:func:`vibss.reduction.reduce`):

- ``inputs`` and ``outputs``: signal names as in :mod:`vibss.signals` (an input may also be an
  :class:`vibss.model.excitation.Excitation`, which names its own signal);
- a frequency band ``[f1, f2]`` [Hz], given directly (a frequency response) or derived from a time
  span (a simulation): ``[0, f_max]`` with ``f_max`` the inputs' highest significant frequency;
- ``tolerance``: the relative accuracy asked for: the error of every input/output channel over the
  band, relative to its output's largest response to any of the scope's inputs over the band.

Time scopes and input content
-----------------------------
:meth:`Scope.for_simulation` estimates ``f_max`` from the excitations: ``content_factor / tau``
for the shortest interval ``tau`` between breakpoints (pulse durations, ramp times, table knots),
the frequency of a sine and the top frequency of a sweep; capped by the Nyquist frequency
``1 / (2 dt)`` when ``dt`` is given. A step (one breakpoint, unlimited content) gets the Nyquist
frequency. Give ``f_max`` yourself when you know better.

Examples
--------
>>> s = Scope(["b.fz"], ["b.z"], f1=0.0, f2=50.0, tolerance=1e-4)
>>> s.band_hz, s.tolerance
((0.0, 50.0), 0.0001)
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any, cast

import numpy as np
import numpy.typing as npt

from .._validate import number
from ..errors import ModelError

__all__ = ["Scope", "content_frequency", "peak_checks", "low_end", "LOW_END", "RIGID_LOW_END"]


LOW_END = 1e-3
"""A band from 0 Hz is measured from this fraction of its top (0 Hz itself is a limit)."""

RIGID_LOW_END = 0.1
"""On a model with rigid-body modes, a band from 0 Hz is measured from this fraction of the lowest
elastic frequency (where the rigid-body response is about the elastic peak at 2 % damping)."""

PEAK_OFFSETS = (-1.0, -0.5, -0.25, 0.0, 0.25, 0.5, 1.0)
"""Where a resonance is sampled, in half-power half-widths from its undamped frequency: the peak
itself and both flanks, where a pole that is slightly off makes its largest error."""


def low_end(band: tuple[float, float], natural: npt.ArrayLike = ()) -> float:
    """:meth:`Scope.low_end` of a band ``(w1, w2)`` [rad/s]."""
    w1, w2 = band
    if w1 > 0:
        return float(w1)
    w = np.asarray(natural, float).ravel()
    lo = w2 * LOW_END
    if np.any(w <= 0) and np.any(w > 0):
        lo = max(lo, min(RIGID_LOW_END * float(w[w > 0].min()), w2))
    return float(lo)


def peak_checks(w: npt.ArrayLike, g: npt.ArrayLike, lo: float, hi: float) -> np.ndarray:
    """Check frequencies [rad/s] that sample each resonance's peak and flanks, inside ``[lo, hi]``.

    A lightly damped resonance is narrower than any fixed relative offset: a check ``2e-4``
    beside a mode of damping ratio 1e-5 sees neither its peak nor a pole that is slightly off, and
    a relative error taken against the largest response sampled then understates that peak too.

    Parameters
    ----------
    w : (r,) array_like
        Undamped natural frequencies [rad/s].
    g : (r,) array_like
        Modal damping ``phi^T C phi`` (mass-normalised) plus ``phi^T H phi / w`` [rad/s]: the
        half-power bandwidth. An undamped mode (``g = 0``) is sampled at ``w (1 +- 1e-6)``, not on
        its pole.
    lo, hi : float
        The band [rad/s].

    Returns
    -------
    (k,) ndarray
        Sorted, unique frequencies [rad/s].
    """
    wr: np.ndarray = np.asarray(w, float).ravel()
    gr: np.ndarray = np.abs(np.asarray(g, float).ravel())
    half = np.where(gr > 0, 0.5 * gr, 1e-6 * wr)
    off = np.array(PEAK_OFFSETS)[None, :]
    pts = wr[:, None] + half[:, None] * np.where((gr > 0)[:, None], off, np.where(off == 0, 1.0, off))
    pts = pts.ravel()
    return np.unique(pts[(pts >= lo) & (pts <= hi) & (pts > 0)])


def _signal_name(item: Any) -> str:
    if isinstance(item, str):
        return item
    name = getattr(item, "signal", None)
    if isinstance(name, str):
        return name
    raise ModelError(f"scope: inputs: expected signal names (str) or Excitation objects, got {item!r}")


@dataclass(frozen=True, eq=False)
class Scope:
    """What a reduced model must reproduce, and how accurately.

    Parameters
    ----------
    inputs : sequence of str or Excitation
        Input signals (``'engine.fz'``, ``'ground.z.acc'`` ...; see :mod:`vibss.signals`).
    outputs : sequence of str
        Output signals (``'engine.z'``, ``'mount.fl.fz'`` ...).
    f1, f2 : float
        Frequency band [Hz], ``0 <= f1 < f2``.
    tolerance : float
        Relative accuracy in ``(0, 1)``: the largest allowed ``max_w |H_red,ij - H_full,ij|`` divided
        by output i's largest response ``max_j max_w |H_full,ij|`` over the band [-].
    t_end : float or None
        Simulation length [s] of a time scope (informational; None for a frequency scope).
    origin : str
        How the band was obtained (for reports).

    Attributes
    ----------
    sources : tuple
        The inputs as given (names or Excitation objects, used to build the plant).
    """

    inputs: tuple[str, ...]
    outputs: tuple[str, ...]
    f1: float
    f2: float
    tolerance: float = 1e-3
    t_end: float | None = None
    origin: str = "frequency band"
    sources: tuple[Any, ...] = field(default=(), repr=False)

    def __post_init__(self) -> None:
        raw_in = self.inputs
        if isinstance(raw_in, str) or not isinstance(raw_in, Sequence):
            raw_in = (raw_in,)
        if len(raw_in) == 0:
            raise ModelError("scope: inputs: give at least one input signal, e.g. 'body.fz'")
        names = tuple(_signal_name(x) for x in raw_in)
        outs = self.outputs
        if isinstance(outs, str):
            outs = (outs,)
        if outs is None or not isinstance(outs, Sequence) or len(outs) == 0:
            raise ModelError(f"scope: outputs: give at least one output signal name, got {self.outputs!r}")
        if not all(isinstance(o, str) for o in outs):
            raise ModelError(f"scope: outputs: expected signal names (str), got {list(outs)!r}")
        for what, seq in (("inputs", names), ("outputs", tuple(outs))):
            dup = sorted({x for x in seq if seq.count(x) > 1})
            if dup:
                raise ModelError(f"scope: {what}: signal(s) {dup} given more than once")
        f1 = number(self.f1, "f1", who="scope", minimum=0.0, what="a finite frequency >= 0 Hz")
        f2 = number(self.f2, "f2", who="scope", minimum=f1, strict=True,
                    what=f"a finite frequency above f1 = {f1:g} Hz")
        tol = number(self.tolerance, "tolerance", who="scope", minimum=0.0, strict=True,
                     what="a relative accuracy in (0, 1), e.g. 1e-3")
        if not tol < 1.0:
            raise ModelError(f"scope: tolerance: must be a relative accuracy in (0, 1), e.g. 1e-3, "
                             f"got {self.tolerance!r}")
        if self.t_end is not None:
            number(self.t_end, "t_end", who="scope", minimum=0.0, strict=True, what="a positive time [s]")
        object.__setattr__(self, "sources", tuple(self.sources) or tuple(raw_in))
        object.__setattr__(self, "inputs", names)
        object.__setattr__(self, "outputs", tuple(outs))
        object.__setattr__(self, "f1", f1)
        object.__setattr__(self, "f2", f2)
        object.__setattr__(self, "tolerance", tol)

    @property
    def band_hz(self) -> tuple[float, float]:
        """The band ``(f1, f2)`` [Hz]."""
        return (self.f1, self.f2)

    @property
    def band_rad(self) -> tuple[float, float]:
        """The band ``(w1, w2)`` [rad/s]."""
        return (2 * np.pi * self.f1, 2 * np.pi * self.f2)

    def low_end(self, natural: npt.ArrayLike = ()) -> float:
        """The lowest frequency [rad/s] the scope's error is measured from.

        The band's lower end when it is above 0 Hz. A band from 0 Hz is measured from
        :data:`LOW_END` of its top; on a model with rigid-body modes (``natural`` holds a 0) from
        :data:`RIGID_LOW_END` of its lowest elastic frequency if that is higher: the rigid-body
        response grows as ``1 / w^2`` toward 0 Hz and, sampled lower, would swamp the elastic
        response the tolerance is about (every reduction keeps the rigid-body modes exactly).

        Parameters
        ----------
        natural : (k,) array_like
            Natural frequencies of the model or its reduction [rad/s], zeros for rigid-body modes.
        """
        return low_end(self.band_rad, natural)

    @classmethod
    def for_frequency_response(cls, inputs: Sequence[Any], outputs: Sequence[str],
                               frequencies: npt.ArrayLike, tolerance: float = 1e-3) -> Scope:
        """Scope of a frequency response on the grid ``frequencies`` [Hz] (band = its range).

        Parameters
        ----------
        inputs : sequence of str or Excitation
            Input signals.
        outputs : sequence of str
            Output signals.
        frequencies : (nf,) array_like
            Analysis frequencies [Hz], at least two distinct values.
        tolerance : float
            Relative accuracy (see :class:`Scope`).

        Returns
        -------
        Scope

        Examples
        --------
        >>> Scope.for_frequency_response(["b.fz"], ["b.z"], [1.0, 5.0, 20.0]).band_hz
        (1.0, 20.0)
        """
        f = np.asarray(frequencies, dtype=float).ravel()
        if f.size < 2 or not np.all(np.isfinite(f)):
            raise ModelError(f"scope: frequencies: expected at least two finite frequencies [Hz], got {frequencies!r}")
        # __post_init__ makes a tuple of any sequence of outputs
        return cls(tuple(inputs) if not isinstance(inputs, str) else (inputs,), cast("tuple[str, ...]", outputs),
                   float(f.min()), float(f.max()), tolerance, origin="frequency-response grid")

    @classmethod
    def for_simulation(cls, excitations: Sequence[Any], outputs: Sequence[str], t_end: float,
                       dt: float | None = None, tolerance: float = 1e-3, f_max: float | None = None,
                       content_factor: float = 5.0) -> Scope:
        """Scope of a simulation to ``t_end`` driven by ``excitations`` (band ``[0, f_max]``).

        Parameters
        ----------
        excitations : sequence of Excitation
            The excitations (their time functions set ``f_max``, see the module docstring).
        outputs : sequence of str
            Output signals.
        t_end : float
            Simulation length [s].
        dt : float or None
            Sample interval [s]; caps ``f_max`` at the Nyquist frequency ``1 / (2 dt)``.
        tolerance : float
            Relative accuracy (see :class:`Scope`), checked in the frequency domain over the band.
        f_max : float or None
            Highest input frequency [Hz]; estimated from the excitations when None.
        content_factor : float
            ``f_max = content_factor / tau`` for the shortest breakpoint interval ``tau`` [-].

        Returns
        -------
        Scope

        Raises
        ------
        ModelError
            No ``f_max`` can be found (give ``f_max`` or ``dt``), or bad arguments.
        """
        exc = list(excitations) if not isinstance(excitations, str) else [excitations]
        if f_max is None:
            if dt is not None:
                dt = number(dt, "dt", who="scope", minimum=0.0, strict=True, what="a positive time step [s]")
            nyquist = None if dt is None else 0.5 / dt
            est = max((content_frequency(getattr(e, "function", None), content_factor) for e in exc),
                      default=0.0)
            if est == math.inf or est == 0.0:
                if nyquist is None:
                    raise ModelError("scope: f_max: the excitations do not limit their frequency content "
                                     "(a step, or plain signal names); give f_max [Hz] or dt [s]")
                est = nyquist
            f_max = est if nyquist is None else min(est, nyquist)
            origin = f"time span: f_max = {f_max:.6g} Hz from the excitations' content"
        else:
            origin = f"time span: f_max = {float(f_max):.6g} Hz given"
        return cls(tuple(exc), cast("tuple[str, ...]", outputs), 0.0, f_max, tolerance, t_end=t_end,
                   origin=origin)

    def to_dict(self) -> dict[str, Any]:
        """Plain data (names, band [Hz], tolerance, t_end [s])."""
        return {"inputs": list(self.inputs), "outputs": list(self.outputs), "f1_hz": self.f1,
                "f2_hz": self.f2, "tolerance": self.tolerance, "t_end_s": self.t_end, "origin": self.origin}


def content_frequency(function: Any, content_factor: float = 5.0) -> float:
    """Highest significant frequency [Hz] of a time function (0: none found, inf: unlimited).

    Parameters
    ----------
    function : TimeFunction or None
        A :mod:`vibss.timefunctions` function.
    content_factor : float
        Multiplier of ``1 / tau`` for the shortest interval ``tau`` between breakpoints [-].

    Returns
    -------
    float
        [Hz]
    """
    if function is None:
        return 0.0
    terms = getattr(function, "terms", None)
    if terms:
        return max(content_frequency(t, content_factor) for t in terms)
    f = 0.0
    for key in ("frequency", "f1", "f2"):
        v = getattr(function, key, None)
        if isinstance(v, (int, float)) and math.isfinite(v):
            f = max(f, float(v))
    bp = np.unique(np.asarray(getattr(function, "breakpoints", ()), dtype=float))
    if bp.size >= 2:
        f = max(f, content_factor / float(np.diff(bp).min()))
    elif bp.size == 1 and f == 0.0:
        return math.inf
    return f
