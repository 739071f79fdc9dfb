"""The model file's ``[shock]`` environment: SRS of the input pulse and of the responses, with the
specification check; run by ``vibss srs`` (and the report)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import ModelError
from ..results import Result, TextTable
from .api import check_envelope, srs
from .result import EnvelopeCheck, ShockResponseSpectrum

__all__ = ["ShockStudy", "run_shock"]


@dataclass(frozen=True, eq=False)
class ShockStudy(Result):
    """SRS of a file's shock input and of the responses to it.

    Attributes
    ----------
    spectra : dict of str to ShockResponseSpectrum
        By signal (the input first).
    checks : dict of str to EnvelopeCheck
        The input's spectrum against the file's spec (when it gives one).
    note : str
        Window, step and Q.
    """

    spectra: dict[str, ShockResponseSpectrum]
    checks: dict[str, EnvelopeCheck] = field(default_factory=dict)
    note: str = ""
    name: str = "shock"

    @property
    def output_labels(self) -> tuple[str, ...]:
        """The signals."""
        return tuple(self.spectra)

    def _item(self, i: int, j: int | None) -> np.ndarray:
        return list(self.spectra.values())[i].response

    def summary(self) -> TextTable:
        """Peak of every spectrum, and the spec verdicts."""
        rows = []
        for name, s in self.spectra.items():
            k = int(np.argmax(s.response))
            verdict = ("PASS" if self.checks[name].passed else "FAIL") if name in self.checks else "-"
            rows.append([name, f"{s.response[k]:.5g}", f"{s.frequency_hz[k]:.4g}", verdict])
        return TextTable(["signal", "peak SRS [SI]", "at [Hz]", "spec"], rows,
                     title=f"Shock response spectra ({self.note})")

    def report(self) -> str:
        """Summary, then each spectrum and check."""
        parts = [str(self.summary())]
        parts += [c.report() for c in self.checks.values()]
        return "\n\n".join(parts)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready spectra and checks (SI)."""
        return {"note": self.note, "spectra": {k: s.to_dict() for k, s in self.spectra.items()},
                "checks": {k: c.to_dict() for k, c in self.checks.items()}}

    def plot(self, ax: Any = None) -> Any:
        """Every spectrum on log-log axes, the spec band shaded."""
        from ..plotting._draw import new_figure, plain_frequency_axis

        if ax is None:
            fig = new_figure(8.0, 4.8)
            ax = fig.subplots()
        else:
            fig = ax.figure
        for k, (name, s) in enumerate(self.spectra.items()):
            ax.loglog(s.frequency_hz, s.response, color=f"C{k}", lw=1.6, label=f"{name} (Q = {s.q:g})")
        for name, c in self.checks.items():
            lo = c.spec * 10 ** (max(c.lower_db, -60.0) / 20)
            hi = c.spec * 10 ** (min(c.upper_db, 60.0) / 20)
            ax.loglog(c.frequency_hz, c.spec, color="0.2", ls="--", lw=1.0, label=f"spec ({c.lower_db:+g}/{c.upper_db:+g} dB)")
            ax.fill_between(c.frequency_hz, lo, hi, color="0.85", zorder=0)
        ax.set_xlabel("natural frequency [Hz]")
        ax.set_ylabel("SRS, absolute acceleration [m/s^2]")
        plain_frequency_axis(ax)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
        ax.set_title(f"Shock response spectra ({self.note})", fontsize=9)
        return fig


def run_shock(model: Any) -> ShockStudy:
    """SRS of the ``[shock]`` excitation and of its outputs' responses; the spec check of the input.

    Parameters
    ----------
    model : Model
        With ``settings["shock"]`` (:mod:`vibss.io.environmentsfile`).
    """
    from ..studies import time_window
    from ..time.api import simulate

    spec = model.settings.get("shock")
    if not spec:
        raise ModelError("the model has no [shock] table (excitation, outputs, band, q, spec)")
    found = {e.name: e for e in model.excitations}
    exc = found.get(spec["excitation"])
    if exc is None:
        raise ModelError(f"[shock] excitation: no [[excitation]] named {spec['excitation']!r}; the file's are "
                         f"{sorted(found)}")
    lo, hi = spec.get("band", (5.0, 2000.0))
    f = np.geomspace(lo, hi, spec.get("points", 60))
    q = spec.get("q", 10.0)
    window = time_window(model)
    step = min(window.step, 1.0 / (20.0 * hi))
    end = max(window.end, float(getattr(exc.function, "end_time", 0.0)) + 1.0 / lo)
    t = np.arange(0.0, end + 0.5 * step, step)
    spectra = {exc.signal: srs(t, exc.function.value(t), f, q=q, name=exc.signal)}
    outputs = spec.get("outputs") or []
    if outputs:
        r = simulate(model, [exc], outputs=outputs, t_end=float(t[-1]), dt=step)
        for name in outputs:
            spectra[name] = srs(r.time, r[name], f, q=q, name=name)
    checks = {}
    if "spec" in spec:
        s = spec["spec"]
        checks[exc.signal] = check_envelope(spectra[exc.signal], s["frequency"], s["level"],
                                            s.get("lower_db", -3.0), s.get("upper_db", 6.0))
    return ShockStudy(spectra, checks, f"Q = {q:g}, 0 to {t[-1]:.3g} s every {step:.3g} s")
