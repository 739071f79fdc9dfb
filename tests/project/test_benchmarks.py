"""Issue 16: the quick benchmarks are deterministic. The Krylov reduction of the quick run (a seeded
random chain, its band from a seeded sparse eigen-solve) gives the same basis sizes twice in one
process (where ARPACK's unseeded start vector would move on between calls); no timing is asserted."""

from __future__ import annotations

import sys

import numpy as np
import pytest
from cases import ROOT



@pytest.fixture(scope="module")
def bench_reduction():
    pytest.importorskip("threadpoolctl")
    sys.path.insert(0, str(ROOT))
    try:
        from benchmarks import bench_reduction
    finally:
        sys.path.remove(str(ROOT))
    return bench_reduction


def test_quick_reduction_gives_the_same_basis_sizes_twice(bench_reduction):
    first = bench_reduction.quick_basis_sizes(n_bodies=30, n_modes_band=6)
    second = bench_reduction.quick_basis_sizes(n_bodies=30, n_modes_band=6)
    assert first == second and min(first) > 0


def test_seeded_shift_invert_is_repeatable():
    """vibss's own shift-invert solver starts from a seeded vector: bit-identical frequencies twice,
    and equal (to round-off) to the dense solution of the same problem."""
    import vibss

    sys.path.insert(0, str(ROOT))
    try:
        from benchmarks.models import chain_model
    finally:
        sys.path.remove(str(ROOT))
    from vibss.linear.plant.memo import forget

    model = chain_model(8, damping="none", seed=3)
    a = []
    for _ in range(2):
        forget()                 # solved twice, not the remembered spectrum handed out again
        a.append(vibss.modes(model, n_modes=6, method="shift-invert").omega)
    assert np.array_equal(a[0], a[1])
    assert np.allclose(a[0], vibss.modes(model, method="dense").omega[:6], rtol=1e-8)


def test_krylov_numerical_failure_is_a_vibss_error(monkeypatch):
    """A linear-algebra failure inside the Krylov step surfaces as an AnalysisError naming the step."""
    import vibss
    from vibss.errors import AnalysisError
    from vibss.reduction import krylov as kr

    def broken(*args, **kwargs):
        raise np.linalg.LinAlgError("Singular matrix")

    import vibss.linear.project.krylov as basis_pieces          # the basis' Gram-Schmidt lives there

    monkeypatch.setattr(basis_pieces, "symmetric_eigen", broken)
    p = kr.sparse_plant(vibss.load_example("two_mass"), ["body1.fz"], ["body2.z"])
    with pytest.raises(AnalysisError, match="krylov: a linear-algebra step failed"):
        kr.krylov(p, (0.1, 100.0), 1e-6)


def test_every_benchmark_has_the_harness_shape():
    """Issue 28 item 7: each benchmarks/bench_*.py defines ``bench(quick: bool) -> dict`` and leaves
    threads, JSON and tables to run_all.py (airspeed velocity's shape): no benchmark writes its own
    results file, and each one's ``__main__`` goes through the harness."""
    import ast

    for path in sorted((ROOT / "benchmarks").glob("bench_*.py")):
        text = path.read_text()
        tree = ast.parse(text)
        funcs = {n.name: n for n in tree.body if isinstance(n, ast.FunctionDef)}
        assert "bench" in funcs, f"{path.name} defines no bench(quick)"
        assert [a.arg for a in funcs["bench"].args.args] == ["quick"], path.name
        assert "write_text(json" not in text and "json.dump(" not in text, f"{path.name} writes its own JSON"
        assert f'main_one("{path.stem[len("bench_"):]}")' in text, f"{path.name}: __main__ bypasses the harness"
