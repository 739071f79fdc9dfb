"""FRF benchmark over topologies and damping: python-control's stock path vs vibss, same run.

``topology_model(kind, 100)`` for kind in chain, grid (10 wide), tree (600 DOF each), 6 force
inputs x 36 displacement outputs x 1000 log-spaced frequencies, one BLAS thread, three dampings:

- ``classical``: c = beta k in every mount (``modal``);
- ``general``: a random beta per mount, every mount damped (damper rank 3 x mounts > n);
- ``dampers``: the same with only 10 mounts damped (rank 30), the rest undamped: the case the
  ``woodbury`` kernel (undamped modes + the dampers as a low-rank update) is built for.

Timed in the same run: ``control.frequency_response`` on the physical state space (the stock
path, best of two calls), ``frequency_response(method="auto")`` through the public API (best of two,
fresh plant each call, so its choice, the modal basis and every cache count) and each candidate
kernel once on a fresh plant (``modal``, ``complex_modal``, ``woodbury``, ``sparse``). Error: max
over frequencies of ||H - H_ref||_F / ||H_ref||_F against ``direct``. The worst topology is named.

With general damping two *floors* are timed as well, in the same run: what any exact method of each
family must pay at the least, whatever its implementation: ``scipy.linalg.eig`` (right vectors only)
of the dense 2n-state matrix, for complex-mode superposition, and that ``eig`` plus the least
superposition on it (residues from the right vectors, the left ones being the right ones for the
symmetric quadratic problem, normalised by ``x^T Q'(lam) x``, then one ``(nf x 2n) x (2n x p m)``
GEMM; its answer is checked against ``direct``): ``auto_over_eig_sum`` is ``auto`` over that, issue
34's "one eig plus its GEMMs"; and a bare ``scipy.sparse.linalg.splu``
loop of K - w^2 M + i w C with the 6 input columns, for a sparse solve per frequency (no output
product counted). ``best_possible`` = control's time over the smaller floor: the largest speed-up
either family can reach on that model.
Written to ``benchmarks/results/frf_topology.json``. Run:
``python benchmarks/bench_frf_topology.py [--quick] [classical] [general] [dampers]`` (quick: 50
bodies, 200 frequencies, no repeats; the dampings named, default all).
"""

from __future__ import annotations

import json
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
import scipy.linalg as sl
import scipy.sparse as sp
import scipy.sparse.linalg as spl
from threadpoolctl import threadpool_limits

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from benchmarks.bench_frf import _err, _stock  # noqa: E402
from benchmarks.machine import timed  # noqa: E402
from benchmarks.models import TOPOLOGIES, topology_model  # noqa: E402
from vibss import Mount, MountType  # noqa: E402
from vibss.frequency.api import frequency_response  # noqa: E402
from vibss.frequency.kernels import METHODS  # noqa: E402
from vibss.linear.eigen.basis import modal_basis  # noqa: E402
from vibss.linear.eigen.basis import damping_factors  # noqa: E402
from vibss.linear.plant.build import build_plant  # noqa: E402

CANDIDATES = {"classical": ("modal", "sparse"), "general": ("complex_modal", "sparse"),
              "dampers": ("woodbury", "sparse")}
"""Kernels timed beside ``auto``. Not ``woodbury`` on ``general``: every mount damped makes its rank
3 x mounts = 1.6-1.9 n, and its bordered LU per frequency that order (236 s on the chain, 278 s on the
grid for 200 frequencies in a quick run); ``auto`` never picks it there."""


def few_dampers(model, count: int = 10, seed: int = 1):
    """The model with the damping of all but ``count`` (seeded, random) mounts removed."""
    keep = set(np.random.default_rng(seed).choice(len(model.mounts), count, replace=False).tolist())
    return model.replace(mounts=[
        m if i in keep else Mount(m.name, MountType(m.type.name, m.type.stiffness), m.body, at=m.at, to=m.to,
                                  orientation=m.orientation)
        for i, m in enumerate(model.mounts)])


def case(kind: str, damping: str, n_bodies: int, n_freq: int, repeat: int) -> dict:
    model = topology_model(kind, n_bodies, damping="classical" if damping == "classical" else "general")
    if damping == "dampers":
        model = few_dampers(model)
    step = max(1, n_bodies // 6)
    inputs = [f"b{i * step}.f{'xyz'[i % 3]}" for i in range(6)]
    outputs = [f"b{i * step}.{d}" for i in range(6) for d in ("x", "y", "z", "rx", "ry", "rz")]
    plant = build_plant(model, inputs, outputs)
    basis = modal_basis(plant)
    w = basis.omega
    omega = np.geomspace(0.5 * w.min(), 1.5 * w.max(), n_freq)
    s = 1j * omega
    res: dict = {"kind": kind, "damping": damping, "n_dof": plant.n,
                 "damper_rank": int(damping_factors(plant, basis)[0].shape[1])}
    with threadpool_limits(1):
        href = METHODS["direct"](plant, s)
        res["control_s"], hs = timed(lambda: _stock(plant, omega), min_time=float("inf"), repeat=repeat)
        res["control_error"] = _err(hs, href)
        res["auto_s"], r = timed(lambda: frequency_response(replace(plant), frequencies=omega / (2 * np.pi)),
                                 min_time=float("inf"), repeat=repeat)
        res.update(auto_method=r.method, auto_reason=r.note, auto_error=_err(r.response, href),
                   auto_speedup=res["control_s"] / res["auto_s"])
        for name in CANDIDATES[damping]:
            t = time.perf_counter()
            h = METHODS[name](replace(plant), s)
            res[f"{name}_s"] = time.perf_counter() - t
            res[f"{name}_error"] = _err(h, href)
            res[f"{name}_speedup"] = res["control_s"] / res[f"{name}_s"]
        if damping == "general":
            fl = floors(plant, omega)
            res["eig_sum_floor_error"] = _err(fl.pop("eig_sum_floor_h"), href)
            res.update(fl)
            res["auto_over_eig_sum"] = res["auto_s"] / res["eig_sum_floor_s"]
            res["best_possible"] = res["control_s"] / min(res["eig_floor_s"], res["splu_floor_s"])
    return res


def floors(plant, omega: np.ndarray) -> dict:
    """Seconds of the two floors (module docstring): dense eig of the state matrix, splu loop."""
    n = plant.n
    M, C, K = (np.asarray(x.toarray() if sp.issparse(x) else x, dtype=float) for x in (plant.M, plant.C, plant.K))
    a = np.zeros((2 * n, 2 * n))
    a[:n, n:] = np.eye(n)
    a[n:, :n] = -np.linalg.solve(M, K)
    a[n:, n:] = -np.linalg.solve(M, C)
    t = time.perf_counter()
    lam, v = sl.eig(a, right=True, left=False, check_finite=False, overwrite_a=True)
    t_eig = time.perf_counter() - t
    # the superposition every complex-mode method adds to its eig: residues from the right vectors
    # (left = right for the symmetric quadratic problem), normalised by x^T Q'(lam) x (two n x n x 2n
    # products), then one (nf x 2n) x (2n x p m) GEMM; its answer is checked against direct
    t = time.perf_counter()
    x = np.ascontiguousarray(v[:n])
    mx = (M @ x.view(float)).view(complex)
    cx = (C @ x.view(float)).view(complex)
    norm = 2 * lam * np.einsum("ij,ij->j", x, mx) + np.einsum("ij,ij->j", x, cx)
    out = plant.Oq @ x                                   # (p, 2n)
    inp = (x.T @ np.asarray(plant.F, float)) / norm[:, None]   # (2n, m)
    res = (out.T[:, :, None] * inp[:, None, :]).reshape(2 * n, -1)
    h = (1.0 / (1j * omega[:, None] - lam[None, :])) @ res
    t_sum = time.perf_counter() - t
    h = np.moveaxis(h.reshape(omega.size, *out.shape[:1], inp.shape[1]), 0, -1)
    Ms, Cs, Ks = (sp.csc_matrix(x) for x in (M, C, K))
    rhs = np.asarray(plant.F, dtype=complex)
    t = time.perf_counter()
    for w in omega:
        spl.splu((Ks - w * w * Ms + 1j * w * Cs).tocsc()).solve(rhs)
    return {"eig_floor_s": t_eig, "eig_sum_floor_s": t_eig + t_sum, "eig_sum_floor_h": h,
            "splu_floor_s": time.perf_counter() - t}


def bench(quick: bool) -> dict:
    """Every damping of :data:`CANDIDATES` on 100 bodies, 1,000 frequencies (50 and 200 with ``quick``)."""
    return run(n_bodies=50 if quick else 100, n_freq=200 if quick else 1000, repeat=1 if quick else 2,
               dampings=tuple(CANDIDATES))


def run(n_bodies: int = 100, n_freq: int = 1000, repeat: int = 2,
        dampings: tuple[str, ...] = ("classical", "general", "dampers")) -> dict:
    out: dict = {"n_bodies": n_bodies, "inputs": 6, "outputs": 36, "frequencies": n_freq, "threads": 1,
                 "cases": []}
    for damping in dampings:
        rows = []
        for kind in TOPOLOGIES:
            res = case(kind, damping, n_bodies, n_freq, repeat)
            rows.append(res)
            out["cases"].append(res)
            fast = "  ".join(f"{n} {res[f'{n}_s']:.3f} s ({res[f'{n}_speedup']:.1f}x, err {res[f'{n}_error']:.1e})"
                             for n in CANDIDATES[damping])
            print(f"{damping:9s} {kind:5s} n={res['n_dof']} r={res['damper_rank']}: control {res['control_s']:.2f} s "
                  f"(err {res['control_error']:.1e}); auto -> {res['auto_method']} {res['auto_s']:.3f} s "
                  f"= {res['auto_speedup']:.1f}x (err {res['auto_error']:.1e}); {fast}", flush=True)
            if "best_possible" in res:
                print(f"          floors: eig of the {2 * res['n_dof']}-state matrix {res['eig_floor_s']:.2f} s, "
                      f"eig + its superposition {res['eig_sum_floor_s']:.2f} s (err "
                      f"{res['eig_sum_floor_error']:.1e}; auto {res['auto_over_eig_sum']:.2f}x it), "
                      f"splu loop {res['splu_floor_s']:.2f} s: at most {res['best_possible']:.1f}x control "
                      f"for either family", flush=True)
        worst = min(rows, key=lambda x: x["auto_speedup"])
        print(f"  {damping}: auto at least {worst['auto_speedup']:.1f}x control on every topology "
              f"(worst: {worst['kind']}), worst error {max(x['auto_error'] for x in rows):.1e}", flush=True)
        out[f"worst_{damping}"] = {"kind": worst["kind"], "auto_speedup": worst["auto_speedup"]}
        if damping == "general":
            far = max(rows, key=lambda x: x["auto_over_eig_sum"])
            out["worst_general_over_floor"] = {"kind": far["kind"], "auto_over_eig_sum": far["auto_over_eig_sum"]}
    return out


if __name__ == "__main__":
    from run_all import main_one

    main_one("frf_topology")
