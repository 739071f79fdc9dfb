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

from collections.abc import Callable
from dataclasses import dataclass, field, replace
import numpy as np
import scipy.sparse as sp

from ...errors import AnalysisError
from ...linear.eigen.basis import modal_basis
from ...linear.plant.plant import Plant
from ...linear.solve.exact import forcing, observe, output_map, states, without_hysteresis, zfactor
from .aft import to_complex, to_real

__all__ = ["Condensed", "Linear"]


@dataclass(frozen=True)
class Linear:
    """The condensed linear part at one fundamental frequency.

    Attributes
    ----------
    G : (H+1, m, m) complex ndarray
        Local compliance per harmonic [m/N].
    U : (m,) complex ndarray
        Local deflections' linear response to the inputs at the fundamental [m].
    T : (H+1, p, m) complex ndarray or None
        Outputs per local force beyond the tangent per harmonic (the outputs' units per N), with
        the direct part ``-W``: ``y_k = Y - T_k F_k``.
    Y : (p,) complex ndarray or None
        Outputs' linear response to the inputs at the fundamental.
    """

    G: np.ndarray
    U: np.ndarray
    T: np.ndarray | None = None
    Y: np.ndarray | None = None

    def apply(self, F: np.ndarray) -> np.ndarray:
        """``G F`` on the stacked real coefficients ``F`` ((2H+1) m,) of the local forces (:mod:`.aft`):
        harmonic by harmonic, the complex ``G_k F_k`` [m]."""
        H, m = self.G.shape[0] - 1, self.G.shape[1]
        return to_real(np.einsum("kij,kj->ki", self.G, to_complex(F, H, m)))

    def times(self, gamma: np.ndarray) -> np.ndarray:
        """The real matrix of ``X -> G J X`` ((2H+1) m square) for the AFT Jacobian ``J`` given by its
        blocks ``gamma`` (m, 2H+1, 2H+1) (:func:`.aft.aft`): ``G`` couples only the cosine and sine
        of one harmonic, ``J`` only an axis to itself, so the product costs ``4 H m^2 (2H+1)``, not
        its cube."""
        H, m = self.G.shape[0] - 1, self.G.shape[1]
        S = 2 * H + 1
        gr, gi = self.G[1:].real, self.G[1:].imag
        ga, gb = gamma[:, 1::2, :], gamma[:, 2::2, :]               # (m, H, S): rows a_k, b_k
        out = np.empty((S, m, S, m))
        out[0] = np.einsum("ij,jd->idj", self.G[0].real, gamma[:, 0, :])
        out[1::2] = np.einsum("kij,jkd->kidj", gr, ga) - np.einsum("kij,jkd->kidj", gi, gb)
        out[2::2] = np.einsum("kij,jkd->kidj", gi, ga) + np.einsum("kij,jkd->kidj", gr, gb)
        return out.reshape(S * m, S * m)


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
    law : callable or None
        Input amplitudes that follow the frequency: ``law(omegas)`` with omegas (nf,) [rad/s] gives
        (nf, ni) complex amplitudes (an unbalance's ``m e omega^2``); None: ``u`` at every frequency.
        The continuation's ``dR/domega`` then includes the amplitudes' change.
    """

    plant: Plant
    local: np.ndarray
    p: int
    u: np.ndarray
    harmonics: int
    W: np.ndarray
    law: Callable[[np.ndarray], np.ndarray] | None = None
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

    def at(self, omega: float, pair: float | None = None) -> Linear:
        """The condensed linear part at ``omega`` [rad/s] (remembered for the last few); ``pair``: a
        second frequency solved in the same batch (the forward difference's)."""
        key = float(omega)
        hit = self._cache.get(key)
        if hit is None:
            if len(self._cache) > 16:
                self._cache.clear()
            todo = [key] if pair is None or float(pair) in self._cache else [key, float(pair)]
            for w, made in zip(todo, self._solve(np.array(todo))):
                self._cache[w] = made
            hit = self._cache[key]
        return hit

    def outputs(self, omegas: np.ndarray, chunk: int = 64) -> list[Linear]:
        """The condensed linear part at each of ``omegas`` [rad/s] with the outputs' parts ``T`` and ``Y``:
        batched exact solves of ``chunk`` frequencies at a time."""
        w = np.asarray(omegas, dtype=float).ravel()
        return [lin for a in range(0, w.size, chunk) for lin in self._solve(w[a:a + chunk], outputs=True)]

    def _static(self) -> tuple[np.ndarray, Plant]:
        static = self.plant.cached("harmonic balance: static plant", lambda: without_hysteresis(self.plant))
        return self.plant.cached("harmonic balance: static solution", lambda: _static(static, self.rows())), static

    def _solve(self, omegas: np.ndarray, outputs: bool = False) -> list[Linear]:
        """One batched exact solve at every harmonic of every ``omegas`` [rad/s]: local forces and inputs."""
        H, p, m, plant = self.harmonics, self.p, self.m, self.plant
        L = self.rows()
        s = (1j * np.outer(omegas, np.arange(1, H + 1))).ravel()
        zf = zfactor(s, plant.order)
        rhs = np.concatenate([np.broadcast_to(L.T, (s.size,) + L.T.shape), forcing(plant, s, zf)], axis=2)
        x, bad = states(plant, s, rhs=rhs)
        if np.any(bad):
            k = int(np.flatnonzero(bad)[0])
            raise AnalysisError(f"harmonic_balance: the tangent model is singular at harmonic {k % H + 1} of "
                                f"{omegas[k // H] / (2 * np.pi):.6g} Hz (an undamped resonance): add damping")
        per = observe(plant, s[::H], x[::H, :, m:], zf[::H])          # (nf, p + extra, ni)
        amps = np.broadcast_to(self.u, (omegas.size, self.u.size)) if self.law is None else self.law(omegas)
        y = np.einsum("fpi,fi->fp", per, amps)                                # inputs alone, at the fundamental
        out = []
        x0, static = self._static() if m else (np.zeros((plant.n, 0)), plant)
        t0 = (output_map(static, 0.0)[:p] @ x0).real if outputs else None     # the mean's part: one for all
        for i, w in enumerate(omegas):
            part = slice(i * H, (i + 1) * H)
            G = np.empty((H + 1, m, m), dtype=complex)
            G[0] = L @ x0
            G[1:] = L @ x[part, :, :m]
            T = Y = None
            if outputs:
                T = np.empty((H + 1, p, m), dtype=complex)
                T[0] = t0
                for k in range(1, H + 1):
                    T[k] = output_map(plant, s[i * H + k - 1])[:p] @ x[i * H + k - 1, :, :m]
                T -= self.W[None]             # y = Y_lin - T F: the structure sees -L^T F, the output +W F
                Y = y[i, :p]
            out.append(Linear(G, y[i, self.local], T, Y))
        return out


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
