"""Test data in and out: universal file format dataset 58 (function at a node) through pyuff.

``write_uff(result, path)`` writes one dataset 58 per channel of a
:class:`~vibss.frequency.api.FrequencyResponse` (function type 4, FRF: complex, frequency abscissa)
or of a :class:`~vibss.time.api.TimeResponse` (function type 1, time response: real); ``read_uff(path)``
reads FRF datasets back as a FrequencyResponse, e.g. a measured FRF to overlay on a computed one
(:func:`frac`: the frequency response assurance criterion per channel). Signal names travel in the
ID lines (``id1`` the output, ``id2`` the input); nodes are channel numbers and directions the DOF
(x, y, z, rx, ry, rz = 1 ... 6; 0 when the signal is not a DOF). Binary double precision by default,
so values come back exactly. pyuff is an optional extra: ``pip install 'vibss[uff]'``.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from ..errors import MissingDependencyError, ModelError

__all__ = ["write_uff", "read_uff", "frac"]

_DIRS = {"x": 1, "y": 2, "z": 3, "rx": 4, "ry": 5, "rz": 6, "fx": 1, "fy": 2, "fz": 3, "mx": 4, "my": 5, "mz": 6}


def _pyuff() -> Any:
    try:
        import pyuff
    except ImportError:
        raise MissingDependencyError("UFF files need pyuff, an optional dependency: pip install 'vibss[uff]'",
                                     argument="pyuff") from None
    return pyuff


def _dir(name: str) -> int:
    parts = name.split(".")
    for p in reversed(parts[1:]):
        if p in _DIRS:
            return _DIRS[p]
    return 0


def write_uff(result: Any, path: str | Path, binary: bool = True) -> Path:
    """Write a frequency or time response as UFF dataset 58 records (one per channel).

    Parameters
    ----------
    result : FrequencyResponse or TimeResponse
        What to write.
    path : str or Path
        The file (overwritten).
    binary : bool
        Binary double precision (exact) or ASCII (about 11 digits).

    Returns
    -------
    Path
    """
    pyuff = _pyuff()
    path = Path(path)
    sets = []
    if hasattr(result, "frequency_hz") and hasattr(result, "response"):
        f = np.asarray(result.frequency_hz, dtype=float)
        for i, y in enumerate(result.outputs):
            for j, u in enumerate(result.inputs):
                h = np.asarray(result.response[i, j], dtype=complex)
                if not np.all(np.isfinite(h)):
                    raise ModelError(f"write_uff: channel {y}/{u} is not finite (inf at 0 Hz?); choose "
                                     "frequencies > 0")
                unit = result.channel_unit(i, j) if hasattr(result, "channel_unit") else result.units[i]
                sets.append(pyuff.prepare_58(
                    binary=int(binary), id1=y[:80], id2=u[:80], id3=f"vibss {result.quantity}"[:80],
                    id4=unit[:80], id5=str(result.name)[:80], func_type=4, rsp_node=i + 1, rsp_dir=_dir(y),
                    ref_node=j + 1, ref_dir=_dir(u), abscissa_spacing=1 if _even(f) else 0,
                    abscissa_axis_units_lab="Hz", ordinate_axis_units_lab=unit[:10],
                    ordinate_spec_data_type=_data_type(result.units[i]),
                    orddenom_spec_data_type=_data_type(result.input_units[j]) if result.input_units else 0,
                    data=h, x=f))
    elif hasattr(result, "time") and hasattr(result, "output_names"):
        t = np.asarray(result.time, dtype=float)
        for i, y in enumerate(result.output_names):
            sets.append(pyuff.prepare_58(
                binary=int(binary), id1=y[:80], id2="time response", id3="vibss time response",
                id4=result.units[i][:80], id5=str(result.name)[:80], func_type=1, rsp_node=i + 1,
                rsp_dir=_dir(y), ref_node=0, ref_dir=0, abscissa_spacing=1 if _even(t) else 0,
                abscissa_axis_units_lab="s", ordinate_axis_units_lab=result.units[i][:10],
                ordinate_spec_data_type=_data_type(result.units[i]), orddenom_spec_data_type=0,
                data=np.asarray(result.outputs[i], dtype=float), x=t))
    else:
        raise ModelError(f"write_uff: expected a FrequencyResponse or a TimeResponse, got {type(result).__name__}")
    if path.exists():
        path.unlink()
    pyuff.UFF(str(path)).write_sets(sets, mode="add")
    return path


def _data_type(unit: str) -> int:
    """UFF specific data type of a signal from its SI unit: 8 displacement, 11 velocity,
    12 acceleration, 13 excitation force, 0 unknown."""
    if unit.startswith("N"):
        return 13
    if unit.endswith("/s^2"):
        return 12
    if unit.endswith("/s"):
        return 11
    return 8 if unit in ("m", "rad") else 0


def _even(x: np.ndarray) -> bool:
    return x.size > 2 and bool(np.allclose(np.diff(x), x[1] - x[0], rtol=1e-12, atol=0.0))


def read_uff(path: str | Path) -> Any:
    """Read the FRF records (dataset 58, function type 4) of a UFF file as one FrequencyResponse.

    Channels are named by the records' ``id1``/``id2`` lines when they hold signal names, else
    ``node<n>.<dir>``; every record must share one frequency axis.

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    FrequencyResponse
        ``quantity`` from the records (``"frf"``), ``method = "uff"``.
    """
    from ..frequency.api import FrequencyResponse

    pyuff = _pyuff()
    path = Path(path)
    if not path.is_file():
        raise ModelError(f"read_uff: {path}: no such file")
    data = pyuff.UFF(str(path)).read_sets()
    records = [data] if isinstance(data, dict) else list(data)
    frfs = [r for r in records if r.get("type") == 58 and int(r.get("func_type", 0)) == 4]
    if not frfs:
        raise ModelError(f"read_uff: {path}: no dataset 58 FRF records (function type 4)")
    f = np.asarray(frfs[0]["x"], dtype=float)
    outs: list[str] = []
    ins: list[str] = []
    cells: dict[tuple[str, str], np.ndarray] = {}
    units: dict[str, str] = {}
    for r in frfs:
        x = np.asarray(r["x"], dtype=float)
        if x.shape != f.shape or not np.allclose(x, f, rtol=1e-12, atol=0.0):
            raise ModelError(f"read_uff: {path}: the FRF records do not share one frequency axis")
        y = str(r.get("id1", "")).strip() or f"node{r.get('rsp_node')}.{r.get('rsp_dir')}"
        u = str(r.get("id2", "")).strip() or f"node{r.get('ref_node')}.{r.get('ref_dir')}"
        outs += [y] if y not in outs else []
        ins += [u] if u not in ins else []
        cells[(y, u)] = np.asarray(r["data"], dtype=complex)
        units[y] = str(r.get("id4", "")).strip() or str(r.get("ordinate_axis_units_lab", "")).strip() or "-"
    h = np.zeros((len(outs), len(ins), f.size), dtype=complex)
    for (y, u), v in cells.items():
        h[outs.index(y), ins.index(u)] = v
    return FrequencyResponse(f, h, tuple(outs), tuple(ins), tuple(units[y] for y in outs), "frf", "uff",
                             f"read from {path.name}", np.zeros(0), path.stem)


def frac(measured: Any, computed: Any) -> dict[str, float]:
    """Frequency response assurance criterion per common channel: ``|sum H_m conj(H_c)|^2 /
    (sum |H_m|^2 sum |H_c|^2)`` on the measured frequencies (the computed response interpolated
    there, real and imaginary parts linearly); 1 = same shape.

    Parameters
    ----------
    measured, computed : FrequencyResponse

    Returns
    -------
    dict of str to float
        ``{"<output>/<input>": FRAC}`` for every channel both have.
    """
    out = {}
    fm = np.asarray(measured.frequency_hz, dtype=float)
    fc = np.asarray(computed.frequency_hz, dtype=float)
    for i, y in enumerate(measured.outputs):
        for j, u in enumerate(measured.inputs):
            if y not in computed.outputs or u not in computed.inputs:
                continue
            hc = computed.response[computed.outputs.index(y), computed.inputs.index(u)]
            hci = np.interp(fm, fc, hc.real) + 1j * np.interp(fm, fc, hc.imag)
            hm = measured.response[i, j]
            num = abs(np.vdot(hci, hm)) ** 2
            den = float(np.vdot(hm, hm).real * np.vdot(hci, hci).real)
            out[f"{y}/{u}"] = float(num / den) if den > 0 else float("nan")
    return out
