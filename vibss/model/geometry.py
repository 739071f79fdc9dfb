"""Rotations, skew matrices and the point-transfer matrix of small rigid-body motion.

Conventions (see ``docs/conventions.md``): an orientation is a rotation matrix whose *columns*
are the local axes in global coordinates. Euler angles are converted by
:class:`scipy.spatial.transform.Rotation`; the default sequence is ``"ZYX"`` (upper case:
intrinsic, i.e. yaw about Z, then pitch about the new Y, then roll about the newest X).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
import numpy.typing as npt
from scipy.spatial.transform import Rotation

from .._validate import vector
from .limits import MAX_EULER_RAD
from ..errors import ModelError

__all__ = [
    "DEFAULT_SEQUENCE",
    "Orientation",
    "skew",
    "lever",
    "point_transfer",
    "MIRRORS",
]

DEFAULT_SEQUENCE = "ZYX"
"""Default Euler sequence: intrinsic Z, then Y, then X (scipy's upper-case spelling)."""

_ORTHO_TOL = 1e-6

#: Reflection matrices of the symmetry planes, by name.
MIRRORS: dict[str, np.ndarray] = {
    "xz": np.diag([1.0, -1.0, 1.0]),  # y -> -y
    "yz": np.diag([-1.0, 1.0, 1.0]),  # x -> -x
    "xy": np.diag([1.0, 1.0, -1.0]),  # z -> -z
}


@dataclass(frozen=True, eq=False)
class Orientation:
    """A right-handed orientation: rotation matrix whose columns are the local axes.

    Parameters
    ----------
    matrix : (3, 3) array_like
        Rotation matrix [-]; column ``i`` is local axis ``i+1`` in global coordinates.
    euler : (3,) array_like or None
        The Euler angles it was made from [rad], kept for reports only.
    sequence : str or None
        The Euler sequence of ``euler`` (scipy spelling: upper case intrinsic).

    Examples
    --------
    >>> o = Orientation.from_euler([90, 0, 0], degrees=True)
    >>> o.matrix.round(6)[:, 0]   # local axis 1 points along global Y
    array([0., 1., 0.])
    """

    matrix: np.ndarray
    euler: np.ndarray | None = field(default=None)
    sequence: str | None = field(default=None)

    def __post_init__(self) -> None:
        m = _as_matrix(self.matrix, "orientation matrix")
        object.__setattr__(self, "matrix", m)
        if self.euler is not None:
            object.__setattr__(self, "euler", np.array(self.euler, dtype=float))

    @classmethod
    def identity(cls) -> Orientation:
        """Local axes along the global axes."""
        return cls(np.eye(3))

    @classmethod
    def from_euler(
        cls,
        angles: npt.ArrayLike,
        sequence: str = DEFAULT_SEQUENCE,
        degrees: bool = False,
    ) -> Orientation:
        """Orientation from three Euler angles.

        Parameters
        ----------
        angles : (3,) array_like
            Angles [rad, or deg with ``degrees=True``].
        sequence : str
            Axis sequence in scipy's spelling (``"ZYX"`` intrinsic, ``"zyx"`` extrinsic).
        degrees : bool
            Whether ``angles`` are in degrees.
        """
        a = _vector(angles, 3, "euler")
        if not isinstance(sequence, str) or len(sequence) != 3 or not (
            set(sequence) <= set("XYZ") or set(sequence) <= set("xyz")
        ):
            raise ModelError(
                f"sequence: expected three axis letters, all upper case (intrinsic) or all "
                f"lower case (extrinsic), e.g. 'ZYX'; got {sequence!r}"
            )
        try:
            rot = Rotation.from_euler(sequence, a, degrees=degrees)
        except ValueError as exc:  # e.g. 'XXY'
            raise ModelError(f"sequence {sequence!r}: {exc}") from None
        rad = np.deg2rad(a) if degrees else a
        if np.any(np.abs(rad) > MAX_EULER_RAD * (1 + 1e-12)):
            raise ModelError(f"euler: {a.tolist()} {'deg' if degrees else 'rad'}: every angle must be within "
                             "+-360 degrees (an angle beyond it is a typo or a unit mistake)")
        return cls(rot.as_matrix(), euler=rad, sequence=sequence)

    @classmethod
    def coerce(cls, value: Any, what: str = "orientation") -> Orientation:
        """Accept an Orientation, a (3, 3) matrix, a scipy Rotation or None (identity)."""
        if value is None:
            return cls.identity()
        if isinstance(value, Orientation):
            return value
        if isinstance(value, Rotation):
            return cls(value.as_matrix())
        try:
            return cls(_as_matrix(value, what))
        except ModelError:
            raise
        except Exception:  # pragma: no cover - defensive
            raise ModelError(f"{what}: expected a 3x3 rotation matrix, got {value!r}") from None

    def mirrored(self, plane: str) -> Orientation:
        """Orientation mirrored in a global plane, kept right-handed.

        The reflection ``S T S`` maps the axis directions by ``S`` and flips the sign of the axis
        that the plane reverses, so ``T' diag(k) T'^T = S (T diag(k) T^T) S``: the mirrored
        stiffness, with a proper rotation.
        """
        s = MIRRORS[plane]
        return Orientation(s @ self.matrix @ s)

    def describe(self) -> str:
        """Short text for reports: the Euler angles and sequence, or 'matrix'."""
        if self.euler is not None:
            deg = np.rad2deg(self.euler)
            return f"{self.sequence} ({deg[0]:.2f}, {deg[1]:.2f}, {deg[2]:.2f}) deg"
        if np.allclose(self.matrix, np.eye(3)):
            return "global axes"
        return "matrix"


def _vector(value: npt.ArrayLike, n: int, what: str) -> np.ndarray:
    return vector(value, n, what, strict=False)


def _as_matrix(value: Any, what: str) -> np.ndarray:
    try:
        m = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise ModelError(f"{what}: expected a 3x3 matrix of numbers, got {value!r}") from None
    if m.shape != (3, 3):
        raise ModelError(f"{what}: expected a 3x3 matrix, got shape {m.shape}")
    if not np.all(np.isfinite(m)):
        raise ModelError(f"{what}: values must be finite")
    err = np.abs(m.T @ m - np.eye(3)).max()
    if err > _ORTHO_TOL:
        raise ModelError(
            f"{what}: not orthogonal (max |T^T T - I| = {err:.3g}); columns must be unit, "
            "mutually perpendicular local axes"
        )
    if np.linalg.det(m) < 0:
        raise ModelError(f"{what}: left-handed (determinant -1); the local axes must be right-handed")
    m.setflags(write=False)
    return m


def skew(v: npt.ArrayLike) -> np.ndarray:
    """Cross-product matrix: ``skew(a) @ b == np.cross(a, b)``; works on (..., 3) stacks."""
    v = np.asarray(v, dtype=float)
    out = np.zeros(v.shape[:-1] + (3, 3))
    out[..., 0, 1], out[..., 0, 2] = -v[..., 2], v[..., 1]
    out[..., 1, 0], out[..., 1, 2] = v[..., 2], -v[..., 0]
    out[..., 2, 0], out[..., 2, 1] = -v[..., 1], v[..., 0]
    return out


def lever(r: npt.ArrayLike) -> np.ndarray:
    """``R(r) = -[r]x``: displacement of point ``r`` [m] per small rotation [rad] (..., 3, 3)."""
    return -skew(r)


def point_transfer(r: npt.ArrayLike) -> np.ndarray:
    """``L(r) = [I3 | R(r)]`` (..., 3, 6): point displacement from a body's 6 COG DOFs.

    Parameters
    ----------
    r : (..., 3) array_like
        Point position relative to the body's centre of gravity [m].

    Examples
    --------
    >>> point_transfer([1.0, 0.0, 0.0]) @ [0, 0, 0, 0, 0, 0.01]   # rz turns (1,0,0) towards +y
    array([0.  , 0.01, 0.  ])
    """
    r = np.asarray(r, dtype=float)
    out = np.zeros(r.shape[:-1] + (3, 6))
    out[..., :, :3] = _EYE3
    # the six entries of R(r) = -[r]x, each +-r_k (exact), in one step: z, -y, -z, x, y, -x
    out[..., _LEVER_ROWS, _LEVER_COLS] = r[..., _LEVER_FROM] * _LEVER_SIGNS
    return out


_EYE3 = np.eye(3)
_EYE3.flags.writeable = False
_LEVER_ROWS, _LEVER_COLS = np.array([0, 0, 1, 1, 2, 2]), np.array([4, 5, 3, 5, 3, 4])
_LEVER_FROM = np.array([2, 1, 2, 0, 1, 0])
_LEVER_SIGNS = np.array([1.0, -1.0, -1.0, 1.0, 1.0, -1.0])
