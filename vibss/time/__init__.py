"""Time responses: exact modal recurrences, integrators, swept-sine envelopes (api / result / inputs / methods / kernels)."""

from .api import *  # noqa: F401,F403
from .api import __all__
