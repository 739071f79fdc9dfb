"""The modal kinetic-energy distribution as a heat map or stacked bars."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
from matplotlib.figure import Figure
from matplotlib.patches import Patch

from ..errors import ModelError
from ..model.model import DOF_NAMES
from ._draw import fitted_title, new_figure

if TYPE_CHECKING:      # a figure is handed computed modes; it imports no analysis
    from ..modal.result import Modes

__all__ = ["plot_energy"]

_DOF_COLOURS = {"x": "#1f77b4", "y": "#2ca02c", "z": "#d62728",
                "rx": "#aec7e8", "ry": "#98df8a", "rz": "#ff9896"}
_HATCHES = ("", "//", "..", "xx", "\\\\", "oo")


def plot_energy(modes: Modes, kind: str = "heatmap", which: Sequence[int] | None = None) -> Figure:
    """Kinetic-energy distribution of the modes over the body DOFs.

    For mode phi the share of DOF j is ``phi_j (M phi)_j / (phi^T M phi)``; a mode whose energy
    sits in one DOF is decoupled. The heat map shows every share [%] (values of 1 % and more
    written in the cells); the bars stack the shares of each mode, coloured by direction and
    hatched by body.

    Parameters
    ----------
    modes : Modes
        Result of :func:`vibss.modes`.
    kind : {"heatmap", "bar"}
        Presentation.
    which : sequence of int or None
        Mode indices (0-based); default all.

    Returns
    -------
    Figure

    Examples
    --------
    >>> import vibss
    >>> t = vibss.MountType("t", [1e4, 2e4, 3e4])
    >>> m = vibss.Model([vibss.Body("b", 1000.0, [10, 20, 30])],
    ...                 vibss.symmetric(vibss.Mount("m", t, "b", at=[1, 2, 0])))
    >>> fig = plot_energy(vibss.modes(m))
    >>> fig.axes[0].get_xlabel()
    'body DOF'
    """
    if kind not in ("heatmap", "bar"):
        raise ModelError(f"kind: expected 'heatmap' or 'bar', got {kind!r}")
    ks = list(range(len(modes))) if which is None else [int(k) for k in which]
    if not ks or min(ks) < 0 or max(ks) >= len(modes):
        raise ModelError(f"which: mode indices are 0 ... {len(modes) - 1}, got {which!r}")
    e = 100 * modes.energy[ks]
    names = modes.model.body_names
    cols = list(DOF_NAMES) if len(names) == 1 else list(modes.dofs)
    ylabels = [f"{k + 1}: {modes.frequency_hz[k]:.3g} Hz {modes.labels[k]}" for k in ks]
    if kind == "heatmap":
        fig = new_figure(1.2 + 0.62 * len(cols), 1.3 + 0.36 * len(ks))
        ax = fig.add_subplot()
        im = ax.imshow(e, cmap="Blues", vmin=0, vmax=100, aspect="auto")
        for i in range(e.shape[0]):
            for j in range(e.shape[1]):
                if e[i, j] >= 1:
                    ax.text(j, i, f"{e[i, j]:.0f}", ha="center", va="center", fontsize=7,
                            color="w" if e[i, j] > 60 else "k")
        ax.set_xticks(range(len(cols)), cols, rotation=90 if len(names) > 1 else 0, fontsize=8)
        ax.set_yticks(range(len(ks)), ylabels, fontsize=8)
        ax.set_xlabel("body DOF")
        ax.set_ylabel("mode: frequency, direction")
        fig.colorbar(im, ax=ax, label="kinetic energy [%]", shrink=0.9)
    else:
        fig = new_figure(1.5 + 0.5 * len(ks), 4.2)
        ax = fig.add_subplot()
        bottom = np.zeros(len(ks))
        x = np.arange(len(ks))
        for b in range(len(names)):
            for d, dof in enumerate(DOF_NAMES):
                v = e[:, 6 * b + d]
                ax.bar(x, v, bottom=bottom, color=_DOF_COLOURS[dof], hatch=_HATCHES[b % len(_HATCHES)],
                       edgecolor="w", lw=0.5)
                bottom += v
        ax.set_xticks(x, ylabels, rotation=60, ha="right", fontsize=8)
        ax.set_ylim(0, 100)
        ax.set_xlabel("mode: frequency, direction")
        ax.set_ylabel("kinetic energy [%]")
        handles = [Patch(color=c, label=d) for d, c in _DOF_COLOURS.items()]
        if len(names) > 1:
            handles += [Patch(facecolor="w", edgecolor="k", hatch=_HATCHES[b % len(_HATCHES)], label=n)
                        for b, n in enumerate(names)]
        ax.legend(handles=handles, loc="upper left",
                  bbox_to_anchor=(1.0, 1.0), fontsize=8, frameon=False)
    fitted_title(ax, f"Modal kinetic-energy distribution of {modes.model.name!r}")
    return fig
