"""Internal states of frequency-dependent mounts: the Maxwell branches of a plant.

A mount type with a ``rheology`` (:mod:`vibss.model.rheology`) is a Maxwell ladder per principal
axis: its static stiffness ``k_0`` and dashpot ``c`` are in the plant's ``K`` and ``C`` like any
mount's, and each branch ``i`` (a spring ``k_i`` in series with a dashpot ``k_i tau_i``) adds one
internal coordinate ``u_i``, the dashpot's stroke:

    branch force      f_i = k_i (delta_i - u_i),       delta_i = B_i q + Bz_i z  (deflection along the axis)
    internal state    tau_i u_i' + u_i = delta_i
    on the DOFs       M q'' + C q' + K q = F u - (Kz z + Cz z' + Mz z'') - B^T f
    on the outputs    y += O f

so ``f_i = k_i tau_i s / (1 + tau_i s) delta_i`` in the frequency domain. A hydraulic mount's branch
(:class:`~vibss.model.rheology.Hydraulic`) gives its coordinate a mass, ``mu_i u_i'' + tau_i u_i' +
u_i = delta_i`` with ``mu_i = m_i / k_i``: ``f_i = k_i P_i / (1 + P_i) delta_i``, ``P_i = mu_i s^2 +
tau_i s`` (two states in the time domain: ``u_i`` and its rate). :class:`Branches` holds
``B, Bz, O, k, tau`` of a plant (a field of :class:`~vibss.linear.plant.plant.Plant`); every analysis
takes the same ladder:

- the exact solve (:mod:`vibss.linear.solve.exact`) eliminates the ``u_i`` exactly (:func:`groups`):
  ``K + iH + sC + s^2 M + sum_tau tau s / (1 + tau s) K_tau``, through every back-end;
- :func:`vibss.linear.statespace.statespace` appends the ``u_i`` as states (:func:`close`), which the
  time response (``forced_response``) and the damped modes use;
- the modal time response (:mod:`vibss.time.branched`) takes the branch forces as states beside the
  undamped modes and diagonalises the two together (:mod:`vibss.linear.eigen.branch_modes`).

Examples
--------
>>> from ... import Body, Model, Mount, MountType
>>> from .build import build_plant
>>> t = MountType("rubber", rheology={"type": "zener", "k_0": 1e4, "k_inf": 3e4, "tau": 1e-2})
>>> p = build_plant(Model([Body("b", 1.0, [1, 1, 1])], [Mount("m", t, "b")]), ["b.fz"], ["b.z"])
>>> p.branches.labels
('mount.m.1.b1', 'mount.m.2.b1', 'mount.m.3.b1')
>>> g = groups(p)[0]                      # one relaxation time; k_inf - k_0 on each axis
>>> g.tau, float(g.K[2, 2])
(0.01, 20000.0)
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp

from ...errors import AnalysisError

__all__ = ["Branches", "Group", "build_branches", "groups", "mechanical", "close", "require_none"]


@dataclass(frozen=True, eq=False)
class Branches:
    """The Maxwell branches of a plant's frequency-dependent mounts (r of them).

    Attributes
    ----------
    labels : tuple of str
        ``'mount.<name>.<axis 1-3>.b<i>'`` per branch.
    mounts : tuple of str
        Names of the mounts that have branches (for messages).
    k : (r,) ndarray
        Branch stiffnesses [N/m].
    tau : (r,) ndarray
        Relaxation times [s].
    B : (r, n) ndarray
        Deflection along the branch's axis per unit free-DOF motion [m/m, m/rad].
    Bz : (r, m) ndarray
        Deflection per unit prescribed coordinate ``z`` of each input (zero for forces).
    O : (p, r) ndarray
        Output per unit branch force [output unit / N].
    fit_error : float
        Largest relative error of a fitted ladder over its band (0: every ladder exact).
    mu : (r,) ndarray or None
        Branch mass per unit stiffness [s^2] (hydraulic mounts; None: zeros, Maxwell branches).
    """

    labels: tuple[str, ...]
    mounts: tuple[str, ...]
    k: np.ndarray
    tau: np.ndarray
    B: np.ndarray
    Bz: np.ndarray
    O: np.ndarray
    fit_error: float = 0.0
    mu: np.ndarray | None = None

    def __post_init__(self) -> None:
        if self.mu is None:
            object.__setattr__(self, "mu", np.zeros(len(self.labels)))

    @property
    def inertial(self) -> np.ndarray:
        """(r,) bool: branches whose coordinate has mass (two states each in the time domain)."""
        return np.asarray(self.mu) > 0

    @property
    def r(self) -> int:
        """Number of branches."""
        return len(self.labels)

    def dynamic(self, s: np.ndarray) -> np.ndarray:
        """(nf, r) branch stiffness ``k P / (1 + P)``, ``P = mu s^2 + tau s``, at Laplace values ``s`` [N/m]."""
        sv = np.asarray(s, dtype=complex)[:, None]
        st = sv * sv * np.asarray(self.mu)[None] + sv * self.tau[None]
        return self.k[None] * st / (1.0 + st)

    def select(self, inputs: list[int] | None, outputs: list[int] | None) -> Branches:
        """The branches of a plant with a subset of its inputs and outputs."""
        return dataclasses.replace(self, Bz=self.Bz if inputs is None else self.Bz[:, inputs],
                                   O=self.O if outputs is None else self.O[outputs])

    def restrict(self, idx: np.ndarray) -> Branches:
        """The branches of a plant restricted to the free DOFs ``idx``."""
        return dataclasses.replace(self, B=self.B[:, idx])

    def project(self, v: np.ndarray) -> Branches:
        """The branches of a plant projected on ``q = V a``."""
        return dataclasses.replace(self, B=self.B @ v)

    def note(self) -> str:
        """One sentence for a result's note."""
        fit = (f"; fitted ladders within {self.fit_error:.2g} of the rheology over their bands"
               if self.fit_error else " (exact ladders)")
        n2 = int(np.count_nonzero(self.inertial))
        kinds = f"{self.r - n2} internal Maxwell states" + (f" and {n2} fluid-track coordinates (two states each)"
                                                             if n2 else "")
        return f"frequency-dependent mounts {list(self.mounts)}: {kinds}{fit}"


def build_branches(model: Any, deflection: Any, free: np.ndarray, motion: np.ndarray,
                   force_rows: np.ndarray) -> Branches | None:
    """The :class:`Branches` of a study (None when no mount type has Maxwell branches).

    Parameters
    ----------
    model : Model
        Its mount types' ladders (:attr:`vibss.MountType.ladder`) give ``k`` and ``tau``.
    deflection : (3 n_mounts, n + nz) sparse matrix
        :meth:`vibss.linear.plant.assemble.Assembly.deflection_matrix` (global axes, ground last).
    free : (n_free,) int ndarray
        Free body DOFs.
    motion : (n + nz, m) ndarray
        Prescribed coordinates per input (:func:`vibss.linear.plant.build.input_maps`).
    force_rows : (p, 3 n_mounts) ndarray
        Each output per unit force of each mount into its ``to`` side (global axes).

    Returns
    -------
    Branches or None
    """
    labels: list[str] = []
    names: list[str] = []
    k: list[float] = []
    tau: list[float] = []
    mu: list[float] = []
    rows: list[tuple[int, np.ndarray]] = []
    fit = 0.0
    for p, mount in enumerate(model.mounts):
        t = mount.type
        if not t.has_branches:
            continue
        names.append(mount.name)
        fit = max(fit, t.fit_error)
        lad = t.ladder
        axes = mount.orientation.matrix
        for j in range(3):
            for count, i in enumerate(np.flatnonzero(lad.k[j] > 0)):
                labels.append(f"mount.{mount.name}.{j + 1}.b{count + 1}")
                k.append(float(lad.k[j, i]))
                tau.append(float(lad.tau[j, i]))
                mu.append(float(np.asarray(lad.mu)[j, i]))
                rows.append((p, axes[:, j]))
    if not labels:
        return None
    d = sp.csr_matrix(deflection)
    full = np.array([axis @ d[3 * p:3 * p + 3].toarray() for p, axis in rows])       # (r, n + nz)
    o = np.column_stack([force_rows[:, 3 * p:3 * p + 3] @ axis for p, axis in rows]) if len(force_rows) \
        else np.zeros((0, len(rows)))
    return Branches(labels=tuple(labels), mounts=tuple(names), k=np.array(k), tau=np.array(tau),
                    B=full[:, free], Bz=full @ motion, O=o.reshape(force_rows.shape[0], len(rows)),
                    fit_error=fit, mu=np.array(mu))


def require_none(plant: Any, where: str, instead: str) -> None:
    """Refuse a plant with branches in an analysis that cannot represent them.

    Parameters
    ----------
    plant : Plant
    where : str
        The analysis or method (for the message).
    instead : str
        What to use instead.

    Raises
    ------
    AnalysisError
        Naming the frequency-dependent mounts.
    """
    br = getattr(plant, "branches", None)
    if br is not None:
        raise AnalysisError(f"{where}: the frequency-dependent mounts {list(br.mounts)} have internal "
                            f"states (Maxwell branches) that {where} does not represent; {instead}")


@dataclass(frozen=True, eq=False)
class Group:
    """The branches of one relaxation time ``tau`` (and mass ratio ``mu``), condensed: they add
    ``g(s) = P / (1 + P)``, ``P = mu s^2 + tau s``, times these matrices to the dynamic stiffness,
    the input coupling and the outputs.

    Attributes
    ----------
    tau : float
        Relaxation time [s].
    K : (n, n) ndarray or scipy.sparse CSR matrix
        ``B^T diag(k) B`` over the group [N/m].
    Kz : (n, m) ndarray
        ``B^T diag(k) Bz``.
    Oq : (p, n) ndarray
        ``O diag(k) B``.
    Pz : (p, m) ndarray
        ``O diag(k) Bz``.
    mu : float
        Branch mass per unit stiffness [s^2] (0: Maxwell).
    """

    tau: float
    K: Any
    Kz: np.ndarray
    Oq: np.ndarray
    Pz: np.ndarray
    mu: float = 0.0

    def factor(self, s: np.ndarray, derivative: bool = False) -> np.ndarray:
        """``g(s) = P / (1 + P)`` with ``P = mu s^2 + tau s`` (or ``dg/ds = (2 mu s + tau) / (1 + P)^2``)
        at Laplace values ``s`` (``tau s / (1 + tau s)`` for a Maxwell group)."""
        s = np.asarray(s, dtype=complex)
        p = self.mu * s * s + self.tau * s
        return (2 * self.mu * s + self.tau) / (1 + p) ** 2 if derivative else p / (1 + p)


def groups(plant: Any) -> list[Group]:
    """The plant's branches condensed per relaxation time (computed once per plant; [] without).

    Eliminating each internal coordinate, ``u_i = delta_i / (1 + tau_i s)``, is exact: the dynamic
    stiffness becomes ``K + iH + sC + s^2 M + sum_tau g_tau(s) K_tau`` with the pattern of the
    mounts' own stiffness, so the exact solve costs about what it costs without the branches
    (one ``g_tau(s) K_tau`` per distinct ``tau`` per frequency; a Zener model has one ``tau`` per
    mount type, a fitted ladder shares three per decade of its band).

    Parameters
    ----------
    plant : Plant

    Returns
    -------
    list of Group
    """
    br = plant.branches
    if br is None:
        return []
    return plant.cached("branch groups", lambda: _groups(plant, br))


def _groups(plant: Any, br: Branches) -> list[Group]:
    out = []
    sparse = sp.issparse(plant.K)
    mu_all = np.asarray(br.mu)
    for tau, mu in np.unique(np.column_stack([br.tau, mu_all]), axis=0):
        sel = (br.tau == tau) & (mu_all == mu)
        b, k = br.B[sel], br.k[sel]
        kb = b * k[:, None]
        kmat = b.T @ kb
        kmat = 0.5 * (kmat + kmat.T)
        out.append(Group(tau=float(tau), K=sp.csr_matrix(kmat) if sparse else kmat, Kz=kb.T @ br.Bz[sel],
                         Oq=(br.O[:, sel] * k[None]) @ b, Pz=(br.O[:, sel] * k[None]) @ br.Bz[sel], mu=float(mu)))
    return out


def close(plant: Any, make: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, list[str]]:
    """State-space matrices of a plant with branches: the mechanical part closed with the ``u_i``.

    The :func:`mechanical` plant is realized by ``make`` (the statespace construction); then
    ``u' = (delta - u) / tau`` closes it (``mu u'' + tau u' + u = delta`` for a fluid-track branch):
    states ``[x; u; u']`` (the rates of the fluid-track branches last).

    Parameters
    ----------
    plant : Plant
        With branches.
    make : callable
        ``plant -> (A, B, C, D, state_names)`` for a plant without branches.

    Returns
    -------
    A, B, C, D : ndarray
        The closed system (inputs and outputs the plant's).
    states : list of str
        The mechanical states' names then the branches' labels (python-control spelling).
    """
    br = plant.branches
    r, m, p = br.r, len(plant.inputs), len(plant.outputs)
    mech = mechanical(plant)
    a0, b0, c0, d0, names = make(mech)
    if np.any(d0[p:, m:]):
        raise AnalysisError("statespace: a branch deflection depends directly on a branch force")
    heavy = np.flatnonzero(br.inertial)                # fluid-track branches: a rate state each
    light = np.setdiff1d(np.arange(r), heavy)
    N, r2 = a0.shape[0], heavy.size
    A = np.zeros((N + r + r2, N + r + r2))
    B = np.zeros((N + r + r2, m))
    A[:N, :N], A[:N, N:N + r] = a0, b0[:, m:]
    B[:N] = b0[:, :m]
    inv_tau = 1.0 / br.tau[light]                      # tau u' + u = delta
    A[N + light, :N] = inv_tau[:, None] * c0[p + light]
    A[N + light, N + light] = -inv_tau
    B[N + light] = inv_tau[:, None] * d0[p + light, :m]
    inv_mu = 1.0 / np.asarray(br.mu)[heavy]            # mu u'' + tau u' + u = delta
    rate = N + r + np.arange(r2)
    A[N + heavy, rate] = 1.0
    A[rate, :N] = inv_mu[:, None] * c0[p + heavy]
    A[rate, N + heavy] = -inv_mu
    A[rate, rate] = -br.tau[heavy] * inv_mu
    B[rate] = inv_mu[:, None] * d0[p + heavy, :m]
    C = np.hstack([c0[:p], d0[:p, m:], np.zeros((p, r2))])
    D = d0[:p, :m]
    return A, B, C, D, (list(names) + [lab.replace(".", ":") for lab in br.labels]
                        + [br.labels[i].replace(".", ":") + ":v" for i in heavy])


def mechanical(plant: Any) -> Any:
    """The plant's mechanical part with the branches opened (computed once per plant).

    ``K + B^T k B`` (every branch spring at its instantaneous stiffness), ``Kz + B^T k Bz``, the
    outputs plus ``O k (B q + Bz z)``; r extra force inputs ``B^T k u`` (the outputs' ``-O k u``,
    named ``'<branch>.u'``) and r extra outputs ``delta = B q + Bz z`` (``'<branch>.delta'``). No
    hysteretic part (the time domain has none), no branches.

    Parameters
    ----------
    plant : Plant
        With branches.

    Returns
    -------
    Plant
    """
    return plant.cached("mechanical", lambda: _mechanical(plant))


def _mechanical(plant: Any) -> Any:
    br = plant.branches
    r, m, p = br.r, len(plant.inputs), len(plant.outputs)
    kb = br.B * br.k[:, None]
    ok = br.O * br.k[None]
    return dataclasses.replace(
        plant, K=plant.K + br.B.T @ kb, H=np.zeros_like(plant.H), Oh=None, Ph=None,
        inputs=tuple(plant.inputs) + tuple(f"{lab}.u" for lab in br.labels),
        kinds=tuple(plant.kinds) + ("force",) * r,
        F=np.hstack([plant.F, kb.T]),
        Kz=np.hstack([plant.Kz + br.B.T @ (br.Bz * br.k[:, None]), np.zeros((plant.n, r))]),
        Cz=np.hstack([plant.Cz, np.zeros((plant.n, r))]), Mz=np.hstack([plant.Mz, np.zeros((plant.n, r))]),
        Hz=np.zeros((plant.n, m + r)),
        outputs=tuple(plant.outputs) + tuple(f"{lab}.delta" for lab in br.labels),
        units=tuple(plant.units) + ("m",) * r,
        Oq=np.vstack([plant.Oq + ok @ br.B, br.B]), Ov=np.vstack([plant.Ov, np.zeros((r, plant.n))]),
        Oa=np.vstack([plant.Oa, np.zeros((r, plant.n))]),
        Pz=np.block([[plant.Pz + ok @ br.Bz, np.zeros((p, r))], [br.Bz, np.zeros((r, r))]]),
        Pv=np.block([[plant.Pv, np.zeros((p, r))], [np.zeros((r, m + r))]]),
        Pa=np.block([[plant.Pa, np.zeros((p, r))], [np.zeros((r, m + r))]]),
        Pf=np.block([[plant.Pf, -ok], [np.zeros((r, m + r))]]),
        Kf=None, mounts=None, branches=None)
