"""Random vibration: PSD specifications and the output PSDs and RMS values they cause."""

from __future__ import annotations

from .psd import G, PSD
from .response import RandomResponse, random_response

__all__ = ["G", "PSD", "RandomResponse", "random_response"]
