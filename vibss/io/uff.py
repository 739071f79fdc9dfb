"""Test data in and out: universal file datasets 58 (functions), 55 (mode shapes) and 2411 (nodes)
through pyuff.

``write_uff(result, path)`` writes one dataset 58 per channel of a
:class:`~vibss.frequency.result.FrequencyResponse` (function type 4, FRF: complex, frequency abscissa)
or of a :class:`~vibss.time.result.TimeResponse` (function type 1, time response: real); ``read_uff(path)``
reads FRF datasets back as a FrequencyResponse, e.g. a measured FRF to overlay on a computed one
(:func:`vibss.frequency.compare.frac`: the frequency response assurance criterion per channel). Signal names travel in the
ID lines (``id1`` the output, ``id2`` the input); nodes are channel numbers and directions the DOF
(x, y, z, rx, ry, rz = 1 ... 6; 0 when the signal is not a DOF). Binary double precision by default,
so values come back exactly.

A :class:`~vibss.modal.result.Modes` goes out as one dataset 2411 with a node per body at its
centre of gravity [m] (node ``n`` is the model's ``n``-th body), then one per control point (moving
with its body), the names in each 55's ``id2``, and one dataset 55 per mode (structural normal mode, six real values per node: x, y, z
[m] and rx, ry, rz [rad] of the mass-normalised shape, zero for a DOF the analysis held fixed);
:func:`read_uff_modes` reads them back. pyuff is an optional extra: ``pip install 'vibss[uff]'``.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import MissingDependencyError, ModelError

__all__ = ["write_uff", "read_uff", "read_uff_modes", "UffModes"]

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
    result : FrequencyResponse, TimeResponse or Modes
        What to write (a Modes as nodes and mode shapes, datasets 2411 and 55).
    path : str or Path
        The file (overwritten).
    binary : bool
        Binary double precision (exact) or ASCII (about 11 digits) for dataset 58; datasets 55 and
        2411 are ASCII by the format: mode shapes and frequencies to six significant digits (its
        E13.5 fields), node coordinates to 16.

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
    elif hasattr(result, "shapes") and hasattr(result, "omega"):
        sets = _mode_sets(pyuff, result)
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
        raise ModelError(f"write_uff: expected a FrequencyResponse, a TimeResponse or a Modes, "
                         f"got {type(result).__name__}")
    if path.exists():
        path.unlink()
    pyuff.UFF(str(path)).write_sets(sets, mode="add")
    return path


_SIX = ("x", "y", "z", "rx", "ry", "rz")


def _mode_sets(pyuff: Any, modes: Any) -> list[dict[str, Any]]:
    """Dataset 2411 (a node per body at its COG, then per control point) and one dataset 55 per mode."""
    from ..model.geometry import point_transfer

    model = modes.model
    bodies = [b.name for b in model.bodies]
    points = list(model.control_points)
    count = len(bodies) + len(points)
    nodes = np.arange(1, count + 1)                # int: pyuff's 2411 check fails on float arrays
    xyz = np.array([np.asarray(b.cog, float) for b in model.bodies]
                   + [model.point(c.body, c.at, c.frame) + model.body(c.body).cog for c in points]).reshape(-1, 3)
    sets = [pyuff.prepare_2411(node_nums=nodes, def_cs=np.ones(count, dtype=int), disp_cs=np.ones(count, dtype=int),
                               color=np.ones(count, dtype=int), x=xyz[:, 0], y=xyz[:, 1], z=xyz[:, 2])]
    rows = {d: i for i, d in enumerate(modes.dofs)}
    names = ",".join(bodies + [c.name for c in points])
    for k in range(modes.shapes.shape[1]):
        full = np.zeros((count, 6))
        for n, b in enumerate(bodies):
            for c, d in enumerate(_SIX):
                i = rows.get(f"{b}.{d}")
                if i is not None:
                    full[n, c] = modes.shapes[i, k]
        for j, c in enumerate(points):             # a point moves with its body: L(r) q and its rotation
            q = full[bodies.index(c.body)]
            full[len(bodies) + j, :3] = point_transfer(model.point(c.body, c.at, c.frame)) @ q
            full[len(bodies) + j, 3:] = q[3:]
        f = float(modes.omega[k]) / (2 * np.pi)
        sets.append(pyuff.prepare_55(
            id1=f"vibss mode {k + 1}"[:80], id2=f"nodes: {names}"[:80], id3=f"{f:.12g} Hz"[:80],
            id4=str(getattr(modes.model, "name", "vibss"))[:80], id5="mass-normalised, m and rad"[:80],
            model_type=1, analysis_type=2, data_ch=3, spec_data_type=8, data_type=2, n_data_per_node=6,
            r1=full[:, 0], r2=full[:, 1], r3=full[:, 2], r4=full[:, 3], r5=full[:, 4], r6=full[:, 5],
            load_case=1, mode_n=k + 1, freq=f, modal_m=1.0, modal_damp_vis=0.0, modal_damp_his=0.0,
            node_nums=nodes))
    return sets


@dataclass(frozen=True)
class UffModes:
    """Mode shapes read from datasets 55 (and node coordinates from 2411 or 15).

    Attributes
    ----------
    frequency_hz : (k,) ndarray
        Natural frequencies [Hz].
    shapes : (6 n, k) ndarray
        Rows x, y, z, rx, ry, rz of node 1, then node 2 ...; columns the modes.
    nodes : (n,) ndarray of int
        Node numbers.
    coordinates : (n, 3) ndarray
        Node coordinates in the file's units (NaN where the file has no node record).
    ids : tuple of str
        Each mode's ``id1`` line.
    """

    frequency_hz: np.ndarray
    shapes: np.ndarray
    nodes: np.ndarray
    coordinates: np.ndarray
    ids: tuple[str, ...]


def read_uff_modes(path: str | Path) -> UffModes:
    """Read the normal-mode records (dataset 55) of a UFF file, with the nodes (2411 or 15).

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    UffModes

    Raises
    ------
    ModelError
        No such file, no dataset 55, or records over different node sets.
    """
    pyuff = _pyuff()
    path = Path(path)
    if not path.is_file():
        raise ModelError(f"read_uff_modes: {path}: no such file")
    data = pyuff.UFF(str(path)).read_sets()
    records = [data] if isinstance(data, dict) else list(data)
    shapes = [r for r in records if r.get("type") == 55]
    if not shapes:
        raise ModelError(f"read_uff_modes: {path}: no dataset 55 (mode shape) records")
    nodes = np.asarray(shapes[0]["node_nums"], dtype=int)
    cols, freqs, ids = [], [], []
    for r in shapes:
        if not np.array_equal(np.asarray(r["node_nums"], dtype=int), nodes):
            raise ModelError(f"read_uff_modes: {path}: the mode records do not share one node set")
        parts = [np.asarray(r.get(f"r{c}", np.zeros(nodes.size)), dtype=float).real for c in range(1, 7)]
        cols.append(np.column_stack(parts).ravel())
        freqs.append(float(np.real(r.get("freq", np.nan))))
        ids.append(str(r.get("id1", "")).strip())
    xyz = np.full((nodes.size, 3), np.nan)
    for r in records:
        if r.get("type") in (15, 2411):
            for n, x, y, z in zip(np.asarray(r["node_nums"], dtype=int), r["x"], r["y"], r["z"]):
                hit = np.flatnonzero(nodes == n)
                if hit.size:
                    xyz[hit[0]] = (x, y, z)
    return UffModes(np.array(freqs), np.column_stack(cols), nodes, xyz, tuple(ids))


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
        Made by :meth:`~vibss.frequency.result.FrequencyResponse.from_measurement`: ``quantity``
        ``"frf"``, ``method = "measured"`` (no model behind it), the file named in ``note``.
    """
    from ..frequency.result import FrequencyResponse

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
    return FrequencyResponse.from_measurement(f, h, ins, outs, [units[y] for y in outs], name=path.stem,
                                              source=path.name)
