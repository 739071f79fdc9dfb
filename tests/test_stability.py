"""Failure modes of numerical methods, and that vibss's checks (vibss.stability) detect them.

Each test pins a number that does not come from the code under test: a closed form (SDOF
responses, 2/omega), a second method (exact rational arithmetic, the rigid-body formulation) or an
invariant (zeta = beta |p| / 2 for C = beta K; diagonal unit scalings leave equilibrated matrices
unchanged).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import scipy.linalg as sl
from scipy.spatial.transform import Rotation

from vibss import AnalysisError, Body, Model, Mount, MountType, assemble, damped_modes, modes, static
from vibss.errors import ModelError
from vibss.model.excitation import Excitation, Rectangular, SineSweep, Step
from vibss.time.integrators import central_difference, critical_step, newmark, newmark_method
from vibss.linear.plant.build import build_plant
from vibss.diagnostics import (Finding, VibssWarning, check_central_difference, check_damping_resolution,
                             check_excitations, check_explicit_rk, check_repeated, check_sampling,
                             check_static, conditioning, equilibrate, natural_frequencies,
                             repeated_frequencies)
from vibss.time.api import simulate

MASS, KZ = 2.0, 800.0                  # z of a body on one mount at its COG: SDOF, w = 20 rad/s
WN = np.sqrt(KZ / MASS)


def sdof(c: float = 0.0) -> Model:
    t = MountType("t", [KZ, KZ, KZ], [c, c, c])
    return Model([Body("b", MASS, [1.0, 1.0, 1.0])], [Mount("m", t, "b")], name="sdof")


def step_response(t: np.ndarray, f: float, t0: float) -> np.ndarray:
    """Undamped SDOF response to a force step f at t0 (closed form)."""
    tau = np.clip(t - t0, 0.0, None)
    return np.where(t >= t0, f / KZ * (1 - np.cos(WN * tau)), 0.0)


def chain(n: int, scale: str = "nice", beta: float | None = None, stiff: float = 1.0, seed: int = 0) -> Model:
    """Random chain of rigid bodies on rotated mounts; C = beta K when beta is given."""
    rng = np.random.default_rng(seed)
    lo_m, hi_m, lo_k, hi_k = (1.0, 100.0, 1e4, 1e6) if scale == "nice" else (1e-3, 1e4, 1e2, 1e8)
    bodies, mounts = [], []
    for i in range(n):
        m = float(np.exp(rng.uniform(np.log(lo_m), np.log(hi_m))))
        sz = rng.uniform(0.2, 0.6, 3) ** 2
        bodies.append(Body(f"b{i}", m, m / 12 * (sz.sum() - sz), cog=[float(i), 0.0, 0.0],
                           principal_axes=Rotation.random(random_state=int(rng.integers(1 << 30))).as_matrix()))
        for j, to in enumerate(["ground", "ground"] + ([f"b{i - 1}"] if i else [])):
            k = np.exp(rng.uniform(np.log(lo_k), np.log(hi_k), 3)) * (stiff if (i, j) == (0, 1) else 1.0)
            c = beta * k if beta is not None else np.zeros(3)
            mounts.append(Mount(f"m{i}_{j}", MountType(f"t{i}_{j}", k, c), f"b{i}", at=rng.uniform(-0.4, 0.4, 3),
                                to=to, orientation=Rotation.random(random_state=int(rng.integers(1 << 30))).as_matrix()))
    return Model(bodies, mounts, name=f"chain {n}")


# --------------------------------------------------------------------------------------------
# findings and warnings

def test_finding_warns_with_vibss_warning_only_when_not_ok() -> None:
    with pytest.warns(VibssWarning, match="central_difference: dt = 0.2"):
        check_central_difference(np.eye(1), 1e2 * np.eye(1), 0.2).warn()   # 2/w = 0.2 s exactly
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        Finding("x", True, "fine").warn()
    assert issubclass(VibssWarning, UserWarning)


# --------------------------------------------------------------------------------------------
# central difference beyond 2 / omega_max

def test_central_difference_limit_is_two_over_omega_max() -> None:
    M, K = np.diag([1.0, 4.0]), np.diag([100.0, 4e4])                     # w = 10, 100 rad/s
    f = check_central_difference(M, K, 0.019)
    assert f.ok and f.limit == pytest.approx(0.02, rel=1e-12)
    assert not check_central_difference(M, K, 0.021).ok


@pytest.mark.parametrize("ratio, stable", [(0.9, True), (1.1, False)])
def test_central_difference_blows_up_where_the_check_says(ratio: float, stable: bool) -> None:
    model = chain(2, beta=1e-5)
    plant = build_plant(model, ["b0.fz"], ["b0.z", "b1.x"])
    dtc = critical_step(plant)
    assert dtc == pytest.approx(2 / natural_frequencies(plant.M, plant.K).max(), rel=1e-12)
    dt = ratio * dtc
    t = dt * np.arange(int(0.1 / dt) + 1)
    exc = Excitation("p", "force", "b0", Rectangular(100.0, 0.0, 0.005), dof="z")
    with np.errstate(all="ignore"):
        y = central_difference(plant, t, exc.function.value(t)[:, None])
    ref = simulate(plant, [exc], t_end=t[-1], dt=dt, method="modal").outputs.T
    growth = np.nanmax(np.abs(y)) / np.abs(ref).max() if np.all(np.isfinite(y)) else np.inf
    assert check_central_difference(plant.M, plant.K, dt).ok is stable
    assert (growth < 2.0) if stable else (growth > 1e6)


# --------------------------------------------------------------------------------------------
# Newmark: closed form, second order

def test_newmark_second_order_against_closed_form() -> None:
    plant = build_plant(sdof(), ["b.fz"], ["b.z"])
    errs = []
    for dt in (2e-3, 1e-3):
        t = dt * np.arange(int(0.5 / dt) + 1)
        y = newmark(plant, t, np.full((t.size, 1), 10.0))[:, 0]
        errs.append(np.abs(y - step_response(t, 10.0, 0.0)).max() / (20.0 / KZ))
    assert errs[1] < 1e-3
    assert errs[0] / errs[1] == pytest.approx(4.0, rel=0.1)               # O(dt^2)


def test_newmark_is_a_simulate_method_and_unconditionally_stable() -> None:
    model = chain(2, beta=1e-4)
    plant = build_plant(model, ["b0.fz"], ["b0.z"])
    dt = 5 * critical_step(plant)                                           # far beyond the explicit limit
    r = simulate(plant, [Excitation("s", "force", "b0", Step(10.0), dof="z")], t_end=200 * dt, dt=dt,
                 method=newmark_method)
    ref = simulate(plant, [Excitation("s", "force", "b0", Step(10.0), dof="z")], t_end=200 * dt, dt=dt)
    assert np.abs(r.outputs).max() < 3 * np.abs(ref.outputs).max()


def test_integrators_refuse_motion_inputs() -> None:
    plant = build_plant(sdof(), ["ground.z.disp"], ["b.z"])
    with pytest.raises(ModelError, match="only force inputs"):
        newmark(plant, np.linspace(0, 1, 11), np.zeros((11, 1)))


# --------------------------------------------------------------------------------------------
# explicit Runge-Kutta on a stiff model

def test_explicit_rk_on_stiff_model_is_flagged_and_auto_avoids_it() -> None:
    t_end = 0.02
    exc = Excitation("p", "force", "b0", Rectangular(100.0, 0.002, 0.005), dof="z")
    counts, flags = [], []
    for stiff in (1.0, 1e5):
        model = chain(2, beta=1e-5, stiff=stiff)
        plant = build_plant(model, ["b0.fz"], ["b0.z"])
        f = check_explicit_rk(plant.M, plant.K, t_end, rtol=1e-6, solver="RK45", C=plant.C)
        flags.append(f)
        if f.ok:
            r = simulate(plant, [exc], t_end=t_end, dt=1e-3, method="ivp", solver="RK45", rtol=1e-6)
        else:   # simulate itself warns, naming the cause
            with pytest.warns(VibssWarning, match="stiff for an explicit solver"):
                r = simulate(plant, [exc], t_end=t_end, dt=1e-3, method="ivp", solver="RK45", rtol=1e-6)
        counts.append(int(r.note.split(" evaluations")[0].split()[-1]))
        auto = simulate(plant, [exc], t_end=t_end, dt=1e-3, method="auto")
        assert auto.method == "modal"
        assert np.abs(auto.outputs - r.outputs).max() <= 1e-4 * np.abs(auto.outputs).max()
    # the stiff mount (its overdamped pole) multiplies the step count; the check predicts it
    assert counts[1] / counts[0] > 10
    assert flags[0].ok and not flags[1].ok
    # on the stiff model the stability bound t_end |lambda|_max / 3.3 steps (6 evaluations each)
    # is the actual cost within a small factor
    assert 0.8 < counts[1] / (6 * flags[1].data["steps_stability"]) < 2.0


# --------------------------------------------------------------------------------------------
# fixed-step sampling: short pulses, edges, aliasing

def test_short_pulse_flagged_and_modal_path_exact() -> None:
    dt, t1, dur = 1e-3, 0.01037, 0.0023                                     # 2.3 steps, edges between samples
    exc = Excitation("p", "force", "b", Rectangular(10.0, t1, dur), dof="z")
    flags = {f.check: f for f in check_excitations([exc], dt)}
    assert not flags["sampling_pulse"].ok and flags["sampling_pulse"].value == pytest.approx(2.3)
    assert not flags["sampling_edges"].ok and flags["sampling_edges"].value == 2
    assert check_excitations([exc], dt, inserts_breakpoints=True) == []
    r = simulate(sdof(), [exc], outputs=["b.z"], t_end=0.2, dt=dt, method="modal")
    x = step_response(r.time, 10.0, t1) - step_response(r.time, 10.0, t1 + dur)
    scale = np.abs(x).max()
    assert np.abs(r.output("b.z") - x).max() <= 1e-10 * scale
    with pytest.warns(VibssWarning, match="shortest pulse"), \
            pytest.warns(VibssWarning, match="between samples"):     # simulate says why, up front
        fr = simulate(sdof(), [exc], outputs=["b.z"], t_end=0.2, dt=dt, method="forced_response")
    assert np.abs(fr.output("b.z") - x).max() > 0.05 * scale


def test_sweep_above_nyquist_is_flagged() -> None:
    sweep = Excitation("s", "force", "b", SineSweep(10.0, 700.0, 1.0, 1.0, 1.0), dof="z")
    f = {x.check: x for x in check_excitations([sweep], 1e-3)}["sampling_frequency"]
    assert not f.ok and "Nyquist frequency 500 Hz" in f.message
    (g,) = check_sampling(2e-4, f_max=700.0)                               # 7 samples per period
    assert not g.ok and "Nyquist" not in g.message
    (h,) = check_sampling(1e-4, f_max=700.0)                               # 14 samples per period
    assert h.ok


# --------------------------------------------------------------------------------------------
# lever arms (point masses + stiff links) against the rigid-body formulation

def _octahedron(k_link: float) -> tuple[np.ndarray, np.ndarray, Model]:
    a, m = 0.3, 60.0
    nodes = a * np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1.0]])
    kmt = np.array([[1.0e5, 1.3e5, 2.0e5], [1.1e5, 1.5e5, 2.2e5], [0.9e5, 1.2e5, 1.8e5], [1.2e5, 1.4e5, 2.5e5]])
    M, K = np.eye(18) * m / 6, np.zeros((18, 18))
    for i in range(6):
        for j in range(i + 1, 6):
            e = (nodes[j] - nodes[i]) / np.linalg.norm(nodes[j] - nodes[i])
            ke = k_link * np.outer(e, e)
            for p, q, s in ((i, i, 1), (j, j, 1), (i, j, -1), (j, i, -1)):
                K[3 * p:3 * p + 3, 3 * q:3 * q + 3] += s * ke
    for node, k in enumerate(kmt):
        K[3 * node:3 * node + 3, 3 * node:3 * node + 3] += np.diag(k)
    rigid = Model([Body("b", m, [2 * m * a**2 / 3] * 3)],
                  [Mount(f"m{i}", MountType(f"t{i}", k), "b", at=nodes[i]) for i, k in enumerate(kmt)])
    return M, K, rigid


def test_lever_arm_model_converges_to_rigid_body_then_loses_conditioning() -> None:
    w_rigid = modes(_octahedron(1.0)[2]).omega
    err, cond = {}, {}
    for ratio in (1e2, 1e6, 1e15):
        M, K, _ = _octahedron(ratio * 1e5)
        w = np.sqrt(np.abs(sl.eigh(K, M, eigvals_only=True)[:6]))
        err[ratio] = np.max(np.abs(w - w_rigid) / w_rigid)
        cond[ratio] = conditioning(M, K).cond_K
    assert err[1e6] < 1e-5 < err[1e2]                                       # link flexibility error ~ 1/ratio
    assert err[1e15] > 100 * err[1e6]                                       # then round-off ~ eps ratio
    assert cond[1e15] > 1e14 and cond[1e6] > 1e5
    a = assemble(_octahedron(1.0)[2], sparse=False)
    assert conditioning(a.dense("M"), a.dense("K")).cond_K < 100            # rigid-body formulation


# --------------------------------------------------------------------------------------------
# units and equilibration

def test_unit_choice_changes_raw_condition_not_equilibrated_nor_frequencies() -> None:
    a = assemble(chain(3), sparse=False)
    M, K = a.dense("M"), a.dense("K")
    tr = (np.arange(a.n) % 6) < 3
    out = []
    for length, mass in ((1.0, 1.0), (1e3, 1.0), (1e3, 1e-3), (1e3, 1e3)):   # m/kg, mm/kg, mm/t, mm/g
        d = np.sqrt(mass) * np.where(tr, 1.0, length)                     # M_user = D M D
        Mu, Ku = d[:, None] * M * d[None, :], d[:, None] * K * d[None, :]
        out.append((conditioning(Mu, Ku), equilibrate(Ku)[0], natural_frequencies(Mu, Ku)))
    base = out[0]
    assert out[1][0].cond_M > 100 * base[0].cond_M                          # mm: translations vs rotations
    assert out[1][0].cond_K > 1e4 * base[0].cond_K
    for c, ke, w in out[1:]:
        assert c.cond_M_eq == pytest.approx(base[0].cond_M_eq, rel=1e-8)
        assert c.cond_K_eq == pytest.approx(base[0].cond_K_eq, rel=1e-8)
        assert np.abs(ke - base[1]).max() < 1e-13                           # identical after equilibration
        assert np.abs(w - base[2]).max() <= 1e-12 * base[2].max()


# --------------------------------------------------------------------------------------------
# damping ratios of very lightly damped systems

def test_damping_ratios_of_lightly_damped_poles() -> None:
    beta = 2e-8                                                              # zeta ~ 1e-6 .. 1e-4
    model = chain(5, scale="bad", beta=beta, seed=3)
    a = assemble(model, sparse=False)
    dm = damped_modes(a)

    def err(p: np.ndarray) -> float:
        p = p[p.imag > 0]
        return float(np.max(np.abs(-p.real / np.abs(p) - beta * np.abs(p) / 2) / (beta * np.abs(p) / 2)))

    M, K, C = a.dense("M"), a.dense("K"), a.dense("C")
    n = a.n
    Z, I = np.zeros((n, n)), np.eye(n)
    qz = sl.eig(np.block([[Z, I], [-K, -C]]), np.block([[I, Z], [Z, M]]), right=False)
    assert err(dm.poles) < 1e-6                                              # invariant zeta = beta |p| / 2
    assert err(qz) > 100 * err(dm.poles)                                     # unbalanced QZ loses Re(p)
    pred = check_damping_resolution(M, K, C)
    assert not pred.ok and pred.value > 1e-3                                # physical eig(A) predicted unsafe


# --------------------------------------------------------------------------------------------
# statics of nearly free systems

def _soft_z(eps: float) -> Model:
    pts = [[0.4, 0.3, -0.2], [-0.4, 0.3, -0.2], [0.4, -0.3, -0.2], [-0.4, -0.3, -0.2]]
    return Model([Body("b", 50.0, [2.0, 3.0, 4.0])],
                 [Mount(f"m{i}", MountType(f"t{i}", [1e5, 1.2e5, 2e5 * eps]), "b", at=p) for i, p in enumerate(pts)])


def test_static_free_motion_raises_and_names_it() -> None:
    with pytest.raises(AnalysisError, match=r"do not restrain the load.*b\.(rx|ry|z)"):
        static(_soft_z(0.0), np.array([100.0, 0, 0, 0, 0, 0]), gravity=False)
    f = check_static(assemble(_soft_z(0.0), sparse=False).dense("K"), ["x", "y", "z", "rx", "ry", "rz"])
    assert not f.ok and "nearly free motion" in f.message


def test_static_nearly_free_is_accurate_where_the_check_passes() -> None:
    eps = 1e-4
    a = assemble(_soft_z(eps), sparse=False)
    K = a.dense("K")
    f = np.array([100.0, 0, 0, 0, 0, 0])
    # independent closed form: x, ry decouple from the rest; mounts 0.2 m below the COG
    kx, kz, h = 4e5, 4 * 2e5 * eps, 0.2
    kxx, kxr, krr = kx, -kx * h, kx * h**2 + kz * 0.4**2                     # x-ry block: d_x = x - h ry
    det = kxx * krr - kxr**2
    x_exact, ry_exact = 100.0 * krr / det, -100.0 * kxr / det
    q = static(_soft_z(eps), f, gravity=False).q
    assert q[0] == pytest.approx(x_exact, rel=1e-9)
    assert q[4] == pytest.approx(ry_exact, rel=1e-9)
    assert check_static(K).ok
    assert check_static(K).value == pytest.approx(1e-4, rel=0.2)            # softness ~ eps


# --------------------------------------------------------------------------------------------
# repeated frequencies

def test_repeated_frequencies_found_and_directions_clean() -> None:
    t = MountType("t", [3e4, 3e4, 5e4])
    pts = [[0.5, 0.5, -0.1], [-0.5, 0.5, -0.1], [-0.5, -0.5, -0.1], [0.5, -0.5, -0.1]]
    model = Model([Body("b", 100.0, [8.0, 8.0, 12.0])], [Mount(f"m{i}", t, "b", at=p) for i, p in enumerate(pts)])
    md = modes(model)
    groups = repeated_frequencies(md.omega)
    assert len(groups) == 2 and all(len(g) == 2 for g in groups)            # x/ry with y/rx, twice
    assert not check_repeated(md.omega).ok
    for g in groups:
        shapes = md.shapes[:, g]
        # each shape of a pair moves in x (with ry) or in y (with rx), never both
        xs = np.abs(shapes[[0, 4]]).max(axis=0)
        ys = np.abs(shapes[[1, 3]]).max(axis=0)
        assert np.all(np.minimum(xs, ys) <= 1e-8 * np.maximum(xs, ys))
