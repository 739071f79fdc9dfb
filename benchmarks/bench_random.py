"""Random-vibration benchmark: RMS of 6 outputs of a 600-DOF chain under a base-acceleration PSD,
vibss.random_response (adaptive grid on the exact modal FRF) against the stock route (python-control's
``frequency_response`` of the same state space on a fixed log grid, then a trapezoid), same run.

Model: ``chain_model(100, zeta=0.01)`` (600 DOF), input ``ground.z.acc`` with a MIL-STD-810-like
PSD (0.01 g²/Hz at 5 Hz rising to 0.04 g²/Hz at 20 ... 500 Hz, falling to 0.01 at 2000 Hz),
outputs the z acceleration of six bodies. Reference: vibss at rtol = 1e-8. The stock route is
run on log grids of 2,000 ... 64,000 frequencies; the ratio compares vibss at rtol = 1e-6 with the
smallest stock grid that is at least as accurate (or the largest tried). One BLAS thread.
``--quick``: a 20-body chain (120 DOF) and stock grids up to 16,000 points, for ``make bench-quick``.
Run: ``python benchmarks/bench_random.py [--quick]``.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import control
import numpy as np
from threadpoolctl import threadpool_limits

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from benchmarks.models import chain_model  # noqa: E402
from vibss.linear.plant.build import build_plant  # noqa: E402
from vibss.linear.statespace import statespace  # noqa: E402
from vibss.random import PSD, random_response  # noqa: E402

SPEC = PSD([5.0, 20.0, 500.0, 2000.0], [0.01, 0.04, 0.04, 0.01])
QUICK = "--quick" in sys.argv
N_BODIES = 20 if QUICK else 100
OUTPUTS = [f"b{i}.z.acc" for i in ((0, 4, 8, 12, 16, 19) if QUICK else (0, 20, 40, 60, 80, 99))]


def stock(plant, n: int) -> tuple[np.ndarray, float]:
    t = time.perf_counter()
    sys_ = statespace(plant)
    f = np.geomspace(*SPEC.band, n)
    h = np.asarray(control.frequency_response(sys_, 2 * np.pi * f).complex)[:, 0, :]
    s = np.abs(h) ** 2 * SPEC(f)
    ms = np.trapezoid(s, f, axis=1)
    return np.sqrt(ms), time.perf_counter() - t


def main() -> None:
    with threadpool_limits(1):
        model = chain_model(N_BODIES, zeta=0.01)
        plant = build_plant(model, ["ground.z.acc"], OUTPUTS)
        ref = random_response(plant, {"ground.z.acc": SPEC}, rtol=1e-8).rms
        best = np.inf
        for _ in range(2):
            t = time.perf_counter()
            r = random_response(plant, {"ground.z.acc": SPEC}, rtol=1e-6)
            best = min(best, time.perf_counter() - t)
        err = np.max(np.abs(r.rms - ref) / ref)
        print(f"{6 * N_BODIES} DOF, {len(OUTPUTS)} outputs, PSD {SPEC.band[0]:g}-{SPEC.band[1]:g} Hz, zeta 0.01")
        print(f"vibss.random_response rtol 1e-6: {best:7.3f} s, {r.frequency_hz.size} frequencies, max rel. RMS error {err:.1e}")
        chosen = None
        for n in (2000, 4000, 8000, 16000) + (() if QUICK else (32000, 64000)):
            rms, ts = stock(plant, n)
            e = np.max(np.abs(rms - ref) / ref)
            print(f"stock control.frequency_response + trapezoid, {n:6d} log-spaced: {ts:7.3f} s, max rel. RMS error {e:.1e}")
            if chosen is None and e <= err:
                chosen = (n, ts, e)
            last = (n, ts, e)
            if chosen:
                break
        n, ts, e = chosen or last
        tag = "at least as accurate" if chosen else "still less accurate"
        print(f"ratio: stock {n} points ({tag}) / vibss = {ts / best:.1f}x")


if __name__ == "__main__":
    main()
