"""The result of a random-vibration analysis: :class:`RandomResponse` (output PSDs, RMS values and
Miles's estimate per output, with the result protocol of :mod:`vibss.results`)."""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any, ClassVar

import numpy as np

from ..results import Result, TextTable, jsonable, require_pandas
from .psd import G

__all__ = ["RandomResponse"]


@dataclass(frozen=True)
class RandomResponse(Result):
    """Output PSDs and RMS values under random excitation.

    ``r['engine.z.acc']`` is the (nf,) output PSD of one output.

    Attributes
    ----------
    frequency_hz : (nf,) ndarray
        The integration grid [Hz] (adaptive: dense at resonances).
    psd : (p, nf) ndarray
        Output autospectra [output unit^2/Hz].
    rms : (p,) ndarray
        RMS of each output [output unit].
    input_psd : (m, nf) ndarray
        Input autospectra on the grid [SI unit^2/Hz].
    outputs, inputs : tuple of str
        Signals.
    units : tuple of str
        Output units (SI).
    miles : (p,) ndarray
        Miles's single-mode estimate of the RMS (NaN where it does not apply).
    method, note : str
        FRF method and how the integral went.
    input_units : tuple of str
        The unit each input's PSD was given in (``"g^2/Hz"`` ...); figures and tables show the
        inputs in it. Empty: SI.
    """

    signal_kind: ClassVar[str] = "output"

    frequency_hz: np.ndarray
    psd: np.ndarray
    rms: np.ndarray
    input_psd: np.ndarray
    outputs: tuple[str, ...]
    inputs: tuple[str, ...]
    units: tuple[str, ...]
    miles: np.ndarray
    method: str = ""
    note: str = ""
    input_units: tuple[str, ...] = ()

    @property
    def output_labels(self) -> tuple[str, ...]:
        return self.outputs

    @property
    def input_labels(self) -> tuple[str, ...]:
        return self.inputs

    def _item(self, i: int, j: int | None) -> Any:
        return self.psd[i]

    @property
    def three_sigma(self) -> np.ndarray:
        """(p,) 3 x RMS [output unit]: exceeded about 0.27 % of the time by a Gaussian response."""
        return 3.0 * self.rms

    def input_levels(self) -> tuple[np.ndarray, tuple[str, ...]]:
        """The input PSDs in the units they were given in (``(m, nf)``, and those units): a spec in
        g^2/Hz is shown in g^2/Hz."""
        from .psd import UNITS

        units = self.input_units or tuple(_si_psd_unit(n) for n in self.inputs)
        factor = np.array([UNITS.get(u, 1.0) for u in units])
        return self.input_psd / factor[:, None], units

    def in_g(self) -> RandomResponse:
        """The same response with translational accelerations (outputs in m/s^2) in g: their PSDs
        in g^2/Hz, RMS and Miles's estimate in g."""
        acc = np.array([u == "m/s^2" for u in self.units])
        if not acc.any():
            return self
        return replace(self, psd=np.where(acc[:, None], self.psd / G**2, self.psd),
                       rms=np.where(acc, self.rms / G, self.rms), miles=np.where(acc, self.miles / G, self.miles),
                       units=tuple("g" if a else u for a, u in zip(acc, self.units)))

    def psd_units(self) -> tuple[str, ...]:
        """Units of the output PSDs."""
        return tuple(f"({u})^2/Hz" if ("/" in u or " " in u) else f"{u}^2/Hz" for u in self.units)

    def summary(self) -> TextTable:
        """RMS, 3 sigma, peak of the PSD and Miles's estimate per output."""
        rows = []
        for i, (o, u) in enumerate(zip(self.outputs, self.units)):
            k = int(np.argmax(self.psd[i]))
            g = f" ({self.rms[i] / G:.4g} g)" if u == "m/s^2" else ""
            miles = "" if not np.isfinite(self.miles[i]) else f"{self.miles[i]:.4g}" + (
                f" ({self.miles[i] / G:.4g} g)" if u == "m/s^2" else "")
            rows.append([o, u, f"{self.rms[i]:.5g}{g}", f"{self.three_sigma[i]:.5g}",
                         f"{self.psd[i, k]:.4g} at {self.frequency_hz[k]:.4g} Hz", miles])
        return TextTable(["output", "unit", "RMS", "3 sigma", "peak PSD [unit^2/Hz]", "Miles"], rows,
                     title=f"Random response to {', '.join(self.inputs)}")

    def report(self) -> str:
        """The summary and the note."""
        return self.summary().render() + ("\n\n" + self.note if self.note else "")

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: RMS per output, grid and PSDs (SI)."""
        return jsonable({"frequency_hz": self.frequency_hz, "inputs": list(self.inputs),
                         "outputs": {o: {"unit": u, "rms": self.rms[i], "three_sigma": self.three_sigma[i],
                                         "miles": self.miles[i], "psd": self.psd[i]}
                                     for i, (o, u) in enumerate(zip(self.outputs, self.units))},
                         "method": self.method, "note": self.note})

    def to_pandas(self) -> Any:
        """DataFrame of output PSDs indexed by frequency [Hz]."""
        pd = require_pandas()
        df = pd.DataFrame(self.psd.T, index=pd.Index(self.frequency_hz, name="frequency_hz"), columns=list(self.outputs))
        df.attrs["units"] = dict(zip(self.outputs, self.psd_units()))
        df.attrs["rms"] = dict(zip(self.outputs, self.rms.tolist()))
        return df

    def plot(self, ax: Any = None, **kwargs: Any) -> Any:
        """Input and output PSDs on log-log axes: :func:`vibss.plotting.random.plot_random`."""
        from ..plotting.random import plot_random

        return plot_random(self, ax=ax, **kwargs)


def _si_psd_unit(name: str) -> str:
    """The SI PSD unit of an input signal, from its name's suffix (a force otherwise)."""
    last = name.rsplit(".", 1)[-1]
    unit = {"acc": "(m/s^2)^2/Hz", "vel": "(m/s)^2/Hz", "disp": "m^2/Hz"}.get(last)
    if unit is None:
        unit = "(N m)^2/Hz" if last.startswith("m") else "N^2/Hz"
    return unit
