"""The soft tower's FRF, 1 input x 3 outputs x 200 frequencies, every path in one run (issue 34).

``benchmarks.models.tower_model``: a 3 x 3-footprint lattice of rigid bodies on two soft ground mounts
per bottom body (lowest mode 0.03 mHz at 60,000 DOF), mounts' stiffness ratio past 1e3, so the
exact solve is done in the mounts' forces (:mod:`vibss.linear.solve.backends`). One BLAS thread:

- ``auto`` (the method it took, its checked error, its time, and the estimate the decider ranked it
  by: :func:`vibss.frequency.contracts.cost_subspace` / ``cost_sparse``);
- ``method="sparse"`` (the solve in the mounts' forces: the assembled SuperLU refined in the mounts'
  form, :mod:`vibss.linear.solve.refine`) at 20 of the frequencies: time per frequency against its
  estimate; its answer is the reference the others are compared with (tests/linear/test_refine.py
  holds it to a 240-bit reference on an 11-body tower);
- a plain ``scipy.sparse.linalg.splu`` of the assembled ``K + i w C - w^2 M`` per frequency, written
  here (the stock path): its time at all 200 frequencies (the first 100 timed before ``auto``, the
  others after it, so a drifting load weighs on both alike) and its error at the reference
  frequencies (relative to each channel's peak over them: what the assembled matrix loses on the
  soft modes).

Each call starts from the assembly (a fresh plant: nothing cached flatters a figure).
``python benchmarks/bench_tower.py [--quick] [--profile]`` (quick: 1,000 bodies, 6,000 DOF; full:
10,000 bodies, 60,000 DOF, ~6 GB peak). ``--profile`` prints the top of ``auto``'s cProfile.
"""

from __future__ import annotations

import cProfile
import pstats
import resource
import sys
import time
from pathlib import Path

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spl
from threadpoolctl import threadpool_limits

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from benchmarks.models import tower_model  # noqa: E402
import vibss  # noqa: E402
from vibss.frequency.contracts import cost_sparse, cost_subspace  # noqa: E402
from vibss.linear.plant.build import build_plant  # noqa: E402
from vibss.linear.solve.banded import structure  # noqa: E402

FREQUENCIES_HZ = np.logspace(-4, 1, 200)
"""The sweep [Hz]: 0.1 mHz (beside the lowest modes) to 10 Hz, log-spaced."""
PROFILE = False
"""Set by ``--profile``: print the top of ``auto``'s cProfile."""
EXACT_AT = 20
"""Frequencies (evenly by index, both ends) where ``method="sparse"`` is timed (its call, from the
assembly, over them) and is the reference."""


def peak_gb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6


def signals(n_bodies: int) -> tuple[list[str], list[str]]:
    """A lateral force on the top body; the top, middle and bottom-layer bodies' lateral motion."""
    top = n_bodies - 1
    return [f"b{top}.fx"], [f"b{top}.x", f"b{n_bodies // 2}.x", "b4.x"]


def splu_loop(asm: vibss.Assembly, f: np.ndarray, col: int, rows: list[int]) -> tuple[np.ndarray, float]:
    """One SuperLU (scipy's default COLAMD) of the assembled dynamic stiffness per frequency."""
    K, M = sp.csc_matrix(asm.K), sp.csc_matrix(asm.M)
    C = sp.csc_matrix(asm.C) if asm.C is not None else None
    rhs = np.zeros(K.shape[0], dtype=complex)
    rhs[col] = 1.0
    h = np.empty((len(rows), f.size), dtype=complex)
    t = time.perf_counter()
    for j, fj in enumerate(f):
        w = 2 * np.pi * fj
        a = K - (w * w) * M + (1j * w) * C if C is not None else K - (w * w) * M
        h[:, j] = spl.splu(sp.csc_matrix(a, dtype=complex)).solve(rhs)[rows]
    return h, time.perf_counter() - t


def bench(quick: bool) -> dict:
    profile = PROFILE
    n_bodies = 1000 if quick else 10000
    f = FREQUENCIES_HZ
    inputs, outputs = signals(n_bodies)
    with threadpool_limits(1):
        t = time.perf_counter()
        model = tower_model(n_bodies)
        t_model = time.perf_counter() - t
        t = time.perf_counter()
        asm = vibss.assemble(model)
        t_asm = time.perf_counter() - t
        plant = build_plant(asm, inputs, outputs, sparse=True)         # for the estimates only
        t = time.perf_counter()
        est_sub, est_exact = cost_subspace(plant, f.size).seconds, cost_sparse(plant, f.size).seconds
        est_lu = plant.cached("band structure", lambda: structure(plant)).seconds_per_frequency   # assembled LU
        t_est = time.perf_counter() - t
        mf = plant.mounts
        ratio = float(mf.stiffness_ratio) if mf is not None else float("nan")
        unknowns = plant.n + (int(mf.B.shape[0]) if mf is not None else 0)
        del plant
        col = asm.dof_index(inputs[0].replace(".f", "."))
        rows = [asm.dof_index(o) for o in outputs]
        half = f.size // 2              # the stock loop's halves before and after auto: the load drifts
        h1, t_splu1 = splu_loop(asm, f[:half], col, rows)
        prof = cProfile.Profile() if profile else None
        t = time.perf_counter()
        if prof is not None:
            prof.enable()
        r = vibss.frequency_response(asm, inputs, outputs, frequencies=f)
        if prof is not None:
            prof.disable()
        t_auto = time.perf_counter() - t
        pick = np.linspace(0, f.size - 1, EXACT_AT).round().astype(int)
        t = time.perf_counter()
        ref = vibss.frequency_response(asm, inputs, outputs, frequencies=f[pick], method="sparse")
        t_exact = (time.perf_counter() - t) / pick.size
        h2, t_splu2 = splu_loop(asm, f[half:], col, rows)
    h, t_splu = np.hstack([h1, h2]), t_splu1 + t_splu2
    href = ref.response[:, 0, :]
    peak = np.abs(href).max(axis=1, keepdims=True)
    err_auto = float((np.abs(r.response[:, 0, pick] - href) / peak).max())
    err_splu = float((np.abs(h[:, pick] - href) / peak).max())
    note = r.note
    checked = float(note.split("checked error ")[1].split(" ")[0]) if "checked error " in note else float("nan")
    per_exact_est = est_exact / f.size      # linear in the frequencies
    out = {"dofs": 6 * n_bodies, "stiffness_ratio": ratio, "mounts_unknowns": unknowns, "model_s": t_model,
           "assemble_s": t_asm, "estimate_s": t_est, "auto_method": r.method, "auto_s": t_auto,
           "auto_estimate_s": est_sub if r.method == "subspace" else est_exact, "auto_checked_error": checked,
           "auto_error": err_auto, "auto_note": note, "subspace_estimate_s": est_sub,
           "sparse_estimate_s": est_exact, "sparse_per_frequency_s": t_exact,
           "sparse_per_frequency_estimate_s": per_exact_est, "splu_loop_s": t_splu,
           "splu_per_frequency_s": t_splu / f.size, "assembled_lu_estimate_s": est_lu, "splu_error": err_splu, "auto_over_splu": t_auto / t_splu,
           "peak_memory_gb": peak_gb()}
    print(f"{6 * n_bodies} DOF soft tower (stiffness ratio {ratio:.3g}; mounts' form {unknowns} unknowns), "
          f"FRF 1 x 3 x {f.size} f ({f[0]:g}-{f[-1]:g} Hz), one BLAS thread; model {t_model:.1f} s, assemble "
          f"{t_asm:.2f} s, estimates {t_est:.2f} s")
    print(f"  auto: {r.method} {t_auto:.2f} s (estimated {out['auto_estimate_s']:.3g} s: measured/estimated "
          f"{t_auto / out['auto_estimate_s']:.2f}); checked error {checked:.2g}; error against the exact solve at "
          f"{pick.size} f {err_auto:.2g}")
    print(f"  sparse (mounts' form): {t_exact:.3f} s a frequency (estimated {per_exact_est:.3g} s: "
          f"{t_exact / per_exact_est:.2f}); 200 f estimated {est_exact:.3g} s")
    print(f"  plain splu loop: {t_splu:.2f} s ({t_splu / f.size:.3f} s a frequency; the assembled SuperLU's estimate "
          f"{est_lu:.3g} s: {t_splu / f.size / est_lu:.2f}); its error against the exact solve {err_splu:.2g}; "
          f"auto / splu loop {t_auto / t_splu:.2f}")
    print(f"  note: {note[:600]}")
    print(f"  peak memory {peak_gb():.2f} GB")
    if prof is not None:
        pstats.Stats(prof).sort_stats("cumulative").print_stats(25)
    return out


if __name__ == "__main__":
    if "--profile" in sys.argv:         # by hand, outside the harness
        PROFILE = True
        bench("--quick" in sys.argv)
    else:
        from run_all import main_one

        main_one("tower")
