"""The exact solve at a few points, from the undamped modes: one refinement step, certified by its residual.

A modal method's check compares its answer with the exact solve at some 20 frequencies
(:func:`vibss.frequency.contracts.against_exact`). Where the exact solve is costly -- SuperLU on a
2,400-DOF random graph fills 2.1 million entries and takes 0.57 s a frequency, 11 s for the check
beside 3.5 s for the whole modal answer -- the same certified solution comes cheaper from the modes:

    x0 = Phi D(s) Phi^T f,     x1 = x0 + Phi D(s) Phi^T (f - A(s) x0),

``A(s) = K + iH + sC + s^2 M`` applied with the plant's own matrices (independent of the modes),
``D(s) = diag(1 / (w_r^2 + s g_r + i h_r + s^2))`` from the diagonals of ``Phi^T C Phi`` and ``Phi^T H Phi``
(classical damping: the modal inverse is ``A(s)^-1`` up to the modes' error). A point is kept when
``x1``'s normwise backward error ``||f - A x1|| / (||A|| ||x1|| + ||f||)`` is at most :data:`ACCEPT`
-- what LU with partial pivoting leaves (``n eps``), so ``x1`` is as good a reference as the exact
solve's; the other points (and every point of a plant whose residual needs the mounts' form or has
branches) are left to the exact solve. All points at once: four products of ``Phi`` with
``(n, 2 k m)`` real blocks, against ``k`` sparse factorizations.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.sparse as sp

from ..eigen.basis import ModalBasis, classical_damping, projected_damping
from ..plant.plant import Plant
from .exact import _use_mounts, forcing, observe, response, zfactor
from .refine import backward_error_of

__all__ = ["ACCEPT", "refined_response", "reference"]

ACCEPT = 64.0 * np.finfo(float).eps
"""Largest normwise backward error per point (times ``sqrt(n)``) of the refined solution that is
kept: LU with partial pivoting's own level, so the reference is as good as the exact solve's."""


def _sparse(plant: Plant, key: str) -> Any:
    a = getattr(plant, key)
    if a is None or (not sp.issparse(a) and not np.any(a)):
        return None
    return plant.cached(f"sparse {key}", lambda: sp.csr_matrix(a) if not sp.issparse(a) else a.tocsr())


def _modal_solve(phi: np.ndarray, d: np.ndarray, r: np.ndarray) -> np.ndarray:
    """``Phi D_k Phi^T r_k`` for every point k at once: ``r`` (k, n, m) complex, ``d`` (k, q)."""
    k, n, m = r.shape
    block = np.ascontiguousarray(np.moveaxis(r, 0, 1)).reshape(n, k * m)      # (n, k m) complex
    modal = (phi.T @ block.view(float).reshape(n, 2 * k * m)).view(complex)   # (q, k m): real products
    modal = modal.reshape(-1, k, m) * d.T[:, :, None]
    out = (phi @ modal.reshape(-1, k * m).view(float).reshape(phi.shape[1], 2 * k * m)).view(complex)
    return np.moveaxis(out.reshape(n, k, m), 1, 0)


def refined_response(plant: Plant, s: np.ndarray, phi: np.ndarray, w2: np.ndarray, g: np.ndarray,
                     h: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Outputs at the points ``s`` from the modes, refined once; and which points are certified.

    Parameters
    ----------
    plant : Plant
        Classical damping, no branches.
    s : (k,) complex ndarray
        Laplace points [rad/s], nonzero.
    phi : (n, q) ndarray
        Mass-normalised undamped modes (all of them: a truncated set does not invert ``A(s)``, and
        its points fail the residual test).
    w2, g, h : (q,) ndarray
        Their ``omega^2`` [rad^2/s^2] (0 for rigid modes), ``Phi^T C Phi`` [rad/s] and ``Phi^T H Phi``
        [rad^2/s^2] diagonals.

    Returns
    -------
    y : (k, p, m) complex ndarray
        Outputs per unit input (their SI units); meaningful where ``ok``.
    ok : (k,) bool ndarray
        Points whose refined solution's backward error is at most ``ACCEPT sqrt(n)``.
    """
    s = np.asarray(s, complex)
    n = plant.n
    ok = np.zeros(s.size, bool)
    y = np.zeros((s.size, len(plant.outputs), len(plant.inputs)), complex)
    if plant.branches is not None or _use_mounts(plant, "auto") or not s.size or np.any(s == 0) \
            or phi.shape != (n, n):
        return y, ok
    zf = zfactor(s, plant.order)
    f = np.asarray(forcing(plant, s, zf), complex)
    with np.errstate(divide="ignore", invalid="ignore"):       # exactly at an undamped resonance: not certified
        d = 1.0 / (w2[None, :] + s[:, None] * g[None, :] + 1j * h[None, :] + (s * s)[:, None])
    if not np.all(np.isfinite(d)):
        return y, ok
    mats = [(_sparse(plant, key), c) for key, c in (("K", None), ("H", "i"), ("C", "s"), ("M", "s2"))]

    def apply(j: int, x: np.ndarray) -> np.ndarray:
        sj = complex(s[j])
        ax = np.zeros_like(x)
        for a, c in mats:
            if a is not None:
                ax += (1.0 if c is None else 1j if c == "i" else sj if c == "s" else sj * sj) * (a @ x)
        return ax

    x = _modal_solve(phi, d, f)
    r = np.stack([f[j] - apply(j, x[j]) for j in range(s.size)])
    x = x + _modal_solve(phi, d, r)
    for j in range(s.size):
        eta = backward_error_of(plant, complex(s[j]), f[j], x[j], apply(j, x[j]))
        ok[j] = eta <= ACCEPT * np.sqrt(n)
    y[:] = observe(plant, s, x, zf)
    return y, ok


def reference(plant: Plant, s: np.ndarray, basis: ModalBasis | None) -> tuple[np.ndarray, str]:
    """(p, m, k) exact response at ``s``, and how it was solved: refined from a complete basis of classically damped modes
    and certified by its residual where it can be (:func:`~vibss.linear.solve.from_modes.refined_response`:
    four GEMMs for every point, where SuperLU on a 2,400-DOF random graph took 0.57 s a point), the
    exact solve at the other points.

    Parameters
    ----------
    plant : Plant
    s : (k,) complex ndarray
        Laplace points [rad/s].
    basis : ModalBasis or None
        The plant's undamped modes, if known.

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
    y, ok = refined_response(plant, s, basis.phi, w2, np.diag(gam).copy(), np.diag(hys).copy())
    if not ok.any():
        return response(plant, s), plain
    if not ok.all():
        y[~ok] = np.moveaxis(response(plant, s[~ok]), -1, 0)
    how = " against the exact solution (the modes' solve refined once, its backward error at LU's level"
    return np.moveaxis(y, 0, -1), how + (f"; the exact solve at {int((~ok).sum())} of them)" if not ok.all() else ")")
