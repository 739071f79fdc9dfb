"""Finite-rate sine sweeps: the simulated response envelope against the steady-state FRF.

A sweep with ``sweep_time > 0`` passes each resonance in finite time, so the response peak is
lower, later (shifted in the sweep direction) and followed by beating. :func:`sweep_envelope`
simulates the sweep (:func:`vibss.time.simulate`), takes the envelope of every output (magnitude of
the analytic signal, :func:`scipy.signal.hilbert`) against the instantaneous frequency, and sets it
beside the steady-state amplitude ``|H(f)| a(f)`` from the exact solve of
``(K - w^2 M + i w C) X = RHS`` (:func:`vibss.linear.solve.response`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.signal import hilbert

from ..errors import ModelError
from ..model.model import Model
from ..linear.signals import build_plant
from ..linear.solve import response, without_hysteresis
from .api import TimeResponse, simulate

__all__ = ["SweepEnvelope", "sweep_envelope"]


@dataclass(frozen=True, eq=False)
class SweepEnvelope:
    """Envelope of a finite-rate sweep response beside the steady-state amplitude.

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

    def peak_ratio(self) -> np.ndarray:
        """(p,) largest envelope over largest steady-state amplitude (< 1 for a fast sweep)."""
        return self.envelope.max(axis=1) / self.steady.max(axis=1)

    def plot(self, outputs: Any = None) -> Any:
        """Envelope and steady-state amplitude against frequency, one axes per output."""
        import matplotlib.pyplot as plt

        names = list(outputs) if outputs is not None else list(self.outputs)
        fig, axes = plt.subplots(len(names), 1, sharex=True, squeeze=False,
                                 figsize=(8, 1.5 + 2.0 * len(names)))
        for ax, n in zip(axes[:, 0], names):
            i = self.outputs.index(n)
            ax.plot(self.frequency_hz, self.steady[i], "k--", lw=1, label="steady state")
            ax.plot(self.frequency_hz, self.envelope[i], lw=1.2, label="sweep envelope")
            ax.set_ylabel(f"{n} [{self.units[i]}]", fontsize=8)
            ax.grid(True, alpha=0.3)
            ax.legend(fontsize=7)
        axes[-1, 0].set_xlabel("instantaneous frequency [Hz]")
        fig.tight_layout()
        return fig


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
    (:func:`vibss.linear.solve.response`) without the hysteretic parts (the time domain has none).

    At ``w = 0`` the value is the exact limit ``w -> 0+`` (finite, e.g. a static deflection, or
    ``inf``, e.g. a displacement under a constant acceleration). Where the dynamic matrix is exactly
    singular (an undamped resonance on the grid), an output the resonant mode drives is ``inf``
    and one it does not drive keeps its finite value.
    """
    return response(without_hysteresis(plant), 1j * np.asarray(w, float))[:, 0, :]
