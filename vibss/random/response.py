"""Response to stationary random excitation: output PSDs and RMS values from input PSDs and the exact
frequency response.

For inputs ``u`` with one-sided cross-spectral matrix ``S_uu(f)`` the outputs have
``S_yy(f) = H(f) S_uu(f) H(f)^H`` and mean squares ``int S_yy df``. ``H`` is the one exact FRF
(:func:`vibss.frequency_response`); the integral is adaptive in ``ln f`` (Simpson against trapezoid
on every interval, bisected until each is below ``rtol`` of the total), with the PSD breakpoints
and the natural frequencies in the band on the grid, so sharp resonances are resolved whatever the
damping. Inputs are uncorrelated unless ``correlation`` couples them
(``S_ab = rho_ab sqrt(S_aa S_bb)``, ``rho`` complex with ``|rho| <= 1``).

Miles's single-mode estimate ``sqrt(pi/2 f_n Q W(f_n))`` is shown beside the exact RMS for
acceleration outputs under one acceleration input, with ``f_n`` the output PSD's peak and ``Q``
the transmissibility there.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from .. import _validate as v
from ..errors import AnalysisError, ArgumentError
from ..results import Result, Table, jsonable, require_pandas
from .psd import G, PSD, as_psd

__all__ = ["RandomResponse", "random_response"]


def _kind(signal: str) -> str:
    return {"acc": "acceleration", "vel": "velocity", "disp": "displacement"}.get(signal.rsplit(".", 1)[-1], "force")


@dataclass(frozen=True)
class RandomResponse(Result):
    """Output PSDs and RMS values under random excitation.

    ``r['engine.z.acc']`` is the (nf,) output PSD of one output.

    Attributes
    ----------
    frequency_hz : (nf,) ndarray
        The integration grid [Hz] (adaptive: dense at resonances).
    psd : (p, nf) ndarray
        Output autospectra [output unit^2/Hz].
    rms : (p,) ndarray
        RMS of each output [output unit].
    input_psd : (m, nf) ndarray
        Input autospectra on the grid [SI unit^2/Hz].
    outputs, inputs : tuple of str
        Signals.
    units : tuple of str
        Output units (SI).
    miles : (p,) ndarray
        Miles's single-mode estimate of the RMS (NaN where it does not apply).
    method, note : str
        FRF method and how the integral went.
    """

    signal_kind: ClassVar[str] = "output"

    frequency_hz: np.ndarray
    psd: np.ndarray
    rms: np.ndarray
    input_psd: np.ndarray
    outputs: tuple[str, ...]
    inputs: tuple[str, ...]
    units: tuple[str, ...]
    miles: np.ndarray
    method: str = ""
    note: str = ""

    @property
    def output_labels(self) -> tuple[str, ...]:
        return self.outputs

    @property
    def input_labels(self) -> tuple[str, ...]:
        return self.inputs

    def _item(self, i: int, j: int | None) -> Any:
        return self.psd[i]

    @property
    def three_sigma(self) -> np.ndarray:
        """(p,) 3 x RMS [output unit]: exceeded about 0.27 % of the time by a Gaussian response."""
        return 3.0 * self.rms

    def psd_units(self) -> tuple[str, ...]:
        """Units of the output PSDs."""
        return tuple(f"({u})^2/Hz" if ("/" in u or " " in u) else f"{u}^2/Hz" for u in self.units)

    def summary(self) -> Table:
        """RMS, 3 sigma, peak of the PSD and Miles's estimate per output."""
        rows = []
        for i, (o, u) in enumerate(zip(self.outputs, self.units)):
            k = int(np.argmax(self.psd[i]))
            g = f" ({self.rms[i] / G:.4g} g)" if u == "m/s^2" else ""
            miles = "" if not np.isfinite(self.miles[i]) else f"{self.miles[i]:.4g}" + (
                f" ({self.miles[i] / G:.4g} g)" if u == "m/s^2" else "")
            rows.append([o, u, f"{self.rms[i]:.5g}{g}", f"{self.three_sigma[i]:.5g}",
                         f"{self.psd[i, k]:.4g} at {self.frequency_hz[k]:.4g} Hz", miles])
        return Table(["output", "unit", "RMS", "3 sigma", "peak PSD [unit^2/Hz]", "Miles"], rows,
                     title=f"Random response to {', '.join(self.inputs)}")

    def report(self) -> str:
        """The summary and the note."""
        return self.summary().render() + ("\n\n" + self.note if self.note else "")

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: RMS per output, grid and PSDs (SI)."""
        return jsonable({"frequency_hz": self.frequency_hz, "inputs": list(self.inputs),
                         "outputs": {o: {"unit": u, "rms": self.rms[i], "three_sigma": self.three_sigma[i],
                                         "miles": self.miles[i], "psd": self.psd[i]}
                                     for i, (o, u) in enumerate(zip(self.outputs, self.units))},
                         "method": self.method, "note": self.note})

    def to_pandas(self) -> Any:
        """DataFrame of output PSDs indexed by frequency [Hz]."""
        pd = require_pandas()
        df = pd.DataFrame(self.psd.T, index=pd.Index(self.frequency_hz, name="frequency_hz"), columns=list(self.outputs))
        df.attrs["units"] = dict(zip(self.outputs, self.psd_units()))
        df.attrs["rms"] = dict(zip(self.outputs, self.rms.tolist()))
        return df

    def plot(self, ax: Any = None, **kwargs: Any) -> Any:
        """Input and output PSDs on log-log axes: :func:`vibss.plotting.random.plot_random`."""
        from ..plotting.random import plot_random

        return plot_random(self, ax=ax, **kwargs)


def _grid(band: tuple[float, float], extra: Sequence[float], per_decade: int) -> np.ndarray:
    lo, hi = band
    n = max(int(np.ceil(per_decade * np.log10(hi / lo))), 8)
    u = np.concatenate([np.linspace(np.log(lo), np.log(hi), n + 1),
                        [np.log(f) for f in extra if lo < f < hi]])
    return np.unique(u)


def random_response(system: Any, inputs: Mapping[str, Any], outputs: Sequence[str] | None = None, *,
                    correlation: Mapping[tuple[str, str], complex] | None = None, rtol: float = 1e-6,
                    method: str = "auto", max_points: int = 200_000) -> RandomResponse:
    """Output PSDs and RMS values under stationary random inputs.

    Parameters
    ----------
    system : Model, Assembly or Plant
        The system.
    inputs : mapping of str to PSD or (frequency_hz, level)
        Input signal (``'ground.z.acc'``, ``'engine.fz'`` ...) to its one-sided PSD: a
        :class:`~vibss.random.psd.PSD` or a ``(frequency_hz, level)`` pair in g²/Hz for
        accelerations, N²/Hz for forces, m²/Hz for displacements (log-log between breakpoints).
    outputs : sequence of str or None
        Output signals (default every body DOF's displacement).
    correlation : mapping of (str, str) to complex, or None
        Coherence ``rho_ab`` of input pairs (``S_ab = rho_ab sqrt(S_aa S_bb)``, ``S_ab`` the
        spectrum of ``u_a conj(u_b)``; ``S_ba = conj(S_ab)``); default: none.
    rtol : float
        Relative accuracy of each mean square (adaptive quadrature).
    method : str
        FRF method (as :func:`vibss.frequency_response`).
    max_points : int
        Limit on the frequencies evaluated.

    Returns
    -------
    RandomResponse

    Examples
    --------
    >>> import vibss
    >>> t = vibss.MountType("iso", [1e5, 1e5, 1e5], damping=[40.0] * 3)
    >>> m = vibss.Model([vibss.Body("box", 20.0, [1, 1, 1])], [vibss.Mount("m", t, "box")])
    >>> r = random_response(m, {"ground.z.acc": ([20, 2000], [0.04, 0.04])}, ["box.z.acc"])
    >>> r.rms.shape
    (1,)
    """
    from ..frequency.api import frequency_response
    from ..linear.plant.plant import Plant
    from ..linear.plant.build import build_plant
    from ..modal.undamped import modes

    who = "random_response"
    if not isinstance(inputs, Mapping) or not inputs:
        raise ArgumentError(f"{who}: inputs: expected a mapping of input signal to PSD, got {inputs!r}",
                            argument="inputs", received=inputs)
    rtol = v.number(rtol, "rtol", who=who, minimum=0.0, strict=True)
    names = list(inputs)
    psds = [as_psd(inputs[n], _kind(n), n) for n in names]
    m = len(names)
    rho = np.eye(m, dtype=complex)
    for key, value in (correlation or {}).items():
        if not (isinstance(key, tuple) and len(key) == 2 and key[0] in names and key[1] in names and key[0] != key[1]):
            raise ArgumentError(f"{who}: correlation: expected (input, input) pairs of two different inputs "
                                f"among {names}, got {key!r}", argument="correlation", received=key)
        c = complex(value)
        if not abs(c) <= 1.0 + 1e-12:
            raise ArgumentError(f"{who}: correlation[{key!r}]: |rho| must be <= 1, got {value!r}",
                                argument="correlation", received=value)
        i, j = names.index(key[0]), names.index(key[1])
        rho[i, j], rho[j, i] = c, np.conj(c)
    plant = system if isinstance(system, Plant) else build_plant(system, names, outputs)
    band = (min(p.band[0] for p in psds), max(p.band[1] for p in psds))
    if band[0] == band[1]:
        raise ArgumentError(f"{who}: inputs: the PSDs span no band ({band[0]} Hz)", argument="inputs")
    try:
        natural = modes(plant.model if hasattr(plant, "model") and plant.model is not None else system).frequency_hz
    except Exception:                       # a plant without its model: no modes on the grid
        natural = np.zeros(0)
    extra = sorted({f for p in psds for f in p.frequency_hz} | {float(f) for f in natural if f > 0}
                   | {float(f) * (1 + d) for f in natural if f > 0 for d in (-1e-3, 1e-3)})
    used: set[str] = set()

    def integrand(u: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        f = np.exp(u)
        r = frequency_response(plant, frequencies=f, method=method)
        used.add(r.method)
        h = r.response                                         # (p, m, nf)
        s_in = np.array([p(f) for p in psds])                  # (m, nf)
        root = np.sqrt(s_in)
        s_uu = rho[:, :, None] * root[:, None, :] * root[None, :, :]
        s_yy = np.einsum("pan,abn,pbn->pn", h, s_uu, np.conj(h)).real
        return s_yy, s_in, np.abs(h)

    u = _grid(band, extra, 40)
    g_y, g_in, habs = integrand(u)
    err = np.full((len(plant.outputs), u.size - 1), np.inf)     # trapezoid error per interval
    sel = np.arange(u.size - 1)
    while True:
        if u.size + sel.size > max_points:
            raise AnalysisError(f"{who}: the mean squares did not converge to rtol = {rtol:g} within "
                                f"{max_points} frequencies; raise rtol or max_points")
        mid = 0.5 * (u[sel] + u[sel + 1])
        gm, gim, hm = integrand(mid)
        w = g_y * np.exp(u)                       # S df = S f du
        h = np.diff(u)[sel]
        wa, wb, wm = w[:, sel], w[:, sel + 1], gm * np.exp(mid)
        e = np.abs(h / 6.0 * (wa + 4.0 * wm + wb) - 0.5 * (wa + wb) * h)   # Simpson - trapezoid
        # split the checked intervals: each half keeps about an eighth of the error (h^3)
        starts = np.concatenate([u[:-1], mid])
        err_new = np.concatenate([err, e / 8.0], axis=1)
        err_new[:, sel] = e / 8.0
        u = np.concatenate([u, mid])
        order = np.argsort(u)
        u = u[order]
        g_y = np.concatenate([g_y, gm], axis=1)[:, order]
        g_in = np.concatenate([g_in, gim], axis=1)[:, order]
        habs = np.concatenate([habs, hm], axis=2)[:, :, order]
        err = err_new[:, np.argsort(starts)]
        w = g_y * np.exp(u)
        total = np.maximum(np.sum(0.5 * (w[:, 1:] + w[:, :-1]) * np.diff(u), axis=1), 1e-300)
        rel = err / total[:, None]                  # each output's error share per interval
        worst = rel.max(axis=0)
        excess = rel.sum(axis=1).max() - rtol
        if excess <= 0:
            break
        # refine the intervals that carry the excess (largest first)
        ranked = np.argsort(worst)[::-1]
        cum = np.cumsum(worst[ranked])
        sel = np.sort(ranked[:int(np.searchsorted(cum, excess)) + 1])
    f = np.exp(u)
    w = g_y * f
    ms = np.sum(0.5 * (w[:, 1:] + w[:, :-1]) * np.diff(u), axis=1)
    rms = np.sqrt(np.maximum(ms, 0.0))
    miles = np.full(len(plant.outputs), np.nan)
    if m == 1 and _kind(names[0]) == "acceleration":
        for i, o in enumerate(plant.outputs):
            if o.endswith(".acc"):
                k = int(np.argmax(g_y[i]))
                miles[i] = np.sqrt(np.pi / 2 * f[k] * habs[i, 0, k] * g_in[0, k])
    return RandomResponse(f, g_y, rms, g_in, tuple(plant.outputs), tuple(names), tuple(plant.units), miles,
                          ", ".join(sorted(used)),
                          note=f"adaptive quadrature in ln f: {f.size} frequencies over {band[0]:g} ... "
                               f"{band[1]:g} Hz, rtol {rtol:g}; exact FRF; inputs "
                               + ("correlated as given" if correlation else "uncorrelated"))
