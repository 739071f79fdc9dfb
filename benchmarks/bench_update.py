"""Model updating, measured: ``vibss.update`` recovers mount rates from a noisy "measured" FRF.

Models: one 60 kg body (products of inertia) on 4 or 5 mounts at asymmetric points; the rates
updated are the 4 vertical rates (4 rates), or the vertical and one lateral rate of 5 mounts (10
rates). The measurement: receptances of 3 force inputs at the COG to 6 outputs (the COG and a
control point, x y z), 60 log-spaced frequencies from 2 to 40 Hz, computed at the true rates, times
``1 + noise * complex normal`` (seeded) for noise 0.1 %, 1 %, 3 %, 10 %. The start: every rate
off by a seeded factor in 0.7 ... 1.4.

Per size and noise level over several seeds: the RMS relative error of the updated rates, the
RMS of the stated relative standard deviations, and the fraction of rates within 3 stated std.
Time against the stock path in the same run: scipy ``least_squares`` on the same residual, start,
bounds and tolerances with its own finite-difference Jacobian (``jac='2-point'``), at 1 % noise.

Measured modes: the 4-mount layout's 6 modes at the same 6 outputs, 1 % noise on frequencies and
shape components, 6 rates (the 4 vertical, 2 lateral: the 4 lateral rates together are nearly
confounded in 6 modes, their stated std 100 % and more), the same statistics and timing.

Run: ``python benchmarks/bench_update.py``; results in ``benchmarks/results/update.json``; the
chart ``docs/figures/update_recovery.png``.
"""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

import numpy as np
from scipy.optimize import least_squares

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from benchmarks.machine import machine, timed  # noqa: E402
import vibss  # noqa: E402
from vibss import Body, ControlPoint, Model, Mount, MountType  # noqa: E402
from vibss.design.parameters import current_values, parameters_of  # noqa: E402
from vibss.measured.update import RATE_RANGE, _frf_problem, _modes_problem, _scan  # noqa: E402

FIGURE = Path(__file__).resolve().parent.parent / "docs" / "figures" / "update_recovery.png"
F = np.geomspace(2.0, 40.0, 60)
INPUTS = ["b.fx", "b.fy", "b.fz"]
OUTPUTS = ["b.x", "b.y", "b.z", "c.x", "c.y", "c.z"]
POINTS = [(0.5, 0.4, -0.2), (-0.45, 0.35, -0.25), (-0.5, -0.42, -0.2), (0.4, -0.38, -0.22), (0.05, 0.5, -0.3)]
NOISE = (0.001, 0.01, 0.03, 0.1)


def layout(n: int, k3: np.ndarray, k1: np.ndarray) -> Model:
    mounts = [Mount(f"m{i}", MountType(f"t{i}", [k1[i], 1.5e4, k3[i]], [30.0, 30.0, 50.0]), "b", at=POINTS[i])
              for i in range(n)]
    body = Body("b", 60.0, [[3.0, 0.2, 0.1], [0.2, 4.0, -0.15], [0.1, -0.15, 5.0]], cog=[0.02, -0.01, 0.05])
    return Model([body], mounts, [ControlPoint("c", "b", [0.3, 0.2, 0.1])], name=f"{n} mounts")


CASES = {"4 rates": (4, [f"m{i}.k3" for i in range(4)]),
         "10 rates": (5, [f"m{i}.k3" for i in range(5)] + [f"m{i}.k1" for i in range(5)])}
K3 = np.array([2e4, 3e4, 2.5e4, 3.5e4, 2.2e4])
K1 = np.array([1.2e4, 1.0e4, 1.4e4, 0.9e4, 1.1e4])


def _truth(names: list[str]) -> np.ndarray:
    return np.array([(K3 if n.endswith("k3") else K1)[int(n[1])] for n in names])


def _start(n: int, names: list[str], rng: np.random.Generator) -> Model:
    k3, k1 = K3.copy(), K1.copy()
    for name, factor in zip(names, rng.uniform(0.7, 1.4, len(names))):
        (k3 if name.endswith("k3") else k1)[int(name[1])] *= factor
    return layout(n, k3, k1)


def _data(n: int, noise: float, rng: np.random.Generator) -> vibss.FrequencyResponse:
    h = vibss.frequency_response(layout(n, K3, K1), INPUTS, OUTPUTS, frequencies=F).response
    h = h * (1 + noise * (rng.standard_normal(h.shape) + 1j * rng.standard_normal(h.shape)) / np.sqrt(2))
    return vibss.FrequencyResponse.from_measurement(F, h, INPUTS, OUTPUTS, "m/N")


def _modes(noise: float, rng: np.random.Generator) -> vibss.MeasuredModes:
    """The 4-mount layout's modes at 6 outputs, frequencies times ``1 + noise * normal``, shapes plus
    ``noise * |shape| * normal`` per component (the residuals' own scales)."""
    true = layout(4, K3, K1)
    md = vibss.modes(true)
    shapes = vibss.build_plant(true, ["b.fz"], OUTPUTS).Oq @ md.shapes
    shapes = shapes + noise * np.linalg.norm(shapes, axis=0) * rng.standard_normal(shapes.shape)
    return vibss.MeasuredModes(md.frequency_hz * (1 + noise * rng.standard_normal(md.frequency_hz.size)), shapes,
                               OUTPUTS)


def _stock(start: Model, data: vibss.FrequencyResponse | vibss.MeasuredModes, names: list[str]) -> tuple:
    """scipy least_squares on the same residual, from the same start (the same scan of a common
    factor for a frequency response) with a '2-point' Jacobian."""
    params = parameters_of(start, names)
    problem = (_frf_problem(start, data, params, None) if isinstance(data, vibss.FrequencyResponse)
               else _modes_problem(start, data, params, None))
    x0 = current_values(start, params)
    c = _scan(problem, x0, x0 / RATE_RANGE, x0 * RATE_RANGE) if isinstance(data, vibss.FrequencyResponse) else 1.0
    sol = least_squares(lambda x: problem.residual(x * x0, False)[0], np.full(x0.size, c), jac="2-point",
                        bounds=(1 / RATE_RANGE, RATE_RANGE), method="trf", xtol=1e-12, ftol=1e-12, gtol=1e-12,
                        max_nfev=200)
    return sol.x * x0, sol.nfev


def bench(quick: bool) -> dict:
    """Two sizes by four noise levels (3 seeds quick, 10 full); the timing against '2-point' at 1 %."""
    seeds = 3 if quick else 10
    out: dict = {}
    curves: dict = {}
    for case, (n, names) in CASES.items():
        truth = _truth(names)
        rows = []
        for noise in NOISE:
            rng = np.random.default_rng(32)
            err, std, inside = [], [], []
            for _ in range(seeds):
                data, start = _data(n, noise, rng), _start(n, names, rng)
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    r = vibss.update(start, data, names)
                err.append(r.estimate / truth - 1)
                std.append(r.standard_deviation / r.estimate)
                inside.append(np.abs(r.estimate - truth) < 3 * r.standard_deviation)
            e, s = float(np.sqrt(np.mean(np.square(err)))), float(np.sqrt(np.mean(np.square(std))))
            rows.append((noise, e, s))
            out[f"{case}, noise {100 * noise:g} %"] = {"rms_relative_error": e, "rms_stated_std": s,
                                                      "error_over_std": e / s,
                                                      "within_3_std": float(np.mean(inside))}
        curves[case] = rows
        rng = np.random.default_rng(7)
        data, start = _data(n, 0.01, rng), _start(n, names, rng)
        t_exact, r = timed(lambda: vibss.update(start, data, names), repeat=2)
        t_fd, (x_fd, nfev_fd) = timed(lambda: _stock(start, data, names), repeat=2)
        out[f"{case}, time at 1 % noise"] = {
            "update_s": t_exact, "least_squares_2point_s": t_fd, "speedup": t_fd / t_exact,
            "update_evaluations": r.evaluations, "2point_evaluations": nfev_fd,
            "update_error": float(np.max(np.abs(r.estimate / truth - 1))),
            "2point_error": float(np.max(np.abs(x_fd / truth - 1))),
            "2point_vs_update": float(np.max(np.abs(x_fd / r.estimate - 1)))}
    names = [f"m{i}.k3" for i in range(4)] + ["m0.k1", "m2.k1"]     # 4 lateral rates: nearly confounded
    truth = _truth(names)
    rng = np.random.default_rng(32)
    err, std = [], []
    for _ in range(seeds):
        data, start = _modes(0.01, rng), _start(4, names, rng)
        r = vibss.update(start, data, names)
        err.append(r.estimate / truth - 1)
        std.append(r.standard_deviation / r.estimate)
    e, s = float(np.sqrt(np.mean(np.square(err)))), float(np.sqrt(np.mean(np.square(std))))
    t_exact, r = timed(lambda: vibss.update(start, data, names), repeat=2)
    t_fd, (x_fd, nfev_fd) = timed(lambda: _stock(start, data, names), repeat=2)
    out["6 rates from 6 modes, noise 1 %"] = {
        "rms_relative_error": e, "rms_stated_std": s, "error_over_std": e / s,
        "within_3_std": float(np.mean(np.abs(np.array(err)) < 3 * np.array(std))),
        "update_s": t_exact, "least_squares_2point_s": t_fd, "speedup": t_fd / t_exact,
        "update_evaluations": r.evaluations, "2point_evaluations": nfev_fd,
        "2point_vs_update": float(np.max(np.abs(x_fd / r.estimate - 1)))}
    _figure(curves, seeds)
    return {**out, "frequencies": F.size, "channels": len(INPUTS) * len(OUTPUTS), "seeds": seeds,
            "figure": str(FIGURE.relative_to(FIGURE.parent.parent.parent)), "machine": machine()}


def _figure(curves: dict, seeds: int) -> None:
    from vibss.plotting._draw import new_figure

    fig = new_figure(6.5, 4.2)
    ax = fig.subplots()
    for c, (case, rows) in enumerate(curves.items()):
        noise, err, std = (np.array(x) for x in zip(*rows))
        ax.fill_between(100 * noise, 100 * std, 300 * std, color=f"C{c}", alpha=0.15,
                        label=f"{case}: stated std (dashed) to 3 std")
        ax.loglog(100 * noise, 100 * std, "--", color=f"C{c}", lw=1)
        ax.loglog(100 * noise, 100 * err, "o-", color=f"C{c}", label=f"{case}: RMS error over {seeds} seeds")
    ax.set_xlabel("measurement noise (relative, complex) [%]")
    ax.set_ylabel("rate error, RMS over rates and seeds [%]")
    ax.set_title("vibss.update: recovery of mount rates from a noisy FRF (18 channels, 60 frequencies)",
                 fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    top = max(300 * max(r[2] for r in rows) for rows in curves.values())
    ax.set_ylim(top=100 * top)                     # room above the data for the legend
    ax.legend(fontsize=7, loc="upper left")
    FIGURE.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(FIGURE, dpi=110)


if __name__ == "__main__":
    from run_all import main_one
    main_one("update")
