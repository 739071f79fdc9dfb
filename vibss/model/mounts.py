"""Mount types, mounts and their mirror images (symmetric layouts).

Frozen, validated data like the rest of :mod:`vibss.model`; re-exported by
:mod:`vibss.model.model` (``from vibss.model.model import Mount`` keeps working).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import numpy.typing as npt

from .._validate import is_numeric
from .limits import check_range
from ..errors import ModelError
from ._common import GROUND, _frame, _freeze, _orientation, _signal_safe, _vec
from .geometry import MIRRORS
from .nonlinearity import SLOPE_RTOL, AxisLaw, parse_curve, parse_stops
from .rheology import Ladder, Rheology, parse_rheology

__all__ = ["MountType", "Mount", "Support", "symmetric", "SYMMETRIES"]

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
    stiffness : (3,) array_like or None
        Principal (static) stiffnesses (k1, k2, k3) [N/m]; zero is allowed (no stiffness along that
        axis). With ``rheology`` it may be omitted (None: the rheology's static stiffness) and must
        otherwise equal it.
    damping : (3,) array_like
        Viscous dampings (c1, c2, c3) [N s/m], in parallel with the rest. Default zero.
    loss_factor : float or (3,) array_like
        Hysteretic loss factor eta [-] (complex stiffness k (1 + i eta)); frequency domain only
        (time-domain analyses leave it out with a warning naming the mount). Not with ``rheology``
        (give the loss there: a ``table`` with a constant loss factor is its causal approximation).
    rheology : mapping, Rheology or None
        Frequency-dependent stiffness per axis (:mod:`vibss.model.rheology`), e.g.
        ``{"type": "zener", "k_0": [...], "k_inf": [...], "tau": [...]}``: ``kelvin_voigt``,
        ``zener``, ``prony``, ``fractional_zener`` or ``table``. Every analysis uses its Maxwell
        ladder (:attr:`ladder`; exact for the rational models, fitted with :attr:`fit_error` else).
    rotational_stiffness : (3,) array_like
        Torsional and conical rates (kr1, kr2, kr3) about the mount's local axes [N m/rad]: the
        moment ``T diag(kr) T^T (theta_body - theta_to)`` of a bushing or rubber block with size
        (a 6x6 mount). Default zero. Constant (no loss factor, no rheology).
    rotational_damping : (3,) array_like
        Viscous rotational dampings (cr1, cr2, cr3) about the local axes [N m s/rad]. Default zero.
    stiffness_matrix : (6, 6) array_like or None
        A full symmetric positive semi-definite stiffness in the mount's local axes, acting on
        ``(d1, d2, d3, r1, r2, r3)`` (relative deflection [m] and rotation [rad], body side minus
        ``to`` side) and giving ``(f1, f2, f3, m1, m2, m3)``: blocks [N/m] (translation), [N m/rad]
        (rotation) and [N/rad] = [N m/m] (coupling). Its diagonal is ``stiffness`` and
        ``rotational_stiffness`` (which may be omitted, or must equal it). Not with ``rheology``;
        with ``loss_factor`` only when the matrix is diagonal.
    damping_matrix : (6, 6) array_like or None
        The same for viscous damping [N s/m, N m s/rad, N s/rad]; its diagonal is ``damping`` and
        ``rotational_damping``.
    stops : mapping or None
        Bump stops per local axis, ``{"z": (clearance, stiffness)}``: past the clearance [m] (one
        number, or ``(negative side, positive side)``, both >= 0) the stop's stiffness [N/m] adds to
        the mount's own (:mod:`vibss.model.nonlinearity`).
    curve : mapping or None
        Force-deflection curves per local axis, ``{"z": [(deflection [m], force [N]), ...]}``: a
        monotone PCHIP curve through the points, which include (0, 0), continued with its end
        slopes. The axis's ``stiffness`` is the curve's slope at zero (given or not).

    A type with stops or curves is nonlinear (:attr:`nonlinear`): :func:`vibss.operating_point` finds
    where it sits under load, and the linear analyses use its tangent there.

    Examples
    --------
    >>> t = MountType("rubber", rheology={"type": "zener", "k_0": 1e4, "k_inf": 2e4, "tau": 1e-3})
    >>> t.stiffness.tolist(), t.has_branches
    ([10000.0, 10000.0, 10000.0], True)
    >>> complex(t.dynamic_stiffness([1000 / (2 * 3.141592653589793)])[0, 0])   # w tau = 1
    (15000+5000j)
    """

    name: str
    stiffness: Any = None
    damping: Any = (0.0, 0.0, 0.0)
    loss_factor: Any = 0.0
    rheology: Any = None
    rotational_stiffness: Any = (0.0, 0.0, 0.0)
    rotational_damping: Any = (0.0, 0.0, 0.0)
    stiffness_matrix: Any = None
    damping_matrix: Any = None
    stops: Any = None
    curve: Any = None
    _ladder: Any = field(default=None, init=False, repr=False)
    _laws: Any = field(default=None, init=False, repr=False)

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name:
            raise ModelError(f"mount type: name must be a non-empty string, got {self.name!r}")
        who = f"mount type {self.name!r}"
        ladder: Ladder | None = None
        if self.rheology is not None:
            rh = parse_rheology(self.rheology, self.name)
            object.__setattr__(self, "rheology", rh)
            ladder = rh.ladder()
            if self.stiffness is None:
                object.__setattr__(self, "stiffness", ladder.static.copy())
        for key, diag in (("stiffness_matrix", ("stiffness", "rotational_stiffness")),
                          ("damping_matrix", ("damping", "rotational_damping"))):
            if getattr(self, key) is not None:
                if self.rheology is not None:
                    raise ModelError(f"{who}: {key} and rheology: a frequency-dependent type has no 6x6 matrix; "
                                     "give one or the other")
                mat = _symmetric_psd(getattr(self, key), who, key)
                object.__setattr__(self, key, mat)
                _fill_diagonal(self, mat, diag, who, key)
        stops = parse_stops(self.stops, who) if self.stops is not None else {}
        curves = parse_curve(self.curve, who) if self.curve is not None else {}
        if stops or curves:
            self._nonlinear_axes(stops, curves, who)
        if self.stiffness is None:
            raise ModelError(f"{who}: stiffness: give the 3 principal stiffnesses [N/m] (or a rheology "
                             "or a stiffness_matrix)")
        for key, unit in (("stiffness", "N/m"), ("damping", "N s/m"), ("rotational_stiffness", "N m/rad"),
                          ("rotational_damping", "N m s/rad")):
            v = _vec(getattr(self, key), 3, who, key)
            if np.any(v < 0):
                raise ModelError(f"{who}: {key} must not be negative, got {v.tolist()} {unit}")
            if key in ("stiffness", "damping"):
                check_range(v, key, who, key, unit)
            object.__setattr__(self, key, v)
        eta = np.array(self.loss_factor, dtype=float) if is_numeric(self.loss_factor) else None
        if eta is None or eta.shape not in ((), (3,)):
            raise ModelError(f"{who}: loss_factor: expected a number or 3 numbers, got {self.loss_factor!r}")
        eta = np.broadcast_to(eta, (3,)).copy()
        if not np.all(np.isfinite(eta)) or np.any(eta < 0):
            raise ModelError(f"{who}: loss_factor must be finite and not negative, got {eta.tolist()}")
        object.__setattr__(self, "loss_factor", _freeze(eta))
        if np.any(eta) and self.coupled:
            raise ModelError(f"{who}: loss_factor and a stiffness_matrix with off-diagonal terms: the loss "
                             "factor acts on the principal stiffnesses only; give the damping as a "
                             "damping_matrix instead")
        if ladder is not None:
            if np.any(eta):
                raise ModelError(f"{who}: loss_factor and rheology: give the loss in the rheology (a "
                                 "'table' with a loss_factor), not both")
            if not np.allclose(self.stiffness, ladder.static, rtol=1e-9, atol=0.0):
                raise ModelError(f"{who}: stiffness {self.stiffness.tolist()} N/m differs from the static "
                                 f"stiffness of its rheology, {ladder.static.tolist()} N/m; omit it or give "
                                 "the same", argument="stiffness", received=self.stiffness.tolist(),
                                 expected=ladder.static.tolist())
            if np.any(ladder.viscous):
                if np.any(self.damping) and not np.allclose(self.damping, ladder.viscous, rtol=1e-9):
                    raise ModelError(f"{who}: damping {self.damping.tolist()} N s/m differs from the "
                                     f"rheology's c = {ladder.viscous.tolist()} N s/m; omit it or give the same")
                object.__setattr__(self, "damping", _freeze(ladder.viscous.copy()))
            # the ladder every analysis uses: the rheology's branches, this type's static stiffness
            # and damping (a parallel dashpot adds to a Zener or Prony rheology)
            object.__setattr__(self, "_ladder", Ladder(self.stiffness, self.damping, ladder.k, ladder.tau,
                                                       ladder.fit_error, ladder.band, ladder.mu))

    def _nonlinear_axes(self, stops: dict[int, Any], curves: dict[int, np.ndarray], who: str) -> None:
        """Validate stops and curves against the rest of the type; set the curved axes' stiffness to
        the curve's slope at zero; keep the axis laws."""
        for key in ("rheology", "stiffness_matrix"):
            if getattr(self, key) is not None:
                raise ModelError(f"{who}: stops/curve and {key}: a nonlinear type is given by its principal "
                                 "rates, stops and curves only", argument=key)
        given = None if self.stiffness is None else _vec(self.stiffness, 3, who, "stiffness")
        k = np.zeros(3) if given is None else given.copy()
        laws = []
        for j in range(3):
            law = AxisLaw.build(k[j], stops.get(j), curves.get(j))
            if j in curves:
                if given is not None and given[j] and not np.isclose(given[j], law.stiffness, rtol=SLOPE_RTOL, atol=0):
                    raise ModelError(f"{who}: stiffness[{j}] = {given[j]:.6g} N/m differs from the slope at zero of "
                                     f"curve[{'xyz'[j]!r}], {law.stiffness:.6g} N/m; omit it (0) or give the same",
                                     argument="stiffness", received=float(given[j]), expected=law.stiffness)
                k[j] = law.stiffness
            laws.append(law)
        object.__setattr__(self, "stiffness", k)
        object.__setattr__(self, "stops", {"xyz"[j]: v for j, v in stops.items()} or None)
        object.__setattr__(self, "curve", {"xyz"[j]: _freeze(v) for j, v in curves.items()} or None)
        object.__setattr__(self, "_laws", tuple(laws))

    @property
    def nonlinear(self) -> bool:
        """Whether any axis has a stop or a force-deflection curve."""
        return self._laws is not None

    @property
    def laws(self) -> tuple[AxisLaw, AxisLaw, AxisLaw]:
        """The elastic force law of each local axis (linear ones too)."""
        if self._laws is not None:
            return self._laws    # type: ignore[no-any-return]
        return tuple(AxisLaw(float(k)) for k in self.stiffness)  # type: ignore[return-value]

    @property
    def ladder(self) -> Ladder | None:
        """The Maxwell ladder of a frequency-dependent type (None without ``rheology``)."""
        return self._ladder

    @property
    def rotational(self) -> bool:
        """Whether the type has rotational stiffness or damping (a 6x6 mount)."""
        return bool(np.any(self.rotational_stiffness) or np.any(self.rotational_damping) or self.coupled)

    @property
    def coupled(self) -> bool:
        """Whether its ``stiffness_matrix`` or ``damping_matrix`` has off-diagonal terms."""
        return any(m is not None and np.any(m - np.diag(np.diag(m)))
                   for m in (self.stiffness_matrix, self.damping_matrix))

    def mirrored(self, plane: str) -> MountType:
        """The mirror image of a coupled type in a global plane (named ``name.plane``); other types
        are their own mirror image and are returned as they are.

        A mount mirrored by ``S`` (its axes turned to ``T' = S T S``, :meth:`Orientation.mirrored`)
        moves deflections as vectors and rotations as pseudo-vectors (``-S theta``), so its local
        matrix becomes ``Q K6 Q`` with ``Q = diag(S, -S)``: the coupling blocks change sign where
        the translation ones do not.
        """
        if not self.coupled:
            return self
        s = np.diag(MIRRORS[plane])
        q = np.diag(np.concatenate([s, -s]))
        return dataclasses.replace(self, name=f"{self.name}.{plane}", **{
            key: None if getattr(self, key) is None else q @ getattr(self, key) @ q
            for key in ("stiffness_matrix", "damping_matrix")})

    def local_matrix(self, which: str = "stiffness") -> np.ndarray:
        """(6, 6) stiffness [N/m, N/rad, N m/rad] (``"stiffness"``) or damping (``"damping"``) in the
        local axes, on ``(d1, d2, d3, r1, r2, r3)``: the full matrix, or the diagonal of the rates."""
        full = self.stiffness_matrix if which == "stiffness" else self.damping_matrix
        if full is not None:
            return np.array(full)
        tr, rot = ((self.stiffness, self.rotational_stiffness) if which == "stiffness"
                   else (self.damping, self.rotational_damping))
        return np.diag(np.concatenate([tr, rot]))

    @property
    def has_branches(self) -> bool:
        """Whether the type has Maxwell branches (internal states in the time domain)."""
        return self._ladder is not None and bool(np.any(self._ladder.k > 0))

    @property
    def fit_error(self) -> float:
        """Largest relative error of the ladder over its band (0: exact or no rheology)."""
        return 0.0 if self._ladder is None else float(self._ladder.fit_error)

    def dynamic_stiffness(self, frequency_hz: npt.ArrayLike) -> np.ndarray:
        """(nf, 3) complex dynamic stiffness ``k*`` per principal axis at ``frequency_hz`` [Hz] [N/m].

        The rheology's exact ``k*`` (a table's interpolation, with a warning outside it) plus the
        parallel dashpot; without rheology ``k (1 + i eta) + i w c``.
        """
        w = 2 * np.pi * np.atleast_1d(np.asarray(frequency_hz, dtype=float))
        if isinstance(self.rheology, Rheology):
            extra = self.damping - self.rheology.ladder().viscous      # a dashpot beside the rheology
            return self.rheology.dynamic_stiffness(w) + 1j * w[:, None] * extra[None]
        return self.stiffness[None] * (1 + 1j * self.loss_factor[None]) + 1j * w[:, None] * self.damping[None]


def _symmetric_psd(value: Any, who: str, key: str) -> np.ndarray:
    """A (6, 6) symmetric positive semi-definite matrix, frozen; else a ModelError naming ``key``."""
    a = np.array(value, dtype=float) if is_numeric(value) else None
    if a is None or a.shape != (6, 6):
        raise ModelError(f"{who}: {key}: expected a 6x6 matrix (6 rows of 6 numbers) on "
                         f"(d1, d2, d3, r1, r2, r3), got {value!r}", argument=key, received=value,
                         expected="(6, 6)")
    if not np.all(np.isfinite(a)):
        raise ModelError(f"{who}: {key} must be finite, got {a.tolist()}")
    scale = float(np.abs(a).max())
    asym = float(np.abs(a - a.T).max())
    if asym > 1e-12 * scale:
        i, j = np.unravel_index(int(np.argmax(np.abs(a - a.T))), a.shape)
        raise ModelError(f"{who}: {key} must be symmetric: entry [{i}][{j}] = {a[i, j]:.6g} but "
                         f"[{j}][{i}] = {a[j, i]:.6g}", argument=key, received=a.tolist(), expected="symmetric")
    a = 0.5 * (a + a.T)
    # PSD in the scaled matrix D^-1/2 A D^-1/2 (units differ between the blocks)
    d = np.sqrt(np.where(np.diag(a) > 0, np.diag(a), 1.0))
    lam = np.linalg.eigvalsh(a / np.outer(d, d)) if scale > 0 else np.zeros(6)
    if np.any(np.diag(a) < 0) or lam.min() < -1e-10 * max(1.0, lam.max()):
        raise ModelError(f"{who}: {key} is not positive semi-definite (eigenvalues of the diagonally "
                         f"scaled matrix {np.round(lam, 6).tolist()}): a passive mount stores no negative "
                         "energy", argument=key, received=a.tolist(), expected="positive semi-definite")
    return _freeze(a)


def _fill_diagonal(t: MountType, mat: np.ndarray, keys: tuple[str, str], who: str, key: str) -> None:
    """``stiffness``/``rotational_stiffness`` (or the dampings) from a 6x6 matrix's diagonal: taken
    when omitted (None, or all zero), else they must equal it."""
    for part, value in zip(keys, (np.diag(mat)[:3], np.diag(mat)[3:])):
        given = getattr(t, part)
        if given is None or (is_numeric(given) and not np.any(np.asarray(given, dtype=float))):
            object.__setattr__(t, part, value.copy())
            continue
        g = np.asarray(given, dtype=float) if is_numeric(given) else None
        if g is None or g.shape != (3,) or not np.allclose(g, value, rtol=1e-12, atol=0.0):
            raise ModelError(f"{who}: {part} {given!r} differs from the diagonal of {key} {value.tolist()}; "
                             f"omit it or give the same", argument=part, received=given, expected=value.tolist())


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
    support : str or None
        Name of the model's :class:`Support` the ``to`` end stands on (only with ``to="ground"``):
        that support's prescribed motion (``<support>.z.acc`` ...) moves the end, independently of
        the other supports and of the rigid ``ground``. None: the rigid ground.
    """

    name: str
    type: MountType
    body: str
    at: Any = (0.0, 0.0, 0.0)
    to: str = GROUND
    orientation: Any = None
    frame: str = "body"
    support: str | None = None

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
        if self.support is not None:
            if not isinstance(self.support, str) or not self.support:
                raise ModelError(f"{who}: support must be the name of a support, got {self.support!r}")
            if self.to != GROUND:
                raise ModelError(f"{who}: support {self.support!r} is only for a mount whose 'to' end is "
                                 f"ground; this mount joins body {self.body!r} to body {self.to!r}")
        object.__setattr__(self, "at", _vec(self.at, 3, who, "at"))
        check_range(self.at, "length", who, "at", "m")
        object.__setattr__(self, "frame", _frame(self.frame, who))
        object.__setattr__(self, "orientation", _orientation(self.orientation, who, "orientation"))

    def mirrored(self, planes: Sequence[str]) -> Mount:
        """Copy mirrored in the given planes (``"xz"``, ``"yz"``, ``"xy"``), named ``name.plane...``.

        The point is mirrored in the body's planes through its COG (``frame="body"``) or in the
        global planes (``frame="global"``); so is the orientation (kept right-handed), and a type
        with a coupled 6x6 matrix becomes its mirror image (:meth:`MountType.mirrored`).
        """
        at, orient, name, mtype = self.at, self.orientation, self.name, self.type
        for plane in planes:
            if plane not in MIRRORS:
                raise ModelError(f"mount {self.name!r}: unknown mirror plane {plane!r}; "
                                 f"expected one of {sorted(MIRRORS)}")
            at = MIRRORS[plane] @ at
            orient = orient.mirrored(plane)
            name = f"{name}.{plane}"
            mtype = mtype.mirrored(plane)        # a coupled 6x6 type: its mirror image
        return dataclasses.replace(self, name=name, at=at, orientation=orient, type=mtype)


@dataclass(frozen=True, eq=False)
class Support:
    """A named ground point set whose motion is prescribed on its own (multi-support excitation).

    A mount whose ``to`` end is ground stands on the rigid ``ground`` unless it names a support
    (``Mount(..., support="left")``); each support has six rigid-motion DOFs about the global origin
    of its own, driven by the inputs ``<support>.<x|y|z|rx|ry|rz>.disp|vel|acc`` (a vehicle's road
    input per wheel, a floor moving differently under each foot), and the outputs
    ``<support>.fx|fy|fz|mx|my|mz`` give the force and moment about the global origin its mounts put
    into it. In statics a support is fixed ground.

    Parameters
    ----------
    name : str
        Unique name, distinct from every body, control point and ``ground``.
    description : str
        Free text for reports.

    Examples
    --------
    >>> Support("left", "front wheel road input").name
    'left'
    """

    name: str
    description: str = ""

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name.strip():
            raise ModelError(f"support: name must be a non-empty string, got {self.name!r}")
        who = f"support {self.name!r}"
        if self.name in (GROUND, "mount", "sensor", "actuator"):
            raise ModelError(f"{who}: the name {self.name!r} is reserved; name the support otherwise")
        if "." in self.name:
            raise ModelError(f"{who}: name contains '.', which separates the parts of signal names "
                             f"('{self.name}.z.acc' would be ambiguous); use another character")
        _signal_safe(self.name, who)
        if not isinstance(self.description, str):
            raise ModelError(f"{who}: description must be a string, got {self.description!r}")


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
