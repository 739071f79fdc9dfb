"""The benchmark harness: run every benchmark, then write the figures and the generated tables of
docs/performance.md.

``make bench`` runs this. The harness owns what every benchmark shares (airspeed velocity's
shape): each ``benchmarks/bench_<name>.py`` defines ``bench(quick: bool) -> dict`` (its figures:
ratios, errors, timings of the calls it compares) and nothing else; this module runs it in its own
process (``run_all.py --one NAME``) with one BLAS thread (``OPENBLAS_NUM_THREADS=1`` etc. set in
the environment here, and ``threadpoolctl.threadpool_limits(1)`` around the call), times it, writes
its dict to ``benchmarks/results/<name>.json`` and prints its table, the process' output saved to
``benchmarks/results/<name>.txt``; a failing benchmark is reported and the others still run.
:func:`best` is the one timing helper of the calls a benchmark compares. Figures go to ``docs/figures/`` (written by the benchmarks), and the section
between the markers of ``docs/performance.md`` is regenerated from ``benchmarks/results/*.json``
with the machine line on top. The hand-written text around the markers is kept.

Usage: ``python benchmarks/run_all.py [--quick] [--only NAME ...] [--no-run]``, or
``python benchmarks/run_all.py --one NAME [--quick]`` (the same as ``python benchmarks/bench_NAME.py
[--quick]``) for one benchmark in this process.

- ``--quick``: small sizes (under 5 minutes; ``bench(quick=True)``, which one-size benchmarks ignore, and the
  one-model studies of :data:`FULL_ONLY` left out; ``make bench QUICK=1`` or ``make bench-quick``). Every run is seeded: two quick runs give the
  same counts (basis sizes, frequencies, errors to their printed digits), only timings differ;
- ``--only``: run these benchmarks (e.g. ``pareto stability``), tabulate all results present;
- ``--no-run``: only regenerate the tables from the existing results.
"""

from __future__ import annotations

import argparse
import importlib
import json
import os
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
RESULTS = HERE / "results"
DOC = ROOT / "docs" / "performance.md"
BEGIN, END = "<!-- BEGIN GENERATED: benchmarks/run_all.py -->", "<!-- END GENERATED -->"
ORDER = ["core", "frf", "time", "reduction", "pareto", "stability"]
FULL_ONLY = {"tree_refine": "a study of one 600-DOF model's slow poles (about 2 minutes), with no small size",
             "eig_variants": "LAPACK's eigen drivers on the 1,200-state matrices, with no small size",
             "subspace_reduced": "the 200-body grid's channel subspace, dense against sparse reduced solves",
             "time_expm": "the expm route at 600 DOF, measured and not taken (docs/performance.md)"}
"""Benchmarks ``--quick`` leaves out, and why."""
THREAD_ENV = {"OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1",
              "MPLBACKEND": "Agg", "PYTHONHASHSEED": "0"}
"""One BLAS thread (timings comparable, sums in one order) and a fixed hash seed (set iteration order
fixed), so two runs give the same numbers; the benchmarks seed their own random models and starts."""


def benchmarks() -> list[tuple[str, Path]]:
    found = {p.stem[len("bench_"):]: p for p in HERE.glob("bench_*.py")}
    names = [n for n in ORDER if n in found] + sorted(n for n in found if n not in ORDER)
    return [(n, found[n]) for n in names]


def best(f: Callable[[], Any], repeat: int = 3) -> tuple[float, Any]:
    """The shortest of ``repeat`` timed calls of ``f`` [s], and ``f``'s last result."""
    times, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = f()
        times.append(time.perf_counter() - t0)
    return min(times), out


def run_one(name: str, quick: bool) -> dict[str, Any]:
    """Benchmark ``name`` in this process: ``bench_<name>.bench(quick)`` with one BLAS thread,
    timed; its figures written to ``results/<name>.json`` and printed as a table."""
    for p in (str(ROOT), str(HERE)):
        if p not in sys.path:
            sys.path.insert(0, p)
    from threadpoolctl import threadpool_limits

    module = importlib.import_module(f"bench_{name}")
    with threadpool_limits(1):
        t0 = time.perf_counter()
        res = module.bench(quick)
        wall = time.perf_counter() - t0
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / f"{name}.json").write_text(json.dumps(res, indent=1, default=float) + "\n")
    print("\n".join(generic_table(name, res)))
    print(f"[harness] {name}{' --quick' if quick else ''}: {wall:.1f} s, 1 BLAS thread; "
          f"wrote benchmarks/results/{name}.json", flush=True)
    return res


def main_one(name: str) -> None:
    """A benchmark's ``__main__``: ``python benchmarks/bench_NAME.py [--quick]``."""
    ap = argparse.ArgumentParser(description=f"benchmarks/bench_{name}.py through the harness")
    ap.add_argument("--quick", action="store_true", help="small sizes")
    run_one(name, ap.parse_args().quick)


def run(name: str, path: Path, quick: bool, timeout: float) -> dict[str, Any]:
    args = [sys.executable, str((HERE / "run_all.py").relative_to(ROOT)), "--one", name] + (["--quick"] if quick else [])
    env = {**os.environ, **THREAD_ENV, "PYTHONPATH": os.pathsep.join([str(ROOT), str(HERE)])}
    t0 = time.perf_counter()
    try:
        p = subprocess.run(args, cwd=ROOT, env=env, capture_output=True, text=True, timeout=timeout)
        rc, out = p.returncode, p.stdout + ("\n--- stderr ---\n" + p.stderr if p.stderr.strip() else "")
    except subprocess.TimeoutExpired as exc:
        rc, out = -1, f"timed out after {timeout:.0f} s\n{exc.stdout or ''}"
    wall = time.perf_counter() - t0
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / f"{name}.txt").write_text(out)
    status = "ok" if rc == 0 else f"FAILED (exit {rc}; see benchmarks/results/{name}.txt)"
    print(f"[run_all] {name}: {status}, {wall:.1f} s", flush=True)
    return {"name": name, "args": " ".join(args[1:]), "rc": rc, "wall_s": wall, "status": status}


# ---------------------------------------------------------------------------------------------
# tables

def _g(x: Any, fmt: str = ".3g") -> str:
    if isinstance(x, bool) or x is None:
        return str(x)
    if isinstance(x, (int, float)):
        return "inf" if x == float("inf") else format(x, fmt)
    return str(x)


def _table(head: list[str], rows: list[list[Any]]) -> list[str]:
    out = ["| " + " | ".join(h.replace("|", "\\|") for h in head) + " |", "|" + "---|" * len(head)]
    out += ["| " + " | ".join(_g(c).replace("|", "\\|") for c in r) + " |" for r in rows]
    return out + [""]


def _load(name: str) -> dict[str, Any] | None:
    p = RESULTS / f"{name}.json"
    try:
        return json.loads(p.read_text())
    except (OSError, ValueError):
        return None


def _cheapest(points: list[list[Any]], tol: float) -> str:
    ok = [p for p in points if p[1] is not None and p[1] <= tol and p[0] == p[0]]
    if not ok:
        return "–"
    t, _, how = min(ok, key=lambda p: p[0])
    return f"{t:.3g} s ({how})" if how else f"{t:.3g} s"


def time_tables(res: dict[str, Any]) -> list[str]:
    out = []
    for kind, r in res.items():
        out.append(f"**Time response, {kind}** ({r['dofs']} DOF, {r['t_end_s']} s, outputs every "
                   f"{r['dt_out_s'] * 1e3:g} ms; reference: {r['reference']}; reference checks: "
                   + ", ".join(f"{k} {v:.1e}" for k, v in r["reference_checks"].items()) + ")")
        out.append("")
        rows = []
        for label, pts in r["curves"].items():
            if "unstable" in label:
                rows.append([label, ", ".join(p[2] for p in pts), "", "", "", ""])
                continue
            best = min(p[1] for p in pts)
            rows.append([label, _g(best, ".1e"), _cheapest(pts, 1e-2), _cheapest(pts, 1e-5),
                         _cheapest(pts, 1e-9), _g(min(p[0] for p in pts))])
        out += _table(["method", "best error", "cheapest run, error ≤ 1e-2", "≤ 1e-5", "≤ 1e-9",
                       "fastest run [s]"], rows)
    return out


def frf_tables(res: dict[str, Any]) -> list[str]:
    out = []
    for case, r in res.items():
        out.append(f"**Frequency response, {case}** ({r['dofs']} DOF, {r['frequencies']} frequencies, "
                   f"2 inputs × 6 outputs; reference: direct solve refined in extended precision, "
                   f"{r['reference_s']:.2g} s)")
        out.append("")
        rows = [[label + (f" ({p[2]})" if p[2] else ""), _g(p[0]), _g(p[1], ".1e")]
                for label, pts in r["curves"].items() for p in pts]
        out += _table(["method", "time [s]", "max relative error"], rows)
    return out


def eigen_tables(res: dict[str, Any]) -> list[str]:
    out = []
    for scale, r in res.items():
        out.append(f"**Eigen-analysis, {scale} scale** ({r['dofs']} DOF, C = β K, ζ from "
                   f"{r['zeta_range'][0]:.1e} to {r['zeta_range'][1]:.1e}; shift-invert frequencies "
                   f"differ from dense by {r['max_rel_freq_diff_shift_invert']:.1e}"
                   + (f"; **{r['elastic_modes_reported_as_rigid']} elastic mode(s) reported as rigid "
                      f"(omega = 0) by vibss.modes**, shift-invert finds omega_1 = "
                      f"{r['lowest_shift_invert_omega']:.3g} rad/s" if r.get("elastic_modes_reported_as_rigid") else "")
                   + ")")
        out.append("")
        out += _table(["method", "time [s]"], [[k, v] for k, v in r["time_s"].items()])
        out += _table(["poles from", "max relative ζ error (exact: ζ = β|p|/2)"],
                      [[k, _g(v, ".1e")] for k, v in r["max_rel_zeta_error"].items()])
    return out


def scaling_tables(res: dict[str, Any]) -> list[str]:
    rows = res["rows"]
    cols = sorted({k for r in rows for k in r if k not in ("bodies", "dofs")})
    out = [f"**Scaling** (CPU time [s]; stock python-control paths stopped above "
           f"{res['stock_limit_dof']} DOF, dense paths above {6 * res['dense_limit_bodies']} DOF; "
           "– = not run)", ""]
    out += _table(["bodies", "DOF"] + cols, [[r["bodies"], r["dofs"]] + [r.get(c, "–") for c in cols]
                                               for r in rows])
    return out


def stability_tables(res: dict[str, Any]) -> list[str]:
    out = ["**Failure modes** (details in the stability figures)", ""]
    cd = res["central_difference"]
    first_bad = min((r["dt_over_limit"] for r in cd["rows"] if r["peak_ratio"] > 10), default=None)
    flagged = min((r["dt_over_limit"] for r in cd["rows"] if not r["check_ok"]), default=None)
    rows = [["central difference", f"2/ω_max = {cd['limit_s']:.3g} s", f"grows ×10 or more from dt = "
             f"{_g(first_bad)} × limit", f"flagged from {_g(flagged)} × limit"]]
    for r in res["stiff_rk"]["rows"]:
        rows.append([f"RK45, mount ×{r['factor']:g}", f"|λ|max/ω_min = {r['stiffness_ratio']:.3g}",
                     f"{r['nfev_RK45']} evaluations, {r['time_RK45_s']:.3g} s (Radau {r['nfev_Radau']}, "
                     f"{r['time_Radau_s']:.3g} s; auto/modal {r['time_auto_s']:.2g} s)",
                     f"predicted ≥ {6 * r['predicted_rk45_steps']:.3g} evaluations; "
                     f"{'ok' if r['check_ok'] else 'flagged'}"])
    for r in res["short_pulse"]["rows"]:
        rows.append([f"pulse of {r['pulse_steps']:g} steps", "forced_response / modal error",
                     f"{r['err_forced_response']:.1e} / {r['err_modal']:.1e}",
                     "flagged: " + (", ".join(r["flagged"]) or "none")])
    lv = res["lever_arm"]
    rows.append(["lever arms (FE style)", f"cond(K) rigid-body form {lv['cond_K_rigid']:.3g}",
                 f"best frequency error {lv['best']['max_rel_freq_error']:.1e} at k_link/k_mount = "
                 f"{lv['best']['k_link_over_k_mount']:.0e} (cond {lv['best']['cond_K']:.1e})",
                 f"at 1e16: error {lv['rows'][-1]['max_rel_freq_error']:.1e}, cond {lv['rows'][-1]['cond_K']:.1e}"])
    for r in res["units"]["rows"]:
        rows.append([f"units {r['units']}", f"cond M, K = {r['cond_M']:.2e}, {r['cond_K']:.2e}",
                     f"equilibrated {r['cond_M_eq']:.3g}, {r['cond_K_eq']:.3g}",
                     f"frequency difference vs SI {r['freq_diff_equilibrated']:.1e}"])
    for r in res["damping"]["rows"]:
        rows.append([f"ζ = 1e-5 .., {r['dofs']} DOF, {r['scale']}", "control.poles / QZ / damped_modes",
                     " / ".join(_g(r[k], ".1e") for k in ("control.poles (balanced geev of A)",
                                                           "QZ of descriptor form, unbalanced",
                                                           "vibss damped_modes")), "max relative ζ error"])
    for r in res["statics"]["rows"]:
        rows.append([f"statics, eps = {r['eps']:g}", f"check {r['check_value']:.1e} "
                     f"({'ok' if r['check_ok'] else 'flagged'})",
                     f"vibss error {_g(r['vibss_error'], '.1e')}; numpy.solve {_g(r['plain_solve_error'], '.1e')}",
                     ("AnalysisError: " + r["vibss_raised"][:70] + "…") if r["vibss_raised"] else ""])
    return out + _table(["case", "measure", "result", "check"], rows)


def _flatten(d: Any, prefix: str = "") -> list[tuple[str, Any]]:
    if isinstance(d, dict):
        return [kv for k, v in d.items() for kv in _flatten(v, f"{prefix}{k}." if prefix or k else k)]
    if isinstance(d, (int, float, str, bool)):
        return [(prefix.rstrip("."), d)]
    return []


def generic_table(name: str, res: dict[str, Any]) -> list[str]:
    items = [(k, v) for k, v in _flatten(res) if not k.startswith("machine")][:60]
    return [f"**{name}** (benchmarks/bench_{name}.py; all numbers from benchmarks/results/{name}.json)",
            ""] + _table(["quantity", "value"], [[k, v] for k, v in items])


def generate(log: list[dict[str, Any]], quick: bool) -> str:
    sys.path.insert(0, str(HERE))
    from machine import machine, machine_line

    m = machine()
    lines = [f"_Generated {time.strftime('%Y-%m-%d %H:%M')} by `benchmarks/run_all.py"
             f"{' --quick' if quick else ''}`; do not edit by hand._", "",
             f"**Machine:** {machine_line()}.", "",
             f"CPU `{m['cpu']}`, {m['cores']} cores; every timing with 1 BLAS thread "
             "(`threadpoolctl.threadpool_limits(1)` around each timed call, and OPENBLAS/OMP/MKL_NUM_THREADS=1 "
             "in each benchmark process); best of 3 for calls under 0.2 s, else a single run. "
             "The machine is shared: expect ±10 % (more under load; the load average is in the line above).",
             ""]
    if log:
        lines += _table(["benchmark", "command", "status", "wall [s]"],
                        [[r["name"], r["args"], r["status"], r["wall_s"]] for r in log])
        lines.append(f"Total: {sum(r['wall_s'] for r in log):.0f} s.")
        lines.append("")
    pareto, stab = _load("pareto"), _load("stability")
    if pareto:
        if pareto.get("quick"):
            lines += ["_Pareto results from a `--quick` run (small sizes)._", ""]
        for key, fn in (("time", time_tables), ("frf", frf_tables), ("eigen", eigen_tables),
                        ("scaling", scaling_tables)):
            if key in pareto:
                lines += fn(pareto[key])
    if stab:
        lines += stability_tables(stab)
    for name in ("core", "frf", "time", "reduction"):
        res = _load(name)
        if res:
            lines += generic_table(name, res)
    return "\n".join(lines)


def write_doc(generated: str) -> None:
    DOC.parent.mkdir(parents=True, exist_ok=True)
    text = DOC.read_text() if DOC.exists() else f"# Performance\n\n{BEGIN}\n{END}\n"
    if BEGIN not in text or END not in text:
        text += f"\n{BEGIN}\n{END}\n"
    head, rest = text.split(BEGIN, 1)
    _, tail = rest.split(END, 1)
    DOC.write_text(f"{head}{BEGIN}\n{generated}\n{END}{tail}")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="small sizes")
    ap.add_argument("--only", nargs="*", help="benchmarks to run (names without bench_)")
    ap.add_argument("--no-run", action="store_true", help="only regenerate the tables")
    ap.add_argument("--timeout", type=float, default=3600.0, help="per benchmark [s] (the full cost-model survey takes about half an hour)")
    ap.add_argument("--one", metavar="NAME", help="run one benchmark in this process (what each process runs)")
    args = ap.parse_args()
    if args.one:
        run_one(args.one, args.quick)
        return 0
    log = []
    if not args.no_run:
        for name, path in benchmarks():
            if args.only and name not in args.only:
                continue
            if args.quick and name in FULL_ONLY and not args.only:
                print(f"[run_all] {name}: left out with --quick ({FULL_ONLY[name]})", flush=True)
                continue
            log.append(run(name, path, args.quick, args.timeout))
    write_doc(generate(log, args.quick))
    print(f"[run_all] wrote {DOC.relative_to(ROOT)} and figures in docs/figures/")
    return 1 if any(r["rc"] != 0 for r in log) else 0


if __name__ == "__main__":
    sys.exit(main())
