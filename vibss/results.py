"""The result protocol every public result follows, and the plain-text tables of the reports.

:class:`Result` is the base of :class:`~vibss.statics.StaticResult`, :class:`~vibss.modal.Modes`,
:class:`~vibss.modal.DampedModes`, :class:`~vibss.frequency.FrequencyResponse`,
:class:`~vibss.time.TimeResponse`, :class:`~vibss.time.SweepEnvelope` and
:class:`~vibss.reduction.Reduction`. Each result has

- ``report()`` and ``str(result)``: the same engineer's text;
- ``_repr_html_()``: its summary :class:`TextTable` as an escaped HTML table (notebooks);
- ``to_dict()`` (JSON-ready data, SI, non-finite numbers as None, by :func:`jsonable`) and
  ``to_json()`` (strict JSON: ``allow_nan=False``);
- ``to_pandas()`` (pandas is optional: :func:`require_pandas` names the extra when it is missing);
- ``plot(ax=None)``: one line of delegation to :mod:`vibss.plotting` (a matplotlib ``Figure`` on an
  Agg canvas, never pyplot);
- the names python-control uses: ``output_labels`` / ``input_labels`` (signal names in vibss
  spelling, ``'engine.z'``), ``units``, ``method``, ``note`` (why ``auto`` chose what it chose);
- ``result[out]`` and ``result[out, inp]`` by signal name (a :class:`~vibss.errors.SignalError`
  with did-you-mean for an unknown one);
- ``.control``: the python-control twin where one exists (``FrequencyResponseData``,
  ``TimeResponseData``, ``StateSpace``), None elsewhere.
"""

from __future__ import annotations

import dataclasses
import html
import re
import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np

from ._validate import name_index
from .errors import ArgumentTypeError, MissingDependencyError, SignalError

__all__ = ["ZERO_NOTE", "TextTable", "Result", "jsonable", "require_pandas", "freeze", "read_only", "freeze_fields", "ReadOnly"]

ZERO_NOTE = "identically zero (symmetry or no path)"
"""How tables and figures name a channel that is identically zero (every result says it alike)."""


_NEGATIVE_ZERO = re.compile(r"^(\s*)-(0(?:\.0*)?(?:[eE][-+]?\d+)?)(\s.*)?$")


def _no_negative_zero(cell: Any) -> Any:
    """``"-0.000"`` -> ``"0.000"`` (also ``"-0.0 mm"``, ``"-0e+00"``); other cells unchanged."""
    if isinstance(cell, str):
        m = _NEGATIVE_ZERO.match(cell)
        if m:
            return m.group(1) + m.group(2) + (m.group(3) or "")
    return cell


def number_text(value: float, spec: str = ".4f") -> str:
    """``format(value, spec)`` without the sign of a value that rounds to zero (no ``-0.00``).

    Examples
    --------
    >>> number_text(-1e-9, ".2f"), number_text(-0.5, ".2f")
    ('0.00', '-0.50')
    """
    return _no_negative_zero(format(value, spec))


@dataclass(frozen=True)
class TextTable:
    """A titled table of strings that renders as aligned text.

    Parameters
    ----------
    header : sequence of str
        Column names.
    rows : sequence of sequence of str
        Cells, already formatted.
    title : str
        Printed above the table.
    notes : sequence of str
        Printed below it.
    """

    header: Sequence[str]
    rows: Sequence[Sequence[str]]
    title: str = ""
    notes: Sequence[str] = field(default_factory=tuple)

    def __post_init__(self) -> None:
        # a rounded tiny negative prints as "-0.0": an engineer reads a sign that is not there
        object.__setattr__(self, "rows", [[_no_negative_zero(c) for c in r] for r in self.rows])

    def render(self) -> str:
        """The table as aligned text (numbers right-aligned)."""
        cols = list(zip(*([list(self.header)] + [list(r) for r in self.rows])))
        widths = [max(len(c) for c in col) for col in cols]
        def line(cells: Sequence[str]) -> str:
            return "  ".join(c.rjust(w) for c, w in zip(cells, widths)).rstrip()
        out = []
        if self.title:
            out.append(self.title)
        out.append(line(self.header))
        out.append("  ".join("-" * w for w in widths))
        out.extend(line(r) for r in self.rows)
        out.extend(self.notes)
        return "\n".join(out)

    def to_html(self) -> str:
        """The table as HTML (every cell escaped), its title as the caption.

        Examples
        --------
        >>> print(TextTable(["a<b"], [["1"]], title="T & U").to_html())
        <table><caption>T &amp; U</caption><thead><tr><th>a&lt;b</th></tr></thead><tbody><tr><td>1</td></tr></tbody></table>
        """
        e = html.escape
        head = "".join(f"<th>{e(str(h))}</th>" for h in self.header)
        body = "".join("<tr>" + "".join(f"<td>{e(str(c))}</td>" for c in r) + "</tr>" for r in self.rows)
        cap = f"<caption>{e(self.title)}</caption>" if self.title else ""
        notes = "".join(f"<p>{e(n)}</p>" for n in self.notes)
        return f"<table>{cap}<thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>{notes}"

    def __str__(self) -> str:
        return self.render()


def jsonable(value: Any) -> Any:
    """``value`` as plain JSON data: arrays and numpy scalars as lists and numbers, tuples as lists,
    NaN and infinity as None, complex numbers as ``[re, im]``, mapping keys as str.

    Examples
    --------
    >>> jsonable({"a": np.array([1.0, np.inf]), "b": (np.int64(2), float("nan")), "c": 1 + 2j})
    {'a': [1.0, None], 'b': [2, None], 'c': [1.0, 2.0]}
    """
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        v = float(value)
        return v if math.isfinite(v) else None
    if isinstance(value, (complex, np.complexfloating)):
        return [jsonable(value.real), jsonable(value.imag)]
    if isinstance(value, np.ndarray):
        return _array(value)
    if isinstance(value, Mapping):
        return {str(k): jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [jsonable(v) for v in value]
    return value


def _array(a: np.ndarray) -> Any:
    """Nested lists of an array at numpy speed (a time response has millions of samples)."""
    if a.dtype.kind in "biu":
        return a.tolist()
    if a.dtype.kind == "f":
        bad = ~np.isfinite(a)
        if not bad.any():
            return a.tolist()
        out = a.astype(object)
        out[bad] = None
        return out.tolist()
    if a.dtype.kind == "c":
        return _array(np.stack([a.real, a.imag], axis=-1))
    return jsonable(a.tolist())


def freeze(value: Any) -> Any:
    """``value`` with every numpy array in it made read-only **in place**, and returned.

    Walks tuples, lists and dict values and the ``data``, ``indices`` and ``indptr`` arrays of
    scipy.sparse matrices. For objects that own their arrays (an :class:`~vibss.linear.plant.assemble.Assembly`,
    a :class:`~vibss.linear.plant.plant.Plant`); results use :func:`read_only`, which never touches the
    arrays it was given.

    Examples
    --------
    >>> a = freeze({"x": (np.zeros(2),)})["x"][0]
    >>> a.flags.writeable
    False
    """
    if isinstance(value, np.ndarray):
        value.flags.writeable = False
    elif isinstance(value, (str, int, float)):     # labels and numbers: nothing to freeze (60,000 DOF labels)
        pass
    elif isinstance(value, (tuple, list)):
        if not _ATOMS.issuperset(map(type, value)):     # labels (DOF names), numbers: nothing to freeze
            for v in value:
                freeze(v)
    elif isinstance(value, dict):
        for v in value.values():
            freeze(v)
    elif _is_compressed_sparse(value):
        for a in (value.data, value.indices, value.indptr):
            a.flags.writeable = False
    return value


def _is_compressed_sparse(value: Any) -> bool:
    # the three arrays in turn, the rarest name first, no generator: asked of every field of every
    # small result
    return isinstance(getattr(value, "indptr", None), np.ndarray) and \
        isinstance(getattr(value, "indices", None), np.ndarray) and \
        isinstance(getattr(value, "data", None), np.ndarray)


_ATOMS = frozenset({str, int, float, complex, bool, type(None)})


def read_only(value: Any) -> Any:
    """A read-only version of ``value`` that leaves ``value`` itself alone.

    An array becomes a read-only view of it (no copy; the caller's array stays writeable); tuples,
    lists and dicts are rebuilt around read-only versions of their items; a scipy.sparse matrix is
    copied with read-only arrays; anything else is returned as it is.

    Examples
    --------
    >>> mine = np.zeros(2)
    >>> ro = read_only(mine)
    >>> ro.flags.writeable, mine.flags.writeable, np.shares_memory(ro, mine)
    (False, True, True)
    """
    if isinstance(value, np.ndarray):
        if not value.flags.writeable:
            return value
        view = value.view()
        view.flags.writeable = False
        return view
    if type(value) in _ATOMS:          # labels, flags, numbers: nothing to freeze (most fields)
        return value
    if type(value) is tuple:
        if _ATOMS.issuperset(map(type, value)):        # labels (60,000 DOF names), numbers: nothing to freeze
            return value
        return tuple(read_only(v) for v in value)
    if type(value) is list:
        return [read_only(v) for v in value]
    if type(value) is dict:
        return {k: read_only(v) for k, v in value.items()}
    if _is_compressed_sparse(value):
        return freeze(value.copy())
    return value


def freeze_fields(obj: Any) -> None:
    """Replace every public dataclass field of the frozen ``obj`` by its :func:`read_only` version.

    Fields whose name starts with ``_`` (private caches) are left alone.
    """
    for name in _public_fields(obj):
        value = getattr(obj, name)
        frozen = read_only(value)
        if frozen is not value:
            object.__setattr__(obj, name, frozen)


def _public_fields(obj: Any) -> tuple[str, ...]:
    """The names of the dataclass ``obj``'s public fields, listed once per class (a small result is
    built often)."""
    names = _PUBLIC_FIELDS.get(type(obj))
    if names is None:
        names = _PUBLIC_FIELDS[type(obj)] = tuple(f.name for f in dataclasses.fields(obj)
                                                  if not f.name.startswith("_"))
    return names


_PUBLIC_FIELDS: dict[type, tuple[str, ...]] = {}


class ReadOnly:
    """Mixin of frozen dataclasses whose arrays must not change: every public field becomes
    :func:`read_only` on construction, and again after unpickling (pickle brings arrays back
    writeable and does not run ``__post_init__``).

    A class that builds and owns its arrays (``owns_arrays = True``: an assembly, a plant) freezes
    them in place instead, keeping their identity (a plant's mounts' form refers to its very
    arrays); arrays handed to such a constructor become read-only.
    """

    owns_arrays: ClassVar[bool] = False

    def __post_init__(self) -> None:
        if self.owns_arrays:
            for name in _public_fields(self):
                freeze(getattr(self, name))
        else:
            freeze_fields(self)

    def __setstate__(self, state: dict[str, Any]) -> None:
        # cached derived values are pickled with the object: frozen too
        self.__dict__.update(freeze(dict(state)))


def require_pandas() -> Any:
    """The pandas module, or a :class:`~vibss.errors.MissingDependencyError` naming the extra."""
    try:
        import pandas
    except ImportError:
        raise MissingDependencyError("to_pandas needs pandas, an optional dependency: "
                                     "pip install 'vibss[pandas]'", argument="pandas") from None
    return pandas


class Result(ReadOnly):
    """Base of every public result: the shared half of the protocol (see the module docstring).

    A subclass provides ``report()``, ``summary()`` (a :class:`TextTable`), ``to_dict()``,
    ``to_pandas()``, ``plot(ax=None)``, ``output_labels``, ``input_labels``, ``units``,
    ``method``, ``note`` and ``_item(i, j)`` (the data of output ``i``, input ``j`` or None).
    """

    signal_kind: ClassVar[str] = "output"
    """What ``output_labels`` name (``"output"``, or ``"DOF"`` for modes and static results)."""

    __iter__ = None     # result[...] is a lookup by name, not the sequence protocol

    # ReadOnly: results are frozen data; an array handed out cannot be changed in place, so a
    # cached derived value (frequency_hz from omega ...) can never go stale

    # -- supplied by each result -------------------------------------------------------------
    def report(self) -> str:
        """Engineer's text report."""
        raise NotImplementedError

    def summary(self) -> TextTable:
        """The headline table (what ``_repr_html_`` shows)."""
        raise NotImplementedError

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready data (SI; non-finite numbers as None)."""
        raise NotImplementedError

    @property
    def output_labels(self) -> tuple[str, ...]:
        """Output signal names (vibss spelling, ``'engine.z'``)."""
        raise NotImplementedError

    @property
    def input_labels(self) -> tuple[str, ...]:
        """Input signal names (empty where the result has no inputs)."""
        return ()

    def _item(self, i: int, j: int | None) -> Any:
        raise NotImplementedError

    # -- shared ------------------------------------------------------------------------------
    @property
    def noutputs(self) -> int:
        """Number of outputs (python-control's name)."""
        return len(self.output_labels)

    @property
    def ninputs(self) -> int:
        """Number of inputs (python-control's name)."""
        return len(self.input_labels)

    @property
    def control(self) -> Any:
        """The python-control twin of this result, or None where python-control has none."""
        return None

    def __str__(self) -> str:
        return self.report()

    def _repr_html_(self) -> str:
        """The result's tables (:meth:`html_tables`) as HTML, under its name (escaped)."""
        title = html.escape(self.report().split("\n", 1)[0])
        return f"<div><strong>{title}</strong>" + "".join(t.to_html() for t in self.html_tables()) + "</div>"

    def html_tables(self) -> list[TextTable]:
        """The tables a notebook shows: the summary (a result with more to show lists more)."""
        return [self.summary()]

    def to_json(self, indent: int | None = None) -> str:
        """Strict JSON of :meth:`to_dict` (non-finite numbers are null; never NaN or Infinity).

        Parameters
        ----------
        indent : int or None
            As :func:`json.dumps`.
        """
        return json.dumps(jsonable(self.to_dict()), indent=indent, allow_nan=False)

    def __getitem__(self, key: Any) -> Any:
        """``result[out]`` or ``result[out, inp]`` by signal name (or position)."""
        out, inp = key if isinstance(key, tuple) and len(key) == 2 else (key, None)
        if isinstance(key, tuple) and len(key) != 2:
            raise ArgumentTypeError(f"{type(self).__name__}[...]: expected [output] or [output, input], "
                                    f"got {key!r}", argument="key", received=key)
        i = self._position(out, self.output_labels, self.signal_kind)
        j = None if inp is None else self._position(inp, self.input_labels, "input")
        return self._item(i, j)

    @staticmethod
    def _position(key: Any, labels: Sequence[str], what: str) -> int:
        if isinstance(key, (int, np.integer)) and not isinstance(key, (bool, np.bool_)):
            if -len(labels) <= key < len(labels):
                return int(key) % len(labels)
            raise SignalError(f"{what}: index {key} out of range for {len(labels)} {what}s",
                              argument=what, received=key)
        if not labels:
            raise SignalError(f"{what}: this result has no {what}s (got {key!r})", argument=what,
                              received=key)
        return name_index(key, labels, what)


def __getattr__(name: str) -> Any:
    # ``Table`` was this module's name for TextTable (vibss.Table is a time function): kept one release
    if name == "Table":
        from ._deprecated import warn
        warn("vibss.results.Table", "vibss.results.TextTable")
        return TextTable
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
