"""Model files (TOML and JSON) to and from :class:`vibss.Model`, the built-in examples, and test data
(UFF datasets 58, 55 and 2411 through the optional pyuff; CSV)."""

from __future__ import annotations

from typing import Any

from .modelfile import *  # noqa: F401,F403
from .modelfile import __all__ as _model_all
from .csvdata import read_csv, write_csv
from .uff import UffModes, read_uff, read_uff_modes, write_uff

__all__ = [*_model_all, "write_uff", "read_uff", "read_uff_modes", "UffModes", "frac", "frequency_shift", "write_csv",
           "read_csv", "write_matlab", "read_matlab", "MatlabSystem"]


def __getattr__(name: str) -> Any:
    # frac and frequency_shift compare two frequency responses (vibss.frequency.compare); they stay
    # importable here, where the test data they score is read
    if name in ("frac", "frequency_shift"):
        from ..frequency.compare import frac, frequency_shift
        return {"frac": frac, "frequency_shift": frequency_shift}[name]
    if name in ("write_matlab", "read_matlab", "MatlabSystem"):
        # the MATLAB writer builds the state space of a plant or model: a higher layer than io
        from .matlab import MatlabSystem, read_matlab, write_matlab
        return {"write_matlab": write_matlab, "read_matlab": read_matlab, "MatlabSystem": MatlabSystem}[name]
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
