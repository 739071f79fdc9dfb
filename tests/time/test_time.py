"""Time response: closed forms, invariants and the methods against each other."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import cases.models as cases
from cases import small as sc
from vibss import Body, Model, Mount, MountType, VibssWarning, assemble, symmetric
from vibss.errors import AnalysisError, ModelError
from vibss.io import loads_model
from vibss.model.excitation import Excitation, HalfSine, Rectangular, Sine, SineSweep, Step, Triangle
from vibss.linear.plant.build import build_plant
from vibss.time.api import METHODS, TimeResponse, simulate
from vibss.time.sweep import _frf, sweep_envelope

M, K, C = 2.0, 800.0, 4.0          # single DOF: w_n = 20 rad/s, zeta = 0.05
WN = np.sqrt(K / M)


def sdof(c: float = 0.0) -> Model:
    """One body on one mount at its COG: x, y, z are single DOFs (rotations are free rigid modes)."""
    return cases.sdof(M, K, c, name="sdof")


def free(t: np.ndarray, x0: float, v0: float, c: float) -> np.ndarray:
    """Closed-form free response of m x'' + c x' + k x = 0 (underdamped)."""
    z = c / (2 * np.sqrt(K * M))
    wd = WN * np.sqrt(1 - z**2)
    return np.exp(-z * WN * t) * (x0 * np.cos(wd * t) + (v0 + z * WN * x0) / wd * np.sin(wd * t))


def step_response(t: np.ndarray, f: float, t0: float, c: float) -> np.ndarray:
    tau = np.clip(t - t0, 0.0, None)
    return np.where(t >= t0, f / K + free(tau, -f / K, 0.0, c), 0.0)


def two_body(damping: str = "general") -> Model:
    """Asymmetric two-body model: inclined mounts, products of inertia, non-proportional damping."""
    rng = np.random.default_rng(3)
    b1 = Body("base", 40.0, [[2.0, 0.3, -0.1], [0.3, 3.0, 0.2], [-0.1, 0.2, 2.5]], cog=[0.0, 0.0, 0.0])
    b2 = Body("top", 15.0, [0.4, 0.6, 0.5], cog=[0.1, -0.05, 0.4],
              principal_axes=Rotation.from_euler("ZYX", [20.0, 10.0, 5.0], degrees=True).as_matrix())
    mounts = []
    for i, (body, to, at) in enumerate([("base", "ground", [0.3, 0.2, -0.1]), ("base", "ground", [-0.3, 0.25, -0.1]),
                                        ("base", "ground", [0.0, -0.3, -0.1]), ("top", "base", [0.15, 0.1, -0.1]),
                                        ("top", "base", [-0.1, -0.1, -0.1]), ("top", "base", [0.0, 0.15, -0.1])]):
        k = rng.uniform(2e4, 8e4, 3)
        c = {"general": rng.uniform(100.0, 600.0, 3), "classical": 5e-3 * k, "none": np.zeros(3)}[damping]
        rot = np.linalg.qr(rng.normal(size=(3, 3)))[0]
        rot *= np.sign(np.linalg.det(rot))
        mounts.append(Mount(f"m{i}", MountType(f"t{i}", k, c), body, at=at, to=to, orientation=rot))
    return Model([b1, b2], mounts, name="two bodies")


# --------------------------------------------------------------------------------------------
# single DOF closed forms, every method

TOL = {"modal": 1e-10, "forced_response": 1e-9, "ivp": 1e-6, "nonlinear_modal": 1e-10}   # the last: exact modal on a linear Model
# Newmark (average acceleration) and central difference are second order: their phase error after
# time t is about w t (w dt)^2 / 12 (times 2 for safety), with dt = 1 ms and t <= 0.6 s below.
TOL["newmark"] = TOL["central_difference"] = 2 * WN * 0.6 * (WN * 1e-3) ** 2 / 12


@pytest.mark.parametrize("method", list(METHODS))
@pytest.mark.parametrize("c", [0.0, C])
def test_step_force_closed_form(method: str, c: float) -> None:
    # a step at t = 0: forced_response's FOH of the samples is exact too (no edge to smear)
    e = Excitation("s", "force", "b", Step(10.0), dof="z")
    r = simulate(sdof(c), [e], outputs=["b.z"], t_end=0.6, dt=1e-3, method=method, rtol=1e-10)
    x = step_response(r.time, 10.0, 0.0, c)
    assert np.abs(r.output("b.z") - x).max() <= TOL[method] * 10.0 / K * 2


@pytest.mark.parametrize("method", ["modal", "ivp"])
def test_rectangular_pulse_edges_between_samples_not_smeared(method: str) -> None:
    t1, t2 = 0.01234, 0.04567                                       # not on the 1 ms grid
    e = Excitation("p", "force", "b", Rectangular(10.0, t1, t2 - t1), dof="z")
    r = simulate(sdof(C), [e], outputs=["b.z"], t_end=0.3, dt=1e-3, method=method, rtol=1e-10)
    x = step_response(r.time, 10.0, t1, C) - step_response(r.time, 10.0, t2, C)
    assert np.abs(r.output("b.z") - x).max() <= TOL[method] * 10.0 / K * 2
    # forced_response sees the sampled pulse and smears each edge over a step, and vibss says so
    with pytest.warns(VibssWarning, match="between samples"):
        fr = simulate(sdof(C), [e], outputs=["b.z"], t_end=0.3, dt=1e-3, method="forced_response")
    assert np.abs(fr.output("b.z") - x).max() > 1e-4 * 10.0 / K


def test_half_sine_pulse_duhamel() -> None:
    T, F = 0.03, 50.0
    w = np.pi / T
    e = Excitation("p", "force", "b", HalfSine(F, 0.0, T), dof="z")
    r = simulate(sdof(), [e], outputs=["b.z"], t_end=0.5, dt=1e-4)
    t = r.time
    rr = w / WN
    during = F / K / (1 - rr**2) * (np.sin(w * t) - rr * np.sin(WN * t))
    xT = F / K / (1 - rr**2) * (np.sin(w * T) - rr * np.sin(WN * T))
    vT = F / K / (1 - rr**2) * (w * np.cos(w * T) - rr * WN * np.cos(WN * T))
    after = free(t - T, xT, vT, 0.0)
    x = np.where(t <= T, during, after)
    # FOH of a sine sampled at 0.1 ms: error O((w dt)^2)
    assert np.abs(r.output("b.z") - x).max() < 1e-4 * np.abs(x).max()


@pytest.mark.parametrize("method", ["modal", "ivp"])
def test_base_acceleration_pulse(method: str) -> None:
    a0, t1, t2 = 3.0, 0.0105, 0.0405
    e = Excitation("g", "acceleration", "ground", Rectangular(a0, t1, t2 - t1), dof="z")
    r = simulate(sdof(), [e], outputs=["b.z"], t_end=0.4, dt=1e-3, method=method, rtol=1e-10)
    t = r.time

    def ramp2(t0: float) -> np.ndarray:
        return np.where(t >= t0, (t - t0) ** 2 / 2, 0.0)

    def rel(t0: float) -> np.ndarray:
        return np.where(t >= t0, 1 - np.cos(WN * (t - t0)), 0.0)

    zg = a0 * (ramp2(t1) - ramp2(t2))
    x = zg - a0 / WN**2 * (rel(t1) - rel(t2))
    assert np.abs(r.output("b.z") - x).max() < TOL[method] * np.abs(x).max() * 10


@pytest.mark.parametrize("method", list(METHODS))
def test_free_decay_from_initial_conditions(method: str) -> None:
    init = {"b": {"displacement": [0.0, 0.0, 0.01, 0, 0, 0], "velocity": [0.0, 0.0, -0.3, 0, 0, 0.5]}}
    r = simulate(sdof(C), inputs={"b.fz": lambda t: 0.0 * t}, outputs=["b.z", "b.rz"], t_end=0.5,
                 dt=1e-3, initial=init, method=method, rtol=1e-10, atol=1e-14)
    assert np.abs(r.output("b.z") - free(r.time, 0.01, -0.3, C)).max() < TOL[method] * 0.03
    # the free rotation is a rigid-body mode (omega = 0): rz = 0.5 t exactly
    assert np.abs(r.output("b.rz") - 0.5 * r.time).max() < TOL[method] * 0.25


def test_displacement_step_through_damper_is_an_impulse() -> None:
    Z, t0 = 0.002, 0.0333
    e = Excitation("g", "displacement", "ground", Step(Z, start=t0), dof="z")
    for method in ("modal", "ivp"):
        r = simulate(sdof(C), [e], outputs=["b.z"], t_end=0.4, dt=1e-3, method=method, rtol=1e-10)
        x = np.where(r.time >= t0, Z + free(np.clip(r.time - t0, 0, None), -Z, C * Z / M, C), 0.0)
        assert np.abs(r.output("b.z") - x).max() < TOL[method] * Z * 10


# --------------------------------------------------------------------------------------------
# multi-body invariants and agreement

def test_sine_steady_state_equals_frf_amplitude() -> None:
    model = two_body()
    f = 7.0
    e = Excitation("s", "force", "top", Sine(25.0, f), dof="y")
    r = simulate(model, [e], t_end=6.0, dt=5e-4, record_from=5.0)
    p = build_plant(model, ["top.fy"])
    w = 2 * np.pi * f
    X = np.linalg.solve(p.K - w**2 * p.M + 1j * w * p.C, p.F[:, 0] * 25.0)
    amp = np.abs(p.Oq @ X)
    got = np.abs(r.outputs).max(axis=1)
    big = amp > 1e-3 * amp.max()
    np.testing.assert_allclose(got[big], amp[big], rtol=2e-3)


def test_step_settles_to_static_deflection() -> None:
    model = two_body()
    e = Excitation("s", "force", "top", Step(100.0), dof="x")
    r = simulate(model, [e], t_end=20.0, dt=2e-3, record_from=19.0)
    a = assemble(model)
    f = np.zeros(a.n)
    f[a.dof_index("top.x")] = 100.0
    q = np.linalg.solve(a.K, f)
    np.testing.assert_allclose(r.outputs[:, -1], q, atol=1e-6 * np.abs(q).max())


def test_undamped_model_conserves_energy() -> None:
    model = two_body("none")
    dofs = assemble(model).dofs
    init = {"base": {"velocity": [0.1, -0.05, 0.2, 0.3, 0.1, -0.2]},
            "top": {"displacement": [0.001, 0.0, -0.002, 0.0, 0.01, 0.0]}}
    r = simulate(model, outputs=list(dofs) + [d + ".vel" for d in dofs], inputs={"top.fz": lambda t: 0 * t}, t_end=2.0,
                 dt=1e-3, initial=init)
    a = assemble(model)
    q, v = r.outputs[:12], r.outputs[12:]
    energy = 0.5 * np.einsum("it,ij,jt->t", v, a.M, v) + 0.5 * np.einsum("it,ij,jt->t", q, a.K, q)
    assert np.ptp(energy) < 1e-10 * energy[0]


def excitations_2body() -> list[Excitation]:
    return [Excitation("hit", "force", "top", HalfSine(200.0, 0.01, 0.02), direction=[1.0, 0.5, -0.3],
                       at=[0.1, 0.0, 0.1]),
            Excitation("quake", "acceleration", "ground", Triangle(2.0, 0.005, 0.05), dof="x")]


def sampled_2body(t_end: float, dt: float) -> list[Excitation]:
    """The same excitations with the half-sine as a table of its samples (linear between them)."""
    from vibss.model.timefunctions import Table

    hit, quake = excitations_2body()
    ts = dt * np.arange(int(round(t_end / dt)) + 1)
    return [Excitation("hit", "force", "top", Table(ts, hit.function.value(ts)), direction=[1.0, 0.5, -0.3],
                       at=[0.1, 0.0, 0.1]), quake]


def test_methods_agree_on_asymmetric_damped_two_body() -> None:
    model = two_body("general")
    outs = ["top.x", "top.rz", "base.z", "top.z.vel", "top.y.acc", "mount.m3.fz", "ground.fx"]
    kw = dict(outputs=outs, t_end=0.3, dt=5e-4)
    ref = simulate(model, excitations_2body(), method="forced_response", **kw)
    scale = np.abs(ref.outputs).max(axis=1, keepdims=True)
    modal = simulate(model, excitations_2body(), method="modal", **kw)
    # the modal path is exact for the half-sine (its sine piece) and the triangle: a tight ivp run
    ivp = simulate(model, excitations_2body(), method="ivp", rtol=1e-10, atol=1e-14, **kw)
    assert np.all(np.abs(ivp.outputs - modal.outputs) <= 1e-7 * scale)
    # forced_response takes the samples linear between them: the FOH error of the half-sine
    assert np.all(np.abs(ref.outputs - modal.outputs) <= 2e-3 * scale)
    # and with the half-sine given by its samples both are the exact FOH of the same samples
    fr = simulate(model, sampled_2body(0.3, 5e-4), method="forced_response", **kw)
    mo = simulate(model, sampled_2body(0.3, 5e-4), method="modal", **kw)
    assert np.all(np.abs(mo.outputs - fr.outputs) <= 1e-8 * scale)


def test_classical_and_general_paths_agree() -> None:
    model = two_body("classical")
    kw = dict(t_end=0.2, dt=5e-4)
    a = simulate(model, sampled_2body(0.2, 5e-4), method="modal", **kw)    # both: linear between samples
    b = simulate(model, sampled_2body(0.2, 5e-4), method="forced_response", **kw)
    assert "classical" in a.note
    np.testing.assert_allclose(a.outputs, b.outputs, atol=1e-9 * np.abs(b.outputs).max())


@pytest.mark.slow
def test_displacement_velocity_acceleration_inputs_give_the_same_response() -> None:
    A, W = 2.0, 2 * np.pi * 15.0                      # starts at rest: a = A sin(W t)
    motion = {"acc": lambda t: A * np.sin(W * t),
              "vel": lambda t: A / W * (1 - np.cos(W * t)),
              "disp": lambda t: A / W * (t - np.sin(W * t) / W)}
    model = two_body("general")
    outs = ["top.x", "base.rx", "top.z.vel"]
    res = {k: simulate(model, inputs={f"ground.x.{k}": fn}, outputs=outs, t_end=0.25, dt=1e-4,
                       method="ivp", rtol=1e-10, atol=1e-14) for k, fn in motion.items()}
    scale = np.abs(res["acc"].outputs).max(axis=1, keepdims=True)
    for k in ("vel", "disp"):
        assert np.all(np.abs(res[k].outputs - res["acc"].outputs) <= 1e-6 * scale), k
    modal = {k: simulate(model, inputs={f"ground.x.{k}": fn}, outputs=outs, t_end=0.25, dt=1e-4)
             for k, fn in motion.items()}
    for k in motion:
        assert np.all(np.abs(modal[k].outputs - res["acc"].outputs) <= 1e-3 * scale), k


# --------------------------------------------------------------------------------------------
# API

def test_result_object_and_api_errors() -> None:
    e = Excitation("s", "force", "b", Step(10.0, start=0.05), dof="z")
    r = simulate(sdof(C), [e], t_end=0.5, dt=1e-3, record_from=0.1)
    assert isinstance(r, TimeResponse) and r.method == "modal" and "auto" in r.note
    assert r.time[0] == pytest.approx(0.1) and r.outputs.shape == (6, 401)
    d = r.to_dict()
    assert set(d["outputs"]) == {f"b.{x}" for x in ("x", "y", "z", "rx", "ry", "rz")}
    assert len(d["time"]) == 401
    pk = r.peaks()
    i = list(pk.outputs).index("b.z")
    assert pk.value[i] == pytest.approx(np.abs(step_response(r.time, 10.0, 0.05, C)).max(), rel=1e-9)
    assert "b.z" in r.report()
    assert r.data.outputs.shape == (6, 401)
    with pytest.raises(ValueError, match="modal"):
        simulate(sdof(), [e], t_end=0.1, dt=1e-3, method="rk4")
    with pytest.raises(ModelError, match="dt"):
        simulate(sdof(), [e], t_end=0.1, dt=0.0)
    calls = []

    def mine(job):
        calls.append(job)
        return np.zeros((len(job.time), len(job.plant.outputs))), "zeros"

    z = simulate(sdof(), [e], t_end=0.1, dt=1e-3, method=mine)
    assert calls and z.method == "mine" and not z.outputs.any()


def test_finite_rate_sweep_envelope() -> None:
    from vibss.model.excitation import SineSweep
    from vibss.time.sweep import sweep_envelope

    def run(T: float):
        e = Excitation("sw", "force", "b", SineSweep(f1=1.0, f2=6.0, a1=10.0, a2=10.0, sweep_time=T), dof="z")
        return sweep_envelope(sdof(C), e, outputs=["b.z"], points=300)

    slow, fast = run(200.0), run(5.0)
    assert abs(slow.peak_ratio()[0] - 1.0) < 0.03            # quasi-static sweep = steady state
    np.testing.assert_allclose(slow.steady.max(), 10.0 / (C * WN), rtol=2e-3)  # F / (c w_n) at resonance
    assert fast.peak_ratio()[0] < 0.8                          # a fast sweep does not build up ...
    f_peak = fast.frequency_hz[np.argmax(fast.envelope[0])]
    assert f_peak > WN / (2 * np.pi) * 1.05                    # ... and peaks late (upward sweep)


def test_plots_build_with_peaks_and_panels() -> None:
    import matplotlib

    matplotlib.use("Agg")
    model = two_body()
    e = Excitation("p", "force", "base", HalfSine(100.0, 0.0, 0.02), dof="z")
    r = simulate(model, [e], outputs=["base.z", "top.z", "base.z.acc"], t_end=0.3, dt=1e-3)
    fig = r.plot(by="body")
    assert len(fig.axes) >= 2                       # one panel per body at least
    fig_all = r.plot(by="all")
    assert len(fig_all.axes) >= 1
    sweep = Excitation("s", "force", "base", SineSweep(f1=2.0, f2=40.0, a1=50.0, a2=50.0, sweep_time=2.0),
                       dof="z")
    env = sweep_envelope(model, sweep, outputs=["base.z"])
    assert len(env.plot().axes) == 1


def test_modal_time_path_with_damper_only_mounts_matches_forced_response():
    """Found in review: undamped rigid combinations in the complex-mode set formed Jordan blocks
    at 0 and the modal path returned 1e272; the rigid subspace is now rotated as in the FRF path."""
    from vibss import Body, Model, Mount, MountType

    m = Model([Body("b", 10.0, [1, 1.2, 1.4])],
              [Mount("d", MountType("d", [0, 0, 0], [50.0, 60.0, 70.0]), "b", at=[0.1, 0.2, 0.3])])
    t = np.arange(0, 0.2 + 1e-12, 1e-3)
    kw = dict(inputs={"b.fz": np.sin(2 * np.pi * 7 * t)}, outputs=["b.z", "b.rx", "b.y"], t_end=0.2, dt=1e-3)
    got = simulate(m, [], **kw)
    ref = simulate(m, [], method="forced_response", **kw)
    scale = np.abs(ref.outputs).max(axis=1, keepdims=True)
    assert np.abs(got.outputs - ref.outputs).max() <= 1e-8 * scale.max()


def test_auto_falls_back_to_forced_response_when_complex_modes_refuse(monkeypatch):
    """When complex modes refuse (DefectiveModesError: nearly dependent eigenvectors), simulate's
    auto runs forced_response and says so; an explicit method='modal' raises."""
    import vibss.time.kernels.modal as tm
    from vibss import DefectiveModesError
    from cases.models import two_body

    def refuse(*args, **kwargs):
        raise DefectiveModesError("complex modes: the eigenvectors are nearly dependent (test)")

    monkeypatch.setattr(tm, "complex_modes", refuse)        # two_body has non-proportional damping
    t = np.arange(0, 0.1 + 1e-12, 1e-3)
    kw = dict(inputs={"engine.fz": np.sin(2 * np.pi * 9 * t)}, outputs=["engine.z"], t_end=0.1, dt=1e-3)
    r = simulate(two_body(), [], **kw)
    assert r.note.startswith("auto -> forced_response") and "nearly dependent" in r.note
    ref = simulate(two_body(), [], method="forced_response", **kw)
    np.testing.assert_array_equal(r.outputs, ref.outputs)
    with pytest.raises(DefectiveModesError):
        simulate(two_body(), [], method="modal", **kw)


# == moved from the file of review-round fixes: time response and sweep envelope ==========

# 1 -- derivatives of prescribed motions --------------------------------------------------------

@pytest.mark.parametrize("method", ["modal", "forced_response", "ivp"])
def test_acceleration_of_a_prescribed_displacement_is_refused(method: str) -> None:
    with pytest.raises(AnalysisError, match=r"output 'a\.z\.acc' depends on the second derivative "
                                            r"of input 'a\.z\.disp'.*\(a\.z\.acc\)"):
        simulate(sc.chain(), inputs={"a.z.disp": lambda t: np.sin(2 * np.pi * 3 * np.asarray(t))},
                 outputs=["a.z.acc"], t_end=0.5, dt=1e-3, method=method)


@pytest.mark.parametrize("method", ["modal", "forced_response", "ivp"])
def test_representable_derivatives_of_prescribed_motions(method: str) -> None:
    # z = V t: z' = V (piecewise constant, kept); velocity u = A t: z'' = A (kept)
    V, A = 0.02, 3.0
    r = simulate(sc.chain(), inputs={"a.z.disp": lambda t: V * np.asarray(t)}, outputs=["a.z.vel"],
                 t_end=0.2, dt=1e-3, method=method)
    np.testing.assert_allclose(r.output("a.z.vel")[1:], V, rtol=1e-6)
    r = simulate(sc.chain(), inputs={"a.z.vel": lambda t: A * np.asarray(t)}, outputs=["a.z.acc"],
                 t_end=0.2, dt=1e-3, method=method)
    np.testing.assert_allclose(r.output("a.z.acc")[1:], A, rtol=1e-6)


# 2 -- initial conditions ------------------------------------------------------------------------

@pytest.mark.parametrize("initial, message", [
    ({"b": [[0, 0, 0.01, 0, 0, 0]]}, r"initial\['b'\]: expected \{'displacement'"),
    ({"b": (1, 2, 3)}, r"initial\['b'\]: expected \{'displacement'"),
    ({"b": 5}, r"initial\['b'\]: expected .* got 5"),
    ({"c": {"displacement": [0] * 6}}, r"initial: unknown body 'c'; bodies are \['b'\]"),
    ({"b": {"disp": [0] * 6}}, r"initial\['b'\]: unknown key\(s\) \['disp'\]"),
    ({"b": {"velocity": [1, 2]}}, r"initial\['b'\]: velocity: expected 6 finite numbers"),
    ({"b": {"displacement": "abc"}}, r"initial\['b'\]: displacement: expected 6 finite numbers"),
])
def test_malformed_initial_conditions_are_refused(initial: object, message: str) -> None:
    with pytest.raises(ModelError, match=message):
        simulate(sc.sdof(), inputs={"b.fz": lambda t: 0 * t}, outputs=["b.z"], t_end=0.1, dt=1e-3,
                 initial=initial)


# 3 -- other arguments -----------------------------------------------------------------------------

@pytest.mark.parametrize("kwargs, message", [
    ({"t_end": "abc"}, r"t_end: expected a number of seconds, got 'abc'"),
    ({"dt": None}, r"dt: expected a number of seconds, got None"),
    ({"method": "ivp", "rtol": -1}, r"rtol: expected a positive relative tolerance, got -1"),
    ({"method": "ivp", "atol": -1.0}, r"atol: expected None or an absolute tolerance >= 0"),
    ({"solver": "foo"}, r"solver: expected one of .* got 'foo'"),
    ({"t_end": 1e6, "dt": 1e-9}, r"is 1e\+15 samples, more than 5e\+07"),
    ({"dt": 0.0}, r"dt: must be a positive time step"),
    ({"dt": -1e-3}, r"dt: must be a positive time step"),
    ({"t_end": 0.0}, r"t_end: must be at least dt"),
    ({"method": "nope"}, r"method: unknown 'nope'"),
])
def test_bad_simulate_arguments_are_model_errors(kwargs: dict, message: str) -> None:
    args = {"t_end": 0.1, "dt": 1e-3, **kwargs}
    with pytest.raises(ModelError, match=message):
        simulate(sc.sdof(), inputs={"b.fz": lambda t: 0 * t}, outputs=["b.z"], **args)


# 4 -- free vibration ------------------------------------------------------------------------------

@pytest.mark.parametrize("method", ["modal", "forced_response", "ivp"])
def test_free_decay_from_initial_conditions_alone(method: str) -> None:
    x0, v0 = 0.01, -0.2
    r = simulate(sc.sdof(), outputs=["b.z"], t_end=1.0, dt=1e-3, method=method, rtol=1e-10, atol=1e-14,
                 initial={"b": {"displacement": [0, 0, x0, 0, 0, 0], "velocity": [0, 0, v0, 0, 0, 0]}})
    zeta = sc.C / (2 * np.sqrt(sc.K * sc.M))
    wd = sc.WN * np.sqrt(1 - zeta**2)
    t = r.time
    x = np.exp(-zeta * sc.WN * t) * (x0 * np.cos(wd * t) + (v0 + zeta * sc.WN * x0) / wd * np.sin(wd * t))
    assert np.abs(r.output("b.z") - x).max() < 1e-7 * x0
    assert r.input_names == () and r.inputs.shape == (0, t.size)
    assert r.note.startswith("free vibration")


def test_free_vibration_from_the_model_file_initial_conditions() -> None:
    k = (2 * np.pi) ** 2      # 1 Hz with 1 kg
    model = loads_model(f"""
[[body]]
name = "b"
mass = 1.0
inertia = [1.0, 1.0, 1.0]
initial = {{ displacement = [0, 0, 0.01, 0, 0, 0] }}
[[mount_type]]
name = "t"
stiffness = [{k!r}, {k!r}, {k!r}]
[[mount]]
type = "t"
body = "b"
""")
    r = simulate(model, [], outputs=["b.z"], t_end=0.5, dt=1e-3)
    np.testing.assert_allclose(r.output("b.z"), 0.01 * np.cos(2 * np.pi * r.time), atol=1e-12)
    with pytest.raises(ModelError, match="nothing drives the response"):
        simulate(sc.sdof(), outputs=["b.z"], t_end=0.1, dt=1e-3)


# 5 -- sweep envelope at 0 Hz and on an undamped resonance ------------------------------------------

@pytest.mark.parametrize("kind", ["acceleration", "velocity"])
def test_sweep_envelope_from_zero_hz(kind: str) -> None:
    e = Excitation("g", kind, "ground", SineSweep(f1=0.0, f2=20.0, a1=1.0, a2=1.0, sweep_time=5.0), dof="z")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = sweep_envelope(sc.sdof(), e, outputs=["b.z", "mount.m.dz"])
    assert r.frequency_hz[0] == 0.0
    assert np.isinf(r.steady[0, 0])          # absolute displacement under a constant acc / vel
    # relative deflection per unit input at 0 Hz: -m/k for acceleration, -m s/(...) -> 0 for velocity
    expected = sc.M / sc.K if kind == "acceleration" else 0.0
    assert abs(r.steady[1, 0] - expected) <= 1e-9 * sc.M / sc.K
    assert np.all(np.isfinite(r.steady[:, 1:]))


def test_steady_state_exactly_on_an_undamped_resonance() -> None:
    und = sc.sdof(0.0)
    p = build_plant(und, ["b.fz"], ["b.z", "b.x"])
    h = _frf(p, np.array([sc.WN, 0.5 * sc.WN]))
    assert np.isinf(h[0, 0]) and h[1, 0] == 0.0    # the z mode drives b.z, not b.x
    np.testing.assert_allclose(h[0, 1].real, 1 / (sc.K - sc.M * (0.5 * sc.WN) ** 2), rtol=1e-12)
    # the reviewer's case: the envelope grid lands on the 5 Hz natural frequency
    k = (2 * np.pi * 5) ** 2 / 4
    m0 = Model([Body("b", 1.0, [1, 1, 1])], symmetric(Mount("m", MountType("t", [k] * 3), "b", at=[0.5, 0.5, 0.0])))
    e = Excitation("sw", "force", "b", SineSweep(f1=0.0, f2=10.0, a1=1.0, a2=1.0, sweep_time=10.0), dof="z")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = sweep_envelope(m0, e, outputs=["b.z", "b.x"], points=401)
    j = int(np.argmin(np.abs(r.frequency_hz - 5.0)))
    assert r.frequency_hz[j] == 5.0            # the z mode: 4 k on 1 kg, exactly 5 Hz
    assert np.isinf(r.steady[0, j]) and r.steady[1, j] == 0.0
    w = 2 * np.pi * r.frequency_hz[j + 1]
    np.testing.assert_allclose(r.steady[0, j + 1], 1 / abs(4 * k - w**2), rtol=1e-9)
