"""Model files (TOML and JSON) to and from :class:`vibss.Model`, the built-in examples, and test data
(UFF dataset 58, through the optional pyuff)."""

from .modelfile import *  # noqa: F401,F403
from .modelfile import __all__ as _model_all
from .uff import frac, read_uff, write_uff

__all__ = [*_model_all, "write_uff", "read_uff", "frac"]
