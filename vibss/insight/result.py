"""The results of the insight analyses: :class:`EnergyDistribution` (which mount or body holds a
mode's energy), :class:`ModalContributions` (which mode makes a frequency response) and
:class:`PathContributions` (which mount carries the force into a receiver).
:mod:`vibss.insight.api` computes them."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Any, ClassVar

import numpy as np

from ..model.model import Model
from ..results import ZERO_NOTE, Result, TextTable, freeze, jsonable, require_pandas

__all__ = ["EnergyDistribution", "ModalContributions", "PathContributions", "projection_share"]

KIND_TITLES = {"strain": "strain energy", "kinetic": "kinetic energy", "dissipative": "energy dissipated per cycle"}


def projection_share(part: np.ndarray, total: np.ndarray) -> np.ndarray:
    """``Re(part conj(total)) / |total|^2``: the share of ``part`` along the total [-] (parts that
    sum to the total have shares that sum to 1; NaN where the total is 0).

    Examples
    --------
    >>> projection_share(np.array([1 + 1j, 1 - 1j]), np.array(2 + 0j)).tolist()
    [0.5, 0.5]
    """
    t2 = np.abs(total) ** 2
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(t2 > 0, (part * np.conj(total)).real / np.where(t2 > 0, t2, 1.0), np.nan)


@dataclass(frozen=True, eq=False)
class EnergyDistribution(Result):
    """How each mode's energy is shared among the mounts (strain, dissipative) or bodies (kinetic).

    Follows the result protocol (:mod:`vibss.results`): ``r['front']`` is the (k,) share of part
    ``front`` in every mode; ``output_labels`` are the parts (mounts or bodies).

    Attributes
    ----------
    kind : {"strain", "kinetic", "dissipative"}
        Which energy.
    model : Model
        The model analysed.
    frequency_hz : (k,) ndarray
        Natural frequency of each mode [Hz].
    parts : tuple of str
        Mount names (strain, dissipative) or body names (kinetic).
    axes : tuple of str
        The six coordinates of a part: a mount's local axes ``1 2 3 r1 r2 r3`` (deflection along and
        rotation about its principal axes), or a body's DOFs ``x y z rx ry rz``.
    fractions : (k, parts) ndarray
        Share of each part in each mode [-]; rows sum to 1 (NaN rows: rigid-body modes, which store
        no strain energy, and modes that dissipate none).
    by_axis : (k, parts, 6) ndarray
        The same per coordinate of each part [-] (summed over the axes: ``fractions``). A coupled
        6x6 mount shares its coupling energy between the two axes it couples: such a share can be
        negative.
    energy : (k,) ndarray
        The whole of it per unit modal amplitude of the mass-normalised shape [J]: strain
        ``w^2 / 2``; kinetic ``w^2 / 2`` (at the peak velocity); dissipated per cycle
        ``pi phi^T (w C + H) phi``.
    rigid : (k,) bool ndarray
        Rigid-body modes.
    method : str
        How it was computed.
    note : str
        The check and what was left out.
    """

    signal_kind: ClassVar[str] = "part"

    kind: str
    model: Model
    frequency_hz: np.ndarray
    parts: tuple[str, ...]
    axes: tuple[str, ...]
    fractions: np.ndarray
    by_axis: np.ndarray
    energy: np.ndarray
    rigid: np.ndarray
    method: str
    note: str = ""

    @property
    def output_labels(self) -> tuple[str, ...]:
        """The parts: mount names or body names."""
        return self.parts

    @property
    def units(self) -> tuple[str, ...]:
        """Every share is a fraction."""
        return ("-",) * len(self.parts)

    def _item(self, i: int, j: int | None) -> np.ndarray:
        return self.fractions[:, i]

    def __len__(self) -> int:
        return len(self.frequency_hz)

    @cached_property
    def dominant(self) -> tuple[str, ...]:
        """The part holding the largest share of each mode (``"-"`` for a rigid mode)."""
        return tuple("-" if not np.isfinite(row).any() else self.parts[int(np.nanargmax(row))]
                     for row in self.fractions)

    def columns(self, by_axis: bool = False) -> tuple[np.ndarray, list[str]]:
        """The shares as (k, columns) and the column labels: one per part, or per part and coordinate
        (``"front.3"``) leaving out the coordinates no mode loads (the rotations of 3-DOF mounts).

        Parameters
        ----------
        by_axis : bool
            One column per part and coordinate.
        """
        if not by_axis:
            return np.asarray(self.fractions), list(self.parts)
        data = self.by_axis.reshape(len(self), -1)
        cols = [f"{p}.{a}" for p in self.parts for a in self.axes]
        used = np.flatnonzero(np.nan_to_num(np.abs(data)).max(axis=0, initial=0.0) > 0) if len(self) else np.zeros(0, int)
        return data[:, used], [cols[i] for i in used]

    def table(self, by_axis: bool = False) -> TextTable:
        """Shares [%]: one row per mode, one column per part (per part and axis with ``by_axis``).

        Parameters
        ----------
        by_axis : bool
            One column per part and coordinate (those that hold energy in some mode).
        """
        data, cols = self.columns(by_axis)
        rows = [[f"{k + 1}", f"{self.frequency_hz[k]:.3f}", self.dominant[k]]
                + ["-" if not np.isfinite(v) else f"{100 * v:.1f}" for v in data[k]] for k in range(len(self))]
        what = "mount" if self.kind != "kinetic" else "body"
        return TextTable(["mode", "f [Hz]", f"top {what}"] + cols, rows,
                         title=f"Modal {KIND_TITLES[self.kind]} per {what}{' and axis' if by_axis else ''} [%]")

    def summary(self) -> TextTable:
        """The table of shares per part (:meth:`table`)."""
        return self.table()

    def report(self) -> str:
        """Text report: the shares per part and per axis."""
        head = f"Modal {KIND_TITLES[self.kind]} of {self.model.name!r}: {len(self)} modes ({self.method})"
        tail = [self.note] if self.note else []
        return "\n\n".join([head, self.table().render(), self.table(by_axis=True).render()] + tail)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready data: the shares per mode, part and axis."""
        return jsonable({"kind": self.kind, "model": self.model.name, "frequency_hz": self.frequency_hz,
                         "parts": self.parts, "axes": self.axes, "fractions": self.fractions,
                         "by_axis": self.by_axis, "energy": self.energy, "method": self.method, "note": self.note})

    def to_pandas(self, by_axis: bool = False) -> Any:
        """DataFrame: one row per mode (index ``mode`` from 1), ``frequency_hz`` then a column per
        part (per ``(part, axis)`` with ``by_axis``).

        Parameters
        ----------
        by_axis : bool
            Columns per part and coordinate (a two-level column index).
        """
        pd = require_pandas()
        index = pd.RangeIndex(1, len(self) + 1, name="mode")
        if by_axis:
            cols = pd.MultiIndex.from_product([self.parts, self.axes], names=["part", "axis"])
            df = pd.DataFrame(self.by_axis.reshape(len(self), -1), index=index, columns=cols)
        else:
            df = pd.DataFrame(self.fractions, index=index, columns=list(self.parts))
        df.insert(0, ("frequency_hz", "") if by_axis else "frequency_hz", self.frequency_hz)
        df.attrs["units"] = {"frequency_hz": "Hz", "shares": "-"}
        return df

    def plot(self, ax: Any = None, by_axis: bool = False) -> Any:
        """Heat map of the shares: :func:`vibss.plotting.insight.plot_energy_distribution`.

        Parameters
        ----------
        ax : Axes or None
            Axes to draw in; default: a new figure.
        by_axis : bool
            One column per part and coordinate.

        Returns
        -------
        matplotlib.figure.Figure
        """
        from ..plotting.insight import plot_energy_distribution

        return plot_energy_distribution(self, ax=ax, by_axis=by_axis)


@dataclass(frozen=True, eq=False)
class ModalContributions(Result):
    """A frequency response split into the terms of its modes and a residual.

    ``terms.sum(axis=0) + residual`` is the response (:func:`vibss.frequency_response`'s ``h``).
    ``r['b.z', 'b.fz']`` is the (k, nf) terms of one output and input.

    Attributes
    ----------
    frequency : (nf,) ndarray
        Frequencies [Hz].
    terms : (k, p, m, nf) complex ndarray
        Term of each mode (units of the outputs per unit input).
    residual : (p, m, nf) complex ndarray
        Feedthrough plus the modes left out.
    mode_frequency_hz : (k,) ndarray
        Undamped natural frequency of each term's mode [Hz].
    poles : (k, 2) complex ndarray
        The poles each term holds [rad/s] (NaN where fewer).
    output_labels, input_labels : tuple of str
        Signal names.
    units : tuple of str
        Output units.
    method : str
        ``"modal"`` (classical damping: one term per undamped mode) or ``"complex"`` (the complex
        modes, each pole given to the undamped mode that dominates its shape).
    note : str
        The check against the exact solve, the modes left out.
    """

    frequency: np.ndarray
    terms: np.ndarray
    residual: np.ndarray
    mode_frequency_hz: np.ndarray
    poles: np.ndarray
    output_names: tuple[str, ...]
    input_names: tuple[str, ...]
    output_units: tuple[str, ...]
    method: str
    note: str = ""

    @property
    def output_labels(self) -> tuple[str, ...]:
        """Output signal names."""
        return self.output_names

    @property
    def input_labels(self) -> tuple[str, ...]:
        """Input signal names."""
        return self.input_names

    @property
    def units(self) -> tuple[str, ...]:
        """Units of the outputs per unit input."""
        return self.output_units

    def _item(self, i: int, j: int | None) -> np.ndarray:
        return self.terms[:, i, :, :] if j is None else self.terms[:, i, j, :]

    @cached_property
    def total(self) -> np.ndarray:
        """(p, m, nf) the response: the terms plus the residual."""
        return freeze(self.terms.sum(axis=0) + self.residual)

    @cached_property
    def share(self) -> np.ndarray:
        """(k, p, m, nf) each term's share along the response, ``Re(term conj(H)) / |H|^2`` [-]; with
        the residual's they sum to 1 (:func:`projection_share`)."""
        return freeze(projection_share(self.terms, self.total[None]))

    def __len__(self) -> int:
        return self.terms.shape[0]

    def peaks(self, output: int = 0, input: int = 0) -> np.ndarray:
        """Indices of the local maxima of ``|H|`` of one output and input (the largest when none)."""
        mag = np.abs(self.total[output, input])
        inner = np.flatnonzero((mag[1:-1] > mag[:-2]) & (mag[1:-1] >= mag[2:])) + 1
        return inner if inner.size else np.array([int(np.argmax(mag))])

    def dominant(self, top: int = 3) -> TextTable:
        """The ``top`` contributors at each peak of every output and input: their share [%] and
        magnitude relative to the peak.

        Parameters
        ----------
        top : int
            Modes listed per peak.
        """
        rows = []
        for i, out in enumerate(self.output_names):
            for j, inp in enumerate(self.input_names):
                if not np.any(self.total[i, j]):            # no peak to split (a symmetry, or no path)
                    rows.append([out, inp, "", "0", "", "", "", ZERO_NOTE])
                    continue
                for f in self.peaks(i, j):
                    sh = self.share[:, i, j, f]
                    order = np.argsort(-np.nan_to_num(sh, nan=-np.inf))[:top]
                    for rank, k in enumerate(order):
                        head = [out, inp, f"{self.frequency[f]:.3f}", f"{np.abs(self.total[i, j, f]):.4g}"] \
                            if rank == 0 else ["", "", "", ""]
                        rows.append(head + [f"{k + 1}", f"{self.mode_frequency_hz[k]:.3f}", f"{100 * sh[k]:.1f}",
                                            f"{np.abs(self.terms[k, i, j, f]) / np.abs(self.total[i, j, f]):.3f}"])
        return TextTable(["output", "input", "peak [Hz]", "|H|", "mode", "f_mode [Hz]", "share [%]", "|term|/|H|"],
                         rows, title=f"Dominant modes at the response peaks ({self.method})",
                         notes=("share: Re(term conj(H)) / |H|^2; the shares and the residual's sum to 100 %",))

    def summary(self) -> TextTable:
        """The table of dominant modes (:meth:`dominant`)."""
        return self.dominant()

    def report(self) -> str:
        """Text report: the dominant modes at every peak."""
        head = (f"Modal contributions: {len(self)} modes, {len(self.output_names)} outputs x "
                f"{len(self.input_names)} inputs, {self.frequency.size} frequencies ({self.method})")
        return "\n\n".join([head, self.dominant().render()] + ([self.note] if self.note else []))

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready data (complex numbers as ``[re, im]``)."""
        return jsonable({"frequency_hz": self.frequency, "outputs": self.output_names, "inputs": self.input_names,
                         "units": self.output_units, "mode_frequency_hz": self.mode_frequency_hz,
                         "terms": self.terms, "residual": self.residual, "method": self.method, "note": self.note})

    def to_pandas(self) -> Any:
        """Long DataFrame: one row per mode (0 for the residual), output, input and frequency, with
        the term's real and imaginary parts and share."""
        pd = require_pandas()
        k, p, m, nf = self.terms.shape
        full = np.concatenate([self.residual[None], self.terms])
        sh = np.concatenate([projection_share(self.residual, self.total)[None], self.share])
        idx = pd.MultiIndex.from_product([range(k + 1), self.output_names, self.input_names, self.frequency],
                                         names=["mode", "output", "input", "frequency_hz"])
        df = pd.DataFrame({"real": full.real.ravel(), "imag": full.imag.ravel(), "share": sh.ravel()}, index=idx)
        df.attrs["units"] = {"real": "the channel's unit", "imag": "the channel's unit", "share": "-",
                             "by output": dict(zip(self.output_names, self.output_units)),
                             "per unit of": "the input's unit"}
        return df

    def plot(self, ax: Any = None, output: int | str = 0, input: int | str = 0, top: int = 4) -> Any:
        """Magnitudes of the response and its ``top`` terms, and their stacked shares:
        :func:`vibss.plotting.insight.plot_modal_contributions`.

        Parameters
        ----------
        ax : sequence of two Axes or None
            Axes to draw in; default: a new figure.
        output, input : int or str
            The output and input (position or name).
        top : int
            Terms drawn (the largest shares at the peaks); the rest are summed as "other modes".

        Returns
        -------
        matplotlib.figure.Figure
        """
        from ..plotting.insight import plot_modal_contributions

        i = self._position(output, self.output_names, "output")
        j = self._position(input, self.input_names, "input")
        return plot_modal_contributions(self, ax=ax, output=i, input=j, top=top)


@dataclass(frozen=True, eq=False)
class PathContributions(Result):
    """The force each mount passes into a receiver (ground, a support or a body), and its share.

    ``r['fz']`` is the (paths, m, nf) complex z force of every path.

    Attributes
    ----------
    receiver : str
        ``"ground"``, a support or a body.
    frequency : (nf,) ndarray
        Frequencies [Hz].
    paths : tuple of str
        The mounts whose ``to`` side is the receiver.
    components : tuple of str
        ``fx fy fz`` [N] (global axes) and ``mx my mz`` [N m] about the receiver's reference point
        (its COG; the global origin for ground and supports); on a flexible foundation (transfer
        path analysis) the receiver point's motion ``x y z`` [m] (and ``rx ry rz`` [rad]).
    forces : (paths, components, m, nf) complex ndarray
        Force and moment of each path into the receiver per unit input (on a foundation: each
        path's contribution to the receiver's motion).
    input_names : tuple of str
        Input signal names.
    method : str
        The frequency-response method that gave the mount forces.
    note : str
        The check against the receiver's total, what is not a path.
    """

    signal_kind: ClassVar[str] = "component"

    receiver: str
    frequency: np.ndarray
    paths: tuple[str, ...]
    components: tuple[str, ...]
    forces: np.ndarray
    input_names: tuple[str, ...]
    method: str
    note: str = ""
    component_units: tuple[str, ...] = ()

    @property
    def output_labels(self) -> tuple[str, ...]:
        """The components (``fx fy fz mx my mz``)."""
        return self.components

    @property
    def input_labels(self) -> tuple[str, ...]:
        """Input signal names."""
        return self.input_names

    @property
    def units(self) -> tuple[str, ...]:
        """``N`` for forces, ``N m`` for moments (per unit input); ``component_units`` when given."""
        return tuple(self.component_units) or ("N",) * 3 + ("N m",) * 3

    def _item(self, i: int, j: int | None) -> np.ndarray:
        return self.forces[:, i] if j is None else self.forces[:, i, j]

    @cached_property
    def total(self) -> np.ndarray:
        """(6, m, nf) the total force and moment into the receiver: the sum of the paths."""
        return freeze(self.forces.sum(axis=0))

    @cached_property
    def share(self) -> np.ndarray:
        """(paths, 6, m, nf) each path's share along the total, ``Re(f conj(F)) / |F|^2`` [-] (sums to 1)."""
        return freeze(projection_share(self.forces, self.total[None]))

    def _main(self, component: int | str | None, input: int | str) -> tuple[int, int]:
        j = self._position(input, self.input_names, "input")
        if component is None:
            return int(np.argmax(np.abs(self.total[:3, j]).max(axis=1))), j
        return self._position(component, self.components, "component"), j

    def table(self, component: int | str | None = None, input: int | str = 0) -> TextTable:
        """Per path: its largest force over the band, and its share at the total's peak.

        Parameters
        ----------
        component : int, str or None
            ``"fx"`` ... ``"mz"``; default the force component with the largest total.
        input : int or str
            The input.
        """
        c, j = self._main(component, input)
        f = int(np.argmax(np.abs(self.total[c, j])))
        mags = np.abs(self.forces[:, c, j])
        unit = self.units[c]
        rows = [[p, f"{mags[q].max():.4g}", f"{self.frequency[int(np.argmax(mags[q]))]:.3f}",
                 f"{mags[q, f]:.4g}", f"{100 * self.share[q, c, j, f]:.1f}"] for q, p in enumerate(self.paths)]
        rows.append(["total", f"{np.abs(self.total[c, j]).max():.4g}", f"{self.frequency[f]:.3f}",
                     f"{np.abs(self.total[c, j, f]):.4g}", "100.0"])
        return TextTable(["path", f"max |{self.components[c]}| [{unit}]", "at [Hz]", f"at peak [{unit}]",
                          "share at peak [%]"], rows,
                         title=f"Paths into {self.receiver!r}: {self.components[c]} per unit "
                               f"{self.input_names[j]!r}, peak of the total at {self.frequency[f]:.3f} Hz")

    def summary(self) -> TextTable:
        """The table of paths (:meth:`table`)."""
        return self.table()

    def report(self) -> str:
        """Text report: the paths of the largest force component for every input."""
        head = f"Transfer paths into {self.receiver!r}: {len(self.paths)} mounts, {self.frequency.size} frequencies"
        return "\n\n".join([head] + [self.table(None, j).render() for j in range(len(self.input_names))]
                           + ([self.note] if self.note else []))

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready data (complex numbers as ``[re, im]``)."""
        return jsonable({"receiver": self.receiver, "frequency_hz": self.frequency, "paths": self.paths,
                         "components": self.components, "inputs": self.input_names, "forces": self.forces,
                         "method": self.method, "note": self.note})

    def to_pandas(self) -> Any:
        """Long DataFrame: one row per path, component, input and frequency: real, imaginary, share."""
        pd = require_pandas()
        idx = pd.MultiIndex.from_product([self.paths, self.components, self.input_names, self.frequency],
                                         names=["path", "component", "input", "frequency_hz"])
        df = pd.DataFrame({"real": self.forces.real.ravel(), "imag": self.forces.imag.ravel(),
                           "share": self.share.ravel()}, index=idx)
        unit = "/".join(dict.fromkeys(self.units)) if self.component_units else "N (forces) or N m (moments)"
        df.attrs["units"] = {"real": f"{unit} per unit input", "imag": "the same", "share": "-"}
        return df

    def plot(self, ax: Any = None, component: int | str | None = None, input: int | str = 0) -> Any:
        """Each path's force beside the total, and their shares:
        :func:`vibss.plotting.insight.plot_path_contributions`.

        Parameters
        ----------
        ax : sequence of two Axes or None
            Axes to draw in; default: a new figure.
        component : int, str or None
            ``"fx"`` ... ``"mz"``; default the force component with the largest total.
        input : int or str
            The input.

        Returns
        -------
        matplotlib.figure.Figure
        """
        from ..plotting.insight import plot_path_contributions

        c, j = self._main(component, input)
        return plot_path_contributions(self, ax=ax, component=c, input=j)
