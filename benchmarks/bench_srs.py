"""SRS of a 1,000,000-sample record at 100 natural frequencies (Q = 10): ``vibss.srs`` against the naive
per-frequency loop (``scipy.signal.lfilter`` then ``max(abs(y))``) and against ``scipy.signal.lsim`` of
each single-DOF oscillator (the stock state-space route), same run.

Record: seeded white noise, dt = 10 us (10 s). lsim runs on the first 100,000 samples at 5 frequencies
and is scaled to the full problem (it is linear in both). Accuracy: vibss against lsim on that subset.
One BLAS thread. Run: ``python benchmarks/bench_srs.py``.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np
import scipy.signal as ss
from threadpoolctl import threadpool_limits

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
import vibss  # noqa: E402
from vibss.shock.kernels import _coefficients  # noqa: E402


def bench(quick: bool) -> dict:
    rng = np.random.default_rng(0)
    dt, n = 1e-5, 1_000_000
    t = np.arange(n) * dt
    x = rng.standard_normal(n)
    f = np.geomspace(10.0, 4000.0, 100)
    with threadpool_limits(1):
        vibss.srs(t[:1000], x[:1000], [1000.0])           # imports
        t0 = time.perf_counter()
        r = vibss.srs(t, x, f, q=10.0, kind="primary")
        tv = time.perf_counter() - t0
        t0 = time.perf_counter()
        naive = [np.max(np.abs(ss.lfilter(*_coefficients(fn, 0.05, dt), x))) for fn in f]
        tn = time.perf_counter() - t0
        sub, fs = 100_000, f[::20]
        t0 = time.perf_counter()
        ref = []
        for fn in fs:
            w = 2 * np.pi * fn
            sdof = ss.lti([2 * 0.05 * w, w * w], [1.0, 2 * 0.05 * w, w * w])   # absolute acceleration / base
            _, y, _ = ss.lsim(sdof, x[:sub], t[:sub], interp=True)
            ref.append(np.max(np.abs(y)))
        tl = (time.perf_counter() - t0) * (n / sub) * (f.size / fs.size)
        rs = vibss.srs(t[:sub], x[:sub], fs, q=10.0, kind="primary")
    err = float(np.max(np.abs(rs.response - np.array(ref)) / np.array(ref)))
    diff = float(np.max(np.abs(r.response - np.array(naive)) / np.array(naive)))
    print(f"SRS, 1,000,000 samples x 100 frequencies (Q = 10):")
    print(f"  vibss.srs                      {tv:7.3f} s")
    print(f"  naive lfilter + max(abs) loop  {tn:7.3f} s   ratio {tn / tv:.2f}x   (agree to {diff:.1e})")
    print(f"  scipy.signal.lsim per SDOF     {tl:7.1f} s (scaled from 100k samples x 5 frequencies)   ratio {tl / tv:.0f}x")
    print(f"  vibss against lsim on the subset: {err:.1e} relative")
    return {"vibss_s": tv, "naive_s": tn, "lsim_scaled_s": tl, "error_vs_lsim": err}


if __name__ == "__main__":
    from run_all import main_one

    main_one("srs")
