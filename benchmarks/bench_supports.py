"""Multi-support excitation: its cost and its exactness against the rigid ground, in one run.

``chain_model(100)`` (600 DOF, 200 ground mounts); its twin puts the ground mounts of each quarter of
the chain on a support of its own (4 supports, ``q0`` .. ``q3``). Timed in the same run, single BLAS
thread, best of two calls:

- assembly of each model (the twin's ground coupling has 4 more 6-column blocks), and of the model
  with every ground mount on a support of its own (200 supports, 1206 ground-side columns);
- FRF, 36 outputs x 1000 log-spaced frequencies, ``frequency_response`` (``auto``): the rigid model's
  one input ``ground.z.acc`` against the twin's four ``q<k>.z.acc``; exactness: the sum of the
  twin's four columns against the rigid column (max over frequencies of ||sum - ref|| / ||ref||);
- the stock path on the twin: ``control.frequency_response`` of its python-control state space
  (``vibss.statespace``), timed, and its error against vibss's FRF;
- time response, 2000 steps (``simulate``, ``auto``): the rigid model under ``ground.z.acc``
  against the twin with its four inputs given the same signal; the twin's error against the rigid.

Run: ``python benchmarks/bench_supports.py [--quick]``; results in ``benchmarks/results/supports.json``.
"""

from __future__ import annotations

import argparse
import json
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
from threadpoolctl import threadpool_limits

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from benchmarks.machine import machine, timed  # noqa: E402
from benchmarks.models import chain_model  # noqa: E402
from vibss import Model, Support, assemble, frequency_response, simulate, statespace  # noqa: E402
from vibss.linear.plant.build import build_plant  # noqa: E402


def on_supports(model: Model, groups: int) -> Model:
    """The model with its ground mounts split, in order, into ``groups`` supports ``q0`` ...
    (``groups`` = the number of ground mounts: one support each)."""
    ground = [m for m in model.mounts if m.to == "ground"]
    per = -(-len(ground) // groups)
    which = {m.name: f"q{i // per}" for i, m in enumerate(ground)}
    mounts = [replace(m, support=which[m.name]) if m.name in which else m for m in model.mounts]
    names = sorted(set(which.values()), key=lambda s: int(s[1:]))
    return replace(model, mounts=tuple(mounts), supports=tuple(Support(s) for s in names),
                   name=f"{model.name} on {len(names)} supports")


def _err(h: np.ndarray, ref: np.ndarray) -> float:
    return float(np.max(np.linalg.norm(h - ref, axis=0) / np.linalg.norm(ref, axis=0)))


def run(n_bodies: int, n_freq: int, steps: int) -> dict:
    base = chain_model(n_bodies, damping="classical", zeta=1e-3)
    twin = on_supports(base, 4)
    each = on_supports(base, sum(m.to == "ground" for m in base.mounts))
    step = max(1, n_bodies // 6)
    outputs = [f"b{i * step}.{d}" for i in range(6) for d in ("x", "y", "z", "rx", "ry", "rz")]
    ins = [f"{s.name}.z.acc" for s in twin.supports]
    p0, p1 = build_plant(base, ["ground.z.acc"], outputs), build_plant(twin, ins, outputs)
    w2 = np.linalg.eigvalsh(np.linalg.solve(p0.M, p0.K))
    w2 = w2[w2 > 0]
    f = np.geomspace(0.5 * np.sqrt(w2.min()), 1.5 * np.sqrt(w2.max()), n_freq) / (2 * np.pi)
    out: dict = {"n_dof": p0.n, "supports": len(twin.supports), "frequencies": n_freq, "machine": machine()}
    with threadpool_limits(1):
        ta0, _ = timed(lambda: assemble(base), min_time=float("inf"), repeat=2)
        ta1, _ = timed(lambda: assemble(twin), min_time=float("inf"), repeat=2)
        ta2, a2 = timed(lambda: assemble(each), min_time=float("inf"), repeat=2)
        t0, r0 = timed(lambda: frequency_response(replace(p0), frequencies=f), min_time=float("inf"), repeat=2)
        t1, r1 = timed(lambda: frequency_response(replace(p1), frequencies=f), min_time=float("inf"), repeat=2)
        sys_ = statespace(p1)
        import control

        ts, rs = timed(lambda: control.frequency_response(sys_, 2 * np.pi * f), min_time=float("inf"), repeat=1)
    ref = r0.response[:, 0]
    total = r1.response.sum(axis=1)
    stock = np.asarray(rs.frdata).reshape(r1.response.shape)
    out["assembly"] = {"rigid_s": ta0, "four_supports_s": ta1, "ratio_four": ta1 / ta0,
                       "one_support_per_mount_s": ta2, "ratio_each": ta2 / ta0, "ground_columns_each": a2.nz}
    out["frf"] = {"rigid_1_input_s": t0, "rigid_method": r0.method, "supports_4_inputs_s": t1,
                  "supports_method": r1.method, "ratio": t1 / t0,
                  "error_sum_of_supports_vs_rigid": _err(total, ref),
                  "control_frequency_response_4_inputs_s": ts, "speedup_vs_control": ts / t1,
                  "error_control_vs_vibss": max(_err(stock[:, j], r1.response[:, j]) for j in range(len(ins)))}
    a, fr = out["assembly"], out["frf"]
    print(f"assembly {p0.n} DOF: rigid {ta0 * 1e3:.1f} ms, 4 supports {ta1 * 1e3:.1f} ms (x{a['ratio_four']:.2f}), "
          f"{len(each.supports)} supports ({a2.nz} ground columns) {ta2 * 1e3:.1f} ms (x{a['ratio_each']:.2f})")
    print(f"FRF x {n_freq} frequencies x 36 outputs: rigid 1 input {t0:.3f} s ({r0.method}), 4 supports "
          f"{t1:.3f} s ({r1.method}), ratio {fr['ratio']:.2f}; sum of supports vs rigid {fr['error_sum_of_supports_vs_rigid']:.1e}")
    print(f"  control.frequency_response of the twin's state space: {ts:.2f} s ({fr['speedup_vs_control']:.1f}x "
          f"vibss), error vs vibss {fr['error_control_vs_vibss']:.1e}", flush=True)

    dt = 2e-4
    tk = np.arange(steps // 50 + 2) * 50 * dt
    knots = np.random.default_rng(1).standard_normal(tk.size)
    u = lambda t: np.interp(t, tk, knots)  # noqa: E731
    outs = [f"b{n_bodies // 3}.{d}" for d in ("x", "y", "z", "rx", "ry", "rz")]
    with threadpool_limits(1):
        tt0, y0 = timed(lambda: simulate(base, inputs={"ground.z.acc": u}, outputs=outs, t_end=steps * dt, dt=dt),
                        min_time=float("inf"), repeat=2)
        tt1, y1 = timed(lambda: simulate(twin, inputs={k: u for k in ins}, outputs=outs, t_end=steps * dt, dt=dt),
                        min_time=float("inf"), repeat=2)
    err = float(np.abs(y1.outputs - y0.outputs).max() / np.abs(y0.outputs).max())
    out["time"] = {"steps": steps, "rigid_s": tt0, "supports_s": tt1, "ratio": tt1 / tt0, "method": y1.method,
                   "error_vs_rigid": err}
    print(f"time {steps} steps: rigid {tt0:.3f} s, 4 supports moved alike {tt1:.3f} s ({y1.method}), "
          f"ratio {tt1 / tt0:.2f}; error vs rigid {err:.1e}")
    return out


if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    n_bodies, n_freq, steps = (20, 200, 1000) if args.quick else (100, 1000, 2000)
    result = run(n_bodies, n_freq, steps)
    path = Path(__file__).resolve().parent / "results" / "supports.json"
    path.parent.mkdir(exist_ok=True)
    path.write_text(json.dumps(result, indent=2))
    print(f"wrote {path}")
