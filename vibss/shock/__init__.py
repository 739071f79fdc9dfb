"""Shock environments: standard pulses by their specification parameters and the shock response spectrum."""

from __future__ import annotations

from .pulses import G, haversine, half_sine, sawtooth, trapezoid
from .api import check_envelope, srs
from .result import EnvelopeCheck, ShockResponseSpectrum

__all__ = ["G", "ShockResponseSpectrum", "half_sine", "haversine", "sawtooth", "srs", "trapezoid",
           "check_envelope", "EnvelopeCheck"]
