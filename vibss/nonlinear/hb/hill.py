"""Stability of a periodic solution by Hill's method.

A perturbation ``z = (x, x')`` of the periodic solution obeys ``z' = A(t) z`` with
``A(t) = [[0, I], [-M^-1 (K + L^T diag(kappa(t)) L), -M^-1 C]]`` (``kappa`` the nonlinear axes'
tangent rates beyond the tangent model's, periodic). Floquet's form ``z = exp(lambda t) p(t)``
with ``p`` truncated to harmonics ``-H..H`` gives the Hill eigenproblem

    lambda p_r = sum_c A_{r-c} p_c - i r omega p_r,

of size ``2n (2H + 1)``: each Floquet exponent appears once per harmonic shift ``+ i r omega``. The
``2n`` physical ones are those of smallest ``|Im lambda|`` (the central copies, the best
resolved). The solution is unstable when one has ``Re lambda > STABILITY_TOL omega``.
The time-domain model has no hysteretic damping: a mount loss factor is left out of ``C`` here.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sl
import scipy.sparse as sp

from ...linear.plant.plant import Plant
from ...linear.solve.mass import mass_solver

__all__ = ["hill_exponents", "HILL_MAX", "STABILITY_TOL"]

HILL_MAX = 2400
"""Largest Hill matrix (``2n (2H + 1)``) whose eigenvalues are computed (about 10 s); above it
the stability is not computed and the result says so."""

STABILITY_TOL = 1e-7
"""An exponent counts as growing when ``Re lambda`` exceeds this times ``omega``."""


def _dense(a: object) -> np.ndarray:
    return np.asarray(a.toarray() if sp.issparse(a) else a, dtype=float)   # type: ignore[attr-defined]


class Hill:
    """The constant parts of the Hill matrix of one plant (``M^-1 K``, ``M^-1 C``, ``M^-1 L^T``)."""

    def __init__(self, plant: Plant, L: np.ndarray) -> None:
        solve = mass_solver(plant)
        self.n = plant.n
        self.MK = solve(_dense(plant.K))
        self.MC = solve(_dense(plant.C))
        self.ML = solve(np.ascontiguousarray(L.T)) if L.size else np.zeros((plant.n, 0))
        self.L = L

    def exponents(self, kappa: np.ndarray, omega: float, harmonics: int) -> np.ndarray:
        """The ``2n`` Floquet exponents [1/s] for tangent rates ``kappa`` (N, m) [N/m] over one period."""
        n, H = self.n, harmonics
        N = kappa.shape[0]
        # Fourier coefficients kappa_j, j = -2H..2H: c_j = mean(kappa exp(-i j tau))
        c = np.fft.fft(kappa, axis=0) / N                               # (N, m), index j mod N
        size = 2 * n * (2 * H + 1)
        A = np.zeros((size, size), dtype=complex)
        eye = np.eye(n)
        blocks = {}
        for j in range(-2 * H, 2 * H + 1):
            kj = c[j % N]
            b = np.zeros((2 * n, 2 * n), dtype=complex)
            b[n:, :n] = -(self.ML * kj[None, :]) @ self.L if self.L.size else 0.0
            if j == 0:
                b[:n, n:] = eye
                b[n:, :n] -= self.MK
                b[n:, n:] = -self.MC
            blocks[j] = b
        for r in range(-H, H + 1):
            i0 = (r + H) * 2 * n
            for col in range(-H, H + 1):
                j0 = (col + H) * 2 * n
                A[i0:i0 + 2 * n, j0:j0 + 2 * n] = blocks[r - col]
            A[i0:i0 + 2 * n, i0:i0 + 2 * n] -= 1j * r * omega * np.eye(2 * n)
        lam = sl.eigvals(A, overwrite_a=True, check_finite=False)
        lam = lam[np.isfinite(lam)]
        return lam[np.argsort(np.abs(lam.imag), kind="stable")[:2 * n]]


def hill_exponents(hill: Hill, kappa: np.ndarray, omega: float, harmonics: int) -> tuple[bool, float]:
    """Stable or not, and the largest real part of the physical exponents [1/s]."""
    lam = hill.exponents(kappa, omega, harmonics)
    top = float(lam.real.max()) if lam.size else -np.inf
    return top <= STABILITY_TOL * omega, top
