"""Kernels of the insight analyses: the mounts' share of a mode's strain and dissipated energy, and
the terms of a frequency response mode by mode.

Energy (all mounts at once, no Python loop per mount)
-----------------------------------------------------
Mount p's local coordinates in mode r are ``x = [T^T delta; T^T theta]`` (``delta = B_p phi_r`` its
deflection, ``theta = R_p phi_r`` its relative rotation, ``T`` its principal axes), and its local 6x6
stiffness ``K6 = [[T^T kp T, T^T kc T], [T^T kc^T T, T^T kr T]]`` (from the assembly's global
blocks). Its strain energy ``x^T K6 x / 2`` is split over its six local coordinates as
``x_i (K6 x)_i / 2``: the energy of each principal axis for a diagonal mount (a coupled 6x6 mount
shares its coupling between the two axes it couples, and a share may then be negative). Summed over
the mounts it is ``phi^T K phi / 2 = w^2 / 2`` for a mass-normalised shape: the check.

The energy dissipated per cycle of mode r is ``pi x^T (w_r C6 + H6) x`` (viscous and hysteretic).

Modal terms
-----------
With ``R(s) = F - (Kz + iHz + s Cz + s^2 Mz) Z(s)`` the right-hand sides and ``O(s)`` the output
map (:mod:`vibss.linear.solve.exact`), ``Y(s) = O(s) X(s) + P(s) Z(s) + Pf`` and

- classical damping (``Phi^T C Phi`` and ``Phi^T H Phi`` diagonal): ``X = sum_r phi_r phi_r^T R /
  (w_r^2 + i h_r + s c_r + s^2)``, one term per undamped mode;
- otherwise the complex modes of the scaled first-order modal form ``y' = A y + [0; Phi^T R]``,
  ``A = [[0, S], [-(W^2 + i Phi^T H Phi) S^-1, -Phi^T C Phi]]``: ``eta = sum_j v_j w_j^T [0; Phi^T R] /
  (s - lam_j)`` with ``V^-1`` rows ``w_j``. Each pole is given to the undamped mode that dominates its
  shape, so a conjugate pair (or the two real poles of an overdamped mode) is one term. Rigid modes
  that no damper touches are exact ``1 / s^2`` terms.

The feedthrough ``P(s) Z(s) + Pf`` and the modes left out make the residual.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..linear.eigen.basis import ModalBasis
from ..linear.eigen.complex_modes import eigenpairs
from ..linear.eigen.small import symmetric_eigen
from ..linear.plant.assemble import Assembly
from ..linear.plant.plant import Plant
from ..linear.solve.exact import forcing, zfactor
from ..frequency.terms import feedthrough

__all__ = ["AXES", "mount_coordinates", "local_blocks", "strain_energy", "dissipated_energy",
           "ModalTerms", "classical_terms", "complex_terms", "output_maps"]

AXES = ("1", "2", "3", "r1", "r2", "r3")
"""A mount's six local coordinates: deflections along its principal axes 1, 2, 3, rotations about them."""


def _axes(a: Assembly) -> np.ndarray:
    """(nm, 3, 3) every mount's principal axes (columns) in global axes."""
    nm = len(a.model.mounts)
    return np.array([m.orientation.matrix for m in a.model.mounts]).reshape(nm, 3, 3)


def _rotational(a: Assembly, which: str) -> bool:
    """Whether any mount resists or damps rotation (``which`` ``"K"`` or ``"C"``), or couples."""
    mats = (a.krp, a.kcp) if which == "K" else (a.crp, a.ccp) if which == "C" else ()
    return any(m.shape[0] and np.any(m) for m in mats)


def mount_coordinates(a: Assembly, phi: np.ndarray, rotations: bool = True) -> np.ndarray:
    """(nm, 6, k) local deflections [m] and rotations [rad] of every mount in every shape
    ((nm, 3, k) deflections only without ``rotations``).

    Parameters
    ----------
    a : Assembly
    phi : (n, k) ndarray
        Shapes in the body DOFs (ground fixed).
    rotations : bool
        Also the relative rotations.
    """
    nm, k = len(a.model.mounts), phi.shape[1]
    tt = _axes(a).transpose(0, 2, 1)
    d = tt @ np.asarray(a.deflection_matrix()[:, :a.n] @ phi).reshape(nm, 3, k)
    if not rotations:
        return d
    r = np.asarray(a.rotation_matrix()[:, :a.n] @ phi).reshape(nm, 3, k)
    return np.concatenate([d, tt @ r], axis=1)


def local_blocks(a: Assembly, which: str) -> np.ndarray:
    """(nm, 6, 6) every mount's matrix in its local coordinates: ``"K"`` stiffness, ``"C"``
    damping, ``"H"`` hysteretic stiffness (translational only, as the assembly holds it)."""
    nm = len(a.model.mounts)
    t = _axes(a)
    tt = t.transpose(0, 2, 1)
    tr, rr, cp = {"K": (a.kp, a.krp, a.kcp), "C": (a.cp, a.crp, a.ccp), "H": (a.hp, None, None)}[which]
    out = np.zeros((nm, 6, 6))
    out[:, :3, :3] = tt @ tr @ t
    if rr is not None and rr.shape[0] == nm:
        out[:, 3:, 3:] = tt @ rr @ t
    if cp is not None and cp.shape[0] == nm:
        out[:, :3, 3:] = tt @ cp @ t
        out[:, 3:, :3] = out[:, :3, 3:].transpose(0, 2, 1)
    return out


def _form(a: Assembly, phi: np.ndarray, which: str) -> np.ndarray:
    """(k, nm, 6) ``x_i (K6 x)_i`` of the mounts' ``which`` matrix (``"K"``, ``"C"``, ``"H"``): its
    quadratic form split over each mount's coordinates. Without rotational parts only the three
    deflections are formed (the rotations' shares are zeros)."""
    k6 = local_blocks(a, which)
    if _rotational(a, which):
        x = mount_coordinates(a, phi)
        e = x * (k6 @ x)
    else:
        x = mount_coordinates(a, phi, rotations=False)
        e = np.zeros((x.shape[0], 6, x.shape[2]))
        e[:, :3] = x * (k6[:, :3, :3] @ x)
    return e.transpose(2, 0, 1)


def strain_energy(a: Assembly, phi: np.ndarray) -> np.ndarray:
    """(k, nm, 6) strain energy of each mount per local coordinate [J per unit modal amplitude],
    ``x_i (K6 x)_i / 2``."""
    return 0.5 * _form(a, phi, "K")


def dissipated_energy(a: Assembly, phi: np.ndarray, omega: np.ndarray) -> np.ndarray:
    """(k, nm, 6) energy each mount dissipates per cycle of each mode, per local coordinate [J per
    unit modal amplitude]: ``pi x_i ((w C6 + H6) x)_i``.

    Parameters
    ----------
    a : Assembly
    phi : (n, k) ndarray
        Shapes.
    omega : (k,) ndarray
        Natural frequencies [rad/s] (the viscous loss grows with the frequency).
    """
    return np.pi * (omega[:, None, None] * _form(a, phi, "C") + _form(a, phi, "H"))


@dataclass(frozen=True)
class ModalTerms:
    """The modal terms of a plant's response.

    Attributes
    ----------
    terms : (k, p, m, nf) complex ndarray
        Term of each mode (row of the undamped basis).
    feedthrough : (p, m, nf) complex ndarray
        ``P(s) Z(s) + Pf``.
    poles : (k, 2) complex ndarray
        The poles of each term [rad/s] (NaN where a term has fewer than two; more than two: the
        first two).
    """

    terms: np.ndarray
    feedthrough: np.ndarray
    poles: np.ndarray


def output_maps(plant: Plant, s: np.ndarray) -> np.ndarray:
    """(nf, p, n) ``O(s) = Oq + i Oh + s Ov + s^2 Oa`` at every ``s``."""
    oh = 0.0 if plant.Oh is None else np.asarray(plant.Oh)
    sc = s[:, None, None]
    return (np.asarray(plant.Oq) + 1j * oh)[None] + sc * np.asarray(plant.Ov)[None] + sc**2 * np.asarray(plant.Oa)[None]


def _parts(plant: Plant, s: np.ndarray, phi: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``O(s) Phi`` (nf, p, k), ``Phi^T R(s)`` (nf, k, m) and the feedthrough (p, m, nf)."""
    zf = zfactor(s, plant.order)
    rhs = forcing(plant, s, zf)
    ob = output_maps(plant, s) @ phi
    g = phi.T[None] @ rhs
    return ob, g, feedthrough(plant, s, zf).transpose(1, 2, 0)


def classical_terms(plant: Plant, s: np.ndarray, basis: ModalBasis, chat: np.ndarray,
                    hhat: np.ndarray) -> ModalTerms:
    """One term per undamped mode, ``O phi_r phi_r^T R / (w_r^2 + i h_r + s c_r + s^2)`` (classical
    damping: ``chat``, ``hhat`` diagonal)."""
    ob, g, ft = _parts(plant, s, basis.phi)
    c, h = np.diag(chat), np.diag(hhat)
    with np.errstate(divide="ignore", invalid="ignore"):
        d = 1.0 / (basis.omega2[None, :] + 1j * h[None, :] + s[:, None] * c[None, :] + (s**2)[:, None])
    terms = np.einsum("fpr,fr,frm->rpmf", ob, d, g, optimize=True)
    w, zeta = basis.omega, np.divide(c, 2 * basis.omega, out=np.zeros_like(c), where=basis.omega > 0)
    lam = w * (-zeta + 1j * np.sqrt(np.maximum(1 - zeta**2, 0.0)))
    poles = np.stack([lam, lam.conj()], axis=1)
    return ModalTerms(terms, ft, poles)


def complex_terms(plant: Plant, s: np.ndarray, basis: ModalBasis, chat: np.ndarray,
                  hhat: np.ndarray) -> ModalTerms:
    """Terms of the complex modes (general damping), gathered by the undamped mode that dominates
    each pole's shape (see the module docstring)."""
    phi, gam, hys = basis.phi.copy(), chat.copy(), hhat.copy()
    rid = np.flatnonzero(basis.rigid)
    if rid.size:     # the rigid subspace turned so its damping is diagonal: undamped combinations stand apart
        _, q = symmetric_eigen(gam[np.ix_(rid, rid)])
        phi[:, rid] = phi[:, rid] @ q
        for mat in (gam, hys):
            mat[rid, :] = q.T @ mat[rid, :]
            mat[:, rid] = mat[:, rid] @ q
    k = phi.shape[1]
    top = max(float(np.abs(gam).max(initial=0.0)), float(np.abs(hys).max(initial=0.0)), np.finfo(float).tiny)
    free = basis.rigid & (np.abs(gam).max(axis=1) <= 1e-12 * top) & (np.abs(hys).max(axis=1) <= 1e-12 * top)
    keep = np.flatnonzero(~free)
    ob, g, ft = _parts(plant, s, phi)
    nf, p, m = ob.shape[0], ob.shape[1], g.shape[2]
    terms = np.zeros((k, p, m, nf), complex)
    poles = np.full((k, 2), np.nan + 0j)
    for r in np.flatnonzero(free):                  # eta'' = f: exactly 1 / s^2
        terms[r] = np.einsum("fp,fm->pmf", ob[:, :, r], g[:, r, :]) / (s**2)[None, None, :]
        poles[r] = 0.0
    nk = keep.size
    if nk:
        w2 = basis.omega2[keep]
        sc = np.where(w2 > 0, np.sqrt(np.maximum(w2, 0.0)), 1.0)
        a = np.zeros((2 * nk, 2 * nk), complex)
        a[:nk, nk:] = np.diag(sc)
        a[nk:, :nk] = -(np.diag(w2) + 1j * hys[np.ix_(keep, keep)]) / sc[None, :]
        a[nk:, nk:] = -gam[np.ix_(keep, keep)]
        lam, v = eigenpairs(a)
        left = np.linalg.inv(v)[:, nk:]                 # rows w_j: the velocity inputs [0; Phi^T R]
        eta = v[:nk] / sc[:, None]                       # modal displacements of each pole's shape
        owner = keep[np.argmax(np.abs(eta), axis=0)]
        ok = keep
        with np.errstate(divide="ignore", invalid="ignore"):
            pole = 1.0 / (s[:, None] - lam[None, :])     # (nf, 2nk)
        ob_k = ob[:, :, ok] @ eta                        # (nf, p, 2nk)
        g_k = np.einsum("jr,frm->fjm", left, g[:, ok, :])
        per_pole = np.einsum("fpj,fj,fjm->jpmf", ob_k, pole, g_k, optimize=True)
        np.add.at(terms, owner, per_pole)
        for r in np.unique(owner):
            mine = lam[owner == r]
            mine = mine[np.argsort(-mine.imag)][:2]
            poles[r, :mine.size] = mine
    return ModalTerms(terms, ft, poles)
