"""Figures of rotating-machinery studies: order cuts (amplitude against shaft speed) and the Campbell
diagram (natural frequencies and order lines against speed, critical speeds marked)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from matplotlib.figure import Figure

from .._validate import name_index
from ._draw import new_figure

__all__ = ["plot_order_cuts", "plot_campbell"]


def plot_order_cuts(result: Any, outputs: Sequence[str] | None = None, ax: Any = None,
                    overall: bool = True) -> Figure:
    """Amplitude of each output against shaft speed, one line per order (and the overall RMS).

    Parameters
    ----------
    result : vibss.orders.OrderResponse
        The order response.
    outputs : sequence of str or None
        Outputs to draw (default: all, one panel per unit).
    ax : matplotlib Axes or None
        Draw into these axes (one unit only); default: a new figure.
    overall : bool
        Also draw the overall RMS over all orders (dashed) when there are several orders.

    Returns
    -------
    Figure
    """
    names = list(result.outputs) if outputs is None else list(outputs)
    idx = [name_index(n, result.outputs, "output") for n in names]
    units = list(dict.fromkeys(result.units[i] for i in idx))
    if ax is None:
        fig = new_figure(8.0, 3.2 * len(units) + 0.6)
        axes = list(np.atleast_1d(fig.subplots(len(units), 1, sharex=True, squeeze=False)[:, 0]))
    else:
        fig, axes = ax.figure, [ax]
    colours = {n: f"C{c % 10}" for c, n in enumerate(names)}
    styles = ["-", "--", ":", "-."]
    for a, unit in zip(axes, units):
        for n, i in zip(names, idx):
            if result.units[i] != unit:
                continue
            for j, k in enumerate(result.orders):
                a.semilogy(result.rpm, np.abs(result.response[j, i]), styles[j % len(styles)],
                           color=colours[n], label=f"{n}, order {k:g}")
            if overall and len(result.orders) > 1:
                a.semilogy(result.rpm, result.overall[i], color=colours[n], lw=2.5, alpha=0.35,
                           label=f"{n}, overall RMS")
        for k, mode, fn, r in result.critical_speeds():
            a.axvline(r, color="0.6", lw=0.7, ls=":")
        a.set_ylabel(f"amplitude [{unit}]")
        a.grid(True, which="both", alpha=0.3)
        a.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    axes[-1].set_xlabel("shaft speed [rpm]")
    axes[0].set_title(f"Order cuts ({', '.join(result.sources)}); dotted: critical speeds", fontsize=10)
    return fig


def plot_campbell(result: Any, ax: Any = None, max_modes: int = 12) -> Figure:
    """Campbell diagram: natural frequencies (horizontal) and order lines ``f = k rpm / 60``
    against shaft speed, with the critical speeds marked and labelled.

    Parameters
    ----------
    result : vibss.orders.OrderResponse
        The order response (its speeds, orders and natural frequencies).
    ax : matplotlib Axes or None
        Draw into these axes; default: a new figure.
    max_modes : int
        Draw at most the lowest this many natural frequencies.

    Returns
    -------
    Figure
    """
    if ax is None:
        fig = new_figure(8.0, 5.0)
        ax = fig.subplots()
    else:
        fig = ax.figure
    rpm = result.rpm
    f_top = max(float(np.max(result.orders)) * rpm[-1] / 60.0, 1e-9)
    nat = [f for f in result.natural_hz[:max_modes] if 0 < f <= 1.05 * f_top]
    if nat:                                        # the band where orders meet modes, not the whole fan
        f_top = min(f_top, 3.0 * max(nat))
    gap = 0.045 * 1.05 * f_top                     # labels at least this far apart [Hz]
    y_label: list[float] = []
    for fn in nat:                                 # ascending: push each label above the last
        y_label.append(max(fn, y_label[-1] + gap) if y_label else fn)
    for i, (fn, yl) in enumerate(zip(nat, y_label)):
        ax.axhline(fn, color="0.45", lw=0.8)
        ax.annotate(f"mode {i + 1}: {fn:.2f} Hz", xy=(rpm[-1], fn), xytext=(rpm[-1] - 0.02 * (rpm[-1] - rpm[0]), yl),
                    ha="right", va="bottom", fontsize=7, color="0.3",
                    arrowprops={"arrowstyle": "-", "color": "0.6", "lw": 0.5} if yl != fn else None)
    for j, k in enumerate(result.orders):
        ax.plot(rpm, k * rpm / 60.0, color=f"C{j % 10}", label=f"order {k:g}")
    crit = result.critical_speeds()
    if crit:
        ax.plot([c[3] for c in crit], [c[2] for c in crit], "o", mfc="none", mec="C3", label="critical speed")
    ax.set_xlim(rpm[0], rpm[-1])
    # order lines are labelled where they leave the frame
    for j, k in enumerate(result.orders):
        r_end = min(rpm[-1], 60.0 * 1.05 * f_top / k)
        ax.annotate(f"{k:g}x", xy=(r_end, k * r_end / 60.0), xytext=(2, 2), textcoords="offset points",
                    fontsize=8, color=f"C{j % 10}", ha="left", va="bottom", annotation_clip=False)
    ax.set_ylim(0.0, 1.05 * f_top)
    ax.set_xlabel("shaft speed [rpm]")
    ax.set_ylabel("frequency [Hz]")
    ax.set_title("Campbell diagram", fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="upper left")
    return fig
