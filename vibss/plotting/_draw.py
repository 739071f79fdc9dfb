"""Drawing a :class:`~vibss.plotting._scene.Scene` into matplotlib axes, in 2-D or 3-D views.

A *view* is ``"iso"`` (an orthographic 3-D axes seen from the isometric direction), or one of the
orthographic projections ``"xz"`` (front), ``"yz"`` (side), ``"xy"`` (top) drawn in plain 2-D axes.
:class:`Drawing` creates the artists of one state of the model (undeformed or moved) and can
update them in place, which is what the animation needs.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, cast

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from ..errors import ModelError
from ..model.model import GROUND
from ._scene import BOX_EDGES, Moved, Scene, zigzag

if TYPE_CHECKING:
    from mpl_toolkits.mplot3d import Axes3D

__all__ = ["VIEWS", "VIEW_TITLES", "Drawing", "add_view_axes", "set_limits", "legend_handles",
           "check_view", "body_colour"]

VIEWS = ("iso", "xz", "yz", "xy")
VIEW_TITLES = {"iso": "isometric", "xz": "front (x-z)", "yz": "side (y-z)", "xy": "top (x-y)"}
_AXES = {"xz": (0, 2), "yz": (1, 2), "xy": (0, 1)}
_ELEV, _AZIM = 35.264, -50.0

UNDEFORMED: dict[str, Any] = {"color": "0.6", "lw": 0.9, "ls": "--"}
SPRING: dict[str, Any] = {"color": "0.2", "lw": 1.0}
SPRING_UNDEFORMED: dict[str, Any] = {"color": "0.7", "lw": 0.8}


def body_colour(i: int) -> str:
    """Colour of body ``i`` in every figure."""
    return f"C{i % 10}"


def check_view(view: str, allowed: Sequence[str]) -> None:
    """Raise a ValueError naming the valid views."""
    if view not in allowed:
        raise ModelError(f"view: expected one of {list(allowed)}, got {view!r}")


def add_view_axes(fig: Any, spec: Any, view: str) -> Axes:
    """Add axes for ``view`` to a figure (or subfigure) at a subplot spec, labelled in metres."""
    if view == "iso":
        ax = fig.add_subplot(spec, projection="3d", proj_type="ortho")
        ax.view_init(elev=_ELEV, azim=_AZIM)
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        ax.set_zlabel("z [m]")
        ax.tick_params(labelsize=7, pad=0)
        for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
            axis.set_pane_color((0.97, 0.97, 0.97, 1.0))
            axis._axinfo["grid"]["linewidth"] = 0.3
    else:
        ax = fig.add_subplot(spec)
        i, j = _AXES[view]
        ax.set_xlabel(f"{'xyz'[i]} [m]")
        ax.set_ylabel(f"{'xyz'[j]} [m]")
        ax.set_aspect("equal", adjustable="datalim")
        ax.grid(True, lw=0.3, alpha=0.5)
        ax.tick_params(labelsize=8)
    return ax


def set_limits(ax: Axes, view: str, points: Sequence[np.ndarray], margin: float = 0.08) -> None:
    """Equal-scale limits covering all ``points`` ((k, 3) arrays, global coordinates [m])."""
    p = np.vstack([np.reshape(x, (-1, 3)) for x in points])
    lo, hi = p.min(axis=0), p.max(axis=0)
    half = 0.5 * float((hi - lo).max()) * (1 + margin) or 0.5
    mid = 0.5 * (lo + hi)
    if view == "iso":
        ax3 = cast("Axes3D", ax)  # add_view_axes made it a 3-D axes
        ax3.set_xlim(mid[0] - half, mid[0] + half)
        ax3.set_ylim(mid[1] - half, mid[1] + half)
        ax3.set_zlim(mid[2] - half, mid[2] + half)
        ax3.set_box_aspect((1, 1, 1))
    else:
        i, j = _AXES[view]
        pad = max(float((hi - lo)[[i, j]].max()) * margin, 0.04 * half)
        ax.update_datalim([(lo[i] - pad, lo[j] - pad), (hi[i] + pad, hi[j] + pad)])
        ax.autoscale_view()


def legend_handles(deformed: bool = True, control_points: bool = False) -> list[Line2D]:
    """Proxy artists for the figure legend."""
    h = [Line2D([], [], **UNDEFORMED, label="undeformed")]
    if deformed:
        h.append(Line2D([], [], color="C0", lw=1.6, label="deformed (colour per body)"))
    h.append(Line2D([], [], **SPRING, label="mount"))
    if control_points:
        h.append(Line2D([], [], color="k", marker="^", ls="none", mfc="w", label="control point"))
    return h


class _Painter:
    """Lines and markers in one axes, projected for its view."""

    def __init__(self, ax: Axes, view: str) -> None:
        self.ax, self.view = ax, view
        if view == "iso":
            e, a = np.deg2rad(_ELEV), np.deg2rad(_AZIM)
            self.eye = np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])

    def _xy(self, pts: np.ndarray) -> tuple[np.ndarray, ...]:
        pts = np.reshape(pts, (-1, 3))
        if self.view == "iso":
            return pts[:, 0], pts[:, 1], pts[:, 2]
        i, j = _AXES[self.view]
        return pts[:, i], pts[:, j]

    def line(self, pts: np.ndarray, **style: Any) -> Any:
        (artist,) = self.ax.plot(*self._xy(pts), **style)
        return artist

    def set(self, artist: Any, pts: np.ndarray) -> None:
        xy = self._xy(pts)
        if self.view == "iso":
            artist.set_data_3d(*xy)
        else:
            artist.set_data(*xy)

    def text(self, pt: np.ndarray, s: str, **style: Any) -> None:
        xy = [float(v[0]) for v in self._xy(pt)]
        ax: Any = self.ax  # Axes.text(x, y, s) or Axes3D.text(x, y, z, s)
        ax.text(*xy, s, **style)

    def side(self, d: np.ndarray) -> np.ndarray | None:
        """Unit vector across direction ``d`` that shows in this view; None if seen end-on."""
        d = np.asarray(d, float)
        if self.view == "iso":
            side = np.cross(d, self.eye)
            if np.linalg.norm(side) < 1e-9 * max(float(np.linalg.norm(d)), 1e-12):
                side = np.cross(d, [1.0, 0.0, 0.0])
        else:
            i, j = _AXES[self.view]
            if np.hypot(d[i], d[j]) < 0.1 * np.linalg.norm(d):
                return None
            side = np.zeros(3)
            side[[i, j]] = [-d[j], d[i]]
        n = float(np.linalg.norm(side))
        return side / n if n > 0 else None

    def spring(self, a: np.ndarray, b: np.ndarray, width: float) -> np.ndarray:
        """3-D points of a spring symbol from ``a`` to ``b``; a small ring where seen end-on."""
        side = self.side(b - a)
        if side is None:
            i, j = _AXES[self.view]
            t = np.linspace(0, 2 * np.pi, 13)
            ring = np.tile(b, (13, 1))
            ring[:, i] += width * np.cos(t)
            ring[:, j] += width * np.sin(t)
            return ring
        return zigzag(a, b, side, width)


class Drawing:
    """The artists of one state of a scene in one axes.

    Parameters
    ----------
    ax : Axes
        Target axes (3-D for ``view="iso"``).
    view : str
        One of :data:`VIEWS`.
    scene : Scene
        The model's geometry.
    moved : Moved
        The state drawn (``scene.moved(0 * q)`` for the undeformed one).
    deformed : bool
        Coloured (deformed) or grey (undeformed) style.
    labels : bool
        Write body, mount and control-point names.
    ground : bool or None
        Draw the ground symbols; default: with the undeformed state only.
    """

    def __init__(self, ax: Axes, view: str, scene: Scene, moved: Moved, deformed: bool,
                 labels: bool = False, ground: bool | None = None) -> None:
        self.p = _Painter(ax, view)
        self.scene = scene
        self.width = 0.035 * scene.size
        model = scene.model
        self.boxes: list[Any] = []
        self.cogs: list[Any] = []
        for i, c in enumerate(moved.corners):
            style = ({"color": body_colour(i), "lw": 1.6} if deformed else UNDEFORMED)
            self.boxes.append(self.p.line(self._edges(c), **style))
            self.cogs.append(self.p.line(moved.cogs[i], marker="o", ms=4 if deformed else 3, ls="none",
                                         color=style["color"]))
        sstyle = SPRING if deformed else SPRING_UNDEFORMED
        self.to_ground = np.array([m.to == GROUND for m in model.mounts], dtype=bool)
        self.springs = self.p.line(self._springs(moved), **sstyle)
        self.ground_points = self.p.line(moved.mount_body[self.to_ground], marker="s", ms=3.5, ls="none",
                                         color=sstyle["color"])
        self.body_points = self.p.line(moved.mount_body[~self.to_ground], marker="D", ms=4, ls="none",
                                       color=sstyle["color"])
        self.controls = self.p.line(moved.control_points, marker="^", ms=6, ls="none", mfc="w",
                                    mec="k" if deformed else "0.6")
        if (not deformed) if ground is None else ground:
            self._ground()
        if labels:
            self._labels(moved)

    @staticmethod
    def _edges(corners: np.ndarray) -> np.ndarray:
        """Box edges as one polyline with NaN breaks."""
        segs = [np.vstack([corners[a], corners[b], [np.nan] * 3]) for a, b in BOX_EDGES]
        return np.vstack(segs)

    def _springs(self, moved: Moved) -> np.ndarray:
        """All spring symbols as one polyline with NaN breaks."""
        parts = []
        for k, m in enumerate(self.scene.model.mounts):
            if m.to == GROUND:
                parts.append(self.p.spring(moved.mount_to[k], moved.mount_body[k], self.width))
            else:   # body-to-body: zero length; draw the stretch between the two sides
                parts.append(np.vstack([moved.mount_to[k], moved.mount_body[k]]))
            parts.append(np.full((1, 3), np.nan))
        return np.vstack(parts) if parts else np.zeros((0, 3))

    def _ground(self) -> None:
        """A hatched ground symbol at the fixed end of every ground spring (one artist)."""
        segs = []
        for k, m in enumerate(self.scene.model.mounts):
            if m.to != GROUND:
                continue
            a, d = self.scene.anchors[k], self.scene.spring_axis[k]
            side = self.p.side(d)
            if side is None:
                continue
            side = 1.6 * self.width * side
            segs += [a - side, a + side, [np.nan] * 3]
            for s in np.linspace(-1, 1, 4):
                t = a + s * side
                segs += [t, t - 0.6 * self.width * d - 0.3 * side, [np.nan] * 3]
        if segs:
            self.p.line(np.array(segs), color="0.35", lw=0.9)

    def _labels(self, moved: Moved) -> None:
        model = self.scene.model
        for i, b in enumerate(model.bodies):
            self.p.text(moved.cogs[i], f"  {b.name}", color=body_colour(i), fontsize=9, weight="bold")
        for k, m in enumerate(model.mounts):
            self.p.text(moved.mount_body[k], f" {m.name}", color="0.3", fontsize=7)
        for k, c in enumerate(model.control_points):
            self.p.text(moved.control_points[k], f" {c.name}", color="k", fontsize=7, style="italic")

    def update(self, moved: Moved) -> None:
        """Move the artists to another state of the same scene."""
        for i, c in enumerate(moved.corners):
            self.p.set(self.boxes[i], self._edges(c))
            self.p.set(self.cogs[i], moved.cogs[i])
        self.p.set(self.springs, self._springs(moved))
        self.p.set(self.ground_points, moved.mount_body[self.to_ground])
        self.p.set(self.body_points, moved.mount_body[~self.to_ground])
        self.p.set(self.controls, moved.control_points)

    def artists(self) -> list[Any]:
        """Every artist that :meth:`update` changes."""
        return self.boxes + self.cogs + [self.springs, self.ground_points, self.body_points, self.controls]


def new_figure(width: float, height: float) -> Figure:
    """A figure with an Agg canvas, independent of pyplot's global state."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    fig = Figure(figsize=(width, height), layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def plain_frequency_axis(ax: Axes) -> None:
    """Log frequency axis labelled in plain numbers (0.5, 1, 2, 5, 10, 20, 50 ... Hz), not powers of ten.

    Labels sit at 1, 2 and 5 times each power of ten inside the axis range; minor ticks stay unlabelled.
    """
    from matplotlib.ticker import FixedLocator, FuncFormatter, NullFormatter

    lo, hi = ax.get_xlim()
    if not (lo > 0 and hi > lo):
        return
    ticks = [m * 10.0 ** e for e in range(int(np.floor(np.log10(lo))), int(np.ceil(np.log10(hi))) + 1)
             for m in (1, 2, 5) if lo <= m * 10.0 ** e <= hi]
    if len(ticks) < 2:
        return
    ax.xaxis.set_major_locator(FixedLocator(ticks))
    ax.xaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
    ax.xaxis.set_minor_formatter(NullFormatter())
