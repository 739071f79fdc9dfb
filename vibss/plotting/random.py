"""Figure of a random response: input and output PSDs on log-log axes."""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.figure import Figure

from ._draw import new_figure

__all__ = ["plot_random"]


def plot_random(result: Any, ax: Any = None) -> Figure:
    """Output PSDs (one panel per unit, RMS in the legend) above the input PSDs.

    Parameters
    ----------
    result : vibss.random.RandomResponse
        The random response.
    ax : sequence of matplotlib Axes or None
        One axes per output unit plus one for the inputs; default: a new figure.

    Returns
    -------
    Figure
    """
    units = list(dict.fromkeys(result.units))
    psd_units = dict(zip(result.units, result.psd_units()))
    if ax is None:
        fig = new_figure(8.0, 2.8 * (len(units) + 1) + 0.5)
        axes = list(np.atleast_1d(fig.subplots(len(units) + 1, 1, sharex=True, squeeze=False)[:, 0]))
    else:
        axes = list(ax)
        fig = axes[0].figure
    f = result.frequency_hz
    for a, unit in zip(axes, units):
        for i, (o, u) in enumerate(zip(result.outputs, result.units)):
            if u == unit:
                a.loglog(f, _positive(result.psd[i]), color=f"C{i % 10}",
                         label=f"{o}: {result.rms[i]:.4g} {u} RMS")
        a.set_ylabel(f"PSD [{psd_units[unit]}]")
        _two_decades(a)
        a.grid(True, which="both", alpha=0.3)
        a.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    a = axes[-1]
    levels, given = result.input_levels()             # as the spec was given: g^2/Hz stays g^2/Hz
    one = len(set(given)) == 1
    for j, name in enumerate(result.inputs):
        a.loglog(f, _positive(levels[j]), color="0.3", ls=("-", "--", ":")[j % 3],
                 label=name if one else f"{name} [{given[j]}]")
    a.set_ylabel(f"input PSD [{given[0]}]" if one else "input PSD (units in the legend)")
    _two_decades(a)
    a.set_xlabel("frequency [Hz]")
    a.grid(True, which="both", alpha=0.3)
    a.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    axes[0].set_title("Random response (output PSDs and RMS)", fontsize=10)
    return fig


def _positive(y: np.ndarray) -> np.ndarray:
    """Zeros (outside an input's band) left out of a log axis, not drawn as 1e-300."""
    return np.where(y > 0, y, np.nan)


def _two_decades(a: Any) -> None:
    """A log axis spans at least two decades around its lines: a flat spec (0.04 g^2/Hz) would be
    autoscaled onto its round-off (1e-17 of it), drawn as spikes under a single tick."""
    ys = [np.asarray(line.get_ydata(), float) for line in a.get_lines()]
    y = np.concatenate(ys) if ys else np.zeros(0)
    y = y[np.isfinite(y) & (y > 0)]
    if y.size and y.max() < 100.0 * y.min():
        mid = float(np.sqrt(y.max() * y.min()))
        a.set_ylim(mid / 10.0, mid * 10.0)
