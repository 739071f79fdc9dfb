"""``simulate(method="ivp")`` at 600 DOF: the sparse Jacobian vibss passes to Radau against the dense one
(what it passed before, and what a hand-written ``solve_ivp(..., jac=A)`` does), same run.

Model ``chain_model(100, zeta=0.01)``, a 30 rad/s sine force on ``b0.fz``, 0 .. 0.05 s every 0.5 ms,
Radau at rtol 1e-6; reference: vibss's exact modal FOH (method "auto"). One BLAS thread.
Run: ``python benchmarks/bench_ivp.py``.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np
import scipy.sparse as sps
from scipy.integrate import solve_ivp
from threadpoolctl import threadpool_limits

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from benchmarks.models import chain_model  # noqa: E402
import vibss  # noqa: E402


def bench(quick: bool) -> dict:
    with threadpool_limits(1):
        m = chain_model(100, zeta=0.01)
        u = {"b0.fz": lambda t: np.sin(30 * t)}
        ref = vibss.simulate(m, inputs=u, outputs=["b0.z"], t_end=0.05, dt=5e-4)
        t = time.perf_counter()
        r = vibss.simulate(m, inputs=u, outputs=["b0.z"], t_end=0.05, dt=5e-4, method="ivp")
        t_vibss = time.perf_counter() - t
        sys_ = vibss.statespace(m, inputs=["b0.fz"], outputs=["b0.z"], realization="physical", balance=False)
        A, B, C = np.asarray(sys_.A), np.asarray(sys_.B), np.asarray(sys_.C)
        ts = ref.time
        out = {}
        for name, jac in (("dense", A), ("sparse", sps.csc_matrix(A))):
            t = time.perf_counter()
            sol = solve_ivp(lambda tt, x: A @ x + B[:, 0] * np.sin(30 * tt), (0, ts[-1]), np.zeros(A.shape[0]),
                            method="Radau", t_eval=ts, rtol=1e-6, atol=1e-15, jac=jac)
            out[name] = (time.perf_counter() - t, (C @ sol.y)[0])
    err = float(np.abs(r["b0.z"] - ref["b0.z"]).max() / np.abs(ref["b0.z"]).max())
    res = {"vibss_ivp_s": t_vibss, "hand_dense_jac_s": out["dense"][0], "hand_sparse_jac_s": out["sparse"][0],
           "ratio_dense_over_vibss": out["dense"][0] / t_vibss, "vibss_error": err}
    print(f"600 DOF, Radau rtol 1e-6, 100 samples: vibss ivp {t_vibss:.2f} s (error {err:.1e} against the exact FOH)")
    print(f"  hand-written solve_ivp, dense jac  {out['dense'][0]:.2f} s   ratio {out['dense'][0] / t_vibss:.1f}x")
    print(f"  hand-written solve_ivp, sparse jac {out['sparse'][0]:.2f} s")
    return res


if __name__ == "__main__":
    from run_all import main_one

    main_one("ivp")
