"""Shared argument validators: one check per kind of argument, one message style.

Every validator takes the argument's name (``argument``) and, optionally, who owns it (``who``:
``"body 'engine'"``, ``"simulate"``), and raises :class:`~vibss.errors.ArgumentError` (a
:class:`~vibss.errors.ModelError`, so a ``ValueError``) whose message starts with
``"<who>: <argument>: "``, says what was expected and shows what was received; the error carries
``argument``, ``received`` and ``expected``. Unknown names get a did-you-mean
(:func:`~vibss.errors.did_you_mean`) and raise :class:`~vibss.errors.SignalError` when they name
signals or labels.

Examples
--------
>>> vector([1, 2, 3], 3, "cog", who="body 'b'")
array([1., 2., 3.])
>>> number(-1.0, "dt", who="simulate", minimum=0.0, strict=True, unit="s")
Traceback (most recent call last):
...
vibss.errors.ArgumentError: simulate: dt: expected a number > 0 [s], got -1.0
>>> choice("modall", "method", ["auto", "modal", "direct"])
Traceback (most recent call last):
...
vibss.errors.ArgumentError: method: unknown 'modall' (did you mean 'modal'?); expected one of ['auto', 'modal', 'direct']
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from typing import Any

import numpy as np

from .errors import ArgumentError, SignalError, did_you_mean

__all__ = ["prefix", "is_numeric", "array", "vector", "number", "integer", "choice", "name_index"]


def prefix(argument: str, who: str = "") -> str:
    """``"<who>: <argument>"`` (or the argument alone): how every message starts."""
    return f"{who}: {argument}" if who else argument


def is_numeric(value: Any) -> bool:
    """True for a number or (nested) sequence of numbers; bools, strings and None are not.

    Examples
    --------
    >>> is_numeric([1, 2.5]), is_numeric([True, 1.0]), is_numeric("3")
    (True, False, False)
    """
    if isinstance(value, (str, bytes, bool, np.bool_)) or value is None:
        return False
    if isinstance(value, (list, tuple)):        # numpy would upcast [True, 1.0] to floats
        return all(is_numeric(v) for v in value)
    try:
        a = np.asarray(value)
    except (TypeError, ValueError):
        return False
    if a.dtype.kind in "iuf":
        return True
    if a.dtype.kind == "O" and a.size:
        return all(is_numeric(v) for v in a.ravel())
    return False


def _describe(shape: Sequence[int | None]) -> str:
    if len(shape) == 1 and shape[0] is not None:
        return f"{shape[0]} numbers"
    dims = ", ".join("n" if d is None else str(d) for d in shape)
    return f"an array of numbers of shape ({dims}{',' if len(shape) == 1 else ''})"


def array(value: Any, argument: str, shape: Sequence[int | None] | None = None, *, who: str = "",
          unit: str = "", finite: bool = True, strict: bool = True) -> np.ndarray:
    """``value`` as a new float array, checked for shape and finiteness.

    Parameters
    ----------
    value : array_like
        What was received.
    argument : str
        Its name, for the message.
    shape : sequence of int or None, optional
        Required shape; None in a place accepts any length there. Default: any shape.
    who : str
        Owner of the argument (body, mount, function), for the message.
    unit : str
        SI unit shown in the message.
    finite : bool
        Refuse NaN and infinity.
    strict : bool
        Refuse bools and strings (numpy would read ``True`` as 1 and ``"3"`` as 3).

    Returns
    -------
    ndarray
    """
    where = prefix(argument, who)
    want = _describe(shape) if shape is not None else "numbers"
    tail = f" [{unit}]" if unit else ""
    if strict and not is_numeric(value):
        raise ArgumentError(f"{where}: expected {want}{tail}, got {value!r}", argument=argument,
                            received=value, expected=want)
    try:
        a = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise ArgumentError(f"{where}: expected {want}{tail}, got {value!r}", argument=argument,
                            received=value, expected=want) from None
    if shape is not None and (a.ndim != len(shape)
                              or any(d is not None and d != s for d, s in zip(shape, a.shape))):
        raise ArgumentError(f"{where}: expected {want}{tail}, got shape {a.shape} ({value!r})",
                            argument=argument, received=value, expected=want)
    if finite and not np.all(np.isfinite(a)):
        raise ArgumentError(f"{where}: values must be finite, got {a.tolist()}", argument=argument,
                            received=value, expected=f"finite {want}")
    return a


def vector(value: Any, n: int, argument: str, *, who: str = "", unit: str = "",
           strict: bool = True) -> np.ndarray:
    """``value`` as ``n`` finite numbers (a new (n,) float array); see :func:`array`."""
    return array(value, argument, (n,), who=who, unit=unit, strict=strict)


def number(value: Any, argument: str, *, who: str = "", minimum: float | None = None,
           strict: bool = False, unit: str = "", what: str = "a number") -> float:
    """``value`` as a finite float, optionally ``>= minimum`` (``> minimum`` when ``strict``).

    Bools and strings are refused (``float("1e-3")`` would accept a string).
    """
    where = prefix(argument, who)
    bound = "" if minimum is None else f" {'>' if strict else '>='} {minimum:g}"
    want = f"{what}{bound}" + (f" [{unit}]" if unit else "")
    x = math.nan
    if not isinstance(value, (bool, np.bool_, str, bytes)):
        try:
            x = float(value)
        except (TypeError, ValueError):
            pass
    if not math.isfinite(x) or (minimum is not None and (x < minimum or (strict and x == minimum))):
        raise ArgumentError(f"{where}: expected {want}, got {value!r}", argument=argument,
                            received=value, expected=want)
    return x


def integer(value: Any, argument: str, *, who: str = "", minimum: int = 1) -> int:
    """``value`` as an int ``>= minimum`` (integral floats such as ``10.0`` accepted, bools not)."""
    where = prefix(argument, who)
    want = f"an integer >= {minimum}"
    ok = isinstance(value, (int, np.integer)) or (isinstance(value, (float, np.floating))
                                                 and float(value).is_integer())
    if isinstance(value, (bool, np.bool_)) or not ok or value < minimum:
        raise ArgumentError(f"{where}: expected {want}, got {value!r}", argument=argument,
                            received=value, expected=want)
    return int(value)


def choice(value: Any, argument: str, options: Iterable[Any], *, who: str = "",
           callable_ok: bool = False) -> Any:
    """``value`` if it is one of ``options`` (or callable, with ``callable_ok``); else an
    :class:`~vibss.errors.ArgumentError` listing the options, with a did-you-mean."""
    opts = list(options)
    if (callable_ok and callable(value)) or (isinstance(value, str) and value in opts) \
            or (not isinstance(value, str) and any(value is o for o in opts)):
        return value
    hint = did_you_mean(value, opts) if isinstance(value, str) else ""
    more = " or a callable" if callable_ok else ""
    raise ArgumentError(f"{prefix(argument, who)}: unknown {value!r}{hint}; expected one of {opts}{more}",
                        argument=argument, received=value, expected=tuple(opts))


def name_index(name: Any, names: Sequence[str], argument: str, *, who: str = "") -> int:
    """Position of ``name`` in ``names``; a :class:`~vibss.errors.SignalError` with did-you-mean
    and the valid names otherwise.

    Examples
    --------
    >>> name_index("b.z", ("b.x", "b.z"), "output")
    1
    """
    if isinstance(name, str) and name in names:
        return list(names).index(name)
    hint = did_you_mean(name, names) if isinstance(name, str) else ""
    raise SignalError(f"{prefix(argument, who)}: no {argument} named {name!r}{hint}; the {argument}s are "
                      f"{list(names)}", argument=argument, received=name, expected=tuple(names))
