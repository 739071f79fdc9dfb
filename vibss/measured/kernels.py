"""The rheology laws a measured dynamic stiffness is fitted by, and the one least-squares fit.

Each law maps a parameter vector ``x`` (logarithms of stiffnesses and times, so they stay
positive; a fractional order as it is, bounded to ``(0, 1]``) to the complex stiffness
``k*(w)`` of one axis. :func:`fit_axis` minimises the complex log error
``log(k_fit / k_data)`` (real part: the log-magnitude error; imaginary part: the phase error
[rad]) with :func:`scipy.optimize.least_squares`, from a few starting points read off the data
(the ends' storage stiffness, the frequency of the loss peak), and keeps the best.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from ..model.rheology import FractionalZener, Prony, Rheology, Zener

__all__ = ["Law", "ZenerLaw", "PronyLaw", "FractionalLaw", "LAWS", "fit_axis", "log_error"]

XTOL = 1e-15
"""Step and cost tolerances of the least-squares fit (to rounding: noise-free data from the law
itself are recovered to ~1e-10)."""


def log_error(fitted: np.ndarray, data: np.ndarray) -> np.ndarray:
    """``|log(fitted / data)|``: the log-magnitude and the phase error [rad] combined [-]."""
    return np.abs(np.log(fitted / data))


@dataclass(frozen=True)
class Law:
    """A rheology law to fit: its parameters, starting points, bounds and ``k*(w)``."""

    name: ClassVar[str] = ""

    def size(self, order: int) -> int:
        """Number of parameters per axis."""
        raise NotImplementedError

    def starts(self, w: np.ndarray, k: np.ndarray, order: int) -> list[np.ndarray]:
        """Starting points read off one axis' data ``k`` at ``w`` [rad/s]."""
        raise NotImplementedError

    def bounds(self, order: int) -> tuple[np.ndarray, np.ndarray]:
        """Lower and upper bounds of ``x``."""
        n = self.size(order)
        return np.full(n, -np.inf), np.full(n, np.inf)

    def stiffness(self, x: np.ndarray, w: np.ndarray) -> np.ndarray:
        """(nf,) complex ``k*`` [N/m] at ``w`` [rad/s] for parameters ``x``."""
        raise NotImplementedError

    def rheology(self, xs: list[np.ndarray], band: np.ndarray) -> Rheology:
        """The :class:`~vibss.model.rheology.Rheology` of the three axes' parameters."""
        raise NotImplementedError


def _ends(k: np.ndarray) -> tuple[float, float]:
    """Static and high-frequency storage stiffness guessed from the data's ends."""
    k0 = float(max(k.real[0], 1e-300))
    kinf = float(max(k.real[-1], 1.1 * k0))
    return k0, kinf


def _peak(w: np.ndarray, k: np.ndarray) -> float:
    """Angular frequency of the largest loss factor [rad/s]."""
    return float(w[int(np.argmax(k.imag / k.real))])


@dataclass(frozen=True)
class ZenerLaw(Law):
    """``k* = k_0 + (k_inf - k_0) i w tau / (1 + i w tau)``; ``x = log(k_0, k_inf - k_0, tau)``."""

    name: ClassVar[str] = "zener"

    def size(self, order: int) -> int:
        return 3

    def starts(self, w: np.ndarray, k: np.ndarray, order: int) -> list[np.ndarray]:
        k0, kinf = _ends(k)
        tau = np.sqrt(k0 / kinf) / _peak(w, k)          # the Zener loss peaks at w tau = sqrt(k_0 / k_inf)
        return [np.log([k0, kinf - k0, tau * m]) for m in (1.0, 0.1, 10.0)]

    def stiffness(self, x: np.ndarray, w: np.ndarray) -> np.ndarray:
        k0, dk, tau = np.exp(x)
        s = 1j * w * tau
        return k0 + dk * s / (1 + s)

    def rheology(self, xs: list[np.ndarray], band: np.ndarray) -> Rheology:
        p = np.exp(np.array(xs))                          # (3, 3): axis by parameter
        return Zener(k_0=p[:, 0], k_inf=p[:, 0] + p[:, 1], tau=p[:, 2])


@dataclass(frozen=True)
class FractionalLaw(Law):
    """``k* = (k_0 + k_inf (i w tau)^alpha) / (1 + (i w tau)^alpha)``;
    ``x = (log k_0, log(k_inf - k_0), log tau, alpha)``, ``alpha`` in ``[1e-3, 1]``."""

    name: ClassVar[str] = "fractional"

    def size(self, order: int) -> int:
        return 4

    def starts(self, w: np.ndarray, k: np.ndarray, order: int) -> list[np.ndarray]:
        k0, kinf = _ends(k)
        out = []
        for alpha in (0.3, 0.6, 0.9):                     # the loss peaks at (w tau)^alpha = sqrt(k_0 / k_inf)
            tau = (k0 / kinf) ** (0.5 / alpha) / _peak(w, k)
            out.append(np.array([np.log(k0), np.log(kinf - k0), np.log(tau), alpha]))
        return out

    def bounds(self, order: int) -> tuple[np.ndarray, np.ndarray]:
        return np.array([-np.inf, -np.inf, -np.inf, 1e-3]), np.array([np.inf, np.inf, np.inf, 1.0])

    def stiffness(self, x: np.ndarray, w: np.ndarray) -> np.ndarray:
        k0, dk, tau = np.exp(x[:3])
        p = np.exp(x[3] * (np.log(w * tau) + 0.5j * np.pi))   # (i w tau)^alpha
        return (k0 + (k0 + dk) * p) / (1 + p)

    def rheology(self, xs: list[np.ndarray], band: np.ndarray) -> Rheology:
        x = np.array(xs)
        p = np.exp(x[:, :3])
        return FractionalZener(k_0=p[:, 0], k_inf=p[:, 0] + p[:, 1], tau=p[:, 2], alpha=x[:, 3],
                               band=band.tolist())


@dataclass(frozen=True)
class PronyLaw(Law):
    """``k* = k_0 + sum_i k_i i w tau_i / (1 + i w tau_i)`` with ``order`` terms;
    ``x = log(k_0, k_1 ... k_n, tau_1 ... tau_n)``."""

    name: ClassVar[str] = "prony"

    def size(self, order: int) -> int:
        return 1 + 2 * order

    def starts(self, w: np.ndarray, k: np.ndarray, order: int) -> list[np.ndarray]:
        from scipy.optimize import nnls

        tau = 1.0 / np.geomspace(w[0], w[-1], order + 2)[1:-1] if order > 1 else np.array([1.0 / np.sqrt(w[0] * w[-1])])
        s = 1j * w[:, None] * tau[None]
        a = np.hstack([np.ones((w.size, 1)), s / (1 + s)]) / np.abs(k)[:, None]
        b = k / np.abs(k)
        x, _ = nnls(np.vstack([a.real, a.imag]), np.concatenate([b.real, b.imag]))
        x = np.maximum(x, 1e-3 * max(float(x.max()), 1e-300))   # a zero term: small, so its log exists
        return [np.log(np.concatenate([x, tau]))]

    def stiffness(self, x: np.ndarray, w: np.ndarray) -> np.ndarray:
        n = (x.size - 1) // 2
        p = np.exp(x)
        s = 1j * w[:, None] * p[None, 1 + n:]
        return p[0] + np.sum(p[None, 1:1 + n] * s / (1 + s), axis=1)

    def rheology(self, xs: list[np.ndarray], band: np.ndarray) -> Rheology:
        p = np.exp(np.array(xs))
        n = (p.shape[1] - 1) // 2
        order = np.argsort(p[:, 1 + n:], axis=1)          # terms by relaxation time, per axis
        k = np.take_along_axis(p[:, 1:1 + n], order, axis=1)
        tau = np.take_along_axis(p[:, 1 + n:], order, axis=1)
        return Prony(k_0=p[:, 0], k=k, tau=tau)


LAWS: dict[str, Law] = {law.name: law for law in (ZenerLaw(), PronyLaw(), FractionalLaw())}
"""The laws :func:`vibss.fit_rheology` fits, by ``type`` name."""


def fit_axis(law: Law, w: np.ndarray, k: np.ndarray, order: int) -> tuple[np.ndarray, int]:
    """Least-squares parameters of ``law`` on one axis' data ``k`` (nf,) at ``w`` [rad/s].

    Returns
    -------
    x : ndarray
        The best parameters over the starting points.
    evaluations : int
        Residual evaluations spent (cost).
    """
    from scipy.optimize import least_squares

    lk = np.log(k)

    def residual(x: np.ndarray) -> np.ndarray:
        r = np.log(law.stiffness(x, w)) - lk
        return np.concatenate([r.real, r.imag])

    lo, hi = law.bounds(order)
    best: Any = None
    spent = 0
    for x0 in law.starts(w, k, order):
        sol = least_squares(residual, np.clip(x0, lo, hi), bounds=(lo, hi), xtol=XTOL, ftol=XTOL, gtol=XTOL,
                            max_nfev=400 * x0.size)
        spent += int(sol.nfev)
        if best is None or sol.cost < best.cost:
            best = sol
    return np.asarray(best.x), spent


