"""The harmonic-balance response curve: first-harmonic amplitude against frequency, unstable parts dashed."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from matplotlib.figure import Figure

from ._draw import new_figure

__all__ = ["plot_harmonic_balance"]


def plot_harmonic_balance(result: Any, outputs: Sequence[str] | None = None, ax: Any = None) -> Figure:
    """First-harmonic amplitude of each output along the branch, stable solid, unstable dashed,
    the turning points marked.

    Parameters
    ----------
    result : vibss.nonlinear.result.HarmonicBalanceResult
        The branch.
    outputs : sequence of str or None
        Outputs to draw (default all; one axes per unit).
    ax : Axes or None
        Axes to draw on (all outputs on it); default a new figure.

    Returns
    -------
    Figure
    """
    names = list(result.output_labels) if outputs is None else list(outputs)
    idx = [result.output_labels.index(o) for o in names]
    units = list(dict.fromkeys(result.units[i] for i in idx))
    if ax is None:
        fig = new_figure(7, 3.2 * len(units))
        axes = list(fig.subplots(len(units), 1, squeeze=False)[:, 0])
    else:
        axes, fig = [ax] * len(units), ax.figure
    f = result.frequencies
    stable = np.ones(f.size, dtype=bool) if result.stable is None else np.asarray(result.stable)
    for n, i in enumerate(idx):
        a = axes[units.index(result.units[i])]
        y = result.amplitude[i]
        color = f"C{n % 10}"
        seg = stable[:-1] & stable[1:]          # a segment is stable when both its ends are
        start = 0
        for b in range(1, seg.size + 1):        # one line per run of equally styled segments
            if b == seg.size or seg[b] != seg[start]:
                a.plot(f[start:b + 1], y[start:b + 1], color=color, ls="-" if seg[start] else "--",
                       label=names[n] if start == 0 else None)
                start = b
        if f.size == 1:
            a.plot(f, y, "o", color=color, label=names[n])
        for k in result.turning_index:
            a.plot(f[k], y[k], "o", mfc="none", color=color, ms=5)
    for u, a in zip(units, axes):
        a.set_xlabel("frequency [Hz]")
        a.set_ylabel(f"first-harmonic amplitude [{u}]")
        a.grid(True, alpha=0.3)
        a.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, title_fontsize=8,   # off the data
                 title=None if result.stable is None else "dashed:\nunstable")
    return fig
