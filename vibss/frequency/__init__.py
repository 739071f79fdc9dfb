"""Frequency responses, transmissibility and steady swept sines (api / result / grid / methods / kernels / sweep)."""

from .api import *  # noqa: F401,F403
from .api import __all__ as _api_all
from .grid import FrequencyGrid, frequency_grid
from .methods import METHODS, FrequencyMethod, choose, resolve_method
from .result import FrequencyResponse
from .sweep import *  # noqa: F401,F403
from .sweep import __all__ as _sweep_all

__all__ = ["FrequencyResponse", "FrequencyGrid", "frequency_grid", *_api_all, *_sweep_all, "METHODS",
           "FrequencyMethod", "choose", "resolve_method"]
