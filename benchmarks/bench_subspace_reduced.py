"""The channel subspace's reduced plants: SuperLU against the batched dense LU (issue 17, same run).

A 200-body 10-wide grid (1,200 DOF), every mount damped with its own beta and a loss factor 0.05, 2
inputs x 3 outputs x 200 frequencies (tests/test_frequency_subspace.py's grid case), built sparse.
The subspace (:mod:`vibss.linear.project.subspace`) projects the plant on 160-656 Ritz vectors, whose ``C``
and ``H`` are full; each reduced plant's response at the 200 frequencies is an exact solve of it.
Timed, one BLAS thread, CPU seconds (the machine is shared): the subspace with its reduced plants
solved by SuperLU (``backend="sparse"`` forced: the path before ``DENSE_FILL``) and by ``auto``
(the batched dense LU for a full pattern), and the exact sparse solve of the full plant at every
frequency for reference. Error: largest over channels and frequencies relative to the channel's
peak, against that exact solve. Run: ``python benchmarks/bench_subspace_reduced.py``.
"""

from __future__ import annotations

import os
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
from threadpoolctl import threadpool_limits

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from benchmarks.models import grid_model  # noqa: E402
import vibss.linear.project.subspace as sub  # noqa: E402
from vibss import Model  # noqa: E402
from vibss.frequency.kernels import subspace  # noqa: E402
from vibss.linear.plant.build import build_plant  # noqa: E402
from vibss.linear.solve.exact import response  # noqa: E402


def main() -> None:
    f = np.linspace(1.0, 50.0, 200)
    base = grid_model(200, damping="general", seed=5)
    lossy = Model(base.bodies, [replace(m, type=replace(m.type, loss_factor=0.05)) for m in base.mounts])
    plant = build_plant(lossy, ["b0.fz", "b5.fx"], ["b0.z", "b1.z", "b2.x"], sparse=True)
    s = 2j * np.pi * f
    spent = {"reduced": 0.0}
    original = sub.reduced_response

    def timed_reduced(red, s, backend="auto"):
        t = time.process_time()
        out = response(red, s, backend=backend) if (np.any(red.C) or np.any(red.H)) else original(red, s)
        spent["reduced"] += time.process_time() - t
        return out

    print(f"load average at start: {os.getloadavg()[0]:.1f}", flush=True)
    with threadpool_limits(1):
        t = time.process_time()
        exact = response(plant, s, backend="sparse")
        t_exact = time.process_time() - t
        print(f"exact sparse solve of the {plant.n}-DOF plant at {f.size} frequencies: {t_exact:.2f} s", flush=True)
        for name, backend in (("SuperLU (before)", "sparse"), ("auto: dense LU", "auto")):
            spent["reduced"] = 0.0
            sub.reduced_response = lambda red, s, b=backend: timed_reduced(red, s, b)
            try:
                t = time.process_time()
                h, note = subspace(plant, s)
                total = time.process_time() - t
            finally:
                sub.reduced_response = original
            err = float((np.abs(h - exact) / np.abs(exact).max(axis=2, keepdims=True)).max())
            print(f"subspace, reduced plants by {name:17s} {total:6.2f} s (reduced solves {spent['reduced']:6.2f} s), "
                  f"error {err:.1e}; {note.split(' (')[0]}", flush=True)
    print(f"load average at end: {os.getloadavg()[0]:.1f}", flush=True)


if __name__ == "__main__":
    main()
