"""Random vibration: PSD specifications and the output PSDs and RMS values they cause (api / result / psd / kernels)."""

from __future__ import annotations

from .api import random_response
from .psd import G, PSD
from .result import RandomResponse

__all__ = ["G", "PSD", "RandomResponse", "random_response"]
