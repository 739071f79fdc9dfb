"""Figure of an active isolation design: passive and closed-loop transmissibility on one plot."""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.figure import Figure

from ._draw import new_figure, plain_frequency_axis

__all__ = ["plot_transmissibility"]


def plot_transmissibility(passive: Any, active: Any, ax: Any = None, title: str = "") -> Figure:
    """Magnitude [dB] of passive (dashed) and closed-loop (solid) transmissibility, one colour per channel.

    Parameters
    ----------
    passive, active : FrequencyResponse
        On the same frequencies and channels (:meth:`vibss.control.ClosedLoop.transmissibility`).
    ax : matplotlib Axes or None
        Where to draw; default: a new figure.
    title : str
        Figure title (the closed loop's name).

    Returns
    -------
    Figure
    """
    if ax is None:
        fig = new_figure(8.0, 4.2)
        ax = fig.subplots()
    else:
        fig = ax.figure
    f = active.frequency_hz
    peak = max(float(np.abs(passive.response).max()), float(np.abs(active.response).max()), 1e-300)
    k, skipped = 0, 0
    for i, y in enumerate(active.outputs):
        for j, u in enumerate(active.inputs):
            if max(np.abs(passive.response[i, j]).max(), np.abs(active.response[i, j]).max()) < 1e-6 * peak:
                skipped += 1          # a channel the symmetry decouples: round-off, not a response
                continue
            colour = f"C{k % 10}"
            ax.semilogx(f, 20 * np.log10(np.maximum(np.abs(passive.response[i, j]), 1e-300)), color=colour,
                        ls="--", lw=1.0, label=f"{y} / {u}: passive")
            ax.semilogx(f, 20 * np.log10(np.maximum(np.abs(active.response[i, j]), 1e-300)), color=colour,
                        lw=1.6, label=f"{y} / {u}: closed loop")
            k += 1
    top = 20 * np.log10(peak)
    ax.set_ylim(bottom=max(ax.get_ylim()[0], top - 100.0), top=top + 10.0)
    if skipped:
        ax.text(0.01, 0.01, f"{skipped} channel(s) below -120 dB of the largest not drawn", transform=ax.transAxes,
                fontsize=7, color="0.4", va="bottom")
    ax.set_xlabel("frequency [Hz]")
    plain_frequency_axis(ax)
    ax.set_ylabel("transmissibility [dB]  (|output| / |input|, same units)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    ax.set_title(f"Transmissibility, passive and active{': ' + title if title else ''}", fontsize=10)
    return fig
