"""Excitations: what a time function drives, and building both from model-file data.

An :class:`Excitation` applies a time function (:mod:`vibss.timefunctions`, re-exported here) as a
force or moment on a body, or as a prescribed displacement, velocity or acceleration of a DOF of a
body or of ground; its :attr:`~Excitation.signal` is the name of the plant input it feeds.
:func:`function_from_dict` builds a validated time function from plain data (a model file's
``function`` table), converting units.

Examples
--------
>>> pulse = HalfSine(amplitude=1000.0, start=0.01, duration=0.02)
>>> e = Excitation("shock", "force", "engine", pulse, dof="z")
>>> e.signal, e.unit
('engine.fz', 'N')
>>> float(e.value(0.02))
1000.0
"""

from __future__ import annotations

import dataclasses
import math
from functools import cached_property
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, ClassVar

import numpy as np
import numpy.typing as npt

from .._validate import choice, read_regular_file, regular_file, vector
from ..errors import ModelError, did_you_mean
from ._common import unit_direction
from .model import DOF_NAMES, GROUND
from ..linear.plant.plant import INPUT_KINDS
from .timefunctions import (FUNCTIONS, HalfSine, Haversine, Ramp, Rectangular, Sawtooth, Sine,
                            SineSweep, Step, Sum, Table, TimeFunction, Triangle)
from .units import Units

__all__ = [
    "TimeFunction", "Step", "Rectangular", "HalfSine", "Haversine", "Triangle", "Sawtooth",
    "Ramp", "Sine", "SineSweep", "Table", "Sum", "FUNCTIONS", "function_from_dict",
    "read_table_file", "MAX_TABLE_FILE_BYTES", "TableFile", "Excitation", "amplitude_quantity",
]

_MOTION_SUFFIX = {"displacement": "disp", "velocity": "vel", "acceleration": "acc"}


MAX_TABLE_FILE_BYTES = 32 * 2**20
"""Largest table file :func:`read_table_file` reads [bytes] (32 MiB: about a million rows)."""


def read_table_file(path: str | Path) -> tuple[np.ndarray, np.ndarray]:
    """Read a two-column (time, value) text file: comma, semicolon, tab or space separated.

    Blank lines and lines starting with ``#`` are skipped, and so is a first line that is not
    numeric (a header). Values are returned as written (no unit conversion). The file must be a
    regular file (symbolic links are followed and their target checked; a device, FIFO or folder
    is refused before it is opened) of at most :data:`MAX_TABLE_FILE_BYTES`; a UTF-8 byte-order
    mark is accepted.

    Parameters
    ----------
    path : str or Path
        The file.

    Returns
    -------
    time, value : (k,) ndarray
    """
    path = Path(path)
    raw = read_regular_file(path, MAX_TABLE_FILE_BYTES, "table file")
    try:
        lines = raw.decode("utf-8-sig").splitlines()
    except UnicodeDecodeError as exc:
        raise ModelError(f"table file {str(path)!r}: not UTF-8 text ({exc.reason} at byte {exc.start})") from None
    rows: list[tuple[float, float]] = []
    first = True
    for n, line in enumerate(lines, start=1):
        text = line.strip()
        if not text or text.startswith("#"):
            continue
        parts = text.replace(",", " ").replace(";", " ").split()
        is_first, first = first, False
        read = [_table_number(p) for p in parts]
        numbers = [x for x in read if x is not None]
        if len(numbers) < len(read):
            if is_first:
                continue  # a header line
            raise ModelError(f"table file {str(path)!r}: line {n}: expected two numbers, "
                             f"got {text!r}")
        if len(numbers) != 2:
            raise ModelError(f"table file {str(path)!r}: line {n}: expected two columns (time, value), "
                             f"got {len(numbers)}")
        rows.append((numbers[0], numbers[1]))
    if not rows:
        raise ModelError(f"table file {str(path)!r}: no data")
    data = np.array(rows)
    return data[:, 0], data[:, 1]


@dataclass(frozen=True, eq=False)
class TableFile(TimeFunction):
    """A :class:`Table` kept in a two-column text file, read on first use.

    A model file's ``function = { type = "table", file = "rec.csv" }``. Loading the model only
    checks that the file is a regular file within :data:`MAX_TABLE_FILE_BYTES`; the numbers are
    read (by :func:`read_table_file`) when an analysis first asks for a value, so ``vibss modes``
    never reads an excitation's table. Errors in the file's contents are then raised as a
    :class:`~vibss.errors.ModelError` naming the model file's entry (``who``).

    Parameters
    ----------
    file : str
        Path of the file.
    extrapolate : {"zero", "hold"}
        As :class:`Table`.
    time_scale, value_scale : float
        SI value of one unit of the file's times and values.
    who : str
        Prefix of error messages (the model file's entry).

    Examples
    --------
    >>> import tempfile, os
    >>> with tempfile.NamedTemporaryFile("w", suffix=".csv", delete=False) as f:
    ...     _ = f.write("0, 0\\n1, 10\\n")
    >>> TableFile(f.name).value([0.5]).tolist()
    [5.0]
    >>> os.remove(f.name)
    """

    type: ClassVar[str] = "table"
    roles: ClassVar[dict[str, str]] = {"file": "text", "extrapolate": "text"}
    file: str
    extrapolate: str = "zero"
    time_scale: float = 1.0
    value_scale: float = 1.0
    who: str = field(default="", compare=False)

    def __post_init__(self) -> None:
        if self.extrapolate not in ("zero", "hold"):
            raise ModelError(f"table function: extrapolate: expected 'zero' or 'hold', got {self.extrapolate!r}")
        regular_file(self.file, MAX_TABLE_FILE_BYTES, "table file", f"table file {self.file!r}")

    @cached_property
    def table(self) -> Table:
        """The :class:`Table` of the file's numbers in SI (read once, on first use)."""
        try:
            t, v = read_table_file(self.file)
            return Table(t * self.time_scale, v * self.value_scale, self.extrapolate, source=self.file)
        except ModelError as exc:
            raise ModelError(f"{self.who}: {exc}" if self.who else str(exc)) from None

    @property
    def times(self) -> np.ndarray:
        """(k,) times [s] (reads the file)."""
        return self.table.times

    @property
    def values(self) -> np.ndarray:
        """(k,) values [SI] (reads the file)."""
        return self.table.values

    @property
    def source(self) -> str:
        """The file (as :attr:`Table.source`)."""
        return self.file

    def value(self, t: npt.ArrayLike) -> np.ndarray:
        return self.table.value(t)

    @property
    def breakpoints(self) -> tuple[float, ...]:
        return self.table.breakpoints

    @property
    def end_time(self) -> float:
        return self.table.end_time

    def to_dict(self) -> dict[str, Any]:
        """The table's numbers inline (SI), as :meth:`Table.to_dict`."""
        return self.table.to_dict()


def _table_number(text: str) -> float | None:
    """A finite number of a table file, or None (``float`` alone reads ``nan``, ``inf`` and
    5,000-digit integers)."""
    if len(text) > 100:
        return None
    try:
        value = float(text)
    except ValueError:
        return None
    return value if math.isfinite(value) else None


def function_from_dict(data: Any, who: str = "function", *, value_scale: float = 1.0,
                       time_scale: float = 1.0, angle_scale: float = 1.0,
                       base: str | Path | None = None) -> TimeFunction:
    """Build and validate a time function from plain data (a model file's ``function``).

    Parameters
    ----------
    data : mapping, sequence of mappings, or TimeFunction
        ``{"type": "half_sine", "amplitude": ..., ...}``; a list is a :class:`Sum`; a
        TimeFunction is returned as it is.
    who : str
        Prefix for error messages (e.g. ``"model.toml: excitation[1] ('shock'): function"``).
    value_scale, time_scale, angle_scale : float
        SI value of one unit of the excitation's quantity, of time, of angle, as written in
        ``data`` (frequencies are always Hz).
    base : str or Path or None
        Directory that a table's relative ``file`` is taken from (default: the working directory).

    Returns
    -------
    TimeFunction

    Raises
    ------
    ModelError
        Unknown type or key (with a did-you-mean), missing key, wrong type or sign; the message
        starts with ``who`` and names the function type and the key.

    Examples
    --------
    >>> function_from_dict({"type": "step", "amplitude": 5.0, "start": 10.0}, time_scale=1e-3)
    Step(amplitude=5.0, start=0.01, end=inf)
    """
    if isinstance(data, TimeFunction):
        return data
    if isinstance(data, (list, tuple)):
        if not data:
            raise ModelError(f"{who}: expected a function table or a non-empty list of them, got []")
        return Sum(tuple(function_from_dict(d, f"{who}[{i + 1}]", value_scale=value_scale,
                                            time_scale=time_scale, angle_scale=angle_scale, base=base)
                         for i, d in enumerate(data)))
    if not isinstance(data, Mapping):
        raise ModelError(f"{who}: expected a function table like {{ type = \"half_sine\", amplitude = ..., "
                         f"start = ..., duration = ... }}, got {data!r}")
    kind = data.get("type")
    cls = FUNCTIONS[choice(kind, "type", FUNCTIONS, who=who, expected=f"one of {list(FUNCTIONS)}")]
    if cls is Sum:
        return function_from_dict(list(data.get("terms") or []), f"{who}.terms", value_scale=value_scale,
                                  time_scale=time_scale, angle_scale=angle_scale, base=base)
    allowed = set(cls.roles) | {"type"} | ({"file"} if cls is Table else set())
    for key in data:
        if key not in allowed:
            raise ModelError(f"{who}: {kind} function: unknown key {key!r}; expected some of "
                             f"{sorted(allowed - {'type'})}" + did_you_mean(key, allowed))
    params: dict[str, Any] = {k: v for k, v in data.items() if k != "type"}
    if cls is Table and "file" in params:
        if "time" in params or "value" in params:
            raise ModelError(f"{who}: table function: file: give either file or time and value, not both")
        fname = params.pop("file")
        if not isinstance(fname, str):
            raise ModelError(f"{who}: table function: file: expected a file name, got {fname!r}")
        path = Path(fname) if base is None else Path(base) / fname
        try:       # checked now (a regular file, not too large), read by the first analysis using it
            return TableFile(str(path), params.get("extrapolate", "zero"), time_scale, value_scale, who)
        except ModelError as exc:
            raise ModelError(f"{who}: {exc}") from None
    scales = {"value": value_scale, "time": time_scale, "rate": value_scale / time_scale,
              "angle": angle_scale}
    kwargs: dict[str, Any] = {}
    for key, v in params.items():
        role = cls.roles.get(key, "text")
        if role in scales and scales[role] != 1.0:
            try:
                given = np.asarray(v, dtype=float)
                with np.errstate(over="ignore"):
                    v = given * scales[role]
            except (TypeError, ValueError, OverflowError):
                raise ModelError(f"{who}: {kind} function: {key}: expected a number, got {v!r}") from None
            if np.any(np.isfinite(given) & ~np.isfinite(v)):        # (end = inf stays inf)
                raise ModelError(f"{who}: {kind} function: {key}: {data[key]!r} overflows when converted to SI")
            v = float(v) if v.ndim == 0 else v
        kwargs[cls.aliases.get(key, key)] = v
    required = [f.name for f in dataclasses.fields(cls)
                if f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING]
    inverse = {v: k for k, v in cls.aliases.items()}
    missing = [inverse.get(n, n) for n in required if n not in kwargs]
    if missing:
        raise ModelError(f"{who}: {kind} function: missing key(s) {missing}; "
                         f"{kind} takes {list(cls.roles)}")
    try:
        return cls(**kwargs)
    except ModelError as exc:
        raise ModelError(f"{who}: {exc}") from None


def amplitude_quantity(kind: str, dof: str | None) -> str:
    """The quantity (see :data:`vibss.model.units.QUANTITIES`) of an excitation's values.

    Parameters
    ----------
    kind : {"force", "displacement", "velocity", "acceleration"}
    dof : str or None
        ``"x"`` ... ``"rz"``, or None for a direction vector (translational).

    Examples
    --------
    >>> amplitude_quantity("force", "rx"), amplitude_quantity("acceleration", "z")
    ('moment', 'acceleration')
    """
    rotational = dof is not None and dof.startswith("r")
    if kind == "force":
        return "moment" if rotational else "force"
    if kind == "displacement":
        return "angle" if rotational else "length"
    return ("angular_" if rotational else "") + kind


@dataclass(frozen=True, eq=False)
class Excitation:
    """A time function driving a force, a moment or a prescribed motion.

    Parameters
    ----------
    name : str
        Unique name.
    kind : {"force", "displacement", "velocity", "acceleration"}
        A force (or moment, on a rotational DOF), or a prescribed motion of ``target``.
    target : str
        A body's name, or ``"ground"`` (prescribed motion only).
    function : TimeFunction
        The time history [N, N m, m, rad, and per s or per s^2 for velocity and acceleration].
    dof : {"x", "y", "z", "rx", "ry", "rz"} or None
        The DOF driven, in global axes; or None with ``direction``.
    direction : (3,) array_like or None
        A translation direction in global axes (normalised to unit length on construction).
    at : (3,) array_like or None
        Point of application of a force [m] (frame as ``frame``); None: the centre of gravity.
    frame : {"body", "global"}
        How ``at`` is measured: relative to the body's COG, or global coordinates.

    Examples
    --------
    >>> Excitation("base", "acceleration", "ground", Step(1.0), dof="x").signal
    'ground.x.acc'
    """

    name: str
    kind: str
    target: str
    function: TimeFunction
    dof: str | None = None
    direction: Any = None
    at: Any = None
    frame: str = "body"

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name:
            raise ModelError(f"excitation: name must be a non-empty string, got {self.name!r}")
        who = f"excitation {self.name!r}"
        choice(self.kind, "kind", INPUT_KINDS, who=who, expected=f"one of {list(INPUT_KINDS)}")
        if not isinstance(self.target, str) or not self.target:
            raise ModelError(f"{who}: target: expected a body name or {GROUND!r}, got {self.target!r}")
        if self.kind == "force" and self.target == GROUND:
            raise ModelError(f"{who}: a force on {GROUND!r} does nothing (ground is fixed or its "
                             "motion is prescribed); apply it to a body, or prescribe ground motion")
        if not isinstance(self.function, TimeFunction):
            raise ModelError(f"{who}: function: expected a time function, got {self.function!r}")
        if (self.dof is None) == (self.direction is None):
            raise ModelError(f"{who}: give exactly one of dof (one of {list(DOF_NAMES)}) and "
                             "direction (a 3-vector)")
        if self.dof is not None:
            choice(self.dof, "dof", DOF_NAMES, who=who, expected=f"one of {list(DOF_NAMES)}")
        if self.direction is not None:
            d = unit_direction(_vector3(self.direction, who, "direction"))
            if d is None:
                raise ModelError(f"{who}: direction: must not be the zero vector")
            object.__setattr__(self, "direction", d)
        if self.frame not in ("body", "global"):
            raise ModelError(f"{who}: frame: expected 'body' or 'global', got {self.frame!r}")
        if self.at is not None:
            if self.kind != "force":
                raise ModelError(f"{who}: at: a prescribed {self.kind} drives a DOF, not a point; "
                                 "remove 'at'")
            if self.rotational:
                raise ModelError(f"{who}: at: a moment acts the same at every point of a rigid "
                                 "body; remove 'at'")
            a = _vector3(self.at, who, "at")
            a.setflags(write=False)
            object.__setattr__(self, "at", a)

    @property
    def rotational(self) -> bool:
        """Whether the excitation drives a rotational DOF (moment or rotation)."""
        return self.dof is not None and self.dof.startswith("r")

    @property
    def signal(self) -> str:
        """Name of the plant input this excitation feeds.

        ``<target>.fx|fy|fz`` (force at the COG), ``<target>.mx|my|mz`` (moment),
        ``<target>.<dof>.disp|vel|acc`` (prescribed motion); the excitation's own ``name`` when it
        has a ``direction`` or a point ``at``.
        """
        if self.dof is None or self.at is not None:
            return self.name
        if self.kind == "force":
            return f"{self.target}.{'m' + self.dof[1] if self.rotational else 'f' + self.dof}"
        return f"{self.target}.{self.dof}.{_MOTION_SUFFIX[self.kind]}"

    @property
    def unit(self) -> str:
        """SI unit of the values, e.g. ``'N'``, ``'N m'``, ``'m/s^2'``, ``'rad'``."""
        return Units().label(amplitude_quantity(self.kind, self.dof))

    @property
    def steady_state(self) -> bool:
        """Whether this excitation is for frequency studies only (a sweep with ``sweep_time = 0``).

        Time studies should leave such excitations out; frequency studies take only these.
        """
        return self.function.steady_state

    def value(self, t: npt.ArrayLike) -> np.ndarray:
        """The function's value at times ``t`` [s] (see :meth:`TimeFunction.value`)."""
        return self.function.value(t)


def _vector3(value: Any, who: str, key: str) -> np.ndarray:
    return vector(value, 3, key, who=who, strict=False)
