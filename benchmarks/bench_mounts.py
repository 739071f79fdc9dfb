"""Frequency-dependent mounts: their cost against constant mounts, in one run.

``chain_model(100)`` (600 DOF); the frequency-dependent twin gives every ground mount a Zener
rheology with the same static stiffness (``k_inf = 2 k_0``, ``tau`` at the geometric middle of the
band), so each adds three internal Maxwell states (600 in all). Timed in the same run, single BLAS
thread, best of two calls, a fresh copy of the plant each call (nothing cached carries over):

- FRF, 6 force inputs x 36 outputs x 1000 log-spaced frequencies: the ``sparse`` exact solve
  (banded LU) of each model, and ``frequency_response(method="auto")`` of each; error of the
  frequency-dependent ``sparse`` against the dense ``direct`` solve of the same plant
  (max over frequencies of ||H - H_ref||_F / ||H_ref||_F);
- time response, 2 force inputs x 6 outputs x 2000 steps: the constant model's ``auto`` (exact
  modal) path against the frequency-dependent model's (``forced_response`` of the state space with
  the branch states); its error against ``solve_ivp`` (Radau, rtol 1e-10) of the same state space
  on a smaller chain (``--quick`` size) where that is affordable.

Run: ``python benchmarks/bench_mounts.py [--quick]``; results in ``benchmarks/results/mounts.json``.
"""

from __future__ import annotations

import argparse
import json
import sys
import warnings
from dataclasses import replace
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp
from threadpoolctl import threadpool_limits

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from benchmarks.machine import machine, timed  # noqa: E402
from benchmarks.models import chain_model  # noqa: E402
from vibss import Model, MountType, frequency_response, simulate, statespace  # noqa: E402
from vibss.frequency.kernels import METHODS  # noqa: E402
from vibss.linear.signals import build_plant  # noqa: E402


def zener_twin(model: Model, tau: float) -> Model:
    """The model with every ground mount's type made a Zener of the same static stiffness."""
    mounts = []
    for m in model.mounts:
        if m.to == "ground":
            t = m.type
            z = MountType(t.name + "_z", damping=t.damping,
                          rheology={"type": "zener", "k_0": t.stiffness, "k_inf": 2 * t.stiffness, "tau": tau})
            m = replace(m, type=z)
        mounts.append(m)
    return replace(model, mounts=tuple(mounts), name=model.name + " (Zener ground mounts)")


def _err(h: np.ndarray, ref: np.ndarray) -> float:
    return float(np.max(np.linalg.norm(h - ref, axis=(0, 1)) / np.linalg.norm(ref, axis=(0, 1))))


def run(n_bodies: int, n_freq: int, steps: int) -> dict:
    base = chain_model(n_bodies, damping="classical", zeta=1e-3)
    step = max(1, n_bodies // 6)
    inputs = [f"b{i * step}.f{'xyz'[i % 3]}" for i in range(6)]
    outputs = [f"b{i * step}.{d}" for i in range(6) for d in ("x", "y", "z", "rx", "ry", "rz")]
    p0 = build_plant(base, inputs, outputs)
    w2 = np.linalg.eigvalsh(np.linalg.solve(p0.M, p0.K))
    w2 = w2[w2 > 0]
    f = np.geomspace(0.5 * np.sqrt(w2.min()), 1.5 * np.sqrt(w2.max()), n_freq) / (2 * np.pi)
    tau = 1.0 / (2 * np.pi * float(np.sqrt(f[0] * f[-1])))
    twin = zener_twin(base, tau)
    p1 = build_plant(twin, inputs, outputs)
    s = 2j * np.pi * f
    out: dict = {"n_dof": p0.n, "branch_states": p1.branches.r, "frequencies": n_freq, "machine": machine()}
    with threadpool_limits(1):
        t_const, _ = timed(lambda: METHODS["sparse"](replace(p0), s), min_time=float("inf"), repeat=2)
        t_freq, h1 = timed(lambda: METHODS["sparse"](replace(p1), s), min_time=float("inf"), repeat=2)
        href = METHODS["direct"](replace(p1), s)
        ta_const, r0 = timed(lambda: frequency_response(replace(p0), frequencies=f), min_time=float("inf"), repeat=2)
        ta_freq, r1 = timed(lambda: frequency_response(replace(p1), frequencies=f), min_time=float("inf"), repeat=2)
    out["frf"] = {"sparse_constant_s": t_const, "sparse_frequency_dependent_s": t_freq,
                  "ratio_sparse": t_freq / t_const, "error_sparse_vs_direct": _err(h1, href),
                  "auto_constant_s": ta_const, "auto_constant_method": r0.method,
                  "auto_frequency_dependent_s": ta_freq, "auto_frequency_dependent_method": r1.method,
                  "ratio_auto": ta_freq / ta_const}
    fr = out["frf"]
    print(f"FRF {p0.n} DOF (+{p1.branches.r} branch states) x {n_freq} frequencies x 6 x 36:")
    print(f"  sparse: constant {t_const:.2f} s, Zener {t_freq:.2f} s, ratio {fr['ratio_sparse']:.2f} "
          f"(Zener error vs direct {fr['error_sparse_vs_direct']:.1e})")
    print(f"  auto:   constant {ta_const:.2f} s ({r0.method}), Zener {ta_freq:.2f} s ({r1.method}), "
          f"ratio {fr['ratio_auto']:.2f}", flush=True)

    dt = 2e-4
    rng = np.random.default_rng(1)
    knots = rng.standard_normal((2, steps // 50 + 2)) * 100.0
    tk = np.arange(knots.shape[1]) * 50 * dt
    forces = {f"b{n_bodies // 3}.fz": lambda t: np.interp(t, tk, knots[0]),
              f"b{2 * n_bodies // 3}.fx": lambda t: np.interp(t, tk, knots[1])}
    outs = [f"b{n_bodies // 3}.{d}" for d in ("x", "y", "z", "rx", "ry", "rz")]
    t_end = steps * dt
    with warnings.catch_warnings(), threadpool_limits(1):
        warnings.simplefilter("ignore")
        tt_const, y0 = timed(lambda: simulate(base, inputs=forces, outputs=outs, t_end=t_end, dt=dt),
                             min_time=float("inf"), repeat=2)
        tt_freq, y1 = timed(lambda: simulate(twin, inputs=forces, outputs=outs, t_end=t_end, dt=dt),
                            min_time=float("inf"), repeat=2)
    out["time"] = {"steps": steps, "constant_s": tt_const, "constant_method": y0.method,
                   "frequency_dependent_s": tt_freq, "frequency_dependent_method": y1.method,
                   "ratio": tt_freq / tt_const}
    print(f"time {steps} steps x 2 inputs x 6 outputs: constant {tt_const:.2f} s ({y0.method}), "
          f"Zener {tt_freq:.2f} s ({y1.method}), ratio {tt_freq / tt_const:.2f}", flush=True)
    return out


def time_accuracy(n_bodies: int = 5, steps: int = 2000) -> float:
    """Relative error of the Zener chain's time response against solve_ivp of its state space."""
    base = chain_model(n_bodies, damping="classical", zeta=1e-2)
    twin = zener_twin(base, 1e-3)
    dt = 2e-4
    tk = np.arange(0, steps * dt + 50 * dt, 50 * dt)
    knots = np.random.default_rng(2).standard_normal(tk.size) * 100.0
    u = lambda t: np.interp(t, tk, knots)  # noqa: E731
    inp, out = f"b{n_bodies // 2}.fz", [f"b{n_bodies // 2}.z"]
    r = simulate(twin, inputs={inp: u}, outputs=out, t_end=steps * dt, dt=dt)
    sys_ = statespace(build_plant(twin, [inp], out))
    a, b, c = np.asarray(sys_.A), np.asarray(sys_.B)[:, 0], np.asarray(sys_.C)[0]
    y = np.zeros_like(r.time)
    x = np.zeros(a.shape[0])
    for i in range(tk.size - 1):                      # restart at every knot: the input is smooth between
        lo, hi = tk[i], min(tk[i + 1], r.time[-1])
        if lo >= r.time[-1]:
            break
        sel = (r.time >= lo - 1e-12) & (r.time <= hi + 1e-12)
        sol = solve_ivp(lambda t, z: a @ z + b * u(t), (lo, hi), x, method="Radau", rtol=1e-10, atol=1e-16,
                        jac=a, dense_output=True)
        y[sel] = c @ sol.sol(np.clip(r.time[sel], lo, hi))
        x = sol.sol(hi)
    return float(np.abs(r.outputs[0] - y).max() / np.abs(y).max())


if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    n_bodies, n_freq, steps = (20, 200, 1000) if args.quick else (100, 1000, 2000)
    result = run(n_bodies, n_freq, steps)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result["time"]["error_vs_solve_ivp_5_bodies"] = err = time_accuracy()
    print(f"time response of a 5-body Zener chain vs solve_ivp of its state space: {err:.1e}")
    path = Path(__file__).resolve().parent / "results" / "mounts.json"
    path.parent.mkdir(exist_ok=True)
    path.write_text(json.dumps(result, indent=2))
    print(f"wrote {path}")
