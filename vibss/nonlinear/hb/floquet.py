"""Stability of a periodic solution by its Floquet multipliers (the monodromy matrix).

A perturbation ``z = (x, x')`` of the periodic solution obeys ``z' = A(t) z`` (:mod:`.hill`), with
``A`` depending on the nonlinear axes' tangent rates along the orbit. The monodromy matrix
``Phi = E_s ... E_1`` is a product of matrix exponentials over the period, cut where an axis's
deflection ``d0 + y_j(tau)`` crosses a stop's clearance or a curve's point (roots bracketed on the
AFT's samples, refined by Newton's method on the Fourier series):

- **stops only** (piecewise linear laws): ``A`` is constant between the cuts and ``E_i =
  expm(A_i h_i)`` is exact;
- **curves**: ``A`` varies smoothly between the cuts (a PCHIP curve's second derivative jumps at its
  points: a sub-step across one would be of third order only); each piece is split into sub-steps and
  ``E_i = expm(Omega_i)`` with the fourth-order Magnus expansion on two Gauss points,
  ``Omega = h (A_1 + A_2) / 2 + sqrt(3) h^2 [A_2, A_1] / 12``. The sub-steps double until the
  growth rate changes by less than :data:`GROWTH_ATOL` ``omega`` or :data:`GROWTH_RTOL` of itself
  (the estimate of the finer run's error is a fifteenth of the change, fourth order); a point
  whose steps do not converge by :data:`MAX_SUBSTEPS` per period is reported unconverged (the caller
  takes Hill's method there, or keeps this answer with a warning where Hill's is too large).

The solution is unstable when a multiplier has ``|mu| > exp(STABILITY_TOL omega T)`` (the growth
rate limit of Hill's method). A few (stops) to a few hundred (curves: 32 + 64 + ... sub-steps) matrix
exponentials of size ``2n`` per point, batched, against one eigenvalue problem of size ``2n (2H + 1)``
for Hill's: measured on the snubbed cabinet (12 states, H = 11, 137 points) 0.59 s against 3.67 s
(4 against 27 ms a point); with curves Hill's costs less up to H = 3 (``harmonic.HILL_CHEAPER_H``).
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sl

from .aft import LocalLaws
from .hill import STABILITY_TOL, Hill

__all__ = ["piecewise_linear", "floquet", "FLOQUET_MAX", "MAX_SUBSTEPS", "GROWTH_RTOL", "GROWTH_ATOL"]

FLOQUET_MAX = 600
"""Largest state (2n) whose monodromy is computed (dense matrix exponentials of that size per point);
above it Hill's method where its matrix fits, else the stability is not computed and the result says so."""

FIRST_SUBSTEPS = 32
"""Magnus sub-steps per period of the first run on a model with curves (doubled until converged)."""

MAX_SUBSTEPS = 2048
"""Most Magnus sub-steps per period before a point counts as unconverged."""

GROWTH_RTOL = 1e-4
"""Convergence of the growth rate between two runs, relative to itself ..."""

GROWTH_ATOL = 1e-6
"""... or relative to the fundamental ``omega`` (near a bifurcation, where it crosses zero)."""

_GAUSS = 0.5 * np.array([1 - 1 / np.sqrt(3), 1 + 1 / np.sqrt(3)])


def piecewise_linear(laws: LocalLaws) -> bool:
    """Whether every nonlinear axis is a stop on a linear rate (no curve): one exact exponential per
    piece between contact instants, no sub-steps."""
    return all(law.curve is None for law in laws.laws)


def _kinks(law: object, d0: float) -> np.ndarray:
    """Deflections about the operating point [m] where the law's tangent jumps (a stop's clearance)
    or its slope does (a curve's points, where the PCHIP's second derivative jumps)."""
    lo, hi = law.clearance                      # type: ignore[attr-defined]
    out = [v for v in (hi, -lo) if np.isfinite(v)]
    curve = law.curve                           # type: ignore[attr-defined]
    return np.array(out + ([] if curve is None else list(curve.x)), dtype=float) - d0


def _sampled(Yl: np.ndarray, samples: int) -> np.ndarray:
    """(m, N + 1) ``Re sum_k Y_k exp(i k tau)`` at ``tau = 2 pi i / N``, i = 0..N (by an inverse FFT)."""
    c = np.zeros((Yl.shape[0], samples // 2 + 1), dtype=complex)
    c[:, 0] = Yl[:, 0].real
    c[:, 1:Yl.shape[1]] = Yl[:, 1:] / 2
    y = np.fft.irfft(c, n=samples, axis=1) * samples
    return np.concatenate([y, y[:, :1]], axis=1)


def _cuts(laws: LocalLaws, Yl: np.ndarray, samples: int) -> np.ndarray:
    """Phases [rad] that start and end the pieces: 0, every crossing of a kink (:func:`_kinks`), 2 pi.
    The crossings are bracketed on ``samples`` phases and refined together by Newton's method on
    the Fourier series (kept in their brackets)."""
    kinks = [_kinks(law, float(laws.d0[j])) for j, law in enumerate(laws.laws)]
    found = [np.array([0.0, 2 * np.pi])]
    if any(k.size for k in kinks):
        sampled = _sampled(Yl, samples)
        step = 2 * np.pi / samples
        rows, levels, lo = [], [], []
        for j, level in enumerate(kinks):
            y = sampled[j][None, :] - level[:, None]
            which, i = np.nonzero(np.sign(y[:, :-1]) * np.sign(y[:, 1:]) < 0)
            rows.append(np.full(i.size, j))
            levels.append(level[which])
            lo.append(i)
        r, lev, i = np.concatenate(rows), np.concatenate(levels), np.concatenate(lo)
        if i.size:
            y0, y1 = sampled[r, i] - lev, sampled[r, i + 1] - lev
            a = i * step
            t = a + step * y0 / (y0 - y1)
            Y, k = Yl[r], np.arange(Yl.shape[1])
            for _ in range(30):
                e = np.exp(1j * np.outer(t, k)) * Y
                f = np.real(e.sum(axis=1)) - lev
                df = np.real((1j * k * e).sum(axis=1))
                dt = np.divide(f, df, out=np.zeros_like(f), where=df != 0)
                t = np.clip(t - dt, a, a + step)
                if np.all(np.abs(dt) < 1e-15):
                    break
            found.append(t % (2 * np.pi))
    cuts = np.unique(np.concatenate(found))
    cuts = cuts[np.concatenate([[True], np.diff(cuts) >= 1e-14])]
    cuts[-1] = 2 * np.pi
    return cuts


CHUNK = 256
"""Sub-steps whose matrices are built and exponentiated together (memory ``~ CHUNK (2n)^2`` floats a
few times over, whatever the sub-step count)."""


def _monodromy(hill: Hill, laws: LocalLaws, Yl: np.ndarray, omega: float, cuts: np.ndarray,
               per_period: int) -> np.ndarray:
    """The monodromy matrix with about ``per_period`` sub-steps per period (0: one per piece, its
    middle's ``A`` exact, for piecewise-constant laws), :data:`CHUNK` sub-steps at a time."""
    lengths = np.diff(cuts)
    if per_period:
        counts = np.maximum(1, np.ceil(lengths * per_period / (2 * np.pi)).astype(int))
        h = np.repeat(lengths / counts, counts)                         # sub-step lengths [rad]
        start = np.repeat(cuts[:-1], counts) + h * (np.arange(h.size) - np.repeat(np.cumsum(counts) - counts, counts))
    else:
        h, start = lengths, cuts[:-1]
    phi = np.eye(2 * hill.n)
    for a in range(0, h.size, CHUNK):
        phi = _product(hill, laws, Yl, omega, start[a:a + CHUNK], h[a:a + CHUNK], bool(per_period)) @ phi
    return phi


def _product(hill: Hill, laws: LocalLaws, Yl: np.ndarray, omega: float, start: np.ndarray, h: np.ndarray,
             magnus: bool) -> np.ndarray:
    """``E_k ... E_1`` over the sub-steps starting at phases ``start`` [rad] of lengths ``h`` [rad]:
    fourth-order Magnus on two Gauss points (``magnus``), else ``A`` at each middle, exact."""
    n, m = hill.n, Yl.shape[0]
    tau = (start[:, None] + h[:, None] * _GAUSS[None, :]).ravel() if magnus else start + 0.5 * h
    y = np.real(np.exp(1j * np.outer(tau, np.arange(Yl.shape[1]))) @ Yl.T)       # (points, m) [m]
    kappa = laws.tangents(y) if m else np.zeros((tau.size, 0))
    A = np.zeros((tau.size, 2 * n, 2 * n))
    A[:, :n, n:] = np.eye(n)
    A[:, n:, n:] = -hill.MC
    A[:, n:, :n] = -hill.MK - np.einsum("nj,pj,jk->pnk", hill.ML, kappa, hill.L)
    dt = h / omega                                                      # [s]
    if magnus:
        A1, A2 = A[0::2], A[1::2]
        C = A2 @ A1 - A1 @ A2
        Om = 0.5 * dt[:, None, None] * (A1 + A2) + (np.sqrt(3) / 12) * (dt**2)[:, None, None] * C
    else:
        Om = A * dt[:, None, None]
    E = sl.expm(Om)
    while E.shape[0] > 1:                                              # ordered product, pairwise
        if E.shape[0] % 2:
            E = np.concatenate([E, np.eye(2 * n)[None]])
        E = E[1::2] @ E[0::2]
    return E[0]


def _growth(phi: np.ndarray, omega: float) -> float:
    mu = np.abs(sl.eigvals(phi, check_finite=False))
    return float(np.log(max(mu.max(), np.finfo(float).tiny)) * omega / (2 * np.pi))


def floquet(hill: Hill, laws: LocalLaws, Yl: np.ndarray, omega: float, samples: int) -> tuple[bool, float, bool]:
    """Stable or not, the largest growth rate ``ln|mu| / T`` [1/s] of the Floquet multipliers, and
    whether the monodromy converged (always, for stops only).

    Parameters
    ----------
    hill : Hill
        The tangent model's matrices (``M^-1 K``, ``M^-1 C``, ``M^-1 L^T``, ``L``).
    laws : LocalLaws
        The nonlinear axes.
    Yl : (m, H+1) complex ndarray
        Their deflections' harmonics about the operating point [m].
    omega : float
        Fundamental [rad/s].
    samples : int
        Samples per period that bracket the crossings of clearances and curve points.
    """
    cuts = _cuts(laws, Yl, samples)
    if piecewise_linear(laws):
        g = _growth(_monodromy(hill, laws, Yl, omega, cuts, 0), omega)
        return g <= STABILITY_TOL * omega, g, True
    per = FIRST_SUBSTEPS
    g = _growth(_monodromy(hill, laws, Yl, omega, cuts, per), omega)
    while per < MAX_SUBSTEPS:
        per *= 2
        g_fine = _growth(_monodromy(hill, laws, Yl, omega, cuts, per), omega)
        change, g = abs(g_fine - g), g_fine
        if change <= max(GROWTH_RTOL * abs(g), GROWTH_ATOL * omega):
            return g <= STABILITY_TOL * omega, g, True
    return g <= STABILITY_TOL * omega, g, False
