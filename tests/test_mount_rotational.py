"""6x6 mounts: rotational stiffness and damping about the mount's local axes, through assembly,
outputs, statics, files and design, against closed forms and invariants."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import vibss
from vibss import Body, Model, Mount, MountType
from vibss.design.montecarlo import batch_modes
from vibss.design.parameters import apply, current_values, parameters_of, stiffness_derivatives
from vibss.errors import ModelError
from vibss.linear.plant.build import build_plant
from vibss.linear.solve.exact import response

KR, CR = 500.0, 2.0
INERTIA = [0.2, 0.3, 0.4]                       # principal, along the global axes
TURN = Rotation.from_euler("y", 90, degrees=True).as_matrix()   # local axis 3 along global x


def _torsion(damping: float = CR, at=(0.5, 0.2, 0.1)) -> Model:
    """A body on one bushing with only a torsional rate about its axis 3 (= global x), off the COG."""
    t = MountType("bush", [0.0, 0.0, 0.0], rotational_stiffness=[0.0, 0.0, KR],
                  rotational_damping=[0.0, 0.0, damping])
    return Model([Body("b", 3.0, INERTIA)], [Mount("m", t, "b", at=at, orientation=TURN)])


def test_torsional_bushing_gives_the_closed_form_mode():
    md = vibss.modes(_torsion())
    elastic = md.frequency_hz > 0
    assert elastic.sum() == 1                         # only rx is restrained, wherever the bushing is
    np.testing.assert_allclose(md.frequency_hz[elastic], np.sqrt(KR / INERTIA[0]) / (2 * np.pi), rtol=1e-12)
    shape = md.shapes[:, elastic][:, 0]
    assert np.abs(shape[[0, 1, 2, 4, 5]]).max() <= 1e-12 * np.abs(shape[3])
    d = vibss.damped_modes(_torsion())
    roots = np.roots([INERTIA[0], CR, KR])            # J s^2 + cr s + kr = 0
    np.testing.assert_allclose(d.poles[d.poles.imag > 0], roots[roots.imag > 0], rtol=1e-12)


def test_torsional_frf_moment_and_rotation_outputs():
    w = np.array([5.0, 40.0, 80.0])
    plant = build_plant(_torsion(), ["b.mx", "ground.rx.disp"],
                        ["b.rx", "mount.m.m3", "mount.m.mx", "mount.m.r3", "ground.mx", "mount.m.fx"])
    y = response(plant, 1j * w)
    z = KR + 1j * w * CR
    rec = 1 / (z - INERTIA[0] * w**2)
    np.testing.assert_allclose(y[0, 0], rec, rtol=1e-12)
    for row in (1, 2, 4):                              # the moment into ground: z theta
        np.testing.assert_allclose(y[row, 0], z * rec, rtol=1e-12)
    np.testing.assert_allclose(y[3, 0], rec, rtol=1e-12)
    assert np.abs(y[5]).max() == 0.0                   # no force from a rotational rate
    np.testing.assert_allclose(y[0, 1], z / (z - INERTIA[0] * w**2), rtol=1e-12)   # rotation transmissibility


def test_statics_report_the_mount_moment_and_the_reaction():
    bush = MountType("bush", [1e5, 1e5, 1e5], rotational_stiffness=[KR, 2 * KR, 3 * KR])
    model = Model([Body("b", 3.0, INERTIA)], [Mount("m", bush, "b")])      # at the COG: no lever
    load = np.zeros(6)
    load[3] = 12.0                                     # 12 N m about x
    r = vibss.static(model, loads=load)
    np.testing.assert_allclose(r.q[3], 12.0 / KR, rtol=1e-12)
    np.testing.assert_allclose(r.mount_moment[0], [12.0, 0, 0], atol=1e-12)
    assert r.free_motions == ()
    np.testing.assert_allclose(r.mount_rotation[0], [12.0 / KR, 0, 0], atol=1e-15)
    np.testing.assert_allclose(r.reaction, [0, 0, 0, 12.0, 0, 0], atol=1e-12)
    assert "6x6 mounts" in r.report()
    assert r.to_dict()["mounts"][0]["moment_local"][0] == pytest.approx(12.0)     # local axes = global here


def _pair() -> Model:
    bush = MountType("bush", [1e5, 2e5, 3e5], [10.0, 10.0, 10.0], rotational_stiffness=[300.0, 700.0, 1100.0],
                     rotational_damping=[0.5, 0.7, 0.9])
    plain = MountType("plain", [4e4, 4e4, 6e4])
    bodies = [Body("a", 5.0, [0.2, 0.3, 0.25], cog=[0, 0, 0]), Body("c", 2.0, [0.05, 0.06, 0.07], cog=[0.4, 0.1, 0.2])]
    orient = Rotation.from_euler("zyx", [20, -35, 50], degrees=True).as_matrix()
    mounts = [Mount("link", bush, "c", to="a", at=[-0.1, 0.05, -0.05], orientation=orient)]
    mounts += [Mount(f"g{i}", plain, "a", at=p) for i, p in enumerate([[0.2, 0.2, -0.1], [-0.2, 0.2, -0.1],
                                                                      [0.0, -0.25, -0.1]])]
    return Model(bodies, mounts)


def _skew(r):
    return np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]])


def test_bushing_between_bodies_is_the_hand_assembled_6x6_and_keeps_rigid_motion_free():
    model = _pair()
    a = vibss.assemble(model)
    link = model.mounts[0]
    t = link.orientation.matrix
    kr = t @ np.diag(link.type.rotational_stiffness) @ t.T
    rot = np.zeros((3, 12))
    rot[:, 9:12], rot[:, 3:6] = np.eye(3), -np.eye(3)  # theta_c - theta_a (c is body 2)
    only_link = Model(model.bodies, [Mount("link", MountType("t", link.type.stiffness, link.type.damping), "c",
                                           to="a", at=link.at, orientation=t)] + list(model.mounts[1:]))
    np.testing.assert_allclose(a.dense("K") - vibss.assemble(only_link).dense("K"), rot.T @ kr @ rot, atol=1e-9)
    # the link alone annihilates any rigid motion of the pair: translation u, rotation phi about the origin
    alone = vibss.assemble(Model(model.bodies, [model.mounts[0]])).dense("K")
    rng = np.random.default_rng(0)
    u, phi = rng.standard_normal(3), rng.standard_normal(3)
    q = np.concatenate([np.concatenate([u + np.cross(phi, b.cog), phi]) for b in model.bodies])
    assert np.abs(alone @ q).max() <= 1e-10 * np.abs(alone).max() * np.abs(q).max()
    g = a.stiffness_factor()                           # K = G^T G keeps the rotational rates too
    np.testing.assert_allclose((g.T @ g).toarray(), a.dense("K"), atol=1e-9 * np.abs(a.dense("K")).max())


def test_wrench_outputs_include_the_bushing_moment():
    model = _pair()
    plant = build_plant(model, ["c.mz", "c.fx"], ["a.into.mx", "a.into.my", "a.into.mz", "mount.link.mx",
                                                  "mount.link.my", "mount.link.mz", "mount.link.fx",
                                                  "mount.link.fy", "mount.link.fz"])
    s = 1j * np.array([30.0, 150.0])
    y = response(plant, s)
    r = model.mount_point(model.mounts[0]) - model.bodies[0].cog
    for k in range(2):
        f, m = y[6:9, :, k], y[3:6, :, k]
        want = m + np.cross(r, f, axis=0)              # moment about a's COG: own moment + r x F
        np.testing.assert_allclose(y[0:3, :, k], want, rtol=1e-10, atol=1e-12 * np.abs(want).max())
    # the mounts' form (soft modes kept apart) agrees with the assembled matrices
    np.testing.assert_allclose(response(plant, s, form="mounts"), y, rtol=1e-9, atol=1e-12 * np.abs(y).max())


def test_file_keys_in_file_units_round_trip():
    text = """
[model]
name = "bush"
units = {length = "mm", angle = "deg"}
[[body]]
name = "b"
mass = 3.0
inertia = [200000.0, 300000.0, 400000.0]
[[mount_type]]
name = "bush"
stiffness = [0, 0, 0]
rotational_stiffness = [0, 0, 8726.646259971648]
rotational_damping = [0, 0, 34.906585039886586]
[[mount]]
name = "m"
type = "bush"
body = "b"
at = [500, 200, 100]
orientation = {matrix = [[0, 0, 1], [0, 1, 0], [-1, 0, 0]]}
"""
    model = vibss.loads_model(text)
    t = model.mount_types["bush"]
    # 8726.6 N mm/deg = 8.7266 N m / (pi/180 rad) = 500 N m/rad
    np.testing.assert_allclose(t.rotational_stiffness, [0, 0, KR], rtol=1e-12)
    np.testing.assert_allclose(t.rotational_damping, [0, 0, CR], rtol=1e-12)
    np.testing.assert_allclose(vibss.modes(model).frequency_hz[-1], np.sqrt(KR / INERTIA[0]) / (2 * np.pi),
                               rtol=1e-12)
    again = vibss.loads_model(vibss.dumps_model(model)).mount_types["bush"]
    np.testing.assert_array_equal(again.rotational_stiffness, t.rotational_stiffness)
    np.testing.assert_array_equal(again.rotational_damping, t.rotational_damping)
    with pytest.raises(ModelError, match="rotational_stiffness"):
        vibss.loads_model(text.replace("rotational_stiffness = [0, 0, 8726.646259971648]",
                                       "rotational_stiffness = [0, 0, -1]"))
    with pytest.raises(ModelError, match=r"mount type 't': rotational_stiffness must not be negative"):
        MountType("t", [1, 1, 1], rotational_stiffness=[1, -1, 1])


def test_design_batches_and_derivatives_see_the_rotational_rates():
    model = _pair()
    params = parameters_of(model, ["link.rx", "link.rz", "link.k1"])
    v0 = current_values(model, params)
    vals = v0 + np.array([[0.1, -0.2, 2e4], [-0.3, 0.05, -1e4]])
    f, _, _ = batch_modes(model, params, vals)
    for v in range(2):
        np.testing.assert_allclose(f[v], vibss.modes(apply(model, params, vals[v])).frequency_hz, rtol=1e-10)
    a = vibss.assemble(model)
    d = stiffness_derivatives(a, params)
    h = 1e-6
    for i in range(2):                                 # the angles: central differences of K
        step = np.zeros(len(v0))
        step[i] = h
        kp = vibss.assemble(apply(model, params, v0 + step)).dense("K")
        km = vibss.assemble(apply(model, params, v0 - step)).dense("K")
        fd = (kp - km) / (2 * h)
        assert np.abs(d[i] - fd).max() <= 1e-6 * np.abs(fd).max()
