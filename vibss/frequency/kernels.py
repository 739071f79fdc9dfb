"""Frequency-response kernels of a :class:`~vibss.linear.plant.plant.Plant`, chosen by name (:data:`METHODS`).

Every kernel evaluates, at complex Laplace points ``s`` (``s = i w`` on the frequency axis),

    Y(s) = O(s) X(s) + P(s) Z(s) + Pf,    (K + i H + s C + s^2 M) X(s) = F - (Kz + i Hz + s Cz + s^2 Mz) Z(s)

with ``O(s) = Oq + i Oh + s Ov + s^2 Oa``, ``P(s) = Pz + i Ph + s Pv + s^2 Pa`` and
``Z(s) = diag(s^-order)`` (a motion input ``u`` of order 1 or 2 is a velocity or acceleration:
``z = u / s^order``). The hysteretic terms ``i H`` are the frequency-domain loss-factor stiffness
(for ``w > 0``). Kernels return a ``(p, m, nf)`` complex array.

- ``direct``: one complex solve per frequency (batched). The accurate reference.
- ``modal``: undamped modes (:func:`vibss.linear.eigen.basis.modal_basis`) and modal superposition; only for classical damping (``Phi^T C Phi`` and
  ``Phi^T H Phi`` diagonal). Rigid-body modes are exact (omega = 0 double integrators).
- ``complex_modal``: eigen-decomposition of the well-scaled first-order modal form
  ``[[0, S], [-(Omega^2 + i Phi^T H Phi) S^-1, -Phi^T C Phi]]`` (general viscous damping).
- ``woodbury``: undamped modes with the damping as a low-rank update ``U Z(s) U^T`` (U the modes'
  deflections at the damped mounts), a bordered solve of the dampers and the near-resonant modes per
  frequency (:mod:`vibss.frequency.lowrank`); any damping, no damped eigenproblem, cheap when few
  mounts carry damping.
- ``sparse``: the direct solve on the sparse structure, per frequency: a banded LU after a reverse
  Cuthill-McKee ordering (chains and other locally connected layouts), else SuperLU
  (:mod:`vibss.banded`). Exact like ``direct``; any damping.
- ``subspace``: a Galerkin projection on a block rational Krylov basis built from the inputs and
  outputs (real shifts over the band, one sparse or banded LU each), grown where exact solves at
  check frequencies between its interpolation points exceed the tolerance
  (:mod:`vibss.linear.project.subspace`); the note states the basis, the shifts and the checked error. For
  large models asked for many frequencies on few channels; any damping (C and H are projected),
  no frequency-dependent mounts.
- ``statespace``: ``control.frequency_response`` on :func:`vibss.linear.statespace.statespace`
  (SLICOT TB05AD on the scaled modal realization; viscous damping only).

Each entry of :data:`METHODS` is a :class:`FrequencyMethod` carrying its facts; a callable
``f(plant, s, basis) -> (p, m, nf)`` (the kernels' one signature; ``f(plant, s)`` is accepted too)
can be used as a method.
"""

from __future__ import annotations

import inspect
from collections.abc import Callable
from dataclasses import dataclass
from functools import partial, reduce

import numpy as np

from ..linear.eigen.complex_modes import complex_modes, pole_errors
from ..errors import AnalysisError
from ..linear.plant.plant import Plant
from ..linear.eigen.small import symmetric_eigen
from ..linear.eigen.basis import ModalBasis, classical_damping, modal_basis, projected_damping
from ..linear.solve.exact import response, zero_frequency_limit, zfactor
from ..linear.project.subspace import TOLERANCE, channel_subspace
from ..methods import Cost, Method, callable_name
from .contracts import (COMPLEX_MODAL, EXACT, MODAL, STATESPACE, SUBSPACE, WOODBURY, cost_complex_modal, cost_direct,
                        cost_modal, cost_sparse, cost_statespace, cost_subspace, cost_woodbury,
                        subspace_size)
from .lowrank import woodbury
from .terms import feedthrough as _feedthrough, has_feedthrough, mass_solve as _mass_solve, static as _static, terms as _terms

__all__ = ["METHODS", "FrequencyMethod", "custom_method", "direct", "modal", "complex_modal", "complex_modal_estimated", "woodbury", "sparse", "via_statespace",
           "complex_mode_risk", "mode_risks", "COMPLEX_MODE_RISK", "REFINE_PREDICT",
           "zero_frequency_limit"]


_CHUNK_BYTES = 64 * 2**20

_Factors = tuple[np.ndarray, ...]
"""A matrix given as the product of its factors, ``(A, B, ...)`` for ``A @ B @ ...``."""
_RightFactors = tuple[np.ndarray | Callable[[np.ndarray], np.ndarray], ...]
"""The same for right factors, where a callable ``f`` stands for the linear map ``x -> f(x)``."""
_Form = np.ndarray | tuple[np.ndarray, np.ndarray]
"""Modal transfer functions (nf, r), or the factors ``(a, b)`` of ``d * a[:, None] * b[None, :]``."""


def direct(plant: Plant, s: np.ndarray) -> np.ndarray:
    """The exact solve (:func:`vibss.linear.solve.exact.response`) by batched dense LU; returns (p, m, nf)."""
    return response(plant, s, backend="dense")


def sparse(plant: Plant, s: np.ndarray) -> np.ndarray:
    """The exact solve on the sparse structure; returns (p, m, nf).

    The same equations as :func:`direct` (:func:`vibss.linear.solve.exact.response`), solved by a
    banded LU (LAPACK ``zgbsv``, partial pivoting) after a reverse Cuthill-McKee ordering, or by
    SuperLU where the band is wide (:mod:`vibss.linear.solve.banded`). Exact like ``direct``, at
    O(n b^2) per frequency instead of O(n^3).
    """
    return response(plant, s, backend="sparse")


def subspace(plant: Plant, s: np.ndarray, tol: float = TOLERANCE) -> tuple[np.ndarray, str]:
    """The response of a projection built for the plant's channels, checked by exact solves;
    returns ((p, m, nf), note).

    :func:`vibss.linear.project.subspace.channel_subspace`: a block rational Krylov basis from the input
    and output vectors (real shifts over the band, each one sparse or banded LU), ``M, C, K, H``
    and every map projected on it, grown where the exact solve at a check frequency between the
    interpolation points shows an error above the tolerance. When it does not reach ``tol``, or
    stops at its ``budget`` (the exact solve at every frequency: about twice that in all), the exact
    sparse solve (:func:`sparse`) answers where it has not solved exactly, and the note says so.
    """
    return _subspace_checked(plant, s, tol)[:2]


def _subspace_checked(plant: Plant, s: np.ndarray, tol: float = TOLERANCE) -> tuple[np.ndarray, str, float | None]:
    """:func:`subspace` and the error it checked (None where the exact sparse solve answered).

    When its starting basis alone (``N_SHIFTS MOMENTS`` blocks of the channels' vectors) would hold half
    as many vectors as the plant has DOFs, it is no reduction and costs a dense ``r^3`` a frequency (42
    inputs at 600 DOFs: 2,112 vectors, estimated 2,800 s against 0.07 s; 8 channels, 384 vectors: its
    projected mass lost definiteness): the exact sparse solve answers up front, the note giving both
    estimates. A basis that still becomes dependent is answered the same way.
    """
    r = subspace_size(plant)
    if 2 * r >= plant.n:
        nf = np.asarray(s).size
        mine, exact = cost_subspace(plant, nf, projection=True), cost_sparse(plant, nf)
        return sparse(plant, s), (f"the channel subspace would start with about {r} vectors for {plant.n} DOFs "
                                  f"({len(plant.inputs)} inputs, {len(plant.outputs)} outputs), no reduction "
                                  f"(estimated {mine.text()}): exact sparse solve at every frequency instead "
                                  f"(estimated {exact.text()})"), None
    w = np.abs(np.asarray(s).imag)
    try:                                                 # budget: the exact solve at every frequency
        sub = channel_subspace(plant, w, tol, budget=float(np.unique(w).size))
    except np.linalg.LinAlgError as exc:     # its projected mass lost definiteness: a dependent basis
        return sparse(plant, s), (f"the channel subspace's basis of about {r} vectors became dependent ({exc}): "
                                  "exact sparse solve at every frequency instead"), None
    if sub.converged:
        return sub.response, sub.describe(), sub.error
    h, rest = sub.completed(np.asarray(s), lambda x: sparse(plant, x))     # its exact solves kept
    return h, (f"the channel subspace did not reach {tol:g} ({sub.describe()}): exact sparse solve at the other "
               f"{rest} of {w.size} frequencies instead"), None


def _times_left(o: np.ndarray, blocks: list[_Factors]) -> np.ndarray:
    """``o @ [L1 | L2 | ...]`` with each block a tuple of factors, multiplied from the left."""
    parts = [reduce(np.matmul, block, o) for block in blocks]
    return parts[0] if len(parts) == 1 else np.hstack(parts)


def _times_right(blocks: list[_RightFactors], r: np.ndarray) -> np.ndarray:
    """``[R1; R2; ...] @ r`` with each block a tuple of factors, multiplied from the right."""
    parts = [reduce(lambda acc, f: f(acc) if callable(f) else f @ acc, block[::-1], r) for block in blocks]
    return parts[0] if len(parts) == 1 else np.vstack(parts)


def _products(lefts: list, rights: list, dd: np.ndarray, s: np.ndarray, zf: np.ndarray,
              consts: list[tuple[dict, np.ndarray]], p: int, m: int, transposed: bool = False) -> np.ndarray:
    """``sum_ab s^(a+b) Z (O_a left) diag(dd) (right R_b)`` plus ``consts`` (``{(a, i): (p, m)}`` with
    (nr,) factors), (p m, nr): ``dd`` (nr, r), or its contiguous transpose; that (r, nr) transpose is
    read as real pairs, so one real GEMM with a real weight gives the complex products in place."""
    nr = s.size
    dt = dd if transposed else np.ascontiguousarray(dd.T, dtype=complex)
    out: np.ndarray | None = None
    for a, lo in lefts:
        for i, (b, ro, scaled, _) in enumerate(rights):
            w = (lo[:, :, None] * ro[None, :, :]).transpose(1, 0, 2).reshape(-1, p * m)
            if np.isrealobj(w):
                t = (np.ascontiguousarray(w.T) @ dt.view(float)).view(complex)          # (p m, nr)
            else:
                t = w.T @ dt
            for ys, scale in consts:               # t is the product's own array: added in place
                t += ys[(a, i)].reshape(p * m, 1) * scale[None, :]
            if a + b or scaled:
                fac = s[:, None] ** (a + b) * (zf if scaled else np.ones((1, m)))     # (nr, m)
                t = (t.reshape(p, m, nr) * fac.T[None, :, :]).reshape(p * m, nr)
            out = t if out is None else out + t
    return out if out is not None else np.zeros((p * m, nr), dtype=complex)


def _superpose(plant: Plant, s: np.ndarray, left: list[_Factors],
               right: list[_RightFactors], d: np.ndarray,
               d_acc: _Form | None = None, d_mass: _Form | None = None, basis: ModalBasis | None = None) -> np.ndarray:
    """``Y = sum_ab s^(a+b) Z (O_a left) diag(d) (right R_b)`` + feedthrough; returns (p, m, nf).

    ``left`` (n, r) maps modal amplitudes to DOFs, ``right`` (r, n) maps generalised forces to
    modal forces, ``d`` (nf, r) the modal transfer functions. Both come as blocks of factors,
    ``left = [L1 | L2 | ...]`` with ``Lk = A @ B @ ...`` given as the tuple ``(A, B, ...)`` (and
    ``right`` the row blocks likewise), so that only the thin products ``O_a A B`` and
    ``... B (A R_b)`` are formed, never the (n, r) matrices themselves. With ``d_acc`` (the same transfer
    functions less their static part, ``d - d(0)``) the *mode-acceleration* form
    ``Y = O (K + iH)^-1 R + sum(d_acc)`` is evaluated too (static part by :func:`_static`, given ``basis``), and each
    frequency takes the form with the smaller cancellation (sum of term magnitudes): the plain sum
    loses digits below the modes, where many high-mode terms cancel, the other above them. With
    ``d_mass`` (the transfer functions less their high-frequency part, ``d - 1/s^2`` for
    displacements) the *mass-residual* form ``Y = O M^-1 R / s^2 + sum(d_mass)`` competes too: far
    above a mode, its first-order terms ``r/(s - lam) + conj`` cancel to ``~ |s| / omega`` times
    their sum (graded chain, omega_max / omega_1 = 2e7: 1e-8 lost at 1.01 omega_max), which the
    residual form does not. Either form may be given as a pair ``(a, b)`` of (nf,) and (r,) factors
    for ``d * a[:, None] * b[None, :]`` (complex modes: ``d_acc = s d / lam``, ``d_mass = d lam^2 /
    s^2``): its cost is then ``|d|``'s weighted by ``|b|`` and it is formed only at the frequencies
    that take it (two (nf, r) complex arrays and their magnitudes fewer: 0.15 s of 3 s at 600 DOF).
    """
    outs, rhs, order = _terms(plant)
    p, m, nf = len(plant.outputs), len(plant.inputs), s.size
    zf = zfactor(s, order)
    lefts = [(a, _times_left(oa, left)) for a, oa in outs]
    rights = [(b, _times_right(right, rb), scaled, rb) for b, rb, scaled in rhs]
    wl = sum(np.linalg.norm(lo, axis=0) for _, lo in lefts)
    wr = sum(np.linalg.norm(ro, axis=1) for _, ro, _, _ in rights)
    omap = dict(outs)
    weight = wl * wr
    absd = np.abs(d)
    costs = [absd @ weight]
    bad = np.zeros((0, 0), dtype=bool)   # where d is not finite (1 / 0 at an undamped resonance): a sum
    if not np.isfinite(costs[0]).all():  # with such a term is not finite; no test per entry else
        bad = ~np.isfinite(d)
        d = np.where(bad, 0.0, d)
        absd = np.abs(d)
        costs = [absd @ weight]
    # the forms: (transfer functions or their (row, column) factors on d, constant outputs
    # {(a, i): (p, m)}, their factor per frequency)
    forms: list[tuple[_Form, dict | None, np.ndarray | None]] = [(d, None, None)]
    for extra, solver, factor in ((d_acc, partial(_static, basis=basis), None), (d_mass, _mass_solve, -2)):
        if extra is None:
            continue
        if isinstance(extra, tuple) and not np.all(np.isfinite(extra[1])):
            continue
        try:
            const = [solver(plant, rb) for _, _, _, rb in rights]
        except (np.linalg.LinAlgError, ValueError, RuntimeError):
            continue
        with np.errstate(divide="ignore", invalid="ignore"):
            scale = np.ones(nf) if factor is None else s.astype(complex) ** factor
        ok = np.isfinite(scale)
        if isinstance(extra, tuple):                     # d a[:, None] b[None, :], d finite
            ok &= np.isfinite(extra[0])
            terms = (absd @ (np.abs(extra[1]) * weight)) * np.abs(np.where(ok, extra[0], 0.0))
        else:
            terms = np.abs(extra) @ weight
            if not np.isfinite(terms).all():             # at s = 0 or an undamped resonance
                fin = np.isfinite(extra)
                ok &= np.all(fin | bad if bad.size else fin, axis=1)
                extra = np.where(fin, extra, 0.0)
                terms = np.abs(extra) @ weight
        scale = np.where(ok, scale, 0.0)
        ys = {(a, i): omap[a] @ const[i] for a, _ in lefts for i in range(len(rights))}
        # pick per frequency the form with the smallest sum of term magnitudes
        cost = terms + np.abs(scale) * sum(np.linalg.norm(v) for v in ys.values())
        forms.append((extra, ys, scale))
        costs.append(np.where(ok, cost, np.inf))
    pick = np.argmin(np.stack(costs), axis=0)
    if not any(isinstance(form, tuple) for form, _, _ in forms):
        # one product over every frequency, each from the form it picked, its constants added there:
        # no per-form gathers and scatters of columns (150 DOF, 1,000 x 216 channels: 3 ms, not 9)
        dt = np.empty(d.shape[::-1], dtype=complex)      # (r, nf): the transpose the product reads
        dt[...] = d.T
        for which, (form, _, _) in enumerate(forms[1:], 1):
            rows = pick == which
            if np.any(rows):
                dt[:, rows] = form[rows].T
        consts = [(c, np.where(pick == which, cscale, 0.0)) for which, (_, c, cscale) in enumerate(forms)
                  if c is not None and cscale is not None and np.any(pick == which)]
        y = _products(lefts, rights, dt, s, zf, consts, p, m, transposed=True)
    else:
        y = np.zeros((p * m, nf), dtype=complex)         # frequencies last, as the products give them
        for which, (form, consts_k, cscale) in enumerate(forms):
            rows = pick == which
            if not np.any(rows):
                continue
            if isinstance(form, tuple):
                dd = d[rows] * form[0][rows, None]
                dd *= form[1][None, :]
            else:
                dd = form if rows.all() else form[rows]
            y[:, rows] = _products(lefts, rights, dd, s[rows], zf[rows],
                                   [] if consts_k is None or cscale is None else [(consts_k, cscale[rows])], p, m)
    for k in np.flatnonzero(bad.any(axis=1)) if bad.size else ():   # unbounded where seen and driven
        modes = bad[k]
        seen = sum(np.abs(lo[:, modes]) for _, lo in lefts)
        driven = sum(np.abs(ro[modes, :]) for _, ro, _, _ in rights)
        y[(np.asarray(seen) @ np.asarray(driven)).reshape(-1) > 0, k] = np.inf
    out = y.reshape(p, m, nf)
    return out + np.moveaxis(_feedthrough(plant, s, zf), 0, -1) if has_feedthrough(plant) else out


COMPLEX_MODE_RISK = 1e-9
"""Above this :func:`complex_mode_risk` ``eig``'s poles are not trusted as they stand: complex modes
screen and refine the slow ones (:mod:`vibss.linear.eigen.complex_modes`), and ``auto`` counts that cost."""

REFINE_PREDICT = 1e-6
"""``auto`` expects a mode to need the per-mode inverse iteration of the complex modes (after their
a-posteriori screen) when its :func:`mode_risks` exceeds this. Measured, 600 DOF, counted per
conjugate pair: the tree of benchmarks/models.py 2 predicted, 5 refined (107 above
:data:`COMPLEX_MODE_RISK`); its badly scaled chain 132 predicted, 53 refined (344 above)."""


def mode_risks(basis: ModalBasis, projected: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
    """Predicted relative error of complex modes at each elastic mode's resonance; returns (ne,).

    ``eig`` has absolute pole errors of about eps max|lambda| (overdamped modes reach |lambda| ~
    the diagonal of ``Phi^T C Phi``), which a mode decaying at ``zeta omega`` amplifies by
    ``1 / (zeta omega)`` at its resonance; ``inf`` where an elastic mode has no damping. An
    a-priori bound: the true errors can be far smaller (:mod:`vibss.linear.eigen.complex_modes`).

    Parameters
    ----------
    basis : ModalBasis
        Undamped modes.
    projected : (Phi^T C Phi, Phi^T H Phi)
        From :func:`~vibss.linear.eigen.basis.projected_damping`.

    Returns
    -------
    (ne,) ndarray
    """
    el = ~basis.rigid
    if not el.any():
        return np.zeros(0)
    g = np.abs(np.diag(projected[0])[el])
    w = np.sqrt(np.maximum(basis.omega2[el], np.finfo(float).tiny))
    decay = 0.5 * g + 0.5 * np.abs(np.diag(projected[1])[el]) / w
    top = max(float(w.max()), float(g.max()))
    eps = np.finfo(float).eps
    with np.errstate(divide="ignore"):
        return np.where(decay <= eps * top, np.inf, eps * top / decay)   # undamped: a pole on the axis


def complex_mode_risk(basis: ModalBasis, projected: tuple[np.ndarray, np.ndarray]) -> float:
    """The largest of :func:`mode_risks` (0 without elastic modes).

    Parameters
    ----------
    basis : ModalBasis
        Undamped modes.
    projected : (Phi^T C Phi, Phi^T H Phi)
        From :func:`~vibss.linear.eigen.basis.projected_damping`.

    Returns
    -------
    float
    """
    risks = mode_risks(basis, projected)
    return float(risks.max()) if risks.size else 0.0


def modal(plant: Plant, s: np.ndarray, basis: ModalBasis | None = None) -> np.ndarray:
    """Modal superposition over the undamped modes (classical damping only); returns (p, m, nf).

    Raises
    ------
    AnalysisError
        The damping is not classical (use ``complex_modal`` or ``direct``).
    """
    s = np.asarray(s, dtype=complex)
    basis = basis or modal_basis(plant)
    projected = projected_damping(plant, basis)
    ok, why = classical_damping(plant, basis, projected)
    if not ok:
        raise AnalysisError(f"method 'modal' needs classical damping: {why}; use 'complex_modal' or 'direct'")
    phi = basis.phi
    gamma, hyst = np.diag(projected[0]), np.diag(projected[1])
    with np.errstate(divide="ignore", invalid="ignore"):
        kappa = basis.omega2 + 1j * hyst
        dyn = s[:, None] * gamma[None, :]           # s c_r + s^2 (the dynamic part), in place
        dyn += (s**2)[:, None]
        d = dyn + kappa[None, :]
        np.reciprocal(d, out=d)
        # no mass-residual form: second-order terms 1 / (s^2 + g s + k) do not cancel above the modes
        # (graded chain at 1.01 omega_max: 1.2e-10 without it), and it would cost ~12 % at 600 DOF
        if np.any(basis.rigid):
            d_acc = None
        else:
            d_acc = dyn
            d_acc *= d
            d_acc /= -kappa[None, :]
    return _superpose(plant, s, [(phi,)], [(phi.T,)], d, d_acc, basis=basis)


def complex_modal(plant: Plant, s: np.ndarray, basis: ModalBasis | None = None) -> np.ndarray:
    """Complex modes of the scaled first-order modal form (general damping); returns (p, m, nf).
    :func:`complex_modal_estimated` without its error estimate."""
    return _complex_modal(plant, s, basis, False)[0]


def complex_modal_estimated(plant: Plant, s: np.ndarray,
                            basis: ModalBasis | None = None) -> tuple[np.ndarray, np.ndarray]:
    """:func:`complex_modal`'s response (p, m, nf) and its a-posteriori relative error estimate (nf,).

    Per mode ``k`` the pole error bound ``dlam_k`` and the residue's mixing ``mu_k``
    (:func:`vibss.linear.eigen.complex_modes.pole_errors`, from the damped pairs already computed)
    make the term ``w_k / (s - lam_k)`` (``w_k`` its residue's norm through the channels) off by
    ``w_k |d_k| (dlam_k |d_k| + mu_k)`` with ``d_k = 1 / (s - lam_k)``; their sum over the modes,
    relative to the response's norm at ``s``, is the estimate. Cost ``nf N`` and ``N^2 (m + nk)``
    beside the method's ``N^3``. The damped rigid modes' ``1 / (s (s - lam))`` terms are left out.
    """
    h, est = _complex_modal(plant, s, basis, True)
    assert est is not None
    return h, est


def _complex_modal(plant: Plant, s: np.ndarray, basis: ModalBasis | None,
                   estimate: bool) -> tuple[np.ndarray, np.ndarray | None]:
    """Complex modes of the scaled first-order modal form (general damping); returns the response
    (p, m, nf) and, with ``estimate``, its relative error estimate (nf,) (else None).

    Rigid-body modes have no displacement feedback (w = 0), so their displacement states leave the
    eigenproblem, where they would be zero eigenvalues (2x2 Jordan blocks when undamped, repeated
    and ill-conditioned when damped). Rigid modes that no damper touches are exact ``1 / s^2``
    terms; damped rigid modes keep their velocity state, and their displacement ``eta = eta' / s``
    takes the terms ``1 / (s (s - lam))`` as they stand (no partial fractions, which would cancel
    terms of size ``1 / lam`` when a rigid mode is lightly damped). The rows of ``V^-1`` are the
    left eigenvectors, built from the right ones by the symmetry of the quadratic eigenproblem
    (:mod:`vibss.complex_modes`; an LU of ``V`` where that is unsafe).
    """
    s = np.asarray(s, dtype=complex)
    basis = basis or modal_basis(plant)
    phi, sc = basis.phi, basis.scale
    gam, hys = projected_damping(plant, basis)
    rid = np.flatnonzero(basis.rigid)
    if rid.size:
        # rotate the rigid subspace so its damping block is diagonal: undamped combinations of rigid
        # modes (e.g. a body free to turn about its single mount) then stand out as modes of their own
        _, q = symmetric_eigen(gam[np.ix_(rid, rid)])
        phi, gam, hys = phi.copy(), gam.copy(), hys.copy()
        phi[:, rid] = phi[:, rid] @ q
        for g in (gam, hys):
            g[rid, :] = q.T @ g[rid, :]
            g[:, rid] = g[:, rid] @ q
    top = max(float(np.abs(gam).max()), float(np.abs(hys).max()), np.finfo(float).tiny)
    untouched = (np.abs(gam).max(axis=1) <= 1e-12 * top) & (np.abs(hys).max(axis=1) <= 1e-12 * top)
    free = basis.rigid & untouched
    el = np.flatnonzero(~basis.rigid)                 # elastic: displacement and velocity states
    kept = np.flatnonzero(~free)                      # velocity states: elastic + damped rigid
    ne, nk = el.size, kept.size
    lefts: list[_Factors] = []
    rights: list[_RightFactors] = []
    ds: list[np.ndarray] = []
    with np.errstate(divide="ignore", invalid="ignore"):
        inv_s = 1.0 / s
    if free.any():                                    # eta'' = f: 1 / s^2 exactly
        lefts.append((phi[:, free],))
        rights.append((phi[:, free].T,))
        ds.append(np.repeat((inv_s**2)[:, None], int(free.sum()), axis=1))
    lam = np.zeros(0, complex)
    if nk:
        se = sc[el]
        pos = np.searchsorted(kept, el)                # elastic rows among the kept modes
        coupling = 1j * hys[np.ix_(kept, el)] / se[None, :] if np.any(plant.H) else None
        modes = complex_modes(se, pos, basis.omega2[el], gam[np.ix_(kept, kept)], coupling)
        lam, v = modes.lam, modes.vectors
        phik = phi[:, kept]
        with np.errstate(divide="ignore", invalid="ignore"):
            pole = 1.0 / (s[:, None] - lam[None, :])
        if estimate:
            errs = pole_errors(modes, se, pos, basis.omega2[el], gam[np.ix_(kept, kept)], coupling,
                               None if basis.error is None else basis.error[el])
            absolute = _pole_error(plant, pole, [(phi[:, el], v[:ne] / se[:, None])],
                                   [(modes.solve_velocity, phik.T)], *errs)
        lefts.append((phi[:, el], v[:ne] / se[:, None]))   # elastic eta = S^-1 y1, factored
        rights.append((modes.solve_velocity, phik.T))       # V^-1 [0; Phi^T R], refined
        ds.append(pole)
        rig = np.flatnonzero(basis.rigid[kept])       # damped rigid modes among the kept ones
        if rig.size:                                  # eta = eta' / s: 1 / (s (s - lam)) as it stands
            lefts.append((phik[:, rig], v[ne + rig]))
            rights.append((modes.solve_velocity, phik.T))
            with np.errstate(divide="ignore", invalid="ignore"):
                ds.append(pole * inv_s[:, None])
    d = np.asarray(ds[0] if len(ds) == 1 else np.hstack(ds), dtype=complex)   # no copy for one part
    d_acc: _Form | None = None
    d_mass: _Form | None = None
    if not basis.rigid.any():
        with np.errstate(divide="ignore", invalid="ignore"):
            d_acc = (s, 1.0 / lam)            # s d / lam
            # 1 / (s - lam) - 1 / s - lam / s^2: sum_j r_j = 0 and sum_j lam_j r_j = M^-1 for displacements
            d_mass = (1.0 / s**2, lam**2)     # d lam^2 / s^2
    h = _superpose(plant, s, lefts, rights, d, d_acc, d_mass)
    if not estimate:
        return h, None
    if not nk:
        return h, np.zeros(s.size)
    size = np.linalg.norm(np.where(np.isfinite(h), h, 0.0), axis=(0, 1))
    with np.errstate(divide="ignore", invalid="ignore"):
        est = absolute / size
    return h, np.where(np.isnan(est), np.inf, est)


def _pole_error(plant: Plant, pole: np.ndarray, left: list[_Factors], right: list[_RightFactors],
                dlam: np.ndarray, mix: np.ndarray) -> np.ndarray:
    """The absolute error bound ``sum_k w_k |d_k| (dlam_k |d_k| + mix_k)`` (nf,) of the modal terms
    ``pole`` (nf, N), ``w_k`` the norm of mode k's residue through the outputs and inputs
    (:func:`complex_modal_estimated`)."""
    outs, rhs, _ = _terms(plant)
    wl = sum(np.linalg.norm(_times_left(oa, left), axis=0) for _, oa in outs)
    wr = sum(np.linalg.norm(_times_right(right, rb), axis=1) for _, rb, _ in rhs)
    weight = wl * wr
    ad = np.abs(np.where(np.isfinite(pole), pole, np.inf))
    with np.errstate(invalid="ignore", over="ignore"):
        out = (ad * ad) @ (weight * dlam) + ad @ (weight * mix)
    return np.where(np.isnan(out), np.inf, out)


def via_statespace(plant: Plant, s: np.ndarray) -> np.ndarray:
    """``control.frequency_response`` of :func:`vibss.linear.statespace.statespace` (s = i w only)."""
    import control

    from ..linear.statespace import statespace

    s = np.asarray(s, dtype=complex)
    if np.any(plant.H) or np.any(plant.Hz) or (plant.Oh is not None and np.any(plant.Oh)):
        raise AnalysisError("method 'statespace' cannot represent hysteretic damping (loss factors); "
                            "use 'modal', 'complex_modal' or 'direct'")
    if np.any(s.real != 0) or np.any(s.imag <= 0):
        raise AnalysisError("method 'statespace' evaluates positive frequencies only")
    sys = statespace(plant)
    return np.asarray(control.frequency_response(sys, s.imag).complex).reshape(
        len(plant.outputs), len(plant.inputs), s.size)


@dataclass(frozen=True)
class FrequencyMethod(Method):
    """A frequency-response method: ``kernel(plant, s, basis=None) -> (p, m, nf)`` complex.

    ``s`` (nf,) are Laplace points (``i w``, w > 0), ``basis`` the plant's undamped
    :class:`~vibss.linear.eigen.basis.ModalBasis` (computed once per analysis; None for a sparse plant).

    Attributes
    ----------
    needs_basis : bool
        Superposes the undamped modes (the driver computes them for the grid anyway).
    sparse_ok : bool
        Accepts a plant whose ``M, C, K, H`` are scipy.sparse matrices.
    self_checked : bool
        The kernel returns ``(response, note, error)`` and checks itself against the exact solve
        (``error`` the relative error it measured, None where it answered by the exact solve).
    cost : callable or None
        ``cost(plant, nf, basis) -> Cost``: its estimated seconds and peak bytes
        (:mod:`vibss.frequency.contracts`); None for a user's kernel.
    estimated : callable or None
        ``estimated(plant, s, basis) -> (response, estimate)``: the kernel with its a-posteriori
        relative error estimate (nf,), where the check's exact solves go
        (:func:`vibss.frequency.contracts.estimate_frequencies`); None without one.
    """

    needs_basis: bool = False
    sparse_ok: bool = False
    self_checked: bool = False
    cost: Callable[..., Cost] | None = None
    estimated: Callable[..., tuple[np.ndarray, np.ndarray]] | None = None


def _direct(plant: Plant, s: np.ndarray, basis: ModalBasis | None = None) -> np.ndarray:
    return direct(plant, s)


def _sparse(plant: Plant, s: np.ndarray, basis: ModalBasis | None = None) -> np.ndarray:
    return sparse(plant, s)


def _statespace(plant: Plant, s: np.ndarray, basis: ModalBasis | None = None) -> np.ndarray:
    return via_statespace(plant, s)


def _subspace(plant: Plant, s: np.ndarray, basis: ModalBasis | None = None) -> tuple[np.ndarray, str, float | None]:
    return _subspace_checked(plant, s)


METHODS: dict[str, FrequencyMethod] = {m.name: m for m in (
    FrequencyMethod("direct", _direct, exact=True, internal_states=True, claim=EXACT,
                    cost=cost_direct,
                    summary="one dense complex solve per frequency (the reference)"),
    FrequencyMethod("modal", modal, needs_basis=True, claim=MODAL, cost=cost_modal,
                    summary="undamped modal superposition (classical damping only)"),
    FrequencyMethod("complex_modal", complex_modal, needs_basis=True, fallback="sparse",
                    claim=COMPLEX_MODAL, cost=cost_complex_modal, estimated=complex_modal_estimated,
                    summary="complex modes of the scaled modal first-order form (any damping)"),
    FrequencyMethod("woodbury", woodbury, needs_basis=True, internal_states=True, claim=WOODBURY,
                    cost=cost_woodbury,
                    summary="undamped modes + the dampers and frequency-dependent mounts as a low-rank update, "
                            "bordered solve per frequency (any damping)"),
    FrequencyMethod("sparse", _sparse, exact=True, sparse_ok=True, internal_states=True, claim=EXACT,
                    cost=cost_sparse,
                    summary="banded or SuperLU complex solve per frequency"),
    FrequencyMethod("subspace", _subspace, sparse_ok=True, self_checked=True, claim=SUBSPACE,
                    cost=cost_subspace,
                    summary="projection on a rational Krylov basis built for the channels, checked by exact "
                            "solves between its shifts (large models, many frequencies, few channels)"),
    FrequencyMethod("statespace", _statespace, internal_states=True, claim=STATESPACE,
                    cost=cost_statespace,
                    summary="control.frequency_response of the modal state space (viscous only)"),
)}
"""Frequency-response methods by name (:class:`FrequencyMethod`; ``"auto"`` is chosen by
:func:`vibss.frequency.methods.choose`)."""


def custom_method(fn: Callable[..., np.ndarray]) -> FrequencyMethod:
    """A user kernel as a :class:`FrequencyMethod`: it gets ``(plant, s, basis)`` like the built-ins.

    A two-argument ``fn(plant, s)`` (the former signature) is accepted too and gets no basis.
    """
    try:
        params = inspect.signature(fn).parameters.values()
    except (TypeError, ValueError):          # a builtin without a signature: pass the basis
        params = None
    takes_basis = params is None or any(
        q.kind in (q.VAR_POSITIONAL, q.VAR_KEYWORD) or q.name == "basis" for q in params) or \
        sum(q.kind in (q.POSITIONAL_ONLY, q.POSITIONAL_OR_KEYWORD) for q in params) >= 3
    kernel = fn if takes_basis else (lambda plant, s, basis=None: fn(plant, s))
    return FrequencyMethod(callable_name(fn), kernel, sparse_ok=True, summary="user kernel")
