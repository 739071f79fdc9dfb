"""Exceptions raised by vibss.

Every exception subclasses both :class:`VibssError` (catch everything from vibss) and the
built-in it behaves like, so ``except ValueError`` keeps working for callers that do not know
about vibss. Each carries its data where it has any: ``argument`` (the argument, key or signal
that was wrong), ``received`` (what was given) and ``expected`` (what would have been accepted);
all are None when not meaningful. Errors pickle with their message and data (for
multiprocessing and notebooks' parallel runners).

Examples
--------
>>> import pickle
>>> err = ArgumentError("method: unknown 'modall'", argument="method", received="modall",
...                     expected=("auto", "modal"))
>>> back = pickle.loads(pickle.dumps(err))
>>> str(back), back.argument, back.received, isinstance(back, ValueError)
("method: unknown 'modall'", 'method', 'modall', True)
"""

from __future__ import annotations

import difflib
import pickle
from collections.abc import Iterable
from typing import Any

__all__ = ["VibssError", "ModelError", "ArgumentError", "SignalError", "SignalIndexError",
           "ArgumentTypeError", "AnalysisError",
           "DefectiveModesError", "ControlDesignError", "ResourceError", "ModelFileError", "MissingDependencyError", "VibssWarning",
           "did_you_mean"]


class VibssError(Exception):
    """Base class of every error vibss raises on purpose.

    Parameters
    ----------
    message : str
        The full message (it names the argument and shows what was received).
    argument : str or None
        The argument, key, body, mount or signal that was wrong.
    received : object
        What was given (None when not meaningful).
    expected : object
        What would have been accepted (a description or the valid names), or None.
    """

    def __init__(self, message: str = "", *, argument: str | None = None, received: Any = None,
                 expected: Any = None) -> None:
        super().__init__(message)
        self.argument = argument
        self.received = received
        self.expected = expected

    def __str__(self) -> str:
        # the plain message, also where a built-in twin (KeyError) would quote it
        return str(self.args[0]) if len(self.args) == 1 else super().__str__()

    def __reduce__(self) -> tuple[Any, ...]:
        state = {}
        for key, value in self.__dict__.items():
            try:
                pickle.dumps(value)
            except Exception:       # e.g. a lambda received: keep its text
                value = repr(value)
            state[key] = value
        return (type(self), self.args, state)


class ModelError(VibssError, ValueError):
    """Invalid model data: the message names the entity, the key and what was wrong."""


class ArgumentError(ModelError):
    """A bad argument to a vibss function: wrong type, shape, value, or an unknown name
    (a method, a quantity, an option). A :class:`ModelError` (so a ``ValueError``) too."""


class SignalError(ArgumentError, KeyError):
    """An unknown signal, output, input, section or label name (with did-you-mean). Also a
    ``KeyError``, as ``result['engine.z']`` is a lookup."""


class SignalIndexError(SignalError, IndexError):
    """A signal or label index out of range. Also an ``IndexError``."""


class ArgumentTypeError(ArgumentError, TypeError):
    """An argument of the wrong kind (e.g. an index that is neither a name nor a number). Also a
    ``TypeError``."""


class ModelFileError(ModelError):
    """Invalid model file: the message also names the file (and line, for syntax errors)."""


class AnalysisError(VibssError, RuntimeError):
    """An analysis cannot give a meaningful answer (e.g. a load the mounts do not restrain)."""


class DefectiveModesError(AnalysisError):
    """Complex modes refused: the eigenvectors are nearly dependent (critically damped or defective
    modes), so a modal sum would lose accuracy. ``method="auto"`` then uses a direct method."""


class ControlDesignError(AnalysisError):
    """A control plant, design or closed loop is refused: an uncontrollable or unobservable unstable
    mode, a rank-deficient channel, an ill-posed or unstable loop. The message names the channel."""


class ResourceError(AnalysisError, MemoryError):
    """A method would need more memory (or time) than its guard allows; raised before allocating,
    with the estimate in the message and a method that fits."""


class MissingDependencyError(VibssError, ImportError):
    """An optional dependency is not installed; the message names the extra that brings it
    (``pip install vibss[pandas]``)."""


class VibssWarning(UserWarning):
    """A method is expected to lose accuracy or fail here; the message names the cause and the fix."""


def did_you_mean(name: Any, options: Iterable[Any]) -> str:
    """`` (did you mean 'x'?)`` for the closest of ``options`` to ``name``, or an empty string.

    Examples
    --------
    >>> did_you_mean("engin", ["engine", "frame"])
    " (did you mean 'engine'?)"
    """
    close = difflib.get_close_matches(str(name), [str(o) for o in options], n=1)
    return f" (did you mean {close[0]!r}?)" if close else ""
