"""The result of a frequency response: :class:`FrequencyResponse` (complex amplitudes per output,
input and frequency, with the result protocol of :mod:`vibss.results`)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .._validate import name_index
from ..errors import ArgumentError, ModelError
from ..linear.plant.labels import control_name
from ..results import ZERO_NOTE, Result, TextTable, jsonable, require_pandas

__all__ = ["FrequencyResponse", "ZERO_RTOL", "MEASURED_NOTE"]

ZERO_RTOL = 1e-13
"""A channel at most this fraction of the largest channel of its unit is identically zero (the
round-off of an exact zero: a few ``eps`` of the solution's scale)."""


@dataclass(frozen=True, eq=False)
class FrequencyResponse(Result):
    """A frequency response: complex amplitudes per output, input and frequency.

    Follows the result protocol (:mod:`vibss.results`): ``r['b.z']`` is the (m, nf) response of
    one output, ``r['b.z', 'b.fz']`` the (nf,) response of one channel; ``r.control`` is the
    python-control ``FrequencyResponseData``.

    Attributes
    ----------
    frequency_hz : (nf,) ndarray
        Frequencies [Hz].
    response : (p, m, nf) complex ndarray
        Output amplitude per unit input amplitude (or, for a sweep, per the excitations), in the
        outputs' units times ``s^k`` for mobility/accelerance, per unit of the input. ``inf`` at
        0 Hz where the response diverges.
    outputs, inputs : tuple of str
        Signal names (vibss spelling, with dots).
    units : tuple of str
        SI unit of each output row's quantity (``"m"``; ``"m/s"`` for a mobility ...), one per
        output as every result's ``units``; the unit of each channel's values (``"m/N"``) is
        :attr:`channel_units`.
    quantity : str
        ``"receptance"``, ``"mobility"``, ``"accelerance"``, ``"transmissibility"`` or ``"sweep"``.
    method : str
        Kernel that computed it.
    note : str
        Why that kernel (for ``method="auto"``); ``reason`` is the old name.
    natural_hz : (k,) ndarray
        Undamped natural frequencies in the band [Hz] (resonance markers).
    name : str
        System name.
    input_units : tuple of str
        SI unit of each input (``"N"``, ``"m/s^2"`` ...); empty for a sweep (its amplitudes are
        already in the outputs' units). :meth:`channel_unit` combines the two.
    mode_numbers : tuple of int
        Number of the mode at each of ``natural_hz``, counted from 1 over all modes (rigid ones
        included) as in :func:`vibss.modes`; empty when unknown (a reduced or sparse plant).
    mode_labels : tuple of str
        Label of each of those modes as :attr:`vibss.modal.Modes.labels` (``"tank.y"`` on
        multi-body models, ``"y"`` on one body); the plots number the resonances with them.
    """

    frequency_hz: np.ndarray
    response: np.ndarray
    outputs: tuple[str, ...]
    inputs: tuple[str, ...]
    units: tuple[str, ...]
    quantity: str
    method: str
    note: str = ""
    natural_hz: np.ndarray = field(default_factory=lambda: np.zeros(0))
    name: str = "vibss"
    input_units: tuple[str, ...] = ()
    mode_numbers: tuple[int, ...] = ()
    mode_labels: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        for key in ("frequency_hz", "response", "natural_hz"):
            object.__setattr__(self, key, np.asarray(getattr(self, key)))
        object.__setattr__(self, "mode_numbers", tuple(map(int, self.mode_numbers)))
        object.__setattr__(self, "mode_labels", tuple(map(str, self.mode_labels)))
        if self.mode_numbers and len(self.mode_numbers) != len(self.natural_hz):
            raise ModelError(f"mode_numbers: {len(self.mode_numbers)} numbers for {len(self.natural_hz)} "
                             "natural frequencies; give one per frequency or none")
        if self.mode_labels and len(self.mode_labels) != len(self.mode_numbers):
            raise ModelError(f"mode_labels: {len(self.mode_labels)} labels for {len(self.mode_numbers)} "
                             "mode numbers; give one per mode or none")
        super().__post_init__()

    @classmethod
    def from_measurement(cls, frequencies: Any, response: Any, inputs: Sequence[str] | None = None,
                         outputs: Sequence[str] | None = None, units: str | Sequence[str] = "-", *,
                         input_units: Sequence[str] = (), quantity: str = "frf", name: str = "measured",
                         source: str = "") -> FrequencyResponse:
        """A measured frequency response: data with no model behind it (``method = "measured"``).

        What :func:`vibss.io.read_uff` and :func:`vibss.io.read_csv` return; compare it with a
        computed one by :func:`vibss.frequency.compare.frac` or overlay it on a Bode plot.

        Parameters
        ----------
        frequencies : (nf,) array_like
            Frequencies [Hz], finite, >= 0, strictly increasing.
        response : (nf,), (p, nf) or (p, m, nf) array_like
            Complex amplitudes, finite (one channel; p outputs of one input; p outputs by m inputs).
        inputs, outputs : sequence of str or None
            Signal names, one per input and per output (default ``u1 ...``, ``y1 ...``), distinct.
        units : str or sequence of str
            Unit of each output (one for all, or one per output); with ``input_units`` empty,
            the unit of its channels' values (``"m/N"``).
        input_units : sequence of str
            Unit of each input (``"N"``), or empty.
        quantity : str
            What the response is (``"frf"``, ``"receptance"``, ``"mobility"``, ``"accelerance"``,
            ``"transmissibility"``).
        name : str
            Name of the measurement.
        source : str
            Where it came from (a file name), added to the note.

        Returns
        -------
        FrequencyResponse
            ``note`` begins ``"measured: no model behind it"``; no natural frequencies.

        Raises
        ------
        ArgumentError
            A field of the wrong shape, not finite, frequencies not increasing, names that do not
            match the response (the message names the field).

        Examples
        --------
        >>> r = FrequencyResponse.from_measurement([10.0, 20.0], [1e-3, 2e-3j], ["hammer.fz"],
        ...                                        ["table.z"], "m/N")
        >>> r.method, r.note, r.response.shape
        ('measured', 'measured: no model behind it', (1, 1, 2))
        """
        return cls(**_measured_fields(frequencies, response, inputs, outputs, units, input_units, quantity,
                                      name, source))

    @property
    def output_labels(self) -> tuple[str, ...]:
        """Output signal names (python-control's name; ``outputs`` is the same)."""
        return self.outputs

    @property
    def input_labels(self) -> tuple[str, ...]:
        """Input signal names (python-control's name; ``inputs`` is the same)."""
        return self.inputs

    @property
    def reason(self) -> str:
        """Old name of :attr:`note`."""
        return self.note

    def _item(self, i: int, j: int | None) -> np.ndarray:
        return self.response[i] if j is None else self.response[i, j]

    @property
    def omega(self) -> np.ndarray:
        """(nf,) frequencies [rad/s]."""
        return 2 * np.pi * self.frequency_hz

    @property
    def magnitude(self) -> np.ndarray:
        """(p, m, nf) amplitude |H|."""
        return np.abs(self.response)

    @property
    def channel_units(self) -> tuple[tuple[str, ...], ...]:
        """(p, m) unit of each channel's values: output per input (``"m/N"``, ``"-"`` for a
        transmissibility between equal units; the output's for a sweep)."""
        return tuple(tuple(self.channel_unit(i, j) for j in range(len(self.inputs))) for i in range(len(self.outputs)))

    @property
    def zero_channels(self) -> np.ndarray:
        """(p, m) bool: channels identically zero over the band (symmetry, or no path from the input
        to the output): every value exactly 0, or at most :data:`ZERO_RTOL` of the largest channel
        of the same unit (the round-off of a solve whose exact answer is 0)."""
        mag = np.where(np.isfinite(self.response), np.abs(self.response), np.inf)
        p, m = len(self.outputs), len(self.inputs)
        top = mag.max(axis=2) if mag.size else np.zeros((p, m))
        units = [[self.channel_unit(i, j) for j in range(m)] for i in range(p)]
        zero = top == 0
        for u in {x for row in units for x in row}:
            same = np.array([[x == u for x in row] for row in units], dtype=bool).reshape(top.shape)
            ref = float(top[same].max()) if same.any() else 0.0
            if np.isfinite(ref) and ref > 0:
                zero |= same & (top <= ZERO_RTOL * ref)
        return zero

    @property
    def phase(self) -> np.ndarray:
        """(p, m, nf) phase [rad], in (-pi, pi] (python-control's ``phase``)."""
        return np.angle(np.where(np.isfinite(self.response), self.response, 1.0))

    @property
    def phase_deg(self) -> np.ndarray:
        """(p, m, nf) phase [deg], in (-180, 180]."""
        return np.degrees(np.angle(np.where(np.isfinite(self.response), self.response, 1.0)))

    @property
    def control(self) -> Any:
        """The response as a python-control FrequencyResponseData (finite frequencies only, rad/s)."""
        import control

        keep = np.all(np.isfinite(self.response), axis=(0, 1))
        return control.frd(self.response[:, :, keep], self.omega[keep],
                           inputs=[control_name(u) for u in self.inputs],
                           outputs=[control_name(y) for y in self.outputs],
                           name=control_name(self.name))

    frd = control
    """Old name of :attr:`control`."""

    def channel_unit(self, output: str | int, input: str | int | None = None) -> str:
        """Unit of one channel: output per input (``m/N``, ``(m/s^2)/(m/s^2)``, ``N/(N m)``); ``-`` for
        a transmissibility between equal units; the output's unit for a sweep.

        Parameters
        ----------
        output, input : str or int
            Signal names or positions (input: default the only one).
        """
        from ..model.units import ratio_unit

        i = output if isinstance(output, int) else _index(self.outputs, output, "output")
        if not self.input_units:
            return self.units[i]
        j = (0 if input is None else input) if not isinstance(input, str) else _index(self.inputs, input, "input")
        num, den = self.units[i], self.input_units[j]
        if self.quantity == "transmissibility" and num == den:
            return "-"
        return ratio_unit(num, den)

    def channel(self, output: str, input: str | None = None) -> np.ndarray:
        """(nf,) complex response of one output to one input (default: the only input)."""
        i = _index(self.outputs, output, "output")
        if input is None and len(self.inputs) != 1:
            raise ArgumentError(f"input: the response has {len(self.inputs)} inputs {list(self.inputs)}; name one",
                                argument="input", received=None, expected=self.inputs)
        j = 0 if input is None else _index(self.inputs, input, "input")
        return self.response[i, j]

    def peaks(self, output: str, input: str | None = None, count: int = 3) -> list[tuple[float, float]]:
        """The ``count`` largest local maxima ``(frequency [Hz], amplitude)`` of one channel.

        Only finite points are listed. A non-finite point (``inf`` at 0 Hz, or exactly on an
        undamped resonance) counts as larger than anything when its neighbours are tested, so a
        finite point beside it is never a peak; it is not listed itself (``inf`` has no
        frequency-resolved peak to report; :meth:`channel` shows it).
        """
        a = np.abs(self.channel(output, input))
        finite = np.isfinite(a)
        if a.size < 3:
            if not finite.any():
                return []
            i = int(np.argmax(np.where(finite, a, -1.0)))
            return [(float(self.frequency_hz[i]), float(a[i]))]
        a = np.where(finite, a, np.inf)
        inner = np.flatnonzero((a[1:-1] >= a[:-2]) & (a[1:-1] > a[2:]) & finite[1:-1]) + 1
        idx = [int(i) for i in inner[np.argsort(a[inner])[::-1]][:count]]
        return [(float(self.frequency_hz[i]), float(a[i])) for i in idx]

    def to_dict(self, input: str | None = None) -> dict[str, Any]:
        """JSON-ready dict (spec format): ``{"frequency_hz", "outputs": {name: {"amplitude",
        "phase_deg"}}}`` for one input (the only one, or ``input``). With several inputs and no
        ``input``, the spec's top-level ``"outputs"`` holds every channel as ``"<output>/<input>"``
        and ``"inputs": {input: {"outputs": ...}}`` the same grouped by input. ``inf`` -> null.

        Parameters
        ----------
        input : str or None
            Only this input's channels, keyed by output name.
        """
        def outs(j: int) -> dict[str, Any]:
            amp, ph = self.magnitude[:, j], self.phase_deg[:, j]
            return {y: {"amplitude": amp[i], "phase_deg": ph[i], "unit": self.channel_unit(i, j)}
                    for i, y in enumerate(self.outputs)}
        head = {"frequency_hz": self.frequency_hz, "quantity": self.quantity,
                "method": self.method, "note": self.note}
        if input is not None or len(self.inputs) == 1:
            j = 0 if input is None else _index(self.inputs, input, "input")
            return jsonable({**head, "input": self.inputs[j], "outputs": outs(j)})
        grouped = {u: outs(j) for j, u in enumerate(self.inputs)}
        flat = {f"{y}/{u}": v for u, o in grouped.items() for y, v in o.items()}
        return jsonable({**head, "outputs": flat, "inputs": {u: {"outputs": o} for u, o in grouped.items()}})

    def to_pandas(self) -> Any:
        """DataFrame indexed by frequency [Hz], one complex column ``'<output>/<input>'`` per channel."""
        pd = require_pandas()

        cols = {f"{y}/{u}": self.response[i, j] for i, y in enumerate(self.outputs)
                for j, u in enumerate(self.inputs)}
        df = pd.DataFrame(cols, index=pd.Index(self.frequency_hz, name="frequency_hz"))
        df.attrs["units"] = {f"{y}/{u}": self.channel_unit(i, j) for i, y in enumerate(self.outputs)
                             for j, u in enumerate(self.inputs)}
        df.attrs["quantity"] = self.quantity
        return df

    def report(self, count: int = 3) -> str:
        """Text table: the largest peaks of every channel, with their frequencies."""
        lines = [f"Frequency response of {self.name!r}: {self.quantity}, method {self.method!r}"
                 + (f" ({self.note})" if self.note else ""),
                 f"{self.frequency_hz.size} frequencies, {self.frequency_hz.min():.4g} to "
                 f"{self.frequency_hz.max():.4g} Hz",
                 f"{'output':<28} {'input':<22} {'peak f [Hz]':>12} {'amplitude':>12}  unit"]
        zero = self.zero_channels
        for i, y in enumerate(self.outputs):
            for j, u in enumerate(self.inputs):
                if zero[i, j]:
                    lines.append(f"{y:<28} {u:<22} {'-':>12} {0.0:>12.4e}  {self.channel_unit(i, j)}  ({ZERO_NOTE})")
                    continue
                rows = [(f, f"{a:>12.4e}") for f, a in self.peaks(y, u, count)]
                bad = np.flatnonzero(~np.isfinite(self.response[i, j]))
                if bad.size:        # not a peak: say where the response is unbounded instead
                    rows.append((float(self.frequency_hz[bad[0]]), f"{'infinite':>12}"))
                if not rows:        # no resonance in the band: the largest value, marked as such
                    mag = np.where(np.isfinite(self.magnitude[i, j]), self.magnitude[i, j], -np.inf)
                    top = int(np.argmax(mag))
                    rows = [(float(self.frequency_hz[top]), f"{self.magnitude[i, j, top]:>12.4e}")]
                    edge = "  (largest in the band, no peak inside it)"
                else:
                    edge = ""
                for k, (f, a) in enumerate(rows):
                    lines.append(f"{y if k == 0 else '':<28} {u if k == 0 else '':<22} "
                                 f"{f:>12.4f} {a}  {self.channel_unit(i, j)}" + (edge if k == 0 else ""))
        return "\n".join(lines)

    def summary(self) -> TextTable:
        """The largest peak of every channel: frequency [Hz], amplitude and unit."""
        rows = []
        zero = self.zero_channels
        for i, y in enumerate(self.outputs):
            for j, u in enumerate(self.inputs):
                if zero[i, j]:
                    rows.append([y, u, "-", ZERO_NOTE, self.channel_unit(i, j)])
                    continue
                pk = self.peaks(y, u, 1)
                f, a = pk[0] if pk else (float("nan"), float("nan"))
                rows.append([y, u, f"{f:.4f}", f"{a:.4e}", self.channel_unit(i, j)])
        return TextTable(["output", "input", "peak f [Hz]", "amplitude", "unit"], rows,
                     title=f"{self.quantity}, method {self.method}")

    def plot(self, outputs: Sequence[str] | None = None, inputs: Sequence[str] | None = None,
             max_channels: int = 12, mark_resonances: bool = True, ax: Any = None,
             by: str = "all") -> Any:
        """Bode plot of selected channels: :func:`vibss.plotting.plot_frequency_response`.

        Parameters
        ----------
        outputs, inputs : sequence of str or None
            Channels to draw; default: all, but at most ``max_channels`` (the largest peaks).
        max_channels : int
            Limit on the default selection.
        mark_resonances : bool
            Dotted vertical lines at the undamped natural frequencies.
        ax : (2,) sequence of matplotlib Axes or None
            Magnitude and phase axes to draw in (``by="all"`` only).
        by : {"all", "body"}
            All channels on one pair of axes, or one column per body.

        Returns
        -------
        matplotlib.figure.Figure
        """
        from ..plotting import plot_frequency_response

        return plot_frequency_response(self, outputs, inputs, max_channels, mark_resonances, ax, by)


MEASURED_NOTE = "measured: no model behind it"
"""The note of every measured response (:meth:`FrequencyResponse.from_measurement`)."""


def _names(value: Sequence[str] | None, n: int, field: str, stem: str) -> tuple[str, ...]:
    who = "FrequencyResponse.from_measurement"
    if value is None:
        return tuple(f"{stem}{k + 1}" for k in range(n))
    if isinstance(value, str) or not all(isinstance(v, str) and v for v in value):
        raise ArgumentError(f"{who}: {field}: expected a list of non-empty names, got {value!r}",
                            argument=field, received=value, expected=f"{n} names")
    names = tuple(value)
    if len(names) != n:
        raise ArgumentError(f"{who}: {field}: {len(names)} names {list(names)} for {n} {field} of the response",
                            argument=field, received=value, expected=f"{n} names")
    if len(set(names)) != n:
        raise ArgumentError(f"{who}: {field}: a name appears twice in {list(names)}", argument=field,
                            received=value, expected="distinct names")
    return names


def _measured_fields(frequencies: Any, response: Any, inputs: Sequence[str] | None,
                     outputs: Sequence[str] | None, units: str | Sequence[str], input_units: Sequence[str],
                     quantity: str, name: str, source: str) -> dict[str, Any]:
    """The checked fields of a measured :class:`FrequencyResponse` (errors name the argument)."""
    from .._validate import array

    who = "FrequencyResponse.from_measurement"
    f = array(frequencies, "frequencies", (None,), who=who, unit="Hz")
    if f.size == 0 or np.any(f < 0) or np.any(np.diff(f) <= 0):
        raise ArgumentError(f"{who}: frequencies: expected strictly increasing frequencies >= 0 [Hz], "
                            f"got {f.tolist()}", argument="frequencies", received=frequencies,
                            expected="increasing, >= 0")
    try:
        h = np.array(response, dtype=complex)
    except (TypeError, ValueError):
        raise ArgumentError(f"{who}: response: expected complex numbers, got {response!r}", argument="response",
                            received=response) from None
    h = h.reshape((1, 1) + h.shape) if h.ndim == 1 else h[:, None] if h.ndim == 2 else h
    if h.ndim != 3 or h.shape[2] != f.size:
        raise ArgumentError(f"{who}: response: expected shape (nf,), (p, nf) or (p, m, nf) with nf = {f.size} "
                            f"frequencies, got shape {np.shape(response)}", argument="response",
                            received=np.shape(response), expected=f"last axis {f.size}")
    if not np.all(np.isfinite(h)):
        bad = np.argwhere(~np.isfinite(h))[0]
        raise ArgumentError(f"{who}: response: not finite at output {bad[0]}, input {bad[1]}, "
                            f"{f[bad[2]]:g} Hz", argument="response", received=h[tuple(bad)], expected="finite")
    outs = _names(outputs, h.shape[0], "outputs", "y")
    ins = _names(inputs, h.shape[1], "inputs", "u")
    unit = (units,) * len(outs) if isinstance(units, str) else tuple(units)
    if len(unit) != len(outs) or not all(isinstance(u, str) for u in unit):
        raise ArgumentError(f"{who}: units: expected one unit or {len(outs)} (one per output), got {units!r}",
                            argument="units", received=units, expected=f"{len(outs)} units")
    iu = tuple(input_units)
    if iu and (len(iu) != len(ins) or not all(isinstance(u, str) for u in iu)):
        raise ArgumentError(f"{who}: input_units: expected {len(ins)} units (one per input) or none, "
                            f"got {input_units!r}", argument="input_units", received=input_units)
    return dict(frequency_hz=f, response=h, outputs=outs, inputs=ins, units=unit, quantity=str(quantity),
                method="measured", note=MEASURED_NOTE + (f"; read from {source}" if source else ""),
                natural_hz=np.zeros(0), name=str(name), input_units=iu)


def _index(names: Sequence[str], name: str, what: str) -> int:
    return name_index(name, names, what)
