"""Standard shock pulses through the exact modal path, against forced_response and solve_ivp, same run.

Issue 15 item 1. The 20 kg box of docs/studies.md (one vertical isolator mode, 10.07 Hz, 10 %
damping; a chain of 100 such bodies for the cost) under a 30 g, 11 ms half-sine base acceleration and
a haversine, at 3 to 44 samples per pulse. Reference: ``solve_ivp`` (DOP853, rtol 1e-12) of the
single-DOF equation, restarted at the pulse's edges. Seeded (no randomness), one BLAS thread.
Run: ``python benchmarks/bench_pulses.py``.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp
from threadpoolctl import threadpool_limits

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
import vibss  # noqa: E402
from vibss.model.timefunctions import HalfSine, Haversine  # noqa: E402
from benchmarks.models import chain_model  # noqa: E402

M, K, C = 20.0, 8.0e4, 252.0


def box() -> vibss.Model:
    iso = vibss.MountType("iso", stiffness=(1.5e4, 1.5e4, K / 4), damping=(40.0, 40.0, C / 4))
    return vibss.Model([vibss.Body("box", M, (0.25, 0.30, 0.35))],
                       vibss.symmetric(vibss.Mount("iso", iso, "box", at=(0.15, 0.10, 0.0))))


def reference(pulse, ts: np.ndarray) -> np.ndarray:
    def rhs(t, s):
        return [s[1], -float(pulse.value(t)) - (C * s[1] + K * s[0]) / M]
    edges = sorted({0.0, float(ts[-1]), *pulse.breakpoints})
    out, x = np.zeros(ts.size), np.zeros(2)
    for lo, hi in zip(edges[:-1], edges[1:]):
        sel = (ts >= lo) & (ts <= hi)
        sol = solve_ivp(rhs, (lo, hi), x, rtol=1e-12, atol=1e-16, method="DOP853", dense_output=True)
        out[sel] = sol.sol(ts[sel])[0]
        x = sol.y[:, -1]
    return out


def bench(quick: bool) -> dict:
    res: dict = {}
    with threadpool_limits(1):
        for pulse in (HalfSine(30 * 9.80665, duration=0.011), Haversine(30 * 9.80665, duration=0.011)):
            name = type(pulse).__name__
            print(f"{name}, 30 g, 11 ms: relative error of the isolator stroke against solve_ivp (rtol 1e-12)")
            print(f"{'samples/pulse':>14} {'modal (exact)':>14} {'forced_response':>16} {'modal, sampled':>15}")
            for n in (3, 5, 11, 22, 44):
                dt = 0.011 / n
                kw = dict(outputs=["mount.iso.dz"], t_end=0.2, dt=dt)
                exact = vibss.simulate(box(), inputs={"ground.z.acc": pulse}, **kw)
                fr = vibss.simulate(box(), inputs={"ground.z.acc": pulse}, method="forced_response", **kw)
                sampled = vibss.simulate(box(), inputs={"ground.z.acc": lambda t: pulse.value(t)}, **kw)
                ref = reference(pulse, exact.time)
                e = [float(np.abs(r["mount.iso.dz"] - ref).max() / np.abs(ref).max()) for r in (exact, fr, sampled)]
                res[f"{name}_{n}"] = e
                print(f"{n:14d} {e[0]:14.1e} {e[1]:16.1e} {e[2]:15.1e}")
        # cost: a 100-body chain (600 DOF), half-sine force, 2,000 steps: exact pieces vs sampled
        model = chain_model(100, seed=1)
        pulse = HalfSine(100.0, start=0.001, duration=0.011)
        kw = dict(outputs=["b0.z", "b50.z"], t_end=0.2, dt=1e-4)
        vibss.simulate(model, inputs={"b0.fz": pulse}, **kw)
        t = time.perf_counter()
        vibss.simulate(model, inputs={"b0.fz": pulse}, **kw)
        t_exact = time.perf_counter() - t
        t = time.perf_counter()
        vibss.simulate(model, inputs={"b0.fz": lambda x: pulse.value(x)}, **kw)
        t_sampled = time.perf_counter() - t
        t = time.perf_counter()
        vibss.simulate(model, inputs={"b0.fz": pulse}, method="forced_response", **kw)
        t_fr = time.perf_counter() - t
    res.update(exact_s=t_exact, sampled_s=t_sampled, forced_response_s=t_fr)
    print(f"600 DOF, 2,000 steps: modal with the exact sine piece {t_exact:.2f} s, modal sampled {t_sampled:.2f} s, "
          f"forced_response {t_fr:.2f} s ({t_fr / t_exact:.1f}x the exact path)")
    return res


if __name__ == "__main__":
    from run_all import main_one

    main_one("pulses")
