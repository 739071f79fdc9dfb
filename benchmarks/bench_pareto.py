"""Speed against accuracy: every method measured in the same run, on the same problem, against an
exact or converged reference (Pareto charts), plus cost against model size (scaling).

Figures (``docs/figures/``):

- ``pareto_time_shock.png``, ``pareto_time_sweep.png`` — error of the time response against CPU
  time, one curve per method over its step (fixed-step methods) or tolerance (solve_ivp):
  ``control.forced_response``, vibss's exact modal FOH, solve_ivp RK45 / DOP853 / Radau / BDF /
  LSODA, Newmark average acceleration and central difference. Shock: a rectangular force pulse
  whose edges fall between samples; the reference is the modal FOH, exact for piecewise-linear
  inputs whatever the step, checked against a 2nd-order closed form at a finer step. Sweep: a
  smooth linear sine sweep; the reference is the modal FOH at a 1/128 step (shown converging)
  and checked against DOP853 at rtol = 1e-12.
- ``pareto_frf.png`` — error of the frequency response against CPU time for zeta = 0.001 and 0.05:
  direct solves, ``control.frequency_response`` on the plain physical realization and on vibss's
  scaled modal one, modal superposition (all modes, fewer modes with and without the static
  residual correction), complex modes, the sparse (banded LU) direct solve. Reference: direct
  solve with iterative refinement whose
  residual is computed in extended precision.
- ``pareto_eigen.png`` — time and damping-ratio error of dense ``eigh``, sparse shift-invert
  (lowest modes), ``control.poles`` on the physical state matrix, and ``vibss.damped_modes``, on a
  classically damped model where ``zeta_i = beta omega_i / 2`` exactly.
- ``scaling.png`` — cost against number of bodies (log-log) for assembly, modes, FRF and time
  response, with the stock python-control path beside vibss's until it becomes too slow; the
  sparse FRF runs on the sparse plant up to 1,000 bodies (no dense matrix is formed).

Run: ``python benchmarks/bench_pareto.py [--quick]`` (``make bench`` runs all).
"""

from __future__ import annotations

import argparse
import json
import sys
from dataclasses import replace
from pathlib import Path
from typing import Any

import control
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import scipy.linalg as sl  # noqa: E402
from scipy.integrate import solve_ivp  # noqa: E402

sys.path.insert(0, str(Path(__file__).parent))
from machine import machine, stamp, timed  # noqa: E402
from models import chain_model  # noqa: E402

from vibss import assemble, damped_modes, modes  # noqa: E402
from vibss.frequency import kernels as fm  # noqa: E402
from vibss.time import kernels as tm  # noqa: E402
from vibss.model.excitation import Excitation, Rectangular, SineSweep  # noqa: E402
from vibss.time.integrators import central_difference_method, critical_step, newmark_method  # noqa: E402
from vibss.reduction.krylov import sparse_plant  # noqa: E402
from vibss.linear.plant.build import build_plant  # noqa: E402
from vibss.linear.statespace import statespace  # noqa: E402
from vibss.time.api import simulate  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
FIG = ROOT / "docs" / "figures"
OUT = Path(__file__).parent / "results" / "pareto.json"
IVP = ("RK45", "DOP853", "Radau", "BDF", "LSODA")


def rel_err(y: np.ndarray, ref: np.ndarray) -> float:
    """max |y - ref| / max |ref| (inf for a non-finite y)."""
    if not np.all(np.isfinite(y)):
        return np.inf
    return float(np.abs(y - ref).max() / np.abs(ref).max())


def lsoda_method(rtol: float) -> Any:
    """A ``simulate`` method callable: solve_ivp LSODA on vibss's z-only realization, restarted at
    every breakpoint, with the Jacobian as a callable. (``method="ivp", solver="LSODA"`` fails in
    scipy 1.17 because vibss.time.kernels.run_ivp passes the Jacobian as an array, which LSODA
    rejects; reported to the time module's owner.)"""
    def run(job: Any) -> tuple[np.ndarray, str]:
        r = tm.realization(tm.prepare(job.plant))
        n, ts = job.plant.n, job.time
        x = np.zeros(r.A.shape[0])
        x[:n], x[n:2 * n] = job.q0, job.v0
        u = lambda t: np.array([float(f(np.asarray(t))) for f in job.funcs])  # noqa: E731
        cuts = np.concatenate([[0.0], np.sort(job.breakpoints[(job.breakpoints > 0)
                                                              & (job.breakpoints < ts[-1])]), [ts[-1]]])
        X = np.zeros((len(ts), len(x)))
        X[0] = x
        for a, b in zip(cuts[:-1], cuts[1:]):
            lo, hi = np.nextafter(a, np.inf), np.nextafter(b, -np.inf)
            inside = np.flatnonzero((ts > a) & (ts <= b))
            te = ts[inside] if inside.size and ts[inside[-1]] == b else np.append(ts[inside], b)
            sol = solve_ivp(lambda t, x: r.A @ x + r.B @ u(min(max(t, lo), hi)), (a, b), x,
                            method="LSODA", t_eval=te, rtol=rtol, atol=1e-15, jac=lambda t, x: r.A)
            X[inside] = sol.y.T[:inside.size]
            x = sol.y[:, -1]
        tr = np.nextafter(ts, np.inf)
        tr[-1] = np.nextafter(ts[-1], -np.inf)
        U = np.array([f(tr) for f in job.funcs]).T
        return X @ r.C.T + U @ r.D.T, "LSODA"
    return run


def physical_ss(plant: Any) -> control.StateSpace:
    """The stock realization a python-control user writes: A = [[0, I], [-M^-1 K, -M^-1 C]]."""
    return statespace(plant, realization="physical", balance=False)


# ---------------------------------------------------------------------------------------------
# time response

def _time_case(kind: str, quick: bool) -> dict[str, Any]:
    model = chain_model(3 if quick else 5, "classical", zeta=0.02, seed=2)
    plant = build_plant(model, ["b0.fz"], ["b0.z", "b1.x", f"b{len(model.bodies) - 1}.y"])
    if kind == "shock":
        exc = Excitation("shock", "force", "b0", Rectangular(100.0, 0.01234, 0.00731), dof="z")
        t_end, dt_out = 0.15, 1e-3
    else:
        exc = Excitation("sweep", "force", "b0", SineSweep(5.0, 250.0, 100.0, 100.0, 0.15), dof="z")
        t_end, dt_out = 0.15, 1e-3
    w = np.sqrt(np.maximum(sl.eigh(plant.K, plant.M, eigvals_only=True), 0))
    dtc = critical_step(plant)
    run = lambda method, dt, **kw: simulate(plant, [exc], t_end=t_end, dt=dt,  # noqa: E731
                                            method=method, **kw).outputs
    checks = {}
    if kind == "shock":
        # modal FOH is exact for this piecewise-linear input at any step
        t_ref, ref = timed(lambda: run("modal", dt_out), min_time=0)
        checks["modal_dt_vs_modal_dt/16"] = rel_err(run("modal", dt_out / 16)[:, ::16], ref)
        checks["DOP853_rtol1e-12_vs_ref"] = rel_err(run("ivp", dt_out, solver="DOP853", rtol=1e-12), ref)
        ref_name = "vibss modal FOH (exact for PWL input)"
    else:
        # smooth input: DOP853 at rtol 1e-13 (exact input values), checked against Richardson-
        # extrapolated modal FOH (second order in dt) at dt/64 and dt/128
        t_ref, ref = timed(lambda: run("ivp", dt_out, solver="DOP853", rtol=1e-13), min_time=0)
        y64 = run("modal", dt_out / 64)[:, ::64]
        y128 = run("modal", dt_out / 128)[:, ::128]
        checks["modal_dt/64_vs_ref"] = rel_err(y64, ref)
        checks["modal_dt/128_vs_ref"] = rel_err(y128, ref)
        checks["modal_Richardson(dt/64,dt/128)_vs_ref"] = rel_err((4 * y128 - y64) / 3, ref)
        ref_name = "DOP853 rtol 1e-13 (= Richardson-extrapolated modal FOH)"
    ks = [1, 4] if quick else [1, 2, 4, 8, 16, 32]
    curves: dict[str, list[tuple[float, float, str]]] = {}
    fixed = {"modal (vibss, exact FOH)": "modal", "control.forced_response": "forced_response",
             "Newmark avg. accel.": newmark_method, "central difference": central_difference_method}
    for label, method in fixed.items():
        for k in ks:
            dt = dt_out / k
            if method is central_difference_method and dt >= dtc:
                curves.setdefault("central difference: unstable steps", []).append((np.nan, np.inf, f"dt={dt:.3g}"))
                continue
            t, y = timed(lambda: run(method, dt))
            curves.setdefault(label, []).append((t, rel_err(y[:, ::k], ref), f"dt={dt:.3g}"))
    tols = [1e-3, 1e-6] if quick else [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10]
    for solver in IVP:
        for tol in tols:
            if solver == "LSODA":
                t, y = timed(lambda: run(lsoda_method(tol), dt_out), repeat=1 if quick else 2)
            else:
                t, y = timed(lambda: run("ivp", dt_out, solver=solver, rtol=tol), repeat=1 if quick else 2)
            curves.setdefault(f"solve_ivp {solver}", []).append((t, rel_err(y, ref), f"rtol={tol:g}"))
    return {"kind": kind, "dofs": plant.n, "omega_max_rad_s": float(w.max()),
            "central_difference_limit_s": dtc, "dt_out_s": dt_out, "t_end_s": t_end,
            "reference": ref_name, "reference_time_s": t_ref, "reference_checks": checks, "curves": curves}


def _pareto_plot(ax: Any, curves: dict[str, list[tuple[float, float, str]]], floor: float = 1e-16) -> None:
    for label, pts in curves.items():
        pts = [p for p in pts if np.isfinite(p[0])]
        if not pts:
            continue
        t = [p[0] for p in pts]
        e = [min(max(p[1], floor), 1e3) for p in pts]
        ax.loglog(t, e, "o-", ms=3, label=label)
    ax.set_xlabel("CPU time [s] (1 thread)")
    ax.set_ylabel("max relative error")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)


def time_pareto(quick: bool) -> dict[str, Any]:
    res = {}
    for kind in ("shock", "sweep"):
        r = _time_case(kind, quick)
        res[kind] = r
        fig, ax = plt.subplots(figsize=(8, 5.5))
        _pareto_plot(ax, r["curves"])
        title = ("rectangular force pulse, edges between samples" if kind == "shock"
                 else "linear sine sweep 5-250 Hz")
        ax.set_title(f"Time response, {title}: {r['dofs']} DOF, 0.15 s, outputs every 1 ms\n"
                     f"reference: {r['reference']}; errors floored at 1e-16", fontsize=9)
        bad = [p[2] for p in r["curves"].get("central difference: unstable steps", [])]
        if bad:
            ax.text(0.02, 0.02, "central difference unstable (dt > 2/omega_max = "
                    f"{r['central_difference_limit_s']:.3g} s) at " + ", ".join(bad),
                    transform=ax.transAxes, fontsize=7, color="C3")
        stamp(fig)
        fig.tight_layout(rect=(0, 0.045, 1, 1))
        fig.savefig(FIG / f"pareto_time_{kind}.png", dpi=110)
        plt.close(fig)
        print(f"time/{kind}: {r['dofs']} DOF, reference checks {r['reference_checks']}")
        for label, pts in r["curves"].items():
            print("  " + label + ": " + ", ".join(f"{p[2]} {p[0]:.3g}s {p[1]:.1e}" for p in pts))
    return res


# ---------------------------------------------------------------------------------------------
# frequency response

def reference_frf(plant: Any, s: np.ndarray, steps: int = 3) -> np.ndarray:
    """Direct solve with iterative refinement; residual in extended (long double) precision."""
    out = np.empty((len(plant.outputs), len(plant.inputs), s.size), complex)
    ld = np.clongdouble
    for i, si in enumerate(s):
        D = plant.K + si * plant.C + si**2 * plant.M
        Dl = (plant.K.astype(np.longdouble) + ld(si) * plant.C.astype(np.longdouble)
              + ld(si) ** 2 * plant.M.astype(np.longdouble))
        lu = sl.lu_factor(D)
        x = sl.lu_solve(lu, plant.F.astype(complex))
        xl = x.astype(ld)
        for _ in range(steps):
            r = plant.F.astype(ld) - Dl @ xl
            xl = xl + sl.lu_solve(lu, r.astype(complex)).astype(ld)
        out[:, :, i] = (plant.Oq.astype(ld) @ xl).astype(complex)
    return out


def truncated_modal(plant: Any, s: np.ndarray, r: int, residual: bool,
                    w2: np.ndarray, phi: np.ndarray) -> np.ndarray:
    """Receptance from the lowest ``r`` modes (classical damping), optionally + static residual."""
    ph = phi[:, :r]
    beta = np.diag(ph.T @ plant.C @ ph)
    L, R = plant.Oq @ ph, ph.T @ plant.F                 # (p, r), (r, m)
    d = 1.0 / (w2[None, :r] + s[:, None] * beta[None] + s[:, None] ** 2)      # (nf, r)
    H = np.einsum("pr,fr,rm->pmf", L, d, R)
    if residual:
        static = plant.Oq @ sl.solve(plant.K, plant.F, assume_a="pos") - L @ (R / w2[:r, None])
        H += static[:, :, None]
    return H


def frf_pareto(quick: bool) -> dict[str, Any]:
    nb = 6 if quick else 25
    res: dict[str, Any] = {}
    fig, axes = plt.subplots(1, 2, figsize=(12, 5.5))
    for ax, zeta in zip(axes, (1e-3, 5e-2)):
        model = chain_model(nb, "classical", zeta=zeta, seed=4)
        outs = [f"b{i}.{d}" for i in (0, nb // 2, nb - 1) for d in ("x", "z")]
        plant = build_plant(model, ["b0.fz", f"b{nb // 2}.fx"], outs)
        w2, phi = sl.eigh(plant.K, plant.M)
        w = np.sqrt(w2)
        f = np.concatenate([np.geomspace(w[0] / 4, w[-1] * 1.2, 300 if quick else 1000),
                            w[: len(w) // 2]])            # half the resonances exactly
        s = 1j * np.sort(f)
        t_ref, ref = timed(lambda: reference_frf(plant, s), min_time=0)
        sysp = physical_ss(plant)
        sysm = statespace(plant)
        ct_resp = lambda sys: np.asarray(control.frequency_response(sys, np.abs(s)).complex)  # noqa: E731
        methods = {
            "direct solve (numpy, batched)": lambda: fm.direct(plant, s),
            "control.frequency_response, physical A": lambda: ct_resp(sysp),
            "control.frequency_response, vibss modal realization": lambda: ct_resp(sysm),
            "modal, all modes (vibss)": lambda: fm.modal(plant, s),
            "complex modes (vibss)": lambda: fm.complex_modal(plant, s),
            "sparse direct, banded LU (vibss)": lambda: fm.sparse(replace(plant), s),
        }
        pts: dict[str, list[tuple[float, float, str]]] = {}
        for label, fn in methods.items():
            t, H = timed(fn)
            pts[label] = [(t, rel_err(np.asarray(H).reshape(ref.shape), ref), "")]
        n = plant.n
        for res_corr in (False, True):
            label = "modal, lowest r modes" + (" + residual" if res_corr else "")
            for frac in (8, 4, 2, 1):
                r = max(1, n // frac)
                t, H = timed(lambda: truncated_modal(plant, s, r, res_corr, w2, phi))
                t_eig, _ = timed(lambda: sl.eigh(plant.K, plant.M, subset_by_index=[0, r - 1]))
                band = np.abs(s) <= w[r - 1] * 0.5 if r < n else np.ones(s.size, bool)
                pts.setdefault(label, []).append((t + t_eig, rel_err(H[:, :, band], ref[:, :, band]),
                                                  f"r={r}"))
        res[f"zeta={zeta:g}"] = {"dofs": n, "frequencies": s.size, "reference_s": t_ref, "curves": pts}
        _pareto_plot(ax, pts)
        ax.set_title(f"FRF, zeta = {zeta:g}: {n} DOF, 2 inputs x 6 outputs, {s.size} frequencies\n"
                     "truncated modal: error below half the highest kept mode", fontsize=9)
        print(f"frf zeta={zeta:g}, {n} DOF, {s.size} freqs:")
        for label, p in pts.items():
            print("  " + label + ": " + ", ".join(f"{q[2]} {q[0]:.3g}s {q[1]:.1e}" for q in p))
    stamp(fig)
    fig.tight_layout(rect=(0, 0.045, 1, 1))
    fig.savefig(FIG / "pareto_frf.png", dpi=110)
    plt.close(fig)
    return res


# ---------------------------------------------------------------------------------------------
# eigen-analysis

def _beta(plant: Any) -> float:
    beta = float(np.sum(plant.C * plant.K) / np.sum(plant.K * plant.K))
    assert np.abs(plant.C - beta * plant.K).max() <= 1e-12 * np.abs(plant.C).max()
    return beta


def eigen_bench(quick: bool) -> dict[str, Any]:
    nb = 10 if quick else 60
    res: dict[str, Any] = {}
    fig, axes = plt.subplots(1, 2, figsize=(12, 5))
    for scale, ls in (("nice", "-"), ("bad", "--")):
        model = chain_model(nb, "classical", zeta=1e-4, seed=5, scale=scale)
        a = assemble(model, sparse=False)
        a_sp = assemble(model, sparse=True)
        plant = build_plant(model, ["b0.fz"], ["b0.z"])
        beta = _beta(plant)
        t_eigh, md = timed(lambda: modes(a, method="dense"))
        w = md.omega
        zeta_exact = beta * w / 2
        k = min(30, a.n // 2)
        t_si, low = timed(lambda: modes(a_sp, n_modes=k, method="shift-invert"))
        sysp = physical_ss(plant)
        t_poles, poles = timed(lambda: control.poles(sysp))
        t_dm, dm = timed(lambda: damped_modes(a, undamped=md))
        t_eigA, lam = timed(lambda: sl.eig(sysp.A, right=False))   # LAPACK geev
        def zeta_err(p: np.ndarray) -> np.ndarray:
            # C = beta K makes every pole satisfy zeta = beta |p| / 2 exactly: an invariant that
            # does not depend on how accurate the method's omega is
            p = p[p.imag > 0]
            p = p[np.argsort(np.abs(p))]
            zz, exact = -p.real / np.abs(p), beta * np.abs(p) / 2
            return np.abs(zz - exact) / exact
        e_ct, e_dm = zeta_err(np.asarray(poles)), zeta_err(dm.poles)
        res[scale] = {"dofs": a.n, "beta": beta,
                      "zeta_range": [float(zeta_exact[w > 0].min()), float(zeta_exact.max())],
                      "time_s": {"dense eigh (all)": t_eigh, f"shift-invert (lowest {k})": t_si,
                                 "control.poles (physical A)": t_poles, "scipy eig(A)": t_eigA,
                                 "vibss damped_modes (after eigh)": t_dm},
                      "max_rel_freq_diff_shift_invert": float(np.max(np.abs(low.omega - w[:k])[w[:k] > 0]
                                                                     / w[:k][w[:k] > 0])),
                      "elastic_modes_reported_as_rigid": int(np.sum(w == 0)),
                      "lowest_shift_invert_omega": float(low.omega[0]),
                      "max_rel_zeta_error": {"control.poles": float(e_ct.max()),
                                             "vibss damped_modes": float(e_dm.max())}}
        axes[0].loglog(w[: len(e_ct)] / (2 * np.pi), np.maximum(e_ct, 1e-17), "o" + ls, ms=3,
                       label=f"control.poles, {scale} scale")
        axes[0].loglog(w[: len(e_dm)] / (2 * np.pi), np.maximum(e_dm, 1e-17), "s" + ls, ms=3,
                       label=f"vibss damped_modes, {scale} scale")
        print(f"eigen {scale}: {a.n} DOF, times {res[scale]['time_s']}, zeta errors {res[scale]['max_rel_zeta_error']}")
    axes[0].set_xlabel("natural frequency [Hz]")
    axes[0].set_ylabel("relative error of zeta (exact: zeta = beta |p| / 2 for C = beta K)")
    axes[0].set_title(f"Damping ratios, C = beta K, zeta = 1e-4 at mode 1, {res['nice']['dofs']} DOF", fontsize=9)
    axes[0].grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=7)
    labels = list(res["nice"]["time_s"])
    x = np.arange(len(labels))
    for i, scale in enumerate(("nice", "bad")):
        axes[1].bar(x + 0.4 * i, [res[scale]["time_s"][l] for l in labels], 0.4, label=f"{scale} scale")
    axes[1].set_xticks(x + 0.2, labels, rotation=20, ha="right", fontsize=7)
    axes[1].set_yscale("log")
    axes[1].set_ylabel("CPU time [s]")
    axes[1].set_title("Eigen-analysis cost", fontsize=9)
    axes[1].legend(fontsize=7)
    stamp(fig)
    fig.tight_layout(rect=(0, 0.045, 1, 1))
    fig.savefig(FIG / "pareto_eigen.png", dpi=110)
    plt.close(fig)
    return res


# ---------------------------------------------------------------------------------------------
# scaling

STOCK_LIMIT_DOF = 600
"""Largest model the stock python-control paths are run on (they grow as (2n)^2 per step/frequency
with a Python loop, and as (2n)^3 for expm / Hessenberg: 600 DOF already takes seconds)."""


DIRECT_LIMIT_BODIES = 100
"""Largest model of the scaling run on which the direct FRF (one dense complex LU per frequency,
O(n^3) each) is timed."""


def scaling(quick: bool) -> dict[str, Any]:
    sizes = [1, 3, 10, 30] if quick else [1, 3, 10, 30, 100, 300, 1000]
    dense_limit = 60 if quick else 300         # bodies: dense eigh / modal FRF / modal time
    nf, nsteps = 200, 2000
    rows = []
    for nb in sizes:
        model = chain_model(nb, "classical", zeta=0.01, seed=6)
        row: dict[str, Any] = {"bodies": nb, "dofs": 6 * nb}
        row["assembly (vibss, sparse)"], _ = timed(lambda: assemble(model, sparse=True))
        a_sp = assemble(model, sparse=True)
        k = min(20, 6 * nb - 1)
        if 6 * nb > 60:
            row["lowest 20 modes (shift-invert)"], _ = timed(lambda: modes(a_sp, n_modes=k, method="shift-invert"))
        if nb > dense_limit:       # no dense matrices: the sparse plant and the banded FRF only
            sparse_p = sparse_plant(model, ["b0.fz"], [f"b{nb - 1}.{d}" for d in ("x", "y", "z", "rx", "ry", "rz")])
            row["FRF sparse direct (vibss)"], _ = timed(lambda: fm.sparse(replace(sparse_p), 1j * np.geomspace(1.0, 6000.0, nf)))
        if nb <= dense_limit:
            a = assemble(model, sparse=False)
            row["all modes (dense eigh)"], _ = timed(lambda: modes(a, method="dense"))
            plant = build_plant(model, ["b0.fz"], [f"b{nb - 1}.{d}" for d in ("x", "y", "z", "rx", "ry", "rz")])
            s = 1j * np.geomspace(1.0, 6000.0, nf)
            row["FRF modal (vibss)"], _ = timed(lambda: fm.modal(plant, s))
            row["FRF sparse direct (vibss)"], _ = timed(lambda: fm.sparse(replace(plant), s))
            if nb <= DIRECT_LIMIT_BODIES:
                row["FRF direct (vibss)"], _ = timed(lambda: fm.direct(plant, s), repeat=1)
            exc = Excitation("p", "force", "b0", Rectangular(100.0, 0.0123, 0.01), dof="z")
            row["time modal (vibss)"], _ = timed(lambda: simulate(plant, [exc], t_end=nsteps * 2e-4, dt=2e-4,
                                                                  method="modal"), repeat=1)
            if plant.n <= STOCK_LIMIT_DOF:
                sysp = physical_ss(plant)
                row["FRF control.frequency_response (stock)"], _ = timed(
                    lambda: control.frequency_response(sysp, np.abs(s)), repeat=1)
                tt = np.arange(nsteps + 1) * 2e-4
                u = exc.function.value(tt)
                row["time control.forced_response (stock)"], _ = timed(
                    lambda: control.forced_response(sysp, timepts=tt, inputs=u), repeat=1)
        rows.append(row)
        print("scaling " + ", ".join(f"{k}: {v:.3g}" for k, v in row.items()))
    fig, axes = plt.subplots(1, 3, figsize=(14, 4.8))
    groups = {"assembly and modes": ("assembly", "modes"), f"FRF, {nf} frequencies, 1 in / 6 out": ("FRF",),
              f"time response, {nsteps} steps, 1 in / 6 out": ("time",)}
    for ax, (title, keys) in zip(axes, groups.items()):
        names = sorted({k for r in rows for k in r if any(k.startswith(x) or x in k for x in keys)
                        and k not in ("bodies", "dofs")})
        for name in names:
            xs = [r["bodies"] for r in rows if name in r]
            ys = [r[name] for r in rows if name in r]
            ax.loglog(xs, ys, "o-" if "stock" not in name else "x--", ms=4, label=name)
        ax.set_xlabel("bodies (6 DOF each)")
        ax.set_ylabel("CPU time [s]")
        ax.set_title(title, fontsize=9)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle(f"Scaling: stock python-control stopped above {STOCK_LIMIT_DOF} DOF (too slow), direct FRF "
                 f"above {6 * DIRECT_LIMIT_BODIES} DOF, dense eigh / modal FRF / modal time above "
                 f"{6 * dense_limit} DOF", fontsize=9)
    stamp(fig)
    fig.tight_layout(rect=(0, 0.045, 1, 1))
    fig.savefig(FIG / "scaling.png", dpi=110)
    plt.close(fig)
    return {"rows": rows, "stock_limit_dof": STOCK_LIMIT_DOF, "dense_limit_bodies": dense_limit,
            "direct_limit_bodies": DIRECT_LIMIT_BODIES}


def main(quick: bool = False, parts: tuple[str, ...] = ("time", "frf", "eigen", "scaling")) -> dict[str, Any]:
    FIG.mkdir(parents=True, exist_ok=True)
    res: dict[str, Any] = {"machine": machine(), "quick": quick}
    everything = ("time", "frf", "eigen", "scaling")
    if set(parts) != set(everything) and OUT.exists():
        # a partial run updates its parts of the previous results (same size only)
        old = json.loads(OUT.read_text())
        if old.get("quick") == quick:
            res = {**old, **res}
    for name, fn in (("time", time_pareto), ("frf", frf_pareto), ("eigen", eigen_bench), ("scaling", scaling)):
        if name in parts:
            res[name] = fn(quick)
    OUT.parent.mkdir(exist_ok=True)
    OUT.write_text(json.dumps(res, indent=1, default=float))
    return res


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="small sizes (a minute)")
    ap.add_argument("--only", nargs="*", default=["time", "frf", "eigen", "scaling"])
    args = ap.parse_args()
    main(args.quick, tuple(args.only))
