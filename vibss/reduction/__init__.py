"""Study-driven model reduction: pruning, modal truncation and Krylov projection (api / result / methods; kernels: prune, truncation, krylov)."""

from .api import *  # noqa: F401,F403
from .api import __all__
