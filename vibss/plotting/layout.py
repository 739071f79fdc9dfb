"""The model's layout: bodies, mounts with their local axes, control points."""

from __future__ import annotations

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from .._deprecated import module_aliases
from ..model.model import Model
from ._draw import (VIEW_TITLES, VIEWS, Drawing, add_view_axes, check_view, legend_handles,
                    new_figure, set_limits)
from ._scene import Scene

__all__ = ["plot_model", "AXIS_COLORS"]

AXIS_COLORS = ("tab:red", "tab:green", "tab:blue")
"""Colours of a mount's local axes 1, 2, 3."""

OUTLINE = "0.15"
"""Colour of the body outlines in the model drawing: no body colour may read as a mount axis."""


def _axes_arrows(ax: Axes, view: str, scene: Scene, length: float) -> None:
    """Short arrows along each mount's local axes 1, 2, 3."""
    model = scene.model
    for k, m in enumerate(model.mounts):
        p = scene.mount_points[k]
        for j in range(3):
            d = length * m.orientation.matrix[:, j]
            if view == "iso":
                ax.quiver(*p, *d, color=AXIS_COLORS[j], lw=1.2, arrow_length_ratio=0.3)
            else:
                i0, i1 = {"xz": (0, 2), "yz": (1, 2), "xy": (0, 1)}[view]
                if np.hypot(d[i0], d[i1]) < 0.05 * length:
                    continue
                ax.annotate("", xy=(p[i0] + d[i0], p[i1] + d[i1]), xytext=(p[i0], p[i1]),
                            arrowprops={"arrowstyle": "->", "color": AXIS_COLORS[j], "lw": 1.2})


def plot_model(model: Model, view: str = "iso", labels: bool = True,
               axis_length: float | None = None, box: str = "auto") -> Figure:
    """Draw the model: bodies (inertia boxes at their COGs), mounts with their local axes
    (short arrows: axis 1 red, 2 green, 3 blue) and a spring along each mount's stiffest axis,
    and control points (triangles); names placed so they do not overlap.

    Parameters
    ----------
    model : Model
        The model.
    view : {"iso", "three", "xz", "yz", "xy"}
        Isometric 3-D view, front/side/top views, or one orthographic view.
    labels : bool
        Write the names of bodies, mounts and control points.
    axis_length : float or None
        Length of the local-axis arrows [m]; default 8 % of the model's size.
    box : {"auto", "inertia", "mounts"}
        Body outlines (see :func:`vibss.plotting.plot_modes`).

    Returns
    -------
    Figure

    Examples
    --------
    >>> import vibss
    >>> t = vibss.MountType("t", [1e4, 2e4, 3e4])
    >>> m = vibss.Model([vibss.Body("b", 1000.0, [10, 20, 30])],
    ...                 vibss.symmetric(vibss.Mount("m", t, "b", at=[1, 2, 0])))
    >>> len(plot_model(m, view="three").axes)
    3
    """
    check_view(view, VIEWS + ("three",))
    scene = Scene.of(model, box=box)
    views = ["xz", "yz", "xy"] if view == "three" else [view]
    length = 0.08 * scene.size if axis_length is None else float(axis_length)
    if view == "three":
        fig = new_figure(12.0, 4.4)
    else:
        fig = new_figure(6.4, 5.8)
    grid = fig.add_gridspec(1, len(views))
    rest = scene.moved(np.zeros(model.n_dof))
    drawings: list[Drawing] = []
    for j, v in enumerate(views):
        ax = add_view_axes(fig, grid[0, j], v)
        drawings.append(Drawing(ax, v, scene, rest, deformed=True, labels=labels, ground=True,
                                outline=OUTLINE))
        _axes_arrows(ax, v, scene, length)
        tips = [scene.mount_points[k] + length * m.orientation.matrix.T
                for k, m in enumerate(model.mounts)]
        set_limits(ax, v, [rest.corners, scene.anchors, rest.control_points, *tips])
        ax.set_title(VIEW_TITLES[v], fontsize=9)
    fig.suptitle(f"Model {model.name!r}: {len(model.bodies)} bod{'y' if len(model.bodies) == 1 else 'ies'}, "
                 f"{len(model.mounts)} mounts", fontsize=11)
    handles = legend_handles(deformed=False, control_points=bool(model.control_points))[1:]
    handles = [Line2D([], [], color=OUTLINE, lw=1.6, label="body outline")] + handles
    handles += [Line2D([], [], color=c, lw=1.5, label=f"mount axis {j + 1}") for j, c in enumerate(AXIS_COLORS)]
    # a single panel is half as wide: two legend rows instead of one clipped row
    fig.legend(handles=handles, loc="outside lower center", ncols=min(len(handles), 7 if len(views) > 1 else 4),
               fontsize=8, frameon=False)
    tips = [scene.mount_points[k] + f * length * m.orientation.matrix.T
            for k, m in enumerate(model.mounts) for f in (0.25, 0.5, 0.75, 1.0)]
    for j, d in enumerate(drawings):    # names last: their places depend on the final layout (one for all)
        d.place_labels(avoid=tips, layout=j == 0)
    return fig


__getattr__ = module_aliases(__name__, {"AXIS_COLOURS": ("vibss.plotting.layout.AXIS_COLORS", lambda: AXIS_COLORS)})
