"""Nonlinear mounts (bump stops, force-deflection curves): the operating point under static load
and its tangent model, on which every linear analysis applies; the steady periodic response by
harmonic balance (:mod:`.harmonic`, kernels in :mod:`.hb`).

The package's names load on first use: :mod:`vibss.statics` uses :mod:`.kernels` (the equilibrium)
below the analyses, so importing the package must not import :mod:`.api` (which uses statics).
"""

from __future__ import annotations

from typing import Any

__all__ = ["operating_point", "OperatingPoint", "harmonic_balance", "HarmonicBalanceResult"]


def __getattr__(name: str) -> Any:
    if name == "operating_point":
        from .api import operating_point
        return operating_point
    if name == "harmonic_balance":
        from .harmonic import harmonic_balance
        return harmonic_balance
    if name == "HarmonicBalanceResult":
        from .result import HarmonicBalanceResult
        return HarmonicBalanceResult
    if name == "OperatingPoint":
        from .result import OperatingPoint
        return OperatingPoint
    raise AttributeError(f"module 'vibss.nonlinear' has no attribute {name!r}")
