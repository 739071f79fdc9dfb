"""Multi-support excitation: named supports, each moving on its own (issue 14 item 4).

References: the rigid-ground model (two supports moved identically must give its answer), the
closed-form 2-DOF heave/pitch bar on two springs (written here by hand, not from vibss), scipy's
solve_ivp of that bar, and superposition.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

import vibss
from vibss import Body, Model, Mount, MountType, Support
from vibss.errors import ModelError, ModelFileError, SignalError
from vibss.linear.plant.build import build_plant
from vibss.linear.solve.exact import response

DOFS = ("x", "y", "z", "rx", "ry", "rz")


def _pair(supports: bool, loss: float = 0.0) -> Model:
    """A 3-D body on four inclined, damped mounts; with ``supports`` the left pair stands on
    support L and the right pair on R, else all four on the rigid ground."""
    t = MountType("t", [1.2e4, 1.5e4, 3e4], damping=[12.0, 20.0, 35.0], loss_factor=loss)
    body = Body("box", 25.0, [1.1, 1.7, 2.2], cog=[0.05, -0.02, 0.3],
                principal_axes=Rotation.from_euler("xyz", [5, -8, 12], degrees=True).as_matrix())
    mounts = []
    for name, at, sup in (("fl", [-0.4, 0.3, 0.0], "L"), ("rl", [-0.45, -0.3, 0.02], "L"),
                          ("fr", [0.4, 0.32, -0.01], "R"), ("rr", [0.42, -0.3, 0.0], "R")):
        o = Rotation.from_euler("xyz", [0, 20 * np.sign(at[0]), 10 * np.sign(at[1])], degrees=True).as_matrix()
        mounts.append(Mount(name, t, "box", at=at, orientation=o, frame="global",
                            support=sup if supports else None))
    return Model([body], mounts, supports=[Support("L"), Support("R", "right pair")] if supports else ())


OUT = ["box.z", "box.ry", "box.x.acc", "mount.fl.fz", "mount.fr.f1"]


@pytest.mark.parametrize("kind", ["disp", "vel", "acc"])
def test_two_supports_moved_identically_give_the_rigid_ground_frf(kind):
    w = 2 * np.pi * np.array([0.5, 3.0, 7.0, 15.0, 40.0])
    rigid, split = _pair(False, loss=0.05), _pair(True, loss=0.05)
    for d in DOFS:
        yr = response(build_plant(rigid, [f"ground.{d}.{kind}"], OUT + ["ground.fz", "ground.my"]), 1j * w)
        ys = response(build_plant(split, [f"L.{d}.{kind}", f"R.{d}.{kind}"],
                                  OUT + ["L.fz", "R.fz", "L.my", "R.my", "ground.fz"]), 1j * w)
        both = ys[:, 0] + ys[:, 1]
        scale = np.abs(yr).max(axis=-1, keepdims=True)
        np.testing.assert_allclose(both[:5], yr[:5, 0], atol=1e-12 * scale[:5, 0].max(), rtol=1e-11)
        # the reactions share ground's: to round-off of the mounts' forces (stiffness x unit motion)
        fs = 1e-12 * 4 * 3e4 * max(1.0, float(w.max()) ** {"disp": 0, "vel": -1, "acc": -2}[kind])
        np.testing.assert_allclose(both[5] + both[6], yr[5, 0], rtol=1e-11, atol=fs)
        np.testing.assert_allclose(both[7] + both[8], yr[6, 0], rtol=1e-11, atol=fs)
        assert np.abs(ys[9]).max() == 0.0                  # no mount is on the rigid ground


def test_two_supports_moved_identically_give_the_rigid_ground_time_response():
    def a(t):
        return np.sin(2 * np.pi * 6.0 * t) * np.exp(-3 * t)

    rigid = vibss.simulate(_pair(False), inputs={"ground.z.acc": a, "ground.rx.acc": a},
                           outputs=OUT, t_end=0.5, dt=1e-3)
    split = vibss.simulate(_pair(True), inputs={"L.z.acc": a, "R.z.acc": a, "L.rx.acc": a, "R.rx.acc": a},
                           outputs=OUT, t_end=0.5, dt=1e-3)
    scale = np.abs(rigid.outputs).max(axis=-1, keepdims=True)
    np.testing.assert_allclose(split.outputs, rigid.outputs, atol=1e-9 * scale.max(), rtol=0)
    assert np.abs(split.outputs - rigid.outputs).max(axis=-1).max() <= 1e-9 * scale.max()


def test_statics_treat_supports_as_fixed_ground():
    g = [0.0, 0.0, -9.81]
    rigid, split = _pair(False).replace(gravity=g), _pair(True).replace(gravity=g)
    a, b = vibss.static(rigid), vibss.static(split)
    np.testing.assert_allclose(b.q, a.q, rtol=1e-13, atol=1e-16)
    np.testing.assert_allclose(b.mount_force, a.mount_force, rtol=1e-12, atol=1e-10)
    np.testing.assert_allclose(b.reaction, a.reaction, rtol=1e-12, atol=1e-9)


# -- a rigid bar on two springs, each end on its own support: the 2-DOF closed form --------------
M_BAR, J_BAR, XA, XB = 40.0, 6.0, -0.7, 0.5
K1, K2, C1, C2 = 3e4, 5e4, 60.0, 20.0


def _bar() -> Model:
    """Bar with its COG at the origin; spring 1 at x = XA on support A, spring 2 at x = XB on B.
    The mounts also hold the other DOFs (x, y and rotational rates), which do not couple to z, ry."""
    t1 = MountType("s1", [1e4, 1e4, K1], damping=[0, 0, C1], rotational_stiffness=[100.0, 0.0, 100.0])
    t2 = MountType("s2", [1e4, 1e4, K2], damping=[0, 0, C2], rotational_stiffness=[100.0, 0.0, 100.0])
    return Model([Body("bar", M_BAR, [2.0, J_BAR, 6.5])],
                 [Mount("m1", t1, "bar", at=[XA, 0, 0], support="A"),
                  Mount("m2", t2, "bar", at=[XB, 0, 0], support="B")],
                 supports=[Support("A", "left end"), Support("B", "right end")])


def _bar_matrices():
    """Heave z and pitch ry of the bar by hand: a point at x moves by z - x ry."""
    b1, b2 = np.array([1.0, -XA]), np.array([1.0, -XB])
    M = np.diag([M_BAR, J_BAR])
    K = K1 * np.outer(b1, b1) + K2 * np.outer(b2, b2)
    C = C1 * np.outer(b1, b1) + C2 * np.outer(b2, b2)
    return M, K, C, (b1, K1, C1), (b2, K2, C2)


def test_bar_on_two_supports_matches_the_closed_form_frf():
    w = 2 * np.pi * np.array([0.3, 2.0, 4.5, 6.0, 9.0, 25.0])
    M, K, C, *ends = _bar_matrices()
    y = response(build_plant(_bar(), ["A.z.disp", "B.z.disp"], ["bar.z", "bar.ry", "A.fz", "B.fz"]), 1j * w)
    for j, (b, k, c) in enumerate(ends):
        for i, wi in enumerate(w):
            x = np.linalg.solve(K - wi**2 * M + 1j * wi * C, (k + 1j * wi * c) * b)
            np.testing.assert_allclose(y[:2, j, i], x, rtol=1e-11)
            # force into each support: its spring's (k + i w c)(deflection) with the end's own motion
            for row, (bb, kk, cc) in enumerate(ends):
                own = 1.0 if row == j else 0.0
                f = (kk + 1j * wi * cc) * (bb @ x - own)
                np.testing.assert_allclose(y[2 + row, j, i], f, rtol=1e-10, atol=1e-10 * abs(k))


def test_transmissibility_per_support():
    f = np.array([0.0, 1.0, 3.0, 8.0])
    M, K, C, *ends = _bar_matrices()
    for j, name in enumerate(["A", "B"]):
        tr = vibss.transmissibility(_bar(), [f"{name}.z"], ["bar.z", "bar.ry"], frequencies=f)
        b, k, c = ends[j]
        for i, fi in enumerate(f):
            wi = 2 * np.pi * fi
            x = np.linalg.solve(K - wi**2 * M + 1j * wi * C, (k + 1j * wi * c) * b)
            np.testing.assert_allclose(tr.response[:, 0, i], x, rtol=1e-10, atol=1e-14)
    # the transmissibility of each end at 0 Hz: the bar follows it quasi-statically
    a = vibss.transmissibility(_bar(), ["A.z"], ["bar.z"], frequencies=[0.0]).response[0, 0, 0]
    b = vibss.transmissibility(_bar(), ["B.z"], ["bar.z"], frequencies=[0.0]).response[0, 0, 0]
    np.testing.assert_allclose(a.real, XB / (XB - XA), rtol=1e-12)     # lever rule
    np.testing.assert_allclose(b.real, -XA / (XB - XA), rtol=1e-12)
    forced = vibss.transmissibility(_bar(), ["bar.fz"], frequencies=[0.0])
    assert {"A.fz", "B.fz", "ground.fz"} <= set(forced.outputs)


def test_bar_time_response_to_separate_support_motion_matches_solve_ivp():
    wa, wb = 2 * np.pi * 3.0, 2 * np.pi * 7.0
    za = (lambda t: 1e-3 * np.sin(wa * t) ** 2, lambda t: 1e-3 * wa * np.sin(2 * wa * t))
    zb = (lambda t: -2e-3 * np.sin(wb * t) ** 3,
          lambda t: -6e-3 * wb * np.sin(wb * t) ** 2 * np.cos(wb * t))
    M, K, C, (b1, k1, c1), (b2, k2, c2) = _bar_matrices()
    mi = np.linalg.inv(M)

    def rhs(t, s):
        x, v = s[:2], s[2:]
        f = b1 * (k1 * za[0](t) + c1 * za[1](t)) + b2 * (k2 * zb[0](t) + c2 * zb[1](t))
        return np.concatenate([v, mi @ (f - K @ x - C @ v)])

    t = np.arange(0, 0.6 + 1e-12, 1e-3)
    ref = solve_ivp(rhs, (0, t[-1]), np.zeros(4), t_eval=t, rtol=1e-11, atol=1e-15, method="DOP853")
    scale = np.abs(ref.y[:2]).max()
    for method, tol in (("ivp", 1e-9), ("modal", 4e-4)):     # modal: inputs held first-order, O(dt^2)
        r = vibss.simulate(_bar(), inputs={"A.z.vel": za[1], "B.z.vel": zb[1]}, outputs=["bar.z", "bar.ry"],
                           t_end=0.6, dt=1e-3, method=method, rtol=1e-10)
        assert np.abs(r.outputs - ref.y[:2]).max() <= tol * scale


def test_superposition_of_two_supports():
    def fa(t):
        return np.sin(2 * np.pi * 4 * t)

    def fb(t):
        return np.where(t < 0.05, np.sin(np.pi * t / 0.05), 0.0)

    kw = dict(outputs=["bar.z", "bar.ry", "A.fz", "B.fz", "mount.m1.fz"], t_end=0.4, dt=1e-3)
    both = vibss.simulate(_bar(), inputs={"A.z.acc": fa, "B.z.acc": fb}, **kw)
    a = vibss.simulate(_bar(), inputs={"A.z.acc": fa}, **kw)
    b = vibss.simulate(_bar(), inputs={"B.z.acc": fb}, **kw)
    scale = np.abs(both.outputs).max(axis=-1, keepdims=True)
    assert np.abs(both.outputs - (a.outputs + b.outputs)).max(axis=-1).max() <= 1e-10 * scale.max()
    assert np.all(np.abs(both.outputs - (a.outputs + b.outputs)) <= 1e-10 * scale)


def test_statespace_takes_support_inputs():
    pytest.importorskip("control")
    w = 2 * np.pi * np.array([1.0, 4.0, 11.0])
    ins, outs = ["A.z.acc", "B.z.acc"], ["bar.z", "bar.ry.acc", "A.fz"]
    sys = vibss.statespace(_bar(), inputs=ins, outputs=outs)
    ref = response(build_plant(_bar(), ins, outs), 1j * w)
    h = np.stack([sys(1j * wi) for wi in w], axis=-1)
    np.testing.assert_allclose(h, ref, rtol=1e-9, atol=1e-12 * np.abs(ref).max())
    assert list(sys.input_labels) == ["A:z:acc", "B:z:acc"]


def test_control_plant_takes_support_motion():
    pytest.importorskip("control")
    from vibss.control import plant

    prop = MountType("p", [1e4, 1e4, 2e4], damping=[1e-3 * 1e4, 1e-3 * 1e4, 1e-3 * 2e4],
                     rotational_stiffness=[50.0, 50.0, 50.0], rotational_damping=[0.05, 0.05, 0.05])
    model = Model([Body("bar", M_BAR, [2.0, J_BAR, 6.5])],
                  [Mount("m1", prop, "bar", at=[XA, 0, 0], support="A"),
                   Mount("m2", prop, "bar", at=[XB, 0, 0], support="B")],
                  supports=[Support("A"), Support("B")],
                  actuators=[vibss.Actuator("a", mount="m1", axis=3)])
    w = 2 * np.pi * np.array([2.0, 9.0])
    for kind, y in (("disp", "bar.z"), ("vel", "bar.z.vel"), ("acc", "bar.z.acc")):
        u = f"A.z.{kind}"
        P = plant(model, disturbances=[u], performance=[y], measurements=[y])
        ref = response(build_plant(model, [u], [y]), 1j * w)
        h = np.stack([P(1j * wi)[0, 0] for wi in w])
        np.testing.assert_allclose(h, ref[0, 0], rtol=1e-8)
    # the bar on two springs is statically determinate: under one end's motion it follows without
    # deflecting a spring, so any dampers follow too and the realization is exact
    P = plant(_bar().replace(actuators=[vibss.Actuator("a", mount="m1", axis=3)]),
              disturbances=["A.z.acc"], performance=["bar.z.acc"], measurements=["bar.z.acc"])
    ref = response(build_plant(_bar(), ["A.z.acc"], ["bar.z.acc"]), 1j * w)
    np.testing.assert_allclose(np.stack([P(1j * wi)[0, 0] for wi in w]), ref[0, 0], rtol=1e-8)
    # two mounts per support, dampers not proportional to the springs: the quasi-static motion
    # deflects dampers, the relative realization would not be exact; refused
    box = _pair(True).replace(actuators=[vibss.Actuator("a", mount="fl", axis=3)])
    with pytest.raises(vibss.ControlDesignError, match=r"support 'L'.*'L\.z\.disp'"):
        plant(box, disturbances=["L.z.acc"], performance=["box.z.acc"], measurements=["box.z.acc"])
    P = plant(box, disturbances=["L.z.disp"], performance=["box.z"], measurements=["box.z"])
    ref = response(build_plant(box, ["L.z.disp"], ["box.z"]), 1j * w)
    np.testing.assert_allclose(np.stack([P(1j * wi)[0, 0] for wi in w]), ref[0, 0], rtol=1e-8)


def test_file_round_trip_keeps_supports():
    model = _bar()
    text = vibss.dumps_model(model)
    assert "[[support]]" in text and 'support = "A"' in text
    back = vibss.loads_model(text)
    assert [(s.name, s.description) for s in back.supports] == [("A", "left end"), ("B", "right end")]
    assert [m.support for m in back.mounts] == ["A", "B"]
    assert vibss.dumps_model(back) == text
    w = 1j * 2 * np.pi * np.array([1.0, 5.0])
    ins = ["A.z.acc", "B.rx.vel"]
    np.testing.assert_array_equal(response(build_plant(back, ins), w), response(build_plant(model, ins), w))


def test_supports_in_a_model_file_with_units_and_an_excitation():
    text = """
[model]
units = { length = "mm", mass = "kg", force = "N" }
[[body]]
name = "bar"
mass = 40.0
inertia = [2e6, 6e6, 6.5e6]
[[mount_type]]
name = "s"
stiffness = [10, 10, 30]
[[support]]
name = "front"
description = "front wheel"
[[support]]
name = "rear"
[[mount]]
type = "s"
body = "bar"
at = [-700, 0, 0]
support = "front"
[[mount]]
type = "s"
body = "bar"
at = [500, 0, 0]
support = "rear"
[[excitation]]
name = "bump"
kind = "acceleration"
target = "front"
dof = "z"
function = { type = "half_sine", amplitude = 1.0, duration = 0.01 }
"""
    model = vibss.loads_model(text)
    assert [m.support for m in model.mounts] == ["front", "rear"]
    assert model.excitations[0].signal == "front.z.acc"
    r = vibss.simulate(model, outputs=["bar.z", "rear.fz"], t_end=0.2, dt=1e-3)
    assert np.abs(r.outputs).max() > 0


def test_bad_supports_are_refused_with_their_names():
    t = MountType("t", [1.0, 1.0, 1.0])
    b = [Body("b", 1.0, [1, 1, 1]), Body("c", 1.0, [1, 1, 1])]
    with pytest.raises(ModelError, match=r"mount 'm': support: unknown support 'lft'.*did you mean 'left'"):
        Model(b, [Mount("m", t, "b", support="lft")], supports=[Support("left")])
    with pytest.raises(ModelError, match=r"mount 'm': support: unknown support 'left'; the model has no supports"):
        Model(b, [Mount("m", t, "b", support="left")])
    with pytest.raises(ModelError, match=r"mount 'm': support 'left' is only for a mount whose 'to' end is "
                                         r"ground; this mount joins body 'b' to body 'c'"):
        Mount("m", t, "b", to="c", support="left")
    with pytest.raises(ModelError, match=r"support name 'left' is used twice"):
        Model(b, [], supports=[Support("left"), Support("left")])
    with pytest.raises(ModelError, match=r"support 'c': the name is taken by a body"):
        Model(b, [], supports=[Support("c")])
    for bad in ("ground", "mount"):
        with pytest.raises(ModelError, match=rf"support '{bad}': the name '{bad}' is reserved"):
            Support(bad)
    with pytest.raises(ModelError, match=r"support 'a.b': name contains '.'"):
        Support("a.b")
    with pytest.raises(ModelError, match=r"model: supports\[0\] must be a Support"):
        Model(b, [], supports=["left"])
    model = Model(b, [Mount("m", t, "b", support="left")], supports=[Support("left")])
    with pytest.raises(SignalError, match=r"a force on 'left' does nothing"):
        build_plant(model, ["left.fz"])
    with pytest.raises(SignalError, match=r"'right' is neither a body nor 'ground' nor a support"):
        build_plant(model, ["right.z.acc"])
    text = vibss.dumps_model(model).replace('support = "left"', 'support = "lefty"')
    with pytest.raises(ModelFileError, match=r"mount\[1\].*support.*unknown support 'lefty'"):
        vibss.loads_model(text)


def test_models_without_supports_are_unchanged():
    model = _pair(False)
    asm = vibss.assemble(model)
    assert asm.nz == 6 and asm.Kg.shape == (6, 6) and asm.deflection_matrix().shape == (12, 12)
    assert "support" not in vibss.model_to_dict(model) if hasattr(vibss, "model_to_dict") else True
    from vibss.io.modelfile import model_to_dict
    assert "support" not in model_to_dict(model)


def test_the_model_file_guide_example_of_supports_loads():
    import re
    from pathlib import Path

    text = (Path(__file__).parents[1] / "docs" / "model-file.md").read_text()
    block = next(b for b in re.findall(r"```toml\n(.*?)```", text, re.S) if "[[support]]" in b)
    model = vibss.loads_model('[model]\nunits = { length = "mm" }\n[[body]]\nname = "bar"\nmass = 40.0\n'
                              'inertia = [2e6, 6e6, 6.5e6]\n[[mount_type]]\nname = "spring"\n'
                              'stiffness = [10, 10, 30]\n' + block)
    assert [m.support for m in model.mounts] == ["front", "rear"]
    assert model.excitations[0].signal == "front.z.acc"


def test_design_tools_see_supports_as_ground():
    from vibss.design.montecarlo import batch_modes
    from vibss.design.parameters import apply, current_values, parameters_of, stiffness_derivatives

    rigid, split = _pair(False), _pair(True)
    params = [parameters_of(m, ["fl.k3", "fr.rx", "rl.x"]) for m in (rigid, split)]
    v0 = current_values(split, params[1])
    vals = v0 + np.array([[2e3, 0.1, 0.01], [-1e3, -0.2, -0.02]])
    fr, _, _ = batch_modes(rigid, params[0], vals)
    fs, _, _ = batch_modes(split, params[1], vals)
    np.testing.assert_allclose(fs, fr, rtol=1e-12)
    np.testing.assert_allclose(stiffness_derivatives(vibss.assemble(split), params[1]),
                               stiffness_derivatives(vibss.assemble(rigid), params[0]), rtol=1e-12, atol=1e-6)
    moved = apply(split, params[1], vals[0])
    assert [m.support for m in moved.mounts] == ["L", "L", "R", "R"] and moved.support_names == ["L", "R"]


def test_time_plot_groups_support_reactions_with_ground():
    pytest.importorskip("matplotlib")
    from vibss.plotting.response import quantity_of

    assert quantity_of("front.fz", "N") == "force into ground"
    assert quantity_of("front.my", "N m") == "moment into ground"
    r = vibss.simulate(_bar(), inputs={"A.z.acc": lambda t: np.sin(20 * t)}, outputs=["bar.z", "A.fz"],
                       t_end=0.1, dt=1e-3)
    fig = r.plot()
    assert len(fig.axes) == 3                        # the input on top, then bar and A


def test_static_settlement_of_one_support_follows_the_lever_rule():
    r = vibss.static(_bar(), prescribed={"A.z": -0.01})
    # the bar on two springs turns about the other end: no spring deflects, no force
    np.testing.assert_allclose(r.body("bar")[2], -0.01 * XB / (XB - XA), rtol=1e-12)
    np.testing.assert_allclose(r.body("bar")[4], -0.01 / (XB - XA), rtol=1e-12)
    assert np.abs(r.mount_force).max() <= 1e-9
    split = vibss.static(_pair(True), prescribed={"L.z": 0.002, "R.z": 0.002})
    rigid = vibss.static(_pair(False), prescribed={"ground.z": 0.002})
    np.testing.assert_allclose(split.q, rigid.q, rtol=1e-12, atol=1e-17)
    with pytest.raises(ModelError, match=r"unknown L DOF 'L.w'"):
        vibss.static(_pair(True), prescribed={"L.w": 0.1})


def test_static_reaction_splits_per_support_by_the_lever_rule():
    """Under gravity each end of the bar carries its lever-rule share of the weight (the pitch
    stiffness of the mounts is zero, so the two vertical springs are statically determinate)."""
    w = M_BAR * 9.81
    r = vibss.static(_bar().replace(gravity=[0.0, 0.0, -9.81]))
    reactions = r.reactions
    assert list(reactions) == ["ground", "A", "B"]
    np.testing.assert_allclose(reactions["A"][2], -w * XB / (XB - XA), rtol=1e-12)
    np.testing.assert_allclose(reactions["B"][2], w * XA / (XB - XA), rtol=1e-12)
    np.testing.assert_allclose(reactions["ground"], 0.0, atol=0.0)
    # each support's moment about the origin is its force times its arm
    np.testing.assert_allclose(reactions["A"][4], -XA * reactions["A"][2], rtol=1e-12)
    np.testing.assert_allclose(r.reaction, sum(reactions.values()), rtol=0, atol=1e-12 * w)
    np.testing.assert_allclose(r.reaction[:3], [0.0, 0.0, -w], atol=1e-9 * w)
    assert "Reaction per support" in r.report()
    assert set(r.to_dict()["reactions"]) == {"ground", "A", "B"}
    assert "reactions" not in vibss.static(_pair(False)).to_dict()
