"""General damping in the time domain without an eigen solve: one ``expm`` and a blocked recursion.

Issue 17 item 3 asks for 10x ``control.forced_response`` with general (non-proportional) damping at
600 DOF; vibss's exact path diagonalises the 1,200-state modal form once (``scipy.linalg.eig``),
which alone costs more than a tenth of ``forced_response``. The other exact family needs no eigen
solve: the first-order hold of ``forced_response`` itself, by ONE ``expm`` of the
``(2n + 2m)``-state augmented matrix, followed by its recursion ``x[k+1] = Phi x[k] + B0 u[k] + B1 u[k+1]``
— which ``forced_response`` runs as 10,000 matrix-vector products (BLAS-2, 11.5 MB of ``Phi`` read
per step). Here the recursion is blocked so that no step is a Python or BLAS-2 loop:

- ``m = 2^k`` steps per block; ``Phi^j G`` and ``C Phi^j`` (``j < m``, ``G = [B0, B1]``) by
  doubling, ``Phi^m`` by ``k`` squarings;
- the block-boundary states ``x[(b+1) m] = Phi^m x[b m] + sum_j Phi^(m-1-j) G [u; u+]`` (``steps / m``
  matrix-vector products, the forcing of every block by one GEMM);
- the outputs inside every block at once: ``[C Phi^0; ...; C Phi^(m-1)] @ [x_0, x_m, ...]`` plus the
  intra-block convolution with the Markov parameters ``C Phi^i G`` (one GEMM with the block
  Toeplitz matrix).

It is as exact as ``forced_response`` (the same discretisation, regrouped). Timed in the same run
in CPU time of the process (less sensitive than wall time to the other jobs on a shared machine),
cold, one BLAS thread, ``forced_response`` once and the others best of ``--repeat`` interleaved, on chain / grid / tree of :mod:`models` (100 bodies, general damping,
2 force inputs, 6 outputs, 10,000 steps of 2e-4 s, the inputs of bench_time.py) and on the badly
scaled chain (``scale="bad"``: 1e-3-1e4 kg, 1e2-1e8 N/m): ``forced_response``, ``expm`` alone,
the blocked route (``expm`` included), ``scipy.linalg.eig`` of the 1,200-state matrix (the eig
route's floor) and vibss ``modal`` (the eig route). Errors relative to each output's peak.
Results go to benchmarks/results/time_expm.json.

Run: ``OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/bench_time_expm.py [--quick] [--block 64]``
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path

import numpy as np
import scipy.linalg as sl
from threadpoolctl import threadpool_limits

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from models import chain_model, topology_model  # noqa: E402

from vibss.linear.plant.build import build_plant  # noqa: E402
from vibss.time import kernels as tk  # noqa: E402
from vibss.time.api import simulate  # noqa: E402

DT, STEPS = 2e-4, 10_000


def blocked_foh(A: np.ndarray, B: np.ndarray, C: np.ndarray, D: np.ndarray, U: np.ndarray, dt: float,
                m: int) -> tuple[np.ndarray, dict[str, float]]:
    """Outputs (steps + 1, p) of ``x' = A x + B u, y = C x + D u`` from rest, ``U`` (steps + 1, ni)
    linear between samples ``dt`` [s] apart (exact FOH), recursion blocked by ``m = 2^k`` steps;
    and the time of each phase [s]."""
    n, ni = B.shape
    p = C.shape[0]
    times = {}
    t0 = time.process_time()
    aug = np.zeros((n + 2 * ni, n + 2 * ni))
    aug[:n, :n] = A * dt
    aug[:n, n:n + ni] = B * dt
    aug[n:n + ni, n + ni:] = np.eye(ni)
    E = sl.expm(aug)
    phi, b1 = E[:n, :n], E[:n, n + ni:]
    b0 = E[:n, n:n + ni] - b1                      # x+ = Phi x + B0 u + B1 u+ (forced_response's form)
    times["expm_s"] = time.process_time() - t0
    t0 = time.process_time()
    G = np.hstack([b0, b1])                        # (n, 2 ni)
    cp, pg, pk, k = C, G, phi, 1                   # rows C Phi^j, columns Phi^j G (j < k), Phi^k
    while k < m:
        cp = np.vstack([cp, cp @ pk])
        pg = np.hstack([pg, pk @ pg])
        pk = pk @ pk
        k *= 2
    times["powers_s"] = time.process_time() - t0
    t0 = time.process_time()
    steps = U.shape[0] - 1
    nb = -(-steps // m)
    Up = np.zeros((nb * m + 1, ni))
    Up[:steps + 1] = U
    # block b's forcing of its end state: sum_j Phi^j G [u_i; u_i+1], i = b m + m - 1 - j
    idx = np.arange(nb)[:, None] * m + (m - 1 - np.arange(m))[None, :]
    W = np.concatenate([Up[idx], Up[idx + 1]], axis=2).reshape(nb, m * 2 * ni)
    F = W @ pg.reshape(n, m, 2 * ni).reshape(n, -1).T          # (nb, n)
    X = np.zeros((nb + 1, n))
    for b in range(nb):
        X[b + 1] = pk @ X[b] + F[b]
    times["boundary_s"] = time.process_time() - t0
    t0 = time.process_time()
    Y = (cp @ X[:nb].T).reshape(m, p, nb)                        # the start states carried in
    H = (cp @ G).reshape(m, p, 2 * ni)                           # Markov parameters C Phi^l G
    T = np.zeros((m, p, m, 2 * ni))
    for j in range(1, m):
        T[j, :, :j] = np.transpose(H[j - 1::-1][:j], (1, 0, 2))
    Wi = np.concatenate([Up[:nb * m].reshape(nb, m, ni), Up[1:nb * m + 1].reshape(nb, m, ni)], axis=2)
    Y += (T.reshape(m * p, -1) @ Wi.reshape(nb, -1).T).reshape(m, p, nb)
    y = np.vstack([np.transpose(Y, (2, 0, 1)).reshape(nb * m, p), (C @ X[nb])[None]])[:steps + 1]
    times["outputs_s"] = time.process_time() - t0
    return y + U @ D.T, times


def _first_order(plant) -> np.ndarray:
    """The 1,200-state matrix ``[[0, I], [-M^-1 K, -M^-1 C]]`` (the eig floor of bench_time.py)."""
    K, M, C = (np.asarray(x, float) for x in (plant.K, plant.M, plant.C))
    n = K.shape[0]
    a = np.zeros((2 * n, 2 * n))
    a[:n, n:] = np.eye(n)
    a[n:, :n] = -np.linalg.solve(M, K)
    a[n:, n:] = -np.linalg.solve(M, C)
    return a


def case(name: str, model, m: int, repeat: int) -> dict:
    n_bodies = 100
    inputs = [f"b{n_bodies // 3}.fz", f"b{2 * n_bodies // 3}.fx"]
    outputs = [f"b{n_bodies // 3}.{d}" for d in ("x", "y", "z", "rx", "ry", "rz")]
    rng = np.random.default_rng(1)
    u = {k: np.cumsum(rng.normal(0.0, 20.0, STEPS + 1)) for k in inputs}
    kw = dict(inputs=u, t_end=STEPS * DT, dt=DT)
    out: dict = {"case": name, "model": model.name, "block": m, "steps": STEPS, "dt": DT}
    with threadpool_limits(1):
        plant = build_plant(model, inputs, outputs)
        t0 = time.process_time()
        ref = simulate(plant, method="forced_response", **kw)
        out["forced_response_s"] = time.process_time() - t0
        a = _first_order(plant)
        best: dict = {}
        for _ in range(repeat):                 # the three routes interleaved, each cold, best of repeat
            plant = build_plant(model, inputs, outputs)
            t0 = time.process_time()
            modal = simulate(plant, method="modal", **kw)
            t_modal = time.process_time() - t0
            plant = build_plant(model, inputs, outputs)
            t0 = time.process_time()
            r = tk.realization(tk.prepare(plant))
            y, phases = blocked_foh(r.A, r.B, r.C, r.D, np.column_stack([u[k] for k in inputs]), DT, m)
            t_blocked = time.process_time() - t0
            t0 = time.process_time()
            sl.eig(a, right=True, check_finite=False)
            t_eig = time.process_time() - t0
            for key, value in {"modal_s": t_modal, "blocked_s": t_blocked, "eig_s": t_eig, **phases}.items():
                best[key] = min(best.get(key, np.inf), value)
        out.update(best)
        out["norm1_A_dt"] = float(np.linalg.norm(r.A * DT, 1))
    R, Ym = np.asarray(ref.outputs), np.asarray(modal.outputs)
    scale = np.abs(R).max(axis=1, keepdims=True)
    out["err_blocked_vs_fr"] = float((np.abs(y.T - R) / scale).max())
    out["err_blocked_vs_modal"] = float((np.abs(y.T - Ym) / scale).max())
    out["err_modal_vs_fr"] = float((np.abs(Ym - R) / scale).max())
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--quick", action="store_true", help="the grid only")
    parser.add_argument("--block", type=int, default=64, help="steps per block (a power of 2)")
    parser.add_argument("--repeat", type=int, default=3, help="best of this many cold runs of each route")
    args = parser.parse_args()
    cases = [(k, topology_model(k, 100, damping="general")) for k in ("chain", "grid", "tree")]
    cases.append(("chain, badly scaled", chain_model(100, "general", scale="bad")))
    if args.quick:
        cases = cases[1:2]
    load = os.getloadavg()[0]
    results = {"load_1min_at_start": load, "cases": []}
    print(f"load average at start: {load:.1f}")
    print(f"{'case':20s} {'forced_resp.':>12s} {'expm':>7s} {'blocked':>8s} {'eig':>7s} {'modal':>7s} "
          f"{'fr/blk':>7s} {'fr/modal':>8s} {'err blk-fr':>10s} {'blk-modal':>10s} {'modal-fr':>9s}")
    for name, model in cases:
        r = case(name, model, args.block, args.repeat)
        results["cases"].append(r)
        fr = r["forced_response_s"]
        print(f"{name:20s} {fr:10.2f} s {r['expm_s']:5.2f} s {r['blocked_s']:6.2f} s {r['eig_s']:5.2f} s "
              f"{r['modal_s']:5.2f} s {fr / r['blocked_s']:6.1f}x {fr / r['modal_s']:7.1f}x "
              f"{r['err_blocked_vs_fr']:10.1e} {r['err_blocked_vs_modal']:10.1e} {r['err_modal_vs_fr']:9.1e}"
              f"   (|A dt|_1 {r['norm1_A_dt']:.1e}; powers {r['powers_s']:.2f} s, boundary "
              f"{r['boundary_s']:.2f} s, outputs {r['outputs_s']:.2f} s)", flush=True)
    results["load_1min_at_end"] = os.getloadavg()[0]
    if not args.quick:
        path = Path(__file__).resolve().parent / "results" / "time_expm.json"
        path.write_text(json.dumps(results, indent=2) + "\n")
        print(f"written {path}")


if __name__ == "__main__":
    main()
