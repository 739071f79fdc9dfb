"""Study-driven model reduction: pruning, modal truncation and Krylov projection (api / methods / kernels)."""

from .api import *  # noqa: F401,F403
from .api import __all__
