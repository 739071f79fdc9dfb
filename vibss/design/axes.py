"""Axes and centres of one body on its mounts: torque-roll axis, elastic centre and axes, principal
axes of inertia, the static response to a pure torque.

Conventions: every vector is in global axes; points are relative to the body's centre of gravity
(COG) [m]; the body's 6x6 matrices are taken about its COG with every other body held fixed
(the mount system of that body).

- **Torque-roll axis** (TRA): a free rigid body under a torque ``T e`` about a crank axis ``e`` starts
  to turn about ``J^-1 e`` (``J`` the full inertia tensor about the COG), whatever the mounts.
- **Elastic centre** ``c`` and **elastic axes**: with ``C = K^-1`` (compliance about the COG) a pure
  torque ``T`` turns the body by ``theta = C_rr T`` and moves the COG by ``C_tr T``; the point ``c``
  moves by ``(C_tr - [c]x C_rr) T``. Write ``A = C_tr C_rr^-1``: where ``A`` is skew, ``A = [c]x``
  and every torque turns the body about an axis through ``c`` (an elastic centre exists). In general
  ``c`` is the least-squares point (the skew part of ``A``) and the symmetric part ``A_s`` is the
  residual screw: a rotation ``theta`` about an axis through ``c`` comes with a translation
  ``A_s theta``. The elastic axes are the principal directions of the rotational stiffness about
  ``c`` (``C_rr^-1``); they are *elastic axes* in the strict sense (a force along one gives a
  translation along it, a torque about one a rotation about it) only when the screw vanishes and
  the translational stiffness shares those directions.

Examples
--------
>>> import vibss
>>> t = vibss.MountType("t", [1e5, 1e5, 3e5])
>>> body = vibss.Body("b", 100.0, [2.0, 4.0, 5.0])
>>> m = vibss.Model([body], vibss.symmetric(vibss.Mount("m", t, "b", at=[0.3, 0.2, -0.1])))
>>> ea = elastic_axes(m)
>>> ea.exists, ea.center.round(6).tolist()
(True, [0.0, 0.0, -0.1])
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..linear.eigen.small import symmetric_eigen
from .._deprecated import renamed_attribute
from ..results import ReadOnly, Result, TextTable, jsonable, require_pandas
from ..linear.plant.assemble import Assembly
from ..linear.solve.static import static_solve
from ..model.model import Model
from ._common import body_blocks, body_name, unit_axis

__all__ = ["torque_roll_axis", "principal_axes", "elastic_axes", "torque_response", "design_axes",
           "plot_design_axes", "ElasticAxes", "TorqueResponse", "DesignAxes", "EXIST_RTOL"]

EXIST_RTOL = 1e-6
"""Elastic centre / axes exist when the residual screw (and axis mismatch) is below this, relative."""


def _vex(a: np.ndarray) -> np.ndarray:
    """The vector of a skew matrix: ``_vex(skew(v)) == v``."""
    return np.array([a[2, 1], a[0, 2], a[1, 0]])


def _sorted_axes(a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Eigenvalues ascending, eigenvectors as columns, each with its largest component positive,
    right-handed."""
    w, v = symmetric_eigen(a)
    v = v * np.sign(v[np.argmax(np.abs(v), axis=0), np.arange(3)])
    if np.linalg.det(v) < 0:
        v[:, 2] = -v[:, 2]
    return w, v


def torque_roll_axis(model: Model | Assembly, body: str | None = None, axis: Any = "x") -> np.ndarray:
    """Unit vector (global axes) of the torque-roll axis of ``body`` for a torque about ``axis``.

    The direction of ``J^-1 e``, ``J`` the full inertia tensor about the COG (products of inertia
    included) and ``e`` the crank axis. The axis passes through the COG.

    Parameters
    ----------
    model : Model or Assembly
        The system.
    body : str or None
        The body (None: the only body).
    axis : {"x", "y", "z"} or (3,) array_like
        Crank (torque) axis in global axes [-], any length.

    Returns
    -------
    (3,) ndarray
        The TRA direction [-], unit length, pointing along ``e`` (``e . tra > 0``).

    Examples
    --------
    >>> import vibss
    >>> b = vibss.Body("b", 10.0, [[2.0, -0.5, 0.0], [-0.5, 4.0, 0.0], [0.0, 0.0, 5.0]])
    >>> m = vibss.Model([b], [vibss.Mount("m", vibss.MountType("t", [1e4] * 3), "b")])
    >>> torque_roll_axis(m, "b", "x").round(4)
    array([0.9923, 0.124 , 0.    ])
    """
    e = unit_axis(axis, "axis", "torque_roll_axis")
    d = np.linalg.solve(_mass(model, body)[3:, 3:], e)
    return d / np.linalg.norm(d)


def _mass(model: Model | Assembly, body: str | None) -> np.ndarray:
    m = model.model if isinstance(model, Assembly) else model
    return m.body(body_name(m, body, "torque_roll_axis")).mass_matrix


def principal_axes(model: Model | Assembly, body: str | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Principal moments and axes of inertia of ``body`` about its COG.

    Parameters
    ----------
    model : Model or Assembly
        The system.
    body : str or None
        The body (None: the only body).

    Returns
    -------
    moments : (3,) ndarray
        Principal moments of inertia, ascending [kg m^2].
    axes : (3, 3) ndarray
        Principal axes as columns (global axes), right-handed [-].
    """
    return _sorted_axes(_mass(model, body)[3:, 3:])


@dataclass(frozen=True, eq=False)
class ElasticAxes(ReadOnly):
    """Elastic centre and axes of the mounts of one body (see the module docstring).

    Attributes
    ----------
    body : str
        The body.
    center : (3,) ndarray
        Elastic centre relative to the COG [m] (least-squares point where none exists).
    center_global : (3,) ndarray
        The same in global coordinates [m].
    axes : (3, 3) ndarray
        Principal directions of the rotational stiffness about ``centre`` (columns, global axes).
    rotational_stiffness : (3,) ndarray
        Rotational stiffness about each axis [N m/rad], ascending.
    translational_axes : (3, 3) ndarray
        Principal directions of the translational stiffness (columns).
    translational_stiffness : (3,) ndarray
        Translational stiffnesses along them [N/m], ascending.
    screw : float
        Residual coupling: ``|A_s| / |A|`` (0 where an elastic centre exists) [-].
    mismatch : float
        How far the translational and rotational principal directions differ: largest
        ``1 - |cos|`` between matched axes [-].
    exists : bool
        Elastic centre exists (``screw <= EXIST_RTOL``).
    axes_exist : bool
        Strict elastic axes exist (centre exists and ``mismatch <= EXIST_RTOL``).
    note : str
        Why they do or do not exist.
    """

    body: str
    center: np.ndarray
    center_global: np.ndarray
    axes: np.ndarray
    rotational_stiffness: np.ndarray
    translational_axes: np.ndarray
    translational_stiffness: np.ndarray
    screw: float
    mismatch: float
    exists: bool
    axes_exist: bool
    note: str

    centre = renamed_attribute("centre", "center", "ElasticAxes")
    centre_global = renamed_attribute("centre_global", "center_global", "ElasticAxes")


def elastic_axes(model: Model | Assembly, body: str | None = None) -> ElasticAxes:
    """Elastic centre and elastic axes of the mounts of ``body``, and whether they exist.

    Parameters
    ----------
    model : Model or Assembly
        The system (the other bodies held fixed).
    body : str or None
        The body (None: the only body).

    Returns
    -------
    ElasticAxes
    """
    a, i, _, K = body_blocks(model, body, "elastic_axes")
    C = np.linalg.inv(K)
    C = 0.5 * (C + C.T)
    ctr, crr = C[:3, 3:], C[3:, 3:]
    A = np.linalg.solve(crr.T, ctr.T).T                 # C_tr C_rr^-1
    skew_part, sym_part = 0.5 * (A - A.T), 0.5 * (A + A.T)
    c = _vex(skew_part)
    scale = max(float(np.linalg.norm(A)), float(np.linalg.norm(c)), 1e-300)
    screw = float(np.linalg.norm(sym_part) / scale)
    kr, vr = _sorted_axes(np.linalg.inv(crr))
    kt, vt = _sorted_axes(K[:3, :3])
    mismatch = float(np.max(1.0 - np.max(np.abs(vr.T @ vt), axis=1)))
    exists = screw <= EXIST_RTOL
    axes_exist = exists and mismatch <= EXIST_RTOL
    name = a.model.bodies[i].name
    if axes_exist:
        note = "elastic centre and elastic axes exist: torques about the axes give pure rotations, forces along them pure translations"
    elif exists:
        note = (f"an elastic centre exists (every torque turns the body about an axis through it), but "
                f"the translational and rotational principal directions differ (mismatch {mismatch:.3g}): "
                "no strict elastic axes")
    else:
        note = (f"no elastic centre: a torque gives a screw (rotation plus translation along the axis); "
                f"residual {screw:.3g}; the centre given is the least-squares point")
    return ElasticAxes(body=name, center=c, center_global=c + a.model.bodies[i].cog, axes=vr,
                       rotational_stiffness=kr, translational_axes=vt, translational_stiffness=kt,
                       screw=screw, mismatch=mismatch, exists=exists, axes_exist=axes_exist, note=note)


@dataclass(frozen=True, eq=False)
class TorqueResponse(ReadOnly):
    """Static response of one body to a pure torque, against its torque-roll axis.

    Attributes
    ----------
    body : str
        The body.
    torque : (3,) ndarray
        The torque applied [N m].
    displacement : (6,) ndarray
        COG displacement [m] and rotation [rad] (x y z rx ry rz).
    rotation_axis : (3,) ndarray
        Unit direction of the static rotation [-].
    tra : (3,) ndarray
        Torque-roll axis for the torque's direction [-].
    misalignment : float
        Angle between the static rotation axis and the TRA [rad].
    """

    body: str
    torque: np.ndarray
    displacement: np.ndarray
    rotation_axis: np.ndarray
    tra: np.ndarray
    misalignment: float

    @property
    def misalignment_deg(self) -> float:
        """Misalignment angle [deg]."""
        return float(np.degrees(self.misalignment))


def torque_response(model: Model | Assembly, body: str | None = None, axis: Any = "x",
                    torque: float = 1.0) -> TorqueResponse:
    """Static response of ``body`` to a pure torque about ``axis``, and its angle to the TRA.

    Parameters
    ----------
    model : Model or Assembly
        The system (the other bodies held fixed).
    body : str or None
        The body (None: the only body).
    axis : {"x", "y", "z"} or (3,) array_like
        Torque axis in global axes [-].
    torque : float
        Torque magnitude [N m].

    Returns
    -------
    TorqueResponse
    """
    e = unit_axis(axis, "axis", "torque_response")
    a, i, M, K = body_blocks(model, body, "torque_response")
    load = np.concatenate([np.zeros(3), float(torque) * e])
    q = static_solve(a, load, free=np.arange(6 * i, 6 * i + 6), kff=K).x   # the others held fixed
    rot = q[3:] / np.linalg.norm(q[3:])
    rot = rot if rot @ e >= 0 else -rot
    tra = np.linalg.solve(M[3:, 3:], e)
    tra /= np.linalg.norm(tra)
    angle = float(np.arctan2(np.linalg.norm(np.cross(rot, tra)), rot @ tra))
    return TorqueResponse(body=a.model.bodies[i].name, torque=float(torque) * e, displacement=q,
                          rotation_axis=rot, tra=tra, misalignment=angle)



_XYZ = ("x", "y", "z")


@dataclass(frozen=True, eq=False)
class DesignAxes(Result):
    """The axes of one body on its mounts, computed together so a figure can draw them
    (scikit-learn's Display objects: the result computes, :meth:`plot` only draws).

    Attributes
    ----------
    model : Model
        The system.
    torque : TorqueResponse
        Static response to a unit torque about the crank axis, with its torque-roll axis.
    elastic : ElasticAxes
        Elastic centre and axes of the body's mounts.
    principal_moments : (3,) ndarray
        Principal moments of inertia, ascending [kg m^2].
    principal_axes : (3, 3) ndarray
        Principal axes of inertia as columns (global axes), right-handed [-].
    """

    model: Model
    torque: TorqueResponse
    elastic: ElasticAxes
    principal_moments: np.ndarray
    principal_axes: np.ndarray

    signal_kind = "axis"

    @property
    def _vectors(self) -> dict[str, np.ndarray]:
        return {"tra": self.torque.tra, "rotation_axis": self.torque.rotation_axis,
                "elastic_centre": self.elastic.center_global,
                **{f"principal_{k + 1}": self.principal_axes[:, k] for k in range(3)},
                **{f"elastic_{k + 1}": self.elastic.axes[:, k] for k in range(3)}}

    @property
    def output_labels(self) -> tuple[str, ...]:
        """``"<axis>.x"`` ... for the torque-roll axis, the static rotation axis, the elastic centre,
        the principal and the elastic axes."""
        return tuple(f"{k}.{c}" for k in self._vectors for c in _XYZ)

    @property
    def units(self) -> tuple[str, ...]:
        """``m`` for the elastic centre, ``-`` for the unit directions."""
        return tuple("m" if k == "elastic_centre" else "-" for k in self._vectors for _ in _XYZ)

    @property
    def method(self) -> str:
        """How the axes were computed."""
        return "exact"

    @property
    def note(self) -> str:
        """Whether an elastic centre and axes exist, and why."""
        return self.elastic.note

    def _item(self, i: int, j: int | None) -> Any:
        return float(np.concatenate(list(self._vectors.values()))[i])

    def summary(self) -> TextTable:
        """One row per axis: its x, y, z components."""
        rows = [[k] + [f"{v:+.4f}" for v in vec] for k, vec in self._vectors.items()]
        return TextTable(["axis", "x", "y", "z"], rows, title=f"Axes of {self.torque.body!r} (global, unit "
                     f"directions; elastic centre [m])", notes=[self.note])

    def report(self) -> str:
        """Text: the axes, the TRA's angle to the static rotation axis, the elastic centre's verdict."""
        return "\n\n".join([self.summary().render(),
                             f"TRA {self.torque.misalignment_deg:.1f} deg from the static rotation axis"])

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready axes (SI)."""
        return jsonable({"body": self.torque.body, **self._vectors,
                         "principal_moments": self.principal_moments,
                         "misalignment": self.torque.misalignment, "elastic_centre_exists": self.elastic.exists,
                         "note": self.note})

    def to_pandas(self) -> Any:
        """DataFrame: one row per axis, columns x, y, z."""
        pd = require_pandas()
        df = pd.DataFrame(np.array(list(self._vectors.values())), columns=list(_XYZ),
                          index=pd.Index(list(self._vectors), name="axis"))
        df.attrs["units"] = {c: "-" for c in _XYZ}          # unit vectors, global axes
        return df

    def plot(self, ax: Any = None, view: str = "three", length: float | None = None) -> Any:
        """The axes drawn on the layout: :func:`vibss.plotting.design.plot_axes`.

        Parameters
        ----------
        ax : None
            Not supported (the figure has one panel per view); kept for the result protocol.
        view : {"three", "iso", "xz", "yz", "xy"}
            As :func:`vibss.plotting.plot_model`.
        length : float or None
            Half-length of the drawn axes [m]; default: half the largest mount distance from the COG.

        Returns
        -------
        matplotlib.figure.Figure
        """
        from ..plotting.design import plot_axes

        if ax is not None:
            from ..errors import ArgumentError
            raise ArgumentError("DesignAxes.plot draws a figure of its own (one panel per view): ax must be None",
                                argument="ax", received=ax)
        return plot_axes(self, view=view, length=length)


def design_axes(model: Model | Assembly, body: str | None = None, axis: Any = "x") -> DesignAxes:
    """Torque-roll axis, static rotation axis, elastic centre and axes, and principal axes of inertia
    of ``body``, together (what :meth:`DesignAxes.plot` draws).

    Parameters
    ----------
    model : Model or Assembly
        The system (the other bodies held fixed).
    body : str or None
        The body (None: the only body).
    axis : {"x", "y", "z"} or (3,) array_like
        Crank axis [-].

    Returns
    -------
    DesignAxes
    """
    m = model.model if isinstance(model, Assembly) else model
    moments, axes = principal_axes(model, body)
    return DesignAxes(model=m, torque=torque_response(model, body, axis), elastic=elastic_axes(model, body),
                      principal_moments=moments, principal_axes=axes)


def plot_design_axes(model: Model | Assembly, body: str | None = None, axis: Any = "x", view: str = "three",
                     length: float | None = None) -> Any:
    """``design_axes(model, body, axis).plot(view=view, length=length)``: the layout with the
    torque-roll axis, the static rotation axis under a torque about ``axis``, the elastic centre and
    its axes, and the principal axes of inertia drawn through the body.

    Parameters
    ----------
    model : Model or Assembly
        The model.
    body : str or None
        The body (None: the only body).
    axis : {"x", "y", "z"} or (3,) array_like
        Crank axis [-].
    view : {"three", "iso", "xz", "yz", "xy"}
        As :func:`vibss.plotting.plot_model`.
    length : float or None
        Half-length of the drawn axes [m]; default: half the largest mount distance from the COG.

    Returns
    -------
    matplotlib.figure.Figure
    """
    return design_axes(model, body, axis).plot(view=view, length=length)
