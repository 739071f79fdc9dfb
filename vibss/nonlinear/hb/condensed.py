"""The linear part of a harmonic-balance problem, condensed exactly onto the nonlinear mount axes.

The model about its operating point is the tangent model (every nonlinear axis at its tangent
rate ``k_t``) plus the forces beyond the tangent ``g(y)`` on the m nonlinear axes, whose local
deflections are ``y = L q`` (``L``: the plant's ``mount.<name>.d1|d2|d3`` output rows). At
harmonic ``k`` of ``omega`` the exact solve of the tangent plant gives

- ``G_k = L A(i k omega)^-1 L^T`` (m, m): local deflection per local force [m/N];
- ``T_k = O(i k omega) A(i k omega)^-1 L^T`` (p, m): each output per local force;
- at ``k = 1`` the linear response of the local axes ``U`` and of the outputs to the inputs;

so the harmonic-balance equations have only the ``(2H + 1) m`` local unknowns. The 0th harmonic
(the mean shift) uses the plant without hysteresis (a loss factor has no static part); a model
that its mounts do not hold statically (a free rigid-body motion) has no mean shift and is refused.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
import numpy as np
import scipy.sparse as sp

from ...errors import AnalysisError
from ...linear.eigen.basis import modal_basis
from ...linear.plant.plant import Plant
from ...linear.solve.exact import output_map, response, states, without_hysteresis

__all__ = ["Condensed", "Linear"]


@dataclass(frozen=True)
class Linear:
    """The condensed linear part at one fundamental frequency.

    Attributes
    ----------
    G : (H+1, m, m) complex ndarray
        Local compliance per harmonic [m/N].
    T : (H+1, p, m) complex ndarray
        Outputs per local force per harmonic (the outputs' units per N).
    U : (m,) complex ndarray
        Local deflections' linear response to the inputs at the fundamental [m].
    Y : (p,) complex ndarray
        Outputs' linear response to the inputs at the fundamental.
    Greal : (N, N) ndarray
        ``G`` as the real block matrix acting on the stacked real coefficients (:mod:`.aft`).
    """

    G: np.ndarray
    T: np.ndarray
    U: np.ndarray
    Y: np.ndarray
    Greal: np.ndarray


@dataclass(frozen=True, eq=False)
class Condensed:
    """The tangent plant with its user outputs first and the nonlinear axes' deflections after them.

    Attributes
    ----------
    plant : Plant
        Outputs: the user's (``p``), then those of ``local`` (which may repeat a user's).
    local : (m,) int ndarray
        The plant's output rows of the nonlinear axes' local deflections.
    p : int
        Number of user outputs.
    u : (ni,) complex ndarray
        Input amplitudes (phasors of ``u(t) = Re(u exp(i omega t))``).
    harmonics : int
        H.
    W : (p, m) ndarray
        Direct part of each output per local force beyond the tangent (a mount or ground force output of a
        nonlinear mount carries that mount's force beyond the tangent).
    """

    plant: Plant
    local: np.ndarray
    p: int
    u: np.ndarray
    harmonics: int
    W: np.ndarray
    _cache: dict = field(default_factory=dict, repr=False)

    @property
    def m(self) -> int:
        return int(self.local.size)

    def rows(self) -> np.ndarray:
        """(m, n) dense local deflection rows on the free DOFs [m/m, m/rad]."""
        def make() -> np.ndarray:
            oq = self.plant.Oq[self.local]
            return np.asarray(oq.toarray() if sp.issparse(oq) else oq, dtype=float)
        return self.plant.cached("harmonic balance: local rows", make)

    def at(self, omega: float) -> Linear:
        """The condensed linear part at ``omega`` [rad/s] (remembered for the last few)."""
        key = float(omega)
        hit = self._cache.get(key)
        if hit is None:
            if len(self._cache) > 16:
                self._cache.clear()
            hit = self._cache[key] = self._make(key)
        return hit

    def _make(self, omega: float) -> Linear:
        H, p, m = self.harmonics, self.p, self.m
        L = self.rows()
        G = np.zeros((H + 1, m, m), dtype=complex)
        T = np.zeros((H + 1, p, m), dtype=complex)
        if m:
            static = self.plant.cached("harmonic balance: static plant", lambda: without_hysteresis(self.plant))
            x0 = self.plant.cached("harmonic balance: static solution", lambda: _static(static, L))
            G[0] = L @ x0
            T[0] = (output_map(static, 0.0)[:p] @ x0).real
            s = 1j * omega * np.arange(1, H + 1)
            x, bad = states(self.plant, s, rhs=L.T)
            if np.any(bad):
                k = int(np.flatnonzero(bad)[0]) + 1
                raise AnalysisError(f"harmonic_balance: the tangent model is singular at harmonic {k} of "
                                    f"{omega / (2 * np.pi):.6g} Hz (an undamped resonance): add damping")
            G[1:] = L @ x
            for k in range(1, H + 1):
                T[k] = output_map(self.plant, s[k - 1])[:p] @ x[k - 1]
            T -= self.W[None]             # y = Y_lin - T F: the structure sees -L^T F, the output +W F
        y = response(self.plant, np.array([1j * omega]))[:, :, 0] @ self.u
        return Linear(G, T, y[self.local], y[:p], _real_blocks(G))


def _static(static: Plant, L: np.ndarray) -> np.ndarray:
    """(n, m) static deflection per unit local force: ``K^-1 L^T``, or, when free rigid-body motions
    leave ``K`` singular but move no nonlinear axis, the solution without them
    (``(K + M R R^T M)^-1 L^T``, ``R`` the mass-normalised rigid modes: ``R^T L^T = 0``)."""
    x0, bad = states(static, np.zeros(1), rhs=L.T)
    if not bad[0]:
        return x0[0].real
    basis = modal_basis(static)
    R = basis.phi[:, basis.rigid]
    seen = np.abs(L @ R).max(initial=0.0) > 1e-9 * np.abs(L).max(initial=1.0) * np.abs(R).max(initial=1.0)
    if not R.size or seen:
        raise AnalysisError("harmonic_balance: a free rigid-body motion of the tangent model moves a nonlinear "
                            "mount axis: the mean shift (0th harmonic) is undefined; restrain the model",
                            argument="model")
    MR = static.M @ R
    K = static.K + (sp.csr_matrix(MR @ MR.T) if sp.issparse(static.K) else MR @ MR.T)
    x0, bad = states(replace(static, K=K, Kf=None, mounts=None), np.zeros(1), rhs=L.T)
    return x0[0].real


def _real_blocks(G: np.ndarray) -> np.ndarray:
    """The real (2H+1) m square matrix of ``F -> G F`` on the stacked real coefficients."""
    H, m = G.shape[0] - 1, G.shape[1]
    N = (2 * H + 1) * m
    out = np.zeros((N, N))
    out[:m, :m] = G[0].real
    for k in range(1, H + 1):
        a, b = (2 * k - 1) * m, 2 * k * m
        gr, gi = G[k].real, G[k].imag
        out[a:a + m, a:a + m] = gr
        out[a:a + m, b:b + m] = -gi
        out[b:b + m, a:a + m] = gi
        out[b:b + m, b:b + m] = gr
    return out


