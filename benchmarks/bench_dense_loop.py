"""The dense exact solve: one LAPACK ``zgesv`` per frequency on a matrix built in place, against
numpy's batched LU of the stacked dynamic stiffness (the path before ``LOOP_DOFS``), same run.

Seeded chains and grids (``benchmarks/models.py``), every mount damped with its own beta and a loss
factor 0.05, 1-2 inputs, 2-3 outputs, on the frequency axis; and the channel subspace's reduced
plant (a random symmetric ``K``, ``C``, ``H``, ``M = I``: the shape the test
``tests/frequency/test_frequency_subspace.py::test_grid_with_loss_factors_and_dampers_matches_the_exact_solve``
solves 5 times at 160-656 DOFs). Both sides through :func:`vibss.linear.solve.exact.response`
(``backend="dense"``), each path forced by :data:`~vibss.linear.solve.backends.LOOP_DOFS` (the
stock one: numpy's ``linalg.solve`` of :func:`~vibss.linear.solve.backends.dynamic_stiffness`'s
chunks), "taken" the one the solve uses at that size; best of 3 interleaved calls, one BLAS thread. Difference: largest ``|y_new - y_stock|``
over the channels' peaks (0 where the bits agree: the same LAPACK routine on the same matrix).
Run: ``python benchmarks/bench_dense_loop.py [--quick]``.
"""

from __future__ import annotations

import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from benchmarks.models import chain_model, grid_model  # noqa: E402
import vibss.linear.solve.backends as backends  # noqa: E402
from vibss import Model  # noqa: E402
from vibss.linear.plant.build import build_plant  # noqa: E402
from vibss.linear.plant.plant import Plant  # noqa: E402
from vibss.linear.solve.exact import response  # noqa: E402


def _lossy(model: Model) -> Model:
    return Model(model.bodies, [replace(m, type=replace(m.type, loss_factor=0.05)) for m in model.mounts])


def _reduced(r: int, seed: int = 3) -> Plant:
    """A plant in Ritz coordinates like the channel subspace's (``M = I``, ``K`` diagonal, full ``C``
    and ``H``): a seeded grid's plant projected on ``r`` random orthonormal vectors, as
    :mod:`vibss.linear.project.subspace` projects (``Plant.project`` with the small matrices given)."""
    rng = np.random.default_rng(seed)
    full = build_plant(grid_model(r // 6 + 20, damping="general", seed=seed), ["b0.fz", "b5.fx"],
                       ["b0.z", "b1.z", "b2.x"])
    v = np.linalg.qr(rng.standard_normal((full.n, r)))[0]
    w2 = np.sort(rng.uniform(10.0, 4e5, r))
    g = rng.standard_normal((r, r)) / np.sqrt(r)
    return full.project(v, tuple(f"krylov{k + 1}" for k in range(r)), M=np.eye(r), K=np.diag(w2),
                        C=2.0 * (g @ g.T), H=0.05 * np.diag(w2) + 0.01 * (g + g.T))


def cases(quick: bool) -> list[tuple[str, Plant, int]]:
    out = [("chain 30 bodies (180 DOF)", build_plant(_lossy(chain_model(30, damping="general", seed=1)),
                                                    ["b0.fz"], ["b3.z", "mount.n2.fz"]), 200),
           ("grid 40 bodies (240 DOF)", build_plant(_lossy(grid_model(40, damping="general", seed=5)),
                                                   ["b0.fz", "b5.fx"], ["b0.z", "b1.z", "b2.x"]), 200),
           ("chain 12 bodies (72 DOF, below LOOP_DOFS)", build_plant(_lossy(chain_model(12, damping="general", seed=2)),
                                                                    ["b0.fz"], ["b3.z"]), 200)]
    if not quick:
        out += [("chain 100 bodies (600 DOF)", build_plant(_lossy(chain_model(100, zeta=2e-3)),
                                                          ["b50.fz"], ["b50.z", "b52.x"]), 150),
                ("reduced plant, 656 Ritz vectors", _reduced(656), 200)]
    else:
        out += [("reduced plant, 300 Ritz vectors", _reduced(300), 100)]
    return out


def bench(quick: bool) -> dict:
    res: dict = {}
    loop = backends.LOOP_DOFS
    for name, plant, nf in cases(quick):
        s = 2j * np.pi * np.linspace(0.5, 60.0, nf)
        times = {"stock": [], "loop": []}
        ys = {}
        for _ in range(3):
            for side, limit in (("stock", 10**9), ("loop", 0)):        # each path forced
                backends.LOOP_DOFS = limit
                try:
                    t0 = time.perf_counter()
                    ys[side] = response(plant, s, backend="dense")
                    times[side].append(time.perf_counter() - t0)
                finally:
                    backends.LOOP_DOFS = loop
        peak = np.abs(ys["stock"]).max(axis=2, keepdims=True)
        diff = float((np.abs(ys["loop"] - ys["stock"]) / np.where(peak > 0, peak, 1.0)).max())
        t_stock, t_loop = min(times["stock"]), min(times["loop"])
        res[name] = {"dofs": int(plant.n), "frequencies": nf, "stock_s": t_stock, "loop_s": t_loop,
                     "speedup": t_stock / t_loop, "max_rel_difference": diff,
                     "same_bits": bool(np.array_equal(ys["loop"], ys["stock"])),
                     "taken": "loop" if plant.n >= loop else "stock"}
        print(f"{name:42s} {nf:4d} freq: numpy batched {t_stock:7.3f} s, per-frequency zgesv {t_loop:7.3f} s "
              f"({t_stock / t_loop:4.2f}x), difference {diff:.1e}; taken: {res[name]['taken']}", flush=True)
    return res


if __name__ == "__main__":
    from run_all import main_one

    main_one("dense_loop")
