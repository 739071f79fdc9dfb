"""Machine, library and thread description stamped on every benchmark figure and table.

Benchmarks run single-threaded (``threadpoolctl.threadpool_limits(1)`` around every timed call,
and ``OPENBLAS_NUM_THREADS=1`` set by ``run_all.py`` before numpy loads): on the shared 2-core
machine threaded OpenBLAS made small calls erratic (see docs/performance.md).
"""

from __future__ import annotations

import os
import platform
import textwrap
import time
from collections.abc import Callable
from typing import Any

import control
import matplotlib
import numpy as np
import scipy
from threadpoolctl import threadpool_info, threadpool_limits

__all__ = ["machine", "machine_line", "stamp", "timed", "THREADS"]

THREADS = 1
"""BLAS threads used for every timing."""


def _cpu() -> str:
    try:
        with open("/proc/cpuinfo") as fh:
            for line in fh:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def machine() -> dict[str, Any]:
    """CPU model, core count, library versions, thread settings (JSON-able)."""
    try:
        import slycot
        slycot_v = slycot.__version__
    except ImportError:  # pragma: no cover
        slycot_v = "absent"
    pools = [f"{i.get('internal_api')} {i.get('version')}" for i in threadpool_info()]
    return {"cpu": _cpu(), "cores": os.cpu_count(), "python": platform.python_version(),
            "numpy": np.__version__, "scipy": scipy.__version__, "control": control.__version__,
            "slycot": slycot_v, "matplotlib": matplotlib.__version__,
            "blas": sorted(set(pools)), "threads_per_timing": THREADS,
            "OPENBLAS_NUM_THREADS": os.environ.get("OPENBLAS_NUM_THREADS", "unset"),
            "load_average_at_start": os.getloadavg()[0]}


def machine_line() -> str:
    """One line for figure footers and tables."""
    m = machine()
    return (f"{m['cpu']}, {m['cores']} cores; Python {m['python']}, numpy {m['numpy']}, scipy "
            f"{m['scipy']}, control {m['control']}, slycot {m['slycot']}; {', '.join(m['blas'])}; "
            f"{THREADS} BLAS thread (threadpoolctl), load {m['load_average_at_start']:.1f}")


def stamp(fig: Any) -> None:
    """Write the machine line at the bottom of a matplotlib figure."""
    width = max(60, int(fig.get_figwidth() * 22))          # characters per line at 6 pt
    fig.text(0.005, 0.003, "\n".join(textwrap.wrap(machine_line(), width)), fontsize=6, color="0.4",
             ha="left", va="bottom")


def timed(f: Callable[[], Any], min_time: float = 0.2, repeat: int = 3) -> tuple[float, Any]:
    """(best wall time [s], result) of ``f``, single-threaded; repeats only calls faster than ``min_time``."""
    with threadpool_limits(THREADS):
        t0 = time.perf_counter()
        out = f()
        best = time.perf_counter() - t0
        if best < min_time:
            for _ in range(repeat - 1):
                t0 = time.perf_counter()
                out = f()
                best = min(best, time.perf_counter() - t0)
    return best, out
