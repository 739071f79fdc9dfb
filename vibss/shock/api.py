"""Shock response spectrum by the ramp-invariant recursive filter (Smallwood 1981; ISO 18431-4).

For each natural frequency ``fn`` the base acceleration ``x`` drives a single-DOF oscillator of
quality factor ``Q`` (``zeta = 1/(2Q)``); its absolute acceleration follows from the
second-order recursion whose coefficients are exact for an input linear between samples::

    E = exp(-zeta w dt),  K = wd dt,  C = E cos K,  S = E sin K,  Sp = S / K
    b = [1 - Sp, 2 (Sp - C), E^2 - Sp],   a = [1, -2 C, E^2]

The residual part (after the input ends) is obtained by running the filter on appended zeros
for one period of the lowest natural frequency (plus the record's own step).

:func:`check_envelope` holds a spectrum against a specification envelope (a test tolerance band,
or an allowable). A specification is a table of (frequency [Hz], level) points, log-log interpolated as shock specs are
written (MIL-STD-810, NASA-STD-7003); the check gives, at every frequency of the spectrum inside the
spec's band, the level, the margin in dB (``20 log10(SRS / spec)``) and whether it lies inside
``[lower_db, upper_db]`` (a test's tolerance band, e.g. -3/+6 dB; ``lower_db = -inf`` for an
allowable that must not be exceeded).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.signal

from .. import _validate as v
from ..errors import ArgumentError
from .kernels import _coefficients, spec_level
from .result import EnvelopeCheck, ShockResponseSpectrum

KINDS = ("maximax", "positive", "negative", "primary", "residual")
RESPONSES = ("acceleration", "pseudo_velocity", "displacement")
SIGNAL_UNITS = ("m/s^2", "g")
"""Units an SRS's input may be given in (the spectrum keeps it)."""


def srs(time: Any, signal: Any, frequencies: Any, q: float = 10.0, kind: str = "maximax", *,
        quantity: str = "acceleration", name: str = "srs", zeta: float | None = None,
        unit: str = "m/s^2") -> ShockResponseSpectrum:
    """Shock response spectrum of a uniformly sampled base acceleration.

    Parameters
    ----------
    time : (N,) array_like
        Uniformly spaced sample times [s].
    signal : (N,) array_like
        Base acceleration in ``unit`` (the spectrum has the same unit).
    frequencies : (n,) array_like
        Natural frequencies [Hz], > 0 and below the Nyquist frequency.
    q : float
        Quality factor, ``Q = 1/(2 zeta)``; ``numpy.inf`` for undamped.
    kind : {"maximax", "positive", "negative", "primary", "residual"}
        ``positive``/``negative``: largest positive / negative response (negative returned as a
        magnitude); ``primary``: largest |response| while the input lasts; ``residual``: after it.
    quantity : {"acceleration", "pseudo_velocity", "displacement"}
        Absolute acceleration, or its pseudo-velocity ``A/w`` and relative displacement ``A/w^2``
        (the pseudo relations, exact for the undamped oscillator).
    name : str
        Name of the signal, the result's one output label (e.g. ``"table.az"``).
    zeta : float or None
        Damping ratio instead of ``q`` (``Q = 1 / (2 zeta)``; 0 is undamped); give one of the two.
    unit : {"m/s^2", "g"}
        The signal's unit, kept on the result: its ``units`` and its tripartite plot (whose lines are
        in m and g) read it, so a spectrum of an input in g is drawn at its true level.

    Returns
    -------
    ShockResponseSpectrum

    Examples
    --------
    >>> import numpy as np
    >>> t = np.arange(0, 0.02, 1e-6)
    >>> x = np.where(t < 0.01, np.sin(np.pi * t / 0.01), 0.0)
    >>> round(float(srs(t, x, [81.0], q=np.inf).response[0]), 3)
    1.768
    """
    t = v.array(time, "time", (None,), who="srs")
    x = v.array(signal, "signal", (t.size,), who="srs")
    f = np.atleast_1d(v.array(frequencies, "frequencies", None, who="srs")).astype(float).ravel()
    kind = v.choice(kind, "kind", KINDS, who="srs")
    quantity = v.choice(quantity, "quantity", RESPONSES, who="srs")
    unit = v.choice(unit, "unit", SIGNAL_UNITS, who="srs")
    if zeta is not None:
        z = v.number(zeta, "zeta", who="srs", minimum=0.0)
        if q != 10.0:
            raise ArgumentError("srs: give q or zeta, not both", argument="zeta", received=zeta)
        if not z < 1.0:
            raise ArgumentError(f"srs: zeta must be in [0, 1), got {zeta!r}", argument="zeta", received=zeta)
        q = np.inf if z == 0 else 1.0 / (2.0 * z)
    qv = float(q)
    if not qv > 0.5:
        raise ArgumentError(f"srs: q must be > 0.5 (or inf), got {q!r}", argument="q", received=q)
    if t.size < 2:
        raise ArgumentError("srs: time: need at least 2 samples", argument="time", received=t.size)
    dt = float(t[1] - t[0])
    if dt <= 0 or not np.allclose(np.diff(t), dt, rtol=1e-6, atol=0.0):
        raise ArgumentError("srs: time: samples must be uniformly spaced and increasing",
                            argument="time", received=dt)
    if np.any(f <= 0) or np.any(f >= 0.5 / dt):
        raise ArgumentError(f"srs: frequencies must be in (0, {0.5 / dt:g}) Hz (Nyquist)",
                            argument="frequencies", received=f)
    zeta = 0.0 if np.isinf(qv) else 1.0 / (2.0 * qv)
    ntail = int(np.ceil(1.0 / (f.min() * dt))) + 1 if kind in ("maximax", "residual") else 0
    xx = np.concatenate([x, np.zeros(ntail)])
    out = np.empty(f.size)
    n = x.size
    # one C-speed lfilter pass per frequency (measured as fast as scipy's sosfilt, and threads do not
    # help: the filter holds the GIL); the extremes without an |y| temporary (half the old time)
    for i, fn in enumerate(f):
        b, a = _coefficients(float(fn), zeta, dt)
        y = scipy.signal.lfilter(b, a, xx)
        if kind == "maximax":
            out[i] = max(y.max(), -y.min())
        elif kind == "positive":
            out[i] = y.max()
        elif kind == "negative":
            out[i] = -y.min()
        else:
            part = y[:n] if kind == "primary" else y[n:]
            out[i] = max(part.max(), -part.min())
    w = 2.0 * np.pi * f
    if quantity == "pseudo_velocity":
        out = out / w
    elif quantity == "displacement":
        out = out / (w * w)
    if not isinstance(name, str) or not name:
        raise ArgumentError(f"srs: name must be a non-empty string, got {name!r}", argument="name", received=name)
    return ShockResponseSpectrum(f, out, qv, kind, quantity, name, unit)


__all__ = ["KINDS", "RESPONSES", "SIGNAL_UNITS", "srs", "check_envelope"]


def check_envelope(result: Any, frequency_hz: Any, level: Any, lower_db: float = -3.0,
                   upper_db: float = 6.0) -> EnvelopeCheck:
    """Compare a :class:`~vibss.shock.result.ShockResponseSpectrum` with a specification.

    Parameters
    ----------
    result : ShockResponseSpectrum
        The spectrum (same unit as ``level``).
    frequency_hz, level : (k,) array_like
        The spec's breakpoints [Hz] (increasing) and levels (> 0).
    lower_db, upper_db : float
        Tolerance band [dB] (``-inf`` / ``inf`` for one-sided checks).

    Returns
    -------
    EnvelopeCheck
        Over the spectrum's frequencies inside the spec's band.

    Examples
    --------
    >>> import numpy as np
    >>> from vibss.shock import srs
    >>> t = np.arange(0, 0.05, 1e-5)
    >>> r = srs(t, np.where(t < 0.011, 30 * np.sin(np.pi * t / 0.011), 0.0), [50, 100, 200, 400])
    >>> check_envelope(r, [10, 1000], [60, 60], lower_db=-np.inf, upper_db=0.0).passed   # below 2 x 30
    True
    """
    fp = v.array(frequency_hz, "frequency_hz", (None,), who="check_envelope")
    lp = v.array(level, "level", (fp.size,), who="check_envelope")
    if fp.size < 2 or np.any(np.diff(fp) <= 0) or np.any(fp <= 0) or np.any(lp <= 0):
        raise ArgumentError("check_envelope: the spec needs >= 2 increasing frequencies > 0 [Hz] and levels > 0",
                            argument="frequency_hz", received=fp.tolist())
    if not lower_db < upper_db:
        raise ArgumentError(f"check_envelope: need lower_db < upper_db, got {lower_db}, {upper_db}",
                            argument="lower_db", received=lower_db)
    f = np.asarray(result.frequency_hz, dtype=float)
    spec = spec_level(fp, lp, f)
    keep = np.isfinite(spec)
    if not np.any(keep):
        raise ArgumentError(f"check_envelope: no spectrum frequency lies in the spec's band {fp[0]:g} .. {fp[-1]:g} Hz",
                            argument="frequency_hz", received=fp.tolist())
    s = np.abs(np.asarray(result.response, dtype=float))[keep]
    with np.errstate(divide="ignore"):
        margin = 20 * np.log10(s / spec[keep])
    return EnvelopeCheck(f[keep], s, spec[keep], margin, float(lower_db), float(upper_db))
