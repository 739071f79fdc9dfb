"""Reduction methods: one kernel signature, typed results, the registry and ``auto``'s choice.

Every method, built-in or a user's callable, is ``kernel(plant, scope, options) -> Reduced``:
``plant`` the full plant cut to the scope's signals (scipy.sparse ``M, C, K, H`` for a method
with :attr:`ReductionMethod.sparse`), ``scope`` the :class:`~vibss.reduction.scope.Scope`,
``options`` the :class:`ReduceOptions` given to :func:`vibss.reduction.reduce`; the
:class:`Reduced` it returns becomes the :class:`~vibss.reduction.api.Reduction`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import control
import numpy as np

from ..errors import AnalysisError
from ..linear.plant.plant import Plant
from ..linear.plant.labels import control_name
from ..linear.statespace import NamedStateSpace, statespace
from ..methods import Claim, Cost, Method, callable_name, resolve
from .krylov import as_sparse, krylov, prune_sparse
from .prune import Removal, frf, prune_dofs, prune_modes
from .truncation import truncate
from .scope import Scope

__all__ = ["ReductionMethod", "ReduceOptions", "Reduced", "METHODS", "choose", "resolve_method", "reduction_cost",
           "BALANCED_MAX_STATES", "KRYLOV_MIN_DOF", "MODE_PRUNE_MAX"]

BALANCED_MAX_STATES = 2000
"""Largest state count given to balanced truncation (dense Gramians)."""

KRYLOV_MIN_DOF = 500
"""``"auto"`` uses ``"krylov"`` above this many DOFs. Measured on a 100-body chain (600 DOF, band
with 25 modes, tolerance 1e-6, single thread): ``"krylov"`` 0.07 s, ``"modal"`` 3.8 s (dense
``eigh`` plus its mode search), both within tolerance; on a 1,000-body chain the modal route misses
the tolerance (the lowest modes are localised away from the input, benchmarks/bench_reduction.py).
Below, ``"modal"`` costs well under a second and gives interpretable modal coordinates."""

MODE_PRUNE_MAX = 3000
"""Largest number of DOFs for which zero-participation modes are searched (dense eigh)."""


@dataclass(frozen=True)
class ReduceOptions:
    """The method options of :func:`vibss.reduction.reduce`, passed to every method.

    Attributes
    ----------
    max_modes : int or None
        Upper limit on kept modes (``"modal"``).
    order : int or None
        States to keep (``"balanced"``); None: the fewest meeting the tolerance.
    residual : {"vectors", "static"}
        How ``"modal"`` accounts for truncated modes.
    n_grid : int
        Frequencies of ``"modal"``'s error estimate over the band.
    """

    max_modes: int | None = None
    order: int | None = None
    residual: str = "vectors"
    n_grid: int = 200


@dataclass(frozen=True, eq=False)
class Reduced:
    """What a reduction method returns (the method-specific part of a Reduction).

    Attributes
    ----------
    plant : Plant or None
        The reduced plant (None when the method gives a state space instead).
    system : NamedStateSpace or None
        The reduced state space (``"balanced"``).
    removed : tuple of Removal
        What was removed and why.
    estimate : float
        Estimated relative error over the band [-] (0 for exact methods).
    estimate_kind : str
        ``"exact"``, ``"bound ..."`` or ``"estimate ..."``.
    correction : str
        Which outputs/inputs get a static correction.
    kept_hz : (k,) ndarray
        Natural frequencies of the kept modes [Hz].
    hsv : (ns,) ndarray or None
        Hankel singular values (``"balanced"``).
    hsv_bound : float or None
        ``2 sum(discarded HSV)`` (``"balanced"``).
    io_scale : tuple of (p,) and (m,) ndarray, or None
        Output and input scales of the balanced system.
    notes : tuple of str
        Caveats.
    details : dict
        Method-specific figures (``"krylov"``).
    """

    plant: Plant | None
    system: NamedStateSpace | None = None
    removed: tuple[Removal, ...] = ()
    estimate: float = 0.0
    estimate_kind: str = "exact"
    correction: str = ""
    kept_hz: np.ndarray = field(default_factory=lambda: np.zeros(0))
    hsv: np.ndarray | None = None
    hsv_bound: float | None = None
    io_scale: tuple[np.ndarray, np.ndarray] | None = None
    notes: tuple[str, ...] = ()
    details: dict[str, Any] = field(default_factory=dict)


@dataclass(frozen=True)
class ReductionMethod(Method):
    """A reduction method: ``kernel(plant, scope, options: ReduceOptions) -> Reduced``.

    Attributes
    ----------
    sparse : bool
        Works on scipy.sparse ``M, C, K, H`` (given a Model, the full plant is assembled sparse;
        the only kind of method a sparse plant takes).
    gives_plant : bool
        Returns a reduced Plant (False: a state space, :attr:`Reduced.system`).
    """

    sparse: bool = False
    gives_plant: bool = True


def _floor(peak: np.ndarray) -> np.ndarray:
    """(p, m) reference magnitude of each channel: its output's largest peak over the scope's inputs
    (over all outputs, for an output that does not respond)."""
    row = peak.max(axis=1, keepdims=True)
    row = np.where(row > 0, row, max(float(peak.max()), 1e-300))
    return np.broadcast_to(row, peak.shape)


def check_grid(scope: Scope, n_points: int, resonances: np.ndarray) -> np.ndarray:
    """Verification grid [rad/s]: ``n_points`` over the band plus points beside its resonances.

    The resonances themselves are left out (an undamped response is infinite there); the grid
    starts at :meth:`Scope.low_end` (``resonances`` with zeros for rigid-body modes).
    """
    w1, w2 = scope.band_rad
    lo = scope.low_end(resonances)
    w = np.linspace(lo, w2, int(n_points))
    r = resonances[(resonances >= lo) & (resonances <= w2)]
    extra = np.concatenate([r * (1 - 2e-4), r * (1 + 2e-4), r * (1 - 1e-3), r * (1 + 1e-3)])
    return np.unique(np.concatenate([w, extra[(extra >= lo) & (extra <= w2)]]))


def _states(p: Plant) -> int:
    return 2 * p.n + int(np.sum(np.maximum(p.order, 0)))


def _prune(p: Plant) -> tuple[Plant, list[Removal], list[str]]:
    p1, rem = prune_dofs(p)
    notes: list[str] = []
    if p1.n <= MODE_PRUNE_MAX:
        p2, rem2, _ = prune_modes(p1)
        return p2, rem + rem2, notes
    notes.append(f"zero-participation modes not searched ({p1.n} DOFs > {MODE_PRUNE_MAX})")
    return p1, rem, notes


def _method_prune(p: Plant, scope: Scope, options: ReduceOptions) -> Reduced:
    p1, rem, notes = _prune(p)
    return Reduced(plant=p1, removed=tuple(rem), notes=tuple(notes))


def _method_modal(p: Plant, scope: Scope, options: ReduceOptions) -> Reduced:
    max_modes, residual, n_grid = options.max_modes, options.residual, options.n_grid
    p1, rem = prune_dofs(p)
    if p1.n == 0:
        raise AnalysisError("nothing is left to reduce after pruning")
    w1, w2 = scope.band_rad
    tr = truncate(p1, scope, n_grid, max_modes=max_modes, residual=residual)
    if tr.n_kept < p1.n:
        why = "truncated, accounted for by the residual correction"
        if tr.dropped_in_band:
            why += (f"; {tr.dropped_in_band} of them in the band, with negligible participation "
                    "(e.g. localised away from the inputs and outputs)")
        rem = rem + [Removal("modes", (f"{p1.n - tr.n_kept} modes from {tr.first_truncated_hz:.4g} Hz up",),
                             why, exact=False)]
    corr = VECTORS_NOTE if residual == "vectors" else STATIC_NOTE
    return Reduced(plant=tr.plant, removed=tuple(rem), estimate=float(tr.estimate),
                   estimate_kind=tr.bound_kind, correction=corr, kept_hz=np.asarray(tr.kept_hz, float),
                   notes=tuple(tr.notes))


def _method_balanced(p: Plant, scope: Scope, options: ReduceOptions) -> Reduced:
    order = options.order
    try:
        import slycot  # noqa: F401  (optional dependency of python-control)
    except ImportError:
        raise AnalysisError("method 'balanced' needs slycot: python-control's minreal, hsvd and balred "
                            "are SLICOT-only (pip install slycot); use method='modal' without it") from None
    p1, rem, notes = _prune(p)
    if np.any(p1.H) or np.any(p1.Hz):
        raise AnalysisError("method 'balanced' cannot represent hysteretic damping (loss factors); use 'modal'")
    if _states(p1) > BALANCED_MAX_STATES:
        raise AnalysisError(f"method 'balanced': {_states(p1)} states is too many for dense Gramians "
                            f"(limit {BALANCED_MAX_STATES}); reduce with method='modal' first and balance "
                            "its plant: reduce(reduce(model, scope, 'modal').plant, scope, 'balanced')")
    sys = statespace(p1)
    if np.any(np.linalg.eigvals(sys.A).real >= 0):
        raise AnalysisError("method 'balanced' needs an asymptotically stable system (every mode damped, "
                            "no rigid-body mode, no velocity/acceleration input integrators); use 'modal'")
    # scale channels so that |H_ij| / (a_i b_j) is about 1 at each channel's peak in the band
    w1, w2 = scope.band_rad
    peak = _floor(np.abs(frf(p1, 1j * check_grid(scope, 200, np.zeros(0)))).max(axis=2))
    a = peak.max(axis=1)
    b = (peak / a[:, None]).max(axis=0)
    ratio = float((a[:, None] * b[None, :] / peak).max())     # per-channel relative <= ratio * 2 sum(sigma)
    scaled = control.ss(sys.A, sys.B / b[None, :], sys.C / a[:, None], sys.D / a[:, None] / b[None, :])
    n0 = scaled.nstates
    sysm = control.minreal(scaled, verbose=False)
    if sysm.nstates < n0:
        rem.append(Removal("states", (f"{n0 - sysm.nstates} states",),
                           "uncontrollable or unobservable (control.minreal)"))
    hsv = np.real(np.asarray(control.hsvd(sysm)))      # SLICOT may leave round-off imaginary parts
    tail = np.r_[2 * np.cumsum(hsv[::-1])[::-1], 0.0]      # tail[r] = 2 sum_{i >= r} sigma_i
    if order is None:
        order = int(np.argmax(tail * ratio <= scope.tolerance))
    order = max(1, min(int(order), sysm.nstates))
    red = control.balred(sysm, order, method="truncate") if order < sysm.nstates else sysm
    red = NamedStateSpace(red.A, red.B * b[None, :], red.C * a[:, None], red.D * a[:, None] * b[None, :],
                          inputs=[control_name(u) for u in p1.inputs],
                          outputs=[control_name(y) for y in p1.outputs],
                          name=control_name(p1.name) + ":balanced")
    if order < sysm.nstates:
        rem.append(Removal("states", (f"{sysm.nstates - order} balanced states",),
                           f"Hankel singular values {hsv[order]:.3g} and below", exact=False))
    return Reduced(plant=None, system=red, removed=tuple(rem), hsv=hsv, hsv_bound=float(tail[order]),
                   io_scale=(a, b), estimate=float(tail[order] * ratio),
                   estimate_kind="bound: |dH_ij| <= a_i b_j 2 sum(discarded HSV) of the channel-scaled "
                                 "system, at every frequency",
                   notes=tuple(notes + ["a StateSpace, not a Plant: use it with python-control"]))


def _method_krylov(p: Plant, scope: Scope, options: ReduceOptions) -> Reduced:
    p1, rem = prune_sparse(as_sparse(p))
    kb = krylov(p1, scope.band_rad, scope.tolerance)
    rem = rem + [Removal("dofs", (f"{p1.n} DOFs -> {kb.plant.n} Krylov vectors",),
                         "Galerkin projection on a rational Krylov basis of the inputs/outputs", exact=False)]
    kind = (f"sampled: exact error (complex sparse LU) at the last round's {kb.history[-1][1]} check "
            "frequencies (midpoints between interpolation frequencies, significant Ritz resonances), "
            f"relative per output; basis grown until below {0.5:g} x tolerance")
    details = {"basis_size": kb.plant.n, "shifts_hz": kb.shifts_hz, "moments": kb.moments,
               "interpolation_hz": kb.interpolation_hz, "check_hz": kb.check_hz,
               "history": [list(h) for h in kb.history], "two_sided": kb.two_sided, "timings": kb.timings}
    return Reduced(plant=kb.plant, removed=tuple(rem), estimate=float(kb.estimate), estimate_kind=kind,
                   kept_hz=np.asarray(kb.ritz_hz[kb.ritz_hz <= scope.f2], float), notes=tuple(kb.notes),
                   details=details,
                   correction="none needed: the basis holds the static response when the band starts at 0 Hz"
                   if scope.f1 == 0 else "")


VECTORS_NOTE = ("residual static vectors of the truncated modes for every forcing term (F, Kz, Cz, Mz) "
                "appended as DOFs 'residual<k>' (Galerkin projection): the static response is exact and "
                "every output type (displacement, velocity, acceleration, mount forces) is corrected")

STATIC_NOTE = ("Pf/Pz feedthrough of the residual flexibility of the truncated modes on the displacement-"
               "type output terms (Oq: displacements, deflections, spring part of mount/ground forces) "
               "for force and prescribed-displacement forcing (F, Kz); velocity/acceleration output terms "
               "(Ov, Oa) and damper/mass coupling of motion inputs (Cz, Mz) are not corrected")


_SCOPE = Claim(1e-3, conditions="the scope's tolerance (1e-3 unless the scope says otherwise), by the method's "
               "own estimate of the error over the band; reduce(verify=True) measures it")

METHODS: dict[str, ReductionMethod] = {m.name: m for m in (
    ReductionMethod("prune", _method_prune, exact=True, claim=Claim(
                        3e-8, exact=True, conditions="what it removes carries nothing in the scope (the "
                        "exact solve's rounding remains: 1.4e-8 measured on mass ratios of 1e6)"),
                    summary="remove what no input excites or no output sees (exact)"),
    ReductionMethod("modal", _method_modal, claim=_SCOPE,
                    summary="pruning, then modal truncation with residual correction"),
    ReductionMethod("balanced", _method_balanced, claim=_SCOPE, gives_plant=False,
                    summary="pruning, then balanced truncation of the modal state space"),
    ReductionMethod("krylov", _method_krylov, claim=_SCOPE, sparse=True,
                    summary="sparse pruning, then a rational Krylov Galerkin projection"),
)}
"""Reduction methods by name (``"auto"``: :func:`choose`)."""


def choose(n: int, sparse_plant: bool) -> tuple[str, str]:
    """``auto``'s method for ``n`` DOFs (and whether the plant is sparse), and why.

    Parameters
    ----------
    n : int
        DOFs of the full model.
    sparse_plant : bool
        The plant's matrices are scipy.sparse.

    Returns
    -------
    name, reason : str
    """
    if sparse_plant:
        return "krylov", "auto: sparse plant: krylov"
    name = "krylov" if n > KRYLOV_MIN_DOF else "modal"
    return name, f"auto: {n} DOFs {'>' if n > KRYLOV_MIN_DOF else '<='} {KRYLOV_MIN_DOF}: {name}"


K_EIGH = 1.0e-10
"""[s] per n^3 of the dense symmetric eigen solve (LAPACK dsyevd, one core), as the modal FRF's."""
K_LU = 3e-10
"""[s] per n^3 of one complex dense LU and solve (one check frequency of the full plant)."""
CHECKS = 60
"""Check frequencies a dense truncation or pruning solves the full plant at (24 + 5 over the band,
and the flanks of a few resonances)."""


def reduction_cost(method: ReductionMethod, n: int, channels: int) -> Cost | None:
    """The estimated time [s] and peak memory [B] of a built-in method on ``n`` DOFs (None for a
    user's method, whose cost is unknown).

    Dense methods hold a few ``n x n`` matrices (the eigenvectors, the complex check LU) and pay
    one eigen solve plus the check solves; ``"balanced"`` works on ``2n`` states (Gramians);
    ``"krylov"`` keeps sparse factors and a basis of a few vectors per channel and shift.
    """
    dense = float(n) ** 2
    if method.name in ("prune", "modal"):
        return Cost(K_EIGH * n**3 + (CHECKS * K_LU * n**3 if method.name == "modal" else 0.0), 8.0 * 6 * dense)
    if method.name == "balanced":
        big = 2.0 * n
        return Cost(30 * K_EIGH * big**3, 8.0 * 10 * big * big)
    if method.name == "krylov":
        vectors = 2 * channels * 8 * 4                 # shifts x moments x (real, imag), a few rounds
        return Cost(CHECKS * 1e-6 * n * 40, 8.0 * n * (vectors + 200))
    return None


def _custom(fn: Callable[..., Any]) -> ReductionMethod:
    return ReductionMethod(callable_name(fn), fn, summary="user method")


def resolve_method(method: Any) -> ReductionMethod | None:
    """The :class:`ReductionMethod` for a name, a ReductionMethod or a callable
    ``f(plant, scope, options) -> Reduced``; None for ``"auto"``.

    Parameters
    ----------
    method : str, ReductionMethod or callable

    Returns
    -------
    ReductionMethod or None

    Raises
    ------
    ModelError
        An unknown name (the valid ones listed, with a did-you-mean).
    """
    if isinstance(method, str) and method == "auto":
        return None
    return resolve(method, METHODS, where="reduce", custom=_custom, extra=["auto"])
