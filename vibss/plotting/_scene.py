"""Geometry of the drawings, without matplotlib: boxes, springs, points and their motion.

A :class:`Scene` holds, for one model, everything a drawing needs in global coordinates [m]:
one box per body (the uniform box with the body's mass and principal moments of inertia), the
mount points, the ground anchor of each spring, the control points, and a characteristic
size. :meth:`Scene.moved` places the bodies after a (scaled) motion ``q`` of the body DOFs, using
the exact rotation of the small-rotation vector so that boxes stay rigid in the picture.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.spatial.transform import Rotation

from ..errors import ModelError
from ..linear.eigen.small import symmetric_eigen
from ..model.geometry import point_transfer
from ..model.model import GROUND, Model

__all__ = ["Scene", "box_half_sides", "BOX_EDGES", "zigzag", "spring_direction"]

BOX_EDGES = np.array([[0, 1], [1, 3], [3, 2], [2, 0], [4, 5], [5, 7], [7, 6], [6, 4],
                      [0, 4], [1, 5], [2, 6], [3, 7]])
"""Corner index pairs of the 12 edges of a box whose corners are numbered by sign bits."""

_SIGNS = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], float)


def box_half_sides(mass: float, moments: np.ndarray) -> np.ndarray:
    """Half side lengths [m] of the uniform box with the given mass and principal moments.

    For a box of sides a, b, c: ``I1 = m (b^2 + c^2) / 12`` and so on, hence
    ``a^2 = 6 (I2 + I3 - I1) / m``.

    Parameters
    ----------
    mass : float
        Mass [kg].
    moments : (3,) array_like
        Principal moments of inertia [kg m^2].

    Returns
    -------
    (3,) ndarray
        Half sides along the principal axes [m] (zero where the inertia is degenerate).

    Examples
    --------
    >>> box_half_sides(12.0, [2.0, 2.0, 2.0])   # a 1 m cube of 12 kg has I = 12 * 2 / 12 = 2
    array([0.5, 0.5, 0.5])
    """
    i = np.asarray(moments, float)
    sq = 6.0 * (i.sum() - 2.0 * i) / mass
    return 0.5 * np.sqrt(np.clip(sq, 0.0, None))


def spring_direction(matrix: np.ndarray, stiffness: Any) -> np.ndarray:
    """Unit direction [-] in which a mount's spring symbol is drawn: its stiffest local axis (a strut
    along its rod, a compression mount along its compression axis); among equally stiff axes the
    most nearly vertical. Pointing up (positive global z), or along the positive largest component
    for a horizontal axis.

    Parameters
    ----------
    matrix : (3, 3) ndarray
        Local axes 1, 2, 3 as columns, in global coordinates.
    stiffness : (3,) array_like
        Stiffness along the local axes [N/m].

    Returns
    -------
    (3,) ndarray
    """
    t = np.asarray(matrix, float)
    k = np.abs(np.asarray(stiffness, float).ravel()[:3])
    stiffest = np.flatnonzero(k >= (1 - 1e-9) * k.max()) if k.size == 3 and k.max() > 0 else np.arange(3)
    j = int(stiffest[np.argmax(np.abs(t[2, stiffest]))])
    d = t[:, j]
    if abs(d[2]) > 1e-9:
        return d * np.sign(d[2])
    return d * (np.sign(d[int(np.argmax(np.abs(d)))]) or 1.0)


def zigzag(a: np.ndarray, b: np.ndarray, side: np.ndarray, width: float, coils: int = 5) -> np.ndarray:
    """Points of a spring symbol from ``a`` to ``b`` (any dimension), zig-zagging along ``side``.

    The first and last sixth of the length are straight; the middle alternates by ``width``.
    """
    a, b, side = (np.asarray(v, float) for v in (a, b, side))
    t = np.concatenate([[0.0, 1 / 6], np.linspace(1 / 6, 5 / 6, 2 * coils + 1)[1:-1], [5 / 6, 1.0]])
    off = np.zeros_like(t)
    off[2:-2] = width * np.where(np.arange(len(t) - 4) % 2 == 0, 1.0, -1.0)
    return a + np.outer(t, b - a) + np.outer(off, side)


@dataclass(frozen=True, eq=False)
class Scene:
    """Undeformed geometry of a model for drawing.

    Attributes
    ----------
    model : Model
        The model drawn.
    cogs : (nb, 3) ndarray
        Centres of gravity [m].
    corners : (nb, 8, 3) ndarray
        Box corners [m] (global coordinates).
    mount_points : (nm, 3) ndarray
        Attachment points [m].
    anchors : (nm, 3) ndarray
        Fixed end of each ground spring's symbol [m] (the point itself for body-to-body mounts).
    spring_axis : (nm, 3) ndarray
        Unit direction of each spring symbol: the mount's stiffest local axis (see
        :func:`spring_direction`).
    control_points : (nc, 3) ndarray
        Control points [m].
    size : float
        Characteristic size of the drawing [m]: the largest extent of all of the above.
    """

    model: Model
    cogs: np.ndarray
    corners: np.ndarray
    mount_points: np.ndarray
    anchors: np.ndarray
    spring_axis: np.ndarray
    control_points: np.ndarray
    size: float

    @classmethod
    def of(cls, model: Model, box: str = "auto", spring_length: float = 0.15) -> Scene:
        """Build the scene of ``model``.

        Parameters
        ----------
        model : Model
            The model.
        box : {"auto", "inertia", "mounts"}
            Body outlines: the uniform box with the body's mass and principal moments
            (``"inertia"``), that box grown to enclose the body's mount points (``"mounts"``), or
            the latter only where the inertia box is much smaller than the mount layout (``"auto"``).
        spring_length : float
            Length of the spring symbols as a fraction of the drawing's size [-].
        """
        if box not in ("auto", "inertia", "mounts"):
            raise ModelError(f"box: expected 'auto', 'inertia' or 'mounts', got {box!r}")
        cogs = np.array([b.cog for b in model.bodies])
        mpts = np.array([model.mount_point(m) for m in model.mounts]).reshape(-1, 3)
        cpts = np.array([model.body(c.body).cog + model.point(c.body, c.at, c.frame)
                         for c in model.control_points]).reshape(-1, 3)
        pts = np.vstack([cogs, mpts, cpts])
        span = float(np.ptp(pts, axis=0).max()) if len(pts) > 1 else 0.0
        frames = []
        for b in model.bodies:
            moments, axes = symmetric_eigen(b.tensor)
            half = box_half_sides(b.total_mass, moments)
            lo, hi = -half, half.copy()
            own = np.array([mpts[p] for p, m in enumerate(model.mounts) if b.name in (m.body, m.to)])
            if box == "mounts" or (box == "auto" and len(own) > 1
                                   and np.ptp(own @ axes, axis=0).max() > 4 * half.max()):
                # the inertia box is small beside the mounts: draw the mounts' footprint instead
                local = (own - b.cog) @ axes
                lo, hi = np.minimum(lo, local.min(axis=0)), np.maximum(hi, local.max(axis=0))
            frames.append((axes, lo, hi))
        biggest = max(float(np.max(hi - lo)) for _, lo, hi in frames) / 2
        size = max(span, 2 * biggest, 1e-3)
        box_list = []
        for g, (ax, lo, hi) in zip(cogs, frames):
            # a box too thin to see gets a minimum thickness (8 % of the drawing)
            thin = np.maximum(0.04 * size - 0.5 * (hi - lo), 0.0)
            lo, hi = lo - thin, hi + thin
            box_list.append(g + (np.where(_SIGNS > 0, hi, lo)) @ ax.T)
        boxes = np.array(box_list)
        axis = np.zeros_like(mpts)
        anchors = mpts.copy()
        length = spring_length * size
        for p, m in enumerate(model.mounts):
            d = spring_direction(m.orientation.matrix, m.type.stiffness)
            axis[p] = d
            if m.to == GROUND:
                anchors[p] = mpts[p] - length * d
        size = max(size, float(np.ptp(np.vstack([pts, anchors]), axis=0).max()))
        return cls(model, cogs, boxes, mpts, anchors, axis, cpts, size)

    # -- motion ----------------------------------------------------------------------------
    def max_displacement(self, q: np.ndarray) -> float:
        """Largest small-motion displacement [m] of any drawn point under body DOFs ``q``."""
        q = np.asarray(q, float).reshape(-1, 6)
        worst = 0.0
        for i, (g, box) in enumerate(zip(self.cogs, self.corners)):
            pts = np.vstack([box, self._points_of(i)])
            d = point_transfer(pts - g) @ q[i]
            worst = max(worst, float(np.abs(d).max(initial=0.0)), float(np.linalg.norm(d, axis=1).max()))
        return worst

    def _points_of(self, i: int) -> np.ndarray:
        name = self.model.bodies[i].name
        own = [self.mount_points[p] for p, m in enumerate(self.model.mounts) if m.body == name or m.to == name]
        own += [self.control_points[c] for c, cp in enumerate(self.model.control_points) if cp.body == name]
        return np.array(own).reshape(-1, 3)

    def moved(self, q: np.ndarray) -> Moved:
        """Positions after body motion ``q`` ((n,) array, already scaled for drawing)."""
        q = np.asarray(q, float).reshape(-1, 6)
        rots = [Rotation.from_rotvec(q[i, 3:]) for i in range(len(self.cogs))]
        cogs = self.cogs + q[:, :3]

        def place(i: int, x: np.ndarray) -> np.ndarray:
            return cogs[i] + rots[i].apply(np.atleast_2d(x) - self.cogs[i])

        corners = np.array([place(i, c) for i, c in enumerate(self.corners)])
        names = self.model.body_names
        on_body = np.array([place(names.index(m.body), self.mount_points[p])[0]
                            for p, m in enumerate(self.model.mounts)]).reshape(-1, 3)
        on_to = np.array([self.anchors[p] if m.to == GROUND else place(names.index(m.to), self.mount_points[p])[0]
                          for p, m in enumerate(self.model.mounts)]).reshape(-1, 3)
        cps = np.array([place(names.index(c.body), self.control_points[k])[0]
                        for k, c in enumerate(self.model.control_points)]).reshape(-1, 3)
        return Moved(cogs, corners, on_body, on_to, cps)


@dataclass(frozen=True)
class Moved:
    """Positions of the drawn items after a motion [m] (see :meth:`Scene.moved`)."""

    cogs: np.ndarray
    corners: np.ndarray
    mount_body: np.ndarray
    mount_to: np.ndarray
    control_points: np.ndarray
