"""Figure of a rheology fitted to measured dynamic stiffness: the data, the fit and its error."""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.figure import Figure

from ._draw import new_figure

__all__ = ["plot_rheology_fit"]


def plot_rheology_fit(fit: Any, ax: Any = None) -> Figure:
    """|k*| [N/m] and the loss factor [-] of the data (markers) and the fitted law (lines, over the
    data's band) per axis, and the fit error ``|log(k_fit / k_data)|`` [-] against frequency [Hz].

    Parameters
    ----------
    fit : RheologyFit
        What :func:`vibss.fit_rheology` returned.
    ax : (3,) sequence of Axes or None
        Axes for |k*|, the loss factor and the error; default: a new figure.

    Returns
    -------
    Figure
    """
    if ax is None:
        fig = new_figure(7, 8)
        axes = list(fig.subplots(3, 1, sharex=True))
    else:
        axes = list(np.atleast_1d(ax))
        fig = axes[0].figure
    f = fit.frequency_hz
    fine = np.geomspace(f[0], f[-1], 400)               # the fitted law between the data points
    law = np.asarray(fit.rheology.dynamic_stiffness(2 * np.pi * fine)).T
    groups: list[list[int]] = []                       # axes with the same data and fit: drawn once
    for j in range(3):
        same = [g for g in groups if np.array_equal(fit.data[j], fit.data[g[0]])
                and np.array_equal(fit.fitted[j], fit.fitted[g[0]])]
        same[0].append(j) if same else groups.append([j])
    for n, group in enumerate(groups):
        j = group[0]
        axis = ", ".join(fit.output_labels[i] for i in group)
        c = f"C{n}"
        d, k = fit.data[j], law[j]
        axes[0].loglog(f, np.abs(d), "o", color=c, ms=4, mfc="none", label=f"{axis} data")
        axes[0].loglog(fine, np.abs(k), "-", color=c, label=f"{axis} {fit.type} fit")
        axes[1].semilogx(f, d.imag / d.real, "o", color=c, ms=4, mfc="none")
        axes[1].semilogx(fine, k.imag / k.real, "-", color=c)
        axes[2].loglog(f, np.maximum(fit.error[j], 1e-17), ".-", color=c,
                       label=f"{axis}: RMS {fit.rms_error[j]:.2g}")
    axes[2].axhline(fit.tolerance, color="k", ls=":", lw=1, label=f"tolerance {fit.tolerance:g}")
    axes[0].set_ylabel("|k*| [N/m]")
    axes[1].set_ylabel("loss factor [-]")
    axes[2].set_ylabel("|log(k_fit / k_data)| [-]")
    axes[2].set_xlabel("frequency [Hz]")
    axes[0].set_title(f"{fit.type} fitted to measured dynamic stiffness (markers: data, lines: fit)",
                      fontsize=10)
    axes[0].legend(fontsize=7, loc="lower right")
    axes[2].legend(fontsize=7, loc="best")
    for a in axes:
        a.grid(True, which="both", alpha=0.3)
    return fig
