"""Time responses grouped by quantity: one panel per kind of output, sharing the time axis."""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.figure import Figure

from ._draw import new_figure

__all__ = ["plot_time_groups", "quantity_of"]

_ORDER = ("body translation", "body rotation", "acceleration", "angular acceleration", "velocity",
          "mount deflection", "mount force", "force into ground", "moment into ground", "force into bodies",
          "moment into bodies")


def quantity_of(name: str, unit: str) -> str:
    """The panel an output goes to, from its signal name and SI unit.

    Examples
    --------
    >>> quantity_of("engine.z", "m"), quantity_of("mount.front.dz", "m"), quantity_of("engine.x.acc", "m/s^2")
    ('body translation', 'mount deflection', 'acceleration')
    >>> quantity_of("ground.mx", "N m"), quantity_of("frame.into.fz", "N")
    ('moment into ground', 'force into bodies')
    """
    if name.startswith("mount."):
        return "mount force" if unit in ("N", "N m") else "mount deflection"
    if name.startswith("ground.") or ".into." in name:
        where = "ground" if name.startswith("ground.") else "bodies"
        return f"{'moment' if unit == 'N m' else 'force'} into {where}"
    if name.endswith(".acc"):
        return "angular acceleration" if unit.startswith("rad") else "acceleration"
    if name.endswith(".vel"):
        return "velocity"
    return "body rotation" if unit == "rad" else "body translation"


def plot_time_groups(response: Any, max_lines: int = 6) -> Figure:
    """Plot a time response with one panel per quantity (translation, rotation, acceleration,
    mount deflection ...), each showing its ``max_lines`` outputs of largest peak, peaks marked.

    Parameters
    ----------
    response : vibss.time.TimeResponse
        The response (``time``, ``outputs``, ``output_names``, ``units``).
    max_lines : int
        Most lines per panel (the outputs with the largest peaks).

    Returns
    -------
    Figure
    """
    groups: dict[str, list[int]] = {}
    for i, (n, u) in enumerate(zip(response.output_names, response.units)):
        groups.setdefault(quantity_of(n, u), []).append(i)
    keys = sorted(groups, key=lambda k: _ORDER.index(k) if k in _ORDER else len(_ORDER))
    zero = [k for k in keys if not np.any(np.abs(response.outputs[groups[k]]) > 1e-15)]
    keys = [k for k in keys if k not in zero] or keys[:1]
    fig = new_figure(8.5, 1.0 + 2.1 * max(len(keys), 1))
    axes = np.atleast_1d(fig.subplots(max(len(keys), 1), 1, sharex=True, squeeze=False)[:, 0])
    t = response.time
    for ax, key in zip(axes, keys):
        rows = groups[key]
        peak = np.array([np.max(np.abs(response.outputs[i]), initial=0.0) for i in rows])
        shown = [rows[j] for j in np.argsort(peak)[::-1][:max_lines]]
        for i in shown:
            y = response.outputs[i]
            (line,) = ax.plot(t, y, lw=1.1, label=response.output_names[i])
            if y.size:
                k = int(np.argmax(np.abs(y)))
                ax.plot(t[k], y[k], "o", ms=4, color=line.get_color())
        unit = response.units[rows[0]]
        ax.set_ylabel(f"{key}\n[{unit}]", fontsize=9)
        ax.grid(True, lw=0.3, alpha=0.6)
        hidden = len(rows) - len(shown)
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.0, 1.0), frameon=False,
                  title=f"+{hidden} smaller" if hidden else None, title_fontsize=7)
    axes[-1].set_xlabel("time [s]")
    fig.suptitle(f"Time response of {response.name!r} (peaks marked)"
                 + (f"; zero throughout: {', '.join(zero)}" if zero else ""), fontsize=10)
    return fig
