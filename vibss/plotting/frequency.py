"""Bode plots of frequency responses (magnitude and phase against frequency)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from matplotlib.figure import Figure

from .._validate import name_index
from ..errors import ArgumentError
from ._draw import new_figure

__all__ = ["plot_frequency_response"]


def plot_frequency_response(response: Any, outputs: Sequence[str] | None = None,
                            inputs: Sequence[str] | None = None, max_channels: int = 12,
                            mark_resonances: bool = True, ax: Any = None, by: str = "all") -> Figure:
    """Bode plot (magnitude and phase) of selected channels of a frequency response.

    Parameters
    ----------
    response : vibss.frequency.FrequencyResponse
        The response.
    outputs, inputs : sequence of str or None
        Channels to draw; default: all, but at most ``max_channels`` (the largest peaks).
    max_channels : int
        Limit on the default selection.
    mark_resonances : bool
        Dotted vertical lines at the undamped natural frequencies [Hz].
    ax : (2,) sequence of matplotlib Axes or None
        Magnitude and phase axes to draw in (``by="all"`` only); default: a new figure.
    by : {"all", "body"}
        ``"all"``: every channel on one pair of axes; ``"body"``: one magnitude/phase column per
        group of outputs (the part of their name before the first ``.``).

    Returns
    -------
    Figure
    """
    if by not in ("all", "body"):
        raise ArgumentError(f"plot: by must be 'all' or 'body', got {by!r}", argument="by", received=by,
                            expected=("all", "body"))
    r = response
    if by == "body":
        names = list(r.output_labels) if outputs is None else list(outputs)
        groups: dict[str, list[str]] = {}
        for name in names:
            groups.setdefault(name.split(".")[0], []).append(name)
        fig = new_figure(4.5 * len(groups) + 1, 6)
        axes = fig.subplots(2, len(groups), sharex=True, squeeze=False)
        for col, (group, outs_g) in enumerate(groups.items()):
            plot_frequency_response(r, outs_g, inputs, max_channels, mark_resonances, ax=axes[:, col])
            axes[0, col].set_title(group)
        fig.suptitle(f"{r.name}: method {r.method}")
        return fig
    outs = list(r.output_labels) if outputs is None else list(outputs)
    ins = list(r.input_labels) if inputs is None else list(inputs)
    pairs = [(name_index(y, r.output_labels, "output"), name_index(u, r.input_labels, "input"))
             for y in outs for u in ins]
    mag = r.magnitude
    if outputs is None and inputs is None and len(pairs) > max_channels:
        peak = [np.nanmax(np.where(np.isfinite(mag[i, j]), mag[i, j], np.nan)) for i, j in pairs]
        pairs = [pairs[k] for k in np.argsort(peak)[::-1][:max_channels]]
    if ax is None:
        fig = new_figure(8, 6)
        ax = fig.subplots(2, 1, sharex=True)
    else:
        fig = ax[0].figure
    f = r.frequency_hz
    pos = f > 0
    phase = r.phase_deg
    units = {r.channel_unit(i, j) for i, j in pairs}
    for i, j in pairs:
        label = r.output_labels[i] + (f" / {r.input_labels[j]}" if len(r.input_labels) > 1 else "")
        if len(units) > 1:
            label += f" [{r.channel_unit(i, j)}]"
        ax[0].loglog(f[pos], mag[i, j, pos], label=label)
        ax[1].semilogx(f[pos], phase[i, j, pos])
    if mark_resonances:
        for fr in r.natural_hz:
            for a in ax:
                a.axvline(fr, color="0.6", lw=0.6, ls=":")
    what = "amplitude" if r.quantity == "sweep" else r.quantity
    ax[0].set_ylabel(f"|{'y' if r.quantity == 'sweep' else 'H'}| [{units.pop()}] ({what})" if len(units) == 1
                     else f"|H| ({what}; units in the legend)")
    ax[1].set_ylabel("phase [deg]")
    ax[1].set_xlabel("frequency [Hz]")
    ax[0].set_title(f"{r.name}: method {r.method}")
    ax[0].legend(fontsize="small")
    return fig
