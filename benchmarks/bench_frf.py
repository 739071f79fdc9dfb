"""FRF benchmark: python-control's stock path vs vibss's kernels on a 600-DOF chain.

``chain_model(100)`` (600 DOF), 6 force inputs x 36 displacement outputs x 1000 log-spaced
frequencies, zeta ~ 0.001, single BLAS thread. Timed in the same run:

- ``control.frequency_response`` on the plain physical state space ``A = [[0, I], [-M^-1 K, -M^-1 C]]``
  (the stock path: SLICOT TB05AD, no balancing);
- vibss ``modal`` (classical damping) / ``complex_modal`` (general damping), ``sparse`` (the
  direct solve by a banded LU per frequency, both cases), and ``direct`` (the reference: one dense
  complex solve per frequency).

The stock path and vibss's fast paths are each timed as the best of two calls (the same protocol for
both sides of the headline ratio; ``direct`` once); every vibss call gets a fresh copy of the plant,
so nothing it caches (sparse forms, factorisations, the band structure) carries over between calls.
``auto_method`` is what ``frequency_response(method="auto")`` would pick, and why. Error: max over frequencies of
||H - H_ref||_F / ||H_ref||_F against ``direct``. Results are printed and
written to ``benchmarks/results/frf.json``. Run: ``python benchmarks/bench_frf.py [n_bodies] [--quick]`` (quick: 40 bodies, 200 frequencies).
"""

from __future__ import annotations

import json
import sys
import time
from dataclasses import replace
from pathlib import Path

import control
import numpy as np
from threadpoolctl import threadpool_limits

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from benchmarks.models import chain_model  # noqa: E402
from benchmarks.machine import timed  # noqa: E402
from vibss.frequency.methods import choose as _choose  # noqa: E402
from vibss.frequency.kernels import METHODS  # noqa: E402
from vibss.linear.eigen.basis import modal_basis  # noqa: E402
from vibss.linear.plant.build import build_plant  # noqa: E402


def _stock(plant, omega):
    n = plant.n
    minv = np.linalg.inv(plant.M)
    a = np.block([[np.zeros((n, n)), np.eye(n)], [-minv @ plant.K, -minv @ plant.C]])
    b = np.vstack([np.zeros_like(plant.F), minv @ plant.F])
    c = np.hstack([plant.Oq, np.zeros_like(plant.Oq)])
    sys_ = control.ss(a, b, c, np.zeros((c.shape[0], b.shape[1])))
    return np.asarray(control.frequency_response(sys_, omega).complex)


def _err(h, ref):
    num = np.linalg.norm(h - ref, axis=(0, 1))
    return float(np.max(num / np.linalg.norm(ref, axis=(0, 1))))


def run(n_bodies: int = 100, n_freq: int = 1000) -> dict:
    out = {"n_bodies": n_bodies, "n_dof": 6 * n_bodies, "inputs": 6, "outputs": 36,
           "frequencies": n_freq, "threads": 1, "cases": {}}
    for damping, fast in (("classical", "modal"), ("general", "complex_modal")):
        fasts = (fast, "sparse")
        model = chain_model(n_bodies, damping=damping, zeta=1e-3)
        step = max(1, n_bodies // 6)
        inputs = [f"b{i * step}.f{'xyz'[i % 3]}" for i in range(6)]
        outputs = [f"b{i * step}.{d}" for i in range(6) for d in ("x", "y", "z", "rx", "ry", "rz")]
        plant = build_plant(model, inputs, outputs)
        w2 = np.linalg.eigvalsh(np.linalg.solve(np.linalg.cholesky(plant.M), np.linalg.solve(
            np.linalg.cholesky(plant.M), plant.K).T))
        f = np.geomspace(0.5 * np.sqrt(w2.min()), 1.5 * np.sqrt(w2.max()), n_freq) / (2 * np.pi)
        omega = 2 * np.pi * f
        s = 1j * omega
        res = {}
        with threadpool_limits(1):
            t = time.perf_counter(); href = METHODS["direct"](plant, s); res["direct_s"] = time.perf_counter() - t
            # best of two calls for both sides of the headline ratio (same protocol, no warm-up)
            hf = {}
            for name in fasts:
                res[f"{name}_s"], hf[name] = timed(lambda: METHODS[name](replace(plant), s),
                                                   min_time=float("inf"), repeat=2)
            res["control_s"], hs = timed(lambda: _stock(plant, omega), min_time=float("inf"), repeat=2)
            t = time.perf_counter(); hv = METHODS["statespace"](plant, s); res["vibss_statespace_s"] = time.perf_counter() - t
        res.update({"control_error": _err(hs, href), "vibss_statespace_error": _err(hv, href)})
        for name in fasts:
            res.update({f"{name}_error": _err(hf[name], href),
                        f"speedup_{name}_vs_control": res["control_s"] / res[f"{name}_s"],
                        f"speedup_{name}_vs_direct": res["direct_s"] / res[f"{name}_s"]})
        res["auto_method"], res["auto_reason"] = _choose(plant, s.size, modal_basis(plant))
        out["cases"][damping] = res
        print(f"{damping:9s} n={plant.n}: control {res['control_s']:.2f} s (err {res['control_error']:.2e}), "
              f"direct {res['direct_s']:.2f} s; vibss statespace (scaled modal + TB05AD) "
              f"{res['vibss_statespace_s']:.2f} s err {res['vibss_statespace_error']:.2e}", flush=True)
        for name in fasts:
            print(f"    {name:13s} {res[f'{name}_s']:.3f} s (err {res[f'{name}_error']:.2e}): "
                  f"{res[f'speedup_{name}_vs_control']:.1f}x faster than control, "
                  f"{res[f'speedup_{name}_vs_direct']:.0f}x than direct", flush=True)
        print(f"    auto: {res['auto_method']} ({res['auto_reason']})", flush=True)
    return out


if __name__ == "__main__":
    quick = "--quick" in sys.argv                  # make bench-quick: 40 bodies, 200 frequencies
    args = [a for a in sys.argv[1:] if a != "--quick"]
    nb = int(args[0]) if args else (40 if quick else 100)
    result = run(nb, n_freq=200 if quick else 1000)
    path = Path(__file__).resolve().parent / "results" / "frf.json"
    path.parent.mkdir(exist_ok=True)
    path.write_text(json.dumps(result, indent=2))
    print(f"wrote {path}")
