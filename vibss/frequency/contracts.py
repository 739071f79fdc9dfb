"""The contracts of the frequency-response methods: what each claims, how it is checked, what it costs.

Every entry of :data:`vibss.frequency.kernels.METHODS` carries a :class:`~vibss.methods.Claim` and a cost
model ``cost(plant, nf, basis) -> Cost`` (seconds and peak bytes, from the constants below, measured by
the benchmarks); :func:`check` is the a-posteriori check :func:`vibss.methods.decide` holds answers to:

- an exact method (``direct``, ``sparse``): the normwise backward error of its solve (:func:`backward_error`);
- a method built on the undamped modes, or ``statespace``, or a user's kernel: its relative error
  against the one exact solve at the band's ends and at its largest response (:func:`against_exact`),
  its sharpest peaks and deepest valleys, and, for a method with an a-posteriori estimate
  (``complex_modal``), where that estimate is largest or exceeds the claim (:func:`estimate_frequencies`);
- ``subspace``: its own exact solves between its interpolation points (the error it states).

The checks cost a few exact solves, not ``nf``: cheap next to the method itself.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from ..linear.eigen.basis import ModalBasis, classical_damping, damping_rank, nonzero, projected_damping
from ..linear.plant.plant import Plant
from ..linear.project.subspace import MOMENTS, N_SHIFTS, TWO_SIDED_MAX
from ..linear.solve.backends import _CHUNK_BYTES, MOUNTS_DENSE_MAX
from ..linear.solve.banded import _K_BAND, _T_FREQ, structure, superlu_seconds
from ..linear.solve.exact import MOUNTS_RATIO, forcing, response, states, zfactor
from ..linear.solve.from_modes import reference
from ..linear.solve.refine import assembled_times, backward_error_of, recorded_backward_errors
from ..costs import constant, scale
from ..methods import Check, Claim, Cost, Decision, decide

__all__ = ["settle", "EXACT", "MODAL", "COMPLEX_MODAL", "WOODBURY", "SUBSPACE", "STATESPACE", "check", "backward_error",
           "against_exact", "check_frequencies", "estimate_frequencies", "slower", "SLOWER", "limit", "BASIS_ERROR", "LIGHT_CAP", "cost_direct", "cost_sparse", "cost_modal", "cost_complex_modal",
           "cost_woodbury", "cost_subspace", "subspace_size", "cost_statespace", "woodbury_rank"]

EXACT = Claim(1e-8, exact=True, conditions="relative error of each response against 60 digits on models conditioned "
                                           "up to mass ratios of 1e6 (7e-9 measured there by the contract campaign); "
                                           "the solve's backward error is checked to 1e-10")
"""``direct`` and ``sparse``: LU with partial pivoting, backward stable; its backward error is of the
order ``n eps`` (1e-12 at 6,000 DOF), checked to :data:`BACKWARD` -- the forward error is that times the
problem's conditioning, which the claim's tolerance allows for (measured, not assumed)."""

BACKWARD = 1e-10
"""The backward error an exact solve is checked to (the check of the exact methods)."""

LIGHT = ("; at a mode of damping ratio zeta below 3e-4 the undamped modes' relative error 3e-13 is "
         "amplified at its peak: within 3e-13 / (2 zeta) there, capped at 1e-4")

MODAL = Claim(1e-8, exact=True, conditions="classical damping (Phi^T C Phi and Phi^T H Phi diagonal), "
                                           "on the certified undamped modes" + LIGHT)
"""``modal``: no truncation, every mode; refuses non-classical damping."""

COMPLEX_MODAL = Claim(1e-8, conditions="the damped eigenvectors well conditioned (no near-defective pair) "
                                       "and the poles resolved next to the stiffest ones (penalty links "
                                       "and mass ratios of 1e6 lose digits, and so does a slow resonance "
                                       "beside stiff modes: checked where its error estimate is largest)" + LIGHT)
"""``complex_modal``: one ``eig`` of the 2n-state modal form, its slow poles refined; its check also
visits where its a-posteriori estimate is largest (:func:`estimate_frequencies`)."""

WOODBURY = Claim(1e-8, exact=True, conditions="on the certified undamped modes (no damped eigenproblem, no "
                                              "truncation)" + LIGHT)
"""``woodbury``: the exact equations in the undamped modes, a bordered solve per frequency."""

SUBSPACE = Claim(1e-8, conditions="relative to each channel's peak, at its exact check solves between the "
                                  "interpolation points (sampled, not bounded, between them)")
"""``subspace``: :data:`vibss.linear.project.subspace.TOLERANCE`."""

STATESPACE = Claim(1e-8, conditions="viscous damping only; python-control on the scaled modal realisation")
"""``statespace``: SLICOT TB05AD (Hessenberg form, then a solve per frequency)."""

BASIS_ERROR = 3e-13
"""Relative error of a frequency of the certified undamped modes (eigh and its refinement): a modal
superposition carries it, amplified by ``1 / (2 zeta)`` at the peak of a mode of damping ratio zeta
(a 30-body chain with two dampers: damping ratios 4e-7, 7.6e-9 measured at the peaks)."""

LIGHT_CAP = 1e-4
"""The most a modal method's check allows for its lightly damped (or undamped) modes [-]."""

CHECK_POINTS = 3
"""Frequencies of a check besides its peaks: both ends of the band and the largest response."""

CHECK_PEAKS = 8
"""Most resonance peaks a check visits besides (:func:`check_frequencies`)."""

CHECK_ESTIMATE = 4
"""Largest local maxima of a method's own error estimate a check visits besides (:func:`estimate_frequencies`)."""

CHECK_OVER = 8
"""Most frequencies where the estimate exceeds the claim a check visits (the largest of them)."""

# cost model [s] (one core): the shipped values, read from vibss/data/costs.json (vibss.costs) where
# benchmarks/bench_costs.py re-measured them
K_DENSE_LU = constant("frequency.K_DENSE_LU", 3e-10)  # [s] per n^3 of one complex dense LU and solve
K_EIG = constant("frequency.K_EIG", 4.6e-10)  # [s] per N^3 of the complex-mode eig (N = 2n states)
K_SUPERPOSE = constant("frequency.K_SUPERPOSE", 4e-10)  # [s] per frequency x mode x channel of the superposition
K_REFINE = constant("frequency.K_REFINE", 3.5e-10)  # [s] per nk^3 of one complex mode's inverse iteration (two dense solves)
K_GEMM = constant("frequency.K_GEMM", 4e-10)  # [s] per frequency x mode x column of woodbury's weighted sums
K_BORDER = constant("frequency.K_BORDER", 2e-9)  # [s] per frequency x (r + 2)^3 of woodbury's bordered LU
NEAR_GUESS = 2        # near-resonant modes solved with the dampers per frequency, for the estimate
K_BASIS = constant("frequency.K_BASIS", 1.5e-9)  # [s] per n r^2 of the channel subspace's Gram-Schmidt and projection
K_REDUCED = constant("frequency.K_REDUCED", 1.5e-9)  # [s] per nf r^3 of its damped reduced responses (about four per call, dense LU)
K_HESSENBERG = constant("frequency.K_HESSENBERG", 1e-9)  # [s] per N^3 of the state space's Hessenberg form (N = 2n states)
K_TB05 = constant("frequency.K_TB05", 2e-9)  # [s] per frequency x N^2 of its Hessenberg solve
T_MOUNTS = constant("frequency.T_MOUNTS", 1.2e-3)  # [s] per frequency of the solve in the mounts' forces (penalty links: 12 DOF, 11 mounts)
K_COUPLING = constant("frequency.K_COUPLING", 3e-8)  # [s] per n k of a modal method's damping coupling and projections
T_MODAL = constant("frequency.T_MODAL", 5e-4)  # [s] fixed cost of the modal superposition's call
T_CALL = constant("frequency.T_CALL", 5e-3)  # [s] fixed cost of a modal method's call (its projections, screens and forms)
_C16 = 16.0           # [B] per complex number
_F8 = 8.0             # [B] per float


def check_frequencies(s: np.ndarray, raw: np.ndarray | None) -> np.ndarray:
    """Indices of the check frequencies: both ends of ``s``, the largest response of ``raw``, its
    :data:`CHECK_PEAKS` sharpest peaks (a local maximum over its lower neighbour: where a lightly
    damped mode amplifies a modal method's pole error) and as many deepest valleys (where a modal sum
    cancels: a penalty link's 12-DOF model, complex modes 4e-8 off at 32 kHz while the band's ends
    and largest response were within 1e-11)."""
    if raw is None:
        return np.unique([0, s.size // 2, s.size - 1])
    size = _sizes(raw)
    idx = [0, int(np.argmax(size)), s.size - 1]
    if s.size > 2:
        mid = size[1:-1]
        tiny = np.finfo(float).tiny
        for sign in (1.0, -1.0):            # peaks, then valleys (a modal sum cancels there)
            near = np.minimum(size[:-2], size[2:]) if sign > 0 else np.maximum(size[:-2], size[2:])
            at = np.flatnonzero((sign * (mid - size[:-2]) >= 0) & (sign * (mid - size[2:]) >= 0) & (mid > 0))
            if at.size:
                ratio = (mid[at] / np.maximum(near[at], tiny)) ** sign
                idx += (at[np.argsort(-ratio)[:CHECK_PEAKS]] + 1).tolist()
    return np.unique(idx)


def _sizes(raw: np.ndarray) -> np.ndarray:
    """(nf,) norm of each frequency's response without its entries that are not finite (one pass)."""
    sq = raw.real ** 2 + raw.imag ** 2 if np.iscomplexobj(raw) else raw ** 2
    return np.sqrt(np.einsum("ijk->k", np.where(np.isfinite(sq), sq, 0.0)))


def _where(s: np.ndarray) -> str:
    hz = np.abs(s) / (2 * np.pi)
    return f"{s.size} check frequencies ({', '.join(f'{x:.4g}' for x in hz)} Hz)" if s.size <= CHECK_POINTS else \
        f"{s.size} check frequencies from {hz.min():.4g} to {hz.max():.4g} Hz (band ends, largest response, peaks, valleys)"


def estimate_frequencies(estimate: np.ndarray, limit: float) -> np.ndarray:
    """Indices where a method's error estimate says to check: its :data:`CHECK_ESTIMATE` largest
    local maxima, and the :data:`CHECK_OVER` frequencies where it exceeds ``limit`` most (where the
    estimate itself exceeds the claim the check must measure: a miss beside a slow resonance sampled
    on its flank, 1.1e-5 on the graded chain, is no local maximum of either the response or the
    estimate).

    Parameters
    ----------
    estimate : (nf,) ndarray
        Relative error estimate at each frequency [-].
    limit : float
        What the claim allows [-].

    Returns
    -------
    (k,) int ndarray
    """
    e = np.where(np.isnan(estimate), np.inf, np.asarray(estimate, float))
    if e.size <= 2:
        return np.arange(e.size)
    pad = np.concatenate([[-np.inf], e, [-np.inf]])
    peak = np.flatnonzero((e >= pad[:-2]) & (e >= pad[2:]))
    peak = peak[np.argsort(-e[peak], kind="stable")]
    above = np.flatnonzero(e > limit)
    over = above[np.argsort(-e[above], kind="stable")[:CHECK_OVER]]
    return np.unique(np.concatenate([peak[:CHECK_ESTIMATE], over])).astype(int)


def against_exact(plant: Plant, s: np.ndarray, raw: np.ndarray, limit: float, every: bool = False,
                  estimate: np.ndarray | None = None, basis: ModalBasis | None = None) -> Check:
    """Largest relative error of ``raw`` against the one exact solve (:func:`vibss.linear.solve.exact.response`)
    at :func:`check_frequencies` (relative to each frequency's response).

    Parameters
    ----------
    plant : Plant
    s : (nf,) complex ndarray
        Laplace points [rad/s].
    raw : (p, m, nf) complex ndarray
        The method's answer.
    limit : float
        What its claim allows [-].
    every : bool
        Measure at every frequency (the bound a named method's miss states: the exact solve's cost).
    estimate : (nf,) ndarray or None
        The method's error estimate: its largest places are checked too (:func:`estimate_frequencies`).
    basis : ModalBasis or None
        The undamped modes, when known: with classical damping the reference comes from them,
        refined and certified by its residual (:func:`~vibss.linear.solve.from_modes.reference`).

    Returns
    -------
    Check
    """
    idx = np.arange(s.size) if every else check_frequencies(s, raw)
    if estimate is not None and not every:
        idx = np.union1d(idx, estimate_frequencies(estimate, limit))
    exact, how = reference(plant, s[idx], basis, limit)
    with np.errstate(invalid="ignore"):
        diff = raw[:, :, idx] - exact
    both_inf = np.isinf(raw[:, :, idx]) & np.isinf(exact)
    diff = np.where(both_inf, 0.0, diff)
    size = np.linalg.norm(np.where(np.isfinite(exact), exact, 0.0), axis=(0, 1))
    with np.errstate(invalid="ignore"):
        err = np.linalg.norm(diff, axis=(0, 1)) / np.maximum(size, np.finfo(float).tiny)
    err = np.where(np.isnan(err), np.inf, err)
    where = f"every one of the {s.size} frequencies" if every and s.size > CHECK_POINTS + CHECK_PEAKS else _where(s[idx])
    if estimate is not None and not every:
        where += " and where its error estimate is largest"
    return Check(float(err.max()), limit, where + how)


def backward_error(plant: Plant, s: np.ndarray, limit: float, backend: str = "auto") -> Check | None:
    """Normwise backward error of the exact full-state solve at ``s`` (a few points).

    ``eta = ||F - A(s) x||_F / (||A(s)||_F ||x||_F + ||F||_F)``, ``A(s) = K + iH + sC + s^2 M``, ``x``
    by :func:`vibss.linear.solve.exact.states` with the method's ``backend``, the residual by products
    with the plant's matrices, ``||A(s)||_F`` bounded above by the terms' norms' sum (``eta`` low by at
    most 2). None for frequency-dependent mounts (their internal states are not in ``A``). The refined
    solve in the mounts' forces records it as it solves (:func:`~vibss.linear.solve.refine.record_backward_error`): read.

    Parameters
    ----------
    plant : Plant
    s : (k,) complex ndarray
        Laplace points [rad/s], ``s != 0``.
    limit : float
        What the claim allows [-].
    backend : str
        The exact solve's backend (``direct``: dense, ``sparse``: sparse).

    Returns
    -------
    Check or None
    """
    if plant.branches is not None or plant.n == 0:
        return None
    where = _where(s) + ", backward error of the full-state solve"
    f = np.asarray(forcing(plant, s, zfactor(s, plant.order)))
    if (kept := recorded_backward_errors(plant, s, f)) is not None:    # the 60,000-DOF tower's 18 solves: 12 s
        etas, stall = kept
        where += " (its residual in the mounts' form, as it solved)"
        if stall > 0:                       # exact to A(s)'s conditioning there, not to rounding
            where += f"; its refinement stalled at A(s)'s conditioning, last correction {stall:.1e}"
        return Check(max(float(etas.max(initial=0.0)), stall), limit, where)
    x, singular = states(plant, s, backend=backend)  # the method's own solve; no call of this module after it
    ax = assembled_times(plant, s, x)
    eta = max((backward_error_of(plant, complex(s[j]), f[j], x[j], ax[j]) for j in np.flatnonzero(~singular)),
              default=0.0)
    return Check(eta, limit, where)


def limit(method: Any, plant: Plant, basis: ModalBasis | None) -> float:
    """What ``method``'s claim allows on this plant [-]: its tolerance, raised for a method that
    superposes the undamped modes to ``BASIS_ERROR / (2 zeta_min)`` (at most :data:`LIGHT_CAP`)
    when its lightest damped mode has the damping ratio ``zeta_min``; inf without a claim."""
    claim = method.claim
    if claim is None:
        return float(np.inf)
    tol = claim.tolerance
    if not method.needs_basis or basis is None or not np.any(~basis.rigid):
        return tol
    gam, hys = projected_damping(plant, basis)
    el = ~basis.rigid
    w = np.sqrt(np.maximum(basis.omega2[el], np.finfo(float).tiny))
    zeta = (np.abs(np.diag(gam)[el]) + np.abs(np.diag(hys)[el]) / w) / (2 * w)
    low = float(zeta.min())
    return max(tol, min(LIGHT_CAP, BASIS_ERROR / (2 * low) if low > 0 else np.inf))


def check(method: Any, plant: Plant, s: np.ndarray, raw: np.ndarray, own: float | None = None,
          basis: ModalBasis | None = None, estimate: np.ndarray | None = None) -> Check | None:
    """The a-posteriori check of ``method``'s answer ``raw`` (module docstring).

    Parameters
    ----------
    method : FrequencyMethod
    plant : Plant
    s : (nf,) complex ndarray
        Laplace points [rad/s].
    raw : (p, m, nf) complex ndarray
        The answer.
    own : float or None
        The error a self-checked method measured itself (``subspace``), None if it has none.
    basis : ModalBasis or None
        The undamped modes (a modal method's limit reads their damping, :func:`limit`).
    estimate : (nf,) ndarray or None
        The method's own a-posteriori error estimate: the check also solves where it is largest
        (:func:`estimate_frequencies`).

    Returns
    -------
    Check or None
    """
    allowed = limit(method, plant, basis)
    if method.self_checked:
        return None if own is None else Check(own, allowed, "its own exact solves between the interpolation points")
    if method.exact:
        return backward_error(plant, s[check_frequencies(s, raw)], min(allowed, BACKWARD),
                              {"direct": "dense", "sparse": "sparse"}.get(method.name, "auto"))
    return against_exact(plant, s, raw, allowed, estimate=estimate, basis=basis)


def woodbury_rank(plant: Plant, basis: ModalBasis | None) -> int:
    """Columns of woodbury's update: the non-classical dampers' rank plus the branches (every
    damper counted when the basis is not known: an upper bound)."""
    r = plant.branches.r if plant.branches is not None else 0
    if basis is None or not classical_damping(plant, basis, projected_damping(plant, basis))[0]:
        r += damping_rank(plant)
    return r


def _floor(n: int) -> float:
    """:func:`vibss.linear.solve.banded.seconds_floor`, from its constants (no call down a layer)."""
    return _T_FREQ + _K_BAND * n


def _mounts(plant: Plant) -> int:
    """Unknowns the solve in the mounts' forces adds (3 per mount), 0 where the assembled matrices
    are solved (:func:`vibss.linear.solve.exact.states`' ``form="auto"``: the mounts' form where the
    stiffness ratio passes ``MOUNTS_RATIO``, and below a frequency where the mounts leave a motion
    free, a mechanism: costed as if at every frequency, 6x under the measured time on the 150-DOF
    mechanism chain otherwise)."""
    mf = plant.mounts
    if plant.branches is not None or mf is None or not mf.matches(plant):
        return 0
    if mf.stiffness_ratio <= MOUNTS_RATIO and mf.inertia_w2 <= 0:
        return 0                       # (a free motion: the mounts' form below a frequency, costed at all)
    return int(mf.B.shape[0])


def _per_mounts(plant: Plant, mounts: int) -> float:
    """Seconds of one solve in the mounts' forces (``mounts`` unknowns added): dense LU up to
    :data:`~vibss.linear.solve.backends.MOUNTS_DENSE_MAX` unknowns, else SuperLU of the assembled
    matrix refined in the mounts' form, linear in that LU's fill (unscaled above that size)."""
    size = plant.n + mounts
    if size <= MOUNTS_DENSE_MAX:
        return T_MOUNTS + K_DENSE_LU * float(size) ** 3
    st = plant.cached("band structure", lambda: structure(plant))
    # SuperLU's formula on the assembled LU's fill (a band's when the plant bands), scaled by its own
    # fitted "solve.mounts" (cost_direct), not "solve.superlu" (60,000-DOF tower: 1.5x per nonzero)
    if st.fill:
        return superlu_seconds(st.fill, st.flops)
    # a band's with partial pivoting: L b below, U 2 b above the diagonal, 2 b^2 multiply-adds a pivot
    return superlu_seconds(plant.n * (3 * st.band + 1), 2.0 * plant.n * float(st.band) ** 2)


def _modes(plant: Plant, basis: ModalBasis | None) -> int:
    return plant.n if basis is None else int(basis.phi.shape[1])


def _pm(plant: Plant) -> tuple[int, int]:
    return len(plant.outputs), len(plant.inputs)


def cost_direct(plant: Plant, nf: int, basis: ModalBasis | None = None) -> Cost:
    """One dense LU per frequency, batched by 64 MB chunks: ``nf n^3`` and a fixed cost per
    frequency (:func:`vibss.linear.solve.banded.seconds_floor`); the chunk, its LU copy and the
    solutions."""
    n = plant.n + (plant.branches.r if plant.branches is not None else 0)
    p, m = _pm(plant)
    chunk = max(1, min(nf, int(_CHUNK_BYTES // (_C16 * max(n, 1) ** 2))))
    mounts = _mounts(plant)
    if mounts:
        size = n + mounts               # dense LU up to MOUNTS_DENSE_MAX unknowns, else SuperLU's fill
        if size <= MOUNTS_DENSE_MAX:
            return Cost(scale("frequency.direct") * nf * _per_mounts(plant, mounts),
                        _C16 * (2 * size**2 + nf * n * m + nf * p * m))
        # the assembled LU refined (the saddle system's only where it does not converge), as cost_sparse
        st = plant.cached("band structure", lambda: structure(plant))
        lu = 40 * sum(int(getattr(v, "nnz", 0)) for v in st.parts.values())
        return Cost(scale("solve.mounts") * nf * _per_mounts(plant, mounts), _C16 * (lu + nf * n * m + nf * p * m))
    return Cost(scale("frequency.direct") * nf * (_floor(n) + K_DENSE_LU * float(n) ** 3),
                _C16 * (2 * chunk * n * n + nf * n * m + nf * p * m))


def cost_sparse(plant: Plant, nf: int, basis: ModalBasis | None = None) -> Cost:
    """One banded LU (or SuperLU) per frequency (:func:`vibss.linear.solve.banded.structure`); peak
    memory the band's LU fill ``n (3 b + 1)`` (or ``nnz`` times a fill of 20 for SuperLU) and the
    solutions."""
    mounts = _mounts(plant)
    if mounts:                          # solved in the mounts' forces, as direct
        return cost_direct(plant, nf)
    st = plant.cached("band structure", lambda: structure(plant))
    n = plant.n
    p, m = _pm(plant)
    if st.banded:
        fill = n * (3 * st.band + 1)
    else:
        fill = 20 * sum(int(getattr(v, "nnz", 0)) for v in st.parts.values())
    return Cost(nf * st.seconds_per_frequency, _C16 * (2 * fill + nf * n * m + nf * p * m))


def cost_modal(plant: Plant, nf: int, basis: ModalBasis | None = None) -> Cost:
    """The superposition ``nf k p m`` over ``k`` modes; its (nf, k) transfer functions twice."""
    k = _modes(plant, basis)
    p, m = _pm(plant)
    mf = plant.mounts                       # its static correction: one solve in the mounts' forces
    mounts = _mounts(plant) if mf is not None and mf.stiffness_ratio > MOUNTS_RATIO else 0
    return Cost(scale("frequency.modal") * (T_MODAL + nf * _floor(0) + K_SUPERPOSE * nf * k * p * m
                                            + K_COUPLING * plant.n * k + (_per_mounts(plant, mounts) if mounts else 0.0)),
                _C16 * (3 * nf * k + k * p * m + nf * p * m))


def cost_complex_modal(plant: Plant, nf: int, basis: ModalBasis | None = None) -> Cost:
    """The ``eig`` of the 2k-state modal form with its screen and refinement (four times ``eig``'s
    ``(2k)^3``: 0.029 s measured at 120 DOF) and the superposition over 2k poles; memory the matrix,
    its eigenvectors, a copy and LAPACK's work (4 (2k)^2 complex)."""
    k = _modes(plant, basis)
    p, m = _pm(plant)
    big = 2 * k
    return Cost(scale("frequency.complex_modal") * (T_CALL + nf * _floor(0) + 4 * K_EIG * float(big) ** 3
                                                    + K_SUPERPOSE * nf * big * p * m),
                _C16 * (4 * big * big + 3 * nf * big + big * p * m + nf * p * m))


def cost_woodbury(plant: Plant, nf: int, basis: ModalBasis | None = None) -> Cost:
    """Weighted sums over ``k`` modes and the bordered LUs of order ``r + q`` (``r``
    :func:`woodbury_rank`); peak memory, from :func:`vibss.frequency.lowrank.woodbury`'s arrays: the
    Gram's pair products ``k r (r + 1) / 2`` floats, its real and imaginary halves and the (nf, r, r)
    complex ``U_F^T D_F^-1 U_F`` (``2.5 nf r^2`` complex in all: 332 MB measured against 326 MB
    estimated on a 120-DOF chain with every mount damped, 100 frequencies), ``U_F^T D_F^-1 P_F`` (nf, r, M), a
    chunk of 64 bordered systems and their LU, and the (nf, k) weights."""
    from .lowrank import CHUNK

    k = _modes(plant, basis)
    p, m = _pm(plant)
    r = woodbury_rank(plant, basis)
    pm = p * m
    seconds = scale("frequency.woodbury") * (T_MODAL + K_COUPLING * plant.n * k + nf * _floor(0) + K_GEMM * nf * k * (pm + r * (p + m) + r * r / 2)
               + K_BORDER * nf * (r + NEAR_GUESS) ** 3)
    chunk = min(nf, CHUNK)
    q = r + NEAR_GUESS
    peak = (_F8 * k * r * (r + 1) / 2 + 2.5 * _C16 * nf * r * r + _C16 * nf * r * m
            + _C16 * 3 * chunk * q * q + _C16 * 4 * nf * k + _C16 * 2 * nf * pm)
    return Cost(seconds, peak)


def subspace_size(plant: Plant) -> int:
    """Vectors of the channel subspace's starting basis: ``N_SHIFTS MOMENTS`` times the input
    vectors and, when there are at most ``TWO_SIDED_MAX`` outputs, the output vectors too."""
    p, m = _pm(plant)
    return N_SHIFTS * MOMENTS * (m + (p if p <= TWO_SIDED_MAX else 0))


def cost_subspace(plant: Plant, nf: int, basis: ModalBasis | None = None, projection: bool = False) -> Cost:
    """About ``3 N_SHIFTS`` exact solves (a factorisation per shift, as many checks) plus the basis
    work ``n r^2`` (``r = N_SHIFTS MOMENTS`` times the input and output vectors) and, damped, ``nf
    r^3`` for the small plant's dense solves; memory the basis (n, 2r) as it grows, a factorisation
    and the small plant's batched dense solves, ``nf (2r)^2`` complex (141 MB measured, 131 MB
    estimated: a 600-DOF chain, 3 channels, 100 frequencies).
    Where that basis would hold half as many vectors as the plant has DOFs the sparse solve answers
    instead (:func:`vibss.frequency.kernels.subspace`), and so is its cost, unless ``projection``."""
    r = subspace_size(plant)
    if 2 * r >= plant.n and not projection:  # no reduction: the exact sparse solve answers instead
        return cost_sparse(plant, nf)
    st = plant.cached("band structure", lambda: structure(plant))
    p, m = _pm(plant)
    mounts = _mounts(plant)
    per = _per_mounts(plant, mounts) if mounts else st.seconds_per_frequency
    seconds = 3 * N_SHIFTS * per + K_BASIS * plant.n * r * r
    if nonzero(plant.C) or nonzero(plant.H):
        seconds += K_REDUCED * nf * float(r) ** 3
    seconds *= scale("frequency.subspace")
    one = cost_sparse(plant, 1)
    grown = 2 * r                       # the basis grows by its added checks (144 -> 284 vectors measured)
    return Cost(seconds, _F8 * 3 * plant.n * grown + _C16 * nf * grown * grown + one.bytes + _C16 * nf * p * m * 2)


def cost_statespace(plant: Plant, nf: int, basis: ModalBasis | None = None) -> Cost:
    """The 2k-state realisation: its Hessenberg form ``(2k)^3`` and a Hessenberg solve ``(2k)^2``
    per frequency; memory a few (2k)^2 matrices."""
    big = 2 * _modes(plant, basis)
    p, m = _pm(plant)
    return Cost(scale("frequency.statespace") * (T_CALL + K_HESSENBERG * float(big) ** 3 + K_TB05 * nf * big * big * m),
                _C16 * 6 * big * big + _C16 * nf * p * m)


class _Trial:
    """One frequency response's trial of methods by :func:`vibss.methods.decide`: how each runs, is
    checked and is costed (bound methods, so the decider's calls stay in this module)."""

    def __init__(self, plant: Plant, s: np.ndarray, basis: ModalBasis | None, auto: bool):
        self.plant, self.s, self.basis, self.auto = plant, s, basis, auto
        self.own: dict[str, tuple[str, float | None]] = {}
        self.estimate: dict[str, np.ndarray] = {}

    def run(self, m: Any) -> Any:
        if getattr(m, "estimated", None) is not None:     # its error estimate steers its check
            raw, self.estimate[m.name] = m.estimated(self.plant, self.s, self.basis)
            return raw
        raw = m.kernel(self.plant, self.s, self.basis)
        if m.self_checked:              # (response, the note of its own exact checks, their error)
            raw, note, err = raw if len(raw) == 3 else (*raw, None)
            self.own[m.name] = (note, err)
        return raw

    def check(self, m: Any, raw: Any) -> Check | None:
        found = check(m, self.plant, self.s, raw, self.own.get(m.name, ("", None))[1], self.basis,
                      self.estimate.get(m.name))
        if found is not None and not found.ok and not self.auto and not m.exact and not m.self_checked:
            return against_exact(self.plant, self.s, raw, found.limit, every=True)   # the bound everywhere
        return found

    def cost(self, m: Any) -> Cost | None:
        return m.cost(self.plant, self.s.size, self.basis) if m.cost is not None else None


SLOWER = 2.0
"""A named method estimated this many times slower than another that applies says so (:func:`slower`)."""


def slower(plant: Plant, nf: int, basis: ModalBasis | None, named: Any, others: list[Any]) -> str:
    """What a named method costs against the cheapest other method that applies (said in the result's
    note, where a named method within its claim gives no warning), when it is
    estimated at least :data:`SLOWER` times slower (``sparse`` and ``direct`` on a 600-DOF lattice
    or random graph with classical damping: 2-5x ``modal``), else ``""``. The estimates are the
    cost models above, their constants measured by benchmarks/bench_costs.py.

    Parameters
    ----------
    plant : Plant
    nf : int
        Number of frequencies.
    basis : ModalBasis or None
        The undamped modes.
    named : FrequencyMethod
        The method the user named.
    others : list of FrequencyMethod
        The other methods that apply.

    Returns
    -------
    str
    """
    if named.cost is None or not others:
        return ""
    mine = named.cost(plant, nf, basis).seconds
    rivals = {m.name: m.cost(plant, nf, basis).seconds for m in others if m.cost is not None}
    if not rivals:
        return ""
    best = min(rivals, key=rivals.__getitem__)
    if mine < SLOWER * rivals[best]:
        return ""
    return (f"method {named.name!r} is estimated {mine / rivals[best]:.2g}x slower than {best!r} here "
            f"({mine:.2g} s against {rivals[best]:.2g} s)")


def settle(plant: Plant, s: np.ndarray, basis: ModalBasis | None, order: Sequence[Any], auto: bool,
           others: list[Any]) -> tuple[Decision[Any], dict[str, tuple[str, float | None]]]:
    """Run the frequency methods of ``order`` through :func:`vibss.methods.decide`.

    Parameters
    ----------
    plant : Plant
    s : (nf,) complex ndarray
        Laplace points [rad/s].
    basis : ModalBasis or None
        The undamped modes.
    order : list of FrequencyMethod
        ``auto``'s candidates, or the one named method.
    auto : bool
        Whether the user asked for ``"auto"``.
    others : list of FrequencyMethod
        Methods that also apply (named when a named method passes the memory guard).

    Returns
    -------
    Decision
        The method that answered, its answer and check, and what was tried.
    dict of str to (str, float or None)
        A self-checked method's note and error by name.
    """
    trial = _Trial(plant, s, basis, auto)
    if not auto and len(order) == 1:
        word = slower(plant, s.size, basis, order[0], others)
        if word:            # said in the note; a warning is kept for a missed claim (a named method
            trial.own[order[0].name] = (f"{word}; method='auto' picks by these estimates", None)  # within it is silent)
    dec = decide(order, trial.run, where="frequency_response", auto=auto, check=trial.check, cost=trial.cost,
                 others=others)
    return dec, trial.own
