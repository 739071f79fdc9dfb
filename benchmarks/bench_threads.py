"""BLAS threads beside a busy core: why vibss holds BLAS to one thread while it computes (vibss.threads).

OpenBLAS (NumPy's and SciPy's copies) splits a product over the cores and waits for every part; when
another process holds a core, each threaded call waits for that core's next time slice. Measured here
on the same calls with the pools on one and on two threads, on an idle machine and beside a busy
loop (a second Python process spinning on one core, at the same priority and at nice -5):

- the stock calls: a batch of 256 ``scipy.linalg.expm`` of 24 x 24 matrices (a harmonic-balance
  monodromy's chunk), twenty 200 x 200 products, dense ``eigh`` at 1,000 / 2,000 / 3,000 (the last
  two what :data:`vibss.threads.THREADED_DOFS` gives back the threads for);
- vibss: the snubbed cabinet's harmonic balance as its file asks (12 points), with the pools on two
  threads, with vibss's one-thread limiter and without it (the limiter patched out: the path before).

Run: ``python benchmarks/bench_threads.py [--quick]`` (``--quick``: eigh to 2,000, no cabinet without
the limiter beside the busy core).
"""

from __future__ import annotations

import contextlib
import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np
import scipy.linalg as sl
from threadpoolctl import threadpool_limits

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from run_all import best  # noqa: E402

import vibss  # noqa: E402
import vibss.nonlinear.harmonic as hb  # noqa: E402
from vibss.io.harmonicfile import harmonic_balance_arguments  # noqa: E402


@contextlib.contextmanager
def busy_core(priority: int = 0) -> Iterator[None]:
    """A second process spinning on one core for the duration, at nice ``-priority`` (a job of higher
    priority, as a benchmark run at nice -5 was beside this session's work)."""
    p = subprocess.Popen([sys.executable, "-c", f"import os; os.nice({-priority}); exec('while True: pass')"])
    time.sleep(0.3)
    try:
        yield
    finally:
        p.kill()
        p.wait()


def _cabinet(limited: bool) -> Callable[[], Any]:
    model = vibss.load_example("snubbed_cabinet")
    args = harmonic_balance_arguments(model.settings["harmonic_balance"], model.excitations)
    args["points"] = 12

    def run() -> Any:
        if limited:
            return hb.harmonic_balance(model, **args)
        saved = hb.one_blas_thread
        hb.one_blas_thread = contextlib.nullcontext        # the path before vibss.threads
        try:
            return hb.harmonic_balance(model, **args)
        finally:
            hb.one_blas_thread = saved
    return run


def bench(quick: bool) -> dict:
    """Each call on one and two BLAS threads, idle and beside a busy core [s] (best of 3; the
    cabinet without the limiter beside the busy core once)."""
    rng = np.random.default_rng(0)
    batch = rng.normal(size=(256, 24, 24)) * 0.1
    X = rng.normal(size=(200, 200))
    cases: dict[str, tuple[Callable[[], Any], int]] = {
        "expm 256 x (24 x 24)": (lambda: sl.expm(batch), 3),
        "20 products 200 x 200": (lambda: [X @ X for _ in range(20)], 3),
    }
    for n in (1000, 2000) if quick else (1000, 2000, 3000):
        a = rng.normal(size=(n, n))
        a = a + a.T
        cases[f"eigh {n} x {n}"] = ((lambda a=a: sl.eigh(a, driver="evd", check_finite=False)), 2)
    cases["vibss cabinet harmonic balance (vibss.threads)"] = (_cabinet(True), 2)
    cases["same, limiter patched out"] = (_cabinet(False), 1)
    out: dict = {}
    loads = {"idle": None, "busy": 0, "busy_priority": 5}
    print(f"{'call':<48} " + " ".join(f"{k.replace('_priority', '+5')[:6] + ' ' + str(t):>9}" for k in loads for t in (1, 2))
          + "   [s], pools on 1 / 2 threads; busy+5: the spinner at nice -5")
    for name, (f, repeat) in cases.items():
        row = {}
        for load, prio in loads.items():
            with busy_core(prio) if prio is not None else contextlib.nullcontext():
                for threads in (1, 2):
                    if quick and load != "idle" and threads == 2 and name.startswith("same"):
                        row[f"{load}_{threads}"] = None
                        continue
                    with threadpool_limits(limits=threads):
                        row[f"{load}_{threads}"] = best(f, repeat)[0]
        out[name] = row
        print(f"{name:<48} " + " ".join(f"{v:9.3f}" if v is not None else f"{'-':>9}" for v in row.values()))
    return out


if __name__ == "__main__":
    from run_all import main_one

    main_one("threads")
