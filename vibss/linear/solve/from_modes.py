"""The exact solve at a few points, from the undamped modes: refined once, certified by the next correction.

A modal method's check compares its answer with the exact solve at some 20 frequencies
(:func:`vibss.frequency.contracts.against_exact`). Where the exact solve is costly -- SuperLU on a
2,400-DOF random graph fills 2.1 million entries and takes 0.57 s a frequency, 11 s for the check
beside 3.5 s for the whole modal answer -- a certified reference comes cheaper from the modes, as
iterative refinement with the modal inverse for the approximate one:

    x0 = Phi D(s) Phi^T f,   x1 = x0 + Phi D(s) Phi^T r0,   dx = Phi D(s) Phi^T r1,   r_k = f - A(s) x_k,

``A(s) = K + iH + sC + s^2 M`` applied with the plant's own matrices (the residuals are independent
of the modes), ``D(s) = diag(1 / (w_r^2 + s g_r + i h_r + s^2))`` from the diagonals of
``Phi^T C Phi`` and ``Phi^T H Phi`` (classical damping: the modal inverse is ``A(s)^-1`` up to the modes'
error). A point is kept when the outputs of the next correction ``dx`` are at most ``tol`` of the
outputs of ``x1`` (the refinement has converged there: ``x1``'s error is about that correction,
measured, not assumed from a condition number) and ``x1``'s normwise backward error is at LU's
level (:data:`ACCEPT`). A wrong basis leaves residuals its inverse does not remove, and its points
fail. The other points -- and all of them for a plant with branches, or where the exact solve would
work in the mounts' forces (stiff links, or a free motion below the frequency where the assembled
``K``'s round-off swamps its inertia: the residual ``f - A x`` carries that round-off too) -- go to the
exact solve. All points at once: six products of ``Phi`` with ``(n, 2 k m)`` real blocks, against
``k`` sparse factorizations.
"""

from __future__ import annotations

from functools import partial
from typing import Any

import numpy as np
import scipy.sparse as sp

from ..eigen.basis import ModalBasis, classical_damping, nonzero, projected_damping
from ..eigen.checks import fast_matrix
from ..plant.plant import Plant
from .exact import _mounts_at, forcing, observe, response, zfactor
from .refine import assembled_times, backward_error_of

__all__ = ["ACCEPT", "refined_response", "reference", "static_from_modes", "STATIC_FROM_MODES"]

ACCEPT = 64.0 * np.finfo(float).eps
"""Largest normwise backward error of the refined solution kept at a point, times ``sqrt(n)``
(LU with partial pivoting's order, ``n eps``, is within it up to about 4,000 DOFs)."""

TOL = 1e-11
"""Largest next correction kept, relative to the point's outputs (the reference's measured error), by
default; :func:`reference` takes a tenth of the claim it checks when that is smaller."""


def _modal_solve(phi: np.ndarray, d: np.ndarray, r: np.ndarray) -> np.ndarray:
    """``Phi D_k Phi^T r_k`` for every point k at once: ``r`` (k, n, m) complex, ``d`` (k, q)."""
    k, n, m = r.shape
    block = np.ascontiguousarray(np.moveaxis(r, 0, 1)).reshape(n, k * m)      # (n, k m) complex
    modal = (phi.T @ block.view(float).reshape(n, 2 * k * m)).view(complex)   # (q, k m): real products
    modal = modal.reshape(-1, k, m) * d.T[:, :, None]
    out = (phi @ modal.reshape(-1, k * m).view(float).reshape(phi.shape[1], 2 * k * m)).view(complex)
    return np.moveaxis(out.reshape(n, k, m), 1, 0)


def refined_response(plant: Plant, s: np.ndarray, phi: np.ndarray, w2: np.ndarray, g: np.ndarray,
                     h: np.ndarray, tol: float = TOL) -> tuple[np.ndarray, np.ndarray]:
    """Outputs at the points ``s`` from the modes, refined once; and which points are certified.

    Parameters
    ----------
    plant : Plant
        Classical damping, no branches.
    s : (k,) complex ndarray
        Laplace points [rad/s], nonzero.
    phi : (n, q) ndarray
        Mass-normalised undamped modes (all of them: a truncated set does not invert ``A(s)``, and
        its points fail).
    w2, g, h : (q,) ndarray
        Their ``omega^2`` [rad^2/s^2] (0 for rigid modes), ``Phi^T C Phi`` [rad/s] and ``Phi^T H Phi``
        [rad^2/s^2] diagonals.
    tol : float
        Largest next correction kept, relative to each point's outputs [-].

    Returns
    -------
    y : (k, p, m) complex ndarray
        Outputs per unit input (their SI units); meaningful where ``ok``.
    ok : (k,) bool ndarray
        Points whose next correction is within ``tol`` and whose backward error is within
        ``ACCEPT sqrt(n)``.
    """
    s = np.asarray(s, complex)
    n = plant.n
    ok = np.zeros(s.size, bool)
    y = np.zeros((s.size, len(plant.outputs), len(plant.inputs)), complex)
    apart = _mounts_at(plant, "auto", s) if plant.branches is None else None
    if plant.branches is not None or not s.size or np.any(s == 0) or phi.shape != (n, n) \
            or (apart is not None and apart.all()):
        return y, ok
    with np.errstate(divide="ignore", invalid="ignore"):       # exactly at an undamped resonance: not certified
        d = 1.0 / (w2[None, :] + s[:, None] * g[None, :] + 1j * h[None, :] + (s * s)[:, None])
    if not np.all(np.isfinite(d)):
        return y, ok
    zf = zfactor(s, plant.order)
    f = np.asarray(forcing(plant, s, zf), complex)
    for key in ("K", "H", "C", "M"):       # the residuals' products by the nonzeros (dense K at 2,400 DOF:
        mat = getattr(plant, key)          # 1.4 GFLOP a product), in the cache the modal basis fills too
        if nonzero(mat):
            plant.cached(f"sparse {key}", partial(fast_matrix, mat) if not sp.issparse(mat) else mat.tocsr)
    def residual(x: np.ndarray) -> np.ndarray:
        """(k, n, m) ``f - A(s) x`` at every point."""
        return f - assembled_times(plant, s, x)

    x = _modal_solve(phi, d, f)
    x = x + _modal_solve(phi, d, residual(x))
    r1 = residual(x)
    y[:] = observe(plant, s, x, zf)
    dy = observe(plant, s, _modal_solve(phi, d, r1), np.zeros_like(zf))
    dy -= plant.Pf[None]                              # the correction's outputs: no feedthrough
    size = np.linalg.norm(y, axis=(1, 2))
    for j in range(s.size):
        eta = backward_error_of(plant, complex(s[j]), f[j], x[j], f[j] - r1[j])
        ok[j] = eta <= ACCEPT * np.sqrt(n) and np.linalg.norm(dy[j]) <= tol * size[j]
    if apart is not None:
        ok &= ~apart
    return y, ok


def reference(plant: Plant, s: np.ndarray, basis: ModalBasis | None,
              claim: float = np.inf) -> tuple[np.ndarray, str]:
    """(p, m, k) exact response at ``s``, and how it was solved: refined from a complete basis of
    classically damped modes and certified where it can be (:func:`refined_response`: six GEMMs for
    every point, where SuperLU on a 2,400-DOF random graph took 0.57 s a point), the exact solve at
    the other points.

    Parameters
    ----------
    plant : Plant
    s : (k,) complex ndarray
        Laplace points [rad/s].
    basis : ModalBasis or None
        The plant's undamped modes, if known.
    claim : float
        The relative error the checked method claims [-]: the reference is certified to a tenth of
        it (at most :data:`TOL`).

    Returns
    -------
    (p, m, k) complex ndarray
        Outputs per unit input.
    str
        How, for the check's text (" against the exact solve" ...).
    """
    plain = " against the exact solve"
    if basis is None or basis.phi.shape != (plant.n, plant.n) or s.size == 0:
        return response(plant, s), plain
    gam, hys = projected_damping(plant, basis)
    if not classical_damping(plant, basis, (gam, hys))[0]:
        return response(plant, s), plain
    w2 = np.where(basis.rigid, 0.0, basis.omega2)
    tol = min(TOL, 0.1 * claim)
    y, ok = refined_response(plant, s, basis.phi, w2, np.diag(gam).copy(), np.diag(hys).copy(), tol)
    if not ok.any():
        return response(plant, s), plain
    if not ok.all():
        y[~ok] = np.moveaxis(response(plant, s[~ok]), -1, 0)
    how = (f" against a reference solution (the modes' solve refined once, with the plant's own residual: "
           f"its next correction within {tol:.0e} and its backward error at LU's level")
    return np.moveaxis(y, 0, -1), how + (f"; the exact solve at {int((~ok).sum())} of them)" if not ok.all() else ")")


STATIC_FROM_MODES = 1000
"""From this many DOFs the static part of the mode-acceleration form is taken from the modes
(:func:`static_from_modes`) unless ``K``'s factorisation is already known: SuperLU of a 2,400-DOF
random graph's ``K`` fills 3 million entries, 0.32 s of its 5 s FRF, where the modes' solve, its
refinement and the next correction cost six products of ``Phi`` and two of ``K`` with ``n x m`` blocks."""


def static_from_modes(plant: Plant, basis: ModalBasis, rb: np.ndarray, outputs: list[np.ndarray] | None = None,
                      tol: float = TOL) -> np.ndarray | None:
    """``K^-1 rb`` from the undamped modes, refined once with the plant's ``K`` and certified, or None.

    ``x0 = Phi W^-1 Phi^T rb``, ``x1 = x0 + Phi W^-1 Phi^T (rb - K x0)`` (``W = diag(w2)``): kept when
    the next correction ``dx`` is at most ``tol`` of ``x1`` in every column -- and so are its outputs
    ``O dx`` of ``O x1`` for each map of ``outputs``, what the answer reads, as :func:`refined_response`
    keeps a point by its outputs -- and ``x1``'s normwise backward error is at LU's level
    (:data:`ACCEPT`). None (the caller solves with ``K``) for a plant with rigid modes, a loss factor or
    branches, a truncated basis, or anything not finite.

    Parameters
    ----------
    plant : Plant
    basis : ModalBasis
        Its undamped modes (every one: ``phi`` square).
    rb : (n,) or (n, m) ndarray
        Right-hand sides [N, N m].
    outputs : list of (p, n) ndarray, optional
        The maps from DOFs to the outputs the caller reads from the solution.
    tol : float
        Largest next correction kept, relative to each column of ``x1`` (and of its outputs).

    Returns
    -------
    ndarray or None
        The static displacements [m, rad], shaped as ``rb``.
    """
    n = plant.n
    rb = np.asarray(rb)
    if plant.branches is not None or basis.phi.shape != (n, n) or np.any(basis.rigid) or nonzero(plant.H) \
            or np.iscomplexobj(rb):
        return None
    with np.errstate(divide="ignore", over="ignore"):
        inv = 1.0 / basis.omega2
    if not (np.all(np.isfinite(inv)) and np.all(inv > 0) and np.all(np.isfinite(rb))):
        return None
    phi = basis.phi
    mat: Any = plant.K
    k = plant.cached("sparse K", partial(fast_matrix, mat) if not sp.issparse(mat) else mat.tocsr)

    def solve(r: np.ndarray) -> np.ndarray:
        return phi @ (inv.reshape(-1, *([1] * (r.ndim - 1))) * (phi.T @ r))
    x = solve(rb)
    x = x + solve(rb - np.asarray(k @ x))
    kx = np.asarray(k @ x)
    dx = solve(rb - kx)
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(dx))):
        return None
    x2, dx2 = x.reshape(n, -1), dx.reshape(n, -1)
    for j, (r, xj, axj) in enumerate(zip(rb.reshape(n, -1).T, x2.T, kx.reshape(n, -1).T)):
        if not backward_error_of(plant, 0j, r, xj, axj) <= ACCEPT * np.sqrt(n):
            return None
    pairs = [(x2, dx2)] + [(o @ x2, o @ dx2) for o in (outputs or [])]
    for y, dy in pairs:
        if not np.all(np.linalg.norm(dy, axis=0) <= tol * np.linalg.norm(y, axis=0)):
            return None
    return x
