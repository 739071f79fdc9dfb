"""Bode plots of frequency responses (magnitude and phase against frequency)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from matplotlib.figure import Figure

from .._validate import name_index
from ..errors import ArgumentError
from ..frequency.compare import frac
from ..results import ZERO_NOTE
from ._draw import new_figure, plain_frequency_axis

__all__ = ["plot_frequency_response", "mark_resonances_on"]

_ROW_GAP = 0.015
_CHAR = 0.011
"""Gap between mode numbers in one row and the width of one character (fractions of the axis width);
numbers that would touch go to the next row up."""
_ROWS = 3
_SAME = 0.004
"""Modes closer than this (fraction of the axis width) share one tick label ("1,2,3")."""
_KEY_MAX = 24


def plot_frequency_response(response: Any, outputs: Sequence[str] | None = None,
                            inputs: Sequence[str] | None = None, max_channels: int = 12,
                            mark_resonances: bool = True, ax: Any = None, by: str = "all",
                            key: bool = True, title: str | None = None, what: str | None = None) -> Figure:
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
        Dotted vertical lines at the undamped natural frequencies [Hz] in the plotted band, numbered
        above the magnitude axes with their mode numbers (as in :func:`vibss.modes`).
    ax : (2,) sequence of matplotlib Axes or None
        Magnitude and phase axes to draw in (``by="all"`` only); default: a new figure.
    by : {"all", "body"}
        ``"all"``: every channel on one pair of axes; ``"body"``: one magnitude/phase column per
        group of outputs (the part of their name before the first ``.``).
    key : bool
        With ``mark_resonances``: list the numbered modes (``"3 tank.y 4.12 Hz"``) below the axes.
    title : str or None
        Title above the axes (default: the response's name and method).
    what : str or None
        What the magnitude is, under its unit (default: the response's quantity, e.g.
        ``"receptance"``; a sweep's ``"amplitude"``).

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
            plot_frequency_response(r, outs_g, inputs, max_channels, mark_resonances, ax=axes[:, col],
                                    key=mark_resonances and col == len(groups) - 1)
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
    units = list(dict.fromkeys(r.channel_unit(i, j) for i, j in pairs))   # in order of first use
    if ax is None:          # one magnitude axes per unit (m beside rad would squash one of them)
        n_mag = len(units)
        fig = new_figure(8, 6 if n_mag == 1 else 3.2 + 2.3 * n_mag)
        axs = list(fig.subplots(n_mag + 1, 1, sharex=True, squeeze=False,
                                gridspec_kw={"height_ratios": [1.5] * n_mag + [1.2]})[:, 0])
        mag_ax = dict(zip(units, axs[:-1]))
    else:
        fig = ax[0].figure
        axs = [ax[0], ax[1]]
        mag_ax = {u: ax[0] for u in units}
    f = r.frequency_hz
    pos = f > 0
    phase = r.phase_deg
    colours = _colours(len(pairs))          # one colour per channel, the same in every panel
    zero = r.zero_channels
    for k, (i, j) in enumerate(pairs):
        u = r.channel_unit(i, j)
        label = r.output_labels[i] + (f" / {r.input_labels[j]}" if len(r.input_labels) > 1 else "")
        shared = sum(a is mag_ax[u] for a in mag_ax.values()) > 1
        if shared:
            label += f" [{u}]"
        if zero[i, j]:        # nothing to draw on a log axis: named in the legend (and the panel, if alone)
            mag_ax[u].plot([], [], ls="none", label=f"{label} \u2261 0")
            continue
        mag_ax[u].loglog(f[pos], mag[i, j, pos], label=label, color=colours[k])
        axs[-1].semilogx(f[pos], phase[i, j, pos], color=colours[k])
    for a in [*dict.fromkeys(mag_ax.values()), axs[-1]]:
        _say_if_zero(a, f[pos])
    if tuple(r.inputs) == ("sweep",):   # a sweep's amplitudes: only the swept band
        live = np.flatnonzero(np.any(np.abs(r.response[:, 0, :]) > 0, axis=0) & pos)
        if live.size > 1:
            axs[-1].set_xlim(f[live[0]], f[live[-1]])
    if mark_resonances:
        mark_resonances_on(axs[0], axs, r, key=key)
    what = what or ("amplitude" if r.quantity == "sweep" else r.quantity)
    symbol = "y" if r.quantity == "sweep" or tuple(r.inputs) == ("sweep",) else "H"   # amplitudes, not ratios
    for a in dict.fromkeys(mag_ax.values()):
        here = [u for u in units if mag_ax[u] is a]
        a.set_ylabel(f"|{symbol}| [{here[0]}]\n({what})" if len(here) == 1
                     else f"|{symbol}| ({what}; units in the legend)")
        a.legend(fontsize="small", loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    axs[-1].set_ylabel("phase [deg]")
    axs[-1].set_xlabel("frequency [Hz]")
    plain_frequency_axis(axs[-1])
    axs[0].set_title(title or f"{r.name}: method {r.method}", fontsize=10)
    return fig


def _say_if_zero(a: Any, f: np.ndarray) -> None:
    """An axes that only zero channels went to: no log scale of nothing, the words instead."""
    if any(len(line.get_xdata()) for line in a.get_lines()):
        return
    a.set_xscale("log")
    if f.size:
        a.set_xlim(float(f.min()), float(f.max()))
    a.set_yticks([])
    a.text(0.5, 0.5, ZERO_NOTE, transform=a.transAxes, ha="center", va="center", color="0.35")


def _colours(n: int) -> list[Any]:
    """``n`` distinct colours: tab10, or tab20 for more than ten channels (no colour used twice)."""
    from matplotlib import colormaps

    cmap = colormaps["tab10" if n <= 10 else "tab20"]
    return [cmap(k % cmap.N) for k in range(n)]


def mark_resonances_on(top: Any, axes: Sequence[Any], response: Any, key: bool = True) -> list[str]:
    """Mark the undamped natural frequencies of a response inside its axes' band.

    Dotted vertical lines on every axes; the mode numbers on a secondary axis above ``top``
    (staggered in up to three rows where they would touch); with ``key``, a figure legend below the
    axes lists ``"<number> <label> <f> Hz"`` (labels as :attr:`vibss.modal.Modes.labels`). A
    response without mode numbers gets the lines only.

    Parameters
    ----------
    top : matplotlib Axes
        Axes that carries the numbers (a logarithmic or linear frequency axis [Hz]).
    axes : sequence of matplotlib Axes
        Axes that get the dotted lines (``top`` included if it should have them).
    response : FrequencyResponse
        Its ``natural_hz`` [Hz], ``mode_numbers`` and ``mode_labels``.
    key : bool
        Add the figure legend of the numbered modes (only in a constrained-layout figure).

    Returns
    -------
    list of str
        The key entries, in frequency order.
    """
    lo, hi = sorted(top.get_xlim())
    fr = np.asarray(response.natural_hz, dtype=float)
    inside = np.flatnonzero((fr >= lo) & (fr <= hi))
    for k in inside:
        for a in axes:
            a.axvline(fr[k], color="0.6", lw=0.6, ls=":")
    numbers = tuple(getattr(response, "mode_numbers", ()))
    if not numbers or not inside.size:
        return []
    labels = tuple(getattr(response, "mode_labels", ())) or ("",) * len(numbers)
    log = top.get_xscale() == "log"
    pos = (np.log10(fr[inside]) - np.log10(lo)) / (np.log10(hi) - np.log10(lo)) if log else \
        (fr[inside] - lo) / (hi - lo)
    # modes at (nearly) one frequency share a tick: "1,2,3"
    groups: list[list[int]] = []
    for j in np.argsort(pos, kind="stable"):
        if groups and pos[j] - pos[groups[-1][-1]] < _SAME:
            groups[-1].append(int(j))
        else:
            groups.append([int(j)])
    at = np.array([fr[inside[g[0]]] for g in groups])
    names = [",".join(str(numbers[inside[j]]) for j in g) for g in groups]
    rows = _stagger(np.array([pos[g[0]] for g in groups]), np.array([len(n) for n in names]))
    text = [n + "\n" * int(r) for n, r in zip(names, rows)]
    sec = top.secondary_xaxis("top")
    from matplotlib.ticker import FixedLocator, NullLocator

    sec.xaxis.set_major_locator(FixedLocator(at.tolist()))
    sec.xaxis.set_minor_locator(NullLocator())

    def number_at(v: float, _: Any = None) -> str:
        j = int(np.argmin(np.abs(at - v)))
        return text[j] if np.isclose(at[j], v, rtol=1e-9) else ""

    sec.xaxis.set_major_formatter(number_at)
    sec.tick_params(axis="x", labelsize=7, length=3, pad=1, colors="0.3")
    entries = [f"{numbers[k]} {labels[k]} {fr[k]:.3g} Hz".replace("  ", " ") for k in inside]
    fig = top.figure
    engine = fig.get_layout_engine()
    if key and engine is not None and type(engine).__name__ == "ConstrainedLayoutEngine":
        from matplotlib.lines import Line2D

        shown = entries if len(entries) <= _KEY_MAX else entries[:_KEY_MAX - 1] + [f"... {len(entries) - _KEY_MAX + 1} more"]
        handles = [Line2D([], [], ls="none") for _ in shown]
        fig.legend(handles, shown, loc="outside lower center", ncols=min(len(shown), 4), fontsize=7,
                   handlelength=0, handletextpad=0, columnspacing=1.6, frameon=False,
                   title="numbered resonances (undamped natural frequencies, mode numbers as in the modes table)",
                   title_fontsize=7)
    return entries


def _stagger(pos: np.ndarray, chars: np.ndarray) -> np.ndarray:
    """Row (0, 1, 2) of each label at sorted positions ``pos`` (fractions of the axis width) with
    ``chars`` characters: the lowest row where it clears its left neighbour (half widths plus a
    gap), else the row whose last label is furthest left."""
    last = np.full(_ROWS, -np.inf)
    width = np.zeros(_ROWS)
    rows = np.zeros(len(pos), dtype=int)
    for k in np.argsort(pos, kind="stable"):
        need = _CHAR * 0.5 * (width + chars[k]) + _ROW_GAP
        free = np.flatnonzero(pos[k] - last >= need)
        r = int(free[0]) if free.size else int(np.argmin(last))
        rows[k], last[r], width[r] = r, pos[k], chars[k]
    return rows


def plot_transmissibility_set(motion: Any, force: Any, bodies: Any) -> Any:
    """Motion (ground -> body, per axis) and force (body -> ground, per axis) transmissibility
    magnitudes [-] on two panels, one colour per axis, one line style per body.

    Parameters
    ----------
    motion, force : mapping of {"x", "y", "z"} to FrequencyResponse
        From :func:`vibss.transmissibility` (motion: ground.<d> -> <body>.<d>; force: <body>.f<d> -> ground.f<d>;
        with supports, the first ground node's).
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
                label = (f"{b}.{d} / {r.inputs[0].removesuffix('.disp')}" if what.startswith("motion")
                         else f"{r.outputs[0]} / {b}.f{d}")
                ax.loglog(f[pos], np.abs(r.response[i, j, pos]), color=colours[d], ls=styles[k % 4], label=label)
        ax.axhline(1.0, color="0.5", lw=0.8)
        ax.set_ylabel("|T| [-]")
        ax.set_title(what, fontsize=9)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    axes[1].set_xlabel("frequency [Hz]")
    plain_frequency_axis(axes[1])
    mark_resonances_on(axes[0], list(axes), next(iter(motion.values())))
    fig.suptitle("Transmissibility (dotted, numbered: undamped natural frequencies)", fontsize=10)
    return fig


def plot_test_overlay(measured: Any, computed: Any, channels: Sequence[str] | None = None) -> Figure:
    """Measured FRFs (markers) over computed ones (lines), magnitude and phase, with each channel's
    FRAC (:func:`vibss.frequency.compare.frac`) in the legend.

    Parameters
    ----------
    measured, computed : FrequencyResponse
        E.g. :func:`vibss.io.read_uff` of a test and :func:`vibss.frequency_response` of the model.
    channels : sequence of str or None
        ``"<output>/<input>"`` channels to draw (default: every channel both have that is not
        identically zero, at most 6).

    Returns
    -------
    Figure
    """
    scores = frac(measured, computed)
    # by default the channels that carry something (an identically zero one has no FRAC)
    names = list(channels) if channels is not None else [c for c in scores if np.isfinite(scores[c])][:6]
    unknown = [c for c in names if c not in scores]
    if unknown:
        raise ArgumentError(f"plot_test_overlay: channels {unknown} are not in both responses; common "
                            f"channels are {list(scores)}", argument="channels", received=unknown)
    fig = new_figure(8, 6)
    mag, ph = fig.subplots(2, 1, sharex=True)
    units = []
    for k, ch in enumerate(names):
        y, u = ch.rsplit("/", 1)
        color = f"C{k % 10}"
        hc = computed.response[computed.outputs.index(y), computed.inputs.index(u)]
        hm = measured.response[measured.outputs.index(y), measured.inputs.index(u)]
        mag.semilogy(computed.frequency_hz, np.abs(hc), color=color, label=f"{ch} computed")
        mag.semilogy(measured.frequency_hz, np.abs(hm), ".", color=color, ms=3,
                     label=f"{ch} measured (FRAC {scores[ch]:.3f})")
        ph.plot(computed.frequency_hz, np.degrees(np.angle(hc)), color=color)
        ph.plot(measured.frequency_hz, np.degrees(np.angle(hm)), ".", color=color, ms=3)
        unit = computed.channel_unit(y, u) if hasattr(computed, "channel_unit") else computed.units[0]
        units.append(unit)
    mag.set_ylabel(f"|H| [{', '.join(dict.fromkeys(units))}]")
    ph.set_ylabel("phase [deg]")
    ph.set_xlabel("frequency [Hz]")
    for a in (mag, ph):
        a.set_xscale("log")
        plain_frequency_axis(a)
        a.grid(True, which="both", alpha=0.3)
    mag.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    mag.set_title("test against model", fontsize=10)
    return fig
