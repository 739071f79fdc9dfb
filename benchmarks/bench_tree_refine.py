"""How the general-damping FRF refines its slow complex poles, measured on the 600-DOF tree (issue 17
item 2): which modes need it, what each refinement costs, and how accurate each is.

The tree of ``benchmarks/models.py`` (100 bodies, every mount damped with its own beta) has stiff
overdamped modes (``max|lam|`` 2.5e7 rad/s) beside lightly damped ones, so the a-priori bound
``eps max|lam| / |Re lam|`` flags hundreds of modes. Variants of
``vibss.linear.eigen.complex_modes._refine_slow_modes``, each run through ``complex_modal``:

- ``none``: ``eig``'s pairs as they stand;
- ``all at risk``: the per-mode dense inverse iteration on ``Q(lam)`` for every flagged mode (the
  path before the screen, with conjugate partners taken by conjugation);
- ``screened``: vibss's path: the a-posteriori screen, inverse iteration only where it says so;
- ``hessenberg``: one Hessenberg form of the 2n-state matrix (``scipy.linalg.hessenberg``) and
  LAPACK ``zhsein`` (inverse iteration on it, O(N^2) a vector) for the flagged modes' vectors,
  reached through ``scipy.linalg.cython_lapack``'s capsule with ctypes, then the ``x^T Q x`` root
  for the pole.

References, independent of any eigen-decomposition: (tree) the dense solve with three steps of
iterative refinement whose residuals are formed in long double, at the damped frequency of every
flagged mode and every tenth of the benchmark's 1,000 frequencies; (graded chain of
``tests/scaled_cases.py``) ``tests/mp_reference.py``'s 60-digit receptance at the points of
``tests/test_modal_superposition.py``. Error: max over frequencies of ||H - H_ref||_F / ||H_ref||_F.
One BLAS thread. Run: ``python benchmarks/bench_tree_refine.py`` (about 1-2 minutes).
"""

from __future__ import annotations

import ctypes
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
import scipy.linalg as sl
import scipy.linalg.cython_lapack as cython_lapack
import scipy.sparse as sp
from threadpoolctl import threadpool_limits

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))
from benchmarks.models import topology_model  # noqa: E402
from mp_reference import extended_precision_frf  # noqa: E402
import vibss.linear.eigen.complex_modes as cmm  # noqa: E402
from vibss.frequency.kernels import METHODS  # noqa: E402
from vibss.linear.eigen.basis import modal_basis  # noqa: E402
from vibss.linear.plant.build import build_plant  # noqa: E402

EPS = np.finfo(float).eps


# ----------------------------------------------------------------------- zhsein through ctypes
def _capsule_pointer(name: str) -> int:
    cap = cython_lapack.__pyx_capi__[name]
    get_name = ctypes.pythonapi.PyCapsule_GetName
    get_name.restype, get_name.argtypes = ctypes.c_char_p, [ctypes.py_object]
    get_ptr = ctypes.pythonapi.PyCapsule_GetPointer
    get_ptr.restype, get_ptr.argtypes = ctypes.c_void_p, [ctypes.py_object, ctypes.c_char_p]
    return get_ptr(cap, get_name(cap))


_ZHSEIN = ctypes.CFUNCTYPE(None, *([ctypes.c_void_p] * 19))(_capsule_pointer("zhsein"))


def zhsein(h: np.ndarray, w: np.ndarray, select: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Right eigenvectors of the upper Hessenberg ``h`` for the eigenvalues ``w[select]`` (LAPACK
    ``zhsein``, SIDE='R', EIGSRC='N', INITV='N'); returns (vectors, failed flags)."""
    n = h.shape[0]
    h = np.asfortranarray(h, dtype=complex)
    w = np.array(w, dtype=complex)
    sel = np.asarray(select, dtype=np.int32).copy()
    mm = max(int(sel.sum()), 1)
    vr = np.zeros((n, mm), dtype=complex, order="F")
    vl, work, rwork = np.zeros(1, complex), np.zeros(n * n, complex), np.zeros(n)
    ifl, ifr = np.zeros(mm, np.int32), np.zeros(mm, np.int32)
    ints = [ctypes.c_int(x) for x in (n, n, 1, mm, 0, 0)]
    nn, ld, ldvl, mmc, m, info = ints
    ref = ctypes.byref
    _ZHSEIN(ctypes.c_char_p(b"R"), ctypes.c_char_p(b"N"), ctypes.c_char_p(b"N"), sel.ctypes.data, ref(nn),
            h.ctypes.data, ref(ld), w.ctypes.data, vl.ctypes.data, ref(ldvl), vr.ctypes.data, ref(ld),
            ref(mmc), ref(m), work.ctypes.data, rwork.ctypes.data, ifl.ctypes.data, ifr.ctypes.data, ref(info))
    if info.value < 0:
        raise RuntimeError(f"zhsein: argument {-info.value} illegal")
    return vr[:, :m.value], ifr[:m.value] != 0


# ----------------------------------------------------------------------- the variants
ORIGINAL = cmm._refine_slow_modes
TIMES: dict[str, float] = {}


def _at_risk(lam: np.ndarray) -> np.ndarray:
    risk = EPS * float(np.abs(lam).max()) / np.maximum(np.abs(lam.real), np.finfo(float).tiny)
    return np.flatnonzero((risk > cmm.REFINE_RISK) & (np.abs(lam) > 0) & np.isfinite(risk))


def _kp(scale, rows, omega2, coupling, nk):
    kp = np.zeros((nk, nk), dtype=complex)
    kp[rows, rows] = omega2
    if coupling is not None:
        kp[:, rows] += coupling * scale[None, :]
    return kp


def v_none(lam, v, *args, **kwargs):
    return lam, v


def v_all(lam, v, scale, rows, omega2, damping, coupling, horizon=np.inf):
    todo = _at_risk(lam)
    kp = _kp(scale, rows, omega2, coupling, damping.shape[0])
    t = time.perf_counter()
    out = cmm._inverse_iteration(lam.astype(complex), v.astype(complex), todo, scale, rows, damping, kp)
    TIMES.update(refine=time.perf_counter() - t, modes=todo.size)
    return out


def v_screened(lam, v, *args, **kwargs):
    inverse_iteration = cmm._inverse_iteration

    def counted(lam, v, todo, *rest):
        TIMES.update(modes=todo.size)
        return inverse_iteration(lam, v, todo, *rest)

    cmm._inverse_iteration = counted
    try:
        t = time.perf_counter()
        out = ORIGINAL(lam, v, *args, **kwargs)
        TIMES.update(refine=time.perf_counter() - t)
    finally:
        cmm._inverse_iteration = inverse_iteration
    return out


def v_hessenberg(lam, v, scale, rows, omega2, damping, coupling, horizon=np.inf):
    t0 = time.perf_counter()
    todo = _at_risk(lam)
    lam, v = lam.astype(complex), v.astype(complex)
    ne, nk = scale.size, damping.shape[0]
    a = np.zeros((ne + nk, ne + nk), dtype=complex if coupling is not None else float)
    a[np.arange(ne), ne + rows] = scale
    a[ne + rows, np.arange(ne)] = -omega2 / scale
    if coupling is not None:
        a[ne:, :ne] -= coupling
    a[ne:, ne:] = -damping
    h, q = sl.hessenberg(a, calc_q=True, check_finite=False)
    t1 = time.perf_counter()
    sel = np.zeros(lam.size, bool)
    sel[todo] = True
    y, failed = zhsein(h, lam, sel)
    t2 = time.perf_counter()
    vt = q @ y
    vt /= np.linalg.norm(vt, axis=0)
    v[:, todo[~failed]] = vt[:, ~failed]
    lam, v = cmm._rayleigh(lam, v, todo, scale, rows, damping, _kp(scale, rows, omega2, coupling, nk))
    TIMES.update(refine=time.perf_counter() - t0, hessenberg=t1 - t0, zhsein=t2 - t1, modes=todo.size)
    return lam, v


VARIANTS = {"none": v_none, "all at risk": v_all, "screened": v_screened, "hessenberg": v_hessenberg}


# ----------------------------------------------------------------------- references


def _err(h: np.ndarray, ref: np.ndarray) -> float:
    return float((np.linalg.norm(h - ref, axis=(0, 1)) / np.linalg.norm(ref, axis=(0, 1))).max())


def tree() -> list[dict]:
    model = topology_model("tree", 100, damping="general")
    inputs = [f"b{i * 16}.f{'xyz'[i % 3]}" for i in range(6)]
    outputs = [f"b{i * 16}.{d}" for i in range(6) for d in ("x", "y", "z", "rx", "ry", "rz")]
    plant = build_plant(model, inputs, outputs)
    w = modal_basis(plant).omega
    grid = np.geomspace(0.5 * w.min(), 1.5 * w.max(), 1000)[::10]
    flagged = {}

    def grab(lam, v, *args, **kwargs):
        flagged["lam"] = lam[_at_risk(lam)]
        return lam, v

    cmm._refine_slow_modes = grab
    METHODS["complex_modal"](replace(plant), 1j * grid[:1])
    wr = np.unique(np.abs(flagged["lam"].imag))
    s_res, s_grid = 1j * wr[wr > 0], 1j * grid
    t = time.perf_counter()
    ref_res, ref_grid = extended_precision_frf(plant, s_res), extended_precision_frf(plant, s_grid)
    print(f"tree: {plant.n} DOF, {flagged['lam'].size} modes at risk by the a-priori bound, "
          f"{s_res.size} resonances; reference {time.perf_counter() - t:.0f} s", flush=True)
    rows = []
    with threadpool_limits(1):
        e_direct = _err(METHODS["direct"](plant, s_res), ref_res)
        print(f"  direct (dense LU) at the resonances: {e_direct:.1e}", flush=True)
        for name, fn in VARIANTS.items():
            cmm._refine_slow_modes = fn
            TIMES.clear()
            t = time.perf_counter()
            h_grid = METHODS["complex_modal"](replace(plant), s_grid)
            total = time.perf_counter() - t
            timing = dict(TIMES)
            h_res = METHODS["complex_modal"](replace(plant), s_res)
            row = {"variant": name, "complex_modal_s": total, **timing,
                   "error_resonances": _err(h_res, ref_res), "error_grid": _err(h_grid, ref_grid)}
            rows.append(row)
            extra = "  ".join(f"{k} {v:.2f} s" if isinstance(v, float) else f"{k} {v}" for k, v in timing.items())
            print(f"  {name:12s} complex_modal {total:6.2f} s ({extra}); error at the resonances "
                  f"{row['error_resonances']:.1e}, on the grid {row['error_grid']:.1e}", flush=True)
    cmm._refine_slow_modes = ORIGINAL
    return rows


def graded() -> list[dict]:
    import mp_reference as mpr
    import scaled_cases as sc

    model = sc.graded_chain(damped=True)
    dofs = [f"{b.name}.{d}" for b in model.bodies for d in ("x", "y", "z", "rx", "ry", "rz")]
    ins = [f"{b.name}.{d}" for b in model.bodies for d in ("fx", "fy", "fz", "mx", "my", "mz")]
    plant = build_plant(model, ins, dofs)
    wn = mpr.natural_frequencies(model)
    el = wn[wn > 0]
    points = {"1.001, 1.003 w1": np.array([1.001, 1.003]) * el.min(), "0.3 w1": np.array([0.3]) * el.min(),
              "1.01, 3, 10 wmax": np.array([1.01, 3.0, 10.0]) * el.max()}
    refs = {k: np.stack([mpr.receptance(model, complex(0.0, x)) for x in w], axis=-1) for k, w in points.items()}
    rows = []
    for name, fn in VARIANTS.items():
        cmm._refine_slow_modes = fn
        row = {"variant": name}
        for k, w in points.items():
            h = METHODS["complex_modal"](plant, 1j * w)
            row[k] = float((np.linalg.norm(h - refs[k], axis=0) / np.linalg.norm(refs[k], axis=0)).max())
        rows.append(row)
        print(f"  graded chain, {name:12s} " + "  ".join(f"{k}: {row[k]:.1e}" for k in points), flush=True)
    cmm._refine_slow_modes = ORIGINAL
    return rows


if __name__ == "__main__":
    import os

    print(f"load average at start: {os.getloadavg()[0]:.1f}", flush=True)
    tree()
    print("graded chain (60-digit reference, tests/test_modal_superposition.py's points):", flush=True)
    graded()
    print(f"load average at end: {os.getloadavg()[0]:.1f}", flush=True)
