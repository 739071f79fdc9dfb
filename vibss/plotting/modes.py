"""Mode-shape drawings and animations."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast, overload

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure, SubFigure

from ..errors import ModelError
from ._draw import (VIEW_TITLES, VIEWS, Drawing, add_view_axes, check_view, legend_handles,
                    new_figure, set_limits)
from ._scene import Scene

if TYPE_CHECKING:      # a figure is handed computed modes; it imports no analysis
    from ..modal.result import Modes

__all__ = ["plot_modes", "animate_mode", "mode_title", "mode_motion", "plot_mode_tracks"]

AUTO_SCALE = 0.12
"""Default largest drawn displacement, as a fraction of the drawing's size."""


def mode_title(modes: Modes, k: int) -> str:
    """``"mode k: f Hz (CPM), direction"`` for mode index ``k`` (0-based; printed 1-based)."""
    f = modes.frequency_hz[k]
    if modes.rigid[k]:
        return f"mode {k + 1}: 0 Hz (rigid), {modes.labels[k]}"
    return f"mode {k + 1}: {f:.3g} Hz ({modes.cpm[k]:.0f} CPM), {modes.labels[k]}"


def mode_motion(modes: Modes, k: int, scene: Scene, scale: float | None = None) -> tuple[np.ndarray, float]:
    """The drawn motion of mode ``k``: shape scaled so that its largest point displacement is
    ``scale`` [m] (default 12 % of the drawing's size).

    Returns
    -------
    q : (n,) ndarray
        Scaled body DOFs [m, rad].
    length : float
        The largest drawn displacement [m].
    """
    shape = modes.relative_shapes[:, k]
    biggest = scene.max_displacement(shape)
    length = AUTO_SCALE * scene.size if scale is None else float(scale)
    if not np.isfinite(length) or length <= 0:
        raise ModelError(f"scale: expected a positive length [m], got {scale!r}")
    return shape * (length / biggest if biggest > 0 else 0.0), length


def _which(modes: Modes, which: int | Sequence[int] | None) -> list[int]:
    if which is None:
        return list(range(len(modes)))
    ks = [which] if isinstance(which, (int, np.integer)) else list(which)
    for k in ks:
        if not isinstance(k, (int, np.integer)) or not 0 <= k < len(modes):
            raise ModelError(f"which: mode indices are 0 ... {len(modes) - 1} (0-based), got {k!r}")
    if not ks:
        raise ModelError("which: no mode selected")
    return [int(k) for k in ks]


def _draw_mode(ax: Axes, view: str, scene: Scene, q: np.ndarray) -> Drawing:
    zero = scene.moved(0 * q)
    moved = scene.moved(q)
    Drawing(ax, view, scene, zero, deformed=False)
    drawing = Drawing(ax, view, scene, moved, deformed=True)
    extreme = scene.moved(-q)
    set_limits(ax, view, [zero.corners, moved.corners, extreme.corners, scene.anchors,
                          moved.mount_body, extreme.mount_body, zero.control_points])
    return drawing


@overload
def plot_modes(modes: Modes, which: int | Sequence[int] | None = ..., view: str = ...,
               scale: float | None = ..., ax: None = ..., ncols: int = ..., box: str = ...) -> Figure: ...
@overload
def plot_modes(modes: Modes, which: int | Sequence[int] | None = ..., view: str = ...,
               scale: float | None = ..., ax: Axes | Sequence[Axes] | None = ..., ncols: int = ...,
               box: str = ...) -> Figure | SubFigure: ...
def plot_modes(modes: Modes, which: int | Sequence[int] | None = None, view: str = "iso",
               scale: float | None = None, ax: Axes | Sequence[Axes] | None = None,
               ncols: int = 3, box: str = "auto") -> Figure | SubFigure:
    """Draw mode shapes: each body as a box, mounts as springs, undeformed (grey) and deformed.

    Each body is drawn as the uniform box with its mass and principal moments of inertia, at its
    centre of gravity; ground mounts as springs from a fixed ground symbol to the attachment point
    along the mount's stiffest local axis (the most nearly vertical of equally stiff ones);
    body-to-body mounts as a line showing their stretch; control points as triangles.

    Parameters
    ----------
    modes : Modes
        Result of :func:`vibss.modes`.
    which : int, sequence of int or None
        Mode indices (0-based) to draw; default all.
    view : {"iso", "three", "xz", "yz", "xy"}
        Isometric 3-D view (one panel per mode); ``"three"``: front, side and top views (one row
        of three panels per mode); or one orthographic view.
    scale : float or None
        Largest drawn displacement [m]; default 12 % of the model's size. Mode shapes have no
        absolute size: only the proportions matter.
    ax : Axes, sequence of three Axes, or None
        Draw one mode into existing axes (3-D axes for ``"iso"``; three axes for ``"three"``).
    ncols : int
        Panels per row for ``"iso"`` and single views.
    box : {"auto", "inertia", "mounts"}
        Body outlines: the inertia box, the box enclosing the body's mounts, or the latter where
        the inertia box is small beside the mounts (see :meth:`Scene.of`).

    Returns
    -------
    Figure

    Examples
    --------
    >>> import vibss
    >>> from vibss.plotting import plot_modes
    >>> t = vibss.MountType("t", [1e4, 2e4, 3e4])
    >>> m = vibss.Model([vibss.Body("b", 1000.0, [10, 20, 30])],
    ...                 vibss.symmetric(vibss.Mount("m", t, "b", at=[1, 2, 0])))
    >>> fig = plot_modes(vibss.modes(m), which=[0, 3], view="three")
    >>> len(fig.axes)
    6
    """
    check_view(view, VIEWS + ("three",))
    ks = _which(modes, which)
    scene = Scene.of(modes.model, box=box)
    views = ["xz", "yz", "xy"] if view == "three" else [view]
    if ax is not None:
        axes = [ax] if isinstance(ax, Axes) else list(ax)
        if len(ks) != 1 or len(axes) != len(views):
            raise ModelError(f"ax: with given axes draw exactly one mode into {len(views)} axes "
                             f"(view {view!r}); got {len(ks)} modes and {len(axes)} axes")
        q, _ = mode_motion(modes, ks[0], scene, scale)
        for a, v in zip(axes, views):
            _draw_mode(a, v, scene, q)
            a.set_title(mode_title(modes, ks[0]) if len(views) == 1 else VIEW_TITLES[v], fontsize=9)
        return axes[0].figure  # a SubFigure where the given axes are in one
    if view == "three":
        fig = new_figure(10.5, 3.1 * len(ks) + 0.5)
        subs = np.atleast_1d(cast(Any, fig.subfigures(len(ks), 1)))  # one SubFigure or an array
        for sub, k in zip(subs, ks):
            q, length = mode_motion(modes, k, scene, scale)
            sub.suptitle(f"{mode_title(modes, k)}   (largest drawn displacement {length:.3g} m)",
                         fontsize=10, weight="bold")
            grid = sub.add_gridspec(1, 3)
            for j, v in enumerate(views):
                a = add_view_axes(sub, grid[0, j], v)
                _draw_mode(a, v, scene, q)
                a.set_title(VIEW_TITLES[v], fontsize=9)
    else:
        cols = max(1, min(int(ncols), len(ks)))
        rows = -(-len(ks) // cols)
        panel = 3.6 if view == "iso" else 3.2
        fig = new_figure(panel * cols + 0.3, panel * rows + 0.6)
        grid = fig.add_gridspec(rows, cols)
        for n, k in enumerate(ks):
            a = add_view_axes(fig, grid[n // cols, n % cols], view)
            q, _ = mode_motion(modes, k, scene, scale)
            _draw_mode(a, view, scene, q)
            a.set_title(mode_title(modes, k), fontsize=9)
    fig.suptitle(f"Mode shapes of {modes.model.name!r}", fontsize=11)
    fig.legend(handles=legend_handles(control_points=bool(modes.model.control_points)),
               loc="outside lower center", ncols=4, fontsize=8, frameon=False)
    return fig


def animate_mode(modes: Modes, k: int, path: str | Path, frames: int = 24, view: str = "iso",
                 scale: float | None = None, fps: int = 12) -> Path:
    """Write an animated GIF of mode ``k`` oscillating about the undeformed position.

    Parameters
    ----------
    modes : Modes
        Result of :func:`vibss.modes`.
    k : int
        Mode index (0-based).
    path : str or Path
        Output file (``.gif``).
    frames : int
        Frames per cycle.
    view : {"iso", "xz", "yz", "xy"}
        View (see :func:`plot_modes`).
    scale : float or None
        Largest drawn displacement [m]; default 12 % of the model's size.
    fps : int
        Frames per second of the GIF.

    Returns
    -------
    Path
        The file written.

    Examples
    --------
    >>> import tempfile, pathlib, vibss
    >>> t = vibss.MountType("t", [1e4, 2e4, 3e4])
    >>> m = vibss.Model([vibss.Body("b", 1000.0, [10, 20, 30])],
    ...                 vibss.symmetric(vibss.Mount("m", t, "b", at=[1, 2, 0])))
    >>> out = animate_mode(vibss.modes(m), 3, pathlib.Path(tempfile.mkdtemp()) / "rx.gif", frames=4)
    >>> out.stat().st_size > 0
    True
    """
    from matplotlib.animation import FuncAnimation, PillowWriter

    check_view(view, VIEWS)
    (k,) = _which(modes, k)
    if not isinstance(frames, (int, np.integer)) or frames < 2:
        raise ModelError(f"frames: expected an integer >= 2, got {frames!r}")
    scene = Scene.of(modes.model)
    q, _ = mode_motion(modes, k, scene, scale)
    fig = new_figure(5.0, 4.6)
    ax = add_view_axes(fig, fig.add_gridspec(1, 1)[0, 0], view)
    drawing = _draw_mode(ax, view, scene, q)
    ax.set_title(mode_title(modes, k), fontsize=10)
    phases = np.sin(2 * np.pi * np.arange(frames) / frames)

    def step(i: int) -> list[Any]:
        drawing.update(scene.moved(phases[i] * q))
        return drawing.artists()

    fig.canvas.draw()                 # lay out once; the frames keep that layout
    fig.set_layout_engine("none")
    anim = FuncAnimation(fig, step, frames=frames, blit=False)
    out = Path(path)
    anim.save(out, writer=PillowWriter(fps=fps))
    return out


def plot_mode_tracks(tracks: Any, x: Any = None, xlabel: str = "step", ax: Any = None) -> Figure:
    """Tracked natural frequencies against the swept parameter: one colour and legend entry per
    track (its label at the first step), weak matches (MAC below 0.5) ringed.

    Parameters
    ----------
    tracks : vibss.modal.tracking.ModeTracks
    x : (steps,) array_like or None
        The swept parameter's values (default the step number).
    xlabel : str
        Its axis label, with its unit (``"V-angle [deg]"``).
    ax : Axes or None
        Draw into it; default a new figure.
    """
    f = np.asarray(tracks.frequency_hz)
    xs = np.arange(f.shape[0]) if x is None else np.asarray(x, dtype=float)
    if ax is None:
        fig = new_figure(7.5, 4.2)
        ax = fig.subplots()
    fig = ax.figure
    colours = [f"C{j % 10}" for j in range(f.shape[1])]
    for j, lab in enumerate(tracks.labels):
        ax.plot(xs, f[:, j], "o-", ms=3, color=colours[j], label=f"{j + 1}: {lab} ({f[0, j]:.3g} Hz first)")
    weak = np.zeros_like(f, dtype=bool)
    weak[1:] = np.asarray(tracks.mac) < 0.5
    if weak.any():
        s, k = np.nonzero(weak)
        ax.plot(xs[s], f[s, k], "o", mfc="none", mec="k", ms=8, label="MAC < 0.5 (mode changed)")
    ax.set_xlabel(xlabel)
    ax.set_ylabel("natural frequency [Hz]")
    ax.grid(True, alpha=0.3)
    ax.legend(title="tracked by MAC", fontsize="small", loc="upper left", bbox_to_anchor=(1.01, 1.0),
              borderaxespad=0.0)
    return fig
