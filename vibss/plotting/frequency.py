"""Bode plots of frequency responses (magnitude and phase against frequency)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from matplotlib.figure import Figure

from .._validate import name_index
from ..errors import ArgumentError
from ._draw import new_figure, plain_frequency_axis

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
    plain_frequency_axis(ax[1])
    ax[0].set_title(f"{r.name}: method {r.method}")
    ax[0].legend(fontsize="small", loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    return fig


def plot_transmissibility_set(motion: Any, force: Any, bodies: Any) -> Any:
    """Motion (ground -> body, per axis) and force (body -> ground, per axis) transmissibility
    magnitudes [-] on two panels, one colour per axis, one line style per body.

    Parameters
    ----------
    motion, force : mapping of {"x", "y", "z"} to FrequencyResponse
        From :func:`vibss.transmissibility` (motion: ground.<d> -> <body>.<d>; force: <body>.f<d> -> ground.f<d>).
    bodies : sequence of str
        Body names (line styles).

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig = new_figure(8.5, 6.5)
    axes = fig.subplots(2, 1, sharex=True)
    styles = ["-", "--", ":", "-."]
    colours = {"x": "C0", "y": "C1", "z": "C2"}
    for ax, group, what in ((axes[0], motion, "motion: ground -> body COG"),
                            (axes[1], force, "force: body COG -> ground")):
        for d, r in group.items():
            f = r.frequency_hz
            pos = f > 0
            for k, b in enumerate(bodies):
                i, j = (k, 0) if what.startswith("motion") else (0, k)
                label = (f"{b}.{d} / ground.{d}" if what.startswith("motion") else f"ground.f{d} / {b}.f{d}")
                ax.loglog(f[pos], np.abs(r.response[i, j, pos]), color=colours[d], ls=styles[k % 4], label=label)
        ax.axhline(1.0, color="0.5", lw=0.8)
        for fr in next(iter(group.values())).natural_hz:
            ax.axvline(fr, color="0.7", lw=0.6, ls=":")
        ax.set_ylabel("|T| [-]")
        ax.set_title(what, fontsize=9)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    axes[1].set_xlabel("frequency [Hz]")
    plain_frequency_axis(axes[1])
    fig.suptitle("Transmissibility (dotted: undamped natural frequencies)", fontsize=10)
    return fig
