"""Mount-system design: batched Monte Carlo against a loop of ``vibss.modes``, and the optimiser
with exact gradients against finite-difference gradients — same run, same machine.

- **Monte Carlo**: the powertrain example with its twelve mount rates at +-15 % (LHS, seeded), plus
  position and angle tolerances; ``vibss.design.monte_carlo`` on 100,000 variants (one batched
  eigen-solve per 10,000), against ``vibss.modes(apply(model, ...))`` called in a loop on the first
  ``LOOP`` variants (time per variant extrapolated); largest frequency and KE-fraction differences
  over those variants.
- **Optimization** (when ``vibss.design.optimize`` is present): the powertrain's purity objective
  over 12+ design variables by SLSQP with the exact gradients, and again with finite-difference
  gradients (scipy's 2-point differences on the same objective); wall time, evaluations, result.
- **Study runner on Dask**: ``vibss.grid_study`` of 10,000 variants (``modes``) in-process and on a
  2-worker ``LocalCluster``; the Dask overhead per variant from the same study with an analysis that
  does nothing.

Run: ``python benchmarks/bench_design.py [--quick]``; writes ``benchmarks/results/design.json``.
"""

from __future__ import annotations

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
        from vibss.design.optimize import benchmark_case, optimize
    except ImportError:
        return None
    model, variables, kwargs = benchmark_case()
    res = {}
    for grad in ("exact", "finite-difference"):
        t0 = time.perf_counter()
        r = optimize(model, variables, gradient=grad, starts=1, **kwargs)
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


def _nothing(model: vibss.Model) -> float:
    return 0.0


def bench_dask(n: int) -> dict | None:
    try:
        import distributed
    except ImportError:
        return None
    model = vibss.load_example("powertrain")
    table = {"engine.k3": np.linspace(2e5, 3e5, n)}
    t0 = time.perf_counter()
    local = vibss.grid_study(model, "modes", table=table)
    t_local = time.perf_counter() - t0
    out = {"variants": n, "in_process_s": t_local}
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        t0 = time.perf_counter()
        remote = vibss.grid_study(model, "modes", table=table, client=client)
        out["dask_2_workers_s"] = time.perf_counter() - t0
        t0 = time.perf_counter()
        vibss.grid_study(model, _nothing, table=table, client=client)
        out["dask_trivial_analysis_s"] = time.perf_counter() - t0
    out["same_table"] = bool(local.equals(remote))
    out["overhead_per_variant_us"] = 1e6 * out["dask_trivial_analysis_s"] / n
    out["speedup_2_workers"] = t_local / out["dask_2_workers_s"]
    print(f"study of {n} variants (modes): in-process {t_local:.1f} s, Dask LocalCluster(2) "
          f"{out['dask_2_workers_s']:.1f} s (x{out['speedup_2_workers']:.2f}); Dask overhead "
          f"{out['overhead_per_variant_us']:.0f} us/variant (trivial analysis); same table: {out['same_table']}")
    return out


def figures() -> None:
    """The figures of docs/analyses/design.md."""
    from vibss.design.optimize import benchmark_case, optimize
    from vibss.design import certificate, sensitivity

    folder = Path(__file__).parents[1] / "docs" / "figures"
    pt = vibss.load_example("powertrain")
    win = (5.0, 26.7 / np.sqrt(2))
    from vibss.design import plot_design_axes

    plot_design_axes(pt).savefig(folder / "design_axes.png", dpi=100)
    certificate(pt, purity=0.9, windows=win, frame="tra").plot().savefig(folder / "design_certificate.png", dpi=110)
    sens = sensitivity(pt, ["engine.k3", "gearbox.k3", "torque-strut.k1", "engine.z", "engine.rx"], frame="tra")
    sens.plot(quantity="purity").savefig(folder / "design_sensitivity.png", dpi=110)
    model, variables, options = benchmark_case()
    opt = optimize(model, variables, **options)
    opt.plot().savefig(folder / "design_optimisation.png", dpi=110)
    tol = {f"{m.name}.k{j}": 0.15 for m in opt.model.mounts for j in (1, 2, 3)}
    mc = monte_carlo(opt.model, tol, n=20_000, sampling="lhs", purity=0.9, windows=win, frame="tra")
    mc.plot().savefig(folder / "design_monte_carlo.png", dpi=110)
    mc.plot(kind="tornado").savefig(folder / "design_tornado.png", dpi=100)


def bench(quick: bool) -> dict:
    """Monte Carlo, optimization and the Dask grid study (small sizes with ``quick``)."""
    n, loop = (5_000, 50) if quick else (100_000, 500)
    if not quick:                       # the figures of docs/analyses/design.md: the full run only
        figures()
    out = {"machine": machine(), "quick": quick, "monte_carlo": bench_monte_carlo(n, loop)}
    opt = bench_optimise(quick)
    if opt is not None:
        out["optimise"] = opt
    dk = bench_dask(500 if quick else 10_000)
    if dk is not None:
        out["dask"] = dk
    return out


if __name__ == "__main__":
    from run_all import main_one

    main_one("design")
