"""Robustness benchmark: ``vibss.control.robustness`` on a 600-DOF platform with 4 skyhook loops and
1,000 variants of 8 mount rates (+-20 %), against the stock route in the same run.

- vibss: ``robustness(..., method="lft")``: the rate changes as an internal feedback on the nominal
  loop (frequency responses exact; the lowest 120 closed-loop poles solved per variant in one batched
  eigen-solve, the rest held), 1,200 frequencies, plus the 2^6 corners of the most sensitive rates;
- stock: every variant rebuilt (``vibss.design.parameters.apply``, ``vibss.control.plant``), the loop
  closed again with its full eigenvalues and the same frequency grid (``method="rebuild"``), timed on
  a few variants and scaled to 1,000.

Accuracy: the lft metrics (damping, disk margin, peak transmissibility) of the same variants
against the rebuilt ones (largest relative difference), and the lft self-check.
Model: ``chain_model(100, zeta=0.01)`` with actuators and geophones at the ground mounts of bodies
0, 25, 50, 75 (``--quick``: 20 bodies, 120 DOF, 200 variants). One BLAS thread.
Run: ``python benchmarks/bench_robust.py [--quick]``.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np
from threadpoolctl import threadpool_limits

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from benchmarks.models import chain_model  # noqa: E402
import vibss  # noqa: E402
import vibss.control as vc  # noqa: E402
from vibss import Actuator, Sensor  # noqa: E402

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


def bench(quick: bool) -> dict:
    nb, nv, n_stock = (20, 200, 3) if quick else (100, 1000, 3)
    with threadpool_limits(1):
        m, names = platform(nb)
        P = vc.plant(m, ["ground.z.vel"], performance=["b0.z.vel"])
        K = vc.skyhook(P, GAIN)
        tol = {p: 0.2 for p in names}
        t = time.perf_counter()
        r = vc.robustness(P, K, tol, n=nv, seed=0)
        t_lft = time.perf_counter() - t
        # the stock route on the first few samples, same grid
        sub = {k: v for k, v in tol.items()}
        t = time.perf_counter()
        s = vc.robustness(P, K, sub, n=n_stock, seed=0, method="rebuild", corners=0, frequencies=r.frequency_hz)
        t_stock = (time.perf_counter() - t) * (nv + int(r.corner.sum())) / n_stock
        q = vc.robustness(P, K, sub, n=n_stock, seed=0, method="lft", corners=0, frequencies=r.frequency_hz)
    errs = {k: float(np.max(np.abs(getattr(q, k) - getattr(s, k)) / np.abs(getattr(s, k))))
            for k in ("damping", "disk_margin", "mimo_disk_margin", "peak")}
    out = {"dof": 6 * nb, "loops": 4, "variants": nv, "corners": int(r.corner.sum()), "lft_s": t_lft,
           "stock_s_scaled": t_stock, "ratio_stock_over_lft": t_stock / t_lft, "p_stable": r.p_stable,
           "check": r.check.error if r.check else None, **{f"error_{k}": v for k, v in errs.items()},
           "note": r.note}
    print(f"{6 * nb} DOF, 4 skyhook loops, {len(names)} rates +-20 %: {nv} variants + {out['corners']} corners")
    print(f"  vibss robustness (lft)    {t_lft:8.2f} s   P(stable) = {r.p_stable:.3f}")
    print(f"  stock rebuild per variant {t_stock:8.2f} s (scaled from {n_stock})   ratio {t_stock / t_lft:.1f}")
    print("  lft against rebuild: " + ", ".join(f"{k} {v:.1e}" for k, v in errs.items()))
    print(f"  self-check: {r.check.text() if r.check else '-'}")
    print(f"  {r.note}")
    print(r.table.render())
    return out


if __name__ == "__main__":
    from run_all import main_one

    main_one("robust")
