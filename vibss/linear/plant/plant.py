"""The second-order input/output description of a study ("plant"), shared by every dynamic analysis.

A study picks **inputs** (forces on bodies or points; prescribed displacement, velocity or
acceleration of ground or body DOFs) and **outputs** (motions of DOFs and points, mount deflections
and forces, total transmitted forces). A :class:`Plant` holds the second-order matrices of the
unknown (free) DOFs and the maps of every input and output, in SI:

    M q'' + C q' + K q = F u_f - (Kz z + Cz z' + Mz z'')
    y = Oq q + Ov q' + Oa q'' + Pz z + Pv z' + Pa z'' + Pf u_f   (+ i (Oh q + Ph z), frequency domain)

where ``u_f`` are the force inputs and ``z`` the prescribed coordinates. Each input column ``j``
is one named signal; a force input has a nonzero column in ``F`` and zero columns in ``Kz, Cz, Mz,
Pz, Pv, Pa``; a motion input has the reverse. ``kinds[j]`` says what the signal ``u_j`` *is*:
``"force"`` (u = f), ``"displacement"`` (u = z), ``"velocity"`` (u = z'), ``"acceleration"``
(u = z''). In the frequency domain ``z = u / (i w)^order`` with order 0, 1, 2; in the time domain
each kind gets an exact realization (see :mod:`vibss.statespace`).

Frequency-domain-only hysteretic stiffness enters as ``K + i H`` and ``Kz + i Hz``.

The plant is built by :func:`vibss.linear.plant.build.build_plant`; analyses take a Plant, never re-derive it.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np
import numpy.typing as npt

from ..._validate import name_index
from ...errors import AnalysisError, ModelError, SignalIndexError
from ...results import ReadOnly
from .branches import Branches

__all__ = ["Plant", "MountForm", "INPUT_KINDS", "MOTION_ORDER", "FIELD_ROLES"]

INPUT_KINDS = ("force", "displacement", "velocity", "acceleration")
"""What an input signal is."""

MOTION_ORDER = {"displacement": 0, "velocity": 1, "acceleration": 2}
"""Time derivative of the prescribed coordinate that a motion input gives."""

FIELD_ROLES: dict[str, str] = {
    "dofs": "dof labels", "M": "dof x dof", "C": "dof x dof", "K": "dof x dof", "H": "dof x dof",
    "F": "dof x input", "Kz": "dof x input", "Cz": "dof x input", "Mz": "dof x input",
    "Hz": "dof x input",
    "Oq": "output x dof", "Ov": "output x dof", "Oa": "output x dof", "Oh": "output x dof",
    "Kf": "factor x dof", "mounts": "mount form", "branches": "branches",
    "inputs": "input labels", "kinds": "input labels",
    "outputs": "output labels", "units": "output labels",
    "Pz": "output x input", "Pv": "output x input", "Pa": "output x input", "Pf": "output x input",
    "Ph": "output x input",
    "name": "other", "_cache": "other",
}
"""How each :class:`Plant` field changes under :meth:`Plant.select`, :meth:`Plant.restrict` and
:meth:`Plant.project`, by the axes it spans (``"factor x dof"`` is a stiffness factor ``Kf`` with
``K = Kf^T Kf``: its columns follow the DOFs; ``"mount form"`` is the :class:`MountForm`, kept by a
selection of signals and dropped by restriction and projection, which change the matrices it
reproduces; ``"branches"`` is the :class:`~vibss.linear.plant.branches.Branches`, cut and projected by its
own methods). A field missing here is carried along unchanged when
it is None and refused otherwise, so a new field must be classified before a plant operation can
silently get it wrong."""


@dataclass(frozen=True, eq=False)
class MountForm(ReadOnly):
    """The dynamic stiffness of a plant kept as a sum over its mounts: ``K + iH + sC = R(s) + B^T Z(s) B``.

    Assembling ``K = sum B_p^T k_p B_p`` rounds every entry at the level of the stiffest mount it
    holds; the soft modes beside stiff mounts (stiffness ratios of 1e5 and more) are sensitive to
    exactly that round-off. Kept apart, the mount forces ``lam = Z B q`` become unknowns of their
    own (:mod:`vibss.linear.solve.exact`, ``form="mounts"``) and nothing large is ever summed.

    Attributes
    ----------
    B : (3 q, n) scipy.sparse CSR matrix
        Deflection (global axes) of each of the q mounts kept apart per unit free-DOF motion [m/m, m/rad].
    kp, cp, hp : (q, 3, 3) ndarray
        Their stiffness [N/m], viscous damping [N s/m] and hysteretic stiffness [N/m] in global
        axes; every ``kp`` is positive definite.
    K, C, H : (n, n) scipy.sparse CSR matrix
        The rest, assembled: mounts with a zero principal stiffness, added modal damping.
    source : tuple of ndarray
        The plant's own ``(K, C, H, M)`` arrays this form reproduces; the solve uses the form only
        for a plant holding these very arrays (a plant derived with ``dataclasses.replace`` and
        new matrices falls back to them).
    Ba : (r, n) scipy.sparse CSR matrix
        Deflection along each stiff local axis of the mounts kept apart per axis: those with a zero
        principal stiffness (not positive definite) whose local matrices are diagonal [m/m, m/rad].
    ka, ca, ha : (r,) ndarray
        Stiffness [N/m] (> 0), viscous damping [N s/m] and hysteretic stiffness [N/m] of those axes;
        the zero axes' dampers are in ``C``.
    stiffness_ratio : float
        Largest principal stiffness of the mounts kept apart over the smallest nonzero principal
        stiffness of any mount touching a free DOF (kept apart or assembled with the rest).
    inertia_w2 : float
        When the mounts leave a motion free (only inertia holds it): the largest
        ``k_max,p lambda_max(B_p M^-1 B_p^T)`` over the mounts kept apart [rad^2/s^2], the square of
        the frequency at which a mount's stiffness equals the inertia ``m w^2`` of the lightest mass
        (or moment of inertia at its lever arm) it moves. The assembled ``K`` rounds at the stiffest
        mount's level, so below ``sqrt(inertia_w2 / MOUNTS_RATIO)`` a free motion's inertia is
        swamped by that round-off. 0 when nothing is free.
    """

    B: Any
    kp: np.ndarray
    cp: np.ndarray
    hp: np.ndarray
    K: Any
    C: Any
    H: Any
    source: tuple
    stiffness_ratio: float
    inertia_w2: float = 0.0
    Ba: Any = None
    ka: np.ndarray = field(default_factory=lambda: np.zeros(0))
    ca: np.ndarray = field(default_factory=lambda: np.zeros(0))
    ha: np.ndarray = field(default_factory=lambda: np.zeros(0))

    @property
    def rows(self) -> Any:
        """(3 q + r, n) CSR: ``B`` over ``Ba``, the rows of every mount force kept apart."""
        if self.Ba is None or self.Ba.shape[0] == 0:
            return self.B
        import scipy.sparse as sp
        return sp.csr_matrix(sp.vstack([self.B, self.Ba]))

    def z_blocks(self, s: complex) -> tuple[np.ndarray, np.ndarray] | None:
        """``Z(s)^-1``'s (q, 3, 3) blocks and per-axis scalars (``Z = k + s c + i h`` of every mount force
        kept apart), or None where ``Z`` is singular."""
        with np.errstate(all="ignore"):
            zi = np.linalg.inv(self.kp + s * self.cp + 1j * self.hp)              # (q, 3, 3)
            za = 1.0 / (self.ka + s * self.ca + 1j * self.ha)
        return (zi, za) if np.all(np.isfinite(zi)) and np.all(np.isfinite(za)) else None

    def z_inverse(self, s: complex) -> np.ndarray | None:
        """:meth:`z_blocks` as one dense (3 q + r) square matrix (block diagonal: the 3 x 3 blocks, then
        the per-axis scalars), or None where ``Z`` is singular."""
        z = self.z_blocks(s)
        if z is None:
            return None
        zi, za = z
        q3 = 3 * self.kp.shape[0]
        out = np.zeros((q3 + za.size,) * 2, dtype=complex)
        for p in range(self.kp.shape[0]):
            out[3 * p:3 * p + 3, 3 * p:3 * p + 3] = zi[p]
        out[np.arange(q3, q3 + za.size), np.arange(q3, q3 + za.size)] = za
        return out

    def z_diagonal(self, s: complex) -> np.ndarray:
        """``|Z_pp(s)|`` of every mount force kept apart, (3 q + r,) [N/m]."""
        z = self.kp + s * self.cp + 1j * self.hp
        return np.concatenate([np.abs(np.einsum("qii->qi", z)).ravel(), np.abs(self.ka + s * self.ca + 1j * self.ha)])

    owns_arrays: ClassVar[bool] = True     # read-only in place (source: the plant's own arrays)

    def matches(self, plant: Plant) -> bool:
        """Whether ``plant`` holds the very ``K, C, H, M`` arrays this form was built for."""
        return all(a is b for a, b in zip(self.source, (plant.K, plant.C, plant.H, plant.M)))


@dataclass(frozen=True, eq=False)
class Plant(ReadOnly):
    """Second-order matrices of the free DOFs plus named input and output maps.

    Its arrays are read-only (made so in place on construction: every analysis and cached
    factorisation of the plant shares them); ``.copy()`` one to change it.

    Attributes
    ----------
    dofs : tuple of str
        Labels of the free (unknown) DOFs, ``'<body>.<dof>'`` (n of them).
    M, C, K, H : (n, n) ndarray
        Mass, viscous damping, stiffness and hysteretic stiffness of the free DOFs (SI).
    inputs : tuple of str
        Input signal names (m of them).
    kinds : tuple of str
        ``INPUT_KINDS`` entry per input.
    F : (n, m) ndarray
        Generalised force per unit force input [N/N, N m/N ...].
    Kz, Cz, Mz, Hz : (n, m) ndarray
        Coupling of each prescribed coordinate into the free DOFs (moved to the right-hand side
        with a minus sign).
    outputs : tuple of str
        Output signal names (p of them).
    units : tuple of str
        SI unit of each output (``"m"``, ``"rad"``, ``"m/s"``, ``"N"`` ...).
    Oq, Ov, Oa : (p, n) ndarray
        Output per free-DOF displacement, velocity and acceleration.
    Pz, Pv, Pa, Pf : (p, m) ndarray
        Output per prescribed displacement, velocity, acceleration, and per force input
        (direct feedthrough).
    name : str
        System name (the model's).
    Oh, Ph : (p, n), (p, m) ndarray or None
        Hysteretic part of the outputs (frequency domain only): ``y += i (Oh q + Ph z)``, e.g. the
        loss-factor force ``i H_p delta`` of a mount force output. None means zero.
    Kf : (r, n) ndarray or scipy.sparse matrix or None
        Stiffness factor of the free DOFs, ``K = Kf^T Kf`` (one row per mount principal axis,
        ``sqrt(k) T^T B``); the eigen path and statics use it to stay exact beside stiff links
        (K formed in floats loses soft mounts next to 1e16 N/m links). None: not known (e.g. a
        projected plant); analyses then work from K. Restricting a plant to DOFs keeps
        ``Kf[:, dofs]`` only when the dropped DOFs are prescribed (not condensed).
    mounts : MountForm or None
        ``K, C, H`` kept as a sum over the mounts, for the exact solve on badly scaled models
        (:func:`vibss.linear.plant.build.build_plant` sets it; None: only the assembled matrices).
    branches : Branches or None
        Maxwell branches of frequency-dependent mounts (internal states; ``K`` and ``C`` hold their
        static stiffness and dashpots only): :mod:`vibss.linear.plant.branches`. None: no such mount.
    """

    dofs: tuple[str, ...]
    M: np.ndarray
    C: np.ndarray
    K: np.ndarray
    H: np.ndarray
    inputs: tuple[str, ...]
    kinds: tuple[str, ...]
    F: np.ndarray
    Kz: np.ndarray
    Cz: np.ndarray
    Mz: np.ndarray
    Hz: np.ndarray
    outputs: tuple[str, ...]
    units: tuple[str, ...]
    Oq: np.ndarray
    Ov: np.ndarray
    Oa: np.ndarray
    Pz: np.ndarray
    Pv: np.ndarray
    Pa: np.ndarray
    Pf: np.ndarray
    name: str = "vibss"
    Oh: np.ndarray | None = None
    Ph: np.ndarray | None = None
    Kf: Any = None
    mounts: MountForm | None = None
    branches: Branches | None = None
    _cache: dict[str, Any] = field(default_factory=dict, init=False, repr=False)

    # shared by every analysis of this plant and by its cached factorisations: read-only in place,
    # so an in-place change through a handle cannot make a cached value stale
    owns_arrays: ClassVar[bool] = True

    def cached(self, key: str, make: Callable[[], Any]) -> Any:
        """``make()``, computed once per plant (sparse forms, factorisations of its matrices).

        The plant is frozen, so a derived quantity never goes stale; ``dataclasses.replace`` makes
        a new plant with an empty cache (the field is not an init argument).

        Parameters
        ----------
        key : str
            Name of the quantity (e.g. ``"sparse C"``, ``"solve K"``).
        make : callable
            Computes it.
        """
        if key not in self._cache:
            self._cache[key] = make()
        return self._cache[key]

    def known(self, key: str) -> Any:
        """The quantity ``key`` if it was already computed for this plant (:meth:`cached`), else
        None: for a choice that may read it but should not pay for it."""
        return self._cache.get(key)

    @property
    def n(self) -> int:
        """Number of free DOFs."""
        return len(self.dofs)

    @property
    def order(self) -> np.ndarray:
        """(m,) time-derivative order of each input's prescribed coordinate (-1 for forces)."""
        return np.array([MOTION_ORDER.get(k, -1) for k in self.kinds])

    # ---------------------------------------------------------------- operations on the plant

    def _fields_by_role(self) -> dict[str, list[str]]:
        """The plant's non-None fields grouped by :data:`FIELD_ROLES` (an unclassified one refused)."""
        roles: dict[str, list[str]] = {}
        for f in dataclasses.fields(self):
            role = FIELD_ROLES.get(f.name)
            value = getattr(self, f.name)
            if role is None:
                if value is None:
                    continue
                raise AnalysisError(f"Plant field {f.name!r} has no role in plant.FIELD_ROLES; "
                                    "classify it before selecting, restricting or projecting plants")
            if value is not None:
                roles.setdefault(role, []).append(f.name)
        return roles

    def select(self, inputs: Sequence[str | int] | None = None,
               outputs: Sequence[str | int] | None = None) -> Plant:
        """The plant with a subset (or reordering) of its inputs and outputs.

        Every input- or output-indexed field is cut the same way (hysteretic output parts ``Oh`` and
        ``Ph`` included), so the selected plant's response is the corresponding rows and columns of
        the full one.

        Parameters
        ----------
        inputs, outputs : sequence of str or int, or None
            Signals to keep, by name or index, in the order wanted; None keeps all.

        Returns
        -------
        Plant

        Raises
        ------
        SignalError
            A name that is not among the plant's signals (with did-you-mean), or an index out of
            range (:class:`~vibss.errors.SignalIndexError`).

        Examples
        --------
        >>> from ... import Body, Model, Mount, MountType
        >>> from .build import build_plant
        >>> m = Model([Body("b", 1.0, [1, 1, 1])], [Mount("m", MountType("t", [1e3] * 3), "b")])
        >>> p = build_plant(m, ["b.fz", "b.fx"], ["b.x", "b.z"]).select(["b.fz"], ["b.z"])
        >>> p.inputs, p.outputs, p.F.shape, p.Oq.shape
        (('b.fz',), ('b.z',), (6, 1), (1, 6))
        """
        i = _indices(self.inputs, inputs, "inputs")
        o = _indices(self.outputs, outputs, "outputs")
        changes: dict[str, Any] = {}
        for role, names in self._fields_by_role().items():
            for key in names:
                a = getattr(self, key)
                if role == "input labels" and i is not None:
                    changes[key] = tuple(a[j] for j in i)
                elif role == "output labels" and o is not None:
                    changes[key] = tuple(a[j] for j in o)
                elif role == "dof x input" and i is not None:
                    changes[key] = a[:, i]
                elif role == "output x dof" and o is not None:
                    changes[key] = a[o]
                elif role == "output x input" and (i is not None or o is not None):
                    a = a if o is None else a[o]
                    changes[key] = a if i is None else a[:, i]
                elif role == "branches":
                    changes[key] = a.select(i, o)
        return dataclasses.replace(self, **changes)

    def restrict(self, dofs: Sequence[str | int] | npt.ArrayLike) -> Plant:
        """The plant on a subset of its free DOFs, the others held at zero.

        Rows and columns of ``M, C, K, H``, rows of the input maps ``F, Kz, Cz, Mz, Hz``, columns
        of the output maps ``Oq, Ov, Oa, Oh`` and of a stiffness factor ``Kf`` (so ``K = Kf^T Kf``
        still holds); the :class:`MountForm` is dropped (the exact solve then uses the matrices). Exact when the dropped DOFs are decoupled from the kept ones, or not
        excited and not seen.

        Parameters
        ----------
        dofs : sequence of str or int, or (n,) bool array_like
            DOFs to keep, by label or index (in the order wanted), or a mask over ``plant.dofs``.

        Returns
        -------
        Plant
            Sparse matrices stay sparse (CSR).

        Raises
        ------
        SignalError
            An unknown label, or an index out of range (:class:`~vibss.errors.SignalIndexError`).

        Examples
        --------
        >>> from ... import Body, Model, Mount, MountType
        >>> from .build import build_plant
        >>> m = Model([Body("b", 1.0, [1, 1, 1])], [Mount("m", MountType("t", [1e3] * 3), "b")])
        >>> build_plant(m, ["b.fz"], ["b.z"]).restrict(["b.z"]).K
        array([[1000.]])
        """
        if isinstance(dofs, str):
            dofs = [dofs]
        wanted = list(dofs) if isinstance(dofs, (list, tuple)) else np.asarray(dofs).ravel().tolist()
        if wanted and all(isinstance(w, (bool, np.bool_)) for w in wanted):
            if len(wanted) != self.n:
                raise ModelError(f"restrict: dofs: a mask needs {self.n} entries (one per free DOF), "
                                 f"got {len(wanted)}")
            k = [j for j, w in enumerate(wanted) if w]
        else:
            k = _indices(self.dofs, wanted, "dofs") or []
        idx = np.asarray(k, dtype=int)
        changes: dict[str, Any] = {}
        for role, names in self._fields_by_role().items():
            for key in names:
                a = getattr(self, key)
                if role == "dof labels":
                    changes[key] = tuple(a[j] for j in k)
                elif role == "dof x dof":
                    changes[key] = _rows(a, idx)[:, idx]
                elif role == "dof x input":
                    changes[key] = _rows(a, idx)
                elif role in ("output x dof", "factor x dof"):
                    changes[key] = a[:, idx]
                elif role == "mount form":
                    changes[key] = None
                elif role == "branches":
                    changes[key] = a.restrict(idx)
        return dataclasses.replace(self, **changes)

    def project(self, V: npt.ArrayLike, dofs: Sequence[str] | None = None, **known: Any) -> Plant:
        """Galerkin projection ``q = V a`` on the columns of ``V`` (n, r).

        ``V^T M V``, ``V^T C V``, ``V^T K V``, ``V^T H V`` (symmetrised), ``V^T`` times the input
        maps, the output maps times ``V`` and a stiffness factor ``Kf V`` (dropped when ``K`` is given
        in ``known``: ``Kf V`` need not factor it); the :class:`MountForm` is dropped; feedthrough is
        kept.

        Parameters
        ----------
        V : (n, r) array_like
            Basis (columns) in the free DOFs.
        dofs : sequence of str or None
            Labels of the r generalised coordinates; default ``'v1' ... 'vr'``.
        **known : ndarray
            Fields whose projection is known exactly and is used instead of computing it (e.g.
            ``M=np.eye(r), K=np.diag(omega2)`` for mass-normalised modes).

        Returns
        -------
        Plant
            Dense matrices, ``r`` DOFs.

        Raises
        ------
        ModelError
            ``V`` does not have one row per free DOF, ``dofs`` the wrong length, or ``known``
            names no projected field.

        Examples
        --------
        >>> import numpy as np
        >>> from ... import Body, Model, Mount, MountType
        >>> from .build import build_plant
        >>> m = Model([Body("b", 2.0, [1, 1, 1])], [Mount("m", MountType("t", [1e3] * 3), "b")])
        >>> p = build_plant(m, ["b.fz"], ["b.z"])
        >>> p.project(np.eye(6)[:, [2]], ["z"]).M      # the z row and column
        array([[2.]])
        """
        v = np.asarray(V, dtype=float)
        if v.ndim != 2 or v.shape[0] != self.n:
            raise ModelError(f"project: V: expected an ({self.n}, r) basis (one row per free DOF), "
                             f"got shape {v.shape}")
        r = v.shape[1]
        labels = tuple(f"v{i + 1}" for i in range(r)) if dofs is None else tuple(dofs)
        if len(labels) != r:
            raise ModelError(f"project: dofs: expected {r} labels (one per column of V), got {len(labels)}")
        roles = self._fields_by_role()
        projected = {key for role in ("dof x dof", "dof x input", "output x dof", "factor x dof")
                     for key in roles.get(role, [])}
        unknown = sorted(set(known) - projected)
        if unknown:
            raise ModelError(f"project: {unknown}: not projected fields of this plant; "
                             f"expected some of {sorted(projected)}")
        changes: dict[str, Any] = {"dofs": labels, **known}
        for role, names in roles.items():
            for key in names:
                if key in known:
                    continue
                a = getattr(self, key)
                if role == "dof x dof":
                    g = np.zeros((r, r)) if not _nonzero(a) else np.asarray(v.T @ (a @ v))
                    changes[key] = 0.5 * (g + g.T)
                elif role == "dof x input":
                    changes[key] = np.asarray(v.T @ a) if _nonzero(a) else np.zeros((r, a.shape[1]))
                elif role == "output x dof":
                    changes[key] = np.asarray(a @ v)
                elif role == "factor x dof":      # a factor of a given K is not known: dropped
                    changes[key] = None if "K" in known else np.asarray(a @ v)
                elif role == "mount form":
                    changes[key] = None
                elif role == "branches":
                    changes[key] = a.project(v)
        return dataclasses.replace(self, **changes)


def _nonzero(a: Any) -> bool:
    """Whether a dense or sparse matrix has a nonzero entry."""
    return bool(a.count_nonzero()) if hasattr(a, "count_nonzero") and not isinstance(a, np.ndarray) \
        else bool(np.any(a))


def _rows(a: Any, idx: np.ndarray) -> Any:
    """Rows ``idx`` of a dense or sparse matrix (sparse ones come back as CSR)."""
    out = a[idx]
    return out.tocsr() if hasattr(out, "tocsr") else out


def _indices(names: tuple[str, ...], wanted: Sequence[str | int] | None, what: str) -> list[int] | None:
    """Positions of ``wanted`` (names or indices) among the plant's ``what`` (``names``); None for None."""
    if wanted is None:
        return None
    if isinstance(wanted, str):
        wanted = [wanted]
    one = {"inputs": "input", "outputs": "output", "dofs": "dof"}.get(what, what)
    out = []
    for w in wanted:
        if isinstance(w, (int, np.integer)) and not isinstance(w, (bool, np.bool_)):
            if not -len(names) <= int(w) < len(names):
                raise SignalIndexError(f"Plant: {what}: index {int(w)} is out of range for the plant's "
                                       f"{len(names)} {what}", argument=what, received=int(w),
                                       expected=f"-{len(names)} .. {len(names) - 1}")
            out.append(int(w) % len(names))
        else:
            out.append(name_index(w, names, one, who="Plant"))
    return out
