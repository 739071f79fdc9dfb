"""The result of fitting a rheology to a measured dynamic stiffness: :class:`RheologyFit`."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..model.rheology import Rheology
from ..results import Result, TextTable, jsonable, require_pandas

__all__ = ["RheologyFit", "AXES"]

AXES = ("axis 1", "axis 2", "axis 3")
"""The labels of a mount's three principal axes (a rheology's rows)."""


@dataclass(frozen=True, eq=False)
class RheologyFit(Result):
    """A rheology fitted to a measured complex stiffness, with its error at every frequency.

    ``fit['axis 3']`` is the fitted ``k*`` of that axis (nf,) [N/m]; ``fit.rheology`` goes into
    ``MountType(rheology=...)``.

    Attributes
    ----------
    rheology : Rheology
        The fitted law (:class:`~vibss.model.rheology.Zener`, ``Prony`` or ``FractionalZener``).
    type : str
        The law's name as asked (``"zener"``, ``"prony"``, ``"fractional"``).
    order : int
        Number of Maxwell terms (1 for a Zener, 0 for a fractional law).
    frequency_hz : (nf,) ndarray
        Frequencies of the data [Hz].
    data : (3, nf) complex ndarray
        The measured complex stiffness per axis [N/m].
    fitted : (3, nf) complex ndarray
        The fitted law's ``k*`` at the same frequencies [N/m].
    error : (3, nf) ndarray
        ``|log(fitted / data)|`` per axis and frequency [-]: the log-magnitude error and the phase
        error [rad] combined (0.01: about 1 % in magnitude or 0.01 rad in phase).
    rms_error : (3,) ndarray
        Root mean square of ``error`` over the frequencies, per axis [-].
    tolerance : float
        The RMS error the fit is held to [-]; above it a VibssWarning was given.
    evaluations : int
        Residual evaluations spent by the least-squares fits (cost).
    method : str
        ``"least_squares"`` (scipy.optimize.least_squares on the complex log error).
    note : str
        The check: the largest RMS error against the tolerance; for a fractional law, how far the
        Maxwell ladder every analysis uses is from it.
    """

    rheology: Rheology
    type: str
    order: int
    frequency_hz: np.ndarray
    data: np.ndarray
    fitted: np.ndarray
    error: np.ndarray
    rms_error: np.ndarray
    tolerance: float
    evaluations: int
    method: str = "least_squares"
    note: str = ""

    @property
    def output_labels(self) -> tuple[str, ...]:
        """The principal axes, ``("axis 1", "axis 2", "axis 3")``."""
        return AXES

    @property
    def units(self) -> tuple[str, ...]:
        """Unit of each axis' stiffness, ``"N/m"``."""
        return ("N/m",) * 3

    @property
    def ok(self) -> bool:
        """Every axis within ``tolerance``."""
        return bool(np.all(self.rms_error <= self.tolerance))

    def _item(self, i: int, j: int | None) -> np.ndarray:
        return self.fitted[i]

    def parameters(self) -> dict[str, Any]:
        """The fitted law's parameters (SI), as in a model file's ``rheology = {...}`` table."""
        return self.rheology.to_dict()

    def summary(self) -> TextTable:
        """Per axis: the parameters, the RMS and the largest error."""
        spec = self.parameters()
        keys = [k for k in spec if k not in ("type", "band")]
        rows = []
        for j, axis in enumerate(AXES):
            cells = []
            for key in keys:
                v = np.atleast_1d(np.asarray(spec[key], dtype=float))
                v = v[j] if v.ndim == 1 and v.size == 3 else (v[j] if v.ndim == 2 else v)
                cells.append(" ".join(f"{x:.6g}" for x in np.atleast_1d(v)))
            rows.append([axis, *cells, f"{self.rms_error[j]:.3g}", f"{self.error[j].max():.3g}"])
        units = {"k_0": "N/m", "k_inf": "N/m", "k": "N/m", "tau": "s", "alpha": "-"}
        head = ["axis", *[f"{k} [{units.get(k, '-')}]" for k in keys], "RMS log error [-]", "max [-]"]
        return TextTable(head, rows, title=f"{self.type} fitted to {self.frequency_hz.size} frequencies, "
                                          f"{self.frequency_hz.min():.4g} to {self.frequency_hz.max():.4g} Hz",
                         notes=[self.note] if self.note else [])

    def report(self) -> str:
        """The fitted parameters and errors as text."""
        return f"Rheology fit ({self.method})\n" + self.summary().render()

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: the rheology table, the data, the fit and the errors (SI)."""
        return jsonable({"type": self.type, "rheology": self.parameters(), "frequency_hz": self.frequency_hz,
                         "data": self.data, "fitted": self.fitted, "error": self.error,
                         "rms_error": self.rms_error, "tolerance": self.tolerance, "method": self.method,
                         "note": self.note})

    def to_pandas(self) -> Any:
        """DataFrame indexed by frequency [Hz]: data, fitted (complex, N/m) and error per axis."""
        pd = require_pandas()
        cols = {}
        for j, axis in enumerate(AXES):
            cols[f"{axis} data"] = self.data[j]
            cols[f"{axis} fitted"] = self.fitted[j]
            cols[f"{axis} error"] = self.error[j]
        return pd.DataFrame(cols, index=pd.Index(self.frequency_hz, name="frequency_hz"))

    def plot(self, ax: Any = None) -> Any:
        """The data and the fit: |k*| [N/m] and loss factor against frequency, and the error
        (:func:`vibss.plotting.measured.plot_rheology_fit`).

        Parameters
        ----------
        ax : (3,) sequence of Axes or None
            Axes for |k*|, the loss factor and the error; default: a new figure.

        Returns
        -------
        matplotlib.figure.Figure
        """
        from ..plotting.measured import plot_rheology_fit

        return plot_rheology_fit(self, ax)
