"""Stability of a periodic solution by Hill's method.

A perturbation ``z = (x, x')`` of the periodic solution obeys ``z' = A(t) z`` with
``A(t) = [[0, I], [-M^-1 (K + L^T diag(kappa(t)) L), -M^-1 C]]`` (``kappa`` the nonlinear axes'
tangent rates beyond the tangent model's, periodic). Floquet's form ``z = exp(lambda t) p(t)``
with ``p`` truncated to the real Fourier basis of harmonics ``0..H`` (that of the AFT,
:mod:`.aft`) gives the real Hill eigenproblem

    lambda p = (A_0 (x) I + sum_j Gamma_j (x) B_j - D (x) I) p,

(``Gamma_j`` the AFT Jacobian block of axis ``j``, ``B_j`` its rank-one coupling
``-M^-1 L_j^T L_j``, ``D`` the time derivative on the basis) of size ``2n (2H + 1)``, similar to
the complex Hill matrix and half the cost of its eigenvalues: each Floquet exponent appears once
per harmonic shift ``+ i r omega``. The
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
        self._linear: tuple[int, np.ndarray] | None = None     # the exponents without a stop engaged

    def exponents(self, gamma: np.ndarray, omega: float) -> np.ndarray:
        """The ``2n`` Floquet exponents [1/s].

        Parameters
        ----------
        gamma : (m, 2H+1, 2H+1) ndarray
            Each nonlinear axis's tangent rate beyond the tangent model as a multiplication on the
            real Fourier coefficients, ``P diag(kappa_j(tau)) E`` [N/m] (the AFT Jacobian's blocks).
        omega : float
            Fundamental [rad/s].
        """
        size = gamma.shape[1]
        if not np.any(gamma):                      # no stop engaged: the tangent model's exponents
            if self._linear is None or self._linear[0] != size:
                self._linear = (size, self._exponents(gamma, omega))
            return self._linear[1]
        return self._exponents(gamma, omega)

    def _exponents(self, gamma: np.ndarray, omega: float) -> np.ndarray:
        n, m, size = self.n, gamma.shape[0], gamma.shape[1]
        A0 = np.zeros((2 * n, 2 * n))
        A0[:n, n:] = np.eye(n)
        A0[n:, :n] = -self.MK
        A0[n:, n:] = -self.MC
        hill = np.kron(np.eye(size), A0)
        for j in range(m):
            Bj = np.zeros((2 * n, 2 * n))
            Bj[n:, :n] = -np.outer(self.ML[:, j], self.L[j])
            hill += np.kron(gamma[j], Bj)
        # minus d/dt on the real basis (1, cos k tau, -sin k tau): (a_k, b_k) -> k omega (-b_k, a_k)
        D = np.zeros((size, size))
        for k in range(1, (size - 1) // 2 + 1):
            D[2 * k - 1, 2 * k] = -k * omega
            D[2 * k, 2 * k - 1] = k * omega
        hill -= np.kron(D, np.eye(2 * n))
        lam = sl.eigvals(hill, overwrite_a=True, check_finite=False)
        lam = lam[np.isfinite(lam)]
        return lam[np.argsort(np.abs(lam.imag), kind="stable")[:2 * n]]


def hill_exponents(hill: Hill, gamma: np.ndarray, omega: float) -> tuple[bool, float]:
    """Stable or not, and the largest real part of the physical exponents [1/s] (:meth:`Hill.exponents`)."""
    lam = hill.exponents(gamma, omega)
    top = float(lam.real.max()) if lam.size else -np.inf
    return top <= STABILITY_TOL * omega, top
