"""Calibration of the cost model: every method's estimated against measured seconds on the suite, and
``vibss/data/costs.json`` refitted (issue 34 item 3, issue 29's time guard).

On every topology of :mod:`models` (chain, grid, tree, 3-D lattice, random graph, mechanism chain,
soft tower) at 150 and 600 DOF (full run: 2,400 too), classical and general damping, 3 force inputs x
6 displacement outputs:

- every frequency method of :data:`vibss.frequency.kernels.METHODS` that applies and whose estimate
  is under the budget: its kernel timed on ``NF`` log-spaced frequencies (best of two, one BLAS
  thread, a first call on one frequency out of the timing) against its estimate
  (``method.cost(plant, nf, basis)``);
- the time methods ``modal``, ``forced_response`` and ``newmark`` at 600 DOF (150 in quick): the
  whole ``simulate`` call (2,000 steps) against the method's ``coster``.

Each method's formula is scaled by one factor per family (``vibss.costs.scale``: ``frequency.direct``,
``solve.banded`` and ``solve.superlu`` for ``sparse``, ``time.modal`` ...): the geometric mean of
measured over unscaled estimate over the family's rows. The fitted factors are written to
``vibss/data/costs.json`` (the constants themselves kept) and every row's ratio measured / estimated
after the fit is recorded: within 2x for every method ``auto`` may choose and 10x for every method is
what tests/project/test_costs.py asserts on the recorded figures (``benchmarks/results/costs.json``).
The benchmark prints the worst ratio per family and the load of the machine.
"""

from __future__ import annotations

import json
import os
import sys
import time
import warnings
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import numpy as np
from threadpoolctl import threadpool_limits

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from benchmarks.models import NEW_TOPOLOGIES, TOPOLOGIES, topology_model  # noqa: E402
from vibss import costs  # noqa: E402
from vibss.errors import VibssError  # noqa: E402
from vibss.frequency.contracts import _mounts  # noqa: E402
from vibss.frequency.kernels import METHODS  # noqa: E402
from vibss.frequency.methods import applies, choose  # noqa: E402
from vibss.linear.eigen.basis import modal_basis  # noqa: E402
from vibss.linear.plant.build import build_plant  # noqa: E402
from vibss.linear.solve.backends import MOUNTS_DENSE_MAX  # noqa: E402
from vibss.linear.solve.banded import structure  # noqa: E402
from vibss.methods import MEMORY_FRACTION, available_memory  # noqa: E402
from vibss.time import methods as time_methods  # noqa: E402
from vibss.time.api import simulate  # noqa: E402

AUTO_WITHIN = 2.0
"""Measured over estimated seconds, both ways, for a method ``auto`` may choose."""
GUARD_WITHIN = 10.0
"""The same for every method (issue 29's time guard)."""
FREQUENCY_BUDGET = 20.0
"""A frequency method estimated past this [s] is not run (its row says so)."""
AUTO_CHOICES = {"direct", "sparse", "modal", "complex_modal", "woodbury", "subspace"}
"""Frequency methods ``auto`` may choose (``statespace`` only by name); time: ``modal`` and its fallback."""
TIME_AUTO = {"modal", "forced_response"}


def family(name: str, plant: Any) -> str:
    """The ``vibss.costs.scale`` key of a frequency method on ``plant``."""
    if name in ("sparse", "direct") and (mounts := _mounts(plant)):    # solved in the mounts' forces:
        # dense LU of the saddle system up to MOUNTS_DENSE_MAX unknowns, else the assembled SuperLU refined
        return "frequency.direct" if plant.n + mounts <= MOUNTS_DENSE_MAX else "solve.mounts"
    if name == "sparse":
        st = plant.cached("band structure", lambda: structure(plant))
        return "solve.banded" if st.banded else "solve.superlu"
    return f"frequency.{name}"


def _channels(nb: int) -> tuple[list[str], list[str]]:
    step = max(1, nb // 3)
    ins = [f"b{i * step}.f{'xyz'[i % 3]}" for i in range(3)]
    outs = [f"b{min(nb - 1, i * step + 1)}.{d}" for i in range(3) for d in ("x", "z")]
    return ins, outs


def _best(f: Any, repeat: int = 2) -> float:
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        f()
        best = min(best, time.perf_counter() - t0)
    return float(best)


def frequency_rows(kind: str, n_dof: int, damping: str, nf: int) -> list[dict]:
    nb = n_dof // 6
    ins, outs = _channels(nb)
    plant = build_plant(topology_model(kind, nb, damping), ins, outs)
    basis = modal_basis(plant)
    s = 2j * np.pi * np.geomspace(0.1, 100.0, nf)
    picked = choose(plant, nf, basis)[0]
    rows = []
    for name, m in METHODS.items():
        if m.cost is None or not applies(m, plant, basis):
            continue
        key = family(name, plant)
        est = m.cost(plant, nf, basis)
        row = {"analysis": "frequency", "model": f"{kind} {n_dof} DOF {damping}", "method": name, "family": key,
               "auto_may_choose": name in AUTO_CHOICES, "auto_chose": name == picked,
               "formula_s": est.seconds / costs.scale(key)}
        if est.seconds > FREQUENCY_BUDGET or est.bytes > MEMORY_FRACTION * available_memory():
            rows.append({**row, "skipped": f"estimated {est.seconds:.3g} s"})
            continue
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                m.kernel(plant, s[:1], basis)
                row["seconds"] = _best(lambda: m.kernel(plant, s, basis))
        except VibssError as exc:
            row["refused"] = str(exc)[:120]
        rows.append(row)
    return rows


def time_rows(kind: str, n_dof: int, damping: str, steps: int) -> list[dict]:
    nb = n_dof // 6
    ins, outs = _channels(nb)
    plant = build_plant(topology_model(kind, nb, damping), ins, outs)
    rng = np.random.default_rng(3)
    dt = 2e-4
    walks = {u: np.cumsum(rng.normal(0.0, 20.0, steps + 1)) for u in ins}     # PWL random walks [N]
    job = SimpleNamespace(plant=plant, time=np.arange(steps + 1) * dt, breakpoints=np.zeros(0))
    rows = []
    for name in ("modal", "forced_response", "newmark"):
        coster = time_methods.METHODS[name].coster
        assert coster is not None
        key = f"time.{_kind(name)}"
        est = coster(job)
        row = {"analysis": "time", "model": f"{kind} {n_dof} DOF {damping}", "method": name, "family": key,
               "auto_may_choose": name in TIME_AUTO, "auto_chose": name == "modal",
               "formula_s": est.seconds / costs.scale(key)}
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                # a fresh plant per call (no eigen-analysis kept), built outside the clock: the
                # coster prices the simulation, not the model's assembly
                plants = [build_plant(topology_model(kind, nb, damping), ins, outs) for _ in range(2)]
                fresh = iter(plants)
                row["seconds"] = _best(lambda: simulate(next(fresh), inputs=walks, t_end=steps * dt, dt=dt,
                                                        method=name), repeat=len(plants))
        except VibssError as exc:
            row["refused"] = str(exc)[:120]
        rows.append(row)
    return rows


def _kind(name: str) -> str:
    return {"modal": "modal", "forced_response": "state", "ivp": "state"}.get(name, "fixed")


def fit(rows: list[dict]) -> dict[str, float]:
    """Each family's factor: the geometric mean of measured over unscaled estimated seconds."""
    out: dict[str, list[float]] = {}
    for r in rows:
        if "seconds" in r and r["formula_s"] > 0:
            out.setdefault(r["family"], []).append(np.log(r["seconds"] / r["formula_s"]))
    return {k: float(np.exp(np.mean(v))) for k, v in out.items()}


def write(scales: dict[str, float], quick: bool) -> None:
    data = json.loads(costs.PATH.read_text())
    data["scale"].update({k: float(f"{v:.4g}") for k, v in scales.items()})   # within the test's 2e-3
    data["measured"] = (f"benchmarks/bench_costs.py{' --quick' if quick else ''} on {time.strftime('%Y-%m-%d')}, "
                        f"1 BLAS thread, load {os.getloadavg()[0]:.1f}")
    refitted = json.dumps(data, indent=1) + "\n"      # package data (its figures go through the harness)
    costs.PATH.write_text(refitted)


def bench(quick: bool) -> dict:
    """Estimated against measured seconds of every method on the suite; costs.json refitted."""
    sizes = (150, 600) if quick else (150, 600, 2400)
    nf = 100 if quick else 200
    load = os.getloadavg()[0]
    rows: list[dict] = []
    with threadpool_limits(1):
        for kind in TOPOLOGIES + NEW_TOPOLOGIES:
            for damping in ("classical", "general"):
                for n in sizes:
                    rows += frequency_rows(kind, n, damping, nf)
                rows += time_rows(kind, 150 if quick else 600, damping, 2000)
                print(f"{kind} {damping}: {len(rows)} rows", flush=True)
    scales = fit(rows)
    for r in rows:
        if "seconds" in r:
            r["estimate_s"] = r["formula_s"] * scales[r["family"]]
            r["ratio"] = r["seconds"] / r["estimate_s"]
    write(scales, quick)
    worst: dict[str, Any] = {}
    for r in rows:
        if "ratio" in r:
            spread = max(r["ratio"], 1 / r["ratio"])
            w = worst.setdefault(r["family"], {"spread": 0.0})
            if spread > w["spread"]:
                worst[r["family"]] = {"spread": spread, "at": f"{r['method']} on {r['model']}", "scale": scales[r["family"]]}
    for k, w in sorted(worst.items()):
        print(f"{k:26s} scale {w['scale']:8.3g}  worst measured/estimated {w['spread']:6.2f}x  ({w['at']})")
    bad_auto = [r for r in rows if "ratio" in r and r["auto_may_choose"] and max(r["ratio"], 1 / r["ratio"]) > AUTO_WITHIN]
    bad = [r for r in rows if "ratio" in r and max(r["ratio"], 1 / r["ratio"]) > GUARD_WITHIN]
    print(f"load {load:.1f} -> {os.getloadavg()[0]:.1f}; rows past {AUTO_WITHIN:g}x (auto's methods): {len(bad_auto)}; "
          f"past {GUARD_WITHIN:g}x (any): {len(bad)}")
    return {"load": load, "frequencies": nf, "sizes": list(sizes), "scales": scales, "worst": worst,
            "auto_within": AUTO_WITHIN, "guard_within": GUARD_WITHIN, "rows": rows}


if __name__ == "__main__":
    from run_all import main_one

    main_one("costs")
