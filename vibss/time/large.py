"""Large models in the time domain without a dense n x n matrix: kept modes plus residual vectors.

:func:`vibss.time.simulate` of a :class:`~vibss.model.model.Model` with more than
:data:`~vibss.time.api.LARGE_DOFS` (6,000) DOFs and ``method="auto"`` runs here first (issue 17 item 4):
computing every mode densely is O(n^3) (196 s at 6,000 DOF, 26.8 GiB of memory at 60,000).

1. **Cut-off.** The inputs' significant frequency ``f_in`` [Hz] (:func:`input_frequency`: the
   excitations' own content, e.g. ``1 / tau`` of a pulse of length tau, a sine's frequency, a
   sweep's top; else the frequency below which the sampled inputs' amplitude spectrum holds all but
   :data:`SPECTRUM_TAIL` of its L1 mass), and the cut-off ``f_c = CUTOFF_FACTOR f_in``.
2. **Kept modes.** Every undamped mode up to ``f_c`` by shift-invert ``eigsh`` (the one eigen path,
   :func:`vibss.linear.eigen.undamped`), the count grown (at least doubled, more where the modes found
   are far below ``f_c``, counted as growing like ``w^2``) until the highest one lies above ``f_c``.
   When that needs more than :data:`MAX_MODES` (or the count predicted from the modes found exceeds
   twice it) an :class:`~vibss.errors.AnalysisError` says so and names the other routes: modes
   missing below the cut-off may be the very ones the inputs and outputs see (on a long chain the
   lowest modes lie far from them), so no estimate from the kept ones could be trusted.
3. **Residual vectors** (mode-acceleration / static correction): the static response
   ``K^-1 [F, Kz, Cz, Mz]`` of every forcing term, made M-orthogonal to the kept modes, is appended
   to the basis and the plant projected on it (Galerkin). The kept modes stay exact eigenpairs of the
   projected plant; the truncated ones enter through their exact static response, so every output
   type (displacement, velocity, acceleration, mount force) is corrected.
4. **Error estimate.** The same path with only the modes up to a half and a quarter of the
   cut-off (each with its own residual vectors) runs beside it; from the two differences of each
   output, ``d1`` (quarter to half) and ``d2`` (half to all), the estimate is the geometric tail
   ``d2 / (1 - r)``, ``r = d2 / d1`` kept within 0.5 .. 0.9 (:func:`error_estimate`), over the
   output's peak. An *estimate*, not a bound. What limits the accuracy is the free ringing of the
   truncated modes that the input's kinks (a half-sine's start and end) excite: lightly damped, it is
   a few per cent of a displacement at a cut-off of 8 / tau, and more of an acceleration.

The reduced plant then runs through the exact modal path (:mod:`vibss.time.kernels`); the result's
``note`` says what was kept and the estimate, and a :class:`~vibss.errors.VibssWarning` says when
the estimate exceeds :data:`WARN_ERROR`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp

from ..errors import AnalysisError
from ..linear.eigen import symmetric_eigen, undamped
from ..linear.plant import Plant
from ..linear.solve import SingularMatrixError, lu_solver

__all__ = ["CUTOFF_FACTOR", "MAX_MODES", "FIRST_MODES", "SPECTRUM_TAIL", "RATIO_MIN", "RATIO_MAX", "WARN_ERROR",
           "Truncated", "input_frequency", "truncated_plant", "error_estimate"]

CUTOFF_FACTOR = 8.0
"""Kept modes reach this multiple of the inputs' significant frequency ``f_in``."""

MAX_MODES = 400
"""Most modes computed by shift-invert (memory: about 2 n MAX_MODES doubles in ARPACK's basis)."""

FIRST_MODES = 40
"""Modes asked for first; doubled until the highest lies above the cut-off."""

SPECTRUM_TAIL = 1e-3
"""Share of the sampled inputs' amplitude spectrum (L1) left above ``f_in`` when the excitations
do not state their content (a step, sampled or callable inputs)."""

RATIO_MIN = 0.5
"""Smallest convergence ratio the error estimate assumes (at least twice the last difference: the
differences are maxima over time of errors that need not line up in time)."""

RATIO_MAX = 0.9
"""Largest convergence ratio the error estimate assumes (a stalled convergence counts ten steps)."""

WARN_ERROR = 1e-2
"""Estimated relative error above which :func:`vibss.time.simulate` warns."""


@dataclass(frozen=True, eq=False)
class Truncated:
    """A large plant reduced to its low modes and residual vectors (see the module docstring).

    Attributes
    ----------
    plant : Plant
        Dense reduced plant: DOFs ``mode<k>`` then ``residual<k>``, ``M = I``, ``K`` diagonal [rad^2/s^2].
    coarse : (Plant, Plant)
        The same with the modes up to a half and a quarter of the cut-off only (error estimate).
    full : Plant
        The sparse plant it came from.
    n_modes : int
        Kept undamped modes.
    n_coarse : (int, int)
        Modes of ``coarse``.
    n_residual : int
        Residual static vectors appended.
    input_hz : float
        The inputs' significant frequency ``f_in`` [Hz].
    cutoff_hz : float
        Asked cut-off ``CUTOFF_FACTOR f_in`` [Hz].
    top_hz : float
        Highest kept mode [Hz] (above ``cutoff_hz`` unless every mode is kept).
    """

    plant: Plant
    coarse: tuple[Plant, Plant]
    full: Plant
    n_modes: int
    n_coarse: tuple[int, int]
    n_residual: int
    input_hz: float
    cutoff_hz: float
    top_hz: float

    def describe(self) -> str:
        """What was kept, in words (for a result's note)."""
        return (f"{self.full.n} DOFs above the large-model threshold: kept sparse; the {self.n_modes} "
                f"modes up to {self.top_hz:.4g} Hz (cut-off {CUTOFF_FACTOR:g} x the inputs' "
                f"{self.input_hz:.4g} Hz = {self.cutoff_hz:.4g} Hz) by shift-invert, plus "
                f"{self.n_residual} residual static vectors (mode-acceleration correction of every "
                f"truncated mode)")


def input_frequency(functions: Sequence[Any], samples: np.ndarray, dt: float) -> float:
    """The inputs' significant frequency ``f_in`` [Hz].

    Parameters
    ----------
    functions : sequence of TimeFunction or None
        The excitations' time functions (None for a sampled or callable input).
    samples : (m, ns) ndarray
        The inputs sampled every ``dt``.
    dt : float
        Sample interval [s].

    Returns
    -------
    float
        [Hz]: the largest ``content_frequency(fn, 1)`` (``1 / tau`` of the shortest interval between
        breakpoints, a sine's frequency, a sweep's top) where every function states a finite one;
        else the frequency below which the sampled spectrum holds all but :data:`SPECTRUM_TAIL` of
        its L1 mass. Capped by the Nyquist frequency ``1 / (2 dt)``.
    """
    # late: importing vibss.reduction loads python-control, which `vibss time` must not pay for
    # (tests/test_startup.py); this path runs only for large models
    from ..reduction.scope import content_frequency

    nyquist = 0.5 / dt
    stated = [content_frequency(fn, 1.0) if fn is not None else math.inf for fn in functions]
    if stated and all(0.0 < f < math.inf for f in stated):
        return min(max(stated), nyquist)
    f, mag = _spectrum(samples, dt)
    total = mag.sum(axis=1)
    tail = np.cumsum(mag[:, ::-1], axis=1)[:, ::-1]          # mass at and above each bin
    best = 0.0
    for j in range(mag.shape[0]):
        if total[j] > 0:
            above = np.flatnonzero(tail[j] > SPECTRUM_TAIL * total[j])
            best = max(best, float(f[above[-1]]) if above.size else 0.0)
    return min(max(best, f[1] if f.size > 1 else nyquist), nyquist)


def _spectrum(samples: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """Frequencies [Hz] and amplitude spectra ``|U_j(f)|`` [unit s] of the sampled inputs (zero-padded 4x)."""
    ns = samples.shape[1]
    nfft = 1 << int(math.ceil(math.log2(max(4 * ns, 16))))
    return np.fft.rfftfreq(nfft, dt), np.abs(np.fft.rfft(samples, nfft, axis=1)) * dt


def truncated_plant(full: Plant, input_hz: float) -> Truncated:
    """Reduce a sparse plant to its modes up to ``CUTOFF_FACTOR input_hz`` plus residual vectors.

    Parameters
    ----------
    full : Plant
        Plant with sparse ``M, C, K`` (:func:`vibss.linear.signals.build_plant` ``sparse=True``).
    input_hz : float
        The inputs' significant frequency [Hz] (:func:`input_frequency`).

    Returns
    -------
    Truncated
    """
    n = full.n
    wc = 2 * np.pi * CUTOFF_FACTOR * input_hz
    K, M = sp.csr_matrix(full.K), sp.csr_matrix(full.M)
    k = min(FIRST_MODES, n - 2)
    while True:
        spec = undamped(K, M, None, n_modes=k, method="shift-invert")
        top_hz = float(np.sqrt(max(spec.omega2[-1], 0.0)) / (2 * np.pi))
        if spec.omega2[-1] > wc**2 or k >= n - 2:
            break
        # the next count from the one found (modes counted as growing like w^2), at least doubled
        want = min(math.ceil(k * 1.25 * wc**2 / max(float(spec.omega2[-1]), np.finfo(float).tiny)), n - 2)
        if (k >= MAX_MODES and want > k) or want > 2 * MAX_MODES:
            # refused rather than answered: modes missing below the cut-off may be the ones the
            # inputs and outputs see (on a long chain the lowest ones lie far from them), and the
            # estimate from the kept ones would not know
            raise AnalysisError(
                f"simulate: {n} DOFs above the large-model threshold, but {k} modes reach only "
                f"{top_hz:.4g} Hz of the cut-off {wc / (2 * np.pi):.4g} Hz ({CUTOFF_FACTOR:g} x the inputs' "
                f"{input_hz:.4g} Hz; about {want} modes needed, at most {MAX_MODES} are computed): a "
                "truncated answer could not state its error. Use method='modal' (every mode, dense: "
                "O(n^3) time, 8 n^2 bytes), vibss.reduce(model, Scope.for_simulation(...), 'krylov') "
                "and simulate its plant, or inputs with less high-frequency content")
        k = int(min(max(2 * k, want), max(MAX_MODES, k + 1), n - 2))
    phi, w2 = spec.phi, spec.omega2
    forcing = np.hstack([full.F, full.Kz, full.Cz, full.Mz])
    forcing = forcing[:, np.any(forcing != 0, axis=0)]
    try:
        solve = lu_solver(K)
    except SingularMatrixError:     # rigid-body modes: a small shift keeps K + s M regular
        d = K.diagonal() / np.maximum(M.diagonal(), np.finfo(float).tiny)
        solve = lu_solver(K + 1e-6 * float(np.median(d[d > 0]) if np.any(d > 0) else 1.0) * M)
    static = np.asarray(solve(forcing), float).reshape(n, -1) if forcing.size else np.zeros((n, 0))
    top_w2 = min(float(w2[-1]), wc**2)      # all modes kept (a small model) or the cut-off
    # the coarser answers of the error estimate: the modes up to a half and a quarter of the cut-off
    half, quarter = (int(np.searchsorted(w2, top_w2 * c**2, side="right")) for c in (0.5, 0.25))
    plant, nres = _project(full, phi, w2, static)
    coarse = (_project(full, phi[:, :half], w2[:half], static)[0],
              _project(full, phi[:, :quarter], w2[:quarter], static)[0])
    top = float(np.sqrt(max(w2[-1], 0.0)) / (2 * np.pi)) if w2.size else 0.0
    return Truncated(plant=plant, coarse=coarse, full=full, n_modes=int(w2.size), n_coarse=(half, quarter),
                     n_residual=nres, input_hz=float(input_hz), cutoff_hz=float(wc / (2 * np.pi)), top_hz=top)


def _project(full: Plant, phi: np.ndarray, w2: np.ndarray, static: np.ndarray) -> tuple[Plant, int]:
    """``full`` projected on the modes ``phi`` and the static responses ``static`` made M-orthogonal
    to them (Ritz vectors of that residual space); returns the plant and the residual vectors' count."""
    M, K = full.M, full.K
    x = static.copy()
    for _ in range(2):                                      # M-orthogonal to the kept modes, twice
        x = x - phi @ (phi.T @ (M @ x))
    w2r = np.zeros(0)
    if x.shape[1]:
        lam, u = symmetric_eigen(x.T @ (M @ x))
        keep = lam > 1e-12 * max(float(lam.max()), np.finfo(float).tiny)
        x = x @ (u[:, keep] / np.sqrt(lam[keep]))           # M-orthonormal, rank revealed
        lam2, u2 = symmetric_eigen(x.T @ (K @ x))           # Ritz vectors of the residual space
        x, w2r = x @ u2, np.maximum(lam2, 0.0)
    basis = np.hstack([phi, x])
    labels = tuple(f"mode{i + 1}" for i in range(phi.shape[1])) + tuple(f"residual{i + 1}" for i in range(x.shape[1]))
    return full.project(basis, labels, M=np.eye(basis.shape[1]), K=np.diag(np.r_[w2, w2r])), int(x.shape[1])


def error_estimate(y: np.ndarray, y_half: np.ndarray, y_quarter: np.ndarray) -> np.ndarray:
    """(p,) estimated error of each output of ``y`` (ns, p), relative to its peak, from the answers
    with the modes up to half and a quarter of the cut-off.

    With ``d1 = max|y_quarter - y_half|`` and ``d2 = max|y_half - y|`` the convergence ratio is
    ``r = d2 / d1`` (kept within :data:`RATIO_MIN` .. :data:`RATIO_MAX`) and the estimate
    ``d2 / (1 - r)``: the sum of a geometric tail that starts at ``d2`` (over-estimating the answer's
    error for a geometric convergence, where it is ``d2 r / (1 - r)``). An estimate, not a bound: a convergence that
    stalls between the three answers and resumes later is not seen.
    """
    if not y.size:
        return np.zeros(y.shape[1])
    d1 = np.abs(y_half - y_quarter).max(axis=0)
    d2 = np.abs(y - y_half).max(axis=0)
    peak = np.abs(y).max(axis=0)
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.clip(np.where(d1 > 0, d2 / d1, RATIO_MAX), RATIO_MIN, RATIO_MAX)
        est = d2 / (1 - r)
        return np.where(peak > 0, est / peak, np.where(est > 0, np.inf, 0.0))
