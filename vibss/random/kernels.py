"""Kernels of :func:`vibss.random_response`: the input cross-spectral matrix from the coherences, the
adaptive quadrature of the mean squares in ``ln f`` and Miles's single-mode estimate."""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence

import numpy as np

from ..errors import AnalysisError, ArgumentError

__all__ = ["kind", "coherence", "adaptive_grid", "miles"]

Integrand = Callable[[np.ndarray], tuple[np.ndarray, np.ndarray, np.ndarray]]


def kind(signal: str) -> str:
    """The kind of an input signal by its suffix: acceleration, velocity, displacement or force."""
    return {"acc": "acceleration", "vel": "velocity", "disp": "displacement"}.get(signal.rsplit(".", 1)[-1], "force")


def coherence(names: Sequence[str], correlation: Mapping[tuple[str, str], complex] | None,
              who: str) -> np.ndarray:
    """(m, m) complex coherence ``rho`` of the inputs ``names`` (identity where uncoupled)."""
    m = len(names)
    rho = np.eye(m, dtype=complex)
    for key, value in (correlation or {}).items():
        if not (isinstance(key, tuple) and len(key) == 2 and key[0] in names and key[1] in names and key[0] != key[1]):
            raise ArgumentError(f"{who}: correlation: expected (input, input) pairs of two different inputs "
                                f"among {list(names)}, got {key!r}", argument="correlation", received=key)
        c = complex(value)
        if not abs(c) <= 1.0 + 1e-12:
            raise ArgumentError(f"{who}: correlation[{key!r}]: |rho| must be <= 1, got {value!r}",
                                argument="correlation", received=value)
        i, j = names.index(key[0]), names.index(key[1])
        rho[i, j], rho[j, i] = c, np.conj(c)
    return rho


def _grid(band: tuple[float, float], extra: Sequence[float], per_decade: int) -> np.ndarray:
    """Points in ``ln f``: ``per_decade`` a decade over the band (at least 8), plus ``extra`` [Hz] inside it."""
    lo, hi = band
    n = max(int(np.ceil(per_decade * np.log10(hi / lo))), 8)
    u = np.concatenate([np.linspace(np.log(lo), np.log(hi), n + 1),
                        [np.log(f) for f in extra if lo < f < hi]])
    return np.unique(u)


def adaptive_grid(integrand: Integrand, band: tuple[float, float], extra: Sequence[float], rtol: float,
                  max_points: int, n_outputs: int,
                  who: str) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The grid ``u = ln f`` on which every output's mean square ``int S_yy df`` is within ``rtol``
    (Simpson against trapezoid on every interval, the intervals that carry the excess bisected,
    largest first), and the integrand's output PSDs, input PSDs and ``|H|`` on it."""
    u = _grid(band, extra, 40)
    g_y, g_in, habs = integrand(u)
    err = np.full((n_outputs, u.size - 1), np.inf)     # trapezoid error per interval
    sel = np.arange(u.size - 1)
    while True:
        if u.size + sel.size > max_points:
            raise AnalysisError(f"{who}: the mean squares did not converge to rtol = {rtol:g} within "
                                f"{max_points} frequencies; raise rtol or max_points")
        mid = 0.5 * (u[sel] + u[sel + 1])
        gm, gim, hm = integrand(mid)
        w = g_y * np.exp(u)                       # S df = S f du
        h = np.diff(u)[sel]
        wa, wb, wm = w[:, sel], w[:, sel + 1], gm * np.exp(mid)
        e = np.abs(h / 6.0 * (wa + 4.0 * wm + wb) - 0.5 * (wa + wb) * h)   # Simpson - trapezoid
        # split the checked intervals: each half keeps about an eighth of the error (h^3)
        starts = np.concatenate([u[:-1], mid])
        err_new = np.concatenate([err, e / 8.0], axis=1)
        err_new[:, sel] = e / 8.0
        u = np.concatenate([u, mid])
        order = np.argsort(u)
        u = u[order]
        g_y = np.concatenate([g_y, gm], axis=1)[:, order]
        g_in = np.concatenate([g_in, gim], axis=1)[:, order]
        habs = np.concatenate([habs, hm], axis=2)[:, :, order]
        err = err_new[:, np.argsort(starts)]
        w = g_y * np.exp(u)
        total = np.maximum(np.sum(0.5 * (w[:, 1:] + w[:, :-1]) * np.diff(u), axis=1), 1e-300)
        rel = err / total[:, None]                  # each output's error share per interval
        worst = rel.max(axis=0)
        excess = rel.sum(axis=1).max() - rtol
        if excess <= 0:
            return u, g_y, g_in, habs
        # refine the intervals that carry the excess (largest first)
        ranked = np.argsort(worst)[::-1]
        cum = np.cumsum(worst[ranked])
        sel = np.sort(ranked[:int(np.searchsorted(cum, excess)) + 1])


def miles(outputs: Sequence[str], names: Sequence[str], f: np.ndarray, g_y: np.ndarray, g_in: np.ndarray,
          habs: np.ndarray) -> np.ndarray:
    """Miles's single-mode estimate ``sqrt(pi/2 f_n Q W(f_n))`` per acceleration output under one
    acceleration input (``f_n`` the output PSD's peak, ``Q`` the transmissibility there); NaN else."""
    out = np.full(len(outputs), np.nan)
    if len(names) == 1 and kind(names[0]) == "acceleration":
        for i, o in enumerate(outputs):
            if o.endswith(".acc"):
                k = int(np.argmax(g_y[i]))
                out[i] = np.sqrt(np.pi / 2 * f[k] * habs[i, 0, k] * g_in[0, k])
    return out
