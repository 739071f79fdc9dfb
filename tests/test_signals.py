"""Named signals -> Plant: names, units, errors, prescribed DOFs, mount and ground forces."""

from __future__ import annotations

import numpy as np
import pytest

from vibss import Body, ControlPoint, Model, ModelError, Mount, MountType, Orientation, assemble
from vibss.linear.plant.build import build_plant
from vibss.linear.plant.names import control_name, default_outputs


def two_body() -> Model:
    t1 = MountType("soft", [2e4, 3e4, 5e4], [40.0, 10.0, 80.0])
    t2 = MountType("stiff", [8e4, 6e4, 9e4], [5.0, 60.0, 20.0])
    inertia = [[12.0, -1.5, 0.8], [-1.5, 20.0, 0.6], [0.8, 0.6, 25.0]]
    b1 = Body("frame", 300.0, inertia, cog=[0.1, -0.05, 0.3])
    b2 = Body("engine", 120.0, [3.0, 5.0, 6.0], cog=[0.4, 0.2, 0.9],
              principal_axes=Orientation.from_euler([20, 10, -5], degrees=True))
    tilt = Orientation.from_euler([30, 15, 0], degrees=True)
    mounts = [Mount("g1", t1, "frame", at=[0.8, 0.6, -0.3], orientation=tilt),
              Mount("g2", t1, "frame", at=[-0.7, 0.5, -0.2]),
              Mount("g3", t1, "frame", at=[0.6, -0.6, -0.35], orientation=Orientation.from_euler([-40, 0, 20], degrees=True)),
              Mount("g4", t1, "frame", at=[-0.5, -0.7, -0.3]),
              Mount("e1", t2, "engine", at=[0.3, 0.3, -0.2], to="frame", orientation=tilt),
              Mount("e2", t2, "engine", at=[-0.3, 0.25, -0.25], to="frame"),
              Mount("e3", t2, "engine", at=[0.0, -0.3, -0.2], to="frame",
                    orientation=Orientation.from_euler([0, 45, 0], degrees=True))]
    cps = [ControlPoint("sensor", "engine", [0.2, 0.1, 0.3])]
    return Model([b1, b2], mounts, cps, name="two body")


def test_names_units_and_shapes():
    m = two_body()
    p = build_plant(m, ["engine.fz", "frame.mx", "sensor.fy", "ground.z.acc"],
                    ["engine.x", "engine.rx.vel", "sensor.z.acc", "mount.e1.d2", "mount.g1.f3", "ground.mz"])
    assert p.inputs == ("engine.fz", "frame.mx", "sensor.fy", "ground.z.acc")
    assert p.kinds == ("force", "force", "force", "acceleration")
    assert p.units == ("m", "rad/s", "m/s^2", "m", "N", "N m")
    assert p.n == 12 and p.F.shape == (12, 4) and p.Oq.shape == (6, 12)
    assert default_outputs(m)[:2] == ("frame.x", "frame.y")
    assert control_name("mount.e1.d2") == "mount:e1:d2"


@pytest.mark.parametrize("name, hint", [("engine.fzz", "engine.fz"), ("engin.fz", "engine.fz"),
                                        ("ground.q.disp", None), ("ground.fz", None)])
def test_bad_input_names(name, hint):
    with pytest.raises(ModelError) as exc:
        build_plant(two_body(), [name])
    assert "valid forms" in str(exc.value) and repr(name) in str(exc.value)
    if hint:
        assert f"did you mean {hint!r}" in str(exc.value)


@pytest.mark.parametrize("name", ["engine.xx", "mount.nope.f1", "mount.e1.f7", "sensor.rx", "ground.fq"])
def test_bad_output_names(name):
    with pytest.raises(ModelError, match="valid forms"):
        build_plant(two_body(), ["engine.fz"], [name])


def test_duplicates_and_empty():
    with pytest.raises(ModelError, match="more than once"):
        build_plant(two_body(), ["engine.fz", "engine.fz"])
    with pytest.raises(ModelError, match="at least one"):
        build_plant(two_body(), [])


def test_prescribed_body_dof_leaves_unknowns():
    m = two_body()
    a = assemble(m)
    p = build_plant(m, ["frame.rx.disp"], ["frame.rx", "engine.z"])
    assert p.n == 11 and "frame.rx" not in p.dofs
    free = [i for i in range(12) if i != 3]
    np.testing.assert_allclose(p.Kz[:, 0], a.K[free, 3])
    np.testing.assert_allclose(p.Mz[:, 0], a.M[free, 3])      # products of inertia couple rx
    assert np.any(p.Mz[:, 0] != 0)
    np.testing.assert_allclose(p.Pz[:, 0], [1.0, 0.0])          # the prescribed DOF itself


def test_mount_and_ground_forces_balance_statically():
    """Static: each mount force = K delta; the total into ground equals the applied force."""
    m = two_body()
    outs = [f"mount.{n}.f{c}" for n in ("g1", "g2", "g3", "g4") for c in "xyz"] + ["ground.fx", "ground.fy", "ground.fz",
                                                                                 "mount.g1.d1", "mount.g1.f1"]
    p = build_plant(m, ["engine.fz", "sensor.fx"], outs)
    q = np.linalg.solve(p.K, p.F)
    y = p.Oq @ q
    tot = y[:12].reshape(4, 3, 2).sum(axis=0)
    np.testing.assert_allclose(tot, y[12:15], atol=1e-9)
    np.testing.assert_allclose(y[12:15], [[0, 1], [0, 0], [1, 0]], atol=1e-9)
    assert y[16, 0] == pytest.approx(2e4 * y[15, 0], rel=1e-9)   # local axis 1: k1 delta1


def test_excitation_objects_and_direction():
    from vibss.model.excitation import Excitation, Step
    m = two_body()
    d = np.array([1.0, 2.0, 2.0]) / 3
    e1 = Excitation("push", "force", "engine", Step(1.0), direction=d, at=[0.1, 0.0, 0.0])
    e2 = Excitation("base", "acceleration", "ground", Step(1.0), dof="z")
    p = build_plant(m, [e1, e2], ["engine.x"])
    assert p.inputs == ("push", "ground.z.acc") and p.kinds == ("force", "acceleration")
    r = np.array([0.1, 0.0, 0.0])
    np.testing.assert_allclose(p.F[6:9, 0], d)
    np.testing.assert_allclose(p.F[9:12, 0], np.cross(r, d))



def test_force_into_a_body_sums_its_carried_mounts():
    """``frame.into.*`` against the engine mounts' own force outputs and the lever arms from the
    model's geometry (frequency domain, viscous damping), and Newton-Euler for the frame: M a =
    applied + into the frame from above - the wrench of the frame's own ground mounts."""
    from vibss import assemble
    from vibss.frequency.kernels import direct

    m = two_body()
    comps = ("fx", "fy", "fz", "mx", "my", "mz")
    carried = [mt for mt in m.mounts if mt.to == "frame"]
    below = [mt for mt in m.mounts if mt.body == "frame"]
    outs = ([f"frame.{d}.acc" for d in ("x", "y", "z", "rx", "ry", "rz")] + [f"frame.into.{c}" for c in comps]
            + [f"mount.{mt.name}.f{c}" for mt in carried + below for c in "xyz"])
    p = build_plant(m, ["engine.fz", "frame.mx", "sensor.fy", "ground.z.acc", "ground.rx.vel"], outs)
    assert p.units[6:12] == ("N",) * 3 + ("N m",) * 3
    h = direct(p, 1j * np.array([3.0, 40.0, 170.0, 900.0]))    # (p, 5, nf)
    cog = np.asarray(m.bodies[m.body_index("frame")].cog)

    def wrench(mounts, first):
        total = np.zeros((6,) + h.shape[1:], complex)
        for j, mt in enumerate(mounts):
            f = h[first + 3 * j:first + 3 * j + 3]
            owner = m.bodies[m.body_index(mt.body)]
            point = np.asarray(mt.at) + np.asarray(owner.cog)     # mounts given in the body frame
            total[:3] += f
            total[3:] += np.cross(point - cog, f, axis=0)
        return total

    into = wrench(carried, 12)
    assert np.abs(h[6:12] - into).max() <= 1e-10 * np.abs(into).max()
    mb = assemble(m, sparse=False).M[:6, :6]                    # frame is body 0
    applied = np.zeros((6, 5))
    applied[:, :3] = p.F[:6, :3]
    lhs = np.einsum("ij,jkf->ikf", mb, h[:6])
    rhs = applied[:, :, None] + h[6:12] - wrench(below, 12 + 3 * len(carried))
    assert np.abs(lhs - rhs).max() <= 1e-9 * np.abs(lhs).max()


def test_ground_into_alias_and_bad_body():
    m = two_body()
    p = build_plant(m, ["engine.fz"], ["ground.fz", "ground.into.fz", "ground.into.my", "ground.my"])
    assert np.array_equal(p.Oq[0], p.Oq[1]) and np.array_equal(p.Oq[2], p.Oq[3])
    with pytest.raises(ModelError, match="'engin' is not a body"):
        build_plant(m, ["engine.fz"], ["engin.into.fz"])
    with pytest.raises(ModelError, match="'sensor' is a control point, not a body"):
        build_plant(m, ["engine.fz"], ["sensor.into.fz"])
    with pytest.raises(ModelError, match="component 'fq' is not one of"):
        build_plant(m, ["engine.fz"], ["frame.into.fq"])
    with pytest.raises(ModelError, match="no mount has 'engine' as its 'to' side"):
        build_plant(m, ["engine.fz"], ["engine.into.fz"])
