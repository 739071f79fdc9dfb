"""Time response: python-control ``forced_response`` against the exact modal path, in one run.

``chain_model(100)`` (600 DOF, 1200 states), 2 force inputs, 6 displacement outputs, 10,000 steps of
dt = 2e-4 s, piecewise-linear random forces; classical and general (non-proportional) damping. Then
one modal run of ``chain_model(1000)`` (6000 DOF; forced_response is not run there). BLAS is limited
to one thread for every timing. Results are printed and written to benchmarks/results/time.json.

Run: ``OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/bench_time.py [--quick]``
"""

from __future__ import annotations

import argparse
import json
import platform
import sys
import time
from pathlib import Path

import numpy as np
from threadpoolctl import threadpool_limits

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from models import chain_model  # noqa: E402
from machine import timed  # noqa: E402

from vibss.linear.signals import build_plant  # noqa: E402
from vibss.time.api import simulate  # noqa: E402

DT, STEPS = 2e-4, 10_000


def case(n_bodies: int, damping: str, run_reference: bool, seed: int = 1) -> dict:
    model = chain_model(n_bodies, damping=damping)
    inputs = [f"b{n_bodies // 3}.fz", f"b{2 * n_bodies // 3}.fx"]
    outputs = [f"b{n_bodies // 3}.{d}" for d in ("x", "y", "z", "rx", "ry", "rz")]
    t0 = time.perf_counter()
    plant = build_plant(model, inputs, outputs)
    t_plant = time.perf_counter() - t0
    rng = np.random.default_rng(seed)
    u = {name: np.cumsum(rng.normal(0.0, 20.0, STEPS + 1)) for name in inputs}   # PWL random walk [N]
    kw = dict(inputs=u, t_end=STEPS * DT, dt=DT)
    out = {"model": model.name, "dof": plant.n, "states": 2 * plant.n, "steps": STEPS, "dt": DT,
           "inputs": len(inputs), "outputs": len(outputs), "build_plant_s": round(t_plant, 3)}
    repeat = 2 if run_reference else 1      # best of two for both sides of the ratio (no warm-up)
    with threadpool_limits(1):
        out["modal_s"], modal = timed(lambda: simulate(plant, method="modal", **kw), min_time=float("inf"), repeat=repeat)
        out["modal_note"] = modal.note
        if run_reference:
            out["forced_response_s"], ref = timed(lambda: simulate(plant, method="forced_response", **kw),
                                                min_time=float("inf"), repeat=repeat)
            out["speedup"] = round(out["forced_response_s"] / out["modal_s"], 1)
            scale = np.abs(ref.outputs).max(axis=1, keepdims=True)
            out["max_rel_diff"] = float((np.abs(modal.outputs - ref.outputs) / scale).max())
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--quick", action="store_true", help="skip the 6000-DOF run")
    args = parser.parse_args()
    results = {"python": platform.python_version(), "machine": platform.processor() or platform.machine(),
               "cases": []}
    for damping in ("classical", "general"):
        r = case(100, damping, run_reference=True)
        results["cases"].append(r)
        print(f"{r['dof']} DOF, {damping:9s}: forced_response {r['forced_response_s']:7.2f} s, "
              f"modal {r['modal_s']:6.3f} s, speed-up {r['speedup']:6.1f}x, "
              f"max rel. diff {r['max_rel_diff']:.1e}")
    if not args.quick:
        r = case(1000, "classical", run_reference=False)
        results["cases"].append(r)
        print(f"{r['dof']} DOF, classical: modal {r['modal_s']:.2f} s (build_plant {r['build_plant_s']:.2f} s)")
    path = Path(__file__).resolve().parent / "results" / "time.json"
    path.parent.mkdir(exist_ok=True)
    path.write_text(json.dumps(results, indent=2) + "\n")
    print(f"written {path}")


if __name__ == "__main__":
    main()
