"""Where methods fail: each failure mode measured, the check in :mod:`vibss.stability` that predicts
it, and what vibss does instead. One figure per case in ``docs/figures/stability_*.png``; the same
cases are guarded by ``tests/test_stability.py``.

1. ``central_difference`` — explicit central difference blows up beyond ``dt = 2 / omega_max``.
2. ``stiff_rk`` — explicit Runge-Kutta on a model with one stiff mount: the step count explodes;
   Radau and vibss's modal method (its ``auto`` choice) do not care.
3. ``short_pulse`` — fixed-step sampling of a pulse a few steps long: ``forced_response`` sees a
   smeared pulse; the modal path inserts the edges and stays exact.
4. ``lever_arm`` — a rigid body modelled as finite-element packages do (point masses joined by
   very stiff links) against the rigid-body formulation: condition number and frequency error as
   the link stiffness grows.
5. ``units`` — condition numbers of M and K in m/kg, mm/kg, mm/t, mm/g, before and after
   equilibration, and the frequencies computed in each.
6. ``damping`` — damping ratios of very lightly damped models from the poles: balanced ``eig`` of
   the physical A (``control.poles``), unbalanced QZ of the descriptor form, and
   ``vibss.damped_modes``.
7. ``statics`` — a nearly free motion in statics: the error of a plain solve, the check, and
   vibss's AnalysisError naming the motion.

Run: ``python benchmarks/bench_stability.py [--quick]``.
"""

from __future__ import annotations

import argparse
import json
import re
import sys
from fractions import Fraction
from pathlib import Path
from typing import Any

import control
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import scipy.linalg as sl  # noqa: E402

sys.path.insert(0, str(Path(__file__).parent))
from machine import machine, stamp, timed  # noqa: E402
from models import chain_model  # noqa: E402

from vibss import AnalysisError, Body, Model, Mount, MountType, assemble, damped_modes, modes, static  # noqa: E402
from vibss.model.excitation import Excitation, HalfSine, Rectangular  # noqa: E402
from vibss.time.integrators import central_difference, critical_step  # noqa: E402
from vibss.linear.plant.build import build_plant  # noqa: E402
from vibss.diagnostics import (check_central_difference, check_explicit_rk, check_sampling,  # noqa: E402
                             check_static, conditioning, equilibrate)
from vibss.linear.statespace import statespace  # noqa: E402
from vibss.time.api import simulate  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
FIG = ROOT / "docs" / "figures"
OUT = Path(__file__).parent / "results" / "stability.json"


def _save(fig: Any, name: str) -> None:
    stamp(fig)
    fig.tight_layout(rect=(0, 0.05, 1, 1))
    fig.savefig(FIG / f"stability_{name}.png", dpi=110)
    plt.close(fig)


# 1 ------------------------------------------------------------------------------------------
def central_difference_case(quick: bool) -> dict[str, Any]:
    model = chain_model(3, "classical", zeta=0.005, seed=2)
    plant = build_plant(model, ["b0.fz"], ["b0.z", "b2.x"])
    dtc = critical_step(plant)
    t_end = 0.2
    exc = Excitation("p", "force", "b0", HalfSine(100.0, 0.0, 0.01), dof="z")
    ratios = np.array([0.5, 0.8, 0.9, 0.95, 0.99, 1.01, 1.05, 1.1, 1.3] if quick else
                      [0.3, 0.5, 0.7, 0.8, 0.9, 0.95, 0.98, 0.995, 1.005, 1.02, 1.05, 1.1, 1.2, 1.5])
    rows = []
    for r in ratios:
        dt = r * dtc
        t = np.arange(int(t_end / dt) + 1) * dt
        f = exc.function.value(t)[:, None]
        y = central_difference(plant, t, f)
        ref = simulate(plant, [exc], t_end=t[-1], dt=dt, method="modal").outputs.T
        growth = float(np.nanmax(np.abs(y)) / np.abs(ref).max()) if np.all(np.isfinite(y)) else np.inf
        finding = check_central_difference(plant.M, plant.K, dt)
        rows.append({"dt_over_limit": float(r), "peak_ratio": growth, "check_ok": finding.ok})
    fig, ax = plt.subplots(figsize=(7, 4.5))
    pr = np.array([min(x["peak_ratio"], 1e300) for x in rows])
    ok = np.array([x["check_ok"] for x in rows])
    ax.semilogy(ratios[ok], pr[ok], "o", color="C0", label="check_central_difference: ok")
    ax.semilogy(ratios[~ok], pr[~ok], "x", color="C3", ms=8, label="check_central_difference: flagged")
    ax.axvline(1.0, color="0.5", ls="--")
    ax.set_xlabel("dt / (2 / omega_max)")
    ax.set_ylabel("peak |y| central difference / peak |y| exact")
    ax.set_title(f"Central difference, {plant.n} DOF, half-sine pulse, {t_end} s "
                 f"(2/omega_max = {dtc:.3g} s)", fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    _save(fig, "central_difference")
    print("central difference: " + ", ".join(f"{x['dt_over_limit']:.3g}:{x['peak_ratio']:.2g}" for x in rows))
    return {"limit_s": dtc, "rows": rows}


# 2 ------------------------------------------------------------------------------------------
def stiffen(model: Model, mount: str, factor: float) -> Model:
    """Copy of ``model`` with one mount's stiffness (and damping) multiplied by ``factor``."""
    out = []
    for m in model.mounts:
        if m.name == mount:
            t = MountType(m.type.name, m.type.stiffness * factor, m.type.damping * factor)
            m = Mount(m.name, t, m.body, at=m.at, to=m.to, orientation=m.orientation)
        out.append(m)
    return model.replace(mounts=out)


def _nfev(note: str) -> int:
    hit = re.search(r"(\d+) evaluations", note)
    return int(hit.group(1)) if hit else -1


def stiff_case(quick: bool) -> dict[str, Any]:
    base = chain_model(3, "classical", zeta=0.02, seed=2)
    factors = [1, 1e2, 1e3] if quick else [1, 1e1, 1e2, 1e3, 1e4]
    t_end, dt = 0.1, 1e-3
    # a rectangular pulse is piecewise linear: the modal method is exact and the reference
    exc = Excitation("p", "force", "b0", Rectangular(100.0, 0.005, 0.02), dof="z")
    rows = []
    for fac in factors:
        model = stiffen(base, "g1_0", fac)
        plant = build_plant(model, ["b0.fz"], ["b0.z", "b2.x"])
        w = np.sqrt(np.maximum(sl.eigh(plant.K, plant.M, eigvals_only=True), 0.0))
        row: dict[str, Any] = {"factor": fac, "stiffness_ratio": float(w.max() / w[w > 0].min())}
        t_m, ref = timed(lambda: simulate(plant, [exc], t_end=t_end, dt=dt, method="auto"))
        row["auto_method"] = ref.method
        row["time_auto_s"] = t_m
        for solver in ("RK45", "Radau"):
            t_s, r = timed(lambda: simulate(plant, [exc], t_end=t_end, dt=dt, method="ivp",
                                            solver=solver, rtol=1e-6), repeat=1)
            row[f"time_{solver}_s"] = t_s
            row[f"nfev_{solver}"] = _nfev(r.note)
            row[f"err_{solver}"] = float(np.abs(r.outputs - ref.outputs).max() / np.abs(ref.outputs).max())
        f = check_explicit_rk(plant.M, plant.K, t_end, rtol=1e-6, solver="RK45", C=plant.C)
        row["predicted_explosion"] = f.value
        row["check_ok"] = f.ok
        row["predicted_rk45_steps"] = f.data["steps_stability"]
        row["stiffness_ratio"] = f.data["stiffness_ratio"]
        rows.append(row)
        print("stiff: " + ", ".join(f"{k}={v:.3g}" if isinstance(v, float) else f"{k}={v}" for k, v in row.items()))
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.5))
    rows = sorted(rows, key=lambda r: r["stiffness_ratio"])
    sr = [r["stiffness_ratio"] for r in rows]
    axes[0].loglog(sr, [r["nfev_RK45"] for r in rows], "o-", label="RK45 evaluations (measured)")
    axes[0].loglog(sr, [6 * r["predicted_rk45_steps"] for r in rows], "k--",
                   label="6 x t_end |lambda|_max / 3.3 (check_explicit_rk)")
    axes[0].loglog(sr, [r["nfev_Radau"] for r in rows], "s-", label="Radau evaluations")
    axes[0].set_xlabel("stiffness ratio |lambda|_max / omega_min")
    axes[0].set_ylabel("right-hand-side evaluations")
    axes[0].legend(fontsize=7)
    for key, lab in (("time_RK45_s", "solve_ivp RK45"), ("time_Radau_s", "solve_ivp Radau"),
                     ("time_auto_s", "vibss auto (= exact modal)")):
        axes[1].loglog(sr, [r[key] for r in rows], "o-", label=lab)
    axes[1].set_xlabel("stiffness ratio |lambda|_max / omega_min")
    axes[1].set_ylabel("CPU time [s]")
    axes[1].legend(fontsize=7)
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
    fig.suptitle(f"One mount stiffened x1 .. x{factors[-1]:g}: {plant.n} DOF, {t_end} s, rtol 1e-6", fontsize=9)
    _save(fig, "stiff_rk")
    return {"rows": rows}


# 3 ------------------------------------------------------------------------------------------
def short_pulse_case(quick: bool) -> dict[str, Any]:
    model = chain_model(2, "classical", zeta=0.02, seed=3)
    plant = build_plant(model, ["b0.fz"], ["b0.z", "b1.z"])
    dt, t_end = 1e-3, 0.1
    steps = np.array([0.3, 0.7, 1.3, 2.5, 4.5, 8.5, 16.5] if quick else
                     [0.2, 0.35, 0.7, 1.1, 1.7, 2.5, 3.5, 4.5, 6.5, 8.5, 12.5, 16.5, 24.5])
    rows = []
    for k in steps:
        exc = Excitation("p", "force", "b0", Rectangular(100.0, 0.01037, k * dt), dof="z")
        exact = simulate(plant, [exc], t_end=t_end, dt=dt / 8, method="modal").outputs[:, ::8]
        modal = simulate(plant, [exc], t_end=t_end, dt=dt, method="modal").outputs
        fr = simulate(plant, [exc], t_end=t_end, dt=dt, method="forced_response").outputs
        scale = np.abs(exact).max()
        flags = check_sampling(dt, pulses=[(0.01037, k * dt)], breakpoints=exc.function.breakpoints)
        rows.append({"pulse_steps": float(k), "err_modal": float(np.abs(modal - exact).max() / scale),
                     "err_forced_response": float(np.abs(fr - exact).max() / scale),
                     "flagged": [f.check for f in flags if not f.ok]})
    fig, ax = plt.subplots(figsize=(7, 4.5))
    ax.loglog(steps, [max(r["err_forced_response"], 1e-17) for r in rows], "o-", label="control.forced_response (sampled input)")
    ax.loglog(steps, [max(r["err_modal"], 1e-17) for r in rows], "s-", label="vibss modal (edges inserted)")
    ax.axvspan(steps[0] * 0.8, 5.0, color="C3", alpha=0.1, label="check_sampling: pulse < 5 steps")
    ax.set_xlabel("pulse length / dt (edges between samples)")
    ax.set_ylabel("max relative error vs modal at dt/8")
    ax.set_title(f"Rectangular pulse on a fixed {dt * 1e3:g} ms grid, {plant.n} DOF", fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    _save(fig, "short_pulse")
    print("short pulse: " + ", ".join(f"{r['pulse_steps']:g}: fr {r['err_forced_response']:.1e} modal {r['err_modal']:.1e}" for r in rows))
    return {"dt_s": dt, "rows": rows}


# 4 ------------------------------------------------------------------------------------------
LEVER_A = 0.3       # m, half-size of the octahedron of point masses
LEVER_M = 60.0      # kg


def _lever_geometry() -> tuple[np.ndarray, list[tuple[int, int]], np.ndarray, np.ndarray]:
    nodes = LEVER_A * np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1.0]])
    links = [(i, j) for i in range(6) for j in range(i + 1, 6)]          # all 15 pairs
    mount_nodes = np.array([0, 1, 2, 3])                                  # equatorial corners
    k_mount = np.array([[1.0e5, 1.3e5, 2.0e5], [1.1e5, 1.5e5, 2.2e5], [0.9e5, 1.2e5, 1.8e5],
                        [1.2e5, 1.4e5, 2.5e5]])
    return nodes, links, mount_nodes, k_mount


def lever_model(k_link: float) -> tuple[np.ndarray, np.ndarray]:
    """FE-style model: 6 point masses (3 DOF each) joined by axial links of stiffness k_link [N/m]."""
    nodes, links, mnodes, kmt = _lever_geometry()
    n = 3 * len(nodes)
    M = np.eye(n) * LEVER_M / 6
    K = np.zeros((n, n))
    for i, j in links:
        e = nodes[j] - nodes[i]
        e /= np.linalg.norm(e)
        ke = k_link * np.outer(e, e)
        for a, b, s in ((i, i, 1), (j, j, 1), (i, j, -1), (j, i, -1)):
            K[3 * a:3 * a + 3, 3 * b:3 * b + 3] += s * ke
    for node, k in zip(mnodes, kmt):
        K[3 * node:3 * node + 3, 3 * node:3 * node + 3] += np.diag(k)
    return M, K


def lever_rigid() -> Model:
    """The same body in vibss's rigid-body formulation (octahedron inertia 2 m a^2 / 3)."""
    nodes, _, mnodes, kmt = _lever_geometry()
    inertia = 2 * LEVER_M * LEVER_A**2 / 3
    body = Body("b", LEVER_M, [inertia] * 3)
    mounts = [Mount(f"m{i}", MountType(f"t{i}", k), "b", at=nodes[nd]) for i, (nd, k) in enumerate(zip(mnodes, kmt))]
    return Model([body], mounts)


def lever_case(quick: bool) -> dict[str, Any]:
    rigid_model = lever_rigid()
    a = assemble(rigid_model, sparse=False)
    w_rigid = modes(a).omega
    kmount = 1e5
    ratios = np.logspace(0, 16, 9 if quick else 17)
    rows = []
    for r in ratios:
        M, K = lever_model(r * kmount)
        w2 = sl.eigh(K, M, eigvals_only=True)
        w = np.sqrt(np.abs(w2[:6]))
        cond = conditioning(M, K)
        rows.append({"k_link_over_k_mount": float(r), "cond_K": cond.cond_K, "cond_K_equilibrated": cond.cond_K_eq,
                     "max_rel_freq_error": float(np.max(np.abs(w - w_rigid) / w_rigid))})
    c_rigid = conditioning(a.dense("M"), a.dense("K"))
    fig, ax = plt.subplots(figsize=(7.5, 4.8))
    x = [r["k_link_over_k_mount"] for r in rows]
    ax.loglog(x, [r["max_rel_freq_error"] for r in rows], "o-", label="max rel. error, lowest 6 frequencies")
    ax.loglog(x, [r["cond_K"] for r in rows], "s--", label="cond(K), point masses + links")
    ax.loglog(x, [r["cond_K_equilibrated"] for r in rows], "^:", label="cond(K) after equilibration")
    ax.axhline(c_rigid.cond_K, color="C3", lw=1, label=f"cond(K) rigid-body formulation = {c_rigid.cond_K:.3g}")
    ax.loglog(x, np.finfo(float).eps * np.array(x), "k:", lw=0.8, label="eps x k_link / k_mount")
    ax.set_xlabel("link stiffness / mount stiffness")
    ax.set_title("Lever-arm (FE-style) model vs rigid-body formulation: 18 vs 6 DOF", fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    _save(fig, "lever_arm")
    best = min(rows, key=lambda r: r["max_rel_freq_error"])
    print(f"lever arm: best frequency error {best['max_rel_freq_error']:.1e} at k_link/k_mount = "
          f"{best['k_link_over_k_mount']:.0e}; cond(K) rigid {c_rigid.cond_K:.3g}")
    return {"rows": rows, "cond_K_rigid": c_rigid.cond_K, "best": best}


# 5 ------------------------------------------------------------------------------------------
UNITS = {"m, kg": (1.0, 1.0), "mm, kg": (1e3, 1.0), "mm, t": (1e3, 1e-3), "mm, g": (1e3, 1e3)}


def units_case(quick: bool) -> dict[str, Any]:
    model = chain_model(5 if quick else 20, "none", seed=7)
    a = assemble(model, sparse=False)
    M, K = a.dense("M"), a.dense("K")
    w_si = np.sqrt(sl.eigh(K, M, eigvals_only=True))
    rows = []
    for label, (length, mass) in UNITS.items():
        # a unit change is a diagonal congruence: translations by `length`, mass by `mass`
        tr = (np.arange(a.n) % 6) < 3
        # q_user = S q_SI (S = length for translations, 1 for rotations), energy unit mass*length^2:
        # M_user = D M D, K_user = D K D with D = sqrt(mass) length / S (frequencies unchanged)
        d = np.sqrt(mass) * np.where(tr, 1.0, length)
        Mu, Ku = d[:, None] * M * d[None, :], d[:, None] * K * d[None, :]
        c = conditioning(Mu, Ku)
        w_plain = np.sqrt(np.abs(sl.eigh(Ku, Mu, eigvals_only=True)))
        Me, dm = equilibrate(Mu)
        Ke = dm[:, None] * Ku * dm[None, :]
        w_eq = np.sqrt(np.abs(sl.eigh(Ke, Me, eigvals_only=True)))
        rows.append({"units": label, "cond_M": c.cond_M, "cond_K": c.cond_K, "cond_M_eq": c.cond_M_eq,
                     "cond_K_eq": c.cond_K_eq,
                     "freq_diff_plain": float(np.max(np.abs(w_plain - w_si) / w_si)),
                     "freq_diff_equilibrated": float(np.max(np.abs(w_eq - w_si) / w_si))})
    fig, ax = plt.subplots(figsize=(8, 4.5))
    x = np.arange(len(rows))
    for i, (key, lab) in enumerate((("cond_M", "cond(M) as given"), ("cond_K", "cond(K) as given"),
                                    ("cond_M_eq", "cond(M) equilibrated"), ("cond_K_eq", "cond(K) equilibrated"))):
        ax.bar(x + 0.2 * i, [r[key] for r in rows], 0.2, label=lab)
    ax.set_yscale("log")
    ax.set_xticks(x + 0.3, [f"{r['units']}\nfreq. diff {r['freq_diff_equilibrated']:.1e}" for r in rows], fontsize=8)
    ax.set_title(f"Units: same {a.n}-DOF model; equilibrated condition numbers are unit-independent", fontsize=9)
    ax.legend(fontsize=7)
    _save(fig, "units")
    for r in rows:
        print(f"units {r['units']}: cond M {r['cond_M']:.2e} K {r['cond_K']:.2e} -> eq {r['cond_M_eq']:.2e} "
              f"{r['cond_K_eq']:.2e}; freq diff plain {r['freq_diff_plain']:.1e} eq {r['freq_diff_equilibrated']:.1e}")
    return {"rows": rows}


# 6 ------------------------------------------------------------------------------------------
def _beta(C: np.ndarray, K: np.ndarray) -> float:
    return float(np.sum(C * K) / np.sum(K * K))


def zeta_errors(plant: Any, beta: float, poles: np.ndarray) -> float:
    """max |zeta - beta |p| / 2| / (beta |p| / 2): exact for C = beta K."""
    p = poles[poles.imag > 0]
    z, exact = -p.real / np.abs(p), beta * np.abs(p) / 2
    return float(np.max(np.abs(z - exact) / exact))


def qz_poles(M: np.ndarray, K: np.ndarray, C: np.ndarray) -> np.ndarray:
    """Poles from the descriptor pencil without M^-1 and without balancing (QZ)."""
    n = len(M)
    Z, I = np.zeros((n, n)), np.eye(n)
    return sl.eig(np.block([[Z, I], [-K, -C]]), np.block([[I, Z], [Z, M]]), right=False)


def damping_case(quick: bool) -> dict[str, Any]:
    sizes = [3, 10, 30] if quick else [3, 10, 30, 60, 100]
    rows = []
    for nb in sizes:
        for scale in ("nice", "bad"):
            model = chain_model(nb, "classical", zeta=1e-5, seed=5, scale=scale)
            a = assemble(model, sparse=False)
            plant = build_plant(model, ["b0.fz"], ["b0.z"])
            beta = _beta(plant.C, plant.K)
            sysp = statespace(plant, realization="physical", balance=False)
            t_ct, p_ct = timed(lambda: np.asarray(control.poles(sysp)), repeat=1)
            t_qz, p_qz = timed(lambda: qz_poles(plant.M, plant.K, plant.C), repeat=1)
            t_dm, dm = timed(lambda: damped_modes(a), repeat=1)
            rows.append({"bodies": nb, "dofs": a.n, "scale": scale,
                         "control.poles (balanced geev of A)": zeta_errors(plant, beta, p_ct),
                         "QZ of descriptor form, unbalanced": zeta_errors(plant, beta, p_qz),
                         "vibss damped_modes": zeta_errors(plant, beta, dm.poles),
                         "time_s": {"control.poles": t_ct, "QZ": t_qz, "damped_modes": t_dm}})
            print(f"damping {scale} {a.n} DOF: " + ", ".join(f"{k}: {v:.1e}" for k, v in rows[-1].items()
                                                              if isinstance(v, float)))
    fig, ax = plt.subplots(figsize=(7.5, 4.8))
    keys = ["control.poles (balanced geev of A)", "QZ of descriptor form, unbalanced", "vibss damped_modes"]
    for scale, ls in (("nice", "-"), ("bad", "--")):
        rs = [r for r in rows if r["scale"] == scale]
        for i, k in enumerate(keys):
            ax.loglog([r["dofs"] for r in rs], [max(r[k], 1e-17) for r in rs], "o" + ls, color=f"C{i}",
                      label=f"{k}, {scale} scale")
    ax.set_xlabel("DOF")
    ax.set_ylabel("max relative error of zeta (exact: beta |p| / 2)")
    ax.set_title("Damping ratios, C = beta K, zeta = 1e-5 at the first mode", fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    _save(fig, "damping")
    return {"rows": rows}


# 7 ------------------------------------------------------------------------------------------
def soft_z_model(eps: float) -> Model:
    """One body on four mounts 0.2 m below its COG; every mount's vertical stiffness times ``eps``.

    Then z and the rocking about the mounts' plane (x with ry, y with rx) are nearly free, while
    every diagonal entry of K stays large: equilibration cannot remove the ill-conditioning. The
    rates are 1e11 N/m and up so that the softest, 2e11 eps at eps = 1e-14, stays inside the
    plausible range vibss accepts (1e-6 N/m and up); static errors are relative, so the scale does
    not change them.
    """
    body = Body("b", 50.0, [2.0, 3.0, 4.0])
    mounts = [Mount(f"m{i}", MountType(f"t{i}", [1e11, 1.2e11, 2e11 * eps]), "b", at=p)
              for i, p in enumerate([[0.4, 0.3, -0.2], [-0.4, 0.3, -0.2], [0.4, -0.3, -0.2], [-0.4, -0.3, -0.2]])]
    return Model([body], mounts)


def exact_solve(K: np.ndarray, f: np.ndarray) -> np.ndarray:
    """Solve K x = f exactly in rational arithmetic (the float entries taken as exact)."""
    n = len(f)
    A = [[Fraction(float(K[i, j])) for j in range(n)] + [Fraction(float(f[i]))] for i in range(n)]
    for c in range(n):
        p = max(range(c, n), key=lambda r: abs(A[r][c]))
        A[c], A[p] = A[p], A[c]
        if A[c][c] == 0:
            raise ZeroDivisionError("singular")
        for r in range(n):
            if r != c and A[r][c] != 0:
                fac = A[r][c] / A[c][c]
                A[r] = [x - fac * y for x, y in zip(A[r], A[c])]
    return np.array([float(A[i][n] / A[i][i]) for i in range(n)])


def statics_case(quick: bool) -> dict[str, Any]:
    eps_list = [1.0, 1e-2, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12, 1e-14, 0.0]
    rows = []
    for eps in eps_list:
        model = soft_z_model(eps)
        a = assemble(model, sparse=False)
        K = a.dense("K")
        f = np.array([100.0, 0.0, 0.0, 0.0, 0.0, 0.0])      # a side force at the COG: rocks the body
        try:
            exact = exact_solve(K, f)[4]                     # ry
        except ZeroDivisionError:
            exact = np.inf
        finding = check_static(K, [f"b.{d}" for d in ("x", "y", "z", "rx", "ry", "rz")])
        try:
            q = static(model, f, gravity=False).q
            err, raised = float(abs(q[4] - exact) / abs(exact)), ""
        except AnalysisError as exc:
            err, raised = np.nan, str(exc)
        try:
            with np.errstate(all="ignore"):
                plain = float(np.linalg.solve(K, f)[4])
            plain_err = float(abs(plain - exact) / abs(exact)) if eps > 0 else np.inf
        except np.linalg.LinAlgError:
            plain_err = np.inf
        rows.append({"eps": eps, "check_value": finding.value, "check_ok": finding.ok, "vibss_error": err,
                     "vibss_raised": raised, "plain_solve_error": plain_err})
        print(f"statics eps={eps:g}: check {finding.value:.1e} ok={finding.ok}; vibss err {err:.1e} "
              f"{'raised: ' + raised[:90] if raised else ''}; plain solve err {plain_err:.1e}")
    fig, ax = plt.subplots(figsize=(7, 4.5))
    xs = [r["eps"] for r in rows if r["eps"] > 0]
    ax.loglog(xs, [max(r["check_value"], 1e-20) for r in rows if r["eps"] > 0], "o-",
              label="check_static: smallest equilibrated eigenvalue / largest")
    ax.loglog(xs, [max(r["plain_solve_error"], 1e-17) for r in rows if r["eps"] > 0], "x--",
              label="numpy.linalg.solve(K, f)")
    ax.loglog(xs, [max(r["vibss_error"], 1e-17) if np.isfinite(r["vibss_error"]) else np.nan
                   for r in rows if r["eps"] > 0], "s-", label="vibss static")
    ax.axhline(1e-12, color="C3", ls=":", label="check threshold 1e-12")
    ax.set_xlabel("vertical mount stiffness factor eps (rocking nearly free)")
    ax.set_ylabel("relative error of ry (exact: rational arithmetic)")
    ax.invert_xaxis()
    ax.set_title("Statics, side force on a body whose mounts lose vertical stiffness;\n"
                 "eps = 0: vibss raises AnalysisError naming the free motion", fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    _save(fig, "statics")
    return {"rows": rows}


def main(quick: bool = False) -> dict[str, Any]:
    FIG.mkdir(parents=True, exist_ok=True)
    res: dict[str, Any] = {"machine": machine(), "quick": quick}
    for name, fn in (("central_difference", central_difference_case), ("stiff_rk", stiff_case),
                     ("short_pulse", short_pulse_case), ("lever_arm", lever_case), ("units", units_case),
                     ("damping", damping_case), ("statics", statics_case)):
        res[name] = fn(quick)
    OUT.parent.mkdir(exist_ok=True)
    OUT.write_text(json.dumps(res, indent=1, default=float))
    return res


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    main(ap.parse_args().quick)
