"""The harmonic-balance kernels' structured products against their dense definitions: the AFT
Jacobian's blocks ``P diag(kappa_j) E`` (one FFT, any number of samples, aliasing included), and the
condensed compliance ``G`` applied harmonic by harmonic to force coefficients (``G F``) and to the
Jacobian (``G J``), against the real block matrix of ``G`` built entry by entry here."""

from __future__ import annotations

import numpy as np
import pytest

from vibss.nonlinear.hb.aft import basis, jacobian_blocks
from vibss.nonlinear.hb.condensed import Linear


def _real_matrix(G: np.ndarray) -> np.ndarray:
    """``F -> G F`` on the stacked real coefficients (harmonic-major: a_0, a_1, b_1, ...; axis inside)."""
    H, m = G.shape[0] - 1, G.shape[1]
    out = np.zeros(((2 * H + 1) * m, (2 * H + 1) * m))
    out[:m, :m] = G[0].real
    for k in range(1, H + 1):
        a, b = (2 * k - 1) * m, 2 * k * m
        out[a:a + m, a:a + m], out[a:a + m, b:b + m] = G[k].real, -G[k].imag      # (a + ib)(x + iy)
        out[b:b + m, a:a + m], out[b:b + m, b:b + m] = G[k].imag, G[k].real
    return out


@pytest.mark.parametrize("H, N", [(1, 16), (3, 64), (3, 13), (5, 19), (11, 1024)])
def test_structured_products_equal_their_dense_definitions(H: int, N: int) -> None:
    rng = np.random.default_rng(H * 100 + N)
    m = 3
    b = basis(H, N)
    kappa = rng.standard_normal((N, m))
    gamma = jacobian_blocks(kappa, H)
    dense = (b.P[None] * kappa.T[:, None, :]) @ b.E                       # P diag(kappa_j) E per axis
    np.testing.assert_allclose(gamma, dense, rtol=0, atol=1e-13 * np.abs(dense).max())
    G = rng.standard_normal((H + 1, m, m)) + 1j * rng.standard_normal((H + 1, m, m))
    G[0] = G[0].real
    lin = Linear(G, np.zeros(m, complex))
    Gr = _real_matrix(G)
    S = 2 * H + 1
    J = np.zeros((S * m, S * m))
    for j in range(m):
        J[j::m, j::m] = dense[j]                                           # axis j couples only to itself
    F = rng.standard_normal(S * m)
    np.testing.assert_allclose(lin.apply(F), Gr @ F, rtol=0, atol=1e-13 * np.abs(Gr @ F).max())
    np.testing.assert_allclose(lin.times(gamma), Gr @ J, rtol=0, atol=1e-13 * np.abs(Gr @ J).max())
