"""Figures of the insight analyses: the energy shares as a heat map, a response split into its modes,
and the force paths into a receiver. They draw computed results (:mod:`vibss.insight`)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from matplotlib.figure import Figure

from ._draw import fitted_title, new_figure, plain_frequency_axis

if TYPE_CHECKING:      # a figure is handed a computed result; it imports no analysis
    from ..insight.result import EnergyDistribution, ModalContributions, PathContributions

__all__ = ["plot_energy_distribution", "plot_modal_contributions", "plot_path_contributions"]

_TITLES = {"strain": "strain energy", "kinetic": "kinetic energy", "dissipative": "dissipated energy"}


def plot_energy_distribution(result: EnergyDistribution, ax: Any = None, by_axis: bool = False) -> Figure:
    """Heat map of each mode's energy share per part (mount or body) [%], the values of 1 % and
    more written in the cells; rigid-body rows (no strain energy) left blank.

    Parameters
    ----------
    result : EnergyDistribution
        Result of :func:`vibss.insight.energy_distribution`.
    ax : Axes or None
        Axes to draw in; default: a new figure.
    by_axis : bool
        One column per part and coordinate (those some mode loads).

    Returns
    -------
    Figure
    """
    shares, cols = result.columns(by_axis)
    data = 100 * shares
    k = len(result)
    if ax is None:
        fig = new_figure(2.4 + 0.5 * len(cols), 1.4 + 0.32 * k)
        ax = fig.add_subplot()
    else:
        fig = ax.figure
    im = ax.imshow(np.ma.masked_invalid(data), cmap="Blues", vmin=0, vmax=100, aspect="auto")
    for i in range(data.shape[0]):
        for j in range(data.shape[1]):
            if np.isfinite(data[i, j]) and abs(data[i, j]) >= 1:
                ax.text(j, i, f"{data[i, j]:.0f}", ha="center", va="center", fontsize=7,
                        color="w" if data[i, j] > 60 else "k")
    ax.set_xticks(range(len(cols)), cols, rotation=90 if len(cols) > 6 or by_axis else 0, fontsize=8)
    ax.set_yticks(range(k), [f"{i + 1}: {result.frequency_hz[i]:.3g} Hz" for i in range(k)], fontsize=8)
    part = "mount" if result.kind != "kinetic" else "body"
    ax.set_xlabel(f"{part} ({'local axis' if result.kind != 'kinetic' else 'DOF'})" if by_axis else part)
    ax.set_ylabel("mode: natural frequency")
    fig.colorbar(im, ax=ax, label=f"{_TITLES[result.kind]} [%]", shrink=0.9)
    fitted_title(ax, f"Modal {_TITLES[result.kind]} distribution of {result.model.name!r}")
    return fig


def _two_axes(ax: Any, height: float = 5.6) -> tuple[Figure, Any, Any]:
    if ax is None:
        fig = new_figure(7.4, height)
        top, bottom = fig.subplots(2, 1, sharex=True, height_ratios=[3, 2])
        return fig, top, bottom
    top, bottom = ax
    return top.figure, top, bottom


def _stack(bottom: Any, f: np.ndarray, shares: np.ndarray, labels: list[str], colors: list[Any]) -> None:
    """Stacked magnitude shares ``|part| / sum |parts|`` [%] (non-negative, summing to 100 %)."""
    mags = np.abs(shares)
    tot = mags.sum(axis=0)
    frac = 100 * mags / np.where(tot > 0, tot, 1.0)
    bottom.stackplot(f, frac, labels=labels, colors=colors, alpha=0.85)
    bottom.set_ylim(0, 100)
    bottom.set_ylabel("share of sum |terms| [%]")
    bottom.set_xlabel("frequency [Hz]")


def plot_modal_contributions(result: ModalContributions, ax: Any = None, output: int = 0, input: int = 0,
                             top: int = 4) -> Figure:
    """Top: ``|H|`` of one output and input and the magnitudes of its largest modal terms; bottom:
    the terms' magnitudes stacked as shares of their sum [%].

    Parameters
    ----------
    result : ModalContributions
    ax : sequence of two Axes or None
        Axes (top, bottom) to draw in; default: a new figure.
    output, input : int
        Positions of the output and input.
    top : int
        Terms drawn one by one (the largest shares at the peaks); the rest summed as "other modes".

    Returns
    -------
    Figure
    """
    import matplotlib as mpl

    fig, up, low = _two_axes(ax)
    f = result.frequency
    h = result.total[output, input]
    peaks = result.peaks(output, input)
    score = np.nan_to_num(np.abs(result.share[:, output, input][:, peaks]), nan=0.0).max(axis=1)
    best = [int(k) for k in np.argsort(-score)[:top]]
    rest = [k for k in range(len(result)) if k not in best]
    unit = f"{result.units[output]}/{result.input_labels[input]}"
    up.loglog(f, np.abs(h), "k", lw=2.0, label="response")
    tab = mpl.colormaps["tab10"]
    colors = [tab(i) for i in range(10)]
    labels, parts = [], []
    for c, k in enumerate(best):
        lab = f"mode {k + 1} ({result.mode_frequency_hz[k]:.3g} Hz)"
        up.loglog(f, np.abs(result.terms[k, output, input]), color=colors[c % 10], lw=1.1, label=lab)
        labels.append(lab)
        parts.append(result.terms[k, output, input])
    other = result.terms[rest, output, input].sum(axis=0) + result.residual[output, input]
    if rest or np.any(result.residual[output, input]):
        up.loglog(f, np.abs(other), color="0.5", ls="--", lw=1.0, label="other modes + residual")
        labels.append("other modes + residual")
        parts.append(other)
    up.set_ylabel(f"|H| [{unit}]")
    up.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
    up.grid(True, which="both", lw=0.3)
    _stack(low, f, np.array(parts), labels, (colors[:len(best)] + ["0.7"])[:len(parts)])
    plain_frequency_axis(low)
    fitted_title(up, f"Modal contributions to {result.output_labels[output]} / {result.input_labels[input]} "
                     f"({result.method})")
    return fig


def plot_path_contributions(result: PathContributions, ax: Any = None, component: int = 2,
                            input: int = 0) -> Figure:
    """Top: the magnitude of one component of each path's force and of the total; bottom: the
    paths' magnitudes stacked as shares of their sum [%].

    Parameters
    ----------
    result : PathContributions
    ax : sequence of two Axes or None
        Axes (top, bottom) to draw in; default: a new figure.
    component : int
        0 ... 5 for fx ... mz.
    input : int
        Position of the input.

    Returns
    -------
    Figure
    """
    import matplotlib as mpl

    fig, up, low = _two_axes(ax)
    f = result.frequency
    cmap = mpl.colormaps["tab10" if len(result.paths) <= 10 else "tab20"]
    colors = [cmap(i % cmap.N) for i in range(len(result.paths))]
    up.loglog(f, np.abs(result.total[component, input]), "k", lw=2.0, label="total")
    for q, p in enumerate(result.paths):
        up.loglog(f, np.abs(result.forces[q, component, input]), color=colors[q], lw=1.0, label=p)
    unit = result.units[component]
    up.set_ylabel(f"|{result.components[component]}| [{unit}/{result.input_labels[input]}]")
    up.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
    up.grid(True, which="both", lw=0.3)
    _stack(low, f, result.forces[:, component, input], list(result.paths), colors)
    low.set_ylabel("share of sum |paths| [%]")
    plain_frequency_axis(low)
    fitted_title(up, f"Transfer paths into {result.receiver!r}: {result.components[component]} per unit "
                     f"{result.input_labels[input]}")
    return fig
