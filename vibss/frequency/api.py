"""Frequency response: FRFs of named outputs to named inputs (transmissibility and swept-sine
steady states build on it in :mod:`vibss.frequency.sweep`).

``frequency_response`` evaluates ``Y(i w) / U`` of a :class:`~vibss.linear.plant.plant.Plant` for named inputs and
outputs with a kernel from :data:`vibss.frequency.kernels.METHODS` (``"auto"`` picks one and records why).
Conventions:

- frequencies are given and reported in Hz (``omega`` in rad/s is kept too);
- ``quantity`` multiplies every output by ``(i w)^k``: receptance (k = 0, the outputs as named),
  mobility (k = 1, their time derivative) or accelerance (k = 2);
- a motion input ``u`` of order 1 or 2 (velocity, acceleration) prescribes ``z = u / (i w)^order``;
- hysteretic damping (mount loss factors, ``K + i H``) acts in the frequency domain only;
- at exactly 0 Hz the response is the limit ``w -> 0+``, computed exactly from the Laurent series
  (:func:`vibss.frequency.kernels.zero_frequency_limit`): finite where the limit exists (e.g. the static
  deflection, a velocity ratio, a mass line), ``inf`` where it diverges (displacement under a
  constant velocity or acceleration, receptance of an unrestrained rigid-body motion). Never NaN.

Examples
--------
>>> from vibss import Body, Model, Mount, MountType
>>> m = Model([Body("b", 10.0, [1, 1, 1])], [Mount("m", MountType("t", [1e4] * 3, [20.0] * 3), "b")])
>>> r = frequency_response(m, ["b.fz"], ["b.z"], frequencies=[0.0, 1.0])
>>> print(f"{abs(r.response[0, 0, 0]):.6g} m/N by {r.method}")   # 1 / k at 0 Hz
0.0001 m/N by direct
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import scipy.sparse as sp

from ..linear.plant.assemble import Assembly
from .._validate import choice, integer, name_index, number
from ..errors import AnalysisError, ArgumentError, DefectiveModesError, ModelError
from .kernels import COMPLEX_MODE_RISK, METHODS, complex_mode_risk, zero_frequency_limit
from ..linear.plant.branches import require_none
from ..linear.solve.exact import response
from .methods import choose, choose_without_modes, resolve_method
from ..model.model import Model
from ..linear.plant.plant import Plant
from ..linear.plant.build import build_plant
from ..linear.plant.names import control_name
from ..linear.eigen.directions import dof_labels, energy_fractions
from ..linear.eigen.basis import ModalBasis, modal_basis, projected_damping
from ..results import Result, Table, jsonable, require_pandas

__all__ = ["FrequencyResponse", "FrequencyGrid", "frequency_grid", "frequency_response", "QUANTITIES"]

QUANTITIES = {"receptance": 0, "mobility": 1, "accelerance": 2}
"""Output time-derivative order of each FRF quantity."""

_REFINE = (-4.0, -2.0, -1.0, -0.5, 0.0, 0.5, 1.0, 2.0, 4.0)
_UNDAMPED_ZETA = 1e-4


@dataclass(frozen=True)
class FrequencyGrid:
    """A frequency grid specification.

    Parameters
    ----------
    f1, f2 : float or None
        Band [Hz]; None: from a tenth of the lowest to twice the highest natural frequency.
    points : int
        Number of base points.
    spacing : {"log", "linear"}
        Base spacing. A log grid with ``f1 = 0`` keeps 0 Hz and starts its log part at ``f2 / 1e4``.
    refine : bool
        Add points at each natural frequency ``f_r`` in the band and at ``f_r (1 + k zeta_r)``,
        k = +-0.5, +-1, +-2, +-4 (``zeta_r`` from the modal damping estimate; 1e-4 for undamped
        modes, which then get no point exactly at ``f_r``), so lightly damped peaks are resolved.
    """

    f1: float | None = None
    f2: float | None = None
    points: int = 1000
    spacing: str = "log"
    refine: bool = True

    def _checked(self) -> FrequencyGrid:
        """This grid with its values checked and converted (a ModelError names the bad key)."""
        vals: dict[str, Any] = {}
        for key in ("f1", "f2"):
            v = getattr(self, key)
            vals[key] = v if v is None else number(v, key, who="frequencies", minimum=0.0,
                                                   what="a frequency >= 0 [Hz] or None")
        pts = integer(self.points, "points", who="frequencies", minimum=2)
        choice(self.spacing, "spacing", ("log", "linear"), who="frequencies", expected="'log' or 'linear'")
        return dataclasses.replace(self, f1=vals["f1"], f2=vals["f2"], points=pts,
                                   refine=bool(self.refine))

    @classmethod
    def coerce(cls, spec: Any) -> FrequencyGrid:
        """From a FrequencyGrid, a mapping (keys f1, f2, points, spacing, refine) or None."""
        if spec is None:
            return cls()
        if isinstance(spec, cls):
            return spec._checked()
        if isinstance(spec, Mapping):
            unknown = set(spec) - {"f1", "f2", "points", "spacing", "refine"}
            if unknown:
                raise ModelError(f"frequencies: unknown grid key(s) {sorted(unknown)}; expected "
                                 "f1, f2, points, spacing, refine")
            return cls(**dict(spec))._checked()
        raise ModelError(f"frequencies: expected frequencies in Hz, a grid mapping or None, got {spec!r}")


def frequency_grid(plant: Plant, spec: Any = None, basis: ModalBasis | None = None) -> np.ndarray:
    """Frequencies [Hz] of a grid spec for a plant (sorted, unique, refined at resonances).

    Parameters
    ----------
    plant : Plant
    spec : FrequencyGrid, mapping or None
        See :class:`FrequencyGrid`.
    basis : ModalBasis or None
        Undamped modes, if already computed.

    Returns
    -------
    (nf,) ndarray
        Frequencies [Hz].
    """
    g = FrequencyGrid.coerce(spec)
    basis = basis or modal_basis(plant)
    fr = basis.omega[~basis.rigid] / (2 * np.pi)
    f1 = g.f1 if g.f1 is not None else (0.1 * fr.min() if fr.size else 0.01)
    f2 = g.f2 if g.f2 is not None else (2.0 * fr.max() if fr.size else 100.0)
    if not (np.isfinite(f1) and np.isfinite(f2) and 0 <= f1 < f2) or int(g.points) < 2:
        raise ModelError(f"frequencies: need 0 <= f1 < f2 and points >= 2, got f1={f1}, f2={f2}, "
                         f"points={g.points}")
    if g.spacing == "linear":
        f = np.linspace(f1, f2, int(g.points))
    elif g.spacing == "log":
        lo = f1 if f1 > 0 else f2 * 1e-4
        f = np.geomspace(lo, f2, int(g.points) - (f1 == 0))
        f = np.concatenate([[0.0], f]) if f1 == 0 else f
    else:
        raise ModelError(f"frequencies: spacing must be 'log' or 'linear', got {g.spacing!r}")
    if g.refine and fr.size:
        zeta = _modal_zeta(plant, basis)[~basis.rigid]
        z = np.where(zeta > 0, zeta, _UNDAMPED_ZETA)
        k = np.array(_REFINE)
        extra = fr[:, None] * (1 + k[None, :] * z[:, None])
        extra = np.where((zeta[:, None] == 0) & (k[None, :] == 0), np.nan, extra).ravel()
        extra = extra[np.isfinite(extra) & (extra >= f1) & (extra <= f2)]
        f = np.union1d(f, extra)
    return np.unique(f)


def _modal_zeta(plant: Plant, basis: ModalBasis) -> np.ndarray:
    """Modal damping-ratio estimate per mode: diag(Phi^T C Phi) / 2w + eta / 2."""
    w = np.where(basis.rigid, 1.0, basis.omega)
    gamma, eta = projected_damping(plant, basis)
    return np.abs(np.diag(gamma) / (2 * w) + np.diag(eta) / (2 * w**2))


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
        SI unit of each output row's quantity (``"m"``; ``"m/s"`` for a mobility ...).
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
        for i, y in enumerate(self.outputs):
            for j, u in enumerate(self.inputs):
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

    def summary(self) -> Table:
        """The largest peak of every channel: frequency [Hz], amplitude and unit."""
        rows = []
        for i, y in enumerate(self.outputs):
            for j, u in enumerate(self.inputs):
                pk = self.peaks(y, u, 1)
                f, a = pk[0] if pk else (float("nan"), float("nan"))
                rows.append([y, u, f"{f:.4f}", f"{a:.4e}", self.channel_unit(i, j)])
        return Table(["output", "input", "peak f [Hz]", "amplitude", "unit"], rows,
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


def _index(names: Sequence[str], name: str, what: str) -> int:
    return name_index(name, names, what)


LARGE_DOFS = 3000
"""Above this many DOFs a model asked for explicit frequencies (> 0 Hz) with ``method="auto"`` or
``"sparse"`` stays sparse: no dense n x n matrix and no dense eigen-analysis of all the modes
(O(n^3): 200 s at 6,000 DOF for a 20-frequency FRF before; the grid around the modes, resonance
marks and the modal methods need them, so a grid spec keeps the dense path)."""


def _stays_sparse(system: Any, frequencies: Any, chosen: Any) -> bool:
    """Whether :func:`frequency_response` builds the plant sparse (see :data:`LARGE_DOFS`)."""
    if isinstance(system, Plant) or not isinstance(system, (Model, Assembly)):
        return False
    model = system.model if isinstance(system, Assembly) else system
    if 6 * len(model.bodies) <= LARGE_DOFS or (chosen is not None and not any(
            chosen is METHODS[k] for k in ("sparse", "subspace"))):
        return False
    if any(t.has_branches for t in model.mount_types.values()):
        return False
    if frequencies is None or isinstance(frequencies, (Mapping, FrequencyGrid)):
        return False
    try:
        f = np.atleast_1d(np.asarray(frequencies, dtype=float))
    except (TypeError, ValueError):
        return False
    return bool(f.size) and bool(np.all(np.isfinite(f))) and bool(np.all(f > 0))


def _as_plant(system: Model | Assembly | Plant, inputs: Any, outputs: Any) -> Plant:
    if isinstance(system, Plant):
        if inputs is not None or outputs is not None:
            raise ModelError("inputs/outputs: a Plant already fixes its signals; pass a Model to choose them")
        return system
    if inputs is None:
        raise ModelError("inputs: name at least one input signal, e.g. 'engine.fz' or 'ground.z.acc'")
    return build_plant(system, inputs, outputs)


def _frequencies(plant: Plant, frequencies: Any, basis: ModalBasis | None) -> np.ndarray:
    if frequencies is None or isinstance(frequencies, (Mapping, FrequencyGrid)):
        return frequency_grid(plant, frequencies, basis)
    try:
        f = np.atleast_1d(np.asarray(frequencies, dtype=float))
    except (TypeError, ValueError):
        f = np.array([np.nan])
    # min and max say it all: NaN or inf anywhere makes one of them non-finite
    lo, hi = (float(f.min()), float(f.max())) if f.ndim == 1 and f.size else (0.0, 0.0)
    if f.ndim != 1 or not (np.isfinite(lo) and np.isfinite(hi) and lo >= 0):
        raise ModelError(f"frequencies: expected finite frequencies >= 0 [Hz], got {frequencies!r}")
    if f.size == 0:
        raise ModelError("frequencies: got an empty list; give at least one frequency [Hz], a grid "
                         "mapping {f1, f2, points} or None")
    return f


_NO_MODES = ("no undamped modes computed (the method needs none, and those of the static stiffness are not a "
             "frequency-dependent model's resonances)")


def _modes_if_needed(plant: Plant, frequencies: Any,
                     chosen: Any) -> tuple[ModalBasis | None, np.ndarray, tuple[str, str] | None]:
    """The undamped modes (or None), the frequencies [Hz] and ``auto``'s choice if it needed no modes.

    A dense plant's modes are computed for the default grid, for the resonance marks and for the
    methods that superpose them. A plant with frequency-dependent mounts asked for explicit
    frequencies skips them when a built-in method needs none (given, or chosen from sizes and
    structure by :func:`vibss.frequency.methods.choose_without_modes`; a user's kernel still gets
    them, and so does 0 Hz): its static-stiffness modes do not mark its resonances, and at 600 DOFs
    they cost a tenth of the banded exact solve.
    """
    if plant.branches is None or frequencies is None or isinstance(frequencies, (Mapping, FrequencyGrid)):
        basis = modal_basis(plant)
        return basis, _frequencies(plant, frequencies, basis), None
    f = _frequencies(plant, frequencies, None)
    pick = choose_without_modes(plant, f.size) if chosen is None else None
    method = chosen if pick is None else METHODS[pick[0]]
    builtin = method is not None and METHODS.get(method.name) is method      # a user's method gets the modes
    if not builtin or getattr(method, "needs_basis", True) or not np.all(f > 0):
        return modal_basis(plant), f, pick
    return None, f, pick


def _fresh(raw: Any, chosen: Any, shape: tuple[int, ...]) -> bool:
    """Whether a kernel's answer can be the result's array itself: a built-in kernel's new, writeable
    complex array of the result's shape (a user's kernel may keep its array, so that is copied)."""
    return (chosen is METHODS.get(chosen.name) and isinstance(raw, np.ndarray) and raw.dtype == complex
            and raw.shape == shape and raw.flags.writeable)


def _times_power(raw: np.ndarray, s: np.ndarray, k: int) -> np.ndarray:
    """Mobility / accelerance: ``raw * s^k``, keeping inf as inf."""
    if not k:
        return raw
    with np.errstate(invalid="ignore"):
        scaled = raw * s**k
    scaled[np.isinf(raw)] = np.inf
    return scaled


def _units(plant: Plant, quantity: str) -> tuple[str, ...]:
    """Units of the outputs' quantity: the output unit times ``s^-k`` (mobility k = 1, accelerance 2)."""
    from ..model.units import times_s

    return plant.cached(f"units of the {quantity}",
                        lambda: tuple(times_s(u, QUANTITIES[quantity]) for u in plant.units))


def _input_units(plant: Plant) -> tuple[str, ...]:
    from ..model.units import input_unit

    return plant.cached("input units", lambda: tuple(input_unit(u, k) for u, k in zip(plant.inputs, plant.kinds)))


def _check(plant: Plant, s: np.ndarray, raw: np.ndarray) -> tuple[float, str]:
    """Largest error of ``raw`` against the one exact solve at the frequency of the largest response
    and at both ends of the band (relative to each frequency's response), and where [Hz]."""
    size = np.linalg.norm(raw, axis=(0, 1))
    idx = np.unique([0, int(np.argmax(size)), s.size - 1])
    exact = response(plant, s[idx])
    err = np.linalg.norm(raw[:, :, idx] - exact, axis=(0, 1)) / np.maximum(np.linalg.norm(exact, axis=(0, 1)),
                                                                         np.finfo(float).tiny)
    return float(err.max()), f"{idx.size} check frequencies ({', '.join(f'{abs(x) / (2 * np.pi):.4g}' for x in s[idx])} Hz)"


def _checked(plant: Plant, s: np.ndarray, raw: np.ndarray, name: str) -> str:
    """The note of a method that is neither exact nor built on the certified modal basis
    (``statespace``, a user's kernel): its error against the exact solve (:func:`_check`)."""
    err, where = _check(plant, s, raw)
    return f"{name!r} is not an exact method: relative error {err:.1e} against the exact solve at {where}"


AUTO_CHECK_TOL = 1e-9
"""Where ``auto`` takes complex modes although ``eig``'s a-priori pole bound exceeds
:data:`~vibss.frequency.kernels.COMPLEX_MODE_RISK` (their screen refines the slow poles), it checks the
result against the exact solve (:func:`_check`) and takes the exact fallback above this: the bound
also marks models whose modal sum cancels by many orders in a far channel (a 30-body chain every
mount damped: 5.7e-7 at 100 Hz, the slow poles right)."""


def frequency_response(system: Model | Assembly | Plant, inputs: Sequence[Any] | None = None,
                       outputs: Sequence[str] | None = None, frequencies: Any = None,
                       quantity: str = "receptance",
                       method: str | Callable[..., np.ndarray] = "auto") -> FrequencyResponse:
    """Frequency response functions of named outputs to named inputs.

    Parameters
    ----------
    system : Model, Assembly or Plant
        The system; a Plant fixes the signals itself.
    inputs : sequence of str or Excitation
        Input signals (see :mod:`vibss.signals`).
    outputs : sequence of str or None
        Output signals; default every body DOF's displacement.
    frequencies : (nf,) array_like [Hz], FrequencyGrid, mapping or None
        Explicit frequencies, or a grid spec (default: refined log grid around the modes).
    quantity : {"receptance", "mobility", "accelerance"}
        Multiply the outputs by ``(i w)^0, ^1, ^2``.
    method : {"auto", "direct", "modal", "complex_modal", "woodbury", "sparse", "subspace", "statespace"}, FrequencyMethod or callable
        Method (:data:`vibss.frequency.kernels.METHODS`), or a kernel ``f(plant, s, basis) -> (p, m, nf)``
        with the built-ins' signature (``s`` Laplace points ``i w``, ``basis`` the undamped
        :class:`~vibss.linear.eigen.basis.ModalBasis`, None for a sparse plant; ``f(plant, s)`` is
        accepted too).

    Returns
    -------
    FrequencyResponse

    Raises
    ------
    ArgumentError
        Unknown ``method`` or ``quantity`` (a ModelError, so a ValueError, naming the argument).
    ModelError
        Bad signal names or frequencies.
    AnalysisError
        The method cannot answer (e.g. ``modal`` on non-classical damping).
    """
    choice(quantity, "quantity", QUANTITIES)
    chosen = resolve_method(method)
    large = _stays_sparse(system, frequencies, chosen)
    if large and inputs is not None and not isinstance(system, Plant):
        plant = build_plant(system, inputs, outputs, sparse=True)
    else:
        large = False
        plant = _as_plant(system, inputs, outputs)
    reason, pick = "", None
    large_note = (f"{plant.n} DOFs above {LARGE_DOFS} with explicit frequencies: kept sparse, no dense "
                  "eigen-analysis (resonances not marked)") if large else ""
    if sp.issparse(plant.K):    # no dense eigen-analysis: explicit frequencies > 0, no resonance marks
        basis = None
        if frequencies is None or isinstance(frequencies, (Mapping, FrequencyGrid)):
            raise ModelError("frequencies: a sparse plant (build_plant(..., sparse=True)) needs explicit "
                             "frequencies [Hz]: the default grid is built around the modes")
        f = _frequencies(plant, frequencies, None)
        if np.any(f <= 0):
            raise ModelError("frequencies: a sparse plant takes frequencies > 0 (the 0 Hz limit needs the modes)")
        if chosen is not None and not chosen.sparse_ok:
            raise AnalysisError(f"method {chosen.name!r} needs the dense plant; a sparse plant (build_plant("
                                f"..., sparse=True)) takes {[m for m, v in METHODS.items() if v.sparse_ok]} "
                                "or 'auto'")
    else:
        basis, f, pick = _modes_if_needed(plant, frequencies, chosen)
    if pick is not None:                      # auto chose from sizes and structure, without the modes
        name, reason = pick
        chosen = METHODS[name]
    elif chosen is None:
        name, reason = choose(plant, f.size, basis)
        chosen = METHODS[name]
    elif plant.branches is not None and not chosen.internal_states:
        require_none(plant, f"frequency_response: method {chosen.name!r}",
                     f"use one of {[k for k, v in METHODS.items() if v.internal_states]} or 'auto'")
    elif plant.branches is not None:
        reason = plant.branches.note()
    if basis is None and not large and not sp.issparse(plant.K):
        reason = f"{reason}; resonances not marked: {_NO_MODES}"
    reason = "; ".join(x for x in (large_note, reason) if x)
    k = QUANTITIES[quantity]
    pos = f > 0
    every = bool(pos.all())             # no 0 Hz: the kernel's array is the response, no masked copy
    h = None if every else np.empty((len(plant.outputs), len(plant.inputs), f.size), dtype=complex)
    if every or np.any(pos):
        s = 2j * np.pi * (f if every else f[pos])
        try:
            raw = chosen.kernel(plant, s, basis)
        except DefectiveModesError as exc:
            if method != "auto" or chosen.fallback is None:
                exact = [n for n, m in METHODS.items() if m.exact]
                raise DefectiveModesError(f"frequency_response: method {chosen.name!r} refused: {exc}; use an "
                                          f"exact method: {exact} (or 'auto')", argument="method",
                                          received=chosen.name, expected=exact) from None
            refused, chosen = chosen, METHODS[chosen.fallback]
            what = "complex modes" if refused.name == "complex_modal" else f"method {refused.name!r}"
            reason = f"{reason}; {what} refused ({exc}): {chosen.summary}"
            raw = chosen.kernel(plant, s, basis)
        else:
            if method == "auto" and chosen.fallback is not None and chosen.name == "complex_modal" and basis is not None \
                    and complex_mode_risk(basis, projected_damping(plant, basis)) > COMPLEX_MODE_RISK:
                err, where = _check(plant, s, raw)
                if not err <= AUTO_CHECK_TOL:
                    chosen = METHODS[chosen.fallback]
                    reason = (f"{reason}; complex modes missed the exact solve by {err:.1e} at {where}: "
                              f"{chosen.summary}")
                    raw = chosen.kernel(plant, s, basis)
                else:
                    reason = f"{reason}; checked: {err:.1e} against the exact solve at {where}"
        if chosen.self_checked:             # (response, the note of its own exact checks)
            raw, own = raw
            reason = "; ".join(x for x in (reason, own) if x)
        elif not chosen.exact and not chosen.needs_basis:
            reason = "; ".join(x for x in (reason, _checked(plant, s, raw, chosen.name)) if x)
        shape = (len(plant.outputs), len(plant.inputs), f.size)
        if h is None and _fresh(raw, chosen, shape):
            h = _times_power(raw, s, k)
        else:                           # 0 Hz among them, or a user's kernel: copied in, as complex
            h = np.empty(shape, dtype=complex) if h is None else h
            h[:, :, pos] = _times_power(raw, s, k)
    if not every:
        assert h is not None
        h[:, :, ~pos] = zero_frequency_limit(plant, power=k)[:, :, None]
    assert h is not None
    units = _units(plant, quantity)
    fr, numbers, labels = _resonances(plant, basis, float(f.min()), float(f.max()))
    return FrequencyResponse(f, h, plant.outputs, plant.inputs, units, quantity, chosen.name, reason,
                             fr, plant.name, _input_units(plant), numbers, labels)


def _resonances(plant: Plant, basis: ModalBasis | None, lo: float,
                hi: float) -> tuple[np.ndarray, tuple[int, ...], tuple[str, ...]]:
    """Undamped natural frequencies [Hz] in ``[lo, hi]``, their mode numbers (from 1, rigid modes
    counted, as :func:`vibss.modes`) and labels (``"tank.y"``); no numbers when the plant's DOFs are
    not body DOFs (a modal plant)."""
    if basis is None:
        return np.zeros(0), (), ()
    own = plant._cache.get("modal basis") is basis
    if not own:
        return _band_resonances(plant, basis, lo, hi)
    # the plant's own modes: the last band's answer kept (a loop asks the same band again)
    last: dict[tuple[float, float], Any] = plant.cached("resonances of the last band", dict)
    hit = last.get((lo, hi))
    if hit is None:
        hit = _band_resonances(plant, basis, lo, hi)
        hit[0].flags.writeable = False
        last.clear()
        last[(lo, hi)] = hit
    return hit[0].view(), hit[1], hit[2]    # a view of the kept array: it cannot be made writeable


def _band_resonances(plant: Plant, basis: ModalBasis, lo: float,
                     hi: float) -> tuple[np.ndarray, tuple[int, ...], tuple[str, ...]]:
    fr = basis.omega / (2 * np.pi)
    keep = ~basis.rigid & (fr >= lo) & (fr <= hi)
    if not keep.any():
        return np.zeros(0), (), ()
    phi = basis.phi
    own = plant._cache.get("modal basis") is basis
    if own:                                           # the plant's own modes: labelled once per plant
        every = plant.cached("mode labels", lambda: tuple(dof_labels(energy_fractions(phi, plant.M), plant.dofs)))
        labels = [every[k] for k in np.flatnonzero(keep)]
    else:
        labels = dof_labels(energy_fractions(phi[:, keep], plant.M), plant.dofs)
    if not all(labels):
        return fr[keep], (), ()
    return fr[keep], tuple(int(k) + 1 for k in np.flatnonzero(keep)), tuple(labels)
