"""Shock response spectrum by the ramp-invariant recursive filter (Smallwood 1981; ISO 18431-4).

For each natural frequency ``fn`` the base acceleration ``x`` drives a single-DOF oscillator of
quality factor ``Q`` (``zeta = 1/(2Q)``); its absolute acceleration follows from the
second-order recursion whose coefficients are exact for an input linear between samples::

    E = exp(-zeta w dt),  K = wd dt,  C = E cos K,  S = E sin K,  Sp = S / K
    b = [1 - Sp, 2 (Sp - C), E^2 - Sp],   a = [1, -2 C, E^2]

The residual part (after the input ends) is obtained by running the filter on appended zeros
for one period of the lowest natural frequency (plus the record's own step).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.signal

from .. import _validate as v
from ..errors import ArgumentError
from ..results import Result, TextTable, require_pandas

KINDS = ("maximax", "positive", "negative", "primary", "residual")
RESPONSES = ("acceleration", "pseudo_velocity", "displacement")
_UNITS = {"acceleration": "unit of signal", "pseudo_velocity": "unit of signal x s",
          "displacement": "unit of signal x s^2"}


def _coefficients(fn: float, zeta: float, dt: float) -> tuple[np.ndarray, np.ndarray]:
    w = 2.0 * np.pi * fn
    wd = w * np.sqrt(1.0 - zeta * zeta)
    e = np.exp(-zeta * w * dt)
    k = wd * dt
    c, s = e * np.cos(k), e * np.sin(k)
    sp = s / k
    return np.array([1.0 - sp, 2.0 * (sp - c), e * e - sp]), np.array([1.0, -2.0 * c, e * e])


@dataclass(frozen=True)
class ShockResponseSpectrum(Result):
    """Shock response spectrum of one signal.

    Attributes
    ----------
    frequency_hz : (n,) ndarray
        Natural frequencies [Hz].
    response : (n,) ndarray
        The spectrum (absolute acceleration in the signal's unit by default).
    q : float
        Quality factor (inf for undamped).
    kind, quantity : str
        Which extremum and which response quantity.
    name : str
        The signal's name (the one output label; ``"srs"`` when not given).
    """

    frequency_hz: np.ndarray
    response: np.ndarray
    q: float
    kind: str
    quantity: str
    name: str = "srs"

    method = "ramp-invariant recursive filter (Smallwood; ISO 18431-4)"
    note = ""

    @property
    def output_labels(self) -> tuple[str, ...]:
        """One output: the spectrum of the named signal."""
        return (self.name,)

    @property
    def units(self) -> tuple[str, ...]:
        """Unit of the spectrum (the signal's unit, times s or s^2 for the pseudo quantities);
        frequencies are in Hz."""
        return (_UNITS[self.quantity],)

    def _item(self, i: int, j: int | None) -> Any:
        return self.response

    def summary(self) -> TextTable:
        """Kind, quantity, Q and the peak."""
        k = int(np.argmax(np.abs(self.response)))
        return TextTable(["quantity", "value"],
                     [["kind", self.kind], ["response", self.quantity], ["Q", f"{self.q:g}"],
                      ["peak", f"{self.response[k]:.6g} at {self.frequency_hz[k]:.6g} Hz"]])

    def report(self) -> str:
        """The spectrum as a text table."""
        lines = [f"Shock response spectrum ({self.kind} {self.quantity}, Q = {self.q:g})",
                 f"{'f [Hz]':>12} {'response':>14}"]
        lines += [f"{f:12.6g} {r:14.6g}" for f, r in zip(self.frequency_hz, self.response)]
        return "\n".join(lines)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready data (``q`` is null for the undamped spectrum)."""
        return {"frequency_hz": self.frequency_hz.tolist(), "response": self.response.tolist(),
                "q": self.q if np.isfinite(self.q) else None,  # undamped: null (strict JSON)
                "kind": self.kind, "quantity": self.quantity, "name": self.name,
                "units": {"frequency_hz": "Hz", "response": _UNITS[self.quantity]}}

    def tripartite(self, unit: str = "m/s^2", ax: Any = None) -> Any:
        """Four-coordinate plot (:func:`vibss.plotting.shock.plot_tripartite`); ``unit`` of the signal."""
        from ..plotting.shock import plot_tripartite

        return plot_tripartite(self, unit, ax)

    def check(self, frequency_hz: Any, level: Any, lower_db: float = -3.0, upper_db: float = 6.0) -> Any:
        """Against a specification envelope (:func:`vibss.shock.envelope.check_envelope`)."""
        from .envelope import check_envelope

        return check_envelope(self, frequency_hz, level, lower_db, upper_db)

    def plot(self, ax: Any = None, unit: str = "m/s^2") -> Any:
        """The spectrum on four-coordinate (tripartite) axes; ``unit`` is the signal's unit."""
        return self.tripartite(unit, ax)

    def to_pandas(self) -> Any:
        """The spectrum as a DataFrame indexed by frequency [Hz], one column named for the signal."""
        pd = require_pandas()
        return pd.DataFrame({self.name: self.response},
                            index=pd.Index(self.frequency_hz, name="frequency_hz"))


def srs(time: Any, signal: Any, frequencies: Any, q: float = 10.0, kind: str = "maximax", *,
        quantity: str = "acceleration", name: str = "srs", zeta: float | None = None) -> ShockResponseSpectrum:
    """Shock response spectrum of a uniformly sampled base acceleration.

    Parameters
    ----------
    time : (N,) array_like
        Uniformly spaced sample times [s].
    signal : (N,) array_like
        Base acceleration [any unit; the spectrum has the same unit].
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
    return ShockResponseSpectrum(f, out, qv, kind, quantity, name)


__all__ = ["KINDS", "ShockResponseSpectrum", "srs"]
