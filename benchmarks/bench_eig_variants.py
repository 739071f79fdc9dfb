"""What LAPACK allows for complex modes' ``eig`` (issue 17 item 2): on the 1,200-state modal-form
matrix of the grid and the tree of ``benchmarks/models.py`` (600 DOF, every mount damped), CPU seconds
(``time.process_time``, best of two, one BLAS thread), relative to ``scipy.linalg.eig`` (``dgeev``,
right vectors): eigenvalues only; ``dgeevx`` with balancing N, P, S, B; and the split ``dgebal`` +
``dgehrd`` + ``dorghr`` + ``dhseqr`` + ``dtrevc`` with and without the back-transform ``V = Q Y``
(reached through ``scipy.linalg.cython_lapack``'s capsules with ctypes). Run:
``python benchmarks/bench_eig_variants.py [grid] [tree]``.
"""
import os
import ctypes, sys, time
import numpy as np, scipy.linalg as sl
import scipy.linalg.cython_lapack as cl
from threadpoolctl import threadpool_limits

def ptr(name):
    cap = cl.__pyx_capi__[name]
    g = ctypes.pythonapi.PyCapsule_GetName; g.restype = ctypes.c_char_p; g.argtypes = [ctypes.py_object]
    p = ctypes.pythonapi.PyCapsule_GetPointer; p.restype = ctypes.c_void_p; p.argtypes = [ctypes.py_object, ctypes.c_char_p]
    return p(cap, g(cap))
def fn(name, nargs):
    return ctypes.CFUNCTYPE(None, *([ctypes.c_void_p] * nargs))(ptr(name))
GEEVX, GEBAL, GEHRD, ORGHR, HSEQR, TREVC, GEBAK = (fn("dgeevx", 23), fn("dgebal", 8), fn("dgehrd", 9), fn("dorghr", 9),
                                                  fn("dhseqr", 14), fn("dtrevc", 14), fn("dgebak", 11))
I = lambda v: ctypes.byref(ctypes.c_int(v))
C = lambda c: ctypes.c_char_p(c.encode())

def geevx(a, balanc):
    n = a.shape[0]; a = np.asfortranarray(a.copy())
    wr, wi = np.zeros(n), np.zeros(n); vr = np.zeros((n, n), order="F"); vl = np.zeros(1)
    ilo, ihi, info = ctypes.c_int(), ctypes.c_int(), ctypes.c_int()
    scale, abnrm, rce, rcv = np.zeros(n), np.zeros(1), np.zeros(n), np.zeros(n)
    iwork = np.zeros(2 * n, np.int32)
    work = np.zeros(1); 
    args = lambda lw: [C(balanc), C("N"), C("V"), C("N"), I(n), a.ctypes.data, I(n), wr.ctypes.data, wi.ctypes.data,
                       vl.ctypes.data, I(1), vr.ctypes.data, I(n), ctypes.byref(ilo), ctypes.byref(ihi),
                       scale.ctypes.data, abnrm.ctypes.data, rce.ctypes.data, rcv.ctypes.data, work.ctypes.data,
                       I(lw), iwork.ctypes.data, ctypes.byref(info)]
    GEEVX(*args(-1)); lw = int(work[0]); work = np.zeros(lw)
    GEEVX(*args(lw)); assert info.value == 0, info.value
    return wr + 1j * wi, vr

def split(a, backtransform=True, times=None):
    n = a.shape[0]; a = np.asfortranarray(a.copy()); info = ctypes.c_int(); ilo, ihi = ctypes.c_int(), ctypes.c_int()
    scale = np.zeros(n); t0 = time.process_time()
    GEBAL(C("B"), I(n), a.ctypes.data, I(n), ctypes.byref(ilo), ctypes.byref(ihi), scale.ctypes.data, ctypes.byref(info))
    t1 = time.process_time()
    tau = np.zeros(n); work = np.zeros(1)
    GEHRD(I(n), ctypes.byref(ilo), ctypes.byref(ihi), a.ctypes.data, I(n), tau.ctypes.data, work.ctypes.data, I(-1), ctypes.byref(info))
    work = np.zeros(int(work[0])); GEHRD(I(n), ctypes.byref(ilo), ctypes.byref(ihi), a.ctypes.data, I(n), tau.ctypes.data, work.ctypes.data, I(work.size), ctypes.byref(info))
    t2 = time.process_time()
    q = np.asfortranarray(a.copy())
    work = np.zeros(1); ORGHR(I(n), ctypes.byref(ilo), ctypes.byref(ihi), q.ctypes.data, I(n), tau.ctypes.data, work.ctypes.data, I(-1), ctypes.byref(info))
    work = np.zeros(int(work[0])); ORGHR(I(n), ctypes.byref(ilo), ctypes.byref(ihi), q.ctypes.data, I(n), tau.ctypes.data, work.ctypes.data, I(work.size), ctypes.byref(info))
    h = np.triu(a, -1).copy(order="F")
    t3 = time.process_time()
    wr, wi = np.zeros(n), np.zeros(n); work = np.zeros(1)
    HSEQR(C("S"), C("V"), I(n), ctypes.byref(ilo), ctypes.byref(ihi), h.ctypes.data, I(n), wr.ctypes.data, wi.ctypes.data, q.ctypes.data, I(n), work.ctypes.data, I(-1), ctypes.byref(info))
    work = np.zeros(int(work[0])); HSEQR(C("S"), C("V"), I(n), ctypes.byref(ilo), ctypes.byref(ihi), h.ctypes.data, I(n), wr.ctypes.data, wi.ctypes.data, q.ctypes.data, I(n), work.ctypes.data, I(work.size), ctypes.byref(info))
    assert info.value == 0
    t4 = time.process_time()
    vr = q.copy(order="F") if backtransform else np.zeros((n, n), order="F")
    m = ctypes.c_int(); work = np.zeros(3 * n); sel = np.zeros(n, np.int32)
    TREVC(C("R"), C("B" if backtransform else "A"), sel.ctypes.data, I(n), h.ctypes.data, I(n), None, I(1), vr.ctypes.data, I(n), I(n), ctypes.byref(m), work.ctypes.data, ctypes.byref(info))
    t5 = time.process_time()
    if times is not None:
        times.update(gebal=t1 - t0, gehrd=t2 - t1, orghr=t3 - t2, hseqr=t4 - t3, trevc=t5 - t4)
    return wr + 1j * wi, vr


def modal_matrix(kind: str) -> np.ndarray:
    """The matrix ``complex_modal`` hands to ``eig`` on the benchmark's model of that topology."""
    from pathlib import Path
    sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
    from benchmarks.models import topology_model
    import vibss.linear.eigen.complex_modes as cm
    from vibss.frequency.kernels import METHODS
    from vibss.linear.plant.build import build_plant

    plant = build_plant(topology_model(kind, 100, damping="general"), ["b0.fx"], ["b0.x"])
    seen = {}
    original = cm.eigenpairs

    def keep(a):
        seen["a"] = a.copy()
        return original(a)

    cm.eigenpairs = keep
    try:
        METHODS["complex_modal"](plant, np.array([1j]))
    finally:
        cm.eigenpairs = original
    return seen["a"]


print(f"load average at start: {os.getloadavg()[0]:.1f}", flush=True)
with threadpool_limits(1):
    for kind in (sys.argv[1:] or ["grid", "tree"]):
        A = modal_matrix(kind)
        res = {}
        def tm(name, f, rep=2):
            best = 1e9
            for _ in range(rep):
                t = time.process_time(); out = f(); best = min(best, time.process_time() - t)
            res[name] = best; return out
        lam0, _ = tm("dgeev (sl.eig, right)", lambda: sl.eig(A, check_finite=False))
        tm("eigenvalues only (dgeev N,N)", lambda: sl.eig(A, right=False, check_finite=False))
        for b in "NPSB":
            lam, vr = tm(f"dgeevx balanc={b}", lambda: geevx(A, b))
        T = {}
        tm("split, trevc back-transformed", lambda: split(A, True, T))
        parts = dict(T)
        tm("split, trevc without back-transform", lambda: split(A, False))
        print(kind, A.shape)
        for k, v in res.items(): print(f"  {k:40s} {v:.3f} s  ({v / res['dgeev (sl.eig, right)']:.2f})")
        print("  parts of the split:", "  ".join(f"{k} {v:.3f}" for k, v in parts.items()))
