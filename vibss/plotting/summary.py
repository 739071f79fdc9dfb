"""Figures of the results that have no natural curve: static deflections, poles, reductions."""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.figure import Figure

from ._draw import new_figure

__all__ = ["plot_static", "plot_poles", "plot_reduction"]


def _axes(ax: Any, count: int, width: float, height: float) -> tuple[Figure, list[Any]]:
    """``count`` axes: the given ones, or a new figure's column of them."""
    if ax is None:
        fig = new_figure(width, height)
        return fig, list(fig.subplots(count, 1, squeeze=False)[:, 0])
    axes = list(np.atleast_1d(ax))
    return axes[0].figure, axes


def plot_static(result: Any, ax: Any = None) -> Figure:
    """Bar chart of each body's static deflection: translations [mm] and rotations [mrad].

    Parameters
    ----------
    result : vibss.StaticResult
        The static result.
    ax : (2,) sequence of Axes or None
        Axes for translations and rotations; default: a new figure.

    Returns
    -------
    Figure
    """
    d = np.array(result.deflections, dtype=float)
    # round-off (a rotation of 1e-17 rad under a symmetric load) is not a deflection: values below 1e-9
    # of the largest (rotations counted on a 1 m lever) are drawn as zero
    floor = 1e-9 * max(float(np.abs(d).max(initial=0.0)), 1e-300)
    d[np.abs(d) < floor] = 0.0
    names = result.model.body_names
    fig, axes = _axes(ax, 2, 7, 5)
    x = np.arange(len(names))
    for a, cols, scale, unit, labels in ((axes[0], slice(0, 3), 1e3, "mm", "xyz"),
                                         (axes[1], slice(3, 6), 1e3, "mrad", ("rx", "ry", "rz"))):
        if not np.any(d[:, cols]):
            a.set_ylim(-1.0, 1.0)
            a.text(0.5, 0.75, "none (below 1e-9 of the largest deflection)", transform=a.transAxes,
                   ha="center", va="center", fontsize=8, color="0.4")
        for k, lab in enumerate(labels):
            a.bar(x + (k - 1) * 0.27, scale * d[:, cols][:, k], width=0.27, label=lab)
        a.set_xticks(x, names)
        a.set_ylabel(f"[{unit}]")
        a.axhline(0.0, color="0.3", lw=0.6)
        a.grid(True, axis="y", alpha=0.3)
        a.legend(fontsize=7)
    axes[0].set_title(f"Static deflection of {result.model.name!r}"
                      + (f", load case {result.case!r}" if result.case else ""), fontsize=10)
    return fig


def plot_mount_deflections(result: Any, ax: Any = None) -> Figure:
    """Bar chart of every mount's static deflection along its local axes 1, 2, 3 [mm] (what a mount
    catalogue's load-deflection limit is checked against).

    Parameters
    ----------
    result : vibss.StaticResult
        The static result.
    ax : Axes or None
        Axes to draw in; default: a new figure.

    Returns
    -------
    Figure
    """
    names = [m.name for m in result.model.mounts]
    d = np.asarray(result.mount_deflection_local, dtype=float).reshape(len(names), 3) * 1e3
    fig, (a,) = _axes(ax, 1, max(6.0, 0.45 * len(names) + 2.5), 4.2)
    x = np.arange(len(names))
    for k in range(3):
        a.bar(x + (k - 1) * 0.27, d[:, k], width=0.27, label=f"axis {k + 1}")
    a.set_xticks(x, names, rotation=30 if len(names) > 4 else 0, ha="right" if len(names) > 4 else "center",
                 fontsize=8)
    a.set_ylabel("deflection [mm] (local axes)")
    a.axhline(0.0, color="0.3", lw=0.6)
    a.grid(True, axis="y", alpha=0.3)
    a.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    a.set_title(f"Static mount deflections of {result.model.name!r}"
                + (f", load case {result.case!r}" if result.case else ""), fontsize=10)
    return fig


def plot_poles(modes: Any, ax: Any = None) -> Figure:
    """Pole map of damped modes: ``Im(lambda)`` against ``Re(lambda)`` [rad/s], numbered.

    Parameters
    ----------
    modes : vibss.DampedModes
        The damped modes.
    ax : Axes or None
        Axes to draw in; default: a new figure.

    Returns
    -------
    Figure
    """
    fig, (a,) = _axes(ax, 1, 6, 4.5)
    p = modes.poles
    a.plot(p.real, p.imag, "x", ms=7)
    for k, pk in enumerate(p):
        a.annotate(str(k + 1), (pk.real, pk.imag), textcoords="offset points", xytext=(4, 4), fontsize=7)
    a.axvline(0.0, color="0.3", lw=0.6)
    a.set_xlabel("Re p [1/s]")
    a.set_ylabel("Im p [rad/s]")
    a.grid(True, alpha=0.3)
    a.set_title(f"Poles of {modes.undamped.model.name!r} ({modes.method})", fontsize=9)
    return fig


def plot_reduction(reduction: Any, ax: Any = None, n_points: int = 200) -> Figure:
    """Largest response of each output over the band: full model (dashed) and reduced, and the
    relative error of the reduced one.

    Parameters
    ----------
    reduction : vibss.Reduction
        The reduction.
    ax : (2,) sequence of Axes or None
        Axes for the magnitudes and the error; default: a new figure.
    n_points : int
        Frequencies over the band (the kept resonances are added).

    Returns
    -------
    Figure
    """
    f, full, red = reduction.compare(n_points)
    fig, axes = _axes(ax, 2, 8, 6)
    for i, y in enumerate(reduction.output_labels):
        (line,) = axes[0].loglog(f, np.abs(red[i]).max(axis=0), label=y)
        axes[0].loglog(f, np.abs(full[i]).max(axis=0), "--", color=line.get_color(), lw=0.8)
    peak = np.abs(full).max(axis=(1, 2), keepdims=True)
    err = (np.abs(red - full) / np.where(peak > 0, peak, 1.0)).max(axis=(0, 1))
    axes[1].loglog(f, np.maximum(err, 1e-17), "k", lw=1)
    axes[1].axhline(reduction.scope.tolerance, color="C3", ls=":", label="tolerance")
    axes[0].set_ylabel("max over inputs |H|")
    axes[1].set_ylabel("relative error")
    axes[1].set_xlabel("frequency [Hz]")
    axes[0].legend(fontsize=7)
    axes[1].legend(fontsize=7)
    axes[0].set_title(f"Reduction ({reduction.method}): {reduction.dofs_before} -> "
                      f"{reduction.dofs_after} DOFs (dashed: full model)", fontsize=9)
    return fig
