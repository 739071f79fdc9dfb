"""Insight benchmark: energy fractions and modal contributions on a 600-DOF chain, against the stock
route in the same run.

- energy fractions: ``vibss.energy_distribution(modes, "strain")`` (all mounts at once) against a
  per-mount Python loop (each mount's deflection ``B_p Phi`` and local energies ``k_j d_j^2``,
  vectorised over the modes only), both on the same computed modes; max difference of the fractions;
- modal contributions: ``vibss.modal_contributions`` (1 input at body 0, 4 outputs, 200 log-spaced
  frequencies) on the classically damped chain (modal terms) and on its non-proportionally damped
  twin (complex modes) against the exact FRF ``frequency_response(method="direct")`` of the same
  signals: time, and the error of terms + residual per output relative to its largest |H| ("near":
  body 0, body 1 and a ground mount's force at body 0; "far": the middle body, whose response is a
  cancellation of the modes' terms to ~1e-13 of their size, which no modal sum resolves: the
  ``modal`` and ``complex_modal`` FRF kernels miss it alike, measured in the same run).

Model: ``chain_model(100)`` (600 DOF, seeded), ``--quick``: 20 bodies (120 DOF). One BLAS thread.
Run: ``python benchmarks/bench_insight.py [--quick]``.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from threadpoolctl import threadpool_limits

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from benchmarks.models import chain_model  # noqa: E402
from benchmarks.run_all import best  # noqa: E402
import vibss  # noqa: E402


def per_mount_loop(model: vibss.Model, shapes: np.ndarray) -> np.ndarray:
    """(k, mounts) strain fractions by a loop over the mounts (the stock way to write it)."""
    a = vibss.assemble(model)
    b = a.deflection_matrix()[:, :a.n]
    out = np.zeros((shapes.shape[1], len(model.mounts)))
    for p, m in enumerate(model.mounts):
        d = np.asarray(b[3 * p:3 * p + 3] @ shapes)                # (3, k) deflection in global axes
        local = m.orientation.matrix.T @ d
        out[:, p] = 0.5 * (np.asarray(m.type.stiffness)[:, None] * local**2).sum(axis=0)
    return out / out.sum(axis=1, keepdims=True)


def bench(quick: bool) -> dict:
    """The chain of the module docstring (20 bodies with ``quick``)."""
    n = 20 if quick else 100
    res: dict = {"dofs": 6 * n}
    with threadpool_limits(1):
        model = chain_model(n, seed=1)
        und = vibss.modes(model)
        t_v, e = best(lambda: vibss.energy_distribution(und, "strain"))
        t_l, ref = best(lambda: per_mount_loop(model, und.shapes))
        err = float(np.nanmax(np.abs(e.fractions - ref)))
        res["energy"] = {"mounts": len(model.mounts), "modes": len(und), "vibss_s": t_v, "loop_s": t_l,
                         "ratio": t_l / t_v, "max_abs_error": err}
        print(f"{6 * n} DOF, {len(model.mounts)} mounts, {len(und)} modes")
        print(f"energy fractions: vibss {t_v:.4f} s, per-mount loop {t_l:.4f} s (x{t_l / t_v:.1f}), "
              f"max |difference| {err:.1e}")
        f = np.geomspace(0.5, 200.0, 200)
        outs = ["b0.z", "b1.z", "mount.g0_0.fz", f"b{n // 2}.z"]
        for damping in ("classical", "general"):
            m = model if damping == "classical" else chain_model(n, damping="general", seed=1)
            t_c, c = best(lambda: vibss.modal_contributions(m, ["b0.fz"], outs, f), repeat=2)
            t_x, fr = best(lambda: vibss.frequency_response(m, ["b0.fz"], outs, f, method="direct"), repeat=2)
            h = fr.response
            rel = (np.abs(c.total - h) / np.abs(h).max(axis=2, keepdims=True)).max(axis=(1, 2))
            kernel = "modal" if damping == "classical" else "complex_modal"
            hk = vibss.frequency_response(m, ["b0.fz"], outs, f, method=kernel).response
            rel_k = (np.abs(hk - h) / np.abs(h).max(axis=2, keepdims=True)).max(axis=(1, 2))
            res[f"modal_{damping}"] = {"method": c.method, "vibss_s": t_c, "exact_frf_s": t_x,
                                       "ratio": t_x / t_c, "max_rel_error_near": float(rel[:3].max()),
                                       "rel_error_far": float(rel[3]), f"frf_{kernel}_rel_error_far": float(rel_k[3]),
                                       "checked": c.note.split("; ")[1] if "; " in c.note else c.note}
            print(f"modal contributions ({damping}, {c.method}): {t_c:.3f} s; exact FRF (direct) {t_x:.3f} s; "
                  f"rel. error of terms + residual near {rel[:3].max():.1e}, far (b{n // 2}.z) {rel[3]:.1e} "
                  f"(the FRF's {kernel} kernel: {rel_k[3]:.1e})")
    return res


if __name__ == "__main__":
    from benchmarks.run_all import main_one

    main_one("insight")
