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
           "check_view", "body_color", "place_labels"]

VIEWS = ("iso", "xz", "yz", "xy")
VIEW_TITLES = {"iso": "isometric", "xz": "front (x-z)", "yz": "side (y-z)", "xy": "top (x-y)"}
_AXES = {"xz": (0, 2), "yz": (1, 2), "xy": (0, 1)}
_ELEV, _AZIM = 35.264, -50.0

UNDEFORMED: dict[str, Any] = {"color": "0.6", "lw": 0.9, "ls": "--"}
SPRING: dict[str, Any] = {"color": "0.2", "lw": 1.0}
SPRING_UNDEFORMED: dict[str, Any] = {"color": "0.7", "lw": 0.8}


def body_color(i: int) -> str:
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
        Collect body, mount and control-point names; :meth:`place_labels` writes them once the
        axes limits are final.
    ground : bool or None
        Draw the ground symbols; default: with the undeformed state only.
    outline : str or None
        One colour for every body's outline and centre of gravity (the model drawing, where red,
        green and blue mean a mount's local axes); default: each body's own colour.
    """

    def __init__(self, ax: Axes, view: str, scene: Scene, moved: Moved, deformed: bool,
                 labels: bool = False, ground: bool | None = None, outline: str | None = None) -> None:
        self.p = _Painter(ax, view)
        self.view = view
        self.scene = scene
        self.label_items: list[tuple[np.ndarray, str, dict[str, Any]]] = []
        self.width = 0.035 * scene.size
        model = scene.model
        self.boxes: list[Any] = []
        self.cogs: list[Any] = []
        for i, c in enumerate(moved.corners):
            style = ({"color": outline or body_color(i), "lw": 1.6} if deformed else UNDEFORMED)
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
        """Collect the names to write (bodies first, then control points, then mounts); they are
        placed by :meth:`place_labels` once the axes limits are final."""
        model = self.scene.model
        items = self.label_items
        for i, b in enumerate(model.bodies):
            items.append((moved.cogs[i], b.name, {"color": body_color(i), "fontsize": 9, "weight": "bold"}))
        for k, c in enumerate(model.control_points):
            items.append((moved.control_points[k], c.name, {"color": "k", "fontsize": 7, "style": "italic"}))
        for k, m in enumerate(model.mounts):
            items.append((moved.mount_body[k], m.name, {"color": "0.3", "fontsize": 7}))

    def place_labels(self, avoid: Sequence[np.ndarray] = (), layout: bool = True) -> list[Any]:
        """Write the collected names beside their points without overlapping each other, the
        points, the springs or the points in ``avoid`` ((k, 3) arrays [m]; greedy: the first of a
        ring of offsets that collides with nothing placed so far, else the least-overlapping one).
        Call after the axes limits are set; ``layout=False`` when the figure was laid out since
        (:func:`place_labels`). Returns the texts."""
        sc = self.scene
        springs = [sc.anchors + f * (sc.mount_points - sc.anchors) for f in (0.0, 0.25, 0.5, 0.75)]
        # the ring drawn where a spring is seen end-on, and the spring's width
        rings = [sc.mount_points + s * self.width * e for e in np.eye(3) for s in (-1.0, 1.0)]
        return place_labels(self.p.ax, self.view, self.label_items, [*springs, *rings, *avoid], layout)

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


_OFFSETS = [(dx * r, dy * r, ha, va) for r in (1.0, 2.2, 3.6)
            for dx, dy, ha, va in ((5, 2, "left", "bottom"), (5, -2, "left", "top"), (-5, 2, "right", "bottom"),
                                   (-5, -2, "right", "top"), (0, 6, "center", "bottom"), (0, -6, "center", "top"))]
"""Candidate label offsets [points] from the labelled point, nearest first, with the alignment that
keeps the text on that side."""


def _projected(ax: Axes, view: str, pt: np.ndarray) -> tuple[float, float]:
    """2-D data coordinates of a 3-D point in this axes (the 3-D projection for ``iso``)."""
    p = np.reshape(np.asarray(pt, float), 3)
    if view == "iso":
        from mpl_toolkits.mplot3d import proj3d

        x, y, _ = proj3d.proj_transform(p[0], p[1], p[2], cast("Axes3D", ax).get_proj())
        return float(x), float(y)
    i, j = _AXES[view]
    return float(p[i]), float(p[j])


def place_labels(ax: Axes, view: str, items: Sequence[tuple[np.ndarray, str, dict[str, Any]]],
                 avoid: Sequence[np.ndarray] = (), layout: bool = True) -> list[Any]:
    """Write names beside 3-D points, greedily avoiding each other and the points.

    Each label tries the offsets of :data:`_OFFSETS` in turn and takes the first whose box overlaps
    no label placed before it, no labelled point and stays inside the axes; failing that, the one
    with the least overlap. Items earlier in ``items`` are placed first.

    Parameters
    ----------
    ax : Axes
        The axes (3-D for ``view="iso"``), limits already set.
    view : str
        One of :data:`VIEWS`.
    items : sequence of (point, text, style)
        Point [m] (global), text and ``Axes.annotate`` keyword arguments.
    avoid : sequence of (k, 3) ndarray
        Further points [m] (global) the labels should not cover (spring symbols, arrow tips).
    layout : bool
        Lay the figure out first (a draw without rendering). ``False`` where it was laid out since
        its last change: the labels of one panel move no other (they are clipped to their axes, so
        constrained layout leaves them out), and the panels of one figure share one layout.

    Returns
    -------
    list of matplotlib.text.Annotation
    """
    from matplotlib.transforms import Bbox

    if not items:
        return []
    fig = cast(Figure, ax.get_figure(root=True))
    if layout:
        fig.draw_without_rendering()                # final layout, so display boxes are meaningful
    renderer = cast(Any, fig.canvas).get_renderer()
    frame = ax.get_window_extent(renderer)
    xy = [_projected(ax, view, pt) for pt, _, _ in items]
    disp = ax.transData.transform(np.array(xy))
    points = [Bbox.from_bounds(x - 3, y - 3, 6, 6) for x, y in disp]
    extra = np.vstack([np.reshape(a, (-1, 3)) for a in avoid]) if len(avoid) else np.zeros((0, 3))
    if extra.size:
        others = ax.transData.transform(np.array([_projected(ax, view, p) for p in extra]))
        points += [Bbox.from_bounds(x - 3, y - 3, 6, 6) for x, y in others]

    def overlap(a: Any, b: Any) -> float:
        w = min(a.x1, b.x1) - max(a.x0, b.x0)
        h = min(a.y1, b.y1) - max(a.y0, b.y0)
        return w * h if w > 0 and h > 0 else 0.0

    placed: list[Any] = []
    out = []
    for k, ((_, text, style), at) in enumerate(zip(items, xy)):
        ann = ax.annotate(text, xy=at, xycoords="data", xytext=_OFFSETS[0][:2], textcoords="offset points",
                          ha=_OFFSETS[0][2], va=_OFFSETS[0][3], annotation_clip=False, **style)
        best, best_cost = _OFFSETS[0], np.inf
        for cand in _OFFSETS:
            ann.xyann = cand[:2]
            ann.set_horizontalalignment(cast(Any, cand[2]))
            ann.set_verticalalignment(cast(Any, cand[3]))
            box = ann.get_window_extent(renderer)
            inside = overlap(box, frame)
            cost = (sum(overlap(box, b) for b in placed) + sum(overlap(box, p) for j, p in enumerate(points) if j != k)
                    + (box.width * box.height - inside))
            if cost < best_cost:
                best, best_cost = cand, cost
            if cost == 0:
                break
        ann.xyann = best[:2]
        ann.set_horizontalalignment(cast(Any, best[2]))
        ann.set_verticalalignment(cast(Any, best[3]))
        placed.append(ann.get_window_extent(renderer))
        out.append(ann)
    return out


def new_figure(width: float, height: float) -> Figure:
    """A figure with an Agg canvas, independent of pyplot's global state."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    fig = Figure(figsize=(width, height), layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def fitted_title(ax: Axes, text: str, fontsize: float = 10) -> None:
    """``ax.set_title(text)``, wrapped onto as many lines as the figure's width needs (a long model
    name ran off both edges of a narrow figure)."""
    import textwrap

    width_pt = ax.figure.bbox.width * 72.0 / ax.figure.dpi
    chars = max(20, int(width_pt / (0.55 * fontsize)))      # a DejaVu Sans character: ~0.55 em
    ax.set_title(textwrap.fill(text, chars), fontsize=fontsize)


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
