"""Kernels of the modal analyses: the rigid-body motion of the whole model, and the damped modes'
routes (:data:`vibss.modal.methods.DAMPED_ROUTES`).

The poles are those of the state-space system ``x' = A x`` of M, C, K. They are computed in
scaled modal coordinates: with the mass-normalised undamped shapes Phi (``Phi^T M Phi = I``,
``Phi^T K Phi = Omega^2``) and ``Chat = Phi^T C Phi``, the states ``[S eta; eta']`` (S = Omega for
elastic modes, 1 for rigid ones) give

    A = [[0, S], [-Omega^2 S^-1, -Chat]],

a similarity transform of the physical A that is balanced by construction, so its eigenvalues
keep the small real parts of lightly damped poles (see docs/performance.md). Two short cuts:

- rigid-body modes that no damper touches (``Chat`` row ~ 0) are exact double zero poles and are
  left out of the eigenvalue problem: a plain eigen-solve of A turns them into spurious
  +-1e-5 poles with damping ratio -0.98;
- classically damped models (``Chat`` diagonal) have closed-form poles per mode,
  ``lambda = -zeta w +- i w sqrt(1 - zeta^2)``, ``zeta = Chat_ii / (2 w)``.

Every route has one signature: ``route(a, und, chat) -> (poles, shapes, paired, note)`` with ``a``
the assembly, ``und`` all its undamped modes and ``chat`` the symmetric ``Phi^T C Phi`` (None for
the route with frequency-dependent mounts, which needs none).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..linear.eigen.complex_modes import eigenpairs
from ..linear.plant.assemble import Assembly
from ..linear.plant.build import build_plant
from ..linear.solve.exact import without_hysteresis
from ..model.geometry import point_transfer
from ..model.model import Model

if TYPE_CHECKING:
    from .result import Modes

__all__ = ["rigid_influence", "projected_c", "poles_undamped", "poles_classical", "poles_general",
           "poles_with_branches"]

Poles = tuple[np.ndarray, np.ndarray, np.ndarray, str]

_EYE3 = np.eye(3)


def rigid_influence(model: Model, about: np.ndarray | None = None) -> np.ndarray:
    """(n, 6) DOF motion of all bodies moving as one rigid body: unit x, y, z, rx, ry, rz.

    Rotations are about ``about`` [m] (default: the system's centre of gravity).
    """
    c = model.center_of_gravity if about is None else np.asarray(about, float)
    nb = len(model.bodies)
    out = np.zeros((nb, 6, 6))
    r = np.array([b.cog for b in model.bodies], dtype=float).reshape(nb, 3) - c
    # translation of the COG for a rotation theta about c: theta x r = -[r]x theta, i.e. the
    # point transfer [I | -[r]x] of the COG seen from c; rotations pass unchanged
    out[:, :3, :] = point_transfer(r)
    out[:, 3:, 3:] = _EYE3
    return out.reshape(6 * nb, 6)


def projected_c(a: Assembly, und: Modes) -> np.ndarray:
    """``Phi^T C Phi`` on all the undamped modes, symmetrised."""
    phi = und.shapes
    chat = phi.T @ (a.dense("C") @ phi)
    return 0.5 * (chat + chat.T)


def _untouched(und: Modes, chat: np.ndarray) -> np.ndarray:
    """Rigid modes that no damper touches: exact double zero poles."""
    scale = max(float(np.abs(chat).max()), np.finfo(float).tiny)
    return und.rigid & (np.abs(chat).max(axis=1) <= 1e-14 * scale)


def _finish(poles: np.ndarray, eta: np.ndarray, und: Modes) -> Poles:
    """Poles cleaned of round-off imaginary parts and sorted, their shapes in the DOFs scaled to a
    largest component of 1, and the undamped mode each belongs to."""
    poles = np.where(np.abs(poles.imag) <= 1e-14 * np.abs(poles).max(initial=1.0), poles.real + 0j, poles)
    order = np.lexsort((-poles.real, np.abs(poles)))
    poles, eta = poles[order], eta[:, order]
    paired = np.argmax(np.abs(eta), axis=0)
    shapes = und.shapes @ eta
    big = shapes[np.argmax(np.abs(shapes), axis=0), np.arange(shapes.shape[1])]
    shapes = shapes / np.where(big == 0, 1.0, big)
    return poles, shapes, paired, ""


def poles_undamped(a: Assembly, und: Modes, chat: np.ndarray | None) -> Poles:
    """No damping at all: the poles ``i w`` of the undamped modes."""
    w = und.omega
    return _finish(1j * w, np.eye(len(w), dtype=complex), und)


def poles_classical(a: Assembly, und: Modes, chat: np.ndarray | None) -> Poles:
    """Classical damping (``Chat`` diagonal): closed-form poles per undamped mode."""
    assert chat is not None
    w = und.omega
    zeta = np.divide(np.diag(chat), 2 * w, out=np.zeros_like(w), where=w > 0)
    poles_list, eta_cols = [], []
    for j in range(len(w)):
        e = np.zeros(len(w), complex)
        e[j] = 1
        if w[j] == 0:                       # damped rigid motion: poles 0 and -c
            poles_list += [0.0 + 0j, -chat[j, j] + 0j] if chat[j, j] > 0 else [0j]
            eta_cols += [e, e] if chat[j, j] > 0 else [e]
        elif zeta[j] < 1:
            poles_list.append(w[j] * (-zeta[j] + 1j * np.sqrt(1 - zeta[j] ** 2)))
            eta_cols.append(e)
        else:                               # overdamped: two real poles
            r = w[j] * np.sqrt(zeta[j] ** 2 - 1)
            poles_list += [-zeta[j] * w[j] + r + 0j, -zeta[j] * w[j] - r + 0j]
            eta_cols += [e, e]
    return _finish(np.array(poles_list), np.array(eta_cols).T, und)


def poles_general(a: Assembly, und: Modes, chat: np.ndarray | None) -> Poles:
    """General damping: ``eig`` of the scaled modal state matrix, rigid modes no damper touches
    left out as exact double zero poles."""
    assert chat is not None
    w = und.omega
    untouched = _untouched(und, chat)
    keep = np.flatnonzero(~untouched)
    wk = w[keep]
    s = np.where(wk > 0, wk, 1.0)
    nk = len(keep)
    A = np.zeros((2 * nk, 2 * nk))
    A[:nk, nk:] = np.diag(s)
    A[nk:, :nk] = -np.diag(wk ** 2 / s)
    A[nk:, nk:] = -chat[np.ix_(keep, keep)]
    lam, vec = eigenpairs(A)
    sel = lam.imag >= 0                     # one of each conjugate pair, and real poles
    lam, vec = lam[sel], vec[:, sel]
    eta_k = vec[:nk] / s[:, None]
    eta = np.zeros((len(w), len(lam)), complex)
    eta[keep] = eta_k
    extra = np.flatnonzero(untouched)
    lam = np.concatenate([np.zeros(len(extra), complex), lam])
    eye = np.zeros((len(w), len(extra)), complex)
    eye[extra, np.arange(len(extra))] = 1
    return _finish(lam, np.hstack([eye, eta]), und)


def poles_with_branches(a: Assembly, und: Modes, chat: np.ndarray | None) -> Poles:
    """Damped modes of a model with frequency-dependent mounts: ``eig`` of the state matrix of
    :func:`vibss.statespace`, whose states include every mount's Maxwell branches (the same ladder
    as the FRF and the time response). The branches add real relaxation poles; shapes are the
    DOF displacements of the eigenvectors."""
    # python-control is heavy at start-up (tests/project/test_startup.py): only models with branches need it
    from ..linear.statespace import statespace

    plant = without_hysteresis(build_plant(a, [f"{a.model.body_names[0]}.fx"]))   # every DOF out
    sys = statespace(plant)
    lam, vec = eigenpairs(np.asarray(sys.A))
    scale = max(float(np.abs(lam).max(initial=0.0)), np.finfo(float).tiny)
    lam = np.where(np.abs(lam.imag) <= 1e-12 * scale, lam.real + 0j, lam)
    keep = lam.imag >= 0
    lam, shapes = lam[keep], np.asarray(sys.C) @ vec[:, keep]
    order = np.lexsort((-lam.real, np.abs(lam)))
    lam, shapes = lam[order], shapes[:, order]
    mphi = und.shapes.T @ a.dense("M")
    paired = np.argmax(np.abs(mphi @ shapes), axis=0)
    big = shapes[np.argmax(np.abs(shapes), axis=0), np.arange(shapes.shape[1])]
    shapes = shapes / np.where(big == 0, 1.0, big)
    assert plant.branches is not None
    poles_say = ("relaxation poles real, fluid-track poles complex" if plant.branches.inertial.any()
                 else "their relaxation poles are real")
    return lam, shapes, paired, plant.branches.note() + f" ({poles_say}; undamped modes at the static stiffness)"
