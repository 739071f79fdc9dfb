"""BLAS on one thread while an analysis runs: threaded BLAS on a busy machine costs a scheduler quantum
a call.

OpenBLAS (NumPy's and SciPy's own copies, two pools) splits a product over the cores and waits for
every part. On an idle machine the wait is short; when another process holds a core, each threaded
call waits for that core's next time slice. Measured on the 2-core VM with one core busy (docs/
performance.md, "Threads under load"): a batch of 256 expm of 24 x 24 matrices 2.0 s on two threads
against 0.023 s on one, twenty 200 x 200 products 0.35 s against 0.013 s. vibss's work is many
small and middle-sized products, so :func:`one_blas_thread` holds BLAS to one thread inside the one
decider (:func:`vibss.methods.decide`), the time kernels and harmonic balance; :func:`threaded_blas`
gives the pools back their threads for one large dense call (an ``eigh`` from
:data:`THREADED_DOFS` DOFs), where two threads pay even beside a busy core.

The setting is process-wide (threadpoolctl sets the pools), so it is taken by the first user and
given back by the last, from any thread: two threads entering and leaving in turn must not leave
the process on one thread for good (issue 18). One limit measured: with OpenBLAS 0.3.30/0.3.31, pools
that the main thread raised from ``OPENBLAS_NUM_THREADS=1`` do not take a limit set from a worker
thread (the worker's set is ignored); an analysis first entered from a worker then runs on the
pools' threads, as before this module.
"""

from __future__ import annotations

import contextlib
import threading
from collections.abc import Iterator
from typing import Any

from threadpoolctl import ThreadpoolController

__all__ = ["one_blas_thread", "threaded_blas", "dense_threads", "THREADED_DOFS"]

THREADED_DOFS = 2000
"""Dense eigen-solves from this many DOFs run on the process's own BLAS threads (see the module
docstring): their O(n^3) work dwarfs a thread's wake-up."""

_LOCK = threading.Lock()
_users = 0
_threaded = 0
_saved: Any = None
_controller: Any = None


def _pools() -> Any:
    """The process's BLAS thread pools, found once: ``threadpool_limits`` scans the loaded libraries
    on every call (about 2 ms, most of a 1,000-step run of a small model)."""
    global _controller
    if _controller is None:
        _controller = ThreadpoolController()
    return _controller.lib_controllers


def _limit(one: bool) -> None:
    """Every pool not on one thread by itself to one thread (``one``) or back to its saved count."""
    for lib, threads in _saved:
        if threads != 1:
            lib.set_num_threads(1 if one else threads)


@contextlib.contextmanager
def one_blas_thread() -> Iterator[None]:
    """BLAS on one thread for an analysis' many small products, safe from several threads: the first
    user sets every pool to one thread, the last puts back what it found (nesting is free)."""
    global _users, _saved
    with _LOCK:
        if _users == 0:
            # what threadpoolctl's limit(limits=1) does, without its report of every library (45 us)
            _saved = [(lib, lib.num_threads) for lib in _pools()]
            if _threaded == 0:             # a large call outside any analysis keeps its threads till it ends
                _limit(True)
        _users += 1
    try:
        yield
    finally:
        with _LOCK:
            _users -= 1
            if _users == 0:
                if _threaded == 0:
                    _limit(False)
                _saved = None


@contextlib.contextmanager
def threaded_blas() -> Iterator[None]:
    """The pools' own thread counts back for one large call inside :func:`one_blas_thread` (nothing
    outside it); counted like it: one thread again when the last large call ends."""
    global _threaded
    with _LOCK:
        if _users and _threaded == 0:
            _limit(False)
        _threaded += 1
    try:
        yield
    finally:
        with _LOCK:
            _threaded -= 1
            if _users and _threaded == 0:
                _limit(True)


def dense_threads(n: int) -> contextlib.AbstractContextManager[None]:
    """:func:`threaded_blas` for a dense solve of order ``n`` from :data:`THREADED_DOFS`, else nothing."""
    return threaded_blas() if n >= THREADED_DOFS else contextlib.nullcontext()
