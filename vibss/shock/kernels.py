"""The arithmetic of the shock analysis: the SRS filter's ramp-invariant coefficients and a spec's
level at given frequencies (log-log between its breakpoints)."""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["spec_level"]


def _coefficients(fn: float, zeta: float, dt: float) -> tuple[np.ndarray, np.ndarray]:
    w = 2.0 * np.pi * fn
    wd = w * np.sqrt(1.0 - zeta * zeta)
    e = np.exp(-zeta * w * dt)
    k = wd * dt
    c, s = e * np.cos(k), e * np.sin(k)
    sp = s / k
    return np.array([1.0 - sp, 2.0 * (sp - c), e * e - sp]), np.array([1.0, -2.0 * c, e * e])


def spec_level(frequency_hz: Any, level: Any, f: Any) -> np.ndarray:
    """Log-log interpolation of a specification at ``f`` [Hz] (NaN outside its band)."""
    fp = np.asarray(frequency_hz, dtype=float)
    lp = np.asarray(level, dtype=float)
    x = np.asarray(f, dtype=float)
    out = np.full(x.shape, np.nan)
    inside = (x >= fp[0]) & (x <= fp[-1])
    out[inside] = np.exp(np.interp(np.log(x[inside]), np.log(fp), np.log(lp)))
    return out
