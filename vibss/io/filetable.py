"""Reading one table of a model file: typed, unit-converted values and located errors.

:class:`Entry` wraps one table (``[[mount]]`` entry, ``[model]`` ...) with the text that locates it
(``"model.toml: mount[3] ('rear-left')"``) and the file's :class:`~vibss.model.units.Units`; its readers
check keys, types, shapes, finiteness and signs, convert to SI, and raise
:class:`~vibss.errors.ModelFileError` naming the entry, the key and what was expected.
Used by :mod:`vibss.io`.
"""

from __future__ import annotations

import json
import re
import tomllib
from collections.abc import Collection, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import ModelError, ModelFileError, did_you_mean
from ..model.geometry import DEFAULT_SEQUENCE, Orientation
from ..model.units import Units

__all__ = ["MISSING", "Entry", "numbers", "parse_text", "check_tree", "MAX_DEPTH", "MAX_INT_DIGITS", "PLAUSIBLE",
           "MAX_EULER_RAD"]

MISSING: Any = object()
"""Default meaning "this key is required"."""


MAX_DEPTH = 24
"""Deepest nesting of tables and arrays a model file may have (the format needs fewer than 10)."""

MAX_INT_DIGITS = 30
"""Most digits an integer of a model file may have (larger numbers are written as floats, ``1e40``)."""


from ..model.limits import MAX_EULER_RAD, PLAUSIBLE  # noqa: E402  (one definition for files and API)


class _Duplicates(dict):  # type: ignore[type-arg]
    """A JSON object that named a key more than once (``duplicates``); refused by :func:`check_tree`."""

    duplicates: list[str]


def _object(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    out = dict(pairs)
    if len(out) < len(pairs):
        seen: set[str] = set()
        dup = [k for k, _ in pairs if k in seen or seen.add(k)]  # type: ignore[func-returns-value]
        marked = _Duplicates(out)
        marked.duplicates = dup
        return marked
    return out


class _HugeInt:
    """An integer of a JSON file with more than :data:`MAX_INT_DIGITS` digits (refused by :func:`check_tree`)."""

    def __init__(self, text: str) -> None:
        self.digits = len(text.lstrip("-"))


def _int(text: str) -> Any:
    return _HugeInt(text) if len(text.lstrip("-")) > MAX_INT_DIGITS else int(text)


def parse_text(text: str, fmt: str, source: str) -> Any:
    """The data of a model file's text (TOML or JSON), checked by :func:`check_tree`.

    A UTF-8 byte-order mark is skipped; JSON keys given twice, integers of more than
    :data:`MAX_INT_DIGITS` digits and nesting deeper than :data:`MAX_DEPTH` are refused with a
    :class:`~vibss.errors.ModelFileError` naming ``source``, the entry and the key (never a
    ``RecursionError``, ``OverflowError`` or Python's integer-digit limit).

    Parameters
    ----------
    text : str
        The file's contents.
    fmt : {"toml", "json"}
    source : str
        The file name, for messages.

    Examples
    --------
    >>> parse_text('{"body": [{"mass": 1, "mass": 2}]}', "json", "m.json")
    Traceback (most recent call last):
    ...
    vibss.errors.ModelFileError: m.json: body[1]: mass: key given more than once (JSON keys must be unique)
    """
    text = text.removeprefix("\ufeff")
    deep = f"{source}: tables or arrays nested deeper than {MAX_DEPTH} levels; a model file needs fewer than 10"
    if fmt == "toml":
        try:
            data = tomllib.loads(text)
        except tomllib.TOMLDecodeError as exc:
            raise ModelFileError(f"{source}: TOML syntax error: {exc}") from None
        except RecursionError:
            raise ModelFileError(deep) from None
        except ValueError:      # Python's limit on the digits of an integer
            m = re.search(r"\d[\d_]{%d,}" % MAX_INT_DIGITS, text)
            line = text.count("\n", 0, m.start()) + 1 if m else 0
            raise ModelFileError(f"{source}: line {line}: an integer with more than {MAX_INT_DIGITS} digits; "
                                 "write large numbers as floats (1e40)") from None
    elif fmt == "json":
        try:
            data = json.loads(text, object_pairs_hook=_object, parse_int=_int)
        except json.JSONDecodeError as exc:
            raise ModelFileError(f"{source}: JSON syntax error: {exc.msg} "
                                 f"(at line {exc.lineno}, column {exc.colno})") from None
        except RecursionError:
            raise ModelFileError(deep) from None
    else:
        raise ModelFileError(f"{source}: unknown format {fmt!r}; expected 'toml' or 'json'")
    check_tree(data, source)
    return data


def check_tree(data: Any, source: str) -> None:
    """Refuse what no model file means before any table is read (see :func:`parse_text`).

    Parameters
    ----------
    data : object
        Parsed model-file data.
    source : str
        The file name, for messages.
    """
    stack: list[tuple[Any, tuple[str, ...], int]] = [(data, (), 0)]
    while stack:
        node, where, depth = stack.pop()
        here = ": ".join((source,) + where)
        if depth > MAX_DEPTH:
            raise ModelFileError(f"{here}: tables or arrays nested deeper than {MAX_DEPTH} levels; "
                                 "a model file needs fewer than 10")
        if isinstance(node, _HugeInt) or (isinstance(node, int) and not isinstance(node, bool)
                                          and abs(node) >= 10 ** MAX_INT_DIGITS):
            digits = node.digits if isinstance(node, _HugeInt) else len(str(abs(node)))
            raise ModelFileError(f"{here}: an integer with {digits} digits; at most {MAX_INT_DIGITS} "
                                 "(write large numbers as floats: 1e40)")
        if isinstance(node, Mapping):
            dup = getattr(node, "duplicates", None)
            if dup:
                raise ModelFileError(f"{here}: {dup[0]}: key given more than once (JSON keys must be unique)")
            for k, v in node.items():
                stack.append((v, where + (str(k),), depth + 1))
        elif isinstance(node, list):
            for i, v in enumerate(node, start=1):
                if len(where) == 1 and isinstance(v, Mapping):     # [[body]] tables: body[2] ('engine')
                    name = v.get("name")
                    label = f"{where[0]}[{i}]" + (f" ({name!r})" if isinstance(name, str) else "")
                    stack.append((v, (label,), depth + 1))
                else:
                    stack.append((v, where[:-1] + (f"{where[-1] if where else ''}[{i}]",), depth + 1))


def numbers(value: Any) -> np.ndarray | None:
    """``value`` as a float array if it is a number or a (nested) list of numbers, else None."""
    if isinstance(value, bool):
        return None
    if isinstance(value, (int, float)):
        return np.array(float(value))
    if isinstance(value, (list, tuple)):
        items = [numbers(v) for v in value]
        if any(i is None for i in items):
            return None
        try:
            return np.array(items, dtype=float)
        except ValueError:  # ragged
            return None
    return None


def _shape_text(shape: tuple[int, ...]) -> str:
    if shape == ():
        return "a number"
    if len(shape) == 1:
        return f"{shape[0]} numbers"
    return "a " + "x".join(map(str, shape)) + " array of numbers"


@dataclass(frozen=True)
class Entry:
    """One table of a model file.

    Parameters
    ----------
    data : mapping
        The table as read (never modified).
    where : str
        Its location for error messages, e.g. ``"m.toml: mount[3] ('rear-left')"``.
    units : Units
        The units its numbers are written in.
    """

    data: Mapping[str, Any]
    where: str
    units: Units

    def fail(self, key: str | None, message: str) -> ModelFileError:
        return ModelFileError(f"{self.where}: {key}: {message}" if key else f"{self.where}: {message}")

    def check_keys(self, allowed: Sequence[str], required: Sequence[str] = ()) -> None:
        for key in self.data:
            if key not in allowed:
                raise self.fail(key, f"unknown key; expected some of {list(allowed)}"
                                + did_you_mean(key, allowed))
        for key in required:
            if key not in self.data:
                raise self.fail(key, "missing (required)")

    def __contains__(self, key: str) -> bool:
        return key in self.data

    def string(self, key: str, default: Any = MISSING, choices: Collection[str] | None = None) -> Any:
        value = self.data.get(key, default)
        if value is MISSING:
            raise self.fail(key, "missing (required)")
        if value is default and default is not MISSING:
            return value
        if not isinstance(value, str) or not value:
            raise self.fail(key, f"expected a non-empty string, got {value!r}")
        if choices is not None and value not in choices:
            raise self.fail(key, f"expected one of {list(choices)}, got {value!r}"
                            + did_you_mean(value, choices))
        return value

    def array(self, key: str, shapes: Sequence[tuple[int, ...]], quantity: str | Sequence[str],
              default: Any = MISSING, *, positive: bool = False, nonnegative: bool = False) -> Any:
        """Numbers of one of ``shapes``, converted from the file's units of ``quantity`` to SI."""
        value = self.data.get(key, default)
        if value is MISSING:
            raise self.fail(key, "missing (required)")
        if value is default and default is not MISSING:
            return value
        if isinstance(quantity, str):
            label, factor = self.units.label(quantity), np.asarray(self.units.factor(quantity))
        else:
            label = ", ".join(self.units.label(q) for q in quantity)
            factor = np.array([self.units.factor(q) for q in quantity])
        a = numbers(value)
        if a is None or a.shape not in shapes:
            expected = " or ".join(_shape_text(s) for s in shapes)
            raise self.fail(key, f"expected {expected} [{label}], got {value!r}")
        if not np.all(np.isfinite(a)):
            raise self.fail(key, f"values must be finite, got {value!r}")
        if positive and np.any(a <= 0):
            raise self.fail(key, f"must be positive, got {value!r} [{label}]")
        if nonnegative and np.any(a < 0):
            raise self.fail(key, f"must not be negative, got {value!r} [{label}]")
        with np.errstate(over="ignore"):
            out = a * factor
        if not np.all(np.isfinite(out)):
            raise self.fail(key, f"{value!r} [{label}] overflows when converted to SI")
        if isinstance(quantity, str) and quantity in PLAUSIBLE:
            self._plausible(key, value, out, quantity, label, float(factor), positive)
        return out

    def _plausible(self, key: str, value: Any, si: np.ndarray, quantity: str, label: str, factor: float,
                   positive: bool) -> None:
        lo, hi = PLAUSIBLE[quantity]
        size = np.abs(si)
        low = (positive or quantity == "stiffness") and bool(np.any((size > 0) & (size < lo)))
        if low or bool(np.any(size > hi)):
            lower = f"{lo / factor:g}" if positive or quantity == "stiffness" else "0"
            raise self.fail(key, f"{value!r} [{label}] is outside what a rigid-body mount model means: "
                            f"{quantity} magnitudes from {lower} to {hi / factor:g} [{label}]")

    def number(self, key: str, quantity: str = "dimensionless", default: Any = MISSING,
               **checks: bool) -> Any:
        a = self.array(key, [()], quantity, default, **checks)
        return a if a is default else float(a)

    def table(self, key: str) -> Mapping[str, Any] | None:
        value = self.data.get(key)
        if value is not None and not isinstance(value, Mapping):
            raise self.fail(key, f"expected a table {{ ... }}, got {value!r}")
        return value

    def sub(self, key: str) -> Entry | None:
        value = self.table(key)
        return None if value is None else Entry(value, f"{self.where}: {key}", self.units)

    def orientation(self, key: str) -> Orientation | None:
        e = self.sub(key)
        if e is None:
            return None
        e.check_keys(("euler", "sequence", "matrix"))
        if ("euler" in e) == ("matrix" in e):
            raise self.fail(key, "expected { euler = [a, b, c], sequence = \"ZYX\" } or "
                            "{ matrix = [[...], [...], [...]] } (columns = local axes)")
        try:
            if "matrix" in e:
                if "sequence" in e:
                    raise e.fail("sequence", "only applies to euler angles")
                return Orientation(e.array("matrix", [(3, 3)], "dimensionless"))
            angles = e.array("euler", [(3,)], "angle")
            if np.any(np.abs(angles) > MAX_EULER_RAD * (1 + 1e-12)):
                turn = MAX_EULER_RAD / self.units.factor("angle")
                raise e.fail("euler", f"angles must lie within +-{turn:g} [{self.units.label('angle')}] "
                             f"(one turn), got {e.data['euler']!r}")
            return Orientation.from_euler(angles, e.string("sequence", DEFAULT_SEQUENCE))
        except ModelFileError:
            raise
        except ModelError as exc:
            raise self.fail(key, str(exc)) from None
