"""The exact z-only state-space realization of the substituted plant, and the ``forced_response``
method on it."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...errors import AnalysisError
from ...linear.solve.mass import mass_solver
from ...linear.eigen.basis import modal_basis
from ...linear.plant.branches import mechanical, require_none
from .grid import Kinematics
from ...threads import one_blas_thread
from .prepared import Prepared

__all__ = ["Realization", "realization", "run_forced_response"]


@dataclass(frozen=True, eq=False)
class Realization:
    """First-order form ``x' = A x + B u``, ``y = C x + D u + D1p z' + D2p z''`` (see :func:`realization`).

    ``x = [p; xi; z_vel; z_acc; v_acc]`` with ``xi = p' + M^-1 Ct z``. ``post1`` / ``post2`` (p, m)
    multiply the z' of displacement inputs and the z'' of velocity inputs, which the realization
    does not carry (they are evaluated from the input directly).
    """

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    post1: np.ndarray
    post2: np.ndarray
    states: tuple[str, ...]


def realization(prep: Prepared) -> Realization:
    """The exact z-only realization of the substituted plant (no differentiated inputs)."""
    plant = prep.plant
    n, m = plant.F.shape
    kinds = prep.kinds
    iv = [j for j, k in enumerate(kinds) if k == "velocity"]
    ia = [j for j, k in enumerate(kinds) if k == "acceleration"]
    nv, na = len(iv), len(ia)
    ns = 2 * n + nv + 2 * na
    # z = Zx x + Zu u ; z' = Z1x x + Z1u u (for velocity/acceleration kinds)
    Zx, Zu = np.zeros((m, ns)), np.zeros((m, m))
    Z1x, Z1u = np.zeros((m, ns)), np.zeros((m, m))
    for j, k in enumerate(kinds):
        if k == "displacement":
            Zu[j, j] = 1.0
        elif k == "velocity":
            Zx[j, 2 * n + iv.index(j)] = 1.0
            Z1u[j, j] = 1.0
        elif k == "acceleration":
            a = ia.index(j)
            Zx[j, 2 * n + nv + a] = 1.0
            Z1x[j, 2 * n + nv + na + a] = 1.0
    solve = mass_solver(plant)
    MiK = solve(plant.K)
    MiC = solve(plant.C)
    MiCt = solve(prep.Ct)
    MiF = solve(plant.F * prep.force)
    MiKt = solve(prep.Kt)
    A = np.zeros((ns, ns))
    B = np.zeros((ns, m))
    P, X = slice(0, n), slice(n, 2 * n)
    # p' = xi - M^-1 Ct z
    A[P, X] = np.eye(n)
    A[P] -= MiCt @ Zx
    B[P] -= MiCt @ Zu
    # xi' = -M^-1 K p - M^-1 C (xi - M^-1 Ct z) + M^-1 F f - M^-1 Kt z
    A[X, P] = -MiK
    A[X, X] = -MiC
    zc = MiC @ MiCt - MiKt
    A[X] += zc @ Zx
    B[X] += zc @ Zu + MiF
    for a, j in enumerate(iv):
        B[2 * n + a, j] = 1.0
    for a, j in enumerate(ia):
        A[2 * n + nv + a, 2 * n + nv + na + a] = 1.0
        B[2 * n + nv + na + a, j] = 1.0
    # y = Cp p + Cv (xi - M^-1 Ct z) + D0 z + D1 z' + D2 z'' + Df f
    C = np.zeros((len(plant.outputs), ns))
    C[:, P] = prep.Cp
    C[:, X] = prep.Cv
    zy = prep.D0 - prep.Cv @ MiCt
    C += zy @ Zx + prep.D1 @ Z1x
    D = zy @ Zu + prep.D1 @ Z1u + prep.Df * prep.force
    disp = np.array([k == "displacement" for k in kinds])
    acc = np.array([k == "acceleration" for k in kinds])
    vel = np.array([k == "velocity" for k in kinds])
    D += prep.D2 * acc
    post1 = prep.D1 * disp
    post2 = prep.D2 * vel
    states = (tuple(f"{d}.p" for d in plant.dofs) + tuple(f"{d}.xi" for d in plant.dofs)
              + tuple(f"{plant.inputs[j]}.z" for j in iv) + tuple(f"{plant.inputs[j]}.z" for j in ia)
              + tuple(f"{plant.inputs[j]}.v" for j in ia))
    return Realization(A=A, B=B, C=C, D=D, post1=post1, post2=post2, states=states)


def run_forced_response(prep: Prepared, t: np.ndarray, u: np.ndarray, kin: Kinematics,
                        q0: np.ndarray, v0: np.ndarray) -> tuple[np.ndarray, str]:
    """python-control ``forced_response`` on the uniform grid ``t`` [s]; (ns, p) outputs and a note.

    The system is :func:`vibss.linear.statespace.statespace` (modal realization) of the plant. Where that
    refuses an output that needs an input's derivative, the local z-only realization is used and
    the derivative term is added from the inputs' piecewise-linear slopes.
    """
    import control

    from ...linear.statespace import statespace

    plant = prep.plant
    n = plant.n
    try:
        sys = statespace(plant)
    except AnalysisError as exc:
        require_none(plant, "simulate: the local z-only realization", f"here: {exc}")
        r = realization(prep)
        sys = control.ss(r.A, r.B, r.C, r.D)
        x0 = np.zeros(r.A.shape[0])
        x0[:n], x0[n:2 * n] = q0, v0
        post = kin.z1 @ r.post1.T + kin.z2 @ r.post2.T
        note = f"python-control forced_response of the local z-only realization ({exc})"
    else:
        mb = modal_basis(plant if plant.branches is None else mechanical(plant))   # statespace's basis
        M = np.asarray(plant.M, float)
        x0 = np.zeros(sys.nstates)
        x0[:n] = mb.scale * (mb.phi.T @ (M @ q0))
        x0[n:2 * n] = mb.phi.T @ (M @ v0)
        if plant.branches is not None:   # branches relaxed at the initial deflection (no force in them)
            x0[2 * n:2 * n + plant.branches.r] = plant.branches.B @ q0   # fluid-track rates (last) at rest
        post = 0.0
        note = "python-control forced_response of vibss.statespace (modal realization), FOH of the samples"
    with one_blas_thread():
        res = control.forced_response(sys, timepts=t, inputs=u.T, initial_state=x0)
    y = np.asarray(res.outputs).reshape(len(plant.outputs), -1).T
    return y + post, note
