"""Large models without a dense n x n matrix: lowest modes and a few-channel FRF, same run.

Issue 17 item 4. A seeded chain of rigid bodies (``benchmarks.models.chain_model``, undamped so the
model builder itself needs no eigen-analysis), one BLAS thread:

- ``vibss.modes(model, n_modes=20)`` against raw ``scipy.sparse.linalg.eigsh`` shift-invert on the
  same assembled K and M (time ratio, largest relative difference of the frequencies, peak memory);
- ``vibss.frequency_response(model, 1 input, 3 outputs, 200 explicit frequencies)``: ``auto`` (the
  channel subspace, :mod:`vibss.linear.project.subspace`) against the exact banded LU per frequency
  (``method="sparse"``) and a plain ``scipy.sparse.linalg.splu`` per frequency written here (the
  stock path), with the error of both against the splu answer at every frequency (relative to each
  channel's peak);
- ``vibss.simulate(model, half-sine force, 3 outputs)`` for two pulse lengths: kept sparse and
  projected on a subspace built for the channels and the input's spectrum (:mod:`vibss.time.large`),
  its time, the basis and the error estimate it states (no stock path runs at this size:
  python-control would need a dense 2n-state system; tests/time/test_time_large.py checks the path
  against the exact dense modal one on 1,800 DOF).

``--huge``: 100,000 bodies (600,000 DOF): building the Model, assembly and ``modes(n_modes=20)``,
with the peak memory (``resource.getrusage``) after each; raw ``eigsh`` on the same matrices in the
same run. Memory-heavy (several GB): not run by ``make bench``.

Run: ``python benchmarks/bench_large.py [--quick | --huge]`` (quick: 2,000 bodies instead of 10,000).
"""

from __future__ import annotations

import resource
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spl
from threadpoolctl import threadpool_limits

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from benchmarks.models import chain_model  # noqa: E402
import vibss  # noqa: E402
from vibss.model.excitation import Excitation  # noqa: E402
from vibss.model.timefunctions import HalfSine  # noqa: E402

SHOCKS_S = (0.5, 2.5)
"""Half-sine force pulse lengths [s] of the time-response cases: a shock (content 2 Hz, cut-off
16 Hz) and a slow pulse (0.4 Hz, cut-off 3.2 Hz)."""


def peak_gb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6


def bench(quick: bool) -> dict:
    n_bodies = 2000 if quick else 10000
    out: dict = {}
    with threadpool_limits(1):
        model = chain_model(n_bodies, damping="none", seed=3)
        t = time.perf_counter()
        asm = vibss.assemble(model)
        t_asm = time.perf_counter() - t
        t = time.perf_counter()
        md = vibss.modes(asm, n_modes=20)
        t_modes = time.perf_counter() - t
        K, M = asm.K.tocsc(), asm.M.tocsc()
        t = time.perf_counter()
        w2 = np.sort(spl.eigsh(K, k=20, M=M, sigma=0.0, which="LM")[0])
        t_eigsh = time.perf_counter() - t
        err_modes = float(np.abs(md.omega ** 2 / w2 - 1).max())
        f = np.linspace(1.0, 50.0, 200)
        outputs = ["b0.z", "b1.z", "b2.z"]
        t = time.perf_counter()
        # from the assembly (timed above), as the stock path below starts from K and M
        r = vibss.frequency_response(asm, ["b0.fz"], outputs, frequencies=f)        # auto: the subspace
        t_frf = time.perf_counter() - t
        t = time.perf_counter()
        r_exact = vibss.frequency_response(asm, ["b0.fz"], outputs, frequencies=f, method="sparse")
        t_exact = time.perf_counter() - t
        # the stock path: one sparse LU of (K - w^2 M) per frequency, unit force on b0.fz (DOF 2)
        rhs = np.zeros(K.shape[0])
        rhs[2] = 1.0
        rows = [6 * i + 2 for i in range(3)]
        t = time.perf_counter()
        h = np.empty((3, f.size))
        for j, fj in enumerate(f):
            w = 2 * np.pi * fj
            h[:, j] = spl.splu(sp.csc_matrix(K - w * w * M)).solve(rhs)[rows]
        t_splu = time.perf_counter() - t
        peak = np.abs(h).max(axis=1, keepdims=True)                   # per channel, as the checks
        err_frf = float((np.abs(r.response[:, 0, :] - h) / peak).max())
        err_exact = float((np.abs(r_exact.response[:, 0, :] - h) / peak).max())
        stated = float(r.note.split("checked error ")[1].split(" ")[0]) if "checked error" in r.note else 0.0
        basis = r.note.split("channel subspace of ")[1].split(" vectors")[0] if "subspace of" in r.note else "-"
        shocks = []
        for duration in SHOCKS_S:
            shock = Excitation("shock", "force", "b0", HalfSine(100.0, duration=duration), dof="z")
            t = time.perf_counter()
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    sim = vibss.simulate(model, [shock], outputs=outputs, t_end=2 * duration, dt=duration / 500)
                what = "channel subspace of " + sim.note.split("channel subspace of ")[1].split(" (")[0]
                stated_t = float(sim.note.split("estimated error ")[1].split(" ")[0])
            except vibss.errors.AnalysisError as exc:
                what, stated_t = "refused: " + str(exc).split(": ", 1)[1][:200], float("nan")
            shocks.append({"duration_s": duration, "s": time.perf_counter() - t, "kept": what,
                           "error_estimate": stated_t})
    out = {"dofs": 6 * n_bodies, "assemble_s": t_asm, "shocks": shocks, "modes_s": t_modes, "eigsh_s": t_eigsh,
           "modes_ratio": t_modes / t_eigsh, "modes_error": err_modes, "frf_s": t_frf, "frf_method": r.method,
           "frf_basis": basis, "frf_checked_error": stated, "frf_error": err_frf, "frf_exact_s": t_exact,
           "frf_exact_error": err_exact, "splu_loop_s": t_splu, "frf_ratio_splu": t_splu / t_frf,
           "frf_ratio_exact": t_exact / t_frf, "peak_memory_gb": peak_gb()}
    print(f"{6 * n_bodies} DOF chain (seed 3), one BLAS thread:")
    print(f"  assemble {t_asm:.2f} s")
    print(f"  modes(n_modes=20) {t_modes:.2f} s   raw eigsh shift-invert {t_eigsh:.2f} s   ratio {t_modes / t_eigsh:.2f}x"
          f"   frequencies differ by {err_modes:.1e}")
    print(f"  FRF 1 x 3 x 200 f: {r.method} {t_frf:.2f} s ({basis} vectors, checked error {stated:.1e}, error "
          f"against splu at all 200 f {err_frf:.1e} of each channel's peak)")
    print(f"    exact banded LU per frequency (method='sparse') {t_exact:.2f} s ({t_exact / t_frf:.2f}x the "
          f"subspace's time; error {err_exact:.1e})   splu per frequency {t_splu:.2f} s ({t_splu / t_frf:.2f}x)")
    for c in shocks:
        print(f"  half-sine force {c['duration_s']:g} s, 3 outputs, 1,000 steps: {c['s']:.2f} s: {c['kept']}; "
              f"estimated error {c['error_estimate']:.2g}")
    print(f"  peak memory of the process {peak_gb():.2f} GB")
    return out


def huge(n_bodies: int = 100_000) -> dict:
    """Build, assemble and ``modes(n_modes=20)`` at ``n_bodies`` (600,000 DOF), with peak memory."""
    with threadpool_limits(1):
        t = time.perf_counter()
        model = chain_model(n_bodies, damping="none", seed=3)
        t_model = time.perf_counter() - t
        mem_model = peak_gb()
        t = time.perf_counter()
        asm = vibss.assemble(model)
        t_asm = time.perf_counter() - t
        mem_asm = peak_gb()
        t = time.perf_counter()
        md = vibss.modes(asm, n_modes=20)
        t_modes = time.perf_counter() - t
        mem_modes = peak_gb()
        K, M = asm.K.tocsc(), asm.M.tocsc()
        t = time.perf_counter()
        w2 = np.sort(spl.eigsh(K, k=20, M=M, sigma=0.0, which="LM")[0])
        t_eigsh = time.perf_counter() - t
    err = float(np.abs(md.omega ** 2 / w2 - 1).max())
    out = {"dofs": 6 * n_bodies, "model_s": t_model, "assemble_s": t_asm, "modes_s": t_modes,
           "eigsh_s": t_eigsh, "modes_error": err, "peak_gb_model": mem_model, "peak_gb_assembled": mem_asm,
           "peak_gb_modes": mem_modes, "peak_gb": peak_gb()}
    print(f"{6 * n_bodies} DOF chain (seed 3), one BLAS thread:")
    print(f"  Model built {t_model:.1f} s (peak {mem_model:.2f} GB)   assemble {t_asm:.1f} s (peak {mem_asm:.2f} GB)")
    print(f"  modes(n_modes=20) {t_modes:.1f} s (peak {mem_modes:.2f} GB)   assembly + modes {t_asm + t_modes:.1f} s")
    print(f"  raw eigsh shift-invert {t_eigsh:.1f} s   ratio {t_modes / t_eigsh:.2f}x   frequencies differ by {err:.1e}")
    print(f"  peak memory of the process {peak_gb():.2f} GB")
    return out


if __name__ == "__main__":
    from run_all import main_one

    if "--huge" in sys.argv:            # 100,000 bodies: assembly and 20 modes only, by hand
        huge()
    else:
        main_one("large")
