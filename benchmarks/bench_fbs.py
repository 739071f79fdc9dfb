"""A source on a flexible foundation by frequency-based substructuring, against the whole model and
against a plain numpy solve of the same coupled system.

A 120 kg source on ``n`` mounts (on a circle) stands on a 400 kg plate on four floor mounts; the
plate has a control point under each source mount. Timed in the same run, single BLAS thread:

- ``Foundation.from_model``: the plate's (3n, 3n) receptance at those points (not the coupling);
- the coupled FRF, ``frequency_response(source, ..., foundation=...)``, 3 inputs x 6 outputs (and
  the 3n foundation motions and 3n forces it adds): the source's exact solve split at the
  interface, one (3n x 3n) LU per frequency, its check at three frequencies;
- the plain numpy solve of the same coupled system: per frequency the (6 + 3n) equations of the
  source's DOFs ``q`` and the foundation's motions ``z`` (``[Z, -B'D; -Y D B, I + Y D]``, the mounts'
  ``D = K + i w C`` and the points' kinematics ``B`` written out here, the source's ``M, C, K`` from
  its plant), ``np.linalg.solve`` at each frequency;
- the whole model (the source's mounts to the plate, 12 DOFs) by ``frequency_response``, and the
  stock path, ``control.frequency_response`` of its python-control state space (``vibss.statespace``);
- the errors of the coupled FRF: max over outputs of max |H - H_ref| / max |H_ref|.

Run: ``python benchmarks/bench_fbs.py [--quick]`` (quick: 40 mounts, 200 frequencies; full: 200
mounts, 1,000 frequencies); results in ``benchmarks/results/fbs.json``.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from benchmarks.machine import machine, timed  # noqa: E402
from vibss import (Body, ControlPoint, Foundation, Model, Mount, MountType, build_plant,  # noqa: E402
                   frequency_response, statespace)

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


def plain_numpy(source: Model, found: Foundation, points: dict[str, str]) -> np.ndarray:
    """(6 + 3n, 3, nf): the source's DOFs and the foundation's motions for the inputs ``engine.fz,
    mx, fy``, one ``np.linalg.solve`` of the coupled equations per frequency."""
    plant = build_plant(source, INPUTS, ["engine.z"])
    n = len(points)
    cog = np.asarray(source.bodies[0].cog)
    b = np.zeros((3 * n, 6))
    d0, d1 = np.zeros((3 * n, 3 * n)), np.zeros((3 * n, 3 * n))
    for i, m in enumerate(source.mounts):
        r = np.asarray(m.at) - cog
        b[3 * i:3 * i + 3, :3] = np.eye(3)
        b[3 * i:3 * i + 3, 3:] = [[0, r[2], -r[1]], [-r[2], 0, r[0]], [r[1], -r[0], 0]]   # u = t + rot x r
        d0[3 * i:3 * i + 3, 3 * i:3 * i + 3] = np.diag(m.type.stiffness)
        d1[3 * i:3 * i + 3, 3 * i:3 * i + 3] = np.diag(m.type.damping)
    rhs = np.zeros((6 + 3 * n, 3), dtype=complex)
    rhs[:6] = plant.F
    out = np.empty((6 + 3 * n, 3, found.frequency_hz.size), dtype=complex)
    eye = np.eye(3 * n)
    for k, f in enumerate(found.frequency_hz):
        s = 2j * np.pi * f
        d = d0 + s * d1
        y = found.receptance[:, :, k]
        a = np.block([[plant.K + s * plant.C + s**2 * plant.M, -b.T @ d], [-y @ d @ b, eye + y @ d]])
        out[:, :, k] = np.linalg.solve(a, rhs)
    return out


def bench(quick: bool) -> dict:
    """40 mounts and 200 frequencies (``quick``), else 200 and 1,000."""
    n, nf = (40, 200) if quick else (200, 1000)
    source, deck, whole, points = models(n)
    f = np.geomspace(1.0, 300.0, nf)
    t_found, found = timed(lambda: Foundation.from_model(deck, points, f), min_time=1.0)
    t_fbs, fbs = timed(lambda: frequency_response(source, INPUTS, OUTPUTS, foundation=found), min_time=1.0)
    t_np, ref_np = timed(lambda: plain_numpy(source, found, points), min_time=1.0)
    t_whole, ref = timed(lambda: frequency_response(whole, INPUTS, OUTPUTS + [f"p{i}.{a}" for i in range(n)
                                                                              for a in "xyz"], frequencies=f),
                         min_time=1.0)
    import control

    sys_ = statespace(whole, inputs=INPUTS, outputs=OUTPUTS[:-1])
    t_ss, stock = timed(lambda: control.frequency_response(sys_, 2 * np.pi * f), min_time=1.0)
    h_ss = np.asarray(stock.complex).reshape(len(OUTPUTS) - 1, len(INPUTS), nf)
    p = len(OUTPUTS)
    dofs = frequency_response(source, INPUTS, ["engine.x", "engine.y", "engine.z", "engine.rx", "engine.ry",
                                               "engine.rz"], foundation=found).response[:6]
    return {"mounts": n, "frequencies": nf, "interface_dofs": 3 * n,
            "foundation_from_model_s": t_found, "fbs_frf_s": t_fbs, "plain_numpy_coupled_s": t_np,
            "whole_model_frf_s": t_whole, "control_frequency_response_s": t_ss,
            "fbs_vs_whole_error": _err(fbs.response[:p + 3 * n], ref.response),
            "fbs_vs_plain_numpy_error": _err(np.concatenate([dofs, fbs.response[p:p + 3 * n]]), ref_np),
            "fbs_vs_control_error": _err(fbs.response[:p - 1], h_ss),
            "fbs_over_plain_numpy_time": t_fbs / t_np, "fbs_over_whole_time": t_fbs / t_whole,
            "machine": machine()}


if __name__ == "__main__":
    from run_all import main_one
    main_one("fbs")
