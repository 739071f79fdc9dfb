"""BLAS threads while vibss computes (vibss.threads): one thread inside the decider and harmonic
balance, the process's own count back afterwards, the pools' count for a large dense eigen-solve.

Threaded OpenBLAS beside a busy core cost a time slice a call (2.0 s against 0.023 s for 256 batched
24 x 24 expm on the 2-core VM: docs/performance.md); these tests hold the mechanism, threadpoolctl's
report of every pool is the independent witness."""

from __future__ import annotations

import numpy as np
import pytest
from threadpoolctl import threadpool_info, threadpool_limits

import vibss
import vibss.threads
from vibss.threads import one_blas_thread, threaded_blas


def _counts() -> list[int]:
    return [int(i["num_threads"]) for i in threadpool_info()]


@pytest.fixture()
def two_threads():
    """Every pool on two threads for the test (the suite runs with OPENBLAS_NUM_THREADS=1)."""
    with threadpool_limits(limits=2):
        if max(_counts(), default=0) < 2:
            pytest.skip("the BLAS pools do not take two threads here")
        yield


def test_the_decider_runs_methods_on_one_thread_and_gives_the_threads_back(two_threads, monkeypatch) -> None:
    import vibss.modal.api as modal_api

    seen: list[list[int]] = []
    real = modal_api.decide

    def spy(order, run, **kw):
        return real(order, lambda m: (seen.append(_counts()), run(m))[1], **kw)

    monkeypatch.setattr(modal_api, "decide", spy)
    before = _counts()
    modes = vibss.modes(vibss.load_example("powertrain"))
    assert modes.frequency_hz.size and seen and all(c == [1] * len(c) for c in seen)
    assert _counts() == before


def test_harmonic_balance_runs_on_one_thread(two_threads, monkeypatch) -> None:
    import vibss.nonlinear.harmonic as hb

    seen: list[list[int]] = []
    real = hb.follow
    monkeypatch.setattr(hb, "follow", lambda *a, **k: (seen.append(_counts()), real(*a, **k))[1])
    t = vibss.MountType("snub", [1e4] * 3, damping=[5.0] * 3, stops={"z": (1e-3, 1e6)})
    model = vibss.Model([vibss.Body("b", 1.0, [1.0, 1.0, 1.0])], [vibss.Mount("m", t, "b")])
    before = _counts()
    vibss.harmonic_balance(model, {"b.fz": 10.0}, ["b.z"], (10.0, 20.0), harmonics=3, points=5)
    assert seen == [[1] * len(before)] and _counts() == before


def test_a_large_dense_solve_takes_the_pools_threads_inside_one_thread(two_threads) -> None:
    before = _counts()
    with threaded_blas():                       # outside any one-thread region: nothing changes
        assert _counts() == before
    with one_blas_thread():
        assert _counts() == [1] * len(before)
        with threaded_blas():
            assert _counts() == before
            with threaded_blas():               # counted: the inner one's end keeps the outer's threads
                pass
            assert _counts() == before
        assert _counts() == [1] * len(before)
    assert _counts() == before


def test_a_worker_threads_limit_is_given_back(two_threads) -> None:
    """From a worker thread the pools come back as they were. (Whether the limit takes there depends on
    OpenBLAS's state: with the pools raised from OPENBLAS_NUM_THREADS=1 in the main thread, a worker's
    ``openblas_set_num_threads(1)`` did not take in 0.3.30/0.3.31; vibss.threads says so.)"""
    import threading

    before = _counts()
    done: list[bool] = []

    def work() -> None:
        with one_blas_thread():
            done.append(True)

    t = threading.Thread(target=work)
    t.start()
    t.join()
    assert done == [True] and _counts() == before


def test_dense_eigh_from_threaded_dofs_runs_on_the_pools_threads(two_threads, monkeypatch) -> None:
    """``generalized_eigh`` enters ``threaded_blas`` from THREADED_DOFS (lowered here to 30), not below."""
    import vibss.linear.eigen.undamped as und

    seen: list[list[int]] = []
    real = und.sl.eigh

    def spy(*a, **k):
        seen.append(_counts())
        return real(*a, **k)

    monkeypatch.setattr(vibss.threads, "THREADED_DOFS", 30)
    monkeypatch.setattr(und.sl, "eigh", spy)
    a = np.random.default_rng(3).normal(size=(180, 180))
    K, M = a @ a.T + 180 * np.eye(180), np.eye(180)          # above SMALL_PRODUCTS: scipy's eigh
    with one_blas_thread():
        w2, _ = und.generalized_eigh(K, M)
        assert _counts() == [1] * len(seen[-1])
    assert seen and seen[-1] == [2] * len(seen[-1])
    assert np.allclose(w2, np.linalg.eigvalsh(K), rtol=1e-12)
    monkeypatch.setattr(vibss.threads, "THREADED_DOFS", 1000)
    with one_blas_thread():
        und.generalized_eigh(K, M)
    assert seen[-1] == [1] * len(seen[-1])
