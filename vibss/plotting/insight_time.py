"""Figure of a time response split into its modes (:class:`vibss.insight.time_result.TimeContributions`):
the response near a peak with its largest modal terms, and each term's share at the peak and over
the window around it. It draws a computed result."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from matplotlib.figure import Figure

from ._draw import fitted_title, new_figure

if TYPE_CHECKING:      # a figure is handed a computed result; it imports no analysis
    from ..insight.time_result import TimeContributions

__all__ = ["plot_time_contributions"]


def plot_time_contributions(result: TimeContributions, ax: Any = None, output: int = 0, top: int = 4,
                            window: float | None = None) -> Figure:
    """Top: one output near its peak (three windows wide), the ``top`` modal terms (the largest at the
    peak) and the rest with the residual, the window shaded; bottom: each of them's share at the
    peak and over the window [%].

    Parameters
    ----------
    result : TimeContributions
    ax : sequence of two Axes or None
        Axes (top, bottom) to draw in; default: a new figure.
    output : int
        Position of the output.
    top : int
        Terms drawn one by one; the rest summed with the residual as "other modes + residual".
    window : float or None
        Width of the window centred on the peak [s] (default: :meth:`TimeContributions.window_of`).

    Returns
    -------
    Figure
    """
    import matplotlib as mpl
    from matplotlib.patches import Patch

    if ax is None:
        fig = new_figure(7.6, 6.0)
        up, low = fig.subplots(2, 1, height_ratios=[3, 2])
    else:
        up, low = ax
        fig = up.figure
    t, j = result.time, result.peak_index(output)
    win = result.window_of(output, window)
    at, over = result.share_at(output, j), result.share_in(output, win)
    best = [int(k) for k in np.argsort(-np.nan_to_num(np.abs(at[:-1]), nan=-np.inf))[:top]]
    rest = [k for k in range(len(result)) if k not in best]
    width = max(float(t[win.stop - 1] - t[win.start]), 2 * float(t[1] - t[0]) if t.size > 1 else 1.0)
    show = (t >= t[j] - 1.5 * width) & (t <= t[j] + 1.5 * width)
    unit = result.units[output]
    tab = mpl.colormaps["tab10"]
    up.plot(t[show], result.total[output, show], "k", lw=2.2, label="response")
    labels: list[str] = []
    now: list[float] = []
    inwin: list[float] = []
    colors: list[Any] = []
    for c, k in enumerate(best):
        lab = f"mode {k + 1} ({result.mode_frequency_hz[k]:.3g} Hz)"
        up.plot(t[show], result.terms[k, output, show], color=tab(c % 10), lw=1.2, label=lab)
        labels.append(lab)
        now.append(at[k])
        inwin.append(over[k])
        colors.append(tab(c % 10))
    other = result.terms[rest, output].sum(axis=0) + result.residual[output]
    if rest or np.any(result.residual[output]):
        up.plot(t[show], other[show], color="0.45", ls="--", lw=1.0, label="other modes + residual")
        labels.append("other modes + residual")
        now.append(float(np.nansum(at[rest]) + at[-1]))
        inwin.append(float(np.nansum(over[rest]) + over[-1]))
        colors.append("0.6")
    up.axvspan(t[win.start], t[win.stop - 1], color="0.9", zorder=0, label="window")
    up.axvline(t[j], color="k", lw=0.6, ls=":")
    up.set_xlabel("time [s]")
    up.set_ylabel(f"{result.output_names[output]} [{unit}]")
    up.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
    up.grid(True, lw=0.3)
    y = np.arange(len(labels))
    low.barh(y - 0.2, 100 * np.array(now), height=0.4, color=colors)
    low.barh(y + 0.2, 100 * np.array(inwin), height=0.4, color=colors, alpha=0.45, hatch="//")
    keys = [Patch(color="0.5", label=f"at the peak (t = {t[j]:.4g} s)"),
            Patch(facecolor="0.5", alpha=0.45, hatch="//", label=f"over the window ({width:.3g} s)")]
    low.set_yticks(y, labels, fontsize=7)
    low.invert_yaxis()
    low.axvline(0, color="k", lw=0.6)
    low.set_xlabel("share of the response [%]")
    low.legend(handles=keys, fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
    low.grid(True, axis="x", lw=0.3)
    fitted_title(up, f"Modal contributions to the peak of {result.output_names[output]} ({result.method})")
    return fig
