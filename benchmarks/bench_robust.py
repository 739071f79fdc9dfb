"""Robustness benchmark: ``vibss.control.robustness`` on a 600-DOF platform with 4 skyhook loops and
1,000 variants of 8 mount rates (+-20 %), against the stock route in the same run.

- vibss: ``robustness(..., method="lft")``: the rate changes as an internal feedback on the nominal
  loop (frequency responses exact; of the lowest 120 closed-loop poles those the rate channels see
  solved per variant in one batched eigen-solve, the rest held), 401 frequencies, plus the 2^6 corners
  of the most sensitive rates;
- stock: every variant rebuilt (``vibss.design.parameters.apply``, ``vibss.control.plant``) and closed
  with ``vibss.control.close`` (full eigenvalues, margins on its own grid), the peak transmissibility
  the largest ``|T|`` on the same grid, resolved on 2,001 points between the largest sample's
  neighbours; timed on 3 variants and scaled to all of them.

Accuracy: the lft metrics of the same variants against the stock ones (largest relative difference:
damping exact both ways; the disk margins on close()'s own grid and lft's refined one; the peak
against the resolved one, beside the grid's own largest sample, ``peak_grid_only``), and the lft
self-check.
Model: ``chain_model(100, zeta=0.01)`` with actuators and geophones at the ground mounts of bodies
0, 25, 50, 75 (``--quick``: 20 bodies, 120 DOF, 200 variants). One BLAS thread.
Run: ``python benchmarks/bench_robust.py [--quick]``.
"""

from __future__ import annotations

import sys
import time
import warnings
from pathlib import Path

import numpy as np
from threadpoolctl import threadpool_limits

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from benchmarks.models import chain_model  # noqa: E402
import vibss  # noqa: E402
import vibss.control as vc  # noqa: E402
from vibss import Actuator, Sensor  # noqa: E402
from vibss.design.parameters import apply, parameters_of  # noqa: E402
from vibss.frequency.statespace_response import evaluate  # noqa: E402

GAIN = 2000.0


def platform(n: int) -> tuple[vibss.Model, list[str]]:
    """The chain with 4 collocated loops, and the 8 ground-mount rates toleranced."""
    m = chain_model(n, zeta=0.01)
    ground = [x for x in m.mounts if x.to == "ground"]
    picks = [next(x for x in ground if x.body == f"b{i}") for i in range(0, n, n // 4)][:4]
    acts = [Actuator(f"a{i}", mount=x.name, axis=3) for i, x in enumerate(picks)]
    sens = [Sensor(f"g{i}", "velocity", body=x.body, at=x.at, frame=x.frame, direction=x.orientation.matrix[:, 2])
            for i, x in enumerate(picks)]
    extra = [x for x in ground if x not in picks][:4]
    names = [f"{x.name}.k3" for x in picks + extra]
    return m.replace(actuators=acts, sensors=sens), names


def stock_variant(m: vibss.Model, params: tuple, values: np.ndarray, K: object, grid_hz: np.ndarray) -> dict:
    """One variant the stock way: apply the values, build the plant, close (poles, margins), and the
    peak transmissibility on the grid (no refinement)."""
    mv = apply(m, params, values)
    P = vc.plant(mv, ["ground.z.vel"], performance=["b0.z.vel"])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cl = vc.close(P, K)
    j = cl.system.input_labels.index("ground:z:vel")
    o = cl.system.output_labels.index("b0:z:vel")
    h = np.abs(evaluate(cl.system, 2 * np.pi * grid_hz, outputs=[o], inputs=[j])[0, 0])
    i = int(np.argmax(h))                    # the peak resolved on 2,001 points between the grid's neighbours
    fine = np.linspace(grid_hz[max(i - 1, 0)], grid_hz[min(i + 1, grid_hz.size - 1)], 2001)
    hf = np.abs(evaluate(cl.system, 2 * np.pi * fine, outputs=[o], inputs=[j])[0, 0])
    return {"damping": float(cl.damping.min()), "disk_margin": min(x.disk_margin for x in cl.margins),
            "mimo_disk_margin": float(cl.mimo_disk_margin), "peak": float(max(h.max(), hf.max())),
            "peak_on_grid": float(h.max())}


def bench(quick: bool) -> dict:
    nb, nv, n_stock = (20, 200, 3) if quick else (100, 1000, 3)
    with threadpool_limits(1):
        m, names = platform(nb)
        P = vc.plant(m, ["ground.z.vel"], performance=["b0.z.vel"])
        K = vc.skyhook(P, GAIN)
        tol = {p: 0.2 for p in names}
        t, c = time.perf_counter(), time.process_time()
        r = vc.robustness(P, K, tol, n=nv, seed=0)
        t_lft, c_lft = time.perf_counter() - t, time.process_time() - c
        # the stock route on the first few samples: rebuild, plant, close (poles and margins), the peak on
        # the same grid
        params = parameters_of(m, list(tol))
        grid = r.frequency_hz
        t, c = time.perf_counter(), time.process_time()
        stock = [stock_variant(m, params, r.values[i], K, grid) for i in range(n_stock)]
        scale = (nv + int(r.corner.sum())) / n_stock
        t_stock, c_stock = (time.perf_counter() - t) * scale, (time.process_time() - c) * scale
    s = {k: np.array([x[k] for x in stock]) for k in stock[0]}
    grid_peak = s.pop("peak_on_grid")
    q = {k: getattr(r, k)[:n_stock] for k in s}
    errs = {k: float(np.max(np.abs(q[k] - s[k]) / np.abs(s[k]))) for k in s}
    errs["peak_grid_only"] = float(np.max(np.abs(grid_peak - s["peak"]) / s["peak"]))
    nall = nv + int(r.corner.sum())
    out = {"dof": 6 * nb, "loops": 4, "variants": nv, "variants_per_cpu_s": nall / c_lft, "variants_per_s": nall / t_lft, "corners": int(r.corner.sum()), "lft_s": t_lft, "lft_cpu_s": c_lft,
           "stock_s_scaled": t_stock, "stock_cpu_s_scaled": c_stock, "ratio_stock_over_lft": t_stock / t_lft, "p_stable": r.p_stable,
           "check": r.check.error if r.check else None, **{f"error_{k}": v for k, v in errs.items()},
           "note": r.note}
    print(f"{6 * nb} DOF, 4 skyhook loops, {len(names)} rates +-20 %: {nv} variants + {out['corners']} corners")
    print(f"  vibss robustness (lft)    {t_lft:8.2f} s (CPU {c_lft:.2f} s; {nall / c_lft:.0f} variants per CPU s)   "
          f"P(stable) = {r.p_stable:.3f}")
    print(f"  stock plant+close per variant {t_stock:8.2f} s (CPU {c_stock:.1f} s; scaled from {n_stock})   "
          f"ratio {t_stock / t_lft:.1f}")
    print("  lft against stock: " + ", ".join(f"{k} {v:.1e}" for k, v in errs.items()))
    print(f"  self-check: {r.check.text() if r.check else '-'}")
    print(f"  {r.note}")
    print(r.table.render())
    return out


if __name__ == "__main__":
    from run_all import main_one

    main_one("robust")
