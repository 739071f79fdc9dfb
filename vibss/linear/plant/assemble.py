"""Assembly: Model -> mass, stiffness and damping matrices, and the maps from named points to DOFs.

The system vector stacks the bodies' DOFs in definition order, ``q = [x1 y1 z1 rx1 ry1 rz1, x2 ...]``.
Ground is assembled as a seventh "body" whose six DOFs come last (its reference point is the global
origin), so that prescribed ground motion and the rigid-motion invariant need no special case:
``K_full`` (size n + 6) annihilates any rigid motion of the whole system with ground released.
Each named support (:class:`vibss.model.mounts.Support`) is one more such ground node after it,
six DOFs about the global origin: the ground-side coordinates are ``nz = 6 (1 + n_supports)``, and a
mount on a support couples to that node's block only (so a model without supports is unchanged).

Per mount p joining point P of body b to the same point of a (a body or ground),
``delta_p = L(r_b) q_b - L(r_a) q_a = B_p q`` and ``K = sum_p B_p^T (T diag(k) T^T) B_p``, likewise
for C; a 6x6 mount adds ``R_p^T (T diag(kr) T^T) R_p`` with ``theta_p = R_p q`` its relative rotation,
and a full 6x6 ``stiffness_matrix`` its blocks ``T K_tt T^T``, ``T K_rr T^T`` and the coupling
``B_p^T (T K_tr T^T) R_p`` plus its transpose. The sum is vectorised over mounts (no Python loop per mount) and scattered as COO triplets,
into a dense array for small models or a scipy.sparse CSR matrix for large ones.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import Any, ClassVar

import numpy as np
import numpy.typing as npt
import scipy.sparse as sp

from ...errors import ModelError
from ...results import ReadOnly, freeze
from ...model.geometry import point_transfer
from ...model.model import DOF_NAMES, GROUND, Model
from ..eigen.csr import csr_of
from ..eigen.small import symmetric_eigen
from .memo import remembered
from .sums import _MountMatrices, _block_pattern, _mass, _mount_matrices, _mount_points, _summed

__all__ = ["Assembly", "assemble", "SPARSE_THRESHOLD", "dof_labels"]

_SIX = np.arange(6)

SPARSE_THRESHOLD = 1200
"""Models with more DOFs than this are assembled as scipy.sparse matrices by default."""

Matrix = "np.ndarray | sp.csr_matrix"


def dof_labels(body_names: list[str]) -> tuple[str, ...]:
    """DOF labels ``'<body>.<dof>'`` in system order."""
    return tuple(f"{b}.{d}" for b in body_names for d in DOF_NAMES)


@dataclass(frozen=True, eq=False)
class Assembly(ReadOnly):
    """Assembled matrices of a model.

    Its arrays and sparse matrices are read-only (every later analysis of the assembly shares
    them); ``.copy()`` one to change it.

    Attributes
    ----------
    model : Model
        The model assembled.
    dofs : tuple of str
        DOF labels ``'<body>.<dof>'`` (n = 6 x bodies).
    M, K, C : (n, n) ndarray or scipy.sparse matrix
        Mass [kg, kg m^2], stiffness [N/m, N m/rad ...] and viscous damping matrices of the body DOFs
        with ground fixed.
    Kg, Cg : (n, nz) ndarray
        Coupling of the body DOFs to the ground-side DOFs: six of the rigid ground (x y z rx ry rz
        about the global origin), then six per support: ground motion ``z_g`` adds
        ``-Kg z_g - Cg dz_g/dt`` to the generalised forces.
    H : (n, n) ndarray or scipy.sparse matrix
        Hysteretic stiffness ``sum B^T T diag(eta k) T^T B`` (frequency domain: ``K + iH``).
    Hg : (n, nz) ndarray
        Hysteretic coupling to ground.
    kp, cp, hp : (n_mounts, 3, 3) ndarray
        Each mount's stiffness, damping and hysteretic matrices in global axes.
    krp, crp : (n_mounts, 3, 3) ndarray
        Each mount's rotational stiffness [N m/rad] and damping [N m s/rad] in global axes (6x6
        mounts; zeros otherwise): the moment ``krp (theta_body - theta_to)``.
    kcp, ccp : (n_mounts, 3, 3) ndarray
        Each mount's coupling stiffness [N/rad] and damping [N s/rad] in global axes (a full 6x6
        matrix's off-diagonal block ``T K_tr T^T``; zeros otherwise): the force into the ``to`` side
        is ``kp delta + kcp theta`` and the moment ``kcp^T delta + krp theta``.
    b_index, a_index : (n_mounts,) int ndarray
        Body index of each mount's ``body`` and ``to`` (``n_bodies`` for the rigid ground,
        ``n_bodies + 1 + s`` for support s).
    r_b, r_a : (n_mounts, 3) ndarray
        Attachment point relative to the COG of ``body`` and of ``to`` (global origin for ground) [m].
    sparse : bool
        Whether the matrices are scipy.sparse.
    """

    model: Model
    dofs: tuple[str, ...]
    M: np.ndarray | sp.csr_matrix
    K: np.ndarray | sp.csr_matrix
    Kg: np.ndarray
    kp: np.ndarray
    cp: np.ndarray
    hp: np.ndarray
    b_index: np.ndarray
    a_index: np.ndarray
    r_b: np.ndarray
    r_a: np.ndarray
    sparse: bool = False
    krp: np.ndarray = field(default_factory=lambda: np.zeros((0, 3, 3)))
    crp: np.ndarray = field(default_factory=lambda: np.zeros((0, 3, 3)))
    kcp: np.ndarray = field(default_factory=lambda: np.zeros((0, 3, 3)))
    ccp: np.ndarray = field(default_factory=lambda: np.zeros((0, 3, 3)))
    _cache: dict = field(default_factory=dict, repr=False)

    # the assembly owns its matrices and every later analysis shares them: frozen in place, so an
    # in-place change through a handle cannot alter those analyses
    owns_arrays: ClassVar[bool] = True

    @property
    def C(self) -> np.ndarray | sp.csr_matrix:
        """Viscous damping of the body DOFs [N s/m ...] (summed on first use, with ``H``: modes need neither)."""
        return self._damping()["C"][0]

    @property
    def H(self) -> np.ndarray | sp.csr_matrix:
        """Hysteretic stiffness of the body DOFs [N/m ...] (``K + iH`` in the frequency domain)."""
        return self._damping()["H"][0]

    @property
    def Cg(self) -> np.ndarray:
        """(n, nz) viscous coupling of the body DOFs to the ground-side DOFs."""
        return self._damping()["C"][1]

    @property
    def Hg(self) -> np.ndarray:
        """(n, nz) hysteretic coupling of the body DOFs to the ground-side DOFs."""
        return self._damping()["H"][1]

    def _damping(self) -> dict[str, tuple[Any, np.ndarray]]:
        """C and H with their ground couplings, summed over the mounts once (both in one call), frozen."""
        if "damping" not in self._cache:
            mm = _MountMatrices(self.kp, self.cp, self.hp, self.krp, self.crp, self.kcp, self.ccp)
            mats, couplings = _summed(self.model, self._cache["pattern"], mm, self.sparse, ("C", "H"))
            self._cache["damping"] = freeze({key: (mats[key], couplings[key]) for key in ("C", "H")})
        return self._cache["damping"]

    @property
    def n(self) -> int:
        """Number of body DOFs."""
        return len(self.dofs)

    @property
    def nz(self) -> int:
        """Number of ground-side DOFs: six of the rigid ground and six per support."""
        return 6 * (1 + len(self.model.supports))

    def ground_offset(self, target: str) -> int:
        """Offset of a ground node's six DOFs (``"ground"`` or a support name) in ``[q; q_ground]``."""
        if target == GROUND:
            return self.n
        return self.n + 6 * (1 + self.model.support_names.index(target))

    @property
    def has_damping(self) -> bool:
        """Whether any mount has viscous damping (translational or rotational)."""
        return bool(np.any(self.cp) or np.any(self.crp))

    @property
    def has_coupling(self) -> bool:
        """Whether any mount has a 6x6 matrix coupling its deflection and rotation."""
        return bool(np.any(self.kcp) or np.any(self.ccp))

    @property
    def has_hysteresis(self) -> bool:
        """Whether any mount has a hysteretic loss factor."""
        return bool(np.any(self.hp))

    def dense(self, name: str) -> np.ndarray:
        """Matrix ``name`` ('M', 'K', 'C' or 'H') as a dense array (cached for sparse models).

        Read-only: it is the assembly's own matrix (or its cached dense copy), shared by every later
        analysis of this assembly; ``.copy()`` it to change it."""
        mat = getattr(self, name)
        if not sp.issparse(mat):
            if isinstance(mat, np.ndarray):
                mat.flags.writeable = False
            return mat
        if name not in self._cache:
            dense = mat.toarray()
            dense.flags.writeable = False
            self._cache[name] = dense
        return self._cache[name]

    def dof_index(self, label: str) -> int:
        """Index of DOF ``'<body>.<dof>'`` in the system vector."""
        try:
            return self._dof_map[label]
        except KeyError:
            raise ModelError(f"unknown DOF {label!r}; DOFs are '<body>.<x|y|z|rx|ry|rz>', "
                             f"e.g. {self.dofs[0]!r}") from None

    @cached_property
    def _dof_map(self) -> dict[str, int]:
        return {d: i for i, d in enumerate(self.dofs)}

    def point_matrix(self, body: str, r: npt.ArrayLike) -> np.ndarray:
        """(3, n) map from q to the displacement of point ``r`` (relative to the COG) of ``body``."""
        out = np.zeros((3, self.n))
        i = self.model.body_index(body)
        out[:, 6 * i:6 * i + 6] = point_transfer(r)
        return out

    def deflection_matrix(self) -> sp.csr_matrix:
        """(3 n_mounts, n + nz) sparse map from ``[q; q_ground]`` to mount deflections (global axes).

        Rows ``3p .. 3p+2`` give ``delta_p = d_body - d_to`` of mount p.
        """
        if "B" not in self._cache:
            nm, nb = len(self.b_index), len(self.model.bodies)
            lb, la = point_transfer(self.r_b), point_transfer(self.r_a)
            rows = np.repeat(3 * np.arange(nm), 18).reshape(nm, 3, 6) + np.arange(3)[None, :, None]
            cb = 6 * self.b_index[:, None, None] + np.arange(6)[None, None, :]
            ca = 6 * self.a_index[:, None, None] + np.arange(6)[None, None, :]
            rr = np.concatenate([rows.ravel(), rows.ravel()])
            cc = np.concatenate([np.broadcast_to(cb, rows.shape).ravel(),
                                 np.broadcast_to(ca, rows.shape).ravel()])
            vv = np.concatenate([lb.ravel(), -la.ravel()])
            self._cache["B"] = sp.csr_matrix((vv, (rr, cc)), shape=(3 * nm, 6 * nb + self.nz))
        return self._cache["B"]

    def rotation_matrix(self) -> sp.csr_matrix:
        """(3 n_mounts, n + nz) sparse map from ``[q; q_ground]`` to each mount's relative rotation.

        Rows ``3p .. 3p+2`` give ``theta_p = theta_body - theta_to`` of mount p (global axes) [rad],
        which its rotational stiffness resists (6x6 mounts).
        """
        if "R" not in self._cache:
            nm, nb = len(self.b_index), len(self.model.bodies)
            rows = np.tile(np.arange(3), nm) + np.repeat(3 * np.arange(nm), 3)
            cb = (6 * np.repeat(self.b_index, 3) + 3 + np.tile(np.arange(3), nm))
            ca = (6 * np.repeat(self.a_index, 3) + 3 + np.tile(np.arange(3), nm))
            self._cache["R"] = sp.csr_matrix((np.concatenate([np.ones(3 * nm), -np.ones(3 * nm)]),
                                              (np.concatenate([rows, rows]), np.concatenate([cb, ca]))),
                                             shape=(3 * nm, 6 * nb + self.nz))
        return self._cache["R"]

    def dense_factor(self) -> np.ndarray:
        """:meth:`stiffness_factor` as a read-only dense (r, n) array, the same numbers (cached).

        A small dense model's factor is made dense and its CSR only built when asked for: the
        eigen path of a 6-DOF model reads the dense array alone."""
        if "Gd" not in self._cache:
            plain = self._plain_dense()
            g = plain if plain is not None else self.stiffness_factor().toarray()
            g.flags.writeable = False
            self._cache["Gd"] = g
        return self._cache["Gd"]

    def _plain_dense(self) -> np.ndarray | None:
        """The dense factor of a dense assembly with translational rows only (else None)."""
        if self.sparse:
            return None
        k, t = self._rates()
        if not self._plain_factor(k):
            return None
        return self._dense_factor(np.sqrt(k)[:, :, None] * t.transpose(0, 2, 1), k)

    def _rates(self) -> tuple[np.ndarray, np.ndarray]:
        """(nm, 3) principal stiffnesses [N/m] (refused if negative) and (nm, 3, 3) local axes."""
        nm = len(self.b_index)
        k = np.array([m.type.stiffness for m in self.model.mounts], dtype=float).reshape(nm, 3)
        if np.any(k < 0):
            raise ModelError("stiffness_factor: a mount has a negative stiffness (K = G^T G needs k >= 0)")
        return k, np.array([m.orientation.matrix for m in self.model.mounts]).reshape(nm, 3, 3)

    def stiffness_factor(self) -> sp.csr_matrix:
        """(r, n) sparse factor G of the stiffness of the body DOFs: ``K = G^T G``.

        One row per mount principal axis with nonzero stiffness: ``sqrt(k_j) t_j^T B_p`` (``t_j`` the
        mount's axis j in global axes, ``B_p`` its deflection rows, ground fixed), then one per
        nonzero rotational rate: ``sqrt(kr_j) t_j^T R_p`` (``R_p`` its rotation rows); a mount with a
        coupled 6x6 ``stiffness_matrix`` gives one row per positive eigenvalue of its (diagonally
        scaled) matrix instead (:meth:`_matrix_factor`). Unlike K it keeps
        every mount's stiffness apart, so soft mounts are not lost beside stiff links when it is
        used by the eigen path (:func:`vibss.linear.eigen.undamped.undamped`) and by statics.

        Examples
        --------
        >>> from ... import Body, MountType, Mount, Model
        >>> m = Model([Body("b", 10.0, [1, 1, 1])], [Mount("m", MountType("t", [1e4, 1e4, 2e4]), "b", at=[0.1, 0, 0])])
        >>> a = assemble(m)
        >>> g = a.stiffness_factor()
        >>> bool(abs(g.T @ g - a.dense("K")).max() < 1e-9 * a.dense("K").max())
        True
        """
        if "G" not in self._cache:
            nm = len(self.b_index)
            k, t = self._rates()
            # block-diagonal diag(sqrt k) T^T, one 3x3 block per mount, times the deflection rows
            blocks = np.sqrt(k)[:, :, None] * t.transpose(0, 2, 1)          # (nm, 3, 3)
            if not self.sparse and self._plain_factor(k):
                self._cache["G"] = csr_of(self.dense_factor())
                return self._cache["G"]
            r = np.repeat(3 * np.arange(nm), 9).reshape(nm, 3, 3) + np.arange(3)[None, :, None]
            c = np.repeat(3 * np.arange(nm), 9).reshape(nm, 3, 3) + np.arange(3)[None, None, :]
            st = sp.csr_matrix((blocks.ravel(), (r.ravel(), c.ravel())), shape=(3 * nm, 3 * nm))
            g = (st @ self.deflection_matrix()[:, :self.n]).tocsr()
            keep = np.flatnonzero(np.sqrt(k).ravel() > 0)
            g = g[keep]
            kr = np.array([m.type.rotational_stiffness for m in self.model.mounts], dtype=float).reshape(nm, 3)
            full6 = np.array([m.type.stiffness_matrix is not None and m.type.coupled for m in self.model.mounts],
                             dtype=bool).reshape(nm)
            if np.any(full6):                 # full 6x6 matrices: their own factor, the rest as before
                g = g[np.flatnonzero(np.repeat(~full6, 3)[keep])]
                kr = np.where(full6[:, None], 0.0, kr)
                g = sp.vstack([g, self._matrix_factor(np.flatnonzero(full6), t)]).tocsr()
            if np.any(kr > 0):
                br = np.sqrt(kr)[:, :, None] * t.transpose(0, 2, 1)
                sr = sp.csr_matrix((br.ravel(), (r.ravel(), c.ravel())), shape=(3 * nm, 3 * nm))
                gr = (sr @ self.rotation_matrix()[:, :self.n]).tocsr()[np.flatnonzero(kr.ravel() > 0)]
                g = sp.vstack([g, gr]).tocsr()
            g.eliminate_zeros()
            g.sort_indices()
            self._cache["G"] = g
        return self._cache["G"]

    def _plain_factor(self, k: np.ndarray, kr: np.ndarray | None = None) -> bool:
        """Whether G has translational rows only (no rotational rates, no full 6x6 matrix); ``kr``:
        the mounts' (nm, 3) rotational rates when already read."""
        if kr is None:
            kr = np.array([m.type.rotational_stiffness for m in self.model.mounts], dtype=float)
        # count_nonzero: np.any's answer without its Python wrapper (a 6-DOF model asks this every time)
        return not np.count_nonzero(kr > 0) and not np.count_nonzero(self.b_index == self.a_index) and \
            not any(m.type.stiffness_matrix is not None and m.type.coupled for m in self.model.mounts)

    def _dense_factor(self, blocks: np.ndarray, k: np.ndarray,
                      levers: tuple[np.ndarray, np.ndarray] | None = None) -> np.ndarray:
        """:meth:`stiffness_factor` of a small model without sparse products: the same sums in the
        same order. scipy's ``st @ B`` adds, per entry, ``st[r, 3p + i] B[3p + i, c]`` over
        ``i = 0, 1, 2`` from zero, left to right (products of structural zeros left out, which adds
        nothing); elementwise NumPy does exactly those roundings (no fused multiply-add), so G is bit
        for bit the sparse path's, which the eigen path's accuracy on graded models depends on."""
        nm, nb = len(self.b_index), len(self.model.bodies)
        far = np.flatnonzero(self.a_index < nb)          # mounts whose far end is a body (not ground)
        if levers is None:
            lever = point_transfer(np.concatenate([self.r_b, -self.r_a]).reshape(2, nm, 3))
            lever[1, :, :, :3] = -lever[1, :, :, :3]                            # -L(r_a), exactly
        else:                                                                   # (L(r_b), L(r_a))
            lever = np.stack([levers[0], -levers[1]]) if far.size else levers[0][None]
        if not far.size:                     # every mount to ground (one body): the body ends alone
            lever = lever[:1]
        terms = blocks[None, :, :, :, None] * lever[:, :, None, :, :]           # (sides, nm, 3, 3, 6)
        acc = terms[:, :, :, 0] + terms[:, :, :, 1] + terms[:, :, :, 2]        # the product's order
        # each mount's 3 rows: its body's 6 columns, and the far body's (never the same body here)
        g4 = np.zeros((nm, 3, nb, 6))
        g4[np.arange(nm), :, self.b_index, :] = acc[0]
        if far.size:
            g4[far, :, self.a_index[far], :] = acc[1, far]
        g = g4.reshape(3 * nm, 6 * nb)
        kept = k.ravel() > 0                 # sqrt(k) > 0 (k >= 0): the rows of G that are not zero
        return (g if np.count_nonzero(kept) == kept.size else g[np.flatnonzero(kept)]) + 0.0   # +0.0: no -0.0

    def _matrix_factor(self, mounts: np.ndarray, t: np.ndarray) -> sp.csr_matrix:
        """Rows of G for mounts with a full 6x6 stiffness: ``K6 = V diag(lam) V^T`` in local axes,
        one row ``sqrt(lam_j) v_j^T [T^T B_p; T^T R_p]`` per positive eigenvalue."""
        rows = []
        b, r = self.deflection_matrix()[:, :self.n], self.rotation_matrix()[:, :self.n]
        for p in mounts:
            mount = self.model.mounts[p]
            k6 = mount.type.local_matrix("stiffness")
            d = np.sqrt(np.where(np.diag(k6) > 0, np.diag(k6), 1.0))
            lam, v = symmetric_eigen(k6 / np.outer(d, d))   # scaled: translation and rotation units differ
            if lam.min() < -1e-10 * max(1.0, lam.max()):
                raise ModelError(f"mount {mount.name!r}: its stiffness_matrix is indefinite (scaled eigenvalues "
                                 f"{np.round(lam, 6).tolist()}); K = G^T G needs it positive semi-definite")
            keep = lam > 1e-14 * max(lam.max(), 0.0)
            f = (np.sqrt(lam[keep])[:, None] * v[:, keep].T) * d[None, :]   # (k, 6): f^T f = K6 (local)
            local = sp.vstack([sp.csr_matrix(t[p].T) @ b[3 * p:3 * p + 3],
                               sp.csr_matrix(t[p].T) @ r[3 * p:3 * p + 3]])    # (6, n): [d_local; r_local]
            rows.append(sp.csr_matrix(f) @ local)
        return sp.vstack(rows).tocsr()

    def load_vector(self, include_gravity: bool = True, case: str | None = None,
                    include_loads: bool = True) -> np.ndarray:
        """(n,) generalised force of the model's static loads (and self-weight) [N, N m].

        Parameters
        ----------
        include_gravity : bool
            Add self-weight when the model defines gravity.
        case : str or None
            Load case: the unnamed loads plus those of this case; None: every load.
        include_loads : bool
            Add the loads at all (False: self-weight alone).
        """
        f = np.zeros(self.n)
        for ld in self.model.loads if include_loads else ():
            if case is not None and ld.case not in ("", case):
                continue
            i = self.model.body_index(ld.body)
            r = np.zeros(3) if ld.at is None else self.model.point(ld.body, ld.at, ld.frame)
            f[6 * i:6 * i + 6] += point_transfer(r).T @ ld.force
            f[6 * i + 3:6 * i + 6] += ld.moment
        if include_gravity and self.model.gravity is not None:
            for i, b in enumerate(self.model.bodies):
                f[6 * i:6 * i + 3] += b.masses * self.model.gravity
        return f


def assemble(model: Model, sparse: bool | None = None) -> Assembly:
    """Assemble M, K, C (and the hysteretic H) of a model.

    Parameters
    ----------
    model : Model
        The system.
    sparse : bool or None
        Return scipy.sparse CSR matrices; default: when the model has more than
        :data:`SPARSE_THRESHOLD` DOFs.

    Returns
    -------
    Assembly

    Examples
    --------
    >>> from ... import Body, MountType, Mount, Model
    >>> t = MountType("t", [1e4, 1e4, 2e4])
    >>> m = Model([Body("b", 10.0, [1, 1, 1])], [Mount("m", t, "b")])
    >>> float(assemble(m).K[2, 2])
    20000.0

    A small model's assembly is remembered (:mod:`vibss.linear.plant.memo`): asked again for the same
    model, ``assemble`` returns the same read-only Assembly (and what is cached on it).
    """
    if sparse is None:
        sparse = 6 * len(model.bodies) > SPARSE_THRESHOLD
    sparse = bool(sparse)
    return remembered(model, ("assembly", sparse), lambda: _assemble(model, sparse))


def _assemble(model: Model, sparse: bool) -> Assembly:
    """The assembly in named steps: where the mounts sit, their matrices in global axes, the
    pattern of their 6x6 blocks, the mass, and K, C, H summed over the mounts."""
    at = _mount_points(model)
    mm = _mount_matrices(model, at.t)
    pattern = _block_pattern(at)
    mass = _mass(model, sparse)
    mats, couplings = _summed(model, pattern, mm, sparse, ("K",))      # C and H when first asked for
    asm = Assembly(
        model=model,
        dofs=dof_labels(model.body_names),
        M=mass,
        K=mats["K"], Kg=couplings["K"],
        kp=mm.kp, cp=mm.cp, hp=mm.hp,
        b_index=at.b_index, a_index=at.a_index, r_b=at.r_b, r_a=at.r_a,
        sparse=bool(sparse), krp=mm.krp, crp=mm.crp, kcp=mm.kcp, ccp=mm.ccp,
        _cache={"pattern": pattern},
    )
    if not sparse and mm.k is not None and np.count_nonzero(mm.k >= 0) == mm.k.size and asm._plain_factor(mm.k, mm.kr):
        # the stiffness factor every analysis asks for, from the arrays already at hand (the same
        # numbers as Assembly.dense_factor computes: the lever arms are the pattern's own)
        g = asm._dense_factor(np.sqrt(mm.k)[:, :, None] * at.t.transpose(0, 2, 1), mm.k,
                              (pattern.lb, pattern.la))
        g.flags.writeable = False
        asm._cache["Gd"] = g
    return asm
