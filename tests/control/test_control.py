"""vibss.control: actuators and sensors, generalized plants, designs, closed loops.

References: closed forms (SDOF skyhook), hand-written python-control plants (the quarter car of
MATLAB's active-suspension example), python-control's own margins, invariants (passivity).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import control

import vibss
import cases.models as cases
import vibss.control as vc
from vibss import Body, Model, Mount, MountType
from vibss.errors import ControlDesignError, ModelError, SignalError
from vibss.frequency.statespace_response import evaluate
from vibss.io.modelfile import dumps_model, load_example, loads_model
from vibss.model.actuation import Actuator, Sensor

M_, K_ = 10.0, 1e4
WN = np.sqrt(K_ / M_)


def sdof(zeta: float, **extra: object) -> Model:
    return cases.sdof(M_, K_, 2 * zeta * M_ * WN, type_name="iso",
                      actuators=[Actuator("a", mount="m", axis=3, **extra)],
                      sensors=[Sensor("v", "velocity", body="b", direction=[0, 0, 1]),
                               Sensor("rv", "relative_velocity", mount="m", axis=3),
                               Sensor("f", "mount_force", mount="m", axis=3),
                               Sensor("s", "relative_displacement", mount="m", axis=3)])


# -- the plant ---------------------------------------------------------------------------------
@pytest.mark.parametrize("kind, order", [("acc", 2), ("vel", 1)])
def test_ground_motion_plant_has_no_integrators_and_the_closed_form(kind: str, order: int) -> None:
    zeta = 0.05
    m = sdof(zeta)
    P = vc.plant(m, [f"ground.z.{kind}"], performance=["b.z.acc"], measurements=["sensor.s"], dofs=["b.z"])
    assert P.nstates == 2                                     # no integrator states
    s = 2j * np.pi * np.array([0.5, 5.0, 50.0])
    h = evaluate(P, s.imag)
    c = 2 * zeta * M_ * WN
    t = (c * s + K_) / (M_ * s ** 2 + c * s + K_)
    np.testing.assert_allclose(h[0, 0], t * s ** (2 - order), rtol=1e-12)
    np.testing.assert_allclose(h[1, 0], (t - 1) / s ** order, rtol=1e-12)     # stroke = body - ground
    np.testing.assert_allclose(h[1, 1], 1 / (M_ * s ** 2 + c * s + K_), rtol=1e-12)
    vc.lqr(vc.plant(m, [f"ground.z.{kind}"], performance=["b.z.acc", "actuator.a.u"], measurements="states",
                    dofs=["b.z"]))                          # control.lqr no longer hits a singular matrix


def test_outputs_needing_the_integral_of_a_disturbance_are_refused() -> None:
    with pytest.raises(ControlDesignError, match=r"sensor\.v.*integral of the acceleration.*'\.vel'"):
        vc.plant(sdof(0.05), ["ground.z.acc"], performance=["b.z.acc"], measurements=["sensor.v"], dofs=["b.z"])


def test_actuator_bandwidth_is_a_first_order_lag() -> None:
    bw = 40.0
    P = vc.plant(sdof(0.05, bandwidth=bw), ["ground.z.vel"], performance=["b.z.acc"], measurements=["sensor.s"],
                 dofs=["b.z"])
    s = 2j * np.pi * np.array([1.0, 40.0, 300.0])
    c = 2 * 0.05 * M_ * WN
    expected = 1 / (M_ * s ** 2 + c * s + K_) / (1 + s / (2 * np.pi * bw))
    np.testing.assert_allclose(evaluate(P, s.imag)[1, 1], expected, rtol=1e-12)
    assert "actuator:a:force" in P.state_labels


def test_sensor_signals_against_their_definitions() -> None:
    t = MountType("iso", [1e4, 2e4, 3e4], [10.0, 20.0, 30.0])
    m = Model([Body("b", 5.0, [0.2, 0.3, 0.4])], [Mount("m", t, "b", at=[0.1, 0.2, -0.1])],
              actuators=[Actuator("h", body="b", direction=[1, 0, 0], at=[0, 0, 0.5])],
              sensors=[Sensor("p", "acceleration", body="b", at=[0.1, 0.2, -0.1], direction=[0, 1, 1]),
                       Sensor("d", "relative_displacement", body="b", at=[0.1, 0.2, -0.1], direction=[0, 0, 1]),
                       Sensor("f", "mount_force", mount="m", direction=[0, 0, 1])])
    f = [2.0, 7.0]
    r = vibss.frequency_response(m, ["actuator.h.f", "ground.z.disp"],
                                 ["sensor.p", "sensor.d", "sensor.f", "mount.m.dz", "mount.m.fz", "ground.my",
                                  "b.x", "b.ry"], f)
    s = 2j * np.pi * np.array(f)
    # the actuator: a unit x force at 0.5 m above the COG = b.fx plus a 0.5 N m moment about y
    ref = vibss.frequency_response(m, ["b.fx", "b.my", "ground.z.disp"], ["b.x", "b.ry"], f)
    np.testing.assert_allclose(r["b.x", "actuator.h.f"], ref["b.x", "b.fx"] + 0.5 * ref["b.x", "b.my"], rtol=1e-12)
    # a relative displacement across the mount point along z is the mount's z deflection
    np.testing.assert_allclose(r["sensor.d"], r["mount.m.dz"], rtol=1e-12)
    np.testing.assert_allclose(r["sensor.f"], r["mount.m.fz"], rtol=1e-12)
    # absolute acceleration of the point along (0, 1, 1)/sqrt(2) from the point's y and z motion
    pts = vibss.frequency_response(m.replace(control_points=[vibss.ControlPoint("q", "b", [0.1, 0.2, -0.1])]),
                                   ["actuator.h.f"], ["q.y", "q.z"], f)
    expected = (pts["q.y", "actuator.h.f"] + pts["q.z", "actuator.h.f"]) / np.sqrt(2) * s ** 2
    np.testing.assert_allclose(r["sensor.p", "actuator.h.f"], expected, rtol=1e-10)
    # the actuator's reaction goes into ground: -1 N along x at z = 0.5 m -> -0.5 N m about y
    static = vibss.frequency_response(m, ["actuator.h.f"], ["ground.my", "mount.m.fx", "mount.m.fz"], [0.0])
    h = static.response[:, 0, 0].real
    lever = np.array([0.1, 0.2, -0.1])
    my_mount = lever[2] * h[1] - lever[0] * h[2]           # (r x F)_y of the mount force into ground
    assert h[0] == pytest.approx(my_mount - 0.5, rel=1e-9)


def test_model_file_round_trip_and_errors() -> None:
    m = load_example("platform")
    assert len(m.actuators) == 12 and len(m.sensors) == 12
    again = loads_model(dumps_model(m))
    assert [a.name for a in again.actuators] == [a.name for a in m.actuators]
    assert again.settings["control"] == m.settings["control"]
    text = dumps_model(m)
    for bad, msg in ((text.replace('mount = "fl"\naxis = 1', 'mount = "fx"\naxis = 1', 1), r"actuator\[1\].*mount.*'fx'"),
                     (text.replace('kind = "velocity"', 'kind = "speed"', 1), r"sensor\[1\].*kind"),
                     (text.replace('axis = 1', 'axis = 7', 1), r"actuator\[1\].*axis.*1, 2 or 3"),
                     (text.replace('design = "skyhook"', 'design = "magic"'), r"\[control\].*design")):
        with pytest.raises(ModelError, match=msg):
            loads_model(bad)


@pytest.mark.parametrize("kwargs, msg", [
    ({"name": "a", "body": "b"}, "needs a direction"),
    ({"name": "a", "mount": "m"}, "axis"),
    ({"name": "a", "body": "b", "direction": [0, 0, 0]}, "nonzero"),
    ({"name": "a", "body": "b", "direction": [0, 0, 1], "bandwidth": -1.0}, "bandwidth"),
    ({"name": "a:b", "body": "b", "direction": [0, 0, 1]}, "':'"),
])
def test_bad_actuators(kwargs: dict, msg: str) -> None:
    with pytest.raises(ModelError, match=msg):
        Actuator(**kwargs)


def test_model_checks_element_references() -> None:
    t = MountType("t", [1.0] * 3)
    with pytest.raises(ModelError, match="actuator 'a': mount: unknown mount 'n'"):
        Model([Body("b", 1.0, [1, 1, 1])], [Mount("m", t, "b")], actuators=[Actuator("a", mount="n", axis=3)])
    with pytest.raises(ModelError, match="sensor 's': body: unknown body 'c'"):
        Model([Body("b", 1.0, [1, 1, 1])], sensors=[Sensor("s", "velocity", body="c", direction=[1, 0, 0])])


# -- skyhook on a single-DOF isolator ------------------------------------------------------------
@pytest.mark.parametrize("zeta", [0.0, 0.05, 0.2])
def test_skyhook_closed_form(zeta: float) -> None:
    m = sdof(zeta)
    P = vc.plant(m, ["ground.z.vel"], performance=["b.z.vel"], measurements=["sensor.v"], dofs=["b.z"])
    zs = 0.3
    K = vc.skyhook(P, 2 * zs * M_ * WN)
    cl = vc.close(P, K)
    t = vibss.transmissibility(cl.system, ["ground.z.vel"], ["b.z.vel"], [WN / (2 * np.pi)])
    assert abs(t.response[0, 0, 0]) == pytest.approx(np.sqrt(1 + 4 * zeta ** 2) / (2 * (zeta + zs)), rel=1e-12)
    # the closed loop's damping ratio is zeta + zeta_sky
    assert cl.damping[cl.poles.imag > 0][0] == pytest.approx(zeta + zs, rel=1e-12)
    if zeta == 0.0:     # with no passive damping the skyhook isolator rolls off at -40 dB/decade
        hi = vibss.transmissibility(cl, ["ground.z.vel"], ["b.z.vel"], [1e3, 1e4])
        slope = 20 * np.log10(abs(hi.response[0, 0, 1]) / abs(hi.response[0, 0, 0]))
        assert slope == pytest.approx(-40.0, abs=0.01)


def test_velocity_feedback_equals_a_passive_damper() -> None:
    """Direct velocity feedback with gain c is a viscous damper c in parallel with the mount."""
    g = 150.0
    m = sdof(0.02)
    P = vc.plant(m, ["ground.z.vel"], performance=["b.z.vel"], measurements=["sensor.rv"], dofs=["b.z"])
    cl = vc.close(P, vc.velocity_feedback(P, g))
    c = 2 * 0.02 * M_ * WN + g
    passive = Model([Body("b", M_, [1, 1, 1])], [Mount("m", MountType("iso", [K_] * 3, [c] * 3), "b")])
    f = [1.0, WN / (2 * np.pi), 40.0]
    ref = vibss.transmissibility(passive, ["ground.z"], ["b.z"], f)
    got = vibss.transmissibility(cl, ["ground.z.vel"], ["b.z.vel"], f)
    np.testing.assert_allclose(got.response, ref.response, rtol=1e-11)


def test_integral_force_feedback_adds_damping_and_is_stable() -> None:
    m = sdof(0.01)
    P = vc.plant(m, ["ground.z.vel"], performance=["b.z.vel"], measurements=["sensor.f"], dofs=["b.z"])
    cl = vc.close(P, vc.integral_force(P, 30.0, leak_hz=0.5))
    assert np.all(cl.poles.real < 0)
    assert cl.damping[np.argmin(np.abs(np.abs(cl.poles) - WN))] > 0.1


# -- names ----------------------------------------------------------------------------------------
def test_names_survive_feedback_and_interconnect() -> None:
    m = sdof(0.05)
    P = vc.plant(m, ["ground.z.vel"], performance=["b.z.vel"], measurements=["sensor.v"], dofs=["b.z"])
    K = vc.skyhook(P, 100.0)
    loop = control.feedback(P["sensor.v", "actuator.a.u"], K, sign=1)
    assert loop.input_labels == ["actuator:a:u"] and loop.output_labels == ["sensor:v"]
    ic = vc.interconnect([P, K], inputs=["ground.z.vel"], outputs=["b.z.vel", "actuator.a.u"])
    assert ic.input_labels == ["ground:z:vel"] and ic.output_labels == ["b:z:vel", "actuator:a:u"]
    cl = vc.close(P, K)
    np.testing.assert_allclose(evaluate(ic, [5.0, 50.0])[0], evaluate(cl.system["b.z.vel", "ground.z.vel"], [5.0, 50.0])[0],
                               rtol=1e-12)
    assert ic["b.z.vel", "ground.z.vel"].ninputs == 1            # dotted names index the result
    wrong = control.ss([], [], [], [[1.0]], inputs=["nope"], outputs=["actuator:a:u"])
    with pytest.raises(SignalError, match="do not match"):
        control.feedback(P["sensor.v", "actuator.a.u"], wrong)


# -- margins --------------------------------------------------------------------------------------
def test_margins_match_python_control_on_a_siso_loop() -> None:
    """A PD loop on relative displacement with a slow actuator: finite gain and phase margins."""
    m = sdof(0.02, bandwidth=15.0)
    P = vc.plant(m, ["ground.z.disp"], performance=["b.z"], measurements=["sensor.s"], dofs=["b.z"])
    K = vc.pid(P, {"a": "sensor.s"}, kp=2e4, kd=300.0, tau=1e-3)
    cl = vc.close(P, K)
    L = -(K * P["sensor.s", "actuator.a.u"])              # return ratio, u = K y
    gm, pm, *_ = control.stability_margins(L)
    got = cl.margins[0]
    assert got.gain_margin_db == pytest.approx(20 * np.log10(gm), rel=1e-6)
    assert got.phase_margin_deg == pytest.approx(pm, rel=1e-6)
    dm = control.disk_margins(L, np.geomspace(1, 1e4, 4000))[0]
    assert got.disk_margin == pytest.approx(float(dm), rel=2e-2)


def test_unstable_design_is_an_error() -> None:
    m = sdof(0.02, bandwidth=15.0)
    P = vc.plant(m, ["ground.z.disp"], performance=["b.z"], measurements=["sensor.s"], dofs=["b.z"])
    K = vc.pid(P, {"a": "sensor.s"}, kp=1e6)                # far beyond what the actuator lag allows
    with pytest.raises(ControlDesignError, match="unstable: pole"):
        vc.close(P, K)
    assert vc.close(P, K, allow_unstable=True, margins=False).poles.real.max() > 0


# -- the quarter car of MATLAB's active suspension example ------------------------------------------
MB, MW, KS, BS, KT = 300.0, 60.0, 16000.0, 1000.0, 190000.0


def quarter_car() -> Model:
    susp, tyre = MountType("susp", [0, 0, KS], [0, 0, BS]), MountType("tyre", [0, 0, KT])
    return Model([Body("body", MB, [1, 1, 1], [0, 0, 0.5]), Body("wheel", MW, [1, 1, 1], [0, 0, 0.2])],
                 [Mount("suspension", susp, "body", to="wheel", at=[0, 0, -0.3]), Mount("tyre", tyre, "wheel")],
                 actuators=[Actuator("act", mount="suspension", axis=3, bandwidth=60 / (2 * np.pi))],
                 sensors=[Sensor("travel", "relative_displacement", mount="suspension", axis=3),
                          Sensor("acc", "acceleration", body="body", direction=[0, 0, 1])])


def hand_written(noise: float | None = None) -> control.StateSpace:
    """MATLAB's quarter car (states x_b, x_b', x_w, x_w'; inputs road r, actuator command), outputs
    body travel, body acceleration, suspension travel, actuator command."""
    A = [[0, 1, 0, 0], [-KS / MB, -BS / MB, KS / MB, BS / MB], [0, 0, 0, 1], [KS / MW, BS / MW, -(KS + KT) / MW, -BS / MW]]
    B = [[0, 0], [0, 1 / MB], [0, 0], [KT / MW, -1 / MW]]
    C = [[1, 0, 0, 0], A[1], [1, 0, -1, 0]]
    D = [[0, 0], [0, 1 / MB], [0, 0]]
    car = control.ss(A, B, C, D) * control.append(control.ss([], [], [], [[1.0]]), control.ss(control.tf([1], [1 / 60, 1])))
    return car


def test_quarter_car_plant_equals_the_hand_written_one() -> None:
    P = vc.plant(quarter_car(), ["ground.z.disp"], performance=["body.z", "body.z.acc", "mount.suspension.d3"],
                 measurements=["sensor.travel"], dofs=["body.z", "wheel.z"])
    w = 2 * np.pi * np.geomspace(0.05, 200, 80)
    got = evaluate(P, w)[:3]
    ref = evaluate(hand_written(), w)
    np.testing.assert_allclose(got, ref, rtol=1e-10, atol=1e-10 * np.abs(ref).max())


def test_quarter_car_lqr_and_hinf_match_the_hand_written_plant() -> None:
    perf = ["body.z.acc", "mount.suspension.d3", "actuator.act.u"]
    wts = {"body.z.acc": 1.0, "mount.suspension.d3": 1e4, "actuator.act.u": 1e-6}
    P = vc.plant(quarter_car(), ["ground.z.disp"], performance=perf, measurements="states", dofs=["body.z", "wheel.z"])
    K = vc.lqr(P, wts)
    hand = hand_written()
    A, B, C, D = (np.asarray(x) for x in (hand.A, hand.B, hand.C, hand.D))
    Cz = np.vstack([C[[1, 2]], np.zeros((1, A.shape[0]))])
    Dz = np.vstack([D[[1, 2]][:, [1]], [[1.0]]])
    W = np.diag(list(wts.values()))
    Kh, _, Eh = control.lqr(A, B[:, [1]], Cz.T @ W @ Cz, Dz.T @ W @ Dz, Cz.T @ W @ Dz)
    np.testing.assert_allclose(np.sort_complex(K.design["poles"]), np.sort_complex(Eh), rtol=1e-8)
    # H-infinity: the same weighted problem on both plants gives the same gamma
    Pn = vc.plant(quarter_car(), ["ground.z.disp"], performance=perf, measurements=["sensor.travel"], noise=1e-3,
                  dofs=["body.z", "wheel.z"])
    Kinf = vc.hinf(Pn, wts and {k: np.sqrt(v) for k, v in wts.items()})
    Bw = np.hstack([B[:, [0]], np.zeros((A.shape[0], 1)), B[:, [1]]])
    sw = np.sqrt(np.array(list(wts.values())))
    Cg = np.vstack([sw[:, None] * Cz, C[[2]]])
    Dg = np.zeros((4, 3))
    Dg[:3, [0]] = sw[:, None] * np.vstack([D[[1, 2]][:, [0]], [[0.0]]])
    Dg[:3, [2]] = sw[:, None] * Dz
    Dg[3, 1] = 1e-3
    _, gam, _ = vc.optimal._synthesise(control.ss(A, Bw, Cg, Dg), 1, 1, "hand-written")
    assert Kinf.design["gamma"] == pytest.approx(gam, rel=2e-3)          # two bisections to 1e-3 each
    # the achieved norm, independently: the weighted closed loop on a dense grid
    cl = vc.close(Pn, Kinf, margins=False)
    w = np.geomspace(0.1, 1e4, 6000)
    h = evaluate(cl.system, w)[:3, :2] * np.sqrt(np.array(list(wts.values())))[:, None, None]
    peak = max(np.linalg.svd(h[:, :, i], compute_uv=False)[0] for i in range(w.size))
    assert peak <= Kinf.design["gamma"] * (1 + 1e-6) and peak >= Kinf.design["gamma"] * (1 - 1e-2)
    assert np.all(vc.close(Pn, Kinf, margins=False).poles.real < 0)


# -- pre-flight ------------------------------------------------------------------------------------
def test_preflight_messages() -> None:
    m = sdof(0.05)
    P = vc.plant(m, ["ground.z.vel"], performance=["b.z.vel"], measurements=["sensor.v"], dofs=["b.z"])
    with pytest.raises(ControlDesignError, match=r"D12 .*actuator\.a\.u"):
        vc.hinf(P)
    P2 = vc.plant(m, ["ground.z.vel"], performance=["b.z.vel", "actuator.a.u"], measurements=["sensor.v"], dofs=["b.z"])
    with pytest.raises(ControlDesignError, match=r"D21 .*sensor\.v.*noise="):
        vc.hinf(P2)
    with pytest.raises(ControlDesignError, match="measure its states"):
        vc.lqr(P2)
    # a free body (no mount in x) that no actuator moves: not stabilizable, named
    free = Model([Body("b", 1.0, [1, 1, 1])], [Mount("m", MountType("t", [0, 0, 1e3], [0, 0, 1.0]), "b")],
                 actuators=[Actuator("a", mount="m", axis=3)])
    P3 = vc.plant(free, ["b.fx"], performance=["b.z", "actuator.a.u"], measurements="states", dofs=["b.x", "b.z"])
    with pytest.raises(ControlDesignError, match="not stabilizable.*uncontrollable"):
        vc.lqr(P3)


# -- semi-active ------------------------------------------------------------------------------------
@pytest.mark.slow
def test_clipped_skyhook_never_injects_power_and_equals_passive_at_fixed_damping() -> None:
    m = sdof(0.0)
    P = vc.plant(m, ["ground.z.vel"], performance=["b.z.vel"], measurements=["sensor.v", "sensor.rv"], dofs=["b.z"])
    pulse = vibss.HalfSine(0.2, start=0.0, duration=0.02)
    r = vc.clipped_skyhook(P, {"ground.z.vel": pulse}, end=1.0, step=1e-3, c_sky=400.0, c_min=5.0, c_max=300.0)
    assert r.power.max() <= 0.0
    assert np.all((r.damping >= 5.0) & (r.damping <= 300.0))
    # fixed damping (c_min = c_max = c): the linear passive isolator, simulated independently
    c = 100.0
    fixed = vc.clipped_skyhook(P, {"ground.z.vel": pulse}, end=0.5, step=1e-3, c_sky=0.0, c_min=c, c_max=c)
    passive = Model([Body("b", M_, [1, 1, 1])], [Mount("m", MountType("iso", [K_] * 3, [c] * 3), "b")])
    t = fixed.time
    from scipy.integrate import solve_ivp

    # relative displacement r and absolute velocity x': r' = x' - v, m x'' = -k r - c (x' - v)
    sol = solve_ivp(lambda tt, x: [x[1] - float(pulse.value(np.array([tt]))[0]),
                                   (-K_ * x[0] - c * (x[1] - float(pulse.value(np.array([tt]))[0]))) / M_],
                    (0, t[-1]), [0.0, 0.0], t_eval=t, max_step=1e-4, rtol=1e-10, atol=1e-14)
    np.testing.assert_allclose(fixed["b.z.vel"], sol.y[1], atol=1e-6 * np.abs(sol.y[1]).max())


# -- the precision platform ----------------------------------------------------------------------------
def test_platform_skyhook_meets_the_isolation_targets() -> None:
    m = load_example("platform")
    cs = m.settings["control"]
    P = vc.plant(m, cs["disturbances"], performance=cs["performance"])
    cl = vc.close(P, vc.skyhook(P, cs["gain"]))
    assert min(x.gain_margin_db for x in cl.margins) >= 6.0
    assert min(x.phase_margin_deg for x in cl.margins) >= 45.0
    f = np.geomspace(0.3, 30.0, 400)
    passive, active = cl.transmissibility(cs["disturbances"], cs["performance"], f)
    for i in range(3):
        tp, ta = np.abs(passive.response[i, i]), np.abs(active.response[i, i])
        k = int(np.argmax(tp))
        assert 20 * np.log10(tp[k] / ta[k]) >= 20.0


def platform_hinf() -> tuple[vc.ClosedLoop, dict]:
    """The documented H-infinity design: synthesised on the ideal-actuator plant, closed on the real one."""
    m = load_example("platform")
    cs = m.settings["control"]
    perf = [f"table.{d}.vel" for d in ("x", "y", "z", "rx", "ry", "rz")]
    design = vc.plant(m, cs["disturbances"], performance=perf + [a.command for a in m.actuators], noise=1e-2,
                      ideal_actuators=True)
    weights = {**{s: 1.0 for s in perf}, "table.x.vel": 2.0, "table.y.vel": 2.0,
               **{a.command: 1.6e-3 for a in m.actuators}}
    K = vc.hinf(design, weights)
    P = vc.plant(m, cs["disturbances"], performance=cs["performance"])
    return vc.close(P, K), cs


def test_platform_hinf_meets_the_isolation_targets() -> None:
    cl, cs = platform_hinf()
    assert min(x.gain_margin_db for x in cl.margins) >= 6.0
    assert min(x.phase_margin_deg for x in cl.margins) >= 45.0
    assert min(x.disk_margin for x in cl.margins) > 0.5
    f = np.geomspace(0.3, 30.0, 400)
    passive, active = cl.transmissibility(cs["disturbances"], cs["performance"], f)
    for i in range(3):
        tp, ta = np.abs(passive.response[i, i]), np.abs(active.response[i, i])
        k = int(np.argmax(tp))
        assert 20 * np.log10(tp[k] / ta[k]) >= 20.0


def test_report_and_cli_run_the_files_control_table(capsys: pytest.CaptureFixture[str]) -> None:
    from vibss.cli import main
    from vibss.report import study

    r = study(load_example("platform"), figures=False)
    sec = r.section("control")
    assert not sec.skipped and not sec.failed
    assert all(x["reduction_db"] >= 20.0 for x in r.results["control"].reductions())
    assert main(["control", "--example", "platform", "--format", "json"]) == 0
    import json
    data = json.loads(capsys.readouterr().out)
    assert len(data["margins"]) == 12 and data["design"]["design"] == "skyhook"
    assert main(["control", "--example", "prism"]) == 2          # no [control] table: one clear line
    assert "no [control] table" in capsys.readouterr().err


def test_demand_random_rms_against_the_closed_form_and_shock_peak_against_simulate() -> None:
    """Velocity feedback makes the isolator a single-DOF oscillator with zeta_total: under a white
    ground-acceleration PSD G the stroke's variance is G / (8 zeta w^3) (one-sided PSD in Hz)."""
    from vibss.random import PSD

    g = 120.0
    m = sdof(0.01)
    P = vc.plant(m, ["ground.z.acc"], performance=["b.z.acc"], measurements=["sensor.rv", "sensor.s"], dofs=["b.z"])
    cl = vc.close(P, vc.velocity_feedback(P, g, pairs={"a": "sensor.rv"}))
    zeta = (2 * 0.01 * M_ * WN + g) / (2 * M_ * WN)
    level = 0.02 * 9.80665 ** 2                               # (m/s^2)^2/Hz
    white = PSD([1e-3, 1e4], [0.02, 0.02])
    d = cl.demand({"ground.z.acc": white}, ["sensor.s", "actuator.a.u"])
    assert d["sensor.s"] == pytest.approx(np.sqrt(level / (8 * zeta * WN ** 3)), rel=2e-3)
    # the actuator force is g times the relative velocity: variance G / (8 zeta w) times g^2
    assert d["actuator.a.u"] == pytest.approx(g * np.sqrt(level / (8 * zeta * WN)), rel=2e-3)
    # a half-sine shock: the peak stroke equals the passive isolator with damping c + g, simulated by vibss
    pulse = vibss.HalfSine(20.0, start=0.0, duration=0.01)
    peak = cl.demand({"ground.z.acc": pulse}, ["sensor.s"], end=1.0, step=2e-5)["sensor.s"]
    c = 2 * 0.01 * M_ * WN + g
    passive = Model([Body("b", M_, [1, 1, 1])], [Mount("m", MountType("iso", [K_] * 3, [c] * 3), "b")])
    r = vibss.simulate(passive, inputs={"ground.z.acc": pulse.value}, outputs=["mount.m.dz"], t_end=1.0, dt=2e-5)
    assert peak == pytest.approx(np.abs(r["mount.m.dz"]).max(), rel=1e-3)


def test_preflight_names_an_undetectable_mode() -> None:
    free = Model([Body("b", 1.0, [1, 1, 1])], [Mount("m", MountType("t", [0, 0, 1e3], [0, 0, 1.0]), "b")],
                 actuators=[Actuator("a", mount="m", axis=3), Actuator("h", body="b", direction=[1, 0, 0])],
                 sensors=[Sensor("s", "relative_displacement", mount="m", axis=3)])
    P = vc.plant(free, ["b.fx", "b.fz"], performance=["b.z", "b.x", "actuator.a.u", "actuator.h.u"],
                 measurements=["sensor.s"], noise=1e-3, dofs=["b.x", "b.z"])
    with pytest.raises(ControlDesignError, match=r"not detectable.*unobservable.*no measurement sees it"):
        vc.lqg(P)


def test_frequency_dependent_mounts_in_a_control_plant() -> None:
    """A Zener isolator (issue 14) under an actuator: with ground displacement the plant carries the
    mount's internal state and matches k*(s) / (m s^2 + k*(s)); ground acceleration, whose
    relative-motion realization has no place for that state, is refused by name."""
    m0, k0, kinf, tau, c = 2.0, 1e4, 3e4, 2e-3, 8.0
    t = MountType("rubber", damping=[c] * 3, rheology={"type": "zener", "k_0": k0, "k_inf": kinf, "tau": tau})
    m = Model([Body("b", m0, [1, 1, 1])], [Mount("m", t, "b")], actuators=[Actuator("a", mount="m", axis=3)],
              sensors=[Sensor("s", "relative_displacement", mount="m", axis=3)])
    P = vc.plant(m, ["ground.z.disp"], performance=["b.z"], measurements=["sensor.s"], dofs=["b.z"])
    w = np.array([3.0, 70.0, 400.0])
    s = 1j * w
    k = k0 + (kinf - k0) * s * tau / (1 + s * tau) + c * s
    h = evaluate(P, w)
    np.testing.assert_allclose(h[0, 0], k / (m0 * s ** 2 + k), rtol=1e-10)
    np.testing.assert_allclose(h[0, 1], 1 / (m0 * s ** 2 + k), rtol=1e-10)        # actuator force -> body
    with pytest.raises(ControlDesignError, match=r"ground\.z\.acc.*frequency-dependent mounts"):
        vc.plant(m, ["ground.z.acc"], performance=["b.z"], measurements=["sensor.s"], dofs=["b.z"])


def test_lqg_closed_loop_poles_are_the_regulator_and_filter_poles() -> None:
    """Separation principle: the LQG loop's poles are eig(A - B2 K) together with eig(A - L C2),
    with K and L the gains the design reports (an invariant of the controller's assembly, not a
    number from it); and it shares lqr's regulator gain on the same weights."""
    perf = ["body.z.acc", "mount.suspension.d3", "actuator.act.u"]
    wts = {"body.z.acc": 1.0, "mount.suspension.d3": 1e4, "actuator.act.u": 1e-6}
    P = vc.plant(quarter_car(), ["ground.z.disp"], performance=perf, measurements=["sensor.travel"], noise=1e-3,
                 dofs=["body.z", "wheel.z"])
    k = vc.lqg(P, wts)
    A = np.asarray(P.A)
    u = [P.input_labels.index(n) for n in P.groups["u"]]
    y = [P.output_labels.index(n) for n in P.groups["y"]]
    B2, C2 = np.asarray(P.B)[:, u], np.asarray(P.C)[y]
    K, L = k.design["K"], k.design["L"]
    expected = np.concatenate([np.linalg.eigvals(A - B2 @ K), np.linalg.eigvals(A - L @ C2)])
    cl = vc.close(P, k)
    got = np.sort_complex(cl.poles)
    np.testing.assert_allclose(got, np.sort_complex(expected), rtol=1e-7, atol=1e-9 * np.abs(expected).max())
    Ps = vc.plant(quarter_car(), ["ground.z.disp"], performance=perf, measurements="states", dofs=["body.z", "wheel.z"])
    np.testing.assert_allclose(K, vc.lqr(Ps, wts).design["K"], rtol=1e-9)


def test_a_fragile_loop_warns_with_python_controls_margins() -> None:
    """Issue 33 item 7: a loop with a 9.7 deg phase margin and a disk margin of 0.17 closed silently."""
    m = sdof(0.02, bandwidth=15.0)
    P = vc.plant(m, ["ground.z.disp"], performance=["b.z"], measurements=["sensor.s"], dofs=["b.z"])
    K = vc.pid(P, {"a": "sensor.s"}, kp=2e4, kd=300.0, tau=1e-3)
    L = -(K * P["sensor.s", "actuator.a.u"])
    pm = control.stability_margins(L)[1]
    assert pm < 30.0                                       # fragile by python-control's own numbers
    with pytest.warns(vibss.VibssWarning, match=rf"loop 'actuator.a.u'.*phase margin {pm:.3g} deg.*disk margin") as rec:
        vc.close(P, K)
    assert len(rec) == 1
    robust = vc.pid(P, {"a": "sensor.s"}, kp=1e3, kd=100.0, tau=1e-3)
    gm, pm2, *_ = control.stability_margins(-(robust * P["sensor.s", "actuator.a.u"]))
    assert abs(20 * np.log10(gm)) > 6 and abs(pm2) > 30   # robust: no word
    with warnings.catch_warnings():
        warnings.simplefilter("error", vibss.VibssWarning)
        vc.close(P, robust)
