"""Reading one table of a model file: typed, unit-converted values and located errors.

:class:`Entry` wraps one table (``[[mount]]`` entry, ``[model]`` ...) with the text that locates it
(``"model.toml: mount[3] ('rear-left')"``) and the file's :class:`~vibss.model.units.Units`; its readers
check keys, types, shapes, finiteness and signs, convert to SI, and raise
:class:`~vibss.errors.ModelFileError` naming the entry, the key and what was expected.
Used by :mod:`vibss.io`.
"""

from __future__ import annotations

from collections.abc import Collection, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import ModelError, ModelFileError, did_you_mean
from ..model.geometry import DEFAULT_SEQUENCE, Orientation
from ..model.units import Units

__all__ = ["MISSING", "Entry", "numbers"]

MISSING: Any = object()
"""Default meaning "this key is required"."""


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
        return a * factor

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
            return Orientation.from_euler(e.array("euler", [(3,)], "angle"),
                                          e.string("sequence", DEFAULT_SEQUENCE))
        except ModelFileError:
            raise
        except ModelError as exc:
            raise self.fail(key, str(exc)) from None
