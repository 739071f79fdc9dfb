"""Finite-rate sine sweeps: the simulated response envelope against the steady-state FRF.

A sweep with ``sweep_time > 0`` passes each resonance in finite time, so the response peak is
lower, later (shifted in the sweep direction) and followed by beating. :func:`sweep_envelope`
simulates the sweep (:func:`vibss.time.simulate`), takes the envelope of every output (magnitude of
the analytic signal, :func:`scipy.signal.hilbert`) against the instantaneous frequency, and sets it
beside the steady-state amplitude ``|H(f)| a(f)`` from the exact solve of
``(K - w^2 M + i w C) X = RHS`` (:func:`vibss.linear.solve.exact.response`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.signal import hilbert

from ..errors import ArgumentError, ModelError
from ..model.model import Model
from ..linear.plant.build import build_plant
from ..linear.solve.exact import response, without_hysteresis
from ..results import Result, TextTable, jsonable, require_pandas
from .api import simulate
from .result import TimeResponse

__all__ = ["SweepEnvelope", "sweep_envelope"]


@dataclass(frozen=True, eq=False)
class SweepEnvelope(Result):
    """Envelope of a finite-rate sweep response beside the steady-state amplitude.

    Follows the result protocol (:mod:`vibss.results`): ``e['b.z']`` is the (k,) envelope of one
    output; ``method`` and ``note`` are the simulation's; there is no python-control twin
    (``control`` is None).

    Attributes
    ----------
    frequency_hz : (k,) ndarray
        Instantaneous sweep frequency [Hz] at the envelope samples.
    envelope : (p, k) ndarray
        Response envelope (SI unit of each output).
    steady : (p, k) ndarray
        Steady-state amplitude at the same frequency and excitation amplitude.
    outputs : tuple of str
        Output names.
    units : tuple of str
        Their SI units.
    response : TimeResponse
        The simulated sweep.
    """

    frequency_hz: np.ndarray
    envelope: np.ndarray
    steady: np.ndarray
    outputs: tuple[str, ...]
    units: tuple[str, ...]
    response: TimeResponse

    @property
    def output_labels(self) -> tuple[str, ...]:
        """Output signal names (``outputs`` is the same)."""
        return self.outputs

    @property
    def input_labels(self) -> tuple[str, ...]:
        """The sweep's input signal."""
        return self.response.input_labels

    @property
    def method(self) -> str:
        """Simulation method."""
        return self.response.method

    @property
    def note(self) -> str:
        """How the simulation ran (and why, for ``auto``)."""
        return self.response.note

    def _item(self, i: int, j: int | None) -> np.ndarray:
        if j is not None:
            raise ArgumentError("SweepEnvelope[output, input]: the sweep has one input; index by output "
                                "only", argument="key", received=(self.outputs[i], self.input_labels[j]))
        return self.envelope[i]

    def peak_ratio(self) -> np.ndarray:
        """(p,) largest envelope over largest steady-state amplitude (< 1 for a fast sweep)."""
        return self.envelope.max(axis=1) / self.steady.max(axis=1)

    def summary(self) -> TextTable:
        """Per output: largest envelope and steady-state amplitude, their frequencies and ratio."""
        rows = []
        ratio = self.peak_ratio()
        for i, y in enumerate(self.outputs):
            ke, ks = int(np.argmax(self.envelope[i])), int(np.argmax(self.steady[i]))
            rows.append([y, f"{self.envelope[i, ke]:.4e}", f"{self.frequency_hz[ke]:.4f}",
                         f"{self.steady[i, ks]:.4e}", f"{self.frequency_hz[ks]:.4f}", f"{ratio[i]:.3f}",
                         self.units[i]])
        return TextTable(["output", "envelope peak", "at [Hz]", "steady peak", "at [Hz]", "ratio", "unit"], rows,
                     title="Sweep envelope against the steady state (ratio < 1: the sweep is too fast "
                           "to build up the resonance)")

    def report(self) -> str:
        """Text report: the peaks of envelope and steady state per output, and their ratio."""
        f = self.frequency_hz
        head = (f"Finite-rate sweep of {self.response.name!r}: {f.size} envelope samples, "
                f"{f.min():.4g} to {f.max():.4g} Hz" if f.size else "Finite-rate sweep: no samples")
        return f"{head}\nmethod: {self.method} ({self.note})\n\n" + self.summary().render()

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready data: frequency [Hz], envelope and steady amplitude per output, peak ratios."""
        return jsonable({"frequency_hz": self.frequency_hz, "method": self.method, "note": self.note,
                         "outputs": {y: {"envelope": self.envelope[i], "steady": self.steady[i],
                                         "peak_ratio": self.peak_ratio()[i], "unit": self.units[i]}
                                     for i, y in enumerate(self.outputs)}})

    def to_pandas(self) -> Any:
        """DataFrame indexed by frequency [Hz], columns ``'<output>/envelope'`` and ``'<output>/steady'``."""
        pd = require_pandas()
        cols = {}
        for i, y in enumerate(self.outputs):
            cols[f"{y}/envelope"] = self.envelope[i]
            cols[f"{y}/steady"] = self.steady[i]
        df = pd.DataFrame(cols, index=pd.Index(self.frequency_hz, name="frequency_hz"))
        df.attrs["units"] = {f"{y}/{k}": u for y, u in zip(self.outputs, self.units) for k in ("envelope", "steady")}
        return df

    def plot(self, outputs: Any = None, ax: Any = None) -> Any:
        """Envelope and steady state against frequency: :func:`vibss.plotting.plot_sweep_envelope`.

        Parameters
        ----------
        outputs : sequence of str or None
            Outputs to draw, one axes each (default all).
        ax : Axes, sequence of Axes or None
            Axes to draw in; default: a new figure.

        Returns
        -------
        matplotlib.figure.Figure
        """
        from ..plotting import plot_sweep_envelope

        return plot_sweep_envelope(self, outputs, ax)


def sweep_envelope(model: Model, excitation: Any, *, outputs: Any = None, dt: float | None = None,
                   points: int = 400, method: str = "auto") -> SweepEnvelope:
    """Simulate a finite-rate sine sweep and compare its envelope with the steady state.

    Parameters
    ----------
    model : Model
        The system.
    excitation : Excitation
        An excitation whose function is a ``SineSweep`` with ``sweep_time > 0``.
    outputs : sequence of str or None
        Output signals (default: every body DOF's displacement).
    dt : float or None
        Sample interval [s]; default 1/40 of the period at the highest sweep frequency.
    points : int
        Number of envelope samples returned.
    method : str
        Simulation method (see :func:`vibss.time.simulate`).

    Returns
    -------
    SweepEnvelope
    """
    fn = excitation.function
    if not hasattr(fn, "frequency_at") or getattr(fn, "sweep_time", 0.0) <= 0:
        raise ModelError("sweep_envelope: excitation: expected a sine_sweep function with sweep_time > 0, "
                         f"got {fn!r}")
    t_end = fn.start + fn.sweep_time
    dt = dt or 1.0 / (40.0 * max(fn.f1, fn.f2))
    resp = simulate(model, [excitation], outputs=outputs, t_end=t_end, dt=dt, method=method)
    env = np.abs(hilbert(resp.outputs - resp.outputs.mean(axis=1, keepdims=True), axis=1))
    inside = resp.time >= fn.start
    pick = np.flatnonzero(inside)[np.linspace(0, inside.sum() - 1, points).astype(int)]
    f = np.asarray(fn.frequency_at(resp.time[pick]), float)
    plant = build_plant(model, [excitation], list(resp.output_names))
    steady = np.abs(_frf(plant, 2 * np.pi * f)) * np.abs(np.asarray(fn.amplitude_at(f), float))
    return SweepEnvelope(frequency_hz=f, envelope=env[:, pick], steady=steady,
                         outputs=resp.output_names, units=resp.units, response=resp)


def _frf(plant: Any, w: np.ndarray) -> np.ndarray:
    """(p, k) response per unit input of the plant's single input: the one exact solve
    (:func:`vibss.linear.solve.exact.response`) without the hysteretic parts (the time domain has none).

    At ``w = 0`` the value is the exact limit ``w -> 0+`` (finite, e.g. a static deflection, or
    ``inf``, e.g. a displacement under a constant acceleration). Where the dynamic matrix is exactly
    singular (an undamped resonance on the grid), an output the resonant mode drives is ``inf``
    and one it does not drive keeps its finite value.
    """
    return response(without_hysteresis(plant), 1j * np.asarray(w, float))[:, 0, :]
