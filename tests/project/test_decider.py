"""The one decider (vibss.methods.decide): auto never keeps an answer that failed its check, a named
method that misses says so with the measured bound, and the memory guard refuses before allocating.

The "analysis" here is the solve of a small linear system; the methods are a direct solve and a
truncated Jacobi iteration whose error is measured against the direct answer, so every check's
number comes from an independent computation."""

from __future__ import annotations

import numpy as np
import pytest

from vibss.errors import AnalysisError, ResourceError, VibssWarning
from vibss.methods import Check, Claim, Cost, Method, available_memory, decide, guard

A = np.array([[4.0, 1.0, 0.0], [1.0, 3.0, 1.0], [0.0, 1.0, 2.0]])
B = np.array([1.0, 2.0, 3.0])
EXACT = np.linalg.solve(A, B)


def _jacobi(sweeps: int) -> np.ndarray:
    d = np.diag(A)
    x = np.zeros(3)
    for _ in range(sweeps):
        x = (B - (A @ x - d * x)) / d
    return x


def _residual(method: Method, x: np.ndarray) -> Check:
    """Relative residual: independent of how x was found."""
    assert method.claim is not None
    err = float(np.linalg.norm(A @ x - B) / (np.linalg.norm(A, 2) * np.linalg.norm(x) + np.linalg.norm(B)))
    return Check(err, method.claim.tolerance, "the residual of A x = b")


ROUGH = Method("rough", lambda: _jacobi(3), claim=Claim(1e-12, conditions="converged"))
DIRECT = Method("direct", lambda: np.linalg.solve(A, B), exact=True, claim=Claim(1e-14, exact=True))
REFUSES = Method("refuses", lambda: (_ for _ in ()).throw(AnalysisError("cannot")), claim=Claim(1e-12))


def test_auto_falls_back_when_a_check_fails_and_says_what_was_tried() -> None:
    d = decide([ROUGH, DIRECT], lambda m: m(), where="demo", auto=True, check=_residual)
    assert d.method is DIRECT
    assert np.allclose(d.answer, EXACT, rtol=1e-14)
    assert [a.outcome for a in d.attempts] == ["check failed", "answered"]
    assert "tried rough check failed" in d.note() and d.check is not None and d.check.ok


def test_auto_skips_a_refusal_and_raises_when_nothing_passes() -> None:
    d = decide([REFUSES, DIRECT], lambda m: m(), where="demo", auto=True, check=_residual)
    assert d.method is DIRECT and "refuses refused (cannot)" in d.note()
    with pytest.raises(AnalysisError, match="no method answered within its claim: refuses refused .*rough check failed"):
        decide([REFUSES, ROUGH], lambda m: m(), where="demo", auto=True, check=_residual)


def test_a_named_method_that_misses_warns_with_the_measured_bound() -> None:
    with pytest.warns(VibssWarning, match=r"method 'rough' missed its claim \(within 1e-12 when converged\)"):
        d = decide([ROUGH], lambda m: m(), where="demo", auto=False, check=_residual)
    measured = np.linalg.norm(A @ _jacobi(3) - B) / (np.linalg.norm(A, 2) * np.linalg.norm(_jacobi(3)) + np.linalg.norm(B))
    assert d.check is not None and d.check.error == pytest.approx(measured, rel=1e-12)
    assert f"{measured:.1e}" in d.note()


def test_a_named_refusal_propagates() -> None:
    with pytest.raises(AnalysisError, match="cannot"):
        decide([REFUSES], lambda m: m(), where="demo", auto=False)


def test_the_memory_guard_refuses_before_running() -> None:
    ran: list[str] = []
    huge = Cost(seconds=1.0, bytes=10 * available_memory())

    def run(m: Method) -> np.ndarray:
        ran.append(m.name)
        return m()

    with pytest.raises(ResourceError, match=r"method 'rough' would allocate about .* GB.*use \['direct'\]"):
        decide([ROUGH], run, where="demo", auto=False, others=[DIRECT],
               cost=lambda m: huge if m is ROUGH else Cost(bytes=1e3), check=_residual)
    assert ran == []
    d = decide([ROUGH, DIRECT], run, where="demo", auto=True, check=_residual,
               cost=lambda m: huge if m is ROUGH else Cost(bytes=1e3))
    assert ran == ["direct"] and d.attempts[0].outcome == "over the memory guard"
    with pytest.raises(ResourceError, match="every method would pass the memory guard"):
        decide([ROUGH], run, where="demo", auto=True, cost=lambda m: huge)
    guard(Cost(bytes=1.0), where="demo", method="x")      # a small estimate passes


def test_check_of_nan_fails() -> None:
    assert not Check(float("nan"), 1e-9).ok
    assert Check(1e-10, 1e-9).ok


def test_a_stated_bound_is_rounded_up_never_down():
    """A check's error is a bound: printed to two digits it must not fall below the measured number
    (1.93e-8 once printed as 1.9e-08 under a measured 1.93e-8)."""
    from vibss.methods import Check

    for x in (1.929810846104498e-08, 9.951e-05, 3.0e-7, 1.05e-12):
        printed = float(Check(x, 1e-9).text().split("error ")[1].split()[0])
        assert x <= printed <= x * 1.06


def test_then_ranks_the_fallback_only_when_the_pick_does_not_answer():
    """``Then(first, rest)``: ``decide`` reads ``rest()`` (an exact fallback ranked by a cost that may
    need a trial factorisation) only when the first candidate refused or failed its check."""
    from vibss.methods import Then

    first, second = Method("first", lambda: 1.0), Method("second", lambda: 0.0, exact=True)
    asked: list[int] = []

    def rest() -> list[Method]:
        asked.append(1)
        return [second]

    dec = decide(Then(first, rest), lambda m: m.name, where="t", auto=True)
    assert dec.method is first and asked == []
    dec = decide(Then(first, rest), lambda m: m.name, where="t", auto=True,
                 check=lambda m, a: Check(1.0 if m is first else 0.0, 0.5, "test"))
    assert dec.method is second and asked == [1] and [a.method for a in dec.attempts] == ["first", "second"]
