"""A source on a flexible foundation by frequency-based substructuring, against the whole model.

A 120 kg source on ``n`` mounts (on a circle) stands on a 400 kg plate on four floor mounts; the
plate has a control point under each source mount. Timed in the same run, single BLAS thread:

- ``Foundation.from_model``: the plate's (3n, 3n) receptance at those points;
- the coupled FRF, ``frequency_response(source, ..., foundation=...)``, 3 inputs x 6 outputs (and
  the 3n foundation motions it adds);
- the reference: the same system modelled whole (the source's mounts to the plate) by
  ``frequency_response``, and the stock path, ``control.frequency_response`` of its python-control
  state space (``vibss.statespace``);
- the error of the coupled FRF against each: max over outputs of max |H - H_ref| / max |H_ref|.

Run: ``python benchmarks/bench_fbs.py [--quick]`` (quick: 12 mounts, 200 frequencies; full: 40
mounts, 500 frequencies); results in ``benchmarks/results/fbs.json``.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from benchmarks.machine import machine, timed  # noqa: E402
from vibss import (Body, ControlPoint, Foundation, Model, Mount, MountType, frequency_response,  # noqa: E402
                   statespace)

INPUTS = ["engine.fz", "engine.mx", "engine.fy"]
OUTPUTS = ["engine.z", "engine.rx", "engine.y", "mount.m0.fz", "mount.m1.fx", "engine.z.acc"]


def models(n: int) -> tuple[Model, Model, Model, dict[str, str]]:
    """The source on ground, the plate with its points, the whole system, and mount -> point."""
    rng = np.random.default_rng(7)
    angle = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
    at = np.column_stack([0.5 * np.cos(angle), 0.35 * np.sin(angle), rng.uniform(-0.02, 0.02, n)])
    iso = MountType("iso", [2e5, 3e5, 5e5], [40.0, 60.0, 100.0])
    floor = MountType("floor", [4e5, 4e5, 1e6], [300.0, 300.0, 800.0])
    engine = Body("engine", 120.0, [4.0, 6.0, 7.0], cog=[0.05, -0.02, 0.25])
    plate = Body("plate", 400.0, [30.0, 50.0, 70.0], cog=[0.0, 0.0, -0.1])
    under = [Mount(f"f{i}", floor, "plate", at=(x, y, -0.2), frame="global")
             for i, (x, y) in enumerate([(0.9, 0.7), (-0.9, 0.7), (-0.9, -0.7), (0.9, -0.7)])]
    points = [ControlPoint(f"p{i}", "plate", a, frame="global") for i, a in enumerate(at)]
    source = Model([engine], [Mount(f"m{i}", iso, "engine", at=a, frame="global") for i, a in enumerate(at)])
    deck = Model([plate], under, control_points=points)
    whole = Model([engine, plate], [Mount(f"m{i}", iso, "engine", at=a, frame="global", to="plate")
                                    for i, a in enumerate(at)] + under, control_points=points)
    return source, deck, whole, {f"m{i}": f"p{i}" for i in range(n)}


def _err(h: np.ndarray, ref: np.ndarray) -> float:
    scale = np.abs(ref).max(axis=(1, 2), keepdims=True)
    return float((np.abs(h - ref) / scale).max())


def bench(quick: bool) -> dict:
    """12 mounts and 200 frequencies (``quick``), else 40 and 500."""
    n, nf = (12, 200) if quick else (40, 500)
    source, deck, whole, points = models(n)
    f = np.geomspace(1.0, 300.0, nf)
    t_found, found = timed(lambda: Foundation.from_model(deck, points, f), min_time=1.0)
    t_fbs, fbs = timed(lambda: frequency_response(source, INPUTS, OUTPUTS, foundation=found), min_time=1.0)
    t_whole, ref = timed(lambda: frequency_response(whole, INPUTS, OUTPUTS, frequencies=f), min_time=1.0)
    import control

    sys_ = statespace(whole, inputs=INPUTS, outputs=OUTPUTS[:-1])
    t_ss, stock = timed(lambda: control.frequency_response(sys_, 2 * np.pi * f), min_time=1.0)
    h_ss = np.asarray(stock.complex).reshape(len(OUTPUTS) - 1, len(INPUTS), nf)
    p = len(OUTPUTS)
    return {"mounts": n, "frequencies": nf, "interface_dofs": 3 * n,
            "foundation_from_model_s": t_found, "fbs_frf_s": t_fbs, "whole_model_frf_s": t_whole,
            "control_frequency_response_s": t_ss,
            "fbs_vs_whole_error": _err(fbs.response[:p], ref.response),
            "fbs_vs_control_error": _err(fbs.response[:p - 1], h_ss),
            "fbs_over_whole_time": t_fbs / t_whole, "machine": machine()}


if __name__ == "__main__":
    from run_all import main_one
    main_one("fbs")
