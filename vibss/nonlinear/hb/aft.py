"""The alternating frequency-time (AFT) evaluation of the nonlinear mount forces.

The local deflection ``y_j(t)`` of each nonlinear axis ``j`` about the operating point is a real
Fourier series in ``tau = omega t``::

    y_j(tau) = Re sum_{k=0}^{H} Y_kj exp(i k tau) = a_0 + sum_k (a_k cos k tau - b_k sin k tau),

``Y_k = a_k + i b_k`` (``b_0 = 0``). Its real coefficients are stacked harmonic-major,
``X[c * m + j]`` with ``c = 0`` for ``a_0``, ``c = 2k - 1`` for ``a_k`` and ``c = 2k`` for
``b_k``. The force beyond the tangent, ``g_j(y) = f_j(d0_j + y) - f_j(d0_j) - k_tj y`` (``f_j``
the axis's law, ``d0`` the operating point, ``k_t`` its tangent rate there), is sampled at ``N``
points of the period and transformed back: its coefficients ``F`` and their Jacobian
``dF/dX = P diag(g'(y(tau))) E`` (``E`` the synthesis matrix, ``P`` its exact left inverse on
``N > 2H`` samples).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

__all__ = ["Basis", "basis", "samples_for", "to_complex", "to_real", "LocalLaws", "aft", "jacobian_blocks"]


def samples_for(harmonics: int) -> int:
    """Default time samples per period: a power of two, at least ``16 H`` and 1024. A smooth law's
    forces are exact for ``N > 2H`` up to their own harmonics above ``N - H``; a stop's kink aliases
    at about ``N^-2`` (measured, bilinear stop, 15 harmonics: first-harmonic error 2.4e-5 with 256
    samples, 8e-7 with 1024; the AFT costs little beside the linear solves)."""
    return int(max(1024, 2 ** int(np.ceil(np.log2(16 * harmonics)))))


@dataclass(frozen=True)
class Basis:
    """Synthesis ``E`` (N, 2H+1) and analysis ``P`` (2H+1, N) matrices of the real Fourier basis."""

    harmonics: int
    E: np.ndarray
    P: np.ndarray

    @property
    def size(self) -> int:
        return 2 * self.harmonics + 1


def basis(harmonics: int, samples: int) -> Basis:
    """The real Fourier basis on ``samples`` equally spaced phases of one period."""
    tau = 2 * np.pi * np.arange(samples) / samples
    k = np.arange(1, harmonics + 1)
    E = np.empty((samples, 2 * harmonics + 1))
    E[:, 0] = 1.0
    E[:, 1::2] = np.cos(np.outer(tau, k))
    E[:, 2::2] = -np.sin(np.outer(tau, k))
    w = np.full(2 * harmonics + 1, 2.0 / samples)
    w[0] = 1.0 / samples
    return Basis(harmonics, E, E.T * w[:, None])


def to_complex(X: np.ndarray, harmonics: int, m: int) -> np.ndarray:
    """(H+1, m) complex coefficients ``Y_k`` from the real vector ``X`` ((2H+1) m,)."""
    R = X.reshape(2 * harmonics + 1, m)
    Y = np.zeros((harmonics + 1, m), dtype=complex)
    Y[0] = R[0]
    Y[1:] = R[1::2] + 1j * R[2::2]
    return Y


def to_real(Y: np.ndarray) -> np.ndarray:
    """The real vector ``X`` from (H+1, m) complex coefficients (the imaginary part of ``Y_0`` dropped)."""
    h, m = Y.shape[0] - 1, Y.shape[1]
    R = np.empty((2 * h + 1, m))
    R[0] = Y[0].real
    R[1::2] = Y[1:].real
    R[2::2] = Y[1:].imag
    return R.ravel()


@dataclass(frozen=True)
class LocalLaws:
    """The nonlinear axes' laws about the operating point.

    Attributes
    ----------
    laws : tuple of AxisLaw
        One per nonlinear axis (m of them).
    d0 : (m,) ndarray
        Their deflections at the operating point [m].
    f0 : (m,) ndarray
        Their forces there [N].
    kt : (m,) ndarray
        Their tangent rates there [N/m] (the linear part's).
    """

    laws: tuple[Any, ...]
    d0: np.ndarray
    f0: np.ndarray
    kt: np.ndarray

    @cached_property
    def groups(self) -> tuple[tuple[Any, np.ndarray], ...]:
        """The axes that share a law (the same axis of mounts of one type), evaluated together."""
        cols: dict[int, list[int]] = {}
        for j, law in enumerate(self.laws):
            cols.setdefault(id(law), []).append(j)
        return tuple((self.laws[js[0]], np.array(js)) for js in cols.values())

    def forces(self, y: np.ndarray) -> np.ndarray:
        """(N, m) forces beyond the tangent [N] at local deflections ``y`` (N, m) about ``d0`` [m]."""
        out = np.empty_like(y)
        for law, js in self.groups:
            out[:, js] = law.force(self.d0[js] + y[:, js]) - self.f0[js] - self.kt[js] * y[:, js]
        return out

    def tangents(self, y: np.ndarray) -> np.ndarray:
        """(N, m) tangent rates beyond ``kt`` [N/m] at local deflections ``y`` (N, m)."""
        out = np.empty_like(y)
        for law, js in self.groups:
            out[:, js] = law.tangent(self.d0[js] + y[:, js]) - self.kt[js]
        return out


def aft(laws: LocalLaws, b: Basis, X: np.ndarray, jacobian: bool = True) -> tuple[np.ndarray, np.ndarray | None, np.ndarray]:
    """Force coefficients ``F`` ((2H+1) m,) of the deflection coefficients ``X``, the Jacobian's
    blocks ((m, 2H+1, 2H+1), or None: ``dF/dX`` couples each axis only to itself, axis ``j``'s block
    ``P diag(kappa_j) E``) and the tangents sampled over the period (N, m) [N/m]."""
    m = laws.d0.size
    R = X.reshape(b.size, m)
    y = b.E @ R                                      # (N, m) deflections over the period
    F = (b.P @ laws.forces(y)).ravel()
    kappa = laws.tangents(y)
    if not jacobian:
        return F, None, kappa
    return F, jacobian_blocks(kappa, b.harmonics), kappa


def jacobian_blocks(kappa: np.ndarray, harmonics: int) -> np.ndarray:
    """(m, 2H+1, 2H+1) blocks ``P diag(kappa_j) E`` from the tangents ``kappa`` (N, m) sampled over
    the period, by their discrete Fourier coefficients up to ``2H`` (one FFT; the discrete means, so
    the same numbers on any ``N``, aliasing included): the products of two basis functions are
    cosines and sines of ``k +- k'``, e.g.
    ``mean(kappa cos k tau cos k' tau) = (A_|k-k'| + A_k+k') / 2`` with ``A_q + i B_q`` the mean of
    ``kappa exp(i q tau)``; rows ``k >= 1`` carry ``P``'s weight 2."""
    N, m = kappa.shape
    H = harmonics
    c = (np.fft.fft(kappa, axis=0) / N)[np.arange(2 * H + 1) % N].T       # (m, 2H+1): A_q - i B_q, aliased
    A, B = c.real, -c.imag
    k = np.arange(H + 1)
    d, s = k[:, None] - k[None, :], k[:, None] + k[None, :]
    Ad, Bd, As, Bs = A[:, np.abs(d)], np.sign(d) * B[:, np.abs(d)], A[:, s], B[:, s]
    a = np.concatenate([[0], 2 * k[1:] - 1])                    # rows of cos k tau (k = 0: the mean)
    b = 2 * k[1:]                                               # rows of -sin k tau
    wa = np.where(k == 0, 1.0, 2.0)[:, None]
    out = np.empty((m, 2 * H + 1, 2 * H + 1))
    out[:, a[:, None], a[None, :]] = wa * 0.5 * (Ad + As)                          # cos k, cos k'
    out[:, a[:, None], b[None, :]] = -wa * 0.5 * (Bs - Bd)[:, :, 1:]              # cos k, -sin k'
    out[:, b[:, None], a[None, :]] = -(Bs + Bd)[:, 1:, :]                         # -sin k, cos k'
    out[:, b[:, None], b[None, :]] = (Ad - As)[:, 1:, 1:]                         # -sin k, -sin k'
    return out
