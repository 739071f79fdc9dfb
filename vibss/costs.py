"""The cost model's constants as data: ``vibss/data/costs.json``, re-measured by ``make bench``.

The seconds a method is estimated to take (its :class:`~vibss.methods.Cost`, which ``auto`` ranks
methods by and the guards read) are formulas in the problem's sizes times constants measured on one
core. The constants live in ``vibss/data/costs.json`` (package data), not in the code:
benchmarks/bench_costs.py times every method on the benchmark suite (chain, grid, tree, 3-D lattice,
random graph, mechanism chain, soft tower), fits each method's ``scale`` (the geometric mean of
measured over estimated seconds) and rewrites the file. Each module reads its constants here at
import, falling back to the value it ships (``constant(name, default)``) when the file or the entry
is missing or unreadable.
"""

from __future__ import annotations

import json
import math
from functools import lru_cache
from pathlib import Path
from typing import Any

__all__ = ["PATH", "table", "constant", "scale"]

PATH = Path(__file__).resolve().parent / "data" / "costs.json"
"""The data file (``{"constants": {name: value}, "scale": {method: factor}, "measured": text}``)."""


@lru_cache(maxsize=1)
def table() -> dict[str, Any]:
    """The parsed data file, ``{}`` when it is missing or unreadable (the shipped values then hold)."""
    try:
        data = json.loads(PATH.read_text())
    except (OSError, ValueError):
        return {}
    return data if isinstance(data, dict) else {}


def _number(value: Any, default: float) -> float:
    try:
        x = float(value)
    except (TypeError, ValueError):
        return default
    return x if math.isfinite(x) and x > 0 else default


def constant(name: str, default: float) -> float:
    """The constant ``name`` (e.g. ``"frequency.K_DENSE_LU"``) from the data file, else ``default``.

    Parameters
    ----------
    name : str
        ``"<module>.<CONSTANT>"``.
    default : float
        The shipped value [its unit: seconds per operation count, or operations per second].

    Returns
    -------
    float
    """
    return _number(table().get("constants", {}).get(name, default), default)


def scale(method: str) -> float:
    """The measured-over-estimated factor of ``method``'s cost formula (``"frequency.sparse"``,
    ``"time.modal"`` ...), 1 when not measured [-]."""
    return _number(table().get("scale", {}).get(method, 1.0), 1.0)
