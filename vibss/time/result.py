"""The result of a simulation: :class:`TimeResponse` (sampled outputs and inputs, with the result
protocol of :mod:`vibss.results`) and its :class:`PeakTable`."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from .._validate import name_index
from ..errors import ArgumentError
from ..results import ReadOnly, Result, TextTable, jsonable, require_pandas

__all__ = ["TimeResponse", "PeakTable", "ContactTable"]


@dataclass(frozen=True, eq=False)
class ContactTable(ReadOnly):
    """The stops a nonlinear time response hit: one row per (mount, local axis, side).

    Attributes
    ----------
    mount, axis, side : tuple of str
        Mount name, local axis (``x``, ``y``, ``z``) and side (``+``: past the positive clearance,
        ``-``: past the negative one) of each row.
    first : (k,) ndarray
        Time of the first contact [s] (0: in contact at the operating point).
    duration : (k,) ndarray
        Total time in contact [s].
    count : (k,) int ndarray
        Number of contacts.
    peak : (k,) ndarray
        Peak deflection of the axis on that side [m] (total: operating point included; located
        between the samples, not read from them).
    peak_time : (k,) ndarray
        Its time [s].
    force : (k,) ndarray
        Peak stop force [N]: the stop rate times the peak's overlap with the stop.
    intervals : tuple of tuple of (float, float)
        Each row's contact intervals ``(start, end)`` [s].
    axes : tuple of str
        Every nonlinear axis, ``"<mount>.<axis>"`` (hit or not).
    peak_hi, peak_lo : (r,) ndarray
        Largest and smallest deflection of each of ``axes`` over the record [m].
    """

    mount: tuple[str, ...]
    axis: tuple[str, ...]
    side: tuple[str, ...]
    first: np.ndarray
    duration: np.ndarray
    count: np.ndarray
    peak: np.ndarray
    peak_time: np.ndarray
    force: np.ndarray
    intervals: tuple[tuple[tuple[float, float], ...], ...]
    axes: tuple[str, ...] = ()
    peak_hi: np.ndarray = field(default_factory=lambda: np.zeros(0))
    peak_lo: np.ndarray = field(default_factory=lambda: np.zeros(0))

    def __len__(self) -> int:
        return len(self.mount)

    @property
    def table(self) -> TextTable:
        """The rows as a text table."""
        rows = [[m, a, s, f"{f:.6g}", f"{d:.6g}", str(c), f"{p:.6e}", f"{pt:.6g}", f"{fo:.6g}"]
                for m, a, s, f, d, c, p, pt, fo in zip(self.mount, self.axis, self.side, self.first, self.duration,
                                                       self.count, self.peak, self.peak_time, self.force)]
        return TextTable(["mount", "axis", "side", "first [s]", "in contact [s]", "contacts", "peak defl. [m]",
                          "at [s]", "peak stop force [N]"], rows,
                         title="stop contacts" if rows else "stop contacts: no stop hit")

    def to_pandas(self) -> Any:
        """DataFrame with one row per stop hit."""
        pd = require_pandas()
        return pd.DataFrame({"mount": self.mount, "axis": self.axis, "side": self.side, "first": self.first,
                             "duration": self.duration, "count": self.count, "peak": self.peak,
                             "peak_time": self.peak_time, "force": self.force})

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready rows (SI)."""
        return jsonable({"rows": [
            {"mount": m, "axis": a, "side": s, "first": f, "duration": d, "count": int(c), "peak": p,
             "peak_time": pt, "force": fo, "intervals": [list(i) for i in iv]}
            for m, a, s, f, d, c, p, pt, fo, iv in zip(self.mount, self.axis, self.side, self.first, self.duration,
                                                       self.count, self.peak, self.peak_time, self.force,
                                                       self.intervals)],
            "axes": {n: [lo, hi] for n, lo, hi in zip(self.axes, self.peak_lo, self.peak_hi)}})

    def __repr__(self) -> str:
        if not self.mount:
            return "ContactTable(no stop hit)"
        hits = ", ".join(f"{m}.{a}{s} at {f:.4g} s ({fo:.4g} N)" for m, a, s, f, fo in
                         zip(self.mount, self.axis, self.side, self.first, self.force))
        return f"ContactTable({hits})"


@dataclass(frozen=True, eq=False)
class PeakTable(ReadOnly):
    """Peak (largest magnitude) value, its time, and RMS of each output.

    Attributes
    ----------
    outputs : tuple of str
        Output names (p).
    units : tuple of str
        SI unit per output.
    value : (p,) ndarray
        Signed value at the peak of ``|y|``.
    time : (p,) ndarray
        Time of the peak [s].
    rms : (p,) ndarray
        Root mean square over the recorded samples.
    """

    outputs: tuple[str, ...]
    units: tuple[str, ...]
    value: np.ndarray
    time: np.ndarray
    rms: np.ndarray

    def to_pandas(self) -> Any:
        """DataFrame indexed by output, columns peak, time, rms, unit."""
        pd = require_pandas()

        df = pd.DataFrame({"peak": self.value, "time": self.time, "rms": self.rms,
                           "unit": self.units}, index=list(self.outputs))
        df.attrs["units"] = {"peak": "the row's unit", "time": "s", "rms": "the row's unit",
                             "by row": dict(zip(self.outputs, self.units))}
        return df


@dataclass(frozen=True, eq=False)
class TimeResponse(Result):
    """A simulated time response.

    Follows the result protocol (:mod:`vibss.results`): ``r['b.z']`` is the (ns,) samples of one
    output; ``r.control`` is the python-control ``TimeResponseData``; ``output_labels`` /
    ``input_labels`` are python-control's names of ``output_names`` / ``input_names``.

    Attributes
    ----------
    time : (ns,) ndarray
        Sample times [s] (from ``record_from``).
    outputs : (p, ns) ndarray
        Output values (SI, unit per output in ``units``).
    output_names : tuple of str
        Output signal names, e.g. ``'engine.z'``, ``'sensor.x'``, ``'mount.front.fz'``.
    units : tuple of str
        SI unit per output.
    inputs : (m, ns) ndarray
        Input signals at the samples.
    input_names : tuple of str
        Input signal names, e.g. ``'engine.fz'``, ``'ground.z.acc'``.
    method : str
        The method that ran.
    note : str
        How it ran (and, for ``auto``, why).
    name : str
        System name.
    contacts : ContactTable or None
        A model with nonlinear mounts: the stops hit, when, for how long, the peak deflections and
        stop forces (None for a linear model).
    """

    time: np.ndarray
    outputs: np.ndarray
    output_names: tuple[str, ...]
    units: tuple[str, ...]
    inputs: np.ndarray
    input_names: tuple[str, ...]
    method: str
    note: str
    name: str = "vibss"
    contacts: ContactTable | None = None

    @property
    def output_labels(self) -> tuple[str, ...]:
        """Output signal names (python-control's name; ``output_names`` is the same)."""
        return self.output_names

    @property
    def input_labels(self) -> tuple[str, ...]:
        """Input signal names (python-control's name; ``input_names`` is the same)."""
        return self.input_names

    def _item(self, i: int, j: int | None) -> np.ndarray:
        if j is not None:
            raise ArgumentError(f"TimeResponse[{self.output_names[i]!r}, {self.input_names[j]!r}]: a time "
                                "response is the sum over its inputs; index by output only",
                                argument="key", received=(self.output_names[i], self.input_names[j]))
        return self.outputs[i]

    @property
    def control(self) -> Any:
        """The same response as a python-control :class:`control.TimeResponseData`."""
        from control import TimeResponseData

        return TimeResponseData(
            self.time, self.outputs, None, self.inputs if self.inputs.size else None,
            output_labels=list(self.output_names),
            input_labels=list(self.input_names) if self.inputs.size else None, sysname=self.name)

    data = control
    """Old name of :attr:`control`."""

    def output(self, name: str) -> np.ndarray:
        """(ns,) samples of output ``name``."""
        return self.outputs[name_index(name, self.output_names, "output", who="TimeResponse.output")]

    def peaks(self) -> PeakTable:
        """Peak value (largest magnitude, signed), its time, and RMS of every output."""
        if self.time.size == 0:
            z = np.zeros(len(self.output_names))
            return PeakTable(self.output_names, self.units, z, z, z)
        i = np.argmax(np.abs(self.outputs), axis=1)
        rows = np.arange(len(i))
        return PeakTable(self.output_names, self.units, self.outputs[rows, i], self.time[i],
                         np.sqrt(np.mean(self.outputs**2, axis=1)))

    def in_g(self) -> TimeResponse:
        """The same response with translational accelerations (outputs in m/s^2) in g
        (standard gravity, 9.80665 m/s^2): for tables and figures of shock studies."""
        from ..model.units import STANDARD_GRAVITY

        acc = np.array([u == "m/s^2" for u in self.units])
        if not acc.any():
            return self
        outputs = np.where(acc[:, None], self.outputs / STANDARD_GRAVITY, self.outputs)
        return replace(self, outputs=outputs, units=tuple("g" if a else u for a, u in zip(acc, self.units)))

    def negligible(self, rel: float = 1e-9) -> tuple[str, ...]:
        """Outputs whose peak is below ``rel`` times the largest peak of their unit (rad counted
        with m, rad/s^2 with m/s^2: rotations of a body of about 1 m): channels the model's symmetry
        leaves at zero, up to rounding (1e-17 m beside a 0.7 m stroke)."""
        return _negligible(self.peaks(), rel)

    def report(self) -> str:
        """Text table: peak value and its time, and RMS, per output (channels left at zero by the
        model's symmetry, :meth:`negligible`, counted below the table rather than listed)."""
        pk = self.peaks()
        width = max([len(n) for n in self.output_names] + [6])
        lines = [f"Time response of {self.name}: {self.time.size} samples"
                 + (f", {self.time[0]:g} .. {self.time[-1]:g} s" if self.time.size else ""),
                 f"method: {self.method} ({self.note})", "",
                 f"{'output':<{width}}  {'peak':>13}  {'at [s]':>10}  {'RMS':>12}  unit"]
        quiet = set(_negligible(pk))
        for n, u, v, t, r in zip(self.output_names, self.units, pk.value, pk.time, pk.rms):
            if n not in quiet:
                lines.append(f"{n:<{width}}  {v:>13.5e}  {t:>10.5f}  {r:>12.5e}  {u}")
        if quiet:
            lines.append(f"({len(quiet)} output{'s' if len(quiet) > 1 else ''} below 1e-9 of the largest of "
                         f"their unit not listed: {', '.join(n for n in self.output_names if n in quiet)})")
        if self.contacts is not None:
            lines += ["", self.contacts.table.render()]
        return "\n".join(lines)

    def summary(self) -> TextTable:
        """Peak value, its time and RMS of every output but the :meth:`negligible` ones."""
        pk = self.peaks()
        quiet = set(_negligible(pk))
        rows = [[n, f"{v:.5e}", f"{t:.5f}", f"{r:.5e}", u]
                for n, u, v, t, r in zip(self.output_names, self.units, pk.value, pk.time, pk.rms) if n not in quiet]
        return TextTable(["output", "peak", "at [s]", "RMS", "unit"], rows, title=f"method {self.method}"
                     + (f"; {len(quiet)} outputs below 1e-9 of the largest of their unit not listed" if quiet else ""))

    def to_dict(self) -> dict[str, Any]:
        """The spec's JSON: ``{"time": [...], "outputs": {name: [...]}}`` plus units and method."""
        return jsonable({"time": self.time,
                         "outputs": {n: row for n, row in zip(self.output_names, self.outputs)},
                         "units": dict(zip(self.output_names, self.units)),
                         "method": self.method, "note": self.note}
                        | ({} if self.contacts is None else {"contacts": self.contacts.to_dict()}))

    def to_pandas(self) -> Any:
        """DataFrame with a ``time`` column, one column per output and one per input."""
        pd = require_pandas()

        cols = {"time": self.time}
        cols.update({n: row for n, row in zip(self.output_names, self.outputs)})
        cols.update({n: row for n, row in zip(self.input_names, self.inputs)})
        df = pd.DataFrame(cols)
        df.attrs["units"] = {"time": "s", **dict(zip(self.output_names, self.units)),
                             **{n: _input_unit(n) for n in self.input_names}}
        return df

    def plot(self, outputs: Sequence[str] | None = None, by: str = "body", ax: Any = None,
             inputs: bool | None = None) -> Any:
        """Plot outputs against time, peaks marked: :func:`vibss.plotting.plot_time_response`.

        Parameters
        ----------
        outputs : sequence of str or None
            Outputs to draw (default all).
        by : {"body", "all"}
            One axes per body (the name before the first dot) or all in one axes.
        ax : Axes, sequence of Axes or None
            Axes to draw in (one per group); default: a new figure.
        inputs : bool or None
            Draw the inputs on top (default: for prescribed ground motion, in a new figure).

        Returns
        -------
        matplotlib.figure.Figure
        """
        from ..plotting import plot_time_response

        return plot_time_response(self, outputs, by, ax, inputs)


def _negligible(pk: PeakTable, rel: float = 1e-9) -> tuple[str, ...]:
    """:meth:`TimeResponse.negligible` from a peak table already computed."""
    family = [u.replace("rad", "m") for u in pk.units]
    largest: dict[str, float] = {}
    for u, v in zip(family, pk.value):
        largest[u] = max(largest.get(u, 0.0), abs(float(v)))
    return tuple(n for n, u, v in zip(pk.outputs, family, pk.value) if not abs(v) > rel * largest[u])


def _input_unit(name: str) -> str:
    """The SI unit of an input signal from its name: ``.disp|.vel|.acc`` a motion, else a force or
    a moment (:func:`vibss.model.units.input_unit`)."""
    from ..model.units import input_unit

    kind = {"disp": "displacement", "vel": "velocity", "acc": "acceleration"}.get(name.rsplit(".", 1)[-1], "force")
    return input_unit(name, kind)
