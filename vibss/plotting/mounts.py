"""Figure of frequency-dependent mount types: |k*|(f) and the loss angle, rheology against ladder."""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from typing import Any

import numpy as np
from matplotlib.figure import Figure

from ._draw import new_figure

__all__ = ["plot_dynamic_stiffness"]


def plot_dynamic_stiffness(mount_types: Sequence[Any], frequency_hz: Any = None, ax: Any = None) -> Figure:
    """|k*|(f) [N/m] and the loss angle [deg] of each axis of each frequency-dependent mount type.

    Solid lines: the rheology's own ``k*`` (a table's interpolation); dashed: the Maxwell ladder
    every analysis uses (they coincide for the rational models).

    Parameters
    ----------
    mount_types : sequence of MountType
        Types without a rheology are skipped.
    frequency_hz : (nf,) array_like or None
        Frequencies [Hz]; default: 0.1 to 1000 Hz, or the types' fitted bands.
    ax : (2,) sequence of Axes or None
        Axes for |k*| and the loss angle; default: a new figure.

    Returns
    -------
    Figure
    """
    types = [t for t in mount_types if getattr(t, "rheology", None) is not None]
    if frequency_hz is None:
        bands = [t.ladder.band for t in types if t.ladder is not None and t.ladder.band is not None]
        lo = min([0.1] + [float(b[0]) for b in bands])
        hi = max([1000.0] + [float(b[1]) for b in bands])
        frequency_hz = np.geomspace(lo, hi, 400)
    f = np.asarray(frequency_hz, dtype=float)
    if ax is None:
        fig = new_figure(7, 6)
        axes = list(fig.subplots(2, 1, sharex=True))
    else:
        axes = list(np.atleast_1d(ax))
        fig = axes[0].figure
    curve = 0
    for t in types:
        with warnings.catch_warnings():       # the held ends of a table are drawn, not reported
            warnings.simplefilter("ignore")
            exact = t.dynamic_stiffness(f)
        ladder = t.ladder.stiffness(2 * np.pi * f) + 0j
        for j in range(3):
            if j and np.allclose(exact[:, j], exact[:, 0]) and np.allclose(ladder[:, j], ladder[:, 0]):
                continue                      # an axis like the first: drawn once
            label = f"{t.name} axis {j + 1}"
            color = f"C{curve % 10}"          # one colour per drawn curve (axes of one type differ)
            curve += 1
            axes[0].loglog(f, np.abs(exact[:, j]), color=color, ls="-", label=label)
            axes[0].loglog(f, np.abs(ladder[:, j]), color=color, ls="--")
            axes[1].semilogx(f, np.degrees(np.angle(exact[:, j])), color=color, ls="-")
            axes[1].semilogx(f, np.degrees(np.angle(ladder[:, j])), color=color, ls="--")
    axes[0].set_ylabel("|k*| [N/m]")
    axes[1].set_ylabel("loss angle [deg]")
    axes[1].set_xlabel("frequency [Hz]")
    axes[0].set_title("Frequency-dependent mount types (solid: rheology, dashed: ladder used)")
    if types:
        axes[0].legend(fontsize=7)
    for a in axes:
        a.grid(True, which="both", alpha=0.3)
    return fig
