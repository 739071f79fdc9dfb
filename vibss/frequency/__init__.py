"""Frequency responses, transmissibility and steady swept sines (api / kernels)."""

from .api import *  # noqa: F401,F403
from .api import __all__
