"""Large models without a dense n x n matrix: lowest modes and a few-channel FRF, same run.

Issue 17 item 4. A seeded chain of rigid bodies (``benchmarks.models.chain_model``, undamped so the
model builder itself needs no eigen-analysis), one BLAS thread:

- ``vibss.modes(model, n_modes=20)`` against raw ``scipy.sparse.linalg.eigsh`` shift-invert on the
  same assembled K and M (time ratio, largest relative difference of the frequencies, peak memory);
- ``vibss.frequency_response(model, 1 input, 3 outputs, explicit frequencies)`` against a plain
  ``scipy.sparse.linalg.splu`` per frequency written here (the stock path), and its difference.

Run: ``python benchmarks/bench_large.py [--quick]`` (quick: 2,000 bodies instead of 10,000).
"""

from __future__ import annotations

import argparse
import resource
import sys
import time
from pathlib import Path

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spl
from threadpoolctl import threadpool_limits

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from benchmarks.models import chain_model  # noqa: E402
import vibss  # noqa: E402


def peak_gb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6


def main(quick: bool = False) -> dict:
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
        r = vibss.frequency_response(model, ["b0.fz"], outputs, frequencies=f)
        t_frf = time.perf_counter() - t
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
        err_frf = float(np.abs(r.response[:, 0, :].real - h).max() / np.abs(h).max())
    out = {"dofs": 6 * n_bodies, "assemble_s": t_asm, "modes_s": t_modes, "eigsh_s": t_eigsh,
           "modes_ratio": t_modes / t_eigsh, "modes_error": err_modes, "frf_s": t_frf, "splu_loop_s": t_splu,
           "frf_ratio": t_splu / t_frf, "frf_difference": err_frf, "peak_memory_gb": peak_gb()}
    print(f"{6 * n_bodies} DOF chain (seed 3), one BLAS thread:")
    print(f"  assemble {t_asm:.2f} s")
    print(f"  modes(n_modes=20) {t_modes:.2f} s   raw eigsh shift-invert {t_eigsh:.2f} s   ratio {t_modes / t_eigsh:.2f}x"
          f"   frequencies differ by {err_modes:.1e}")
    print(f"  FRF 1 x 3 x 200 f {t_frf:.2f} s ({r.method})   splu per frequency {t_splu:.2f} s   "
          f"{t_splu / t_frf:.2f}x faster   difference {err_frf:.1e}")
    print(f"  peak memory of the process {peak_gb():.2f} GB")
    return out


if __name__ == "__main__":
    parser = argparse.ArgumentParser()
    parser.add_argument("--quick", action="store_true")
    main(parser.parse_args().quick)
