"""Methods as objects: a registry entry carries its kernel and its facts (SciPy ``integrate._ivp`` style).

Each analysis keeps a registry ``METHODS = {name: <Method subclass>(...)}`` whose entries say what
the drivers need to know (exact or not, needs the modal basis, hits pulse edges, force inputs
only, falls back to ...), so a driver reads attributes and never tests a method's name. One
resolver, :func:`resolve`, turns what a user passes (a registered name, a :class:`Method`, or a
callable with the analysis' kernel signature) into a :class:`Method`; an unknown name is a
:class:`~vibss.errors.ArgumentError` (a ``ModelError``, so a ``ValueError``) that lists the
valid names with a did-you-mean (:func:`vibss._validate.choice`).

Examples
--------
>>> registry = {"fast": Method("fast", abs)}
>>> resolve("fast", registry, where="demo").name
'fast'
>>> resolve("fats", registry, where="demo")
Traceback (most recent call last):
...
vibss.errors.ArgumentError: demo: method: unknown 'fats' (did you mean 'fast'?); expected one of ['fast']
"""

from __future__ import annotations

import math
import os
import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Generic, TypeVar

from ._validate import choice
from .errors import AnalysisError, ArgumentError, ResourceError, VibssWarning
from .threads import one_blas_thread

__all__ = ["Method", "Then", "resolve", "LARGE_DOFS", "SIMULATE_LARGE_DOFS", "SMALL_DOFS", "Claim", "Check", "Cost", "Attempt", "Decision",
           "decide", "guard", "available_memory", "MEMORY_FRACTION"]


@dataclass(frozen=True)
class Claim:
    """What a method promises about its answer.

    Attributes
    ----------
    tolerance : float
        Relative error bound of the answer [-] when ``conditions`` hold: the level its a-posteriori
        check is held to. An exact method (a direct solve) claims rounding: a small multiple of the
        unit round-off times the problem's conditioning, stated here as the check's limit.
    exact : bool
        Exact to rounding (no truncation, no discretisation).
    conditions : str
        When the claim holds ("classical damping", "inputs piecewise linear between breakpoints").
    """

    tolerance: float
    exact: bool = False
    conditions: str = ""

    def text(self) -> str:
        """One line: ``"exact to rounding (check 1e-09)"`` or ``"within 1e-06 when ..."``."""
        head = f"exact to rounding (checked to {self.tolerance:.0e})" if self.exact else f"within {self.tolerance:.0e}"
        return f"{head}{' when ' + self.conditions if self.conditions else ''}"


@dataclass(frozen=True)
class Check:
    """The outcome of a method's a-posteriori check.

    Attributes
    ----------
    error : float
        Measured error bound [-] (a relative residual, backward error or step-doubling estimate).
    limit : float
        What the method's claim allows [-].
    where : str
        What was checked ("3 check frequencies (1.2, 40, 200 Hz)").
    """

    error: float
    limit: float
    where: str = ""

    @property
    def ok(self) -> bool:
        """The error is within the limit (a NaN error is not)."""
        return bool(self.error <= self.limit)

    def text(self) -> str:
        """``"checked: 2.1e-13 <= 1e-09 at ..."`` or ``"check FAILED: ..."``; the error is rounded up
        to two digits (it is a bound: 1.93e-8 prints as 2.0e-08, never as 1.9e-08)."""
        rel = "<=" if self.ok else ">"
        head = "checked" if self.ok else "check failed"
        return f"{head}: error {_up(self.error)} {rel} {self.limit:.0e}{' at ' + self.where if self.where else ''}"


def _up(x: float) -> str:
    """``x`` in ``%.1e`` form, rounded up (away from zero) in its second digit."""
    if not math.isfinite(x) or x <= 0:
        return f"{x:.1e}"
    text = f"{x:.1e}"
    if float(text) >= x:
        return text
    mant, exp = text.split("e")
    return f"{float(mant) + 0.1:.1f}e{exp}" if float(mant) + 0.1 < 10 else f"{1.0:.1f}e{int(exp) + 1:+03d}"


@dataclass(frozen=True)
class Cost:
    """A method's estimated cost on the problem at hand.

    Attributes
    ----------
    seconds : float
        Estimated run time [s] on one core.
    bytes : float
        Estimated peak memory it allocates [B].
    """

    seconds: float = 0.0
    bytes: float = 0.0

    def text(self) -> str:
        """``"~0.12 s, 35 MB"``."""
        return f"~{self.seconds:.2g} s, {_size(self.bytes)}"


def _size(n: float) -> str:
    for unit, scale in (("GB", 1e9), ("MB", 1e6), ("kB", 1e3)):
        if n >= scale:
            return f"{n / scale:.3g} {unit}"
    return f"{n:.0f} B"

LARGE_DOFS = 3000
"""The large-model threshold [DOF]: above it an analysis of a Model keeps the model sparse instead of
computing every undamped mode densely. The measured crossover: the dense eigen-analysis of all the
modes is O(n^3) (a 20-frequency FRF at 6,000 DOF took 203 s, and the sparse path 0.17 s, the same
answer; docs/performance.md), while below a few thousand DOF the dense modes cost seconds and buy the
grid around the modes, the resonance marks and the modal methods. The frequency response's sparse
path is exact, so :func:`vibss.frequency_response` switches here (:func:`vibss.frequency.methods.stays_sparse`)."""

SMALL_DOFS = 12
"""The small-model threshold [DOF] of :func:`vibss.frequency_response`'s ``auto``: up to it the
dense exact solve is taken without a cost model (a 12 x 12 complex LU per frequency costs less than
computing which modal method would be cheaper; two bodies on mounts)."""

SIMULATE_LARGE_DOFS = 2 * LARGE_DOFS
"""The threshold of :func:`vibss.simulate` [DOF], twice :data:`LARGE_DOFS` for a measured reason: the time
response's large path (:mod:`vibss.time.large`) projects on a subspace and is approximate (a few per
cent on a pulse's displacements at its cut-off, with an error estimate), so it takes over only where
the exact dense modal path costs minutes and gigabytes (65-196 s at 6,000 DOF, by the load on the
machine; :func:`vibss.time.methods.stays_sparse`)."""


@dataclass(frozen=True)
class Method:
    """A method of an analysis: its name, its kernel and the facts a driver needs.

    Attributes
    ----------
    name : str
        Registry name (what results report as ``method``).
    kernel : callable
        The computation, with the analysis' one kernel signature (see the analysis' registry).
    exact : bool
        Exact to round-off (a reference the other methods are checked against).
    fallback : str or None
        Registry name used instead when this method refuses the problem under ``method="auto"``
        (e.g. complex modes refused as defective).
    summary : str
        One line on what it does.
    internal_states : bool
        Represents the internal states of frequency-dependent mounts (their Maxwell branches,
        :mod:`vibss.linear.plant.branches`); a driver refuses a plant with branches otherwise.
    claim : Claim or None
        Its accuracy claim (None: a user's method, which claims nothing and is checked against
        the analysis' exact reference where one exists).

    Calling a Method calls its kernel, so ``METHODS["direct"](plant, s)`` keeps working.
    """

    name: str
    kernel: Callable[..., Any]
    exact: bool = False
    fallback: str | None = None
    summary: str = ""
    internal_states: bool = False
    claim: Claim | None = None

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        return self.kernel(*args, **kwargs)


M = TypeVar("M", bound=Method)


def resolve(method: Any, registry: Mapping[str, M], *, where: str,
            custom: Callable[[Callable[..., Any]], M] | None = None,
            extra: Sequence[str] = ()) -> M:
    """The registry entry for ``method``: a name, a Method, or a user callable wrapped by ``custom``.

    Parameters
    ----------
    method : str, Method or callable
        What the user passed.
    registry : mapping of str to Method
        The analysis' :data:`METHODS`.
    where : str
        The public function, for messages (``"simulate"``, ``"reduce"`` ...).
    custom : callable or None
        Wraps a user callable into the analysis' Method subclass; None: callables are refused.
    extra : sequence of str
        Other accepted names the caller handles itself (listed in the message, e.g. ``"auto"``).

    Returns
    -------
    Method

    Raises
    ------
    ArgumentError
        An unknown name (listing the valid ones, with a did-you-mean), or anything else.
    """
    if isinstance(method, Method):
        return method       # type: ignore[return-value]  # a Method of this analysis, trusted
    if isinstance(method, str) and method in registry:
        return registry[method]
    if callable(method) and custom is not None:
        return custom(method)
    names = [*extra, *registry]
    choice(method, "method", names, who=where, callable_ok=custom is not None)   # raises for the rest
    raise ArgumentError(f"{where}: method: {method!r} is handled by {where} itself, not a registry entry",
                        argument="method", received=method, expected=tuple(registry))


def callable_name(fn: Callable[..., Any]) -> str:
    """The name a user callable is reported under (``__name__``, else ``"custom"``)."""
    return str(getattr(fn, "__name__", "custom"))


MEMORY_FRACTION = 0.5
"""No method allocates more than this fraction of the memory available when it starts: above it
the machine swaps or the kernel's out-of-memory killer ends the process (a rank-1,200 Woodbury
update once asked for 23 GB and was killed), so the method refuses first."""


def available_memory() -> float:
    """Memory available to a new allocation [B]: ``MemAvailable`` of /proc/meminfo (Linux), else
    the free physical pages, else infinity (no guard where the platform does not say)."""
    try:
        with open("/proc/meminfo") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return float(line.split()[1]) * 1024.0
    except OSError:
        pass
    try:
        return float(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (AttributeError, ValueError, OSError):
        return math.inf


def guard(cost: Cost, *, where: str, method: str, instead: Sequence[str] = ()) -> None:
    """Refuse, before allocating, a method whose estimated memory passes the guard.

    Parameters
    ----------
    cost : Cost
        The method's estimate for this problem.
    where : str
        The public function, for the message.
    method : str
        The method's name.
    instead : sequence of str
        Methods that fit, named in the message.

    Raises
    ------
    ResourceError
        ``cost.bytes`` exceeds :data:`MEMORY_FRACTION` of :func:`available_memory`.
    """
    budget = MEMORY_FRACTION * available_memory()
    if cost.bytes > budget:
        alt = f"; use {list(instead)}" if instead else ""
        raise ResourceError(f"{where}: method {method!r} would allocate about {_size(cost.bytes)}, more than "
                            f"{MEMORY_FRACTION:.0%} of the {_size(budget / MEMORY_FRACTION)} available{alt}",
                            argument="method", received=method, expected=tuple(instead))


A = TypeVar("A")


@dataclass(frozen=True)
class Attempt:
    """One method tried by :func:`decide`: its name, what happened and why."""

    method: str
    outcome: str        # "answered", "check failed", "refused", "over the memory guard"
    detail: str = ""

    def text(self) -> str:
        return f"{self.method} {self.outcome}{' (' + self.detail + ')' if self.detail else ''}"


@dataclass(frozen=True)
class Decision(Generic[A]):
    """What :func:`decide` settled: the method that answered, its answer, its check, and the attempts.

    Attributes
    ----------
    method : Method
    answer : object
        What the method returned.
    check : Check or None
        Its a-posteriori check (None: the method has none).
    attempts : tuple of Attempt
        Every method tried, in order, the last the one that answered.
    """

    method: Method
    answer: A
    check: Check | None
    attempts: tuple[Attempt, ...]

    def note(self) -> str:
        """What was tried before the answer, and the answer's check, for the result's ``note``."""
        before = [a.text() for a in self.attempts[:-1]]
        parts = [f"tried {'; '.join(before)}"] if before else []
        if self.check is not None:
            parts.append(self.check.text())
        return "; ".join(parts)


class Then(Sequence[M]):
    """``first``, then the methods ``rest()`` returns, found only when someone reads past ``first``.

    :func:`decide` reads past its first candidate only when that one refused, failed its check or
    passed the memory guard: an exact fallback ranked by its cost estimate (which may need a trial
    factorisation, 0.3 s of a 2,400-DOF random graph's 6 s FRF) costs nothing when the pick answers.
    """

    def __init__(self, first: M, rest: Callable[[], Sequence[M]]) -> None:
        self.first = first
        self._rest = rest
        self._tail: list[M] | None = None

    def tail(self) -> list[M]:
        """The methods after ``first`` (asked for once)."""
        if self._tail is None:
            self._tail = list(self._rest())
        return self._tail

    def __iter__(self) -> Any:
        yield self.first
        yield from self.tail()

    def __len__(self) -> int:
        return 1 + len(self.tail())

    def __bool__(self) -> bool:
        return True

    def __getitem__(self, i: Any) -> Any:
        if isinstance(i, int) and i == 0:
            return self.first
        return [self.first, *self.tail()][i]

    def __repr__(self) -> str:
        return f"Then({self.first!r}, {'...' if self._tail is None else self._tail!r})"


def decide(order: Sequence[Method], run: Callable[[Method], A], *, where: str, auto: bool,
           check: Callable[[Method, A], Check | None] = lambda m, a: None,
           cost: Callable[[Method], Cost | None] = lambda m: None,
           refusals: tuple[type[Exception], ...] = (AnalysisError,),
           others: Sequence[Method] = ()) -> Decision[A]:
    """The one decider: run methods in order until one answers within its claim.

    ``auto`` (``auto=True``): each method of ``order`` (cheapest first, as the analysis' cost model
    ranks them) is skipped when its estimate passes the memory guard, tried, and kept only when its
    check passes; a refusal or a failed check moves on to the next, and the result's note says what
    was tried. ``auto`` never returns an answer that failed its check: when every method fails, it
    raises with the attempts.

    Methods and checks run with BLAS on one thread (:func:`vibss.threads.one_blas_thread`).

    A named method (``auto=False``, ``order`` of one) is guarded (a :class:`ResourceError` before
    allocating), run (its refusal propagates: the analysis' message names a method that works) and
    checked: a miss is a :class:`~vibss.errors.VibssWarning` with the measured bound, and the bound
    is in :meth:`Decision.note`.

    Parameters
    ----------
    order : sequence of Method
        Candidates, in the order to try them.
    run : callable
        ``run(method) -> answer``.
    where : str
        The public function, for messages.
    auto : bool
        Whether the user asked for ``"auto"``.
    check : callable
        ``check(method, answer) -> Check or None``: the a-posteriori check.
    cost : callable
        ``cost(method) -> Cost or None``: the estimate the memory guard reads.
    refusals : tuple of exception types
        What counts as a method refusing the problem (moves ``auto`` to the next method).
    others : sequence of Method
        Methods that also apply, named in a named method's refusal when their estimates fit.

    Returns
    -------
    Decision

    Raises
    ------
    ResourceError
        A named method over the memory guard, or every candidate of ``auto`` over it.
    AnalysisError
        Every candidate of ``auto`` refused or failed its check.
    """
    if not order:
        raise AnalysisError(f"{where}: no method applies to this problem")
    attempts: list[Attempt] = []
    budget = math.nan        # read once, and only when a method has an estimate (/proc/meminfo: 13 us)
    with one_blas_thread():             # small products: threads cost a time slice on a busy core (vibss.threads)
        for method in order:
            est = cost(method)
            if est is not None and math.isnan(budget):
                budget = MEMORY_FRACTION * available_memory()
            if est is not None and est.bytes > budget:
                if auto:
                    attempts.append(Attempt(method.name, "over the memory guard", f"estimated {_size(est.bytes)}"))
                    continue
                fits = [m.name for m in (*order, *others) if m is not method
                        and ((c := cost(m)) is None or c.bytes <= budget)]        # only on the way to a refusal
                guard(est, where=where, method=method.name, instead=fits)
            try:
                answer = run(method)
            except refusals as exc:
                if not auto:
                    raise
                attempts.append(Attempt(method.name, "refused", str(exc)))
                continue
            found = check(method, answer)
            if found is not None and not found.ok:
                if auto:
                    attempts.append(Attempt(method.name, "check failed", found.text()))
                    continue
                warnings.warn(f"{where}: method {method.name!r} missed its claim "
                              f"({method.claim.text() if method.claim else 'no claim'}): {found.text()}",
                              VibssWarning, stacklevel=3)
            attempts.append(Attempt(method.name, "answered"))
            return Decision(method, answer, found, tuple(attempts))
    tried = "; ".join(a.text() for a in attempts)
    if all(a.outcome == "over the memory guard" for a in attempts):
        raise ResourceError(f"{where}: every method would pass the memory guard: {tried}")
    raise AnalysisError(f"{where}: no method answered within its claim: {tried}")

