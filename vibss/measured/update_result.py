"""The result of model updating: :class:`UpdateResult` (:func:`vibss.update`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from ..methods import Check
from ..model.model import Model
from ..results import Result, TextTable, jsonable, require_pandas

__all__ = ["UpdateResult"]


@dataclass(frozen=True, eq=False)
class UpdateResult(Result):
    """Updated parameters with their standard deviations, the updated model, and how well the
    model matches the measurement before and after.

    ``result["front.k3"]`` is the updated value of that parameter [its unit].

    Attributes
    ----------
    model : Model
        The updated model.
    initial_model : Model
        The model as given.
    parameters : tuple of str
        Parameter names.
    parameter_units : tuple of str
        Their units (N/m, -, m, rad).
    initial, estimate, standard_deviation : (k,) ndarray
        Starting values, updated values and their standard deviations ``s (J^T J)^-1/2``
        [parameter units]; ``inf`` for parameters the data cannot tell apart.
    kind : str
        ``"frequency response"`` or ``"modes"``.
    labels : tuple of str
        What the correlation is given for: channels ``"<output>/<input>"`` or ``"mode i"``.
    measured : FrequencyResponse or MeasuredModes
        The data.
    correlation_before, correlation_after : (c,) ndarray
        FRAC per channel, or MAC per measured mode with its paired model mode [-].
    response_before, response_after : FrequencyResponse or None
        The model's response at the measured frequencies (frequency responses only).
    frequency_before, frequency_after : (k,) ndarray
        The paired model modes' natural frequencies [Hz] (modes only; empty otherwise).
    residual_rms : (2,) ndarray
        RMS of the weighted residuals before and after [-].
    singular_values : (k,) ndarray
        Of the Jacobian with columns scaled to unit norm [-] (identifiability).
    unidentifiable : tuple of str
        Groups of parameters the data cannot tell apart (``"a.k3 and b.k3"``).
    check : Check
        The gradient check after the fit.
    evaluations : int
        Residual evaluations of the least-squares run.
    method : str
        ``"least_squares"`` (trf, exact gradients).
    note : str
        Counts, convergence, the check and the residual scale.
    """

    signal_kind: ClassVar[str] = "parameter"

    model: Model
    initial_model: Model
    parameters: tuple[str, ...]
    parameter_units: tuple[str, ...]
    initial: np.ndarray
    estimate: np.ndarray
    standard_deviation: np.ndarray
    kind: str
    labels: tuple[str, ...]
    measured: Any
    correlation_before: np.ndarray
    correlation_after: np.ndarray
    response_before: Any
    response_after: Any
    frequency_before: np.ndarray
    frequency_after: np.ndarray
    residual_rms: np.ndarray
    singular_values: np.ndarray
    unidentifiable: tuple[str, ...]
    check: Check
    evaluations: int
    method: str = "least_squares"
    note: str = ""

    @property
    def values(self) -> dict[str, float]:
        """Updated values by parameter name [parameter units]."""
        return {p: float(v) for p, v in zip(self.parameters, self.estimate)}

    @property
    def std(self) -> dict[str, float]:
        """Standard deviations by parameter name [parameter units] (``inf``: not identifiable)."""
        return {p: float(v) for p, v in zip(self.parameters, self.standard_deviation)}

    @property
    def output_labels(self) -> tuple[str, ...]:
        """The parameters."""
        return self.parameters

    @property
    def units(self) -> tuple[str, ...]:
        """The parameters' units."""
        return self.parameter_units

    def _item(self, i: int, j: int | None) -> float:
        return float(self.estimate[i])

    def summary(self) -> TextTable:
        """Per parameter: start, updated value, standard deviation, change."""
        rows = []
        for p, u, a, b, s in zip(self.parameters, self.parameter_units, self.initial, self.estimate,
                                 self.standard_deviation):
            change = f"{100 * (b - a) / a:+.2f} %" if u in ("N/m", "-") and a else f"{b - a:+.4g} {u}"
            rel = ("inf" if not np.isfinite(s) else f"{100 * s / abs(b):.3g} %" if u in ("N/m", "-") and b else "-")
            rows.append([p, f"{a:.6g}", f"{b:.6g}", f"{s:.3g}", rel, change, u])
        return TextTable(["parameter", "start", "updated", "std", "std/value", "change", "unit"], rows,
                         title=f"Updated to {self._data_text()}",
                         notes=[f"not identifiable: {g}" for g in self.unidentifiable])

    def _data_text(self) -> str:
        m = self.measured
        if self.kind == "modes":
            return f"{len(m)} measured modes at {len(m.outputs)} outputs"
        return (f"a measured response ({len(m.outputs)} x {len(m.inputs)} channels, {m.frequency_hz.size} "
                f"frequencies, {m.frequency_hz.min():.4g} to {m.frequency_hz.max():.4g} Hz)")

    def correlation(self) -> TextTable:
        """FRAC per channel, or measured and model frequencies with MAC per mode, before and after."""
        if self.kind == "modes":
            fm = self.measured.frequency_hz
            rows = [[lab, f"{fm[i]:.4g}", f"{self.frequency_before[i]:.4g}", f"{self.frequency_after[i]:.4g}",
                     f"{100 * (self.frequency_after[i] - fm[i]) / fm[i]:+.3f}", f"{self.correlation_before[i]:.4f}",
                     f"{self.correlation_after[i]:.4f}"] for i, lab in enumerate(self.labels)]
            return TextTable(["mode", "measured [Hz]", "before [Hz]", "after [Hz]", "error after [%]", "MAC before",
                              "MAC after"], rows, title="Modes: frequencies and MAC before and after")
        rows = [[lab, f"{b:.4f}", f"{a:.4f}"] for lab, b, a in
                zip(self.labels, self.correlation_before, self.correlation_after)]
        return TextTable(["channel", "FRAC before", "FRAC after"], rows, title="FRAC per channel before and after")

    def html_tables(self) -> list[TextTable]:
        """The parameters and the correlation."""
        return [self.summary(), self.correlation()]

    def report(self) -> str:
        """Text: the parameters, the correlation, the residual before and after, the note."""
        rms = (f"RMS weighted residual {self.residual_rms[0]:.4g} before, {self.residual_rms[1]:.4g} after "
               f"(smallest scaled singular value {self.singular_values.min() / self.singular_values.max():.2g} "
               "of the largest)")
        return "\n\n".join([f"Model updating of {self.initial_model.name!r} ({self.method})",
                            self.summary().render(), self.correlation().render(), rms, self.note])

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready values, standard deviations and correlation (SI)."""
        return jsonable({"model": self.initial_model.name, "kind": self.kind, "parameters": list(self.parameters),
                         "units": list(self.parameter_units), "initial": self.initial, "values": self.estimate,
                         "std": self.standard_deviation, "labels": list(self.labels),
                         "correlation_before": self.correlation_before, "correlation_after": self.correlation_after,
                         "frequency_before": self.frequency_before, "frequency_after": self.frequency_after,
                         "residual_rms": self.residual_rms, "singular_values": self.singular_values,
                         "unidentifiable": list(self.unidentifiable), "evaluations": self.evaluations,
                         "method": self.method, "note": self.note})

    def to_pandas(self) -> Any:
        """DataFrame: one row per parameter, ``initial``, ``value``, ``std``, ``unit``."""
        pd = require_pandas()
        return pd.DataFrame({"initial": self.initial, "value": self.estimate, "std": self.standard_deviation,
                             "unit": list(self.parameter_units)},
                            index=pd.Index(list(self.parameters), name="parameter"))

    def plot(self, ax: Any = None) -> Any:
        """Measured against the model before and after: |H| per channel against frequency, or the
        frequencies and MAC per mode (:func:`vibss.plotting.update.plot_update`).

        Parameters
        ----------
        ax : Axes or sequence of Axes or None
            Axes to draw into (one per channel, or two for modes); default: a new figure.

        Returns
        -------
        matplotlib.figure.Figure
        """
        from ..plotting.update import plot_update

        return plot_update(self, ax)
