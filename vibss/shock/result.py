"""The results of the shock analysis: the shock response spectrum and its check against a spec."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..results import Result, TextTable, require_pandas

__all__ = ["ShockResponseSpectrum", "EnvelopeCheck"]


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
    unit : str
        The signal's unit, ``"m/s^2"`` or ``"g"`` (the spectrum's acceleration unit).
    """

    frequency_hz: np.ndarray
    response: np.ndarray
    q: float
    kind: str
    quantity: str
    name: str = "srs"
    unit: str = "m/s^2"

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
        return (_unit(self.quantity, self.unit),)

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
                "units": {"frequency_hz": "Hz", "response": _unit(self.quantity, self.unit)}}

    def tripartite(self, unit: str | None = None, ax: Any = None) -> Any:
        """Four-coordinate plot (:func:`vibss.plotting.shock.plot_tripartite`); ``unit`` of the signal,
        by default the one the spectrum was taken in (:attr:`unit`)."""
        from ..plotting.shock import plot_tripartite

        return plot_tripartite(self, self.unit if unit is None else unit, ax)

    def check(self, frequency_hz: Any, level: Any, lower_db: float = -3.0, upper_db: float = 6.0) -> Any:
        """Against a specification envelope (:func:`vibss.shock.api.check_envelope`)."""
        from .api import check_envelope

        return check_envelope(self, frequency_hz, level, lower_db, upper_db)

    def plot(self, ax: Any = None, unit: str | None = None) -> Any:
        """The spectrum on four-coordinate (tripartite) axes; ``unit`` is the signal's unit."""
        return self.tripartite(unit, ax)

    def to_pandas(self) -> Any:
        """The spectrum as a DataFrame indexed by frequency [Hz], one column named for the signal."""
        pd = require_pandas()
        df = pd.DataFrame({self.name: self.response}, index=pd.Index(self.frequency_hz, name="frequency_hz"))
        df.attrs["units"] = {self.name: self.unit, "frequency_hz": "Hz"}
        return df


@dataclass(frozen=True, eq=False)
class EnvelopeCheck(Result):
    """An SRS against a specification: margin [dB] and pass/fail at every spectrum frequency.

    Attributes
    ----------
    frequency_hz, srs, spec, margin_db : (n,) ndarray
        Frequencies inside the spec's band, the spectrum, the spec and ``20 log10(srs / spec)``.
    lower_db, upper_db : float
        The tolerance band.
    """

    frequency_hz: np.ndarray
    srs: np.ndarray
    spec: np.ndarray
    margin_db: np.ndarray
    lower_db: float
    upper_db: float
    name: str = "envelope check"

    @property
    def passed(self) -> bool:
        """Every frequency inside the band."""
        return bool(np.all((self.margin_db >= self.lower_db) & (self.margin_db <= self.upper_db)))

    @property
    def output_labels(self) -> tuple[str, ...]:
        """One output: the margin."""
        return ("margin_db",)

    def _item(self, i: int, j: int | None) -> np.ndarray:
        return self.margin_db

    def summary(self) -> TextTable:
        """Worst margins and the verdict."""
        lo, hi = int(np.argmin(self.margin_db)), int(np.argmax(self.margin_db))
        rows = [["verdict", "PASS" if self.passed else "FAIL"],
                ["band", f"{self.lower_db:+g} / {self.upper_db:+g} dB"],
                ["lowest margin", f"{self.margin_db[lo]:+.2f} dB at {self.frequency_hz[lo]:.4g} Hz"],
                ["highest margin", f"{self.margin_db[hi]:+.2f} dB at {self.frequency_hz[hi]:.4g} Hz"],
                ["frequencies outside", str(int(np.sum((self.margin_db < self.lower_db) | (self.margin_db > self.upper_db))))]]
        return TextTable(["check", "result"], rows, title=self.name)

    def report(self) -> str:
        """The summary and every frequency."""
        lines = [str(self.summary()), "", f"{'f [Hz]':>10} {'SRS':>12} {'spec':>12} {'margin [dB]':>12}"]
        lines += [f"{f:10.4g} {s:12.5g} {p:12.5g} {m:+12.2f}{'' if self.lower_db <= m <= self.upper_db else '  outside'}"
                  for f, s, p, m in zip(self.frequency_hz, self.srs, self.spec, self.margin_db)]
        return "\n".join(lines)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready data."""
        return {"passed": self.passed, "lower_db": self.lower_db, "upper_db": self.upper_db,
                "frequency_hz": self.frequency_hz.tolist(), "srs": self.srs.tolist(), "spec": self.spec.tolist(),
                "margin_db": self.margin_db.tolist()}


def _unit(quantity: str, signal: str) -> str:
    """The spectrum's unit: the signal's acceleration unit, times s (pseudo-velocity) or s^2
    (relative displacement)."""
    if signal == "m/s^2":
        return {"acceleration": "m/s^2", "pseudo_velocity": "m/s", "displacement": "m"}[quantity]
    return {"acceleration": signal, "pseudo_velocity": f"{signal} s", "displacement": f"{signal} s^2"}[quantity]
