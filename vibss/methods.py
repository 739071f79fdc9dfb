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

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, TypeVar

from ._validate import choice
from .errors import ArgumentError

__all__ = ["Method", "resolve", "LARGE_DOFS", "SIMULATE_LARGE_DOFS"]

LARGE_DOFS = 3000
"""The large-model threshold [DOF]: above it an analysis of a Model keeps the model sparse instead of
computing every undamped mode densely. The measured crossover: the dense eigen-analysis of all the
modes is O(n^3) (a 20-frequency FRF at 6,000 DOF took 203 s, and the sparse path 0.17 s, the same
answer; docs/performance.md), while below a few thousand DOF the dense modes cost seconds and buy the
grid around the modes, the resonance marks and the modal methods. The frequency response's sparse
path is exact, so :func:`vibss.frequency_response` switches here (:func:`vibss.frequency.methods.stays_sparse`)."""

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

    Calling a Method calls its kernel, so ``METHODS["direct"](plant, s)`` keeps working.
    """

    name: str
    kernel: Callable[..., Any]
    exact: bool = False
    fallback: str | None = None
    summary: str = ""
    internal_states: bool = False

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
