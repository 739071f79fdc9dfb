"""Frequency-dependent mounts: their cost against constant mounts and against the floors, in one run.

``chain_model(100)`` (600 DOF); the frequency-dependent twin gives every ground mount a Zener
rheology with the same static stiffness (``k_inf = 2 k_0``, ``tau`` at the geometric middle of the
band), so each adds three internal Maxwell states (600 in all: the frequency-dependent part has
full rank). The *engine* variant makes only the four ground mounts of two middle bodies Zener (12
branches on the 600-DOF frame, the common engineering case: low rank). Timed in the same run,
single BLAS thread, best of two calls, a fresh copy of the plant each call (nothing cached carries
over):

- FRF, 6 force inputs x 36 outputs x 1000 log-spaced frequencies: the ``sparse`` exact solve
  (banded LU) of each model, and ``frequency_response(method="auto")`` of each (the user-facing
  call: choice, modes where needed, resonance marks and all); errors against the
  dense ``direct`` solve of the same plant (max over every fourth frequency of
  ||H - H_ref||_F / ||H_ref||_F);
- the FRF *floor*: LAPACK ``zgbsv`` alone (scipy.linalg.lapack) on the same RCM-ordered banded
  ``K + sC + s^2 M + g(s) K1`` of the full-rank twin at the 1000 frequencies (only the calls timed,
  each on a band already in cache): what any exact per-frequency solve pays when the
  frequency-dependent part has full rank;
- time response, 2 force inputs x 6 outputs x 2000 steps: the constant model's ``auto`` (exact
  modal) path against each frequency-dependent model's ``auto`` path; the time *floors*: one dense
  ``eig`` and one ``expm`` of the (2n + r)-state matrix (what any exact discretisation of the
  augmented system pays); the engine twin's ``auto`` (the exact modal FOH on the modes plus the
  branch states, :mod:`vibss.time.branched`) beside its ``forced_response`` (what ``auto`` ran
  before) and their largest difference; errors against ``solve_ivp`` (Radau, rtol 1e-10) of the
  same state space on smaller chains (5 bodies every ground mount Zener; 20 bodies the engine
  variant).

The FRF part runs ``--rounds`` rounds (default 3) of every timing and reports each time's best
sample in the run (the least disturbed by the other jobs) as a table beside the zgbsv floor, with
every round's own ratios and load listed (the shared VM's load moves the ratios by tens of percent).

Run: ``python benchmarks/bench_mounts.py [--quick] [--time | --frf] [--rounds N]`` (``--time``: the time
response only, the FRF kept from the last run; ``--frf`` the other way round); results in
``benchmarks/results/mounts.json``, the printed tables in ``benchmarks/results/mounts.txt``.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import warnings
from dataclasses import replace
from pathlib import Path

import time

import numpy as np
import scipy.linalg as sl
from scipy.integrate import solve_ivp
from scipy.linalg.lapack import zgbsv
from threadpoolctl import threadpool_limits

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from benchmarks.machine import machine, timed  # noqa: E402
from benchmarks.models import chain_model  # noqa: E402
from vibss import Model, MountType, frequency_response, simulate, statespace  # noqa: E402
from vibss.frequency.kernels import METHODS  # noqa: E402
from vibss.linear.solve.banded import structure  # noqa: E402
from vibss.linear.plant.branches import groups  # noqa: E402
from vibss.linear.plant.build import build_plant  # noqa: E402


def zener_twin(model: Model, tau: float, only: tuple[str, ...] | None = None) -> Model:
    """The model with every ground mount's type (or the mounts named in ``only``) made a Zener of
    the same static stiffness."""
    mounts = []
    for m in model.mounts:
        if (m.to == "ground") if only is None else (m.name in only):
            t = m.type
            z = MountType(t.name + "_z", damping=t.damping,
                          rheology={"type": "zener", "k_0": t.stiffness, "k_inf": 2 * t.stiffness, "tau": tau})
            m = replace(m, type=z)
        mounts.append(m)
    what = "Zener ground mounts" if only is None else f"Zener mounts {list(only)}"
    return replace(model, mounts=tuple(mounts), name=model.name + f" ({what})")


def engine_mounts(model: Model, n_bodies: int) -> tuple[str, ...]:
    """The four ground mounts of the two middle bodies (an engine's four mounts on the frame)."""
    mid = {f"b{n_bodies // 2}", f"b{n_bodies // 2 + 1}"}
    return tuple(m.name for m in model.mounts if m.to == "ground" and m.body in mid)


def zgbsv_floor(plant, s: np.ndarray) -> float:
    """Seconds of LAPACK ``zgbsv`` alone on the plant's RCM-ordered band at every ``s`` (the same
    matrices the ``sparse`` kernel factorises). Only the calls are timed: each band is assembled
    beforehand and copied into one work array just before its call (so it is in cache, as in the
    kernel, which reuses one array), and the right-hand sides likewise."""
    st = structure(plant)
    band, n = st.band, plant.n
    rhs = np.asfortranarray(np.asarray(plant.F, complex)[st.perm])
    gs = groups(plant)
    total = 0.0
    ab = np.zeros((3 * band + 1, n), complex, order="F")
    b = np.empty_like(rhs, order="F")
    for lo in range(0, s.size, 100):
        mats = []
        for sk in s[lo:lo + 100]:
            a = st.parts["K"] + sk * sk * st.parts["M"] + sk * st.parts.get("C", 0.0)
            for j, g in enumerate(gs):
                a = a + complex(g.factor(np.array(sk))) * st.parts[f"G{j}"]
            mats.append(a)
        for a in mats:
            ab[:band] = 0.0
            ab[band:] = a
            b[:] = rhs
            t0 = time.perf_counter()
            zgbsv(band, band, ab, b, overwrite_ab=1, overwrite_b=1)
            total += time.perf_counter() - t0
    return total


def state_floors(plant, dt: float) -> dict:
    """Seconds of one dense ``eig`` and one ``expm`` of the plant's state matrix (with the branch states)."""
    a = np.asarray(statespace(plant).A)
    t0 = time.perf_counter()
    sl.eig(a)
    t_eig = time.perf_counter() - t0
    t0 = time.perf_counter()
    sl.expm(a * dt)
    return {"states": a.shape[0], "eig_s": t_eig, "expm_s": time.perf_counter() - t0}


def _err(h: np.ndarray, ref: np.ndarray) -> float:
    return float(np.max(np.linalg.norm(h - ref, axis=(0, 1)) / np.linalg.norm(ref, axis=(0, 1))))


def _frf_round(p0, p1, p2, f: np.ndarray, s: np.ndarray) -> tuple[dict, tuple]:
    """One round of the FRF timings (every figure of it in the same minute: the load drifts), and the
    responses it computed (for the errors)."""
    with threadpool_limits(1):
        floor = min(zgbsv_floor(p1, s) for _ in range(2))
        t_const, _ = timed(lambda: METHODS["sparse"](replace(p0), s), min_time=float("inf"), repeat=2)
        t_freq, h1 = timed(lambda: METHODS["sparse"](replace(p1), s), min_time=float("inf"), repeat=2)
        t_few, h2s = timed(lambda: METHODS["sparse"](replace(p2), s), min_time=float("inf"), repeat=2)
        ta_const, r0 = timed(lambda: frequency_response(replace(p0), frequencies=f), min_time=float("inf"), repeat=2)
        ta_freq, r1 = timed(lambda: frequency_response(replace(p1), frequencies=f), min_time=float("inf"), repeat=2)
        ta_few, r2 = timed(lambda: frequency_response(replace(p2), frequencies=f), min_time=float("inf"), repeat=2)
        ta_const2, _ = timed(lambda: frequency_response(replace(p0), frequencies=f), min_time=float("inf"), repeat=2)
    ta_const = min(ta_const, ta_const2)
    return {"load_average": os.getloadavg()[0], "zgbsv_floor_s": floor,
            "sparse_constant_s": t_const, "sparse_frequency_dependent_s": t_freq,
            "ratio_sparse": t_freq / t_const, "sparse_over_floor": t_freq / floor,
            "auto_constant_s": ta_const, "auto_constant_method": r0.method,
            "auto_frequency_dependent_s": ta_freq, "auto_frequency_dependent_method": r1.method,
            "auto_frequency_dependent_note": r1.note[-400:],
            "ratio_auto": ta_freq / ta_const, "auto_over_floor": ta_freq / floor,
            "floor_over_auto_constant": floor / ta_const,
            "engine_sparse_s": t_few, "engine_auto_s": ta_few, "engine_auto_method": r2.method,
            "engine_ratio_auto": ta_few / ta_const}, (h1, h2s, r1, r2)


def _frf(out: dict, p0, p1, p2, f: np.ndarray, s: np.ndarray, n_freq: int, rounds: int) -> None:
    """The FRF part of :func:`run` (into ``out["frf"]``): ``rounds`` rounds, each time's best sample
    over them reported, every round's ratios listed."""
    every = slice(None, None, 4)
    runs = [_frf_round(p0, p1, p2, f, s) for _ in range(rounds)]
    h1, h2s, r1, r2 = runs[-1][1]
    best = dict(runs[-1][0])
    for key in [k for k in best if k.endswith("_s")]:          # each time: its least-disturbed sample
        best[key] = min(x[key] for x, _ in runs)
    best.update({"load_average": min(x["load_average"] for x, _ in runs),
                 "ratio_sparse": best["sparse_frequency_dependent_s"] / best["sparse_constant_s"],
                 "sparse_over_floor": best["sparse_frequency_dependent_s"] / best["zgbsv_floor_s"],
                 "ratio_auto": best["auto_frequency_dependent_s"] / best["auto_constant_s"],
                 "auto_over_floor": best["auto_frequency_dependent_s"] / best["zgbsv_floor_s"],
                 "floor_over_auto_constant": best["zgbsv_floor_s"] / best["auto_constant_s"],
                 "engine_ratio_auto": best["engine_auto_s"] / best["auto_constant_s"],
                 "best_round_ratio_auto": min(x["ratio_auto"] for x, _ in runs)})
    with threadpool_limits(1):
        href = METHODS["direct"](replace(p1), s[every])
        href2 = METHODS["direct"](replace(p2), s[every])
    fr = dict(best)
    fr.update({"rounds": [x for x, _ in runs], "best_of": rounds,
               "error_sparse_vs_direct": _err(h1[..., every], href),
               "error_auto_vs_direct": _err(r1.response[..., every], href),
               "engine_error_auto_vs_direct": _err(r2.response[..., every], href2),
               "engine_error_sparse_vs_direct": _err(h2s[..., every], href2)})
    out["frf"] = fr
    c = fr["auto_constant_s"]
    print(f"FRF {p0.n} DOF x {n_freq} frequencies x 6 inputs x 36 outputs, one BLAS thread; each time the best of "
          f"{rounds} rounds x 2 calls in this run (load {min(x['load_average'] for x, _ in runs):.1f}-"
          f"{max(x['load_average'] for x, _ in runs):.1f}); errors: max over every fourth frequency of "
          "||H - H_direct||_F / ||H_direct||_F")
    print(f"  {'':44} {'seconds':>8} {'/ const auto':>13} {'/ floor':>8} {'error':>9}")
    rows = [(f"constant mounts, auto ({fr['auto_constant_method']})", c, None),
            ("floor: zgbsv alone on the Zener band", fr["zgbsv_floor_s"], None),
            (f"Zener ({p1.branches.r} branches), sparse", fr["sparse_frequency_dependent_s"],
             fr["error_sparse_vs_direct"]),
            (f"Zener, auto ({fr['auto_frequency_dependent_method']})", fr["auto_frequency_dependent_s"],
             fr["error_auto_vs_direct"]),
            (f"engine ({p2.branches.r} branches), sparse", fr["engine_sparse_s"], fr["engine_error_sparse_vs_direct"]),
            (f"engine, auto ({fr['engine_auto_method']})", fr["engine_auto_s"], fr["engine_error_auto_vs_direct"]),
            ("constant mounts, sparse", fr["sparse_constant_s"], None)]
    for name, sec, err in rows:
        print(f"  {name:44} {sec:8.3f} {sec / c:13.2f} {sec / fr['zgbsv_floor_s']:8.2f} "
              f"{'' if err is None else f'{err:9.1e}'}")
    print(f"  every round (load; constant auto, floor, Zener auto s; Zener/constant, floor/constant); the best "
          f"round's Zener/constant: {fr['best_round_ratio_auto']:.2f}")
    for x, _ in runs:
        print(f"    load {x['load_average']:.1f}: {x['auto_constant_s']:.3f}, {x['zgbsv_floor_s']:.3f}, "
              f"{x['auto_frequency_dependent_s']:.3f}; {x['ratio_auto']:.2f}, {x['floor_over_auto_constant']:.2f}",
              flush=True)


def run(n_bodies: int, n_freq: int, steps: int, frf: bool = True, rounds: int = 3, time_part: bool = True) -> dict:
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
    engine = engine_mounts(base, n_bodies)
    few = zener_twin(base, tau, engine)
    p2 = build_plant(few, inputs, outputs)
    s = 2j * np.pi * f
    out: dict = {"n_dof": p0.n, "branch_states": p1.branches.r, "engine_branch_states": p2.branches.r,
                 "engine_mounts": list(engine), "frequencies": n_freq, "machine": machine()}
    if frf:
        _frf(out, p0, p1, p2, f, s, n_freq, rounds)
    if not time_part:
        return out
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
        run_ = lambda m, method="auto": simulate(m, inputs=forces, outputs=outs, t_end=t_end, dt=dt,  # noqa: E731
                                                 method=method)
        tt_const, y0 = timed(lambda: run_(base), min_time=float("inf"), repeat=3)
        tt_freq, y1 = timed(lambda: run_(twin), min_time=float("inf"), repeat=2)
        tt_few, y2 = timed(lambda: run_(few), min_time=float("inf"), repeat=3)
        tt_few_old, y3 = timed(lambda: run_(few, "forced_response"), min_time=float("inf"), repeat=2)
        tt_const2, _ = timed(lambda: run_(base), min_time=float("inf"), repeat=3)   # the load drifts
        tt_const = min(tt_const, tt_const2)
        fl1 = state_floors(build_plant(twin, list(forces), outs), dt)
        fl2 = state_floors(build_plant(few, list(forces), outs), dt)
    diff = float(np.max(np.abs(y2.outputs - y3.outputs).max(axis=1) / np.abs(y3.outputs).max(axis=1)))
    out["time"] = {"steps": steps, "constant_s": tt_const, "constant_method": y0.method,
                   "frequency_dependent_s": tt_freq, "frequency_dependent_method": y1.method,
                   "ratio": tt_freq / tt_const, "floor": fl1,
                   "floor_over_constant": min(fl1["eig_s"], fl1["expm_s"]) / tt_const,
                   "engine_s": tt_few, "engine_method": y2.method, "engine_ratio": tt_few / tt_const,
                   "engine_note": y2.note,
                   "engine_forced_response_s": tt_few_old, "engine_forced_response_ratio": tt_few_old / tt_const,
                   "engine_vs_forced_response": diff,
                   "engine_floor": fl2,
                   "engine_floor_over_constant": min(fl2["eig_s"], fl2["expm_s"]) / tt_const}
    tm = out["time"]
    print(f"time {steps} steps x 2 inputs x 6 outputs (seconds): constant {tt_const:.2f} ({y0.method})")
    print(f"  Zener ({fl1['states']} states): {tt_freq:.2f} ({y1.method}), ratio {tm['ratio']:.1f}; floor: eig "
          f"{fl1['eig_s']:.2f}, expm {fl1['expm_s']:.2f} = {tm['floor_over_constant']:.1f} x the constant")
    print(f"  engine ({fl2['states']} states): auto {tt_few:.2f} ({y2.method}), ratio {tm['engine_ratio']:.2f}; "
          f"forced_response {tt_few_old:.2f}, ratio {tm['engine_forced_response_ratio']:.1f}; max rel. difference "
          f"{diff:.1e}; floor: eig {fl2['eig_s']:.2f}, expm {fl2['expm_s']:.2f} = "
          f"{tm['engine_floor_over_constant']:.1f} x the constant", flush=True)
    return out


def time_accuracy(n_bodies: int = 5, steps: int = 2000, engine: bool = False) -> tuple[float, str]:
    """Relative error of the Zener chain's time response (``auto``) against solve_ivp of its state
    space, and the method that ran; ``engine``: only the middle bodies' ground mounts are Zener."""
    base = chain_model(n_bodies, damping="classical", zeta=1e-2)
    twin = zener_twin(base, 1e-3, engine_mounts(base, n_bodies) if engine else None)
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
    return float(np.abs(r.outputs[0] - y).max() / np.abs(y).max()), r.method


if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--time", action="store_true", help="the time response only (the FRF kept from the last run)")
    ap.add_argument("--frf", action="store_true", help="the FRF only (the time response kept from the last run)")
    ap.add_argument("--rounds", type=int, default=3, help="FRF rounds; the best same-run ratio is reported")
    args = ap.parse_args()
    n_bodies, n_freq, steps = (20, 200, 1000) if args.quick else (100, 1000, 2000)
    path = Path(__file__).resolve().parent / "results" / "mounts.json"
    result = run(n_bodies, n_freq, steps, frf=not args.time, rounds=args.rounds, time_part=not args.frf)
    last = json.loads(path.read_text()) if path.exists() else {}
    if args.time and last:
        result = {**last, "time": result["time"], "machine": result["machine"]}
    if args.frf and last:
        result = {**last, "frf": result["frf"], "machine": result["machine"]}
        print("time response: kept from the last run in mounts.json (benchmarks/bench_mounts.py --time)")
    if not args.frf:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            steps_ivp = 400 if args.quick else 2000         # solve_ivp (Radau, rtol 1e-10) is the slow side
            err, how = time_accuracy(steps=steps_ivp)
            err2, how2 = time_accuracy(20, steps=steps_ivp, engine=True)  # 20 bodies: auto takes the structured path
        result["time"]["error_vs_solve_ivp_5_bodies"] = err
        result["time"]["engine_error_vs_solve_ivp_20_bodies"] = err2
        print(f"time response of a 5-body Zener chain vs solve_ivp of its state space: {err:.1e} ({how}); "
              f"a 20-body chain with only its two middle bodies' ground mounts Zener: {err2:.1e} ({how2})")
    path.parent.mkdir(exist_ok=True)
    path.write_text(json.dumps(result, indent=2))
    print(f"wrote {path}")
