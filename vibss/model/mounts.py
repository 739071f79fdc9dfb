"""Mount types, mounts and their mirror images (symmetric layouts).

Frozen, validated data like the rest of :mod:`vibss.model`; re-exported by
:mod:`vibss.model.model` (``from vibss.model.model import Mount`` keeps working).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validate import is_numeric
from ..errors import ModelError
from ._common import GROUND, _frame, _freeze, _orientation, _signal_safe, _vec
from .geometry import MIRRORS

__all__ = ["MountType", "Mount", "symmetric", "SYMMETRIES"]

SYMMETRIES: dict[str, tuple[tuple[str, ...], ...]] = {
    "none": ((),),
    "xz": ((), ("xz",)),
    "yz": ((), ("yz",)),
    "double": ((), ("xz",), ("yz",), ("xz", "yz")),
}


@dataclass(frozen=True, eq=False)
class MountType:
    """Stiffness and damping of a mount along its three principal (local) axes.

    Parameters
    ----------
    name : str
        Unique name.
    stiffness : (3,) array_like
        Principal stiffnesses (k1, k2, k3) [N/m]; zero is allowed (no stiffness along that axis).
    damping : (3,) array_like
        Viscous dampings (c1, c2, c3) [N s/m]. Default zero.
    loss_factor : float or (3,) array_like
        Hysteretic loss factor eta [-] (complex stiffness k (1 + i eta)); frequency domain only.
    """

    name: str
    stiffness: Any
    damping: Any = (0.0, 0.0, 0.0)
    loss_factor: Any = 0.0

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name:
            raise ModelError(f"mount type: name must be a non-empty string, got {self.name!r}")
        who = f"mount type {self.name!r}"
        for key, unit in (("stiffness", "N/m"), ("damping", "N s/m")):
            v = _vec(getattr(self, key), 3, who, key)
            if np.any(v < 0):
                raise ModelError(f"{who}: {key} must not be negative, got {v.tolist()} {unit}")
            object.__setattr__(self, key, v)
        eta = np.array(self.loss_factor, dtype=float) if is_numeric(self.loss_factor) else None
        if eta is None or eta.shape not in ((), (3,)):
            raise ModelError(f"{who}: loss_factor: expected a number or 3 numbers, got {self.loss_factor!r}")
        eta = np.broadcast_to(eta, (3,)).copy()
        if not np.all(np.isfinite(eta)) or np.any(eta < 0):
            raise ModelError(f"{who}: loss_factor must be finite and not negative, got {eta.tolist()}")
        object.__setattr__(self, "loss_factor", _freeze(eta))


@dataclass(frozen=True, eq=False)
class Mount:
    """A zero-length mount joining a point of ``body`` to the same point of ``to``.

    Parameters
    ----------
    name : str
        Unique name.
    type : MountType
        Stiffness and damping along the mount's local axes.
    body : str
        The body the point belongs to.
    at : (3,) array_like
        Attachment point [m]: relative to the COG of ``body`` (``frame="body"``, in global axis
        directions) or in global coordinates (``frame="global"``).
    to : str
        ``"ground"`` or the name of another body.
    orientation : Orientation, (3, 3) array_like, scipy Rotation or None
        Local axes (columns) in global coordinates. Default: global axes.
    frame : {"body", "global"}
        How ``at`` is measured.
    """

    name: str
    type: MountType
    body: str
    at: Any = (0.0, 0.0, 0.0)
    to: str = GROUND
    orientation: Any = None
    frame: str = "body"

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name:
            raise ModelError(f"mount: name must be a non-empty string, got {self.name!r}")
        who = f"mount {self.name!r}"
        _signal_safe(self.name, who)
        if not isinstance(self.type, MountType):
            raise ModelError(f"{who}: type must be a MountType, got {self.type!r}")
        for key in ("body", "to"):
            if not isinstance(getattr(self, key), str):
                raise ModelError(f"{who}: {key} must be a body name, got {getattr(self, key)!r}")
        if self.body == GROUND:
            raise ModelError(f"{who}: body must be a body, not {GROUND!r} (put ground in 'to')")
        if self.body == self.to:
            raise ModelError(f"{who}: joins body {self.body!r} to itself; a mount joins two "
                             "different bodies, or a body and ground")
        object.__setattr__(self, "at", _vec(self.at, 3, who, "at"))
        object.__setattr__(self, "frame", _frame(self.frame, who))
        object.__setattr__(self, "orientation", _orientation(self.orientation, who, "orientation"))

    def mirrored(self, planes: Sequence[str]) -> Mount:
        """Copy mirrored in the given planes (``"xz"``, ``"yz"``, ``"xy"``), named ``name.plane...``.

        The point is mirrored in the body's planes through its COG (``frame="body"``) or in the
        global planes (``frame="global"``); so is the orientation (kept right-handed).
        """
        at, orient, name = self.at, self.orientation, self.name
        for plane in planes:
            if plane not in MIRRORS:
                raise ModelError(f"mount {self.name!r}: unknown mirror plane {plane!r}; "
                                 f"expected one of {sorted(MIRRORS)}")
            at = MIRRORS[plane] @ at
            orient = orient.mirrored(plane)
            name = f"{name}.{plane}"
        return dataclasses.replace(self, name=name, at=at, orientation=orient)


def symmetric(mount: Mount, symmetry: str = "double") -> tuple[Mount, ...]:
    """The mount and its mirror images.

    Parameters
    ----------
    mount : Mount
        The generating mount.
    symmetry : {"none", "xz", "yz", "double"}
        Mirror about the XZ plane (y -> -y), the YZ plane (x -> -x), or both ("double
        symmetry": four mounts). Names get ``.xz``, ``.yz``, ``.xz.yz`` appended.

    Examples
    --------
    >>> t = MountType("t", [1.0, 1.0, 1.0])
    >>> [m.at.tolist() for m in symmetric(Mount("a", t, "b", at=[1, 2, 3]), "xz")]
    [[1.0, 2.0, 3.0], [1.0, -2.0, 3.0]]
    """
    if not isinstance(symmetry, str) or symmetry not in SYMMETRIES:
        raise ModelError(f"mount {mount.name!r}: unknown symmetry {symmetry!r}; expected one of "
                         f"{list(SYMMETRIES)}")
    return tuple(mount.mirrored(planes) for planes in SYMMETRIES[symmetry])
