"""The operating point's result: the static equilibrium of nonlinear mounts and its tangent model."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from ..methods import Check, Claim
from ..model.model import Model
from ..results import Result, TextTable, jsonable, require_pandas
from ..statics import StaticResult

__all__ = ["OperatingPoint", "HarmonicBalanceResult"]


@dataclass(frozen=True, eq=False)
class OperatingPoint(Result):
    """The static equilibrium of a model with nonlinear mounts, and its tangent model.

    Follows the result protocol: ``op['engine.z']`` is a DOF's deflection [m or rad].

    Attributes
    ----------
    model : Model
        The nonlinear model.
    static : StaticResult
        Deflections, mount deflections and forces at the equilibrium (forces from each axis's law).
    tangent : Model
        Linear model with the tangent rates there (same names): every linear analysis applies.
    clearance : dict of str to float
        Clearance left per stop, ``"<mount>.<axis>"`` -> [m] (negative: in contact, by that much).
    stop_force : dict of str to float
        Force each stop carries [N] (0 when not in contact).
    iterations : int
        Newton steps taken.
    residual : float
        Final ``|r^T dq| / |F^T q|`` [-].
    note : str
        How it was found.
    """

    signal_kind: ClassVar[str] = "DOF"

    model: Model
    static: StaticResult
    tangent: Model
    clearance: dict
    stop_force: dict
    iterations: int
    residual: float
    note: str = ""
    method: str = "newton"

    @property
    def q(self) -> np.ndarray:
        """(n,) deflection of every body DOF at the equilibrium [m, rad]."""
        return self.static.q

    @property
    def output_labels(self) -> tuple[str, ...]:
        return self.static.output_labels

    @property
    def units(self) -> tuple[str, ...]:
        """Units of the DOFs (m, rad)."""
        return self.static.units

    def _item(self, i: int, j: int | None) -> float:
        return float(self.static.q[i])

    def rates(self) -> TextTable:
        """Tangent rates of the nonlinear mounts against their unloaded rates [N/m]."""
        rows = []
        tangent = {m.name: m for m in self.tangent.mounts}
        for m in self.model.mounts:
            if not getattr(m.type, "nonlinear", False):
                continue
            kt = tangent[m.name].type.stiffness
            for j, ax in enumerate("xyz"):
                k0 = m.type.stiffness[j]
                rows.append([m.name, ax, f"{k0:.4g}", f"{kt[j]:.4g}", f"{kt[j] / k0:.3f}" if k0 else "-"])
        return TextTable(["mount", "axis", "unloaded [N/m]", "tangent [N/m]", "ratio"], rows,
                     title="Tangent rates at the operating point")

    def summary(self) -> TextTable:
        rows = [[key, f"{1e3 * c:.3f}", f"{self.stop_force[key]:.4g}"] for key, c in self.clearance.items()]
        return TextTable(["stop", "clearance left [mm]", "stop force [N]"], rows, title="Stops at the operating point")

    def report(self) -> str:
        head = f"Operating point of {self.model.name!r}: {self.iterations} Newton steps, residual {self.residual:.1e}"
        parts = [head, self.static.report(), self.rates().render()]
        if self.clearance:
            parts.append(self.summary().render())
        return "\n\n".join(parts)

    def to_dict(self) -> dict[str, Any]:
        return {"static": self.static.to_dict(), "clearance": dict(self.clearance),
                "stop_force": dict(self.stop_force), "iterations": self.iterations,
                "residual": self.residual, "note": self.note}

    def to_pandas(self) -> Any:
        """The static deflection's DataFrame (:meth:`StaticResult.to_pandas`)."""
        return self.static.to_pandas()

    def plot(self, ax: Any = None) -> Any:
        """The static deflection's bar chart (:meth:`StaticResult.plot`)."""
        return self.static.plot(ax=ax)


@dataclass(frozen=True, eq=False)
class HarmonicBalanceResult(Result):
    """The steady periodic response of a model with nonlinear mounts under sine inputs, along a branch.

    Every output is ``y(t) = Re sum_{k=0}^{H} Y_k exp(i k omega t)`` about the operating point
    (``Y_0``: the shift of the mean). Follows the result protocol: ``r['b.z']`` is that output's
    first-harmonic amplitude at every branch point.

    Attributes
    ----------
    frequencies : (nb,) ndarray
        Frequency of each branch point [Hz], in the order of the branch (not monotone through a fold).
    harmonics : (p, H+1, nb) complex ndarray
        Coefficients ``Y_k`` of each output (its unit) per harmonic and point.
    stable : (nb,) bool ndarray or None
        Stability per point, by Hill's method or Floquet's multipliers as :attr:`note` says (None: not
        computed, the note says why).
    growth : (nb,) ndarray or None
        Largest real part of the physical Floquet exponents [1/s] (> 0: unstable).
    turning_points : (k,) ndarray
        Frequencies of the folds of the branch [Hz] (where it turns back: the jump frequencies of
        slow sweeps), the extremum of the cubic Hermite in arclength through the two path points around
        each (their frequencies and slopes).
    turning_index : (k,) int ndarray
        The branch point nearest each fold.
    residual : (nb,) ndarray
        Residual of the harmonic-balance equations, relative to the local deflections [-].
    truncation : (nb,) ndarray
        RMS of the larger of the two highest harmonics kept over the RMS of all the harmonics >= 1,
        of the nonlinear axes' deflections [-] (the truncation estimate).
    local_labels : tuple of str
        The nonlinear axes (``mount.<name>.d1|d2|d3``).
    local : (m, H+1, nb) complex ndarray
        Their deflections' coefficients [m] about the operating point.
    inputs : dict of str to complex
        Input amplitudes (phasors of ``u(t) = Re(u exp(i omega t))``, their SI units; at the first
        point for an amplitude that follows the frequency).
    output_labels, units : tuple of str
        Output names and units.
    claim : Claim
        What the method promises (tolerance of the truncation estimate).
    check : Check
        The worst truncation estimate along the branch against the claim.
    note : str
        How the branch was followed, the operating point, stability.
    """

    frequencies: np.ndarray
    harmonics: np.ndarray
    stable: np.ndarray | None
    growth: np.ndarray | None
    turning_points: np.ndarray
    turning_index: np.ndarray
    residual: np.ndarray
    truncation: np.ndarray
    local_labels: tuple[str, ...]
    local: np.ndarray
    inputs: dict
    output_names: tuple[str, ...]
    output_units: tuple[str, ...]
    claim: Claim
    check: Check
    note: str = ""
    method: str = "aft"

    @property
    def omega(self) -> np.ndarray:
        """(nb,) angular frequency of each point [rad/s]."""
        return 2 * np.pi * self.frequencies

    @property
    def amplitude(self) -> np.ndarray:
        """(p, nb) first-harmonic amplitude ``|Y_1|`` of each output (its unit)."""
        return np.abs(self.harmonics[:, 1, :])

    @property
    def peak(self) -> np.ndarray:
        """(p, nb) largest ``|y(t) - y_op|`` over the period of each output (all harmonics; its unit)."""
        H = self.harmonics.shape[1] - 1
        tau = 2 * np.pi * np.arange(16 * H + 16) / (16 * H + 16)
        e = np.exp(1j * np.outer(np.arange(H + 1), tau))          # (H+1, nt)
        y = np.einsum("pkb,kt->pbt", self.harmonics, e).real
        return np.abs(y).max(axis=2)

    @property
    def output_labels(self) -> tuple[str, ...]:
        """Output signal names."""
        return self.output_names

    @property
    def units(self) -> tuple[str, ...]:
        """SI unit of each output."""
        return self.output_units

    def _item(self, i: int, j: int | None) -> np.ndarray:
        return self.amplitude[i]

    def table(self) -> TextTable:
        """Frequency, first-harmonic amplitude per output and stability of every branch point."""
        head = ["f [Hz]"] + [f"|{o}| [{u}]" for o, u in zip(self.output_labels, self.units)] + ["stable"]
        amp = self.amplitude
        rows = [[f"{f:.6g}"] + [f"{a:.4e}" for a in amp[:, b]]
                + ["-" if self.stable is None else ("yes" if self.stable[b] else "no")]
                for b, f in enumerate(self.frequencies)]
        return TextTable(head, rows, title="Harmonic balance: first-harmonic amplitude along the branch")

    def turning_table(self) -> TextTable:
        """The folds: frequency, which slow sweep jumps there and each output's first-harmonic amplitude.

        The branch starts upwards in frequency, so its folds alternate: a highest frequency (an upward
        sweep that followed the branch there leaves it: a jump), then a lowest (a downward sweep's
        jump), and so on.
        """
        head = ["fold", "f [Hz]", "slow sweep"] + [f"|{o}| [{u}]" for o, u in zip(self.output_labels, self.units)]
        amp = self.amplitude
        rows = [[str(n + 1), f"{f:.6g}", "upward sweep jumps" if n % 2 == 0 else "downward sweep jumps"]
                + [f"{a:.4e}" for a in amp[:, int(k)]]
                for n, (f, k) in enumerate(zip(self.turning_points, self.turning_index))]
        return TextTable(head, rows, title="Harmonic balance: turning points (jump frequencies of slow sweeps)"
                         + ("" if rows else ": none in the range"))

    def summary(self) -> TextTable:
        amp = self.amplitude
        rows = []
        for i, (o, u) in enumerate(zip(self.output_labels, self.units)):
            b = int(np.argmax(amp[i])) if amp.shape[1] else 0
            rows.append([o, f"{amp[i, b]:.4e} {u}" if amp.shape[1] else "-",
                         f"{self.frequencies[b]:.6g}" if amp.shape[1] else "-"])
        return TextTable(["output", "largest first harmonic", "at [Hz]"], rows,
                         title="Harmonic balance: peaks along the branch")

    def report(self) -> str:
        folds = ", ".join(f"{f:.6g} Hz" for f in self.turning_points) or "none"
        unstable = "not computed" if self.stable is None else f"{int(np.sum(~self.stable))} of {self.stable.size}"
        head = (f"Harmonic balance ({self.harmonics.shape[1] - 1} harmonics, {self.frequencies.size} points): "
                f"turning points {folds}; unstable points {unstable}; {self.check.text()}")
        return "\n\n".join([head, self.summary().render(), self.note])

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready data (SI; complex numbers as ``[re, im]``)."""
        return jsonable({"frequencies": self.frequencies, "amplitude": self.amplitude,
                         "harmonics": self.harmonics, "stable": self.stable,
                         "turning_points": self.turning_points, "residual": self.residual,
                         "truncation": self.truncation, "outputs": self.output_labels, "units": self.units,
                         "inputs": self.inputs, "claim": self.claim.text(), "check": self.check.text(),
                         "note": self.note})

    def to_pandas(self) -> Any:
        """DataFrame: one row per branch point; frequency [Hz], each output's first-harmonic amplitude, stability
        (the unit of each column in ``attrs["units"]``)."""
        pd = require_pandas()
        data: dict[str, Any] = {"frequency [Hz]": self.frequencies}
        for i, o in enumerate(self.output_labels):
            data[o] = self.amplitude[i]
        data["stable"] = self.stable if self.stable is not None else np.full(self.frequencies.size, None)
        df = pd.DataFrame(data)
        df.attrs["units"] = {"frequency [Hz]": "Hz", **dict(zip(self.output_labels, self.units)), "stable": "-"}
        return df

    def plot(self, outputs: Any = None, ax: Any = None) -> Any:
        """Amplitude against frequency, unstable parts dashed: :func:`vibss.plotting.harmonic.plot_harmonic_balance`."""
        from ..plotting.harmonic import plot_harmonic_balance

        return plot_harmonic_balance(self, outputs=outputs, ax=ax)
