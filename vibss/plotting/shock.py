"""Shock response spectrum figures: the spectrum with its spec envelope, and the tripartite plot."""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.figure import Figure

from ._draw import new_figure, plain_frequency_axis

__all__ = ["plot_tripartite"]


def plot_tripartite(result: Any, unit: str = "m/s^2", ax: Any = None) -> Figure:
    """Four-coordinate (tripartite) SRS plot: pseudo-velocity against frequency on log-log axes, with
    lines of constant relative displacement (slope +1) and absolute acceleration (slope -1).

    Parameters
    ----------
    result : ShockResponseSpectrum
        An acceleration (or pseudo-velocity) spectrum of an acceleration given in ``unit``.
    unit : {"m/s^2", "g"}
        The unit of the signal the spectrum was taken of.
    ax : matplotlib Axes or None

    Returns
    -------
    Figure
    """
    from ..model.units import STANDARD_GRAVITY

    scale = STANDARD_GRAVITY if unit == "g" else 1.0
    f = np.asarray(result.frequency_hz, dtype=float)
    w = 2 * np.pi * f
    resp = np.asarray(result.response, dtype=float) * scale
    pv = {"acceleration": resp / w, "pseudo_velocity": resp, "displacement": resp * w}[result.quantity]
    if ax is None:
        fig = new_figure(7.5, 6.0)
        ax = fig.subplots()
    else:
        fig = ax.figure
    ax.loglog(f, pv, color="C0", lw=1.8, label=f"{result.kind} SRS, Q = {result.q:g}")
    lo_f, hi_f = f.min() / 2, f.max() * 2
    lo_v, hi_v = pv.min() / 10, pv.max() * 10
    fl = np.array([lo_f, hi_f])
    for e in range(-9, 6):                            # displacement [m]: PV = w D
        d = 10.0 ** e
        v = 2 * np.pi * fl * d
        if v.max() > lo_v and v.min() < hi_v:
            ax.loglog(fl, v, color="0.75", lw=0.6)
            x = np.clip(hi_v / (2 * np.pi * d) / 1.5, lo_f, hi_f)
            if lo_v < 2 * np.pi * x * d < hi_v:
                ax.text(x, 2 * np.pi * x * d, f"{d:g} m", fontsize=7, color="0.4", rotation=35, ha="right", va="top")
    for e in range(-3, 7):                            # acceleration: PV = A / w, labelled in g
        a = 10.0 ** e * STANDARD_GRAVITY
        v = a / (2 * np.pi * fl)
        if v.max() > lo_v and v.min() < hi_v:
            ax.loglog(fl, v, color="0.75", lw=0.6, ls="--")
            x = np.clip(a / (2 * np.pi * lo_v * 1.5), lo_f, hi_f)          # along the bottom edge
            if lo_v < a / (2 * np.pi * x) < hi_v:
                ax.text(x, a / (2 * np.pi * x), f"{10.0 ** e:g} g", fontsize=7, color="0.4", rotation=-35, ha="right", va="bottom")
    ax.set_xlim(lo_f, hi_f)
    ax.set_ylim(lo_v, hi_v)
    ax.set_xlabel("natural frequency [Hz]")
    ax.set_ylabel("pseudo-velocity [m/s]")
    plain_frequency_axis(ax)
    ax.grid(True, which="major", alpha=0.3)
    ax.legend(fontsize=8, loc="upper right")
    ax.set_title("Tripartite SRS (solid grey: relative displacement; dashed: absolute acceleration)", fontsize=9)
    return fig
