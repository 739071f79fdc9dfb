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
vibss.errors.ArgumentError: simulate: dt: expected a finite number > 0 [s], got -1.0
>>> choice("modall", "method", ["auto", "modal", "direct"])
Traceback (most recent call last):
...
vibss.errors.ArgumentError: method: unknown 'modall' (did you mean 'modal'?); expected one of ['auto', 'modal', 'direct']
"""

from __future__ import annotations

import math
import os
import stat
from collections.abc import Iterable, Sequence
from typing import Any

import numpy as np

from .errors import ArgumentError, ModelError, SignalError, did_you_mean

__all__ = ["prefix", "is_numeric", "array", "vector", "number", "integer", "choice", "name_index",
           "read_regular_file", "regular_file"]


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
    if a.dtype.kind == "O" and a.ndim and a.size:   # 0-d object: a non-numeric scalar (a callable
        return all(is_numeric(v) for v in a.ravel())  # would otherwise recurse into itself)
    return False


def _describe(shape: Sequence[int | None]) -> str:
    if len(shape) == 1 and shape[0] is not None:
        return f"{shape[0]} numbers"
    dims = ", ".join("n" if d is None else str(d) for d in shape)
    return f"an array of numbers of shape ({dims}{',' if len(shape) == 1 else ''})"


def array(value: Any, argument: str, shape: Sequence[int | None] | None = None, *, who: str = "",
          unit: str = "", finite: bool = True, strict: bool = True, hint: str = "",
          what: str | None = None) -> np.ndarray:
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
    hint : str
        More on what is expected (``"(6 per body)"``), shown after it.
    what : str or None
        What is expected, in place of the description made from ``shape`` and ``hint``.

    Returns
    -------
    ndarray
    """
    where = prefix(argument, who)
    want = what or (_describe(shape) if shape is not None else "numbers") + (f" {hint}" if hint else "")
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
           strict: bool = True, hint: str = "", what: str | None = None) -> np.ndarray:
    """``value`` as ``n`` finite numbers (a new (n,) float array); see :func:`array`."""
    return array(value, argument, (n,), who=who, unit=unit, strict=strict, hint=hint, what=what)


def number(value: Any, argument: str, *, who: str = "", minimum: float | None = None,
           strict: bool = False, unit: str = "", what: str | None = None, must: str | None = None) -> float:
    """``value`` as a finite float, optionally ``>= minimum`` (``> minimum`` when ``strict``).

    Bools and strings are refused (``float("1e-3")`` would accept a string).

    Parameters
    ----------
    value : object
        What was received.
    argument, who : str
        Its name and owner, for the message.
    minimum : float or None
        Lower bound.
    strict : bool
        The bound itself is refused.
    unit : str
        SI unit shown in the message.
    what : str or None
        What is expected (``"a number of seconds"``), in place of ``"a finite number >= minimum [unit]"``.
    must : str or None
        For a number out of range: ``"<argument>: must be <must>, got ..."`` (default: as for
        anything else, ``"expected <what>, got ..."``).
    """
    where = prefix(argument, who)
    bound = "" if minimum is None else f" {'>' if strict else '>='} {minimum:g}"
    want = what or ("a finite number" + bound + (f" [{unit}]" if unit else ""))
    x = math.nan
    if not isinstance(value, (bool, np.bool_, str, bytes)):
        try:
            x = float(value)
        except (TypeError, ValueError):
            pass
    if not math.isfinite(x):
        raise ArgumentError(f"{where}: expected {want}, got {value!r}", argument=argument,
                            received=value, expected=want)
    if minimum is not None and (x < minimum or (strict and x == minimum)):
        text = f"must be {must}" if must else f"expected {want}"
        raise ArgumentError(f"{where}: {text}, got {value!r}", argument=argument, received=value,
                            expected=must or want)
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
           callable_ok: bool = False, expected: str | None = None) -> Any:
    """``value`` if it is one of ``options`` (or callable, with ``callable_ok``); else an
    :class:`~vibss.errors.ArgumentError` listing the options, with a did-you-mean.

    The message is ``"<argument>: unknown <value> (did you mean ...?); expected one of [...]"``, or,
    with ``expected`` (``"'log' or 'linear'"``), ``"<argument>: expected <expected>, got <value>
    (did you mean ...?)"``.
    """
    opts = list(options)
    if (callable_ok and callable(value)) or (isinstance(value, str) and value in opts) \
            or (not isinstance(value, str) and any(value is o for o in opts)):
        return value
    hint = did_you_mean(value, opts) if isinstance(value, str) else ""
    more = " or a callable" if callable_ok else ""
    text = (f"expected {expected}{more}, got {value!r}{hint}" if expected
            else f"unknown {value!r}{hint}; expected one of {opts}{more}")
    raise ArgumentError(f"{prefix(argument, who)}: {text}", argument=argument, received=value,
                        expected=tuple(opts))


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


def read_regular_file(path: str | os.PathLike[str], limit: int, what: str = "file", who: str = "") -> bytes:
    """The bytes of a regular file of at most ``limit`` bytes, or a :class:`~vibss.errors.ModelError`.

    A device (``/dev/zero``), a FIFO, a socket or a directory is refused before it is opened (reading
    one would hang or never end), symbolic links are resolved and their target is checked, and at
    most ``limit + 1`` bytes are ever read (a file that grows while it is read is refused too).

    Parameters
    ----------
    path : str or PathLike
        The file.
    limit : int
        Largest accepted size [bytes] (the caller's module constant, named in its docs).
    what : str
        What the file is, for messages (``"table file"``).
    who : str
        How messages start (default: ``what`` and the quoted path).

    Returns
    -------
    bytes

    Examples
    --------
    >>> read_regular_file("/dev/zero", 1000, "table file")
    Traceback (most recent call last):
    ...
    vibss.errors.ModelError: table file '/dev/zero': not a regular file (a character device); expected a text file
    """
    name = os.fspath(path)
    who = who or f"{what} {name!r}"
    real = regular_file(path, limit, what, who)
    too_big = (f"{who}: larger than the limit of {limit:,} bytes "
               f"({{size:,}} bytes)")
    try:
        with open(real, "rb") as f:
            data = f.read(limit + 1)
    except OSError as exc:
        raise ModelError(f"{who}: cannot read the file ({exc.strerror or exc})", argument=what,
                         received=name) from None
    if len(data) > limit:
        raise ModelError(too_big.format(size=len(data)), argument=what, received=name,
                         expected=f"at most {limit} bytes")
    return data


def regular_file(path: str | os.PathLike[str], limit: int, what: str = "file", who: str = "") -> str:
    """The resolved path of a regular file of at most ``limit`` bytes (checked without opening it),
    or the :class:`~vibss.errors.ModelError` of :func:`read_regular_file`.

    Parameters
    ----------
    path : str or PathLike
        The file.
    limit : int
        Largest accepted size [bytes].
    what, who : str
        As :func:`read_regular_file`.

    Examples
    --------
    >>> regular_file("/tmp", 10, "table file")
    Traceback (most recent call last):
    ...
    vibss.errors.ModelError: table file '/tmp': not a regular file (a directory); expected a text file
    """
    name = os.fspath(path)
    who = who or f"{what} {name!r}"
    try:
        real = os.path.realpath(name)
        info = os.stat(real)
    except (OSError, ValueError) as exc:
        raise ModelError(f"{who}: cannot read the file ({getattr(exc, 'strerror', None) or exc})",
                         argument=what, received=name) from None
    if not stat.S_ISREG(info.st_mode):
        kind = ("a directory" if stat.S_ISDIR(info.st_mode) else "a character device" if stat.S_ISCHR(info.st_mode)
                else "a block device" if stat.S_ISBLK(info.st_mode) else "a FIFO"
                if stat.S_ISFIFO(info.st_mode) else "a socket" if stat.S_ISSOCK(info.st_mode) else "not a file")
        via = f" (a link to {real!r})" if real != os.path.abspath(name) else ""
        raise ModelError(f"{who}{via}: not a regular file ({kind}); expected a text file",
                         argument=what, received=name)
    if info.st_size > limit:
        raise ModelError(f"{who}: larger than the limit of {limit:,} bytes ({info.st_size:,} bytes)",
                         argument=what, received=name, expected=f"at most {limit} bytes")
    return real
