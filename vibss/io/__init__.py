"""Model files (TOML and JSON) to and from :class:`vibss.Model`, the built-in examples, and test data
(UFF datasets 58, 55 and 2411 through the optional pyuff; CSV)."""

from .modelfile import *  # noqa: F401,F403
from .modelfile import __all__ as _model_all
from .csvdata import read_csv, write_csv
from .uff import UffModes, frac, frequency_shift, read_uff, read_uff_modes, write_uff

__all__ = [*_model_all, "write_uff", "read_uff", "read_uff_modes", "UffModes", "frac", "frequency_shift", "write_csv",
           "read_csv"]
