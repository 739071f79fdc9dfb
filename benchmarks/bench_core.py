"""Core benchmark: assembly and eigen-analysis at scale, against the obvious alternatives.

- Assembly of 1,000 bodies (6,000 DOF) on 4,332 mounts: vibss's vectorised COO assembly (sparse
  and dense) against a per-mount Python loop adding B^T k B blocks into a dense matrix.
- Modes of the same model: all modes by dense ``eigh`` against the lowest 50 by sparse
  shift-invert (``eigsh``), with the frequency difference between the two.

``--quick``: 300 bodies (1,800 DOF) for ``make bench-quick``.
Run: ``OPENBLAS_NUM_THREADS=1 python benchmarks/bench_core.py [--quick]`` (``make bench`` runs all).
"""

from __future__ import annotations

import platform

import numpy as np
from threadpoolctl import threadpool_limits

from models import chain_model
from run_all import best
from vibss import assemble, modes
from vibss.model.geometry import point_transfer
from vibss.model import GROUND

def loop_assembly(model):
    """The obvious alternative: one Python iteration per mount, blocks added into dense K."""
    names = {b.name: i for i, b in enumerate(model.bodies)}
    n = 6 * len(model.bodies)
    K = np.zeros((n, n))
    for m in model.mounts:
        i = names[m.body]
        p = model.mount_point(m)
        kp = m.orientation.matrix @ np.diag(m.type.stiffness) @ m.orientation.matrix.T
        lb = point_transfer(p - model.bodies[i].cog)
        K[6 * i:6 * i + 6, 6 * i:6 * i + 6] += lb.T @ kp @ lb
        if m.to != GROUND:
            j = names[m.to]
            la = point_transfer(p - model.bodies[j].cog)
            K[6 * j:6 * j + 6, 6 * j:6 * j + 6] += la.T @ kp @ la
            K[6 * i:6 * i + 6, 6 * j:6 * j + 6] -= lb.T @ kp @ la
            K[6 * j:6 * j + 6, 6 * i:6 * i + 6] -= la.T @ kp @ lb
    return K


def main(n_bodies: int = 1000) -> dict:
    res: dict = {"machine": f"{platform.processor() or platform.machine()}, {platform.system()}",
                 "threads": 1}
    model = chain_model(n_bodies, damping="none", ground_mounts=3, seed=1)
    res["bodies"], res["mounts"], res["dofs"] = len(model.bodies), len(model.mounts), model.n_dof
    with threadpool_limits(1):
        t_sparse, a_sp = best(lambda: assemble(model, sparse=True))
        t_dense, a_d = best(lambda: assemble(model, sparse=False))
        t_loop, k_loop = best(lambda: loop_assembly(model), repeat=1)
        err = np.abs(a_d.K - k_loop).max() / np.abs(k_loop).max()
        res["assembly"] = {"vectorised_sparse_s": t_sparse, "vectorised_dense_s": t_dense,
                           "loop_dense_s": t_loop, "speedup_sparse_vs_loop": t_loop / t_sparse,
                           "max_rel_difference": float(err)}
        print(f"assembly, {res['bodies']} bodies / {res['mounts']} mounts / {res['dofs']} DOF")
        print(f"  vectorised sparse {t_sparse:.3f} s, dense {t_dense:.3f} s, per-mount loop {t_loop:.3f} s"
              f"  -> {t_loop / t_sparse:.1f}x; max rel. difference {err:.1e}")
        t_all, all_modes = best(lambda: modes(a_d, method="dense"), repeat=1)
        t_50, low = best(lambda: modes(a_sp, n_modes=50, method="shift-invert"), repeat=1)
        t_50d, low_d = best(lambda: modes(a_d, n_modes=50, method="dense"), repeat=1)
        ferr = float(np.max(np.abs(low.omega - all_modes.omega[:50]) / all_modes.omega[:50]))
        res["modes"] = {"dense_all_s": t_all, "dense_lowest50_s": t_50d, "shift_invert_lowest50_s": t_50,
                        "speedup_shift_invert_vs_dense_all": t_all / t_50,
                        "max_rel_frequency_difference": ferr}
        print(f"modes: all {res['dofs']} by dense eigh {t_all:.1f} s; lowest 50 by dense eigh subset "
              f"{t_50d:.1f} s; by sparse shift-invert {t_50:.2f} s ({t_all / t_50:.0f}x faster than all); "
              f"max rel. frequency difference {ferr:.1e}")
    return res


def bench(quick: bool) -> dict:
    """Assembly and modes of a 1,000-body chain (300 with ``quick``)."""
    return main(300 if quick else 1000)


if __name__ == "__main__":
    from run_all import main_one

    main_one("core")
