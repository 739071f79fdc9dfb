"""Figure of a model updated to measured data: the measurement against the model before and after."""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.figure import Figure

from ._draw import fitted_title, new_figure

__all__ = ["plot_update"]

MAX_CHANNELS = 6
"""At most this many channels are drawn (the first ones); the others are named in the title."""


def plot_update(result: Any, ax: Any = None) -> Figure:
    """Measured data against the model before and after updating.

    A frequency response: |H| of each channel (up to :data:`MAX_CHANNELS`) against frequency [Hz],
    the measurement as markers, the model before (dashed) and after (solid), the FRAC before and
    after in the legend. Modes: the model's natural frequencies before and after against the
    measured ones [Hz], and the MAC of each pair before and after [-].

    Parameters
    ----------
    result : UpdateResult
        What :func:`vibss.update` returned.
    ax : Axes or sequence of Axes or None
        One axes per channel drawn (two for modes); default: a new figure.

    Returns
    -------
    Figure
    """
    if result.kind == "modes":
        return _modes(result, ax)
    meas, before, after = result.measured, result.response_before, result.response_after
    channels = [(i, j) for i in range(len(meas.outputs)) for j in range(len(meas.inputs))][:MAX_CHANNELS]
    if ax is None:
        fig = new_figure(7, 2.2 + 2.0 * len(channels))
        axes = list(np.atleast_1d(fig.subplots(len(channels), 1, sharex=True, squeeze=False)[:, 0]))
    else:
        axes = list(np.atleast_1d(ax))
        fig = axes[0].figure
    f = meas.frequency_hz
    for a, (i, j), c in zip(axes, channels, range(len(channels))):
        label = f"{meas.outputs[i]}/{meas.inputs[j]}"
        k = result.labels.index(label)
        a.loglog(f, np.abs(meas.response[i, j]), "o", ms=3, mfc="none", color="k", label="measured")
        a.loglog(f, np.abs(before.response[i, j]), "--", color="C1",
                 label=f"before (FRAC {result.correlation_before[k]:.3f})")
        a.loglog(f, np.abs(after.response[i, j]), "-", color="C0",
                 label=f"after (FRAC {result.correlation_after[k]:.3f})")
        unit = _unit(after, meas, i, j)
        a.set_ylabel(f"|{label}| [{unit}]", fontsize=8)
        a.grid(True, which="both", alpha=0.3)
        a.legend(fontsize=7, loc="best")
    axes[-1].set_xlabel("frequency [Hz]")
    more = len(meas.outputs) * len(meas.inputs) - len(channels)
    fitted_title(axes[0], f"Model updating of {result.initial_model.name!r}: measured (markers), before (dashed), "
                          f"after (solid)" + (f"; {more} more channels not drawn" if more > 0 else ""))
    return fig


def _modes(result: Any, ax: Any) -> Figure:
    if ax is None:
        fig = new_figure(7, 6)
        axes = list(fig.subplots(2, 1))
    else:
        axes = list(np.atleast_1d(ax))
        fig = axes[0].figure
    fm = result.measured.frequency_hz
    n = np.arange(1, fm.size + 1)
    a = axes[0]
    a.plot(n, 100 * (result.frequency_before - fm) / fm, "s--", color="C1", mfc="none", label="before")
    a.plot(n, 100 * (result.frequency_after - fm) / fm, "o-", color="C0", label="after")
    a.axhline(0.0, color="k", lw=0.8)
    a.set_ylabel("model - measured frequency [%]")
    a.set_xticks(n, [f"{i}\n{f:.3g} Hz" for i, f in zip(n, fm)], fontsize=7)
    a.legend(fontsize=8, loc="best")
    a.grid(True, alpha=0.3)
    b = axes[1]
    w = 0.38
    b.bar(n - w / 2, result.correlation_before, w, color="C1", label="before")
    b.bar(n + w / 2, result.correlation_after, w, color="C0", label="after")
    b.set_ylim(0.0, 1.3)
    b.set_ylabel("MAC [-]")
    b.set_xlabel("measured mode")
    b.set_xticks(n, [f"{i}" for i in n])
    b.legend(fontsize=8, loc="upper right", ncol=2)
    b.grid(True, axis="y", alpha=0.3)
    fitted_title(a, f"Model updating of {result.initial_model.name!r} to {fm.size} measured modes")
    return fig


def _unit(model: Any, meas: Any, i: int, j: int) -> str:
    """The channel's unit from the model's response (it knows the input's unit, a measured file often
    does not: a UFF read gives the output's unit alone), else the measurement's."""
    out, inp = meas.outputs[i], meas.inputs[j]
    if out in model.outputs and inp in model.inputs:
        return str(model.channel_unit(list(model.outputs).index(out), list(model.inputs).index(inp)))
    return str(meas.channel_unit(i, j))
