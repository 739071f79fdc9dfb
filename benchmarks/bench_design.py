"""Mount-system design: batched Monte Carlo against a loop of ``vibss.modes``, and the optimiser
with exact gradients against finite-difference gradients — same run, same machine.

- **Monte Carlo**: the powertrain example with its twelve mount rates at +-15 % (LHS, seeded), plus
  position and angle tolerances; ``vibss.design.monte_carlo`` on 100,000 variants (one batched
  eigen-solve per 10,000), against ``vibss.modes(apply(model, ...))`` called in a loop on the first
  ``LOOP`` variants (time per variant extrapolated); largest frequency and KE-fraction differences
  over those variants.
- **Optimisation** (when ``vibss.design.optimise`` is present): the powertrain's purity objective
  over 12+ design variables by SLSQP with the exact gradients, and again with finite-difference
  gradients (scipy's 2-point differences on the same objective); wall time, evaluations, result.

Run: ``python benchmarks/bench_design.py [--quick]``; writes ``benchmarks/results/design.json``.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from machine import machine, timed  # noqa: E402

import vibss  # noqa: E402
from vibss.design import Parameter, monte_carlo  # noqa: E402
from vibss.design.montecarlo import batch_modes  # noqa: E402
from vibss.design.parameters import apply, parameters_of  # noqa: E402

RESULTS = Path(__file__).parent / "results"


def tolerances(model: vibss.Model) -> dict:
    tol: dict = {f"{m.name}.k{j}": 0.15 for m in model.mounts for j in (1, 2, 3)}
    tol.update({"engine.z": 0.003, "gearbox.x": 0.003, "engine.rx": np.radians(2.0),
                Parameter("strut angle", [("torque-strut", "rz", 1.0)]): np.radians(3.0)})
    return tol


def bench_monte_carlo(n: int, loop: int) -> dict:
    model = vibss.load_example("powertrain")
    tol = tolerances(model)
    t_batch, mc = timed(lambda: monte_carlo(model, tol, n=n, sampling="lhs", seed=1, purity=0.8,
                                            windows=(5.0, 26.7 / np.sqrt(2))), repeat=1)
    params = parameters_of(model, list(tol))
    t0 = time.perf_counter()
    ref = [vibss.modes(apply(model, params, mc.samples[v])) for v in range(loop)]
    t_loop = (time.perf_counter() - t0) / loop
    _, _, ke = batch_modes(model, params, mc.samples[:loop])
    f_err = max(float(np.max(np.abs(mc.frequency_hz[v] / r.frequency_hz - 1))) for v, r in enumerate(ref))
    ke_err = max(float(np.max(np.abs(ke[v] - r.energy))) for v, r in enumerate(ref))
    out = {"variants": n, "parameters": len(tol), "batched_s": t_batch,
           "batched_per_variant_us": 1e6 * t_batch / n, "loop_variants": loop,
           "loop_per_variant_ms": 1e3 * t_loop, "loop_extrapolated_s": t_loop * n,
           "speedup": t_loop * n / t_batch, "max_rel_frequency_error": f_err,
           "max_ke_fraction_error": ke_err, "probability_all": mc.probability["all"]}
    print(f"Monte Carlo, {n} variants x {len(tol)} parameters: batched {t_batch:.2f} s "
          f"({out['batched_per_variant_us']:.1f} us/variant); loop of vibss.modes "
          f"{out['loop_per_variant_ms']:.2f} ms/variant -> {out['loop_extrapolated_s']:.0f} s; "
          f"speed-up {out['speedup']:.0f}x; max errors: frequency {f_err:.1e} (rel), KE {ke_err:.1e}")
    return out


def bench_optimise(quick: bool) -> dict | None:
    try:
        from vibss.design.optimise import benchmark_case, optimise
    except ImportError:
        return None
    model, variables, kwargs = benchmark_case()
    res = {}
    for grad in ("exact", "finite-difference"):
        t0 = time.perf_counter()
        r = optimise(model, variables, gradient=grad, starts=1, **kwargs)
        wall = time.perf_counter() - t0
        res[grad] = {"wall_s": wall, "evaluations": r.evaluations, "objective": r.objective,
                     "min_purity_before": float(r.before.purity.min()),
                     "min_purity_after": float(r.after.purity.min()), "success": r.success}
        print(f"optimise ({len(r.variables)} variables, {grad} gradients): {wall:.2f} s, "
              f"{r.evaluations} evaluations, min purity {res[grad]['min_purity_before']:.3f} -> "
              f"{res[grad]['min_purity_after']:.3f}")
    res["variables"] = len(variables)
    res["speedup_exact_over_fd"] = res["finite-difference"]["wall_s"] / res["exact"]["wall_s"]
    return res


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    n, loop = (20_000, 100) if args.quick else (100_000, 500)
    out = {"machine": machine(), "quick": args.quick, "monte_carlo": bench_monte_carlo(n, loop)}
    opt = bench_optimise(args.quick)
    if opt is not None:
        out["optimise"] = opt
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "design.json").write_text(json.dumps(out, indent=1, default=float))


if __name__ == "__main__":
    main()
