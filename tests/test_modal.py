"""Undamped modes: reference cases 1 and 2, invariants, a second method."""

from __future__ import annotations

import numpy as np
import pytest

from vibss import Body, Model, modes
from vibss.modal.undamped import rigid_influence

from cases import asymmetric_model
from reference_impl import loop_assemble, loop_mass

TWO_PI = 2 * np.pi


def test_reference_case_1_prism(prism):
    r = modes(prism)
    # closed forms of the uncoupled modes (reference README, case 1)
    expected = {
        "x": np.sqrt(40_000 / 1000), "y": np.sqrt(80_000 / 1000), "z": np.sqrt(120_000 / 1000),
        "rx": np.sqrt(4 * 30_000 * 2**2 / 10), "ry": np.sqrt(4 * 30_000 * 1**2 / 20),
        "rz": np.sqrt(4 * (10_000 * 2**2 + 20_000 * 1**2) / 30),
    }
    got = dict(zip(r.directions, r.omega))
    assert sorted(got) == sorted(expected)
    for d, w in expected.items():
        assert got[d] == pytest.approx(w, rel=1e-12)
    # handbook's printed values: Hz to 2 decimals and CPM
    hz = dict(zip(r.directions, np.round(r.frequency_hz, 2)))
    assert hz == {"x": 1.01, "y": 1.42, "z": 1.74, "rx": 34.87, "ry": 12.33, "rz": 14.24}
    cpm = dict(zip(r.directions, np.round(r.cpm).astype(int)))
    assert cpm == {"x": 60, "y": 85, "z": 105, "rx": 2092, "ry": 740, "rz": 854}
    # each shape a unit vector on its own DOF
    np.testing.assert_allclose(np.abs(r.relative_shapes), np.eye(6)[:, [
        "x y z rx ry rz".split().index(d) for d in r.directions]], atol=1e-10)


# Reference case 2: (direction, Hz, body1 {dof: value}, body2 {dof: value}), signs per mode arbitrary
CASE2 = [
    ("x", 1.26, {"x": 1.0, "ry": 0.5025}, {"x": -0.6180, "ry": -0.3106}),
    ("x", 0.48, {"x": 0.6180, "ry": 0.3106}, {"x": 1.0, "ry": 0.5025}),
    ("y", 1.26, {"y": 1.0, "rx": -0.5012}, {"y": -0.6180, "rx": 0.3098}),
    ("ry", 17.89, {"x": 0.0100, "ry": -1.0}, {"x": -0.0062, "ry": 0.6180}),
    ("rx", 25.26, {"y": -0.0050, "rx": -1.0}, {"y": 0.0031, "rx": 0.6180}),
    ("z", 0.68, {"z": 0.6180}, {"z": 1.0}),
    ("z", 1.78, {"z": 1.0}, {"z": -0.6180}),
]


def test_reference_case_2_frequencies(two_mass):
    r = modes(two_mass)
    table = sorted(zip(r.directions, np.round(r.frequency_hz, 2)))
    expected = sorted([("x", 1.26), ("x", 0.48), ("y", 0.48), ("y", 1.26), ("z", 1.78), ("z", 0.68),
                       ("rx", 25.26), ("rx", 9.65), ("ry", 17.89), ("ry", 6.83), ("rz", 14.57), ("rz", 5.56)])
    assert table == expected
    cpm = sorted(np.round(r.cpm).astype(int).tolist())
    assert cpm == sorted([76, 29, 29, 76, 107, 41, 1516, 579, 1073, 410, 874, 334])


@pytest.mark.parametrize("direction,hz,b1,b2", CASE2)
def test_reference_case_2_relative_eigenvectors(two_mass, direction, hz, b1, b2):
    r = modes(two_mass)
    k = [i for i in range(len(r)) if r.directions[i] == direction and round(r.frequency_hz[i], 2) == hz]
    assert len(k) == 1, "each (direction, frequency) pair appears once, labelled"
    k = k[0]
    s1, s2 = r.shape_of(k, "body1"), r.shape_of(k, "body2")
    names = "x y z rx ry rz".split()
    ref = np.array([b1.get(d, 0.0) for d in names] + [b2.get(d, 0.0) for d in names])
    got = np.concatenate([s1, s2])
    sign = np.sign(got @ ref)
    np.testing.assert_allclose(sign * got, ref, atol=5.1e-5)


def test_near_degenerate_pairs_are_labelled_x_and_y(two_mass):
    r = modes(two_mass)
    low = np.flatnonzero(np.round(r.frequency_hz, 2) == 0.48)
    assert sorted(r.directions[i] for i in low) == ["x", "y"]
    # clean: no mixing of the x-ry and y-rx families
    for i in low:
        e = r.direction_energy[i]
        assert e[[0, 4]].sum() > 0.999 or e[[1, 3]].sum() > 0.999


def test_exactly_repeated_modes_come_out_clean():
    """A square layout with Ixx == Iyy: x and y modes coincide exactly; shapes must not mix."""
    from vibss import Mount, MountType, symmetric

    t = MountType("t", [1e4, 1e4, 3e4])
    m = Model([Body("b", 100.0, [8.0, 8.0, 12.0])], symmetric(Mount("m", t, "b", at=[0.5, 0.5, -0.2])))
    r = modes(m)
    for i in range(len(r)):
        assert r.direction_energy[i].max() > 0.5
        # each shape lives in one of the families x-ry, y-rx, z, rz
        fam = [r.direction_energy[i][[0, 4]].sum(), r.direction_energy[i][[1, 3]].sum(),
               r.direction_energy[i][2], r.direction_energy[i][5]]
        assert max(fam) == pytest.approx(1.0, abs=1e-9)


def test_free_body_has_six_zero_modes():
    r = modes(Model([Body("free", 5.0, [1.0, 2.0, 2.5], cog=[1, 2, 3])]))
    assert r.rigid.all() and np.all(r.omega == 0)
    assert r.directions == ["x", "y", "z", "rx", "ry", "rz"]


def test_partly_free_model_reports_zero_modes(asym):
    free = Body("loose", 2.0, [0.1, 0.1, 0.1], cog=[3, 0, 0])
    r = modes(asym.replace(bodies=list(asym.bodies) + [free]))
    assert r.rigid.sum() == 6
    phi = r.shapes[-6:, r.rigid]
    np.testing.assert_allclose(phi.T @ free.mass_matrix @ phi, np.eye(6), atol=1e-10)
    np.testing.assert_allclose(r.shapes[:-6, r.rigid], 0.0, atol=1e-10)


def test_second_method_on_asymmetric_model(asym):
    """Frequencies equal an independent assembly solved by a different eigen-route (Cholesky)."""
    K, M = loop_assemble(asym), loop_mass(asym)
    L = np.linalg.cholesky(M)
    Li = np.linalg.inv(L)
    w2 = np.sort(np.linalg.eigvalsh(Li @ K @ Li.T))
    np.testing.assert_allclose(modes(asym).omega, np.sqrt(w2), rtol=1e-10)


def test_shapes_orthonormal_and_energy_sums(asym):
    r = modes(asym)
    M = loop_mass(asym)
    np.testing.assert_allclose(r.shapes.T @ M @ r.shapes, np.eye(12), atol=1e-10)
    np.testing.assert_allclose(r.energy.sum(axis=1), 1.0, rtol=1e-12)
    # effective masses add up to the total mass and the inertia about the system COG
    total = rigid_influence(asym).T @ M @ rigid_influence(asym)
    np.testing.assert_allclose(r.effective_mass.sum(axis=0), np.diag(total), rtol=1e-9)


def test_rotating_and_shifting_the_model_keeps_frequencies():
    m = asymmetric_model()
    from scipy.spatial.transform import Rotation

    q = Rotation.from_euler("ZYX", [37, -12, 71], degrees=True).as_matrix()
    moved = m.transformed(q, offset=[5.0, -3.0, 2.0])
    np.testing.assert_allclose(modes(moved).omega, modes(m).omega, rtol=1e-10)


def test_mirrored_model_gives_mirrored_shapes():
    m = asymmetric_model()
    s = np.diag([1.0, -1.0, 1.0])   # mirror in the XZ plane
    # mirror: positions y -> -y; tensors S J S; orientations S T S (kept right-handed)

    bodies = [Body(b.name, b.mass, s @ b.tensor @ s, s @ b.cog) for b in m.bodies]
    mounts = [mt.mirrored(["xz"]) for mt in m.mounts]
    mounts = [type(mt)(orig.name, mt.type, mt.body, at=mt.at, to=mt.to, orientation=mt.orientation)
              for mt, orig in zip(mounts, m.mounts)]
    mirrored = m.replace(bodies=bodies, mounts=mounts)
    r0, r1 = modes(m), modes(mirrored)
    np.testing.assert_allclose(r1.omega, r0.omega, rtol=1e-10)
    # a mirror maps (x, y, z) -> (x, -y, z) and rotations (rx, ry, rz) -> (-rx, ry, -rz)
    flip = np.tile([1, -1, 1, -1, 1, -1], 2)
    for k in range(len(r0)):
        a, b = r0.shapes[:, k], flip * r1.shapes[:, k]
        assert abs(a @ loop_mass(m) @ b) == pytest.approx(1.0, abs=1e-8)


def test_shift_invert_matches_dense_on_large_model():
    from models import chain_model

    from vibss import assemble

    m = chain_model(40, damping="none")
    dense = modes(assemble(m, sparse=False), n_modes=12)
    si = modes(assemble(m, sparse=True), n_modes=12, method="shift-invert")
    np.testing.assert_allclose(si.omega, dense.omega, rtol=1e-9)
    assert si.method == "shift-invert"


def test_unknown_method_lists_valid_ones(prism):
    with pytest.raises(ValueError, match="dense"):
        modes(prism, method="lanczos")


def test_json_structure(two_mass):
    d = modes(two_mass).to_dict()
    assert len(d["frequencies_hz"]) == 12
    m0 = d["modes"][0]
    assert set(m0["shape"]) == {"body1", "body2"} and len(m0["shape"]["body1"]) == 6
    assert sum(sum(v) for v in m0["energy"].values()) == pytest.approx(1.0)
    assert max(abs(v) for vals in m0["shape"].values() for v in vals) == pytest.approx(1.0)


def test_badly_scaled_model_has_no_spurious_rigid_modes():
    """Masses over 7 decades put genuine modes at 1e-12 of the top w^2; none is called rigid."""
    from models import chain_model

    from vibss import assemble

    m = chain_model(20, damping="none", scale="bad", seed=0)
    r = modes(m)
    assert not r.rigid.any()
    # the lowest frequencies agree with an independent shift-invert solve, to dense eigh's
    # precision: absolute error ~ eps * max(w^2), so relative error in w ~ eps/2 * max(w^2)/w^2
    si = modes(assemble(m, sparse=True), n_modes=3, method="shift-invert")
    bound = 0.5 * np.finfo(float).eps * r.omega[-1] ** 2 / si.omega**2
    assert np.all(np.abs(r.omega[:3] - si.omega) / si.omega <= 10 * bound)
    assert r.omega[0] > 0


def test_generalized_eigh_block_path_matches_scipy():
    """Per-body Cholesky + divide and conquer against scipy's eigh(K, M): eigenvalues, mass
    normalisation and residual, with a full inertia tensor, a prescribed DOF (a 5x5 block) and
    the fallback for a mass matrix that is not block-diagonal."""
    import scipy.linalg as sl

    from vibss.linear.eigen.undamped import _inverse_cholesky, generalized_eigh
    from vibss.linear.plant.build import build_plant
    from test_signals import two_body

    p = build_plant(two_body(), ["frame.rz.disp", "engine.fz"], ["engine.z"])   # frame rz prescribed
    assert p.n == 11
    li = _inverse_cholesky(p.M)
    # about the COG, translations and rotations do not couple in M: blocks of 1 (x, y, z of each
    # body), 2 (frame rx, ry: rz is prescribed) and 3 (the engine's rotated inertia)
    assert li is not None and li.nnz == 6 * 1 + 2 * 2 + 3 * 3
    rng = np.random.default_rng(2)
    q = rng.standard_normal((30, 30))
    dense_m = q @ q.T + 30 * np.eye(30)
    k30 = q.T @ np.diag(rng.uniform(1, 100, 30)) @ q
    assert _inverse_cholesky(dense_m) is None                           # one 30-DOF block: fallback
    for K, M in ((p.K, p.M), (k30, dense_m)):
        w2, phi = generalized_eigh(K, M)
        ref = sl.eigh(K, M, eigvals_only=True)
        np.testing.assert_allclose(w2, ref, rtol=1e-11, atol=1e-12 * ref.max())
        np.testing.assert_allclose(phi.T @ M @ phi, np.eye(len(w2)), atol=1e-12)
        assert np.abs(K @ phi - M @ phi * w2).max() <= 1e-11 * np.abs(K).max()
        w3, phi3 = generalized_eigh(K, M, n_modes=3)
        np.testing.assert_allclose(w3, ref[:3], rtol=1e-10, atol=1e-12 * ref.max())
        assert phi3.shape == (K.shape[0], 3)
