"""The arithmetic of the order analysis on arrays: speeds, sources and the critical speeds where an
order meets a natural frequency."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from .. import _validate as v
from ..errors import ArgumentError
from .sources import OrderForce, Source, Unbalance

__all__ = ["critical_speeds"]


def _sources(sources: Any) -> list[Source]:
    if isinstance(sources, (Unbalance, OrderForce)):
        sources = [sources]
    out = list(sources) if isinstance(sources, Sequence) else []
    if not out or not all(isinstance(s, (Unbalance, OrderForce)) for s in out):
        raise ArgumentError(f"sources: expected Unbalance / OrderForce objects, got {sources!r}",
                            argument="sources", received=sources)
    names = [s.name for s in out]
    if len(set(names)) != len(names):
        raise ArgumentError(f"sources: names must be unique, got {names}", argument="sources", received=names)
    return out


def _speeds(rpm: Any, who: str) -> np.ndarray:
    r = np.atleast_1d(v.array(rpm, "rpm", None, who=who))
    if r.ndim != 1 or np.any(r <= 0) or np.any(np.diff(r) <= 0):
        raise ArgumentError(f"{who}: rpm: expected increasing positive shaft speeds [rpm], got {rpm!r}",
                            argument="rpm", received=rpm)
    return r


def critical_speeds(natural_hz: np.ndarray, orders: Sequence[float], rpm: np.ndarray) -> list[tuple[float, int, float, float]]:
    """``(order, mode, f_n [Hz], rpm)`` where an order line ``f = k rpm / 60`` crosses a natural
    frequency inside the speed range (mode 1-based)."""
    out = []
    for k in orders:
        for i, fn in enumerate(natural_hz):
            r = 60.0 * fn / k
            if rpm[0] <= r <= rpm[-1] and fn > 0:
                out.append((float(k), i + 1, float(fn), float(r)))
    return sorted(out, key=lambda x: x[3])
