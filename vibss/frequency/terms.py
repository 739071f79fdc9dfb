"""The plant's frequency-response terms shared by the modal kernels (:mod:`vibss.frequency.kernels`,
:mod:`vibss.frequency.lowrank`): outputs and right-hand sides by power of ``s``, the feedthrough,
and the static and high-frequency solves of the mode-acceleration and mass-residual forms.

Every kernel evaluates ``Y(s) = O(s) X(s) + P(s) Z(s) + Pf`` with
``(K + i H + s C + s^2 M) X(s) = F - (Kz + i Hz + s Cz + s^2 Mz) Z(s)`` (see :mod:`vibss.frequency.kernels`).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import scipy.sparse as sp

from ..linear.eigen.basis import ModalBasis
from ..linear.eigen.undamped import stiffness_solver
from ..linear.plant.plant import Plant
from ..linear.solve.exact import MOUNTS_RATIO, states
from ..linear.solve.from_modes import STATIC_FROM_MODES, static_from_modes

__all__ = ["terms", "feedthrough", "static", "elastic_static", "mass_solve"]


def terms(plant: Plant) -> tuple[list, list, np.ndarray]:
    """Output terms [(power of s, (p, n))] and right-hand-side terms [(power, (n, m), scaled by Z)]."""
    oh = plant.Oh if plant.Oh is not None else 0.0
    out = [(0, plant.Oq + 1j * oh if np.any(oh) else plant.Oq), (1, plant.Ov), (2, plant.Oa)]
    hz = plant.Hz
    rhs = [(0, plant.F, False), (0, -(plant.Kz + 1j * hz) if np.any(hz) else -plant.Kz, True),
           (1, -plant.Cz, True), (2, -plant.Mz, True)]
    out = [(k, a) for k, a in out if np.any(a)]
    rhs = [(k, a, z) for k, a, z in rhs if np.any(a)]
    return out, rhs, plant.order


def has_feedthrough(plant: Plant) -> bool:
    """Whether ``P(s) Z(s) + Pf`` is not identically zero (force inputs and motion outputs: it is)."""
    ph = plant.Ph if plant.Ph is not None else 0.0
    return bool(np.any(plant.Pz) or np.any(ph) or np.any(plant.Pv) or np.any(plant.Pa) or np.any(plant.Pf))


def feedthrough(plant: Plant, s: np.ndarray, zf: np.ndarray) -> np.ndarray:
    """(nf, p, m) ``P(s) Z(s) + Pf``."""
    ph = plant.Ph if plant.Ph is not None else 0.0
    if not has_feedthrough(plant):
        return np.zeros((s.size, len(plant.outputs), len(plant.inputs)))   # force inputs, motion outputs
    p0 = plant.Pz + 1j * ph
    y = (p0[None] + s[:, None, None] * plant.Pv[None] + (s**2)[:, None, None] * plant.Pa[None])
    return y * zf[:, None, :] + plant.Pf[None]


def static(plant: Plant, rb: np.ndarray, basis: ModalBasis | None = None) -> np.ndarray:
    """``(K + iH)^-1 rb``: the static part of the mode-acceleration form.

    Solved in the mounts' forces (:func:`vibss.linear.solve.exact.states` at ``s = 0``) when the plant's
    stiffness ratio exceeds :data:`~vibss.linear.solve.exact.MOUNTS_RATIO`: the assembled ``K`` carries
    round-off of its stiffest mounts, which a Cholesky of it hands on to the soft modes (graded
    chain: 5.5e-5 relative error by the Cholesky of ``K``, 1.4e-14 in the mounts' forces). Else, on a
    model of :data:`~vibss.linear.solve.from_modes.STATIC_FROM_MODES` DOFs or more whose ``K`` is not
    factorised yet, from the modes ``basis``, refined with ``K`` and certified on the plant's outputs
    (:func:`~vibss.linear.solve.from_modes.static_from_modes`); else the plant's cached LU of ``K``. The
    two agree to about 1e-12: which one answers depends on the size and on what the plant already holds.
    """
    form = plant.mounts
    if form is not None and form.stiffness_ratio > MOUNTS_RATIO and form.matches(plant):
        x, bad = states(plant, np.zeros(1, complex), rhs=np.asarray(rb), form="mounts")
        if bad[0]:
            raise np.linalg.LinAlgError("K is singular")
        return x[0] if np.any(plant.H) else x[0].real
    if basis is not None and plant.n >= STATIC_FROM_MODES and plant.known("solve K") is None:
        from_modes = static_from_modes(plant, basis, rb, [o for _, o in terms(plant)[0]])
        if from_modes is not None:
            return from_modes
    if np.any(plant.H):
        return stiffness_solver(plant.K + 1j * plant.H)(rb)
    return plant.cached("solve K", lambda: stiffness_solver(plant.K))(rb)


def mass_solve(plant: Plant, rb: np.ndarray) -> np.ndarray:
    """``M^-1 rb``: the high-frequency part of the mass-residual form (``sum_k phi_k phi_k^T = M^-1``)."""
    mass = plant.M.toarray() if hasattr(plant.M, "toarray") else np.asarray(plant.M)
    return plant.cached("solve M", lambda: stiffness_solver(mass))(rb)


def _elastic(plant: Plant) -> Plant:
    """The plant without its hysteretic stiffness, its mount form (if it has one) likewise."""
    h0 = np.zeros_like(plant.H)
    out = replace(plant, H=h0, Hz=np.zeros_like(plant.Hz), Oh=None, Ph=None)
    form = plant.mounts
    if form is not None and form.matches(plant):
        form = replace(form, hp=np.zeros_like(form.hp), ha=np.zeros_like(form.ha), H=sp.csr_matrix(form.H.shape),
                       source=(out.K, out.C, out.H, out.M))
        out = replace(out, mounts=form)
    return out


def elastic_static(plant: Plant, rb: np.ndarray) -> np.ndarray:
    """``K^-1 rb`` (the hysteretic stiffness left out), solved as :func:`static` solves
    ``(K + iH)^-1 rb``: the static part of a mode-acceleration form on the undamped modes, whose
    ``Phi Omega^-2 Phi^T`` is ``K^-1``."""
    if not np.any(plant.H):
        return static(plant, rb)
    return static(plant.cached("elastic plant", lambda: _elastic(plant)), rb)
