"""Free-motion diagnosis of ``static`` on large models: the sparse path against the dense one.

A row of n boxes, each on four mounts and linked to the next; box n/2 has no z stiffness, and
gravity loads it along that free motion, so ``static`` must name it ("body 'b.' is free to move in
z") and refuse. The stock path is a dense ``eigh`` of the whole equilibrated stiffness (what
``vibss.statics`` did for every size before issue 18; forced here with ``NULL_DENSE_MAX``); the
sparse path works per connected component with a sparse LU condition check and shift-invert.
Both run in the same process on the same model; the messages must agree.

Run: ``OPENBLAS_NUM_THREADS=1 python benchmarks/bench_free_motions.py [--quick]``.
"""

from __future__ import annotations

import sys
import time

from threadpoolctl import threadpool_limits

import vibss
import vibss.linear.solve.static as st
from vibss import Body, Model, Mount, MountType, symmetric


def row(n: int) -> Model:
    t, free, link = MountType("t", [1e4, 1.2e4, 2e4]), MountType("f", [1e4, 1.2e4, 0.0]), MountType("l", [1e3, 1e3, 0.0])
    bodies, mounts = [], []
    for i in range(n):
        bodies.append(Body(f"b{i}", 10.0 + i % 7, [1.0, 1.1, 1.2], cog=[2.0 * i, 0, 0]))
        mounts += list(symmetric(Mount(f"m{i}", free if i == n // 2 else t, f"b{i}", at=[0.3, 0.2, 0.0])))
        if i:
            mounts.append(Mount(f"l{i}", link, f"b{i}", to=f"b{i - 1}", at=[-1.0, 0.0, 0.5]))
    return Model(bodies, mounts, gravity=[0.0, 0.0, -9.81])


def refusal(model: Model) -> tuple[float, str]:
    t0 = time.perf_counter()
    try:
        vibss.static(model)
    except vibss.AnalysisError as exc:
        return time.perf_counter() - t0, str(exc)
    raise AssertionError("no refusal")


def main() -> None:
    sizes = [200, 500] if "--quick" in sys.argv else [200, 500, 1000]
    print(f"{'bodies':>6}  {'DOFs':>5}  {'sparse [s]':>10}  {'dense [s]':>9}  {'ratio':>6}  same message")
    with threadpool_limits(1):
        for n in sizes:
            model = row(n)
            refusal(row(10))                                     # imports, caches
            t_sparse, m_sparse = refusal(model)
            default, st.NULL_DENSE_MAX = st.NULL_DENSE_MAX, 10**9
            try:
                t_dense, m_dense = refusal(model)
            finally:
                st.NULL_DENSE_MAX = default
            print(f"{n:>6}  {6 * n:>5}  {t_sparse:>10.2f}  {t_dense:>9.2f}  {t_dense / t_sparse:>6.1f}  "
                  f"{m_sparse == m_dense}")


if __name__ == "__main__":
    main()
