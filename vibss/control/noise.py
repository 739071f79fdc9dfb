"""Noise budgets of a closed loop: what each sensor's noise and the ground motion put into the payload.

A sensor's noise ``n`` enters the loop where the controller reads it, ``u = K (y + n)``: the plant is
extended with one input per noisy measurement whose only path is the identity into that
measurement, the loop closed on it (:func:`vibss.control.loop._close`), and the response ``H_ok``
from each source ``k`` (noise inputs and ground or other disturbances) to each output ``o`` evaluated
at the frequencies. The sources are independent, so each contributes ``|H_ok|^2 S_k`` to the
output's PSD and the total is their sum. RMS values integrate the PSDs over the frequencies given
(trapezoids); the cumulative RMS runs from the highest frequency down, as in the kontrol package's
noise budgets.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import ArgumentError
from ..linear.statespace import NamedStateSpace
from ..model.actuation import noise_psd
from ..results import Result, TextTable, jsonable, require_pandas
from .plant import vibss_name

__all__ = ["noise_budget", "NoiseBudget"]


@dataclass(frozen=True, eq=False)
class NoiseBudget(Result):
    """Each source's PSD contribution to each output, their total and RMS values.

    Attributes
    ----------
    outputs : tuple of str
        Output signals (vibss spelling).
    sources : tuple of str
        ``"<measurement>.noise"`` per noisy sensor, then the disturbances given.
    frequency_hz : (nf,) ndarray
        Frequencies [Hz].
    psd : (no, ns, nf) ndarray
        Contribution of each source to each output [unit^2/Hz].
    units : tuple of str
        SI unit of each output.
    source_psd : (ns, nf) ndarray
        Each source's own PSD [its unit^2/Hz].
    """

    outputs: tuple[str, ...]
    sources: tuple[str, ...]
    frequency_hz: np.ndarray
    psd: np.ndarray
    units: tuple[str, ...]
    source_psd: np.ndarray
    method: str = "closed-loop responses"
    note: str = ""

    @property
    def output_labels(self) -> tuple[str, ...]:
        """The outputs."""
        return self.outputs

    @property
    def input_labels(self) -> tuple[str, ...]:
        """The sources."""
        return self.sources

    def _item(self, i: int, j: int | None) -> np.ndarray:
        return self.psd[i] if j is None else self.psd[i, j]

    @property
    def total(self) -> np.ndarray:
        """(no, nf) total PSD of each output (the sum over the independent sources) [unit^2/Hz]."""
        return self.psd.sum(axis=1)

    @property
    def rms(self) -> np.ndarray:
        """(no, ns) RMS of each output due to each source over the band [unit]."""
        return np.sqrt(np.trapezoid(self.psd, self.frequency_hz, axis=-1))

    @property
    def rms_total(self) -> np.ndarray:
        """(no,) RMS of each output, all sources [unit]."""
        return np.sqrt(np.trapezoid(self.total, self.frequency_hz, axis=-1))

    @property
    def cumulative_rms(self) -> np.ndarray:
        """(no, nf) RMS integrated from each frequency up to the highest [unit]."""
        s, f = self.total, self.frequency_hz
        seg = 0.5 * (s[:, 1:] + s[:, :-1]) * np.diff(f)
        tail = np.concatenate([np.cumsum(seg[:, ::-1], axis=1)[:, ::-1], np.zeros((s.shape[0], 1))], axis=1)
        return np.sqrt(tail)

    def summary(self) -> TextTable:
        """RMS per output and source, and each source's share of the mean square."""
        rows = []
        for o, out in enumerate(self.outputs):
            tot = self.rms_total[o]
            for k, src in enumerate(self.sources):
                share = (self.rms[o, k] / tot) ** 2 if tot > 0 else 0.0
                rows.append([out, src, f"{self.rms[o, k]:.4g} {self.units[o]}", f"{100 * share:.1f}"])
            rows.append([out, "total", f"{tot:.4g} {self.units[o]}", "100.0"])
        f = self.frequency_hz
        return TextTable(["output", "source", "RMS", "share of mean square [%]"], rows,
                         title=f"noise budget, {f[0]:.3g}-{f[-1]:.3g} Hz")

    def report(self) -> str:
        """The RMS table and the conventions."""
        return "\n\n".join([self.summary().render(), self.note])

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready RMS values per output and source."""
        return jsonable({"outputs": list(self.outputs), "sources": list(self.sources), "units": list(self.units),
                         "rms": self.rms, "rms_total": self.rms_total,
                         "band_hz": [float(self.frequency_hz[0]), float(self.frequency_hz[-1])], "note": self.note})

    def to_pandas(self) -> Any:
        """DataFrame: one column per (output, source) PSD, indexed by frequency [Hz]."""
        pd = require_pandas()
        data = {f"{o} <- {s}": self.psd[i, k] for i, o in enumerate(self.outputs) for k, s in enumerate(self.sources)}
        return pd.DataFrame(data, index=pd.Index(self.frequency_hz, name="frequency_hz"))

    def plot(self, ax: Any = None, output: str | None = None) -> Any:
        """Stacked ASDs per source with the total and the cumulative RMS
        (:func:`vibss.plotting.robust.plot_noise_budget`).

        Parameters
        ----------
        ax : Axes or None
        output : str or None
            The output drawn (default the first).
        """
        from ..plotting.robust import plot_noise_budget

        return plot_noise_budget(self, ax=ax, output=output)


def _psd_spec(value: Any, what: str) -> Any:
    from ..model.actuation import _noise

    try:
        return _noise(value, what)
    except Exception as exc:               # the sensor's message, named after this argument
        raise ArgumentError(str(exc), argument=what, received=value) from None


def noise_budget(closed: Any, outputs: Sequence[str], frequencies: Any, *, ground: Any = None,
                 disturbances: Mapping[str, Any] | None = None, noise: Mapping[str, Any] | None = None) -> NoiseBudget:
    """Each noise source's PSD contribution to the outputs of a closed loop, beside the ground's.

    Parameters
    ----------
    closed : ClosedLoop
        From :func:`vibss.control.close`.
    outputs : sequence of str
        Output signals of the closed loop (payload motion, commands).
    frequencies : (nf,) array_like
        Frequencies [Hz], increasing (the RMS integrates over them).
    ground : PSD spec or None
        The PSD of the plant's single ground-motion disturbance [its unit^2/Hz] (a constant, a function
        of frequency [Hz] or a (frequency_hz, level) table; as :class:`~vibss.model.actuation.Sensor`'s
        ``noise``).
    disturbances : mapping or None
        ``{disturbance: PSD spec}`` for several disturbances (instead of ``ground``).
    noise : mapping or None
        ``{measurement: PSD spec}``: noise of measurements, overriding their sensors' ``noise``.

    Returns
    -------
    NoiseBudget
    """
    from ..frequency.statespace_response import Evaluator
    from .loop import _close, interconnect_indices

    plant, K = closed.plant, closed.controller
    f = np.asarray(frequencies, dtype=float).ravel()
    if f.size < 2 or not np.all(np.isfinite(f)) or np.any(f < 0) or np.any(np.diff(f) <= 0):
        raise ArgumentError("noise_budget: frequencies: expected at least 2 increasing frequencies >= 0 [Hz]",
                            argument="frequencies", received=frequencies)
    meas = [vibss_name(s) for s in K.input_labels]
    sensors = {s.signal: s for s in getattr(getattr(plant, "model", None), "sensors", ())}
    given = {vibss_name(str(k)): v for k, v in (noise or {}).items()}
    unknown = sorted(set(given) - set(meas))
    if unknown:
        raise ArgumentError(f"noise_budget: noise: {unknown} are not measurements of the loop; they are {meas}",
                            argument="noise", received=unknown, expected=meas)
    sources: dict[str, Any] = {}
    for y in meas:
        spec = _psd_spec(given[y], f"noise[{y!r}]") if y in given else getattr(sensors.get(y), "noise", None)
        if spec is not None:
            sources[y] = spec
    dist = _disturbances(plant, ground, disturbances)
    if not sources and not dist:
        raise ArgumentError("noise_budget: no source: give sensors a noise PSD (Sensor(..., noise=...)), or "
                            "noise={measurement: PSD}, or ground=PSD", argument="noise")
    A, B, C, D = (np.asarray(x, dtype=float) for x in (plant.A, plant.B, plant.C, plant.D))
    iy = interconnect_indices(plant.output_labels, [*sources], "noise (measurements)")
    Bn = np.zeros((A.shape[0], len(iy)))
    Dn = np.zeros((C.shape[0], len(iy)))
    Dn[iy, np.arange(len(iy))] = 1.0
    labels = [f"{plant.output_labels[i]}:noise" for i in iy]
    aug = NamedStateSpace(A, np.hstack([B, Bn]), C, np.hstack([D, Dn]),
                          inputs=[*plant.input_labels, *labels], outputs=list(plant.output_labels),
                          states=list(plant.state_labels), name=f"{plant.name}:noisy")
    Acl, Bcl, Ccl, Dcl, ext, _, _ = _close(aug, K)
    ins = [aug.input_labels[i] for i in ext]
    outs = list(plant.output_labels) + list(K.output_labels)
    io = interconnect_indices(outs, list(outputs), "outputs")
    src_names = [f"{y}.noise" for y in sources] + list(dist)
    cols = [ins.index(lab) for lab in labels] + interconnect_indices(ins, list(dist), "disturbances")
    import control

    h = Evaluator(control.ss(Acl, Bcl, Ccl, Dcl), outputs=io, inputs=cols)(2 * np.pi * f)
    spsd = np.array([noise_psd(s, f) for s in [*sources.values(), *dist.values()]])
    psd = np.abs(h) ** 2 * spsd[None]
    units_map = dict(getattr(plant, "units", {}) or {})
    units = tuple(units_map.get(vibss_name(outs[i]), "-") for i in io)
    return NoiseBudget(outputs=tuple(vibss_name(outs[i]) for i in io), sources=tuple(src_names), frequency_hz=f,
                       psd=psd, units=units, source_psd=spsd,
                       note="independent sources: each contributes |H|^2 S to the output PSD; noise enters "
                            "where the controller reads the measurement (u = K (y + n)); RMS by trapezoids "
                            "over the frequencies given, cumulative from the highest frequency down")


def _disturbances(plant: Any, ground: Any, disturbances: Mapping[str, Any] | None) -> dict[str, Any]:
    """``{disturbance: PSD spec}`` from ``ground`` or ``disturbances``."""
    if ground is not None and disturbances:
        raise ArgumentError("noise_budget: give ground or disturbances, not both", argument="ground")
    if disturbances:
        return {vibss_name(str(k)): _psd_spec(v, f"disturbances[{k!r}]") for k, v in disturbances.items()}
    if ground is None:
        return {}
    w = [vibss_name(s) for s in getattr(plant, "groups", {}).get("w", [])]
    g = [s for s in w if s.split(".")[0] == "ground"]
    if len(g) != 1:
        raise ArgumentError(f"noise_budget: ground: the plant has {len(g)} ground-motion disturbances {g}; "
                            "name them with disturbances={signal: PSD}", argument="ground", received=g)
    return {g[0]: _psd_spec(ground, "ground")}
