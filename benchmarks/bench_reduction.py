"""Benchmark: study-driven reduction of a 1,000-body chain (6,000 DOF) against the full model.

A frequency response and a time response of a few outputs over a band holding a few dozen modes:
the full model's fastest exact path (FRF: sparse assembly + one complex sparse LU per frequency;
time: build_plant + vibss.time.simulate's exact modal method, dense eigh) against
reduce(model, scope, "krylov") (its own sparse assembly included) + the same analyses on the reduced
plant, single thread. The errors are relative per output (vibss.reduction.relative_error).
Writes benchmarks/results/reduction.json.

Run: ``OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/bench_reduction.py [n_bodies] [--quick]``
(``--quick``: a 100-body chain, 60 frequencies). Deterministic: the model is seeded and every
sparse eigen-solve starts from a seeded vector (ARPACK's default start is random), so two runs give
the same basis sizes (:func:`quick_basis_sizes`, checked by ``tests/test_benchmarks.py``); only the
timings move.
"""

from __future__ import annotations

import json
import platform
import sys
import time
from pathlib import Path

import numpy as np
import scipy.sparse.linalg as spl
from threadpoolctl import threadpool_limits

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks.models import chain_model  # noqa: E402
from vibss import Mount, MountType, assemble  # noqa: E402
from vibss.model.excitation import Excitation  # noqa: E402
from vibss.reduction.api import reduce, relative_error  # noqa: E402
from vibss.reduction.kernels import exact_response, frf, sparse_plant  # noqa: E402
from vibss.reduction.scope import Scope  # noqa: E402
from vibss.linear.plant.build import build_plant  # noqa: E402
from vibss.time.api import simulate  # noqa: E402
from vibss.model.timefunctions import HalfSine  # noqa: E402

OUT = Path(__file__).resolve().parent / "results" / "reduction.json"


def lowest_w2(a, k: int, seed: int = 0) -> np.ndarray:
    """The k lowest squared natural frequencies [rad^2/s^2] of a sparse assembly, ascending
    (shift-invert ``eigsh`` from a seeded start vector)."""
    v0 = np.random.default_rng(seed).standard_normal(a.K.shape[0])
    w2 = spl.eigsh(a.K.tocsc(), k=k, M=a.M.tocsc(), sigma=-1.0, which="LM", v0=v0, return_eigenvectors=False)
    return np.sort(w2)


def damped_chain(n_bodies: int, zeta: float = 2e-3, seed: int = 0):
    """chain_model without its dense eigh: c = beta k on every mount, beta from a sparse eigsh."""
    model = chain_model(n_bodies, damping="none", seed=seed)
    a = assemble(model, sparse=True)
    w2 = lowest_w2(a, 1)
    beta = 2 * zeta / float(np.sqrt(w2[0]))
    mounts = [Mount(m.name, MountType(m.type.name, m.type.stiffness, beta * np.asarray(m.type.stiffness)),
                    m.body, at=m.at, to=m.to, orientation=m.orientation) for m in model.mounts]
    return model.replace(mounts=mounts), beta


def main(n_bodies: int = 1000, n_modes_band: int = 36, tol: float = 1e-6, nf: int = 200) -> dict:
    t0 = time.perf_counter()
    model, beta = damped_chain(n_bodies)
    mid = n_bodies // 2
    inputs = [f"b{mid}.fz"]
    outputs = [f"b{mid}.z", f"b{mid + 2}.x", f"mount.n{mid + 1}.fz"]
    a = assemble(model, sparse=True)
    w2 = lowest_w2(a, n_modes_band + 1)
    wn = np.sqrt(w2)
    # band top between modes n_modes_band and n_modes_band + 1: the band holds n_modes_band modes
    f2 = float(np.sqrt(wn[n_modes_band - 1] * wn[n_modes_band])) / (2 * np.pi)
    setup = time.perf_counter() - t0
    scope = Scope(inputs, outputs, 0.0, f2, tol)
    w = np.linspace(2 * np.pi * f2 * 1e-3, 2 * np.pi * f2, nf)
    out: dict = {"n_bodies": n_bodies, "n_dof": 6 * n_bodies, "band_hz": [0.0, f2], "modes_in_band": n_modes_band,
                 "tolerance": tol, "n_frequencies": nf, "inputs": inputs, "outputs": outputs, "beta": beta,
                 "setup_s": setup, "threads": 1, "machine": platform.processor() or platform.machine(),
                 "caveat": "2-core VM, single BLAS thread: expect +-10 % between runs"}
    with threadpool_limits(1):
        # full model, fastest exact path: sparse assembly + one complex sparse LU per frequency
        t = time.perf_counter()
        full = sparse_plant(model, inputs, outputs)
        t_asm = time.perf_counter() - t
        t = time.perf_counter()
        h_full = np.stack([exact_response(full, 1j * x)[0] for x in w], axis=-1)
        t_full = time.perf_counter() - t
        # krylov: reduce (its sparse assembly included) + the reduced FRF
        t = time.perf_counter()
        red = reduce(model, scope, "krylov")
        t_red = time.perf_counter() - t
        t = time.perf_counter()
        h_red = frf(red.plant, 1j * w)
        t_rfrf = time.perf_counter() - t
        # untimed: the error at and beside every resonance in the band as well
        wr = wn[:n_modes_band]
        ws = np.concatenate([wr * (1 + k) for k in (-1e-3, -2e-4, 0.0, 2e-4, 1e-3)])
        h_res = np.stack([exact_response(full, 1j * x)[0] for x in ws], axis=-1)
        err_res = relative_error(np.concatenate([h_full, h_res], axis=2),
                                 np.concatenate([h_red, frf(red.plant, 1j * ws)], axis=2))
        out["frf"] = {"full_assembly_s": t_asm, "full_sparse_lu_s": t_full, "full_total_s": t_asm + t_full,
                      "reduce_s": t_red, "reduced_s": t_rfrf,
                      "speedup": (t_asm + t_full) / (t_red + t_rfrf), "error": relative_error(h_full, h_red),
                      "error_with_resonances": err_res, "estimate": red.estimate,
                      "estimate_kind": red.estimate_kind, "dofs_after": red.plant.n,
                      "details": red.to_dict()["details"]}
        # time response: a half-sine on the input; band [0, f_max] with f_max = 32 f2 = 160 / tau
        # (a half-sine spectrum decays as 1/f^2: with the default 5 / tau, or 20 / tau, 1e-3 to 5e-2 of
        # the outputs come from content above the band, whatever the reduction)
        tau = 5.0 / f2
        shock = Excitation("shock", "force", f"b{mid}", HalfSine(1000.0, 0.0, tau), dof="z")
        t_end, dt = 20 * tau, tau / 40
        tscope = Scope.for_simulation([shock], outputs, t_end=t_end, dt=dt, tolerance=tol, f_max=32 * f2)
        t = time.perf_counter()
        tred = reduce(model, tscope, "krylov")
        t_tred = time.perf_counter() - t
        t = time.perf_counter()
        r_red = simulate(tred.plant, [shock], t_end=t_end, dt=dt)
        t_rsim = time.perf_counter() - t
        t = time.perf_counter()
        plant = build_plant(model, [shock], outputs)
        t_plant = time.perf_counter() - t
        t = time.perf_counter()
        r_full = simulate(plant, [shock], t_end=t_end, dt=dt)
        t_fsim = time.perf_counter() - t
        yf, yr = r_full.outputs, r_red.outputs
        err_t = float((np.abs(yr - yf).max(axis=1) / np.abs(yf).max(axis=1)).max())
        out["time"] = {"pulse": f"half-sine {tau:.4g} s", "t_end_s": t_end, "dt_s": dt,
                       "band_hz": [0.0, tscope.f2], "full_build_plant_s": t_plant, "full_modal_s": t_fsim,
                       "full_total_s": t_plant + t_fsim, "reduce_s": t_tred, "reduced_s": t_rsim,
                       "speedup": (t_plant + t_fsim) / (t_tred + t_rsim), "error": err_t,
                       "estimate": tred.estimate, "dofs_after": tred.plant.n,
                       "details": tred.to_dict()["details"]}
    out["report"] = red.report()
    out["report_time"] = tred.report()
    return out


def quick_basis_sizes(n_bodies: int = 100, n_modes_band: int = 12, tol: float = 1e-6) -> tuple[int, int]:
    """The reduced sizes (FRF scope, time scope) of the quick run's Krylov reductions, untimed: two
    calls must return the same pair (the benchmark is deterministic)."""
    model, _ = damped_chain(n_bodies)
    mid = n_bodies // 2
    inputs, outputs = [f"b{mid}.fz"], [f"b{mid}.z", f"b{mid + 2}.x", f"mount.n{mid + 1}.fz"]
    wn = np.sqrt(lowest_w2(assemble(model, sparse=True), n_modes_band + 1))
    f2 = float(np.sqrt(wn[n_modes_band - 1] * wn[n_modes_band])) / (2 * np.pi)
    red = reduce(model, Scope(inputs, outputs, 0.0, f2, tol), "krylov")
    tau = 5.0 / f2
    shock = Excitation("shock", "force", f"b{mid}", HalfSine(1000.0, 0.0, tau), dof="z")
    tscope = Scope.for_simulation([shock], outputs, t_end=20 * tau, dt=tau / 40, tolerance=tol, f_max=32 * f2)
    tred = reduce(model, tscope, "krylov")
    return int(red.plant.n), int(tred.plant.n)


if __name__ == "__main__":
    quick = "--quick" in sys.argv[1:]
    numbers = [a for a in sys.argv[1:] if not a.startswith("--")]
    n = int(numbers[0]) if numbers else (100 if quick else 1000)
    res = main(n, n_modes_band=12, nf=60) if quick else main(n)
    res["quick"] = quick
    OUT.parent.mkdir(exist_ok=True)
    OUT.write_text(json.dumps(res, indent=2))
    print(json.dumps({k: v for k, v in res.items() if not k.startswith("report")}, indent=2))
    print(res["report"])
    print(res["report_time"])
