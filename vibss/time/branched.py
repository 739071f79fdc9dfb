"""The exact modal time response of a plant with a few Maxwell branches (frequency-dependent mounts).

The branch forces ``f`` join the undamped modes' coordinates as states (:mod:`vibss.linear.plant.branches`):

    M p'' + C p' + K p = F f_in - Kt z - Ct z' - B^T f,
    f' = diag(k) (B p' + Bt z') - f / tau,        Bt = Bz - B G,

(``p = q + G z``, :mod:`vibss.time.kernels`), and ``y = Cp p + Cv p' + (O - Oa M^-1 B^T) f + ...``.
:func:`vibss.linear.eigen.branch_modes.branch_modes` diagonalises the augmented modal matrix from the
r x r secular equation, certified, without forming it; each eigenvalue is then one scalar mode of
the existing exact FOH recursion (:func:`vibss.time.kernels.modal.run_modal`), driven through ``V^-1``
(left eigenvectors from the right ones): the generalized forces through the ``eta'`` rows, the
prescribed motion's ``z'`` through the branch rows. A displacement jump is an impulse on ``f``
(the branch spring reacts at once), applied exactly like the dampers' ``Ct`` impulse.

When the structure does not hold (fluid-track branches, rigid-body modes, non-proportional
damping) or the eigen-solve cannot certify its roots, :class:`~vibss.errors.DefectiveModesError`
says why and ``auto`` runs ``forced_response`` on the dense augmented state space instead.
"""

from __future__ import annotations

import numpy as np

from ..errors import DefectiveModesError
from ..linear.solve.mass import mass_solver
from ..linear.eigen.branch_modes import BranchModes, branch_modes
from ..linear.eigen.basis import damping_coupling, modal_basis
from ..linear.plant.plant import Plant
from ..linear.eigen.basis import projected_damping
from .kernels.modal import _ModalSet, channels
from .kernels.prepared import Prepared

__all__ = ["modal_sets", "suits", "COST_FACTOR"]

COST_FACTOR = 4.0
"""``auto`` solves the secular equation when ``COST_FACTOR (n + r) n r^2 <= (2n + r)^3`` and
``r <= n / 2``: a few Newton steps of GEMMs of (n + r) x n x r^2 each against one dense ``expm`` or
``eig`` of the 2n + r states (at 600 DOF and 12 branches about 1/10 of it)."""


def suits(plant: Plant) -> tuple[bool, str]:
    """Whether ``auto`` takes the structured modal path for the plant's branches, and why (not).

    Parameters
    ----------
    plant : Plant
        With branches.

    Returns
    -------
    ok : bool
    why : str
    """
    br = plant.branches
    assert br is not None
    n, r = plant.n, br.r
    if np.any(br.inertial):
        return False, "fluid-track branches (two states each) are not in the structured eigen-solve"
    if not (2 * r <= n and COST_FACTOR * (n + r) * n * r * r <= (2 * n + r) ** 3):
        return False, (f"{r} branch states on {n} DOFs: the dense augmented matrix is cheaper than the "
                       "secular equation")
    return True, f"{r} branch states on {n} DOFs: structured eigen-solve of the modes plus the branches"


def _structure(plant: Plant) -> tuple[np.ndarray, np.ndarray, np.ndarray, BranchModes]:
    """The modal basis (phi), its frequencies and damping, and the certified branch modes."""
    br = plant.branches
    assert br is not None
    who = f"frequency-dependent mounts {list(br.mounts)}"
    if np.any(br.inertial):
        raise DefectiveModesError(f"{who}: the structured branch path takes Maxwell branches only, not "
                                  "fluid-track ones")
    mb = modal_basis(plant)
    if mb.rigid.any():
        raise DefectiveModesError(f"{who}: {int(mb.rigid.sum())} rigid-body mode(s): the structured branch "
                                  "path needs every mode elastic")
    chat = projected_damping(plant, mb)[0]
    if (damping_coupling(0.5 * (chat + chat.T)) > 0).any():
        raise DefectiveModesError(f"{who}: non-proportional damping: the structured branch path needs "
                                  "classical damping")
    w = np.sqrt(mb.omega2)
    try:
        bm = branch_modes(w, np.diag(chat).copy(), br.B @ mb.phi, br.k, br.tau)
    except DefectiveModesError as exc:
        raise DefectiveModesError(f"{who}: {exc}") from None
    return mb.phi, w, np.diag(chat), bm


def modal_sets(prep: Prepared, q0: np.ndarray, v0: np.ndarray) -> tuple[list[_ModalSet], str]:
    """The scalar modes of the augmented system and what was solved, for
    :func:`vibss.time.kernels.modal.run_modal`.

    Parameters
    ----------
    prep : Prepared
        Of a plant with branches.
    q0, v0 : (n,) ndarray
        Initial displacement and velocity of the free DOFs [m, rad, m/s, rad/s]; the branches start
        relaxed (no force).

    Returns
    -------
    sets : list of _ModalSet
    how : str

    Raises
    ------
    DefectiveModesError
        The structure does not hold or the roots cannot be certified (the message says which).
    """
    plant = prep.plant
    br = plant.branches
    assert br is not None
    phi, _, _, bm = plant.cached("branch modes", lambda: _structure(plant))
    de, dd, df = bm.dual()
    M = np.asarray(plant.M, float)
    eta0, deta0 = phi.T @ (M @ q0), phi.T @ (M @ v0)
    m = len(plant.inputs)
    bt = br.Bz - br.B @ prep.G                                  # (r, m) branch deflection per z
    pc = dd.T @ (phi.T @ channels(prep))                       # generalized forces into eta'
    pc[:, 2 * m:] += df.T @ (br.k[:, None] * bt)               # f' = k Bt z'
    Oa = np.asarray(plant.Oa, float)
    cf = br.O - (Oa @ mass_solver(plant)(br.B.T) if np.any(Oa) else 0.0)
    Y = ((prep.Cp @ phi) @ bm.eta + (prep.Cv @ phi) @ (bm.eta * bm.lam[None]) + cf @ bm.force) * bm.weight[None]
    x0 = de.T @ eta0 + dd.T @ deta0
    ms = _ModalSet(A=bm.lam.reshape(-1, 1, 1), P=None, x0=x0[:, None], Y=Y[:, :, None], Pc=pc)
    return [ms], f"modes plus branch states as complex modes ({bm.how})"
