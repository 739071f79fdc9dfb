"""Test data as CSV: frequency responses, time records and response PSDs out, and back in.

One file per result, readable by a spreadsheet or ``pandas.read_csv(path, comment="#")``:

- a first comment line ``# vibss <kind> <name>``, ``kind`` one of ``frf``, ``time``, ``psd``;
- a header row: the abscissa (``frequency_hz`` or ``time_s``), then one column per channel named
  ``<output>/<input> re [unit]`` and ``... im [unit]`` for an FRF (real and imaginary parts),
  ``<output> [unit]`` for a time record and ``<output> [unit^2/Hz]`` for a PSD (``(m/s^2)^2/Hz``);
- the numbers with 17 significant digits, so a file read back gives the same doubles.

:func:`read_csv` reads an FRF file (from vibss or any tool that writes the same columns, e.g. a
measured FRF to overlay and compare with :func:`vibss.io.frac`) as a
:class:`~vibss.frequency.result.FrequencyResponse` and a time file as a
:class:`~vibss.time.result.TimeResponse`.
"""

from __future__ import annotations

import csv
import io
import re
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import ModelError, ModelFileError

__all__ = ["write_csv", "read_csv"]

_HEAD = re.compile(r"^(?P<name>.+?) (?:(?P<part>re|im) )?\[(?P<unit>[^\]]*)\]$")


def _fmt(x: float) -> str:
    return repr(float(x)) if np.isfinite(x) else ("nan" if np.isnan(x) else ("inf" if x > 0 else "-inf"))


def write_csv(result: Any, path: str | Path) -> Path:
    """Write a frequency response, a time response or a random-vibration response as CSV.

    Parameters
    ----------
    result : FrequencyResponse, TimeResponse or RandomResponse
        What to write: complex FRF (real and imaginary columns per channel, frequencies in Hz), the
        output time histories (time in s), or the output PSDs (unit squared per Hz).
    path : str or Path
        The file (overwritten).

    Returns
    -------
    Path

    Raises
    ------
    ModelError
        ``result`` is none of the three.

    Examples
    --------
    >>> import tempfile, pathlib, vibss
    >>> m = vibss.Model([vibss.Body("b", 2.0, [1, 1, 1])],
    ...                 [vibss.Mount("m", vibss.MountType("t", [1e3, 1e3, 1e3], [2, 2, 2]), "b")])
    >>> r = vibss.frequency_response(m, ["b.fz"], ["b.z"], frequencies=[1.0, 2.0])
    >>> p = write_csv(r, pathlib.Path(tempfile.mkdtemp()) / "frf.csv")
    >>> bool((read_csv(p).response == r.response).all())
    True
    """
    path = Path(path)
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    name = str(getattr(result, "name", "vibss"))
    if hasattr(result, "response") and hasattr(result, "frequency_hz"):
        f = np.asarray(result.frequency_hz, float)
        cols, head = [f], ["frequency_hz"]
        for i, y in enumerate(result.outputs):
            for j, u in enumerate(result.inputs):
                unit = result.channel_unit(i, j) if hasattr(result, "channel_unit") else result.units[i]
                h = np.asarray(result.response[i, j], complex)
                cols += [h.real, h.imag]
                head += [f"{y}/{u} re [{unit}]", f"{y}/{u} im [{unit}]"]
        kind = "frf"
    elif hasattr(result, "psd") and hasattr(result, "frequency_hz"):
        cols, head = [np.asarray(result.frequency_hz, float)], ["frequency_hz"]
        for i, y in enumerate(result.outputs):
            cols.append(np.asarray(result.psd[i], float))
            u = result.units[i]
            head.append(f"{y} [{u if u.isalnum() else '(' + u + ')'}^2/Hz]")
        kind = "psd"
    elif hasattr(result, "time") and hasattr(result, "output_names"):
        cols, head = [np.asarray(result.time, float)], ["time_s"]
        for i, y in enumerate(result.output_names):
            cols.append(np.asarray(result.outputs[i], float))
            head.append(f"{y} [{result.units[i]}]")
        kind = "time"
    else:
        raise ModelError(f"write_csv: expected a FrequencyResponse, TimeResponse or RandomResponse, "
                         f"got {type(result).__name__}")
    buf.write(f"# vibss {kind} {name}\n")
    w.writerow(head)
    for row in np.column_stack(cols):
        w.writerow([_fmt(x) for x in row])
    path.write_text(buf.getvalue(), encoding="utf-8")
    return path


def read_csv(path: str | Path) -> Any:
    """Read an FRF or a time-record CSV (the columns :func:`write_csv` writes).

    An FRF file has a ``frequency_hz`` column and pairs ``<output>/<input> re [unit]`` and
    ``... im [unit]``; a time file a ``time_s`` column and ``<output> [unit]`` columns. Lines
    starting with ``#`` are comments.

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    FrequencyResponse or TimeResponse
        An FRF as :meth:`~vibss.frequency.result.FrequencyResponse.from_measurement` makes it
        (``method = "measured"``, no model behind it); a time record with ``method = "csv"``.

    Raises
    ------
    ModelFileError
        Not a file, an unknown first column, a header that is not ``name [unit]``, an FRF column
        without its other part, a row of the wrong length or a value that is not a number (the
        line is named).
    """
    path = Path(path)
    if not path.is_file():
        raise ModelFileError(f"read_csv: {path}: no such file")
    name = path.stem
    rows: list[list[str]] = []
    head: list[str] | None = None
    line_of: list[int] = []
    for n, line in enumerate(path.read_text(encoding="utf-8-sig").splitlines(), 1):
        if not line.strip():
            continue
        if line.startswith("#"):
            parts = line[1:].split(maxsplit=2)
            if len(parts) == 3 and parts[0] == "vibss":
                name = parts[2]
            continue
        cells = next(csv.reader([line]))
        if head is None:
            head = [c.strip() for c in cells]
            continue
        if len(cells) != len(head):
            raise ModelFileError(f"read_csv: {path}: line {n}: {len(cells)} values for {len(head)} columns")
        rows.append(cells)
        line_of.append(n)
    if head is None or not rows:
        raise ModelFileError(f"read_csv: {path}: no header row or no data")
    data = np.empty((len(rows), len(head)))
    for r, (cells, n) in enumerate(zip(rows, line_of)):
        try:
            data[r] = [float(c) for c in cells]
        except ValueError:
            raise ModelFileError(f"read_csv: {path}: line {n}: a value is not a number") from None
    parsed = []
    for c in head[1:]:
        m = _HEAD.match(c)
        if m is None:
            raise ModelFileError(f"read_csv: {path}: column {c!r}: expected '<signal> [unit]'")
        parsed.append((m["name"], m["part"], m["unit"]))
    if head[0] == "frequency_hz":
        return _frf(path, name, data, parsed)
    if head[0] == "time_s":
        from ..time.result import TimeResponse

        if any(p for _, p, _ in parsed):
            raise ModelFileError(f"read_csv: {path}: a time file has real columns only (no 're'/'im')")
        return TimeResponse(data[:, 0].copy(), data[:, 1:].T.copy(), tuple(n for n, _, _ in parsed),
                            tuple(u for _, _, u in parsed), np.zeros((0, data.shape[0])), (), "csv",
                            f"read from {path.name}", name)
    raise ModelFileError(f"read_csv: {path}: first column {head[0]!r}: expected 'frequency_hz' or 'time_s'")


def _frf(path: Path, name: str, data: np.ndarray, parsed: list[tuple[str, str | None, str]]) -> Any:
    from ..frequency.result import FrequencyResponse

    outs: list[str] = []
    ins: list[str] = []
    parts: dict[tuple[str, str], dict[str, np.ndarray]] = {}
    units: dict[str, str] = {}
    for col, (channel, part, unit) in enumerate(parsed, 1):
        if part is None or "/" not in channel:
            raise ModelFileError(f"read_csv: {path}: column {channel!r}: an FRF column is "
                                 "'<output>/<input> re|im [unit]'")
        y, u = channel.rsplit("/", 1)
        outs += [y] if y not in outs else []
        ins += [u] if u not in ins else []
        parts.setdefault((y, u), {})[part] = data[:, col]
        units.setdefault(y, unit)
    h = np.zeros((len(outs), len(ins), data.shape[0]), dtype=complex)
    for (y, u), p in parts.items():
        if set(p) != {"re", "im"}:
            raise ModelFileError(f"read_csv: {path}: channel {y}/{u}: needs both 're' and 'im' columns")
        h[outs.index(y), ins.index(u)] = p["re"] + 1j * p["im"]
    return FrequencyResponse.from_measurement(data[:, 0].copy(), h, ins, outs, [units[y] for y in outs], name=name,
                                              source=path.name)
