"""Time response: python-control ``forced_response`` against the exact modal path, per topology, in one run.

For each topology of :mod:`models` (``chain``, 10-wide ``grid``, random ``tree``, 3-D ``lattice``,
``random`` graph, ``mechanism`` chain, soft ``tower``: :data:`SUITE`) at 100 bodies (600 DOF, 1200 states), classical and general (non-proportional) damping: 2 force inputs (seeded
piecewise-linear random walks), 6 displacement outputs, 10,000 steps of dt = 2e-4 s. Both methods
are timed *cold* (a fresh plant each repeat, so each pays its own eigen-analysis, as a user's first
call does; best of ``--repeat``), BLAS limited to one thread. The error column is the largest
difference between the two, relative to each output's peak: ``forced_response`` is an independent
exact first-order hold (``expm`` of the 1200-state matrix, a dense step-by-step recursion), so it
bounds the error of the modal path. Then one modal run of a 1000-body chain (6000 DOF;
``forced_response`` is not run there). Results go to benchmarks/results/time.json.

The floor of any modal path is timed in the same run: the bare eigen solve (``scipy.linalg.eigh(K,
M)`` for classical damping; ``scipy.linalg.eig`` of the 1200-state matrix ``[[0, I], [-M^-1 K,
-M^-1 C]]``, right vectors only, for general damping) plus the recursion (``simulate`` again on the
same plant, its modes kept: the time path alone). ``floor ratio`` is ``forced_response`` over that sum:
the most a modal path that pays one eigen solve can reach.

Run: ``OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/bench_time.py [--quick] [--topology grid]``
"""

from __future__ import annotations

import json
import platform
import sys
import time
from pathlib import Path

import numpy as np
import scipy.linalg as sl
from threadpoolctl import threadpool_limits

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from models import NEW_TOPOLOGIES, TOPOLOGIES, topology_model  # noqa: E402

SUITE = TOPOLOGIES + NEW_TOPOLOGIES
"""Every topology of the suite: the three of issue 17 and the four of issue 34 (3-D lattice, random
graph, mechanism chain, soft tower)."""

from vibss.linear.plant.build import build_plant  # noqa: E402
from vibss.time.api import simulate  # noqa: E402

DT, STEPS = 2e-4, 10_000


def _cold(model, inputs, outputs, method: str, kw: dict, repeat: int) -> tuple[float, object]:
    """Best wall time of ``simulate`` on a fresh plant (no cached eigen-analysis) [s], and the result."""
    best, res = np.inf, None
    for _ in range(repeat):
        plant = build_plant(model, inputs, outputs)
        t0 = time.perf_counter()
        res = simulate(plant, method=method, **kw)
        best = min(best, time.perf_counter() - t0)
    return best, res


def _best(f, repeat: int) -> float:
    """Best wall time of ``f()`` over ``repeat`` calls [s]."""
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        f()
        best = min(best, time.perf_counter() - t0)
    return best


def _floor(plant, damping: str, kw: dict, repeat: int) -> tuple[float, float]:
    """(bare eigen solve, time path with the modes kept) [s] for the plant."""
    K, M, C = (np.asarray(x, float) for x in (plant.K, plant.M, plant.C))
    if damping == "classical":
        t_eig = _best(lambda: sl.eigh(K, M, check_finite=False), repeat)
    else:
        n = K.shape[0]
        a = np.zeros((2 * n, 2 * n))
        a[:n, n:] = np.eye(n)
        a[n:, :n] = -np.linalg.solve(M, K)
        a[n:, n:] = -np.linalg.solve(M, C)
        t_eig = _best(lambda: sl.eig(a, right=True, check_finite=False), max(1, repeat // 2))
    simulate(plant, method="modal", **kw)                          # the modes, kept on the plant
    t_rec = _best(lambda: simulate(plant, method="modal", **kw), repeat)
    return t_eig, t_rec


def case(kind: str, n_bodies: int, damping: str, run_reference: bool, repeat: int, seed: int = 1,
         floors: bool = True) -> dict:
    model = topology_model(kind, n_bodies, damping=damping)
    inputs = [f"b{n_bodies // 3}.fz", f"b{2 * n_bodies // 3}.fx"]
    outputs = [f"b{n_bodies // 3}.{d}" for d in ("x", "y", "z", "rx", "ry", "rz")]
    t0 = time.perf_counter()
    plant = build_plant(model, inputs, outputs)
    t_plant = time.perf_counter() - t0
    rng = np.random.default_rng(seed)
    u = {name: np.cumsum(rng.normal(0.0, 20.0, STEPS + 1)) for name in inputs}   # PWL random walk [N]
    kw = dict(inputs=u, t_end=STEPS * DT, dt=DT)
    out = {"topology": kind, "damping": damping, "model": model.name, "dof": plant.n,
           "states": 2 * plant.n, "steps": STEPS, "dt": DT, "inputs": len(inputs),
           "outputs": len(outputs), "build_plant_s": round(t_plant, 3)}
    with threadpool_limits(1):
        out["modal_s"], modal = _cold(model, inputs, outputs, "modal", kw, repeat)
        out["modal_note"] = modal.note
        if floors:
            out["eig_s"], out["recursion_s"] = _floor(build_plant(model, inputs, outputs), damping, kw, repeat)
            out["floor_s"] = out["eig_s"] + out["recursion_s"]
        if run_reference:
            out["forced_response_s"], ref = _cold(model, inputs, outputs, "forced_response", kw,
                                                  max(1, repeat // 2))
            out["speedup"] = round(out["forced_response_s"] / out["modal_s"], 1)
            if floors:
                out["floor_speedup"] = round(out["forced_response_s"] / out["floor_s"], 1)
            scale = np.abs(ref.outputs).max(axis=1, keepdims=True)
            out["max_rel_diff"] = float((np.abs(modal.outputs - ref.outputs) / scale).max())
    return out


def bench(quick: bool) -> dict:
    """Every topology and damping at 100 bodies, best of 3, and a 6000-DOF chain (``quick``: 50
    bodies (300 DOF), no 6000-DOF run, no floors, one repeat)."""
    return run(quick)


def run(quick: bool = False, topologies: tuple[str, ...] = SUITE,
        dampings: tuple[str, ...] = ("classical", "general"), repeat: int = 3, skip_large: bool = False) -> dict:
    """:func:`bench` with a choice of topologies and dampings, repeats, and the 6000-DOF run."""
    repeat = 1 if quick else repeat
    results = {"python": platform.python_version(), "machine": platform.processor() or platform.machine(),
               "cases": []}
    print(f"{'topology':8s} {'damping':9s} {'DOF':>5s} {'forced_response':>16s} {'modal':>8s} "
          f"{'ratio':>7s} {'max rel. diff':>14s} {'eig':>7s} {'recursion':>9s} {'floor ratio':>11s}")
    for kind in topologies:
        for damping in dampings:
            r = case(kind, 50 if quick else 100, damping, run_reference=True, repeat=repeat, floors=not quick)
            floor = (f"{r['eig_s']:5.3f} s {r['recursion_s']:7.3f} s {r['floor_speedup']:10.1f}x"
                     if "floor_s" in r else "(floors not timed with --quick)")
            results["cases"].append(r)
            print(f"{kind:8s} {damping:9s} {r['dof']:5d} {r['forced_response_s']:14.2f} s "
                  f"{r['modal_s']:6.3f} s {r['speedup']:6.1f}x {r['max_rel_diff']:14.1e} "
                  f"{floor}", flush=True)
    for damping in dampings:
        rows = [r for r in results["cases"] if r["damping"] == damping]
        if rows:
            worst = min(rows, key=lambda r: r["speedup"])
            results[f"worst_{damping}"] = {"topology": worst["topology"], "speedup": worst["speedup"],
                                           "floor_speedup": worst.get("floor_speedup")}
            print(f"  {damping}: modal at least {worst['speedup']:.1f}x forced_response on every topology "
                  f"(worst: {worst['topology']}, its floor {worst.get('floor_speedup', float('nan'))}x)", flush=True)
    if not (quick or skip_large or tuple(topologies) != tuple(SUITE)):
        r = case("chain", 1000, "classical", run_reference=False, repeat=1, floors=False)
        results["cases"].append(r)
        print(f"6000-DOF chain, classical: modal {r['modal_s']:.2f} s (build_plant {r['build_plant_s']:.2f} s)")
    return results


if __name__ == "__main__":
    from run_all import main_one

    main_one("time")
