"""Stability of a periodic solution by its Floquet multipliers, for stop laws (piecewise linear).

A stop's tangent rate is constant between the instants where the axis's deflection crosses a
clearance, so the variational equation ``z' = A(t) z`` (:mod:`.hill`) is piecewise constant over
the period. The crossing instants are the roots of the harmonic-balance deflection
``d0 + y_j(tau) = +c`` or ``-c`` (bracketed on the AFT's samples, refined by Newton's method on the
Fourier series), and the monodromy matrix is the exact product
``Phi = expm(A_s h_s) ... expm(A_1 h_1)`` over the segments. The solution is unstable when a
multiplier has ``|mu| > exp(STABILITY_TOL omega T)`` (the same growth rate limit as Hill's).
A few matrix exponentials of size 2n per point, against one eigenvalue problem of size
``2n (2H + 1)`` for Hill's method.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sl

from .aft import LocalLaws
from .hill import STABILITY_TOL, Hill

__all__ = ["piecewise_linear", "floquet", "FLOQUET_MAX"]

FLOQUET_MAX = 600
"""Largest state (2n) whose monodromy is computed (a few dense matrix exponentials of that size per
point); above it the stability is not computed and the result says so."""


def piecewise_linear(laws: LocalLaws) -> bool:
    """Whether every nonlinear axis is a stop on a linear rate (no curve): Floquet's path applies."""
    return all(law.curve is None for law in laws.laws)


def _kinks(law: object, d0: float) -> list[float]:
    lo, hi = law.clearance                      # type: ignore[attr-defined]
    return [v - d0 for v in (hi, -lo) if np.isfinite(v)]


def _sampled(Yl: np.ndarray, samples: int) -> np.ndarray:
    """(m, N + 1) ``Re sum_k Y_k exp(i k tau)`` at ``tau = 2 pi i / N``, i = 0..N (by an inverse FFT)."""
    c = np.zeros((Yl.shape[0], samples // 2 + 1), dtype=complex)
    c[:, 0] = Yl[:, 0].real
    c[:, 1:Yl.shape[1]] = Yl[:, 1:] / 2
    y = np.fft.irfft(c, n=samples, axis=1) * samples
    return np.concatenate([y, y[:, :1]], axis=1)


def _crossings(Y: np.ndarray, sampled: np.ndarray, level: float) -> list[float]:
    """Phases tau in [0, 2 pi) where ``Re sum Y_k exp(i k tau) = level`` (``sampled``: the series on
    the N + 1 phases of :func:`_sampled`, which bracket the roots)."""
    k = np.arange(Y.size)
    tau = 2 * np.pi * np.arange(sampled.size) / (sampled.size - 1)
    y = sampled - level
    out = []
    for i in np.flatnonzero(np.sign(y[:-1]) * np.sign(y[1:]) < 0):
        a, b = tau[i], tau[i + 1]
        t = a - y[i] * (b - a) / (y[i + 1] - y[i])
        for _ in range(30):                      # Newton on the series, kept in the bracket
            e = np.exp(1j * k * t)
            f = float(np.real(e @ Y)) - level
            df = float(np.real((1j * k * e) @ Y))
            step = f / df if df else 0.0
            t = min(max(t - step, a), b)
            if abs(step) < 1e-15:
                break
        out.append(float(t % (2 * np.pi)))
    return out


def floquet(hill: Hill, laws: LocalLaws, Yl: np.ndarray, omega: float, samples: int) -> tuple[bool, float]:
    """Stable or not, and the largest growth rate ``ln|mu| / T`` [1/s] of the Floquet multipliers.

    Parameters
    ----------
    hill : Hill
        The tangent model's matrices (``M^-1 K``, ``M^-1 C``, ``M^-1 L^T``, ``L``).
    laws : LocalLaws
        The nonlinear axes (stops only, :func:`piecewise_linear`).
    Yl : (m, H+1) complex ndarray
        Their deflections' harmonics about the operating point [m].
    omega : float
        Fundamental [rad/s].
    samples : int
        Samples per period that bracket the crossings.
    """
    n, m = hill.n, Yl.shape[0]
    found = [0.0, 2 * np.pi]
    sampled = _sampled(Yl, samples)
    for j in range(m):
        for level in _kinks(laws.laws[j], float(laws.d0[j])):
            found += _crossings(Yl[j], sampled[j], level)
    cuts = np.unique(np.array(found))
    k = np.arange(Yl.shape[1])
    base = np.zeros((2 * n, 2 * n))
    base[:n, n:] = np.eye(n)
    base[n:, n:] = -hill.MC
    phi = np.eye(2 * n)
    for a, b in zip(cuts[:-1], cuts[1:]):
        if b - a < 1e-14:
            continue
        mid = np.real(Yl @ np.exp(1j * k * 0.5 * (a + b)))
        kappa = laws.tangents(mid[None, :])[0]
        A = base.copy()
        A[n:, :n] = -hill.MK - (hill.ML * kappa[None, :]) @ hill.L if m else -hill.MK
        phi = sl.expm(A * ((b - a) / omega)) @ phi
    mu = np.abs(sl.eigvals(phi, check_finite=False))
    growth = float(np.log(max(mu.max(), np.finfo(float).tiny)) * omega / (2 * np.pi))
    return growth <= STABILITY_TOL * omega, growth
