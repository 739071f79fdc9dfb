"""Full symmetric 6x6 mount stiffness and damping (issue 14 item 3).

References: the same mount given by its principal rates (bit for bit), a hand-written
``K = T^T K6 T`` with ``T`` the map from body DOFs to the mount's local deflection and rotation,
closed-form frequencies (torsion; a coupled 2-DOF), frame invariance, equilibrium.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import vibss
from vibss import Body, Model, Mount, MountType
from vibss.errors import ModelError, ModelFileError
from vibss.linear.plant.build import build_plant
from vibss.linear.solve.exact import response

ORIENT = Rotation.from_euler("xyz", [15, -25, 40], degrees=True).as_matrix()


def _k6(seed: int = 3, scale=(2e4, 30.0, 500.0)) -> np.ndarray:
    """A coupled, positive-definite 6x6 in local axes: blocks N/m, N m/rad, N/rad."""
    a = np.random.default_rng(seed).normal(size=(6, 6))
    s = np.sqrt(np.array([scale[0]] * 3 + [scale[1]] * 3))
    return (a @ a.T + 0.5 * np.eye(6)) * np.outer(s, s)


def _skew(r):
    return np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]])


def _local_map(r: np.ndarray, t: np.ndarray) -> np.ndarray:
    """(6, 6) body DOFs (COG translation, rotation) -> the mount's local (d1..d3, r1..r3) at the
    point r from the COG: d = u + theta x r = u - [r]x theta, in local axes T^T."""
    w = np.eye(6)
    w[:3, 3:] = -_skew(r)
    return np.kron(np.eye(2), t.T) @ w


def test_a_diagonal_matrix_is_the_same_mount_as_its_rates_bit_for_bit():
    k, kr, c, cr = [1e4, 2e4, 3e4], [100.0, 200.0, 300.0], [10.0, 20.0, 30.0], [0.1, 0.2, 0.3]
    rates = MountType("t", k, c, rotational_stiffness=kr, rotational_damping=cr)
    full = MountType("t", stiffness_matrix=np.diag(k + kr), damping_matrix=np.diag(c + cr))
    assert np.array_equal(full.stiffness, k) and np.array_equal(full.rotational_damping, cr)
    body = Body("b", 3.0, [0.2, 0.3, 0.4], cog=[0.1, -0.2, 0.3])
    a, b = (vibss.assemble(Model([body], [Mount("m", t, "b", at=[0.3, 0.1, -0.2], orientation=ORIENT)]))
            for t in (rates, full))
    for key in ("M", "K", "C", "H", "Kg", "Cg"):
        assert np.array_equal(getattr(a, key), getattr(b, key)), key
    assert (a.stiffness_factor() != b.stiffness_factor()).nnz == 0
    assert not full.coupled


@pytest.mark.parametrize("to_body", [False, True])
def test_a_coupled_matrix_turned_into_global_axes_is_t_transpose_k_t(to_body):
    k6, c6 = _k6(), _k6(7, (3.0, 0.01, 0.2))
    t = MountType("bush", stiffness_matrix=k6, damping_matrix=c6)
    assert t.coupled
    np.testing.assert_array_equal(t.stiffness, np.diag(k6)[:3])
    bodies = [Body("b", 3.0, [0.2, 0.3, 0.4], cog=[0.1, -0.2, 0.3]),
              Body("c", 5.0, [0.5, 0.6, 0.7], cog=[-0.4, 0.2, -0.1])]
    at = np.array([0.35, 0.15, -0.05])                     # global
    mount = Mount("m", t, "b", at=at, orientation=ORIENT, frame="global", to="c" if to_body else "ground")
    asm = vibss.assemble(Model(bodies, [mount]))
    tb = _local_map(at - bodies[0].cog, ORIENT)
    tm = np.zeros((6, 12))
    tm[:, :6] = tb
    if to_body:
        tm[:, 6:] = -_local_map(at - bodies[1].cog, ORIENT)
    for mat, ref in ((asm.K, k6), (asm.C, c6)):
        hand = tm.T @ ref @ tm
        np.testing.assert_allclose(mat, hand, rtol=0, atol=1e-12 * np.abs(hand).max())
    g = asm.stiffness_factor()                                   # K = G^T G keeps the coupling
    np.testing.assert_allclose((g.T @ g).toarray(), tm.T @ k6 @ tm, rtol=0, atol=1e-11 * np.abs(k6).max())
    if not to_body:
        # a rigid motion of the bodies and ground together deflects nothing: K q + Kg z = 0
        for z in np.eye(6):
            q = np.zeros(12)
            for i, b in enumerate(bodies):
                q[6 * i:6 * i + 3] = z[:3] + np.cross(z[3:], b.cog)
                q[6 * i + 3:6 * i + 6] = z[3:]
            np.testing.assert_allclose(asm.K @ q + asm.Kg @ z, 0.0, atol=1e-10 * np.abs(k6).max())


def test_torsion_only_matrix_gives_the_closed_form_frequency():
    kr = 500.0
    k6 = np.zeros((6, 6))
    k6[5, 5] = kr                                   # torsion about local axis 3
    turn = Rotation.from_euler("y", 90, degrees=True).as_matrix()   # local 3 along global x
    inertia = [0.2, 0.3, 0.4]
    m = Model([Body("b", 3.0, inertia)], [Mount("m", MountType("t", stiffness_matrix=k6), "b",
                                                at=[0.5, 0.2, 0.1], orientation=turn)])
    md = vibss.modes(m)
    elastic = md.frequency_hz > 0
    assert elastic.sum() == 1
    np.testing.assert_allclose(md.frequency_hz[elastic], np.sqrt(kr / inertia[0]) / (2 * np.pi), rtol=1e-12)


def test_coupled_translation_and_rotation_give_the_2dof_closed_form():
    """A mount at the COG with k_x, k_ry and their coupling kc (force along x per rad about y):
    det([[kx - w^2 m, kc], [kc, kry - w^2 Iy]]) = 0; the other DOFs held apart by stiff rates."""
    m, iy, kx, kry, kc = 4.0, 0.3, 2e4, 600.0, 1500.0
    k6 = np.diag([kx, 5e4, 6e4, 700.0, kry, 800.0])
    k6[0, 4] = k6[4, 0] = kc
    model = Model([Body("b", m, [0.25, iy, 0.35])], [Mount("m", MountType("t", stiffness_matrix=k6), "b")])
    roots = np.sort(np.roots([m * iy, -(kx * iy + kry * m), kx * kry - kc**2]).real)
    f = vibss.modes(model).frequency_hz
    for w2 in roots:
        assert np.min(np.abs(f - np.sqrt(w2) / (2 * np.pi))) <= 1e-12 * f.max()


def test_frame_invariance_of_a_coupled_mount():
    t = MountType("bush", stiffness_matrix=_k6())
    body = Body("b", 3.0, [0.2, 0.3, 0.4], cog=[0.1, -0.2, 0.3])
    mounts = [Mount("m", t, "b", at=[0.3, 0.1, -0.2], orientation=ORIENT),
              Mount("n", t, "b", at=[-0.3, 0.1, -0.2])]
    model = Model([body], mounts, gravity=[0, 0, -9.81])
    q = Rotation.from_euler("zyx", [33, -12, 71], degrees=True).as_matrix()
    turned = model.transformed(q, offset=[1.0, -2.0, 0.5])
    np.testing.assert_allclose(vibss.modes(turned).frequency_hz, vibss.modes(model).frequency_hz, rtol=1e-11)
    a, b = vibss.static(model), vibss.static(turned)
    np.testing.assert_allclose(b.mount_deflection_local, a.mount_deflection_local, rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(b.mount_force, a.mount_force @ q.T, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(b.mount_moment, a.mount_moment @ q.T, rtol=1e-9, atol=1e-9)


def test_statics_mount_force_and_moment_and_equilibrium():
    k6 = _k6()
    t = MountType("bush", stiffness_matrix=k6)
    body = Body("b", 3.0, [0.2, 0.3, 0.4], cog=[0.1, -0.2, 0.3])
    pts = [np.array([0.3, 0.1, -0.2]), np.array([-0.3, 0.1, -0.2])]
    model = Model([body], [Mount("m", t, "b", at=pts[0], orientation=ORIENT), Mount("n", t, "b", at=pts[1])],
                  loads=[vibss.Load("l", "b", force=[10.0, -20.0, -30.0], moment=[1.0, 2.0, -3.0])])
    r = vibss.static(model)
    for p, (at, o) in enumerate(zip(pts, (ORIENT, np.eye(3)))):
        x = _local_map(at, o) @ r.body("b")                     # local (d, theta) of the mount
        f6 = k6 @ x                                             # local force and moment
        np.testing.assert_allclose(r.mount_force[p], o @ f6[:3], rtol=1e-10, atol=1e-10)
        np.testing.assert_allclose(r.mount_moment[p], o @ f6[3:], rtol=1e-10, atol=1e-10)
    # equilibrium: the reaction into ground balances the load (moments about the origin)
    load = np.concatenate([[10.0, -20.0, -30.0], np.cross(body.cog, [10.0, -20.0, -30.0]) + [1.0, 2.0, -3.0]])
    np.testing.assert_allclose(r.reaction, load, rtol=1e-10, atol=1e-10)


def test_force_and_moment_outputs_of_a_coupled_mount():
    k6, c6 = _k6(), _k6(7, (3.0, 0.01, 0.2))
    t = MountType("bush", stiffness_matrix=k6, damping_matrix=c6)
    at = np.array([0.3, 0.1, -0.2])
    model = Model([Body("b", 3.0, [0.2, 0.3, 0.4])], [Mount("m", t, "b", at=at, orientation=ORIENT)])
    outs = ["b.x", "b.y", "b.z", "b.rx", "b.ry", "b.rz"] + [f"mount.m.{c}" for c in
                                                          ("f1", "f2", "f3", "m1", "m2", "m3", "fz", "mx")]
    outs += ["ground.fx", "ground.my", "sensor.lc"]
    model = model.replace(sensors=[vibss.Sensor("lc", "mount_force", mount="m", axis=2)])
    w = np.array([3.0, 40.0, 90.0])
    plant = build_plant(model, ["b.fx", "b.mz"], outs)
    y = response(plant, 1j * w, form="assembled")
    kept = response(plant, 1j * w, form="mounts")           # the mounts' form holds the coupling too
    np.testing.assert_allclose(kept, y, rtol=1e-10, atol=1e-14 * np.abs(y).max())
    tb = _local_map(at, ORIENT)
    for i, wi in enumerate(w):
        for j in range(2):
            q = y[:6, j, i]
            f6 = (k6 + 1j * wi * c6) @ (tb @ q)
            np.testing.assert_allclose(y[6:12, j, i], f6, rtol=1e-9)
            fg, mg = ORIENT @ f6[:3], ORIENT @ f6[3:]
            np.testing.assert_allclose(y[12, j, i], fg[2], rtol=1e-9)
            np.testing.assert_allclose(y[13, j, i], mg[0], rtol=1e-9)
            np.testing.assert_allclose(y[14, j, i], fg[0], rtol=1e-9)
            np.testing.assert_allclose(y[15, j, i], mg[1] + np.cross(at, fg)[1], rtol=1e-9)
            np.testing.assert_allclose(y[16, j, i], f6[1], rtol=1e-9)


def test_file_round_trip_and_units():
    k6 = _k6()
    model = Model([Body("b", 3.0, [0.2, 0.3, 0.4])],
                  [Mount("m", MountType("bush", stiffness_matrix=k6, damping_matrix=np.diag([1.0] * 6)), "b")])
    text = vibss.dumps_model(model)
    assert "stiffness_matrix" in text and "damping_matrix" in text
    back = vibss.loads_model(text)
    np.testing.assert_array_equal(back.mounts[0].type.stiffness_matrix, model.mounts[0].type.stiffness_matrix)
    assert vibss.dumps_model(back) == text
    np.testing.assert_array_equal(vibss.assemble(back).K, vibss.assemble(model).K)
    # in mm and degrees: N/mm, N mm/deg, N/deg for both coupling blocks
    f = np.full((6, 6), np.pi / 180)             # N/rad -> N/deg
    f[:3, :3] = 1e-3                             # N/m -> N/mm
    f[3:, 3:] = 1e3 * np.pi / 180                # N m/rad -> N mm/deg
    rows = ",\n  ".join("[" + ", ".join(repr(float(v)) for v in row) + "]" for row in k6 * f)
    mm = f"""
[model]
units = {{ length = "mm", angle = "deg" }}
[[body]]
name = "b"
mass = 3.0
inertia = [2e5, 3e5, 4e5]
[[mount_type]]
name = "bush"
stiffness_matrix = [
  {rows}]
[[mount]]
type = "bush"
body = "b"
"""
    other = vibss.loads_model(mm)
    np.testing.assert_allclose(other.mounts[0].type.stiffness_matrix, k6, rtol=1e-14)


def test_bad_matrices_are_refused():
    k6 = _k6()
    bad = k6.copy()
    bad[0, 4] += 1.0
    with pytest.raises(ModelError, match=r"mount type 'x': stiffness_matrix must be symmetric: entry \[0\]\[4\]"):
        MountType("x", stiffness_matrix=bad)
    neg = np.diag([1e4, 1e4, 1e4, 10.0, 10.0, 10.0])
    neg[2, 3] = neg[3, 2] = 400.0                        # |kc| > sqrt(k kr) = 316
    with pytest.raises(ModelError, match=r"mount type 'x': stiffness_matrix is not positive semi-definite"):
        MountType("x", stiffness_matrix=neg)
    with pytest.raises(ModelError, match=r"mount type 'x': damping_matrix is not positive semi-definite"):
        MountType("x", [1.0] * 3, damping_matrix=-np.eye(6))
    with pytest.raises(ModelError, match=r"mount type 'x': stiffness_matrix: expected a 6x6 matrix"):
        MountType("x", stiffness_matrix=np.eye(3))
    with pytest.raises(ModelError, match=r"mount type 'x': stiffness .* differs from the diagonal of stiffness_matrix"):
        MountType("x", [1.0, 2.0, 3.0], stiffness_matrix=k6)
    with pytest.raises(ModelError, match=r"mount type 'x': rotational_stiffness .* differs from the diagonal"):
        MountType("x", stiffness_matrix=k6, rotational_stiffness=[1.0, 1.0, 1.0])
    with pytest.raises(ModelError, match=r"mount type 'x': stiffness_matrix and rheology"):
        MountType("x", stiffness_matrix=k6, rheology={"type": "zener", "k_0": 1.0, "k_inf": 2.0, "tau": 1e-3})
    with pytest.raises(ModelError, match=r"mount type 'x': loss_factor and a stiffness_matrix with off-diagonal"):
        MountType("x", stiffness_matrix=k6, loss_factor=0.1)
    MountType("x", stiffness_matrix=np.diag(np.diag(k6)), loss_factor=0.1)        # diagonal: fine
    model = Model([Body("b", 3.0, [0.2, 0.3, 0.4])], [Mount("m", MountType("x", stiffness_matrix=k6), "b")])
    from vibss.design.montecarlo import batch_modes
    with pytest.raises(ModelError, match=r"batch_modes: mount 'm' \(type 'x'\) has a 6x6 stiffness_matrix"):
        batch_modes(model, (), np.zeros((1, 0)))
    text = vibss.dumps_model(model).replace("stiffness_matrix = [", "stiffness_matrix = [[1.0], ", 1)
    with pytest.raises(ModelFileError, match=r"mount_type\[1\].*stiffness_matrix"):
        vibss.loads_model(text)


@pytest.mark.parametrize("plane", ["xz", "yz"])
def test_a_mirrored_coupled_mount_is_the_mirror_image(plane):
    """Mirrored by S, body DOFs map by P = diag(S, -S) (rotations are pseudo-vectors): the mirror
    image's stiffness about a COG on the plane is P K P."""
    from vibss.model.geometry import MIRRORS

    t = MountType("bush", stiffness_matrix=_k6(), damping_matrix=_k6(7, (3.0, 0.01, 0.2)))
    body = Body("b", 3.0, [0.2, 0.3, 0.4])
    first, image = vibss.symmetric(Mount("m", t, "b", at=[0.3, 0.2, -0.1], orientation=ORIENT), plane)
    assert image.type.name == f"bush.{plane}"
    s = MIRRORS[plane]
    p = np.kron(np.diag([1.0, -1.0]), s)
    one, two = (vibss.assemble(Model([body], [m])) for m in (first, image))
    for key in ("K", "C"):
        ref = p @ getattr(one, key) @ p
        np.testing.assert_allclose(getattr(two, key), ref, rtol=0, atol=1e-12 * np.abs(ref).max())
    # the pair is symmetric about the plane: each mode is symmetric or antisymmetric
    both = Model([body], [first, image])
    md = vibss.modes(both)
    for j in range(6):
        v = md.shapes[:, j]
        assert min(np.abs(p @ v - v).max(), np.abs(p @ v + v).max()) <= 1e-8 * np.abs(v).max()
    text = vibss.dumps_model(both)
    np.testing.assert_array_equal(vibss.assemble(vibss.loads_model(text)).K, vibss.assemble(both).K)


def test_the_model_file_guide_example_loads_in_si():
    import re
    from pathlib import Path

    text = (Path(__file__).parents[1] / "docs" / "model-file.md").read_text()
    block = next(b for b in re.findall(r"```toml\n(.*?)```", text, re.S) if "stiffness_matrix" in b)
    model = vibss.loads_model('[model]\nunits = { length = "mm" }\n[[body]]\nname = "b"\nmass = 4.0\n'
                              'inertia = [2.5e5, 3e5, 3.5e5]\n' + block + '[[mount]]\ntype = "block"\nbody = "b"\n')
    k6 = model.mounts[0].type.stiffness_matrix
    deg = 180 / np.pi                                    # per degree -> per radian
    np.testing.assert_allclose(np.diag(k6), [2e4, 5e4, 6e4, 700 * deg, 600 * deg, 800 * deg], rtol=1e-14)
    np.testing.assert_allclose([k6[0, 4], k6[4, 0]], [300 * deg] * 2, rtol=1e-14)
