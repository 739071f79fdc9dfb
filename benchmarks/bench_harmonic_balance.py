"""Harmonic balance (``vibss.harmonic_balance``): accuracy against long time integrations, the cost
of a response curve, and its turning points against slow sweeps, in one run.

1. *Error against harmonics*: a 10 kg body on a mount whose one-sided stop carries it under its
   weight (4e4 N/m, 3 % damping, stop 4e4 N/m at 2 mm below), 40 N at 10 Hz (it leaves the stop
   each cycle): the first harmonic and the whole waveform over a period against the last period of
   a 60-period ``solve_ivp`` (DOP853, rtol 1e-12) from rest, for H = 1 ... 25 (4096 AFT samples so
   that only the truncation shows), beside the truncation estimate the result reports; the
   integration's time beside one harmonic-balance solve.
2. *Response curve*: a 20 kg box on four snubbered mounts (stops on every local z, 1 mm up and
   2 mm down, 10x the mount rate), ``b.fz`` 60 N and ``b.my`` 3 N m, ``points=300`` from 5 to
   40 Hz (about 600 continuation points: the curve bends), H = 9 (truncation estimate 1.1e-3, so
   ``tolerance=2e-3``), timed without stability, with Floquet's (``auto`` for stops) and with
   Hill's, and where the two disagree; the stock path's price per
   frequency (one steady state by ``solve_ivp`` of the 1-DOF model, 60 periods) for scale.
3. *Turning points against slow sweeps*: the 1-DOF snubber of the tests (10 Hz, stop at 1 mm,
   10 N): the jump frequencies of ``solve_ivp`` sweeps (0.01 Hz/s upwards from the resonant branch,
   0.02 Hz/s downwards from rest) against the turning points.

Figures: ``docs/figures/harmonic_balance_error.png`` and ``docs/figures/harmonic_balance_curve.png``.
Run: ``python benchmarks/bench_harmonic_balance.py [--quick]``.
"""

from __future__ import annotations

import sys
import time
import warnings
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from scipy.integrate import solve_ivp  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from machine import machine, stamp, timed  # noqa: E402

from vibss import Body, Model, Mount, MountType, VibssWarning, harmonic_balance, operating_point, symmetric  # noqa: E402

FIG = Path(__file__).resolve().parents[1] / "docs" / "figures"
G = 9.81


def _stop(x: float, gaps: tuple[float, float], ks: float) -> float:
    return ks * (max(x - gaps[1], 0.0) + min(x + gaps[0], 0.0))


def _steady(k: float, c: float, m: float, gaps: tuple[float, float], ks: float, force: float, f: float,
            gravity: bool, periods: int = 60, rtol: float = 1e-12) -> tuple[np.ndarray, np.ndarray]:
    """The last period of the 1-DOF stop oscillator from rest: phases [rad] and x [m]."""
    w, g = 2 * np.pi * f, G if gravity else 0.0

    def rhs(t: float, y: np.ndarray) -> list[float]:
        return [y[1], (-m * g + force * np.cos(w * t) - c * y[1] - k * y[0] - _stop(y[0], gaps, ks)) / m]

    T = 2 * np.pi / w
    sol = solve_ivp(rhs, [0.0, periods * T], [0.0, 0.0], method="DOP853", rtol=rtol, atol=1e-16, dense_output=True)
    tau = np.linspace(0.0, 2 * np.pi, 2048, endpoint=False)
    return tau, sol.sol((periods - 1) * T + tau / w)[0]


def error_vs_harmonics(quick: bool) -> dict[str, Any]:
    k, c, m, ks, gaps, force, f = 4e4, 126.0, 10.0, 4e4, (2e-3, 1.0), 40.0, 10.0
    model = Model([Body("b", m, [1.0, 1.0, 1.0])],
                  [Mount("m", MountType("snub", [k] * 3, [c] * 3, stops={"z": (gaps, ks)}), "b")], gravity=[0, 0, -G])
    t_ivp, (tau, x) = timed(lambda: _steady(k, c, m, gaps, ks, force, f, True), min_time=0.0, repeat=1)
    ref1 = 2 * np.mean(x * np.exp(-1j * tau))
    q0 = float(operating_point(model).q[2])
    rows = []
    for H in ([1, 3, 5, 9, 17] if quick else [1, 2, 3, 4, 5, 7, 9, 13, 17, 25]):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", VibssWarning)
            t_hb, r = timed(lambda H=H: harmonic_balance(model, {"b.fz": force}, ["b.z"], frequencies=[f],
                                                         harmonics=H, samples=4096, stability=False))
        Y = r.harmonics[0, :, 0]
        wave = q0 + np.real(np.exp(1j * np.outer(tau, np.arange(H + 1))) @ Y)
        rows.append({"harmonics": H, "first_harmonic_error": float(abs(Y[1] - ref1) / abs(ref1)),
                     "waveform_error": float(np.abs(wave - x).max() / np.abs(x - x.mean()).max()),
                     "truncation_estimate": float(r.truncation[0]), "seconds": t_hb})
    print("error against a 60-period DOP853 integration (rtol 1e-12, "
          f"{t_ivp:.2f} s): H, first harmonic, waveform, truncation estimate, s")
    for row in rows:
        print(f"  {row['harmonics']:3d}  {row['first_harmonic_error']:.1e}  {row['waveform_error']:.1e}  "
              f"{row['truncation_estimate']:.1e}  {row['seconds']:.3f}")
    _figure_error(rows)
    return {"integration_s": t_ivp, "rows": rows}


def _figure_error(rows: list[dict[str, Any]]) -> None:
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    H = [r["harmonics"] for r in rows]
    for key, label, mark in (("first_harmonic_error", "first harmonic", "o-"), ("waveform_error", "waveform (max)", "s-"),
                             ("truncation_estimate", "truncation estimate (reported)", "^--")):
        ax.loglog(H, [max(r[key], 1e-16) for r in rows], mark, label=label)
    ax.axhline(1e-6, color="0.5", lw=0.8, ls=":")
    ax.set_xlabel("harmonics kept H [-]")
    ax.set_ylabel("relative error against solve_ivp [-]")
    ax.set_title("Harmonic balance, preloaded one-sided stop, 10 Hz", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="lower left")
    stamp(fig)
    fig.tight_layout(rect=(0, 0.05, 1, 1))
    fig.savefig(FIG / "harmonic_balance_error.png", dpi=110)
    plt.close(fig)


def box() -> Model:
    t = MountType("snub", [2e4, 2e4, 5e4], [20.0, 20.0, 40.0], stops={"z": ((2e-3, 1e-3), 5e5)})
    return Model([Body("b", 20.0, [0.4, 0.5, 0.6])], symmetric(Mount("m", t, "b", at=[0.15, 0.1, 0.0])),
                 gravity=[0, 0, -G], name="box")


def response_curve(quick: bool) -> dict[str, Any]:
    model, inputs, outputs = box(), {"b.fz": 60.0, "b.my": 3.0}, ["b.z", "b.ry", "ground.fz"]

    def run(stability: bool | str) -> Any:
        return harmonic_balance(model, inputs, outputs, frequencies=(5.0, 40.0), harmonics=9, points=300,
                                stability=stability, tolerance=2e-3)
    t_plain, r = timed(lambda: run(False), min_time=0.0, repeat=1 if quick else 2)
    t_hill, rh = timed(lambda: run("hill"), min_time=0.0, repeat=1 if quick else 2)
    t_floquet, r = timed(lambda: run(True), min_time=0.0, repeat=1 if quick else 2)      # auto: Floquet (stops)
    k, c, m, ks = 4e4, 40.0, 10.0, 4e4
    t_ivp, _ = timed(lambda: _steady(k, c, m, (1e-3, 1e-3), ks, 10.0, 12.0, False, rtol=1e-8), min_time=0.0, repeat=1)
    fig = r.plot(outputs=["b.z", "b.ry"])
    fig.axes[0].set_title(f"box on four snubbered mounts: {r.frequencies.size} points, H = 9", fontsize=10)
    fig.get_layout_engine().set(rect=(0, 0.05, 1, 0.95))     # room for the machine line
    stamp(fig)
    fig.savefig(FIG / "harmonic_balance_curve.png", dpi=110)
    out = {"points": int(r.frequencies.size), "seconds": t_plain, "seconds_with_hill": t_hill,
           "seconds_with_floquet": t_floquet, "methods_disagree_at": int(np.sum(r.stable != rh.stable)),
           "growth_difference_max": float(np.abs(r.growth - rh.growth).max()),
           "growth_max": float(np.abs(rh.growth).max()),
           "turning_points_hz": r.turning_points.tolist(), "unstable_points": int(np.sum(~r.stable)),
           "worst_truncation": float(r.truncation.max()), "worst_residual": float(r.residual.max()),
           "solve_ivp_steady_state_per_frequency_s": t_ivp}
    print(f"response curve of the box (12 DOF, 4 nonlinear axes, H = 9): {out['points']} points in {t_plain:.2f} s, "
          f"{t_floquet:.2f} s with Floquet's stability (auto), {t_hill:.2f} s with Hill's (they disagree at "
          f"{out['methods_disagree_at']} points); one steady state by solve_ivp (1 DOF, 60 periods) "
          f"{t_ivp:.2f} s, so {out['points']} of them ~{out['points'] * t_ivp:.0f} s; folds {out['turning_points_hz']}")
    return out


def curved_cabinet(quick: bool) -> dict[str, Any]:
    """The snubbed cabinet's curve (PCHIP mounts and stops, 12 nonlinear axes, H = 11, the report's
    0.25 g base sine): its response curve without stability, with Floquet's (auto: Magnus sub-steps on
    the curves) and with Hill's; where they disagree and by how much their growth rates differ, and
    Floquet's growth against its own run at 2,048 sub-steps a period."""
    import vibss
    from vibss.io.harmonicfile import harmonic_balance_arguments
    import vibss.nonlinear.hb.floquet as fq

    model = vibss.load_example("snubbed_cabinet")
    args = harmonic_balance_arguments(model.settings["harmonic_balance"], model.excitations)

    def run(stability: bool | str) -> Any:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", VibssWarning)
            return harmonic_balance(model, **(args | {"stability": stability}))
    reps = 1 if quick else 2
    t_plain, _ = timed(lambda: run(False), min_time=0.0, repeat=reps)
    t_floquet, r = timed(lambda: run(True), min_time=0.0, repeat=reps)
    t_hill, rh = timed(lambda: run("hill"), min_time=0.0, repeat=reps)
    first = fq.FIRST_SUBSTEPS
    fq.FIRST_SUBSTEPS = fq.MAX_SUBSTEPS // 2
    try:
        fine = run(True)
    finally:
        fq.FIRST_SUBSTEPS = first
    out = {"points": int(r.frequencies.size), "seconds": t_plain, "seconds_with_floquet": t_floquet,
           "seconds_with_hill": t_hill, "methods_disagree_at": int(np.sum(r.stable != rh.stable)),
           "growth_difference_max": float(np.abs(r.growth - rh.growth).max()),
           "growth_max": float(np.abs(rh.growth).max()),
           "floquet_against_2048_substeps": float(np.max(np.abs(r.growth - fine.growth)
                                                         / np.maximum(np.abs(fine.growth), 1e-300))),
           "unstable_points": int(np.sum(~r.stable))}
    print(f"snubbed cabinet (curves and stops, 12 nonlinear axes, H = 11): {out['points']} points in {t_plain:.2f} s, "
          f"{t_floquet:.2f} s with Floquet's stability (Magnus sub-steps), {t_hill:.2f} s with Hill's; they disagree "
          f"at {out['methods_disagree_at']} points, growth rates differ by up to {out['growth_difference_max']:.3g} "
          f"1/s of {out['growth_max']:.3g} (Hill's truncation); Floquet's against 2,048 sub-steps a period "
          f"{out['floquet_against_2048_substeps']:.1e} (relative)")
    return out


def _sweep(f0: float, f1: float, rate: float, y0: list[float]) -> tuple[np.ndarray, np.ndarray]:
    k, c, m, ks, gap, force = 4e4, 40.0, 10.0, 4e4, 1e-3, 10.0
    duration, slope = abs(f1 - f0) / rate, np.sign(f1 - f0) * rate

    def rhs(t: float, y: np.ndarray) -> list[float]:
        phase = 2 * np.pi * (f0 * t + 0.5 * slope * t * t)
        return [y[1], (force * np.cos(phase) - c * y[1] - k * y[0] - _stop(y[0], (gap, gap), ks)) / m]

    sol = solve_ivp(rhs, [0.0, duration], y0, rtol=1e-7, atol=1e-11, dense_output=True)
    per = 1.0 / max(f0, f1)
    edges = np.arange(0.0, duration - 2 * per, 2 * per)
    t = edges[:, None] + np.linspace(0.0, 2 * per, 60)[None, :]
    return f0 + slope * (edges + per), np.abs(sol.sol(t.ravel())[0].reshape(t.shape)).max(axis=1)


def turning_points() -> dict[str, Any]:
    t = MountType("snub", [4e4] * 3, [40.0] * 3, stops={"z": (1e-3, 4e4)})
    model = Model([Body("b", 10.0, [1.0, 1.0, 1.0])], [Mount("m", t, "b")])
    t_hb, r = timed(lambda: harmonic_balance(model, {"b.fz": 10.0}, ["b.z"], frequencies=(8.0, 16.0), harmonics=7,
                                             points=100, stability=False), min_time=0.0, repeat=1)
    upper, lower = float(r.turning_points.max()), float(r.turning_points.min())
    b = int(np.argmin(np.abs(r.frequencies[:int(r.turning_index.min())] - 12.3)))
    Y, k = r.harmonics[0, :, b], np.arange(r.harmonics.shape[1])
    state = [float(np.sum(Y).real), float(np.sum(1j * k * r.omega[b] * Y).real)]
    t0 = time.perf_counter()
    f, a = _sweep(float(r.frequencies[b]), 13.0, 0.01, state)
    up = float(f[int(np.argmin(np.diff(a)))])
    f, a = _sweep(11.9, 10.8, 0.02, [0.0, 0.0])
    down = float(f[int(np.argmax(np.diff(a)))])
    t_sweeps = time.perf_counter() - t0
    out = {"upper_fold_hz": upper, "jump_down_hz": up, "upper_error": up / upper - 1,
           "lower_fold_hz": lower, "jump_up_hz": down, "lower_error": down / lower - 1,
           "harmonic_balance_s": t_hb, "sweeps_s": t_sweeps}
    print(f"turning points {upper:.4f} / {lower:.4f} Hz ({t_hb:.2f} s); slow sweeps jump at {up:.4f} / {down:.4f} Hz "
          f"({100 * out['upper_error']:+.2f} %, {100 * out['lower_error']:+.2f} %; {t_sweeps:.1f} s)")
    return out


def bench(quick: bool) -> dict:
    """Error against harmonics, the 300-point curve and the turning points (``quick``: fewer H)."""
    return {"machine": machine(), "error_vs_harmonics": error_vs_harmonics(quick),
            "response_curve": response_curve(quick), "curves_cabinet": curved_cabinet(quick),
            "turning_points": turning_points()}


if __name__ == "__main__":
    from run_all import main_one

    main_one("harmonic_balance")
