"""Contracts of the frequency-response methods, measured: claim, check, estimated against measured cost.

For every method of :data:`vibss.frequency.kernels.METHODS` on five models (a large chain kept sparse
with one input and two outputs, for ``subspace`` and ``sparse``; a chain with general damping, the
same chain classically damped for ``modal``, the 1-ulp graded chain of
tests/frequency/test_complex_modal_check.py and the 12-DOF penalty-link model of
tests/frequency/test_contracts.py), single BLAS thread:

- its cost estimate ``cost(plant, nf, basis)`` (seconds, peak bytes) against the kernel's measured
  wall time and its peak of traced allocations (``tracemalloc``: NumPy reports its buffers there);
- its a-posteriori check (:func:`vibss.frequency.contracts.check`): the error it states, its limit,
  and the check's own time (for ``complex_modal`` also its error estimate's extra cost), against the
  true error at every frequency against ``direct``
  (max over frequencies of ||H - H_ref||_F / ||H_ref||_F; against ``sparse`` on the sparse plant).

Written to benchmarks/results/contracts.json; docs/methods.md quotes it. Run:
``python benchmarks/bench_contracts.py [--quick]`` (quick: 20 bodies, 100 frequencies, a 600-DOF
sparse chain; full: 100 bodies, 400 frequencies, a 6,000-DOF sparse chain).
"""

from __future__ import annotations

import sys
import time
import tracemalloc
import warnings
from pathlib import Path

import numpy as np
from threadpoolctl import threadpool_limits

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from benchmarks.models import chain_model  # noqa: E402
from vibss.errors import AnalysisError  # noqa: E402
from vibss.frequency.contracts import check  # noqa: E402
from vibss.frequency.kernels import METHODS  # noqa: E402
from vibss.linear.eigen.basis import modal_basis  # noqa: E402
from vibss.linear.plant.build import build_plant  # noqa: E402
from vibss.methods import MEMORY_FRACTION, available_memory  # noqa: E402


def _err(h: np.ndarray, ref: np.ndarray) -> float:
    with np.errstate(invalid="ignore", divide="ignore"):
        e = np.linalg.norm(h - ref, axis=(0, 1)) / np.linalg.norm(ref, axis=(0, 1))
    return float(np.nanmax(e))


def _models(quick: bool) -> dict:
    from frequency.test_complex_modal_check import nudged_chain
    from frequency.test_contracts import penalty_model

    nb = 20 if quick else 100
    step = max(1, nb // 3)
    ins = [f"b{i * step}.f{'xyz'[i % 3]}" for i in range(2)]
    outs = [f"b{i * step}.{d}" for i in range(3) for d in ("x", "z")]
    big = 100 if quick else 1000
    return {f"sparse chain {6 * big} DOF, 1 x 2 channels": (chain_model(big, damping="general", zeta=1e-3),
                                                          ["b0.fz"], [f"b{big - 1}.z", f"b{big // 2}.x"]),
            f"chain {6 * nb} DOF, general damping": (chain_model(nb, damping="general", zeta=1e-3), ins, outs),
            f"chain {6 * nb} DOF, classical damping": (chain_model(nb, damping="classical", zeta=1e-3), ins, outs),
            "graded chain 48 DOF, 1 ulp up": (nudged_chain(), ["b0.fz", "b7.fx"], ["b0.z", "b3.y", "b7.x", "b7.rz"]),
            "penalty link 12 DOF (seed 93)": (penalty_model(93), ["a.fz", "b.fx"],
                                              [f"{b}.{d}" for b in ("a", "b") for d in ("x", "y", "z", "rx")])}


def bench(quick: bool) -> dict:
    """Every frequency method's estimate, measured cost, check and true error on three models."""
    nf = 100 if quick else 400
    out: dict = {"frequencies": nf, "threads": 1, "cases": {}}
    for label, (model, ins, outs) in _models(quick).items():
        large = label.startswith("sparse")
        plant = build_plant(model, ins, outs, sparse=large)
        basis = None if large else modal_basis(plant)
        if basis is None:
            f = np.geomspace(1.0, 100.0, nf)
        else:
            w = np.sqrt(np.maximum(basis.omega2[~basis.rigid], 1e-12))
            f = np.geomspace(0.5 * w.min(), 1.5 * w.max(), nf) / (2 * np.pi)
        s = 2j * np.pi * f
        rows = {}
        with threadpool_limits(1), warnings.catch_warnings():
            warnings.simplefilter("ignore")
            ref = METHODS["sparse" if large else "direct"](plant, s, basis)
            for name, m in METHODS.items():
                if large and not m.sparse_ok:
                    continue
                est = m.cost(plant, nf, basis) if m.cost is not None else None
                if est is not None and (est.seconds > 120 or est.bytes > MEMORY_FRACTION * available_memory()):
                    rows[name] = {"skipped": f"estimated {est.text()}: past 120 s or the memory guard"}
                    print(f"{label:38s} {name:13s} skipped: estimated {est.text()}", flush=True)
                    continue
                try:
                    m.kernel(plant, s[:1], basis)            # imports and first-call costs out of the timing
                except AnalysisError:
                    pass
                tracemalloc.start()
                t = time.perf_counter()
                try:
                    raw = m.kernel(plant, s, basis)
                except AnalysisError as exc:
                    tracemalloc.stop()
                    rows[name] = {"refused": str(exc)[:160]}
                    continue
                sec = time.perf_counter() - t
                peak = tracemalloc.get_traced_memory()[1]
                tracemalloc.stop()
                own = None
                if m.self_checked:
                    raw, _note, *rest = raw
                    own = rest[0] if rest else None
                estimate, estimate_s = None, None
                if m.estimated is not None:              # the kernel with its error estimate: its extra cost
                    t = time.perf_counter()
                    raw, estimate = m.estimated(plant, s, basis)
                    estimate_s = time.perf_counter() - t - sec
                t = time.perf_counter()
                c = check(m, plant, s, raw, own, basis, estimate)
                check_s = time.perf_counter() - t
                rows[name] = {"claim": m.claim.text() if m.claim else "", "estimate_s": est.seconds if est else None,
                              "estimate_bytes": est.bytes if est else None, "seconds": sec, "peak_bytes": peak,
                              "check_error": c.error if c else None, "check_limit": c.limit if c else None,
                              "check_ok": c.ok if c else None, "check_s": check_s, "true_error": _err(raw, ref),
                              "error_estimate_s": estimate_s}
                r = rows[name]
                print(f"{label:38s} {name:13s} est {r['estimate_s'] or 0:.2g} s {(r['estimate_bytes'] or 0) / 1e6:.3g} MB"
                      f" | ran {sec:.3g} s {peak / 1e6:.3g} MB | check {r['check_error'] if c else float('nan'):.1e}"
                      f" <= {r['check_limit'] if c else float('nan'):.0e} {'ok' if c and c.ok else 'MISS' if c else '-'}"
                      f" in {check_s:.3g} s" + (f" (+{estimate_s:.2g} s its estimate)" if estimate_s is not None else "")
                      + f" | true {r['true_error']:.1e}", flush=True)
        out["cases"][label] = {"n_dof": plant.n, "methods": rows}
    return out


if __name__ == "__main__":
    from run_all import main_one

    main_one("contracts")
