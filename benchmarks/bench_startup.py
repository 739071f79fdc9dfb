"""Start-up time of the command line, against ``python -c "import numpy"`` in the same run.

Each command runs in a fresh interpreter (best of 7 wall-clock runs); the issue's targets are
``vibss --help`` under 0.3 s and ``vibss modes --example prism`` under 1 s on the 2-core machine, and
(issue 34) ``vibss modes`` within 3x ``python -c "import numpy, scipy.linalg"``.
Run: ``python benchmarks/bench_startup.py``.
"""

from __future__ import annotations

import subprocess
import sys
import time

RUNS = 7
CASES = [
    ("python -c 'import numpy'", [sys.executable, "-c", "import numpy"]),
    ("python -c 'import numpy, scipy.linalg'", [sys.executable, "-c", "import numpy, scipy.linalg"]),
    ("python -c 'import vibss'", [sys.executable, "-c", "import vibss"]),
    ("vibss --help", [sys.executable, "-m", "vibss", "--help"]),
    ("vibss modes --example prism", [sys.executable, "-m", "vibss", "modes", "--example", "prism"]),
    ("vibss frf --example prism (python-control loaded)",
     [sys.executable, "-m", "vibss", "frf", "--example", "prism", "--input", "prism.fz", "--output", "prism.z"]),
]


def best(cmd: list[str]) -> float:
    times = []
    for _ in range(RUNS):
        t = time.perf_counter()
        subprocess.run(cmd, check=True, capture_output=True)
        times.append(time.perf_counter() - t)
    return min(times)


def bench(quick: bool) -> dict:
    """Each command's best of RUNS cold starts (``quick`` changes nothing)."""
    res: dict = {}
    base = None
    print(f"{'command':<52} {'best of 7 [s]':>14} {'/ import numpy':>15}")
    for label, cmd in CASES:
        t = best(cmd)
        base = base or t
        print(f"{label:<52} {t:14.3f} {t / base:15.1f}")
        res[label] = {"best_s": t, "over_import_numpy": t / base}
    return res


if __name__ == "__main__":
    from run_all import main_one

    main_one("startup")
