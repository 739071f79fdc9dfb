"""Figures of robust isolator control: the metrics of every tolerance variant, and noise budgets."""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.figure import Figure

from ._draw import new_figure

__all__ = ["plot_robustness", "plot_noise_budget"]


def plot_robustness(r: Any, ax: Any = None) -> Figure:
    """Histograms of the smallest damping ratio, disk margin and peak transmissibility of every
    variant, the nominal marked (dashed) and the corners as ticks along the bottom.

    Parameters
    ----------
    r : vibss.control.Robustness
        The study.
    ax : sequence of 3 Axes or None
        Draw into these axes; default: a new three-panel figure.

    Returns
    -------
    Figure
    """
    if ax is None:
        fig = new_figure(12.0, 4.4)
        axes = fig.subplots(1, 3)
    else:
        axes = list(ax)
        fig = axes[0].figure
    lo, hi = r.p_stable_interval
    panels = (("damping", "smallest closed-loop damping ratio [-]"), ("disk_margin", "smallest disk margin [-]"),
              ("peak", f"peak |T| {r.channel[0]} -> {r.channel[1]} [-]"))
    for a, (key, label) in zip(axes, panels):
        v = getattr(r, key)
        s, c = v[~r.corner & r.stable], v[r.corner & r.stable]
        finite = s[np.isfinite(s)]
        span = (finite.min(), finite.max()) if finite.size else (0.0, 1.0)
        nom = r.nominal_metrics[key]
        lo_b, hi_b = min(span[0], nom, *(c if c.size else [nom])), max(span[1], nom, *(c if c.size else [nom]))
        pad = 0.02 * (hi_b - lo_b) or 0.01 * max(abs(hi_b), 1e-12)
        bins = np.linspace(lo_b - pad, hi_b + pad, 40)
        a.hist(finite, bins=bins, color="C0", alpha=0.7, label=f"{finite.size} stable samples")
        a.axvline(nom, ymax=0.66, color="k", ls="--", lw=1.0, label=f"nominal {nom:.4g}")
        if c.size:
            a.plot(c, np.zeros_like(c), "|", color="C3", ms=14, mew=1.5, label=f"{c.size} corners", clip_on=False)
        a.set_xlabel(label, fontsize=8)
        a.set_ylabel("variants")
        a.ticklabel_format(axis="x", useOffset=False)
        a.set_ylim(0, a.get_ylim()[1] * 1.45)                 # room for the legend above the bars
        a.legend(fontsize=7, frameon=False, loc="upper left", ncol=2)
    fig.suptitle(f"{r.model.name}: {r.n} variants + {int(r.corner.sum())} corners; P(stable) = {r.p_stable:.3f} "
                 f"[{lo:.3f}, {hi:.3f}] at {100 * r.confidence:.0f} %", fontsize=10)
    return fig


def plot_noise_budget(b: Any, ax: Any = None, output: str | None = None) -> Figure:
    """A noise budget in the kontrol style: each source's amplitude spectral density of one output,
    stacked with the total, and the cumulative RMS (integrated from the highest frequency down).

    Parameters
    ----------
    b : vibss.control.NoiseBudget
        The budget.
    ax : Axes or None
        Draw into these axes (the RMS on a twin axis); default: a new figure.
    output : str or None
        The output (default the first).

    Returns
    -------
    Figure
    """
    if ax is None:
        fig = new_figure(7.5, 4.6)
        ax = fig.add_subplot()
    else:
        fig = ax.figure
    o = 0 if output is None else list(b.outputs).index(output)
    f = b.frequency_hz
    unit = b.units[o]
    total = b.total[o]
    ax.loglog(f, np.sqrt(np.maximum(total, 1e-300)), color="0.4", lw=4.0, alpha=0.45, label="total")
    for k, src in enumerate(b.sources):         # over the total, so a dominant source stays visible
        ax.loglog(f, np.sqrt(np.maximum(b.psd[o, k], 1e-300)), lw=1.2, label=src)
    rms = b.cumulative_rms[o]
    ax.loglog(f, rms, color="k", ls="--", lw=1.0, label=f"cumulative RMS ({b.rms_total[o]:.3g} {unit})")
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel(f"ASD [{unit}/sqrt(Hz)], RMS [{unit}]")
    ax.set_title(f"noise budget of {b.outputs[o]}", fontsize=10)
    top = max(float(np.sqrt(total).max()), float(rms.max()))
    ax.set_ylim(top * 1e-6, top * 5)
    ax.legend(fontsize=7, frameon=False, loc="lower left")
    ax.grid(True, which="both", lw=0.3, alpha=0.5)
    return fig
