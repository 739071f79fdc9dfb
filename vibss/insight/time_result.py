"""The result of :func:`vibss.insight.time_contributions`: a time response split into the responses of
its modes and a residual, with the modes that make each output's peak."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from ..results import ZERO_NOTE, Result, TextTable, freeze, jsonable, require_pandas
from ..time.result import TimeResponse

__all__ = ["TimeContributions"]


@dataclass(frozen=True, eq=False)
class TimeContributions(Result):
    """A time response split into the responses of its modes and a residual.

    ``terms.sum(axis=0) + residual`` is the response (``response.outputs``, :func:`vibss.simulate`'s).
    ``r['b.z']`` is the (k, ns) terms of one output.

    Attributes
    ----------
    time : (ns,) ndarray
        Sample times [s].
    terms : (k, p, ns) ndarray
        Response of each mode (units of the outputs).
    residual : (p, ns) ndarray
        The direct terms (outputs that see an input directly) plus the modes left out.
    mode_frequency_hz : (k,) ndarray
        Undamped natural frequency of each term's mode [Hz].
    output_names : tuple of str
        Output signal names.
    output_units : tuple of str
        Output units.
    response : TimeResponse
        The response split (:func:`vibss.simulate`'s, method ``"modal"``).
    method : str
        ``"modal"`` (classical damping: one term per undamped mode) or ``"complex"`` (the coupled
        modes' complex modes, each pole given to the undamped mode that dominates its shape).
    note : str
        How it ran and its check.
    """

    time: np.ndarray
    terms: np.ndarray
    residual: np.ndarray
    mode_frequency_hz: np.ndarray
    output_names: tuple[str, ...]
    output_units: tuple[str, ...]
    response: TimeResponse
    method: str
    note: str = ""

    @property
    def output_labels(self) -> tuple[str, ...]:
        """Output signal names."""
        return self.output_names

    @property
    def units(self) -> tuple[str, ...]:
        """Units of the outputs."""
        return self.output_units

    def _item(self, i: int, j: int | None) -> np.ndarray:
        return self.terms[:, i, :]

    def __len__(self) -> int:
        return self.terms.shape[0]

    @cached_property
    def total(self) -> np.ndarray:
        """(p, ns) the response: the terms plus the residual."""
        return freeze(self.terms.sum(axis=0) + self.residual)

    def peak_index(self, output: int | str = 0) -> int:
        """Sample index of the largest ``|y|`` of one output (position or name)."""
        i = self._position(output, self.output_names, "output")
        return int(np.argmax(np.abs(self.total[i])))

    def window_of(self, output: int | str = 0, window: float | None = None) -> slice:
        """The samples within ``window / 2`` of an output's peak; default window: one period of the
        mode with the largest share at the peak (a tenth of the record for a rigid-body mode)."""
        i = self._position(output, self.output_names, "output")
        j = self.peak_index(i)
        if window is None:
            share = self.share_at(i, j)[:-1]
            known = share.size and not np.all(np.isnan(share))      # all NaN: the output is 0 at its peak
            f = self.mode_frequency_hz[int(np.nanargmax(np.abs(share)))] if known else 0.0
            span = float(self.time[-1] - self.time[0])
            window = 1.0 / f if f > 0 else 0.1 * span
        lo = np.searchsorted(self.time, self.time[j] - window / 2, side="left")
        hi = np.searchsorted(self.time, self.time[j] + window / 2, side="right")
        return slice(int(lo), int(max(hi, lo + 1)))

    def share_at(self, output: int | str, index: int) -> np.ndarray:
        """(k + 1,) each term's share of one output at sample ``index`` [-], ``term / y`` (the
        residual's last); they sum to 1 (NaN where ``y`` is 0)."""
        i = self._position(output, self.output_names, "output")
        y = self.total[i, index]
        parts = np.append(self.terms[:, i, index], self.residual[i, index])
        with np.errstate(divide="ignore", invalid="ignore"):
            return parts / y if y != 0 else np.full(parts.size, np.nan)

    def share_in(self, output: int | str, window: slice) -> np.ndarray:
        """(k + 1,) each term's share of one output over a window of samples [-]: its projection
        ``sum(term y) / sum(y^2)`` (the residual's last); they sum to 1."""
        i = self._position(output, self.output_names, "output")
        y = self.total[i, window]
        parts = np.concatenate([self.terms[:, i, window], self.residual[i, window][None]])
        y2 = float(y @ y)
        return parts @ y / y2 if y2 > 0 else np.full(parts.shape[0], np.nan)

    def dominant(self, top: int = 3, window: float | None = None) -> TextTable:
        """The ``top`` modes at each output's peak: the term's value there, its share of the peak and
        its share over a window around it (:meth:`window_of`), and the residual's.

        Parameters
        ----------
        top : int
            Modes listed per output.
        window : float or None
            Width of the window centred on the peak [s] (default: one period of the mode with the
            largest share at the peak).
        """
        rows = []
        for i, out in enumerate(self.output_names):
            if not np.any(self.total[i]):                   # no peak to split (a symmetry, or no path)
                rows.append([out, "", "0", "", "", "", "", ZERO_NOTE, ""])
                continue
            j = self.peak_index(i)
            at = self.share_at(i, j)
            win = self.window_of(i, window)
            over = self.share_in(i, win)
            order = [int(k) for k in np.argsort(-np.nan_to_num(np.abs(at[:-1]), nan=-np.inf))[:top]
                     if self.terms[k, i, j] != 0]
            width = float(self.time[win.stop - 1] - self.time[win.start])
            for rank, k in enumerate(order + [-1]):
                head = [out, f"{self.time[j]:.5g}", f"{self.total[i, j]:.4g}", f"{width:.3g}"] if rank == 0 \
                    else ["", "", "", ""]
                value = self.terms[k, i, j] if k >= 0 else self.residual[i, j]
                name = [f"{k + 1}", f"{self.mode_frequency_hz[k]:.3f}"] if k >= 0 else ["residual", ""]
                rows.append(head + name + [f"{value:.4g}", f"{100 * at[k]:.1f}", f"{100 * over[k]:.1f}"])
        return TextTable(["output", "t_peak [s]", "peak", "window [s]", "mode", "f_mode [Hz]", "term at peak",
                          "share at peak [%]", "share in window [%]"], rows,
                         title=f"Dominant modes at the response peaks ({self.method})",
                         notes=("share at peak: term / y; in window: sum(term y) / sum(y^2) over the window centred "
                                "on the peak; the modes' and the residual's shares sum to 100 %",
                                "units: " + ", ".join(f"{o} [{u}]" for o, u in zip(self.output_names, self.units))))

    def summary(self) -> TextTable:
        """The table of dominant modes (:meth:`dominant`)."""
        return self.dominant()

    def report(self) -> str:
        """Text report: the dominant modes at every output's peak."""
        head = (f"Modal contributions to a time response: {len(self)} modes, {len(self.output_names)} outputs, "
                f"{self.time.size} samples ({self.method})")
        return "\n\n".join([head, self.dominant().render()] + ([self.note] if self.note else []))

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready data."""
        return jsonable({"time": self.time, "outputs": self.output_names, "units": self.output_units,
                         "mode_frequency_hz": self.mode_frequency_hz, "terms": self.terms,
                         "residual": self.residual, "method": self.method, "note": self.note})

    def to_pandas(self) -> Any:
        """Long DataFrame: one row per term (0 for the residual), output and time, with its value."""
        pd = require_pandas()
        k, p, ns = self.terms.shape
        full = np.concatenate([self.residual[None], self.terms])
        idx = pd.MultiIndex.from_product([range(k + 1), self.output_names, self.time], names=["mode", "output", "time_s"])
        df = pd.DataFrame({"value": full.ravel()}, index=idx)
        df.attrs["units"] = {"value": dict(zip(self.output_names, self.output_units))}
        return df

    def plot(self, ax: Any = None, output: int | str = 0, top: int = 4, window: float | None = None) -> Any:
        """The response near an output's peak with its ``top`` modal terms, and their shares at the
        peak and over the window: :func:`vibss.plotting.insight_time.plot_time_contributions`.

        Parameters
        ----------
        ax : sequence of two Axes or None
            Axes to draw in; default: a new figure.
        output : int or str
            The output (position or name).
        top : int
            Terms drawn (the largest shares at the peak); the rest are summed with the residual.
        window : float or None
            The window around the peak [s] (:meth:`window_of`).

        Returns
        -------
        matplotlib.figure.Figure
        """
        from ..plotting.insight_time import plot_time_contributions

        i = self._position(output, self.output_names, "output")
        return plot_time_contributions(self, ax=ax, output=i, top=top, window=window)
