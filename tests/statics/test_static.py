"""Static deflection: closed forms, equilibrium, free-motion detection, prescribed displacement."""

from __future__ import annotations

import numpy as np
import pytest

from vibss import AnalysisError, Body, Load, Model, ModelError, Mount, MountType, assemble, static, symmetric
from vibss.statics import center_of_rotation

from cases.reference_impl import loop_assemble


@pytest.mark.parametrize("n_side", [1, 2, 3])
def test_weight_sag_on_n_identical_vertical_mounts(n_side):
    """m g / (n kz) on n identical mounts (reference case 3)."""
    kz, m, g = 2.5e5, 420.0, 9.81
    t = MountType("t", [1e5, 1e5, kz])
    mounts = []
    for i in range(n_side):
        mounts += symmetric(Mount(f"m{i}", t, "b", at=[0.3 + 0.2 * i, 0.4, 0.0]), "double")
    model = Model([Body("b", m, [10, 12, 15])], mounts, gravity=[0, 0, -g])
    r = static(model)
    n = len(mounts)
    np.testing.assert_allclose(r.body("b"), [0, 0, -m * g / (n * kz), 0, 0, 0], atol=1e-15)
    assert r.center_of_rotation("b") is None          # pure translation
    np.testing.assert_allclose(r.mount_force[:, 2], -m * g / n, rtol=1e-12)


def test_equilibrium_and_independent_stiffness(asym):
    """Mount forces balance the loads (forces and moments), K from an independent loop agrees."""
    loads = [Load("frame load", "frame", force=[120.0, -40.0, -900.0], moment=[10.0, 0.0, -25.0], at=[0.2, 0.1, 0.0]),
             Load("motor load", "motor", force=[0.0, 300.0, -200.0], at=[0.1, -0.1, 0.2], frame="body")]
    model = asym.replace(loads=loads, gravity=[0, 0, -9.81])
    r = static(model)
    f = assemble(model).load_vector()
    np.testing.assert_allclose(loop_assemble(model) @ r.q, f, rtol=1e-9, atol=1e-9 * np.abs(f).max())
    # total force into ground = total applied force; moments about the origin likewise
    total_f = sum(ld.force for ld in loads) + 9.81 * np.array([0, 0, -1]) * (300.0 + 80.0)
    np.testing.assert_allclose(r.reaction[:3], total_f, rtol=1e-9)
    total_m = sum(np.cross(model.body(ld.body).cog + ld.at, ld.force) + ld.moment for ld in loads)
    total_m = total_m + sum(np.cross(b.cog, b.masses * [0, 0, -9.81]) for b in model.bodies)
    np.testing.assert_allclose(r.reaction[3:], total_m, rtol=1e-9, atol=1e-9)


def test_local_deflection_is_rotated_global(asym):
    r = static(asym.replace(loads=[Load("m", "motor", force=[50, 80, -400])]))
    for p, m in enumerate(asym.mounts):
        np.testing.assert_allclose(m.orientation.matrix @ r.mount_deflection_local[p],
                                   r.mount_deflection[p], atol=1e-16)


def test_centre_of_rotation_closed_form():
    # rotation about z through the point (1, 0, 0): COG (origin) moves by theta x (0 - c)
    theta = np.array([0, 0, 1e-3])
    c = np.array([1.0, 0.0, 0.0])
    u = np.cross(theta, -c)
    np.testing.assert_allclose(center_of_rotation(np.r_[u, theta], np.zeros(3)), c, atol=1e-12)
    assert center_of_rotation(np.r_[1e-3, 0, 0, 0, 0, 0], np.zeros(3)) is None


def test_unrestrained_direction_is_named():
    t = MountType("no-x", [0.0, 1e5, 2e5])
    m = Model([Body("engine", 100.0, [5, 5, 5])], symmetric(Mount("m", t, "engine", at=[0.5, 0.5, 0])),
              loads=[Load("e", "engine", force=[100.0, 0, 0])])
    with pytest.raises(AnalysisError, match=r"body 'engine' is free to move in x"):
        static(m)


def test_unconnected_body_is_named():
    t = MountType("t", [1e5, 1e5, 2e5])
    m = Model([Body("a", 100.0, [5, 5, 5]), Body("loose", 1.0, [1, 1, 1])],
              symmetric(Mount("m", t, "a", at=[0.5, 0.5, 0])), loads=[Load("l", "loose", force=[0, 0, -10])])
    with pytest.raises(AnalysisError, match=r"body 'loose' is free to move in z"):
        static(m)
    # loading only the restrained body works and lists the free motions
    ok = static(m.replace(loads=[Load("w", "a", force=[0, 0, -10])]))
    assert len(ok.free_motions) == 6 and ok.body("a")[2] == pytest.approx(-10 / 8e5)


def test_prescribed_ground_displacement_moves_rigidly(asym):
    """Lifting ground by dz with no load lifts every body rigidly and stretches no mount."""
    r = static(asym, prescribed={"ground.z": 0.01})
    for b in asym.body_names:
        np.testing.assert_allclose(r.body(b), [0, 0, 0.01, 0, 0, 0], atol=1e-12)
    np.testing.assert_allclose(r.mount_deflection, 0.0, atol=1e-12)


def test_prescribed_body_dof(prism):
    """Holding z of the prism at -1 mm: the mounts then carry 4 kz * 1 mm into ground."""
    r = static(prism, prescribed={"prism.z": -1e-3})
    assert r.body("prism")[2] == -1e-3
    assert r.reaction[2] == pytest.approx(-4 * 30_000 * 1e-3)


def test_json(asym):
    d = static(asym.replace(loads=[Load("m", "motor", force=[0, 0, -100])])).to_dict()
    assert set(d["bodies"]) == {"frame", "motor"}
    assert len(d["mounts"]) == 7 and len(d["mounts"][0]["deflection_local"]) == 3


def test_load_cases_are_alternatives_not_a_sum(prism):
    """Unnamed loads always apply; each named case adds its own and is opt-in (issue 16)."""
    base = Load("base", "prism", force=[0, 0, -1000.0])
    idle = Load("idle", "prism", force=[100.0, 0, 0], case="idle")
    full = Load("full", "prism", force=[0, 400.0, 0], case="full")
    m = prism.replace(loads=[base, idle, full])
    plain = static(m)       # no case asked for: the unnamed loads alone, the cases named in the note
    np.testing.assert_allclose(plain.body("prism")[:3], [0.0, 0.0, -1000.0 / 12e4], atol=1e-15)
    assert "'idle', 'full' not applied" in plain.note and "'full' not applied" in plain.report()
    assert plain.cases_left_out == ("idle", "full")
    r = static(m, case="full")
    assert r.cases_left_out == () and "not applied" not in r.report()
    # closed form per direction: 4 mounts, kx = 1e4, ky = 2e4, kz = 3e4 N/m
    np.testing.assert_allclose(r.body("prism")[:3], [0.0, 400.0 / 8e4, -1000.0 / 12e4], atol=1e-15)
    assert r.case == "full" and r.to_dict()["case"] == "full"
    with pytest.raises(Exception, match="unknown load case 'ful'"):
        static(m, case="ful")
    # a single named case is opt-in too
    only = static(prism.replace(loads=[base, idle]))
    assert only.case == "" and only.body("prism")[0] == 0.0 and "'idle' not applied" in only.note
    assert static(prism.replace(loads=[base, idle]), case="idle").body("prism")[0] == pytest.approx(100.0 / 4e4)
    assert static(prism.replace(loads=[base])).note == ""


@pytest.mark.parametrize("prescribed,pattern", [
    ({"prism.z": "0.01"}, r"expected a finite number"), ({"prism.z": None}, r"expected a finite number"),
    ({"prism.z": [0.01]}, r"expected a finite number"), ({5: 0.01}, r"keys are DOF labels"),
    ([("prism.z", 0.01)], r"expected a mapping"),
])
def test_bad_prescribed_values_are_model_errors(prism, prescribed, pattern):
    from vibss import ModelError

    with pytest.raises(ModelError, match=pattern):
        static(prism, prescribed=prescribed)


def test_self_weight_alone(prism):
    """case='self-weight': gravity only, whatever loads the model has: m g / (4 k_z) (closed form)."""
    g = 9.81
    m = prism.replace(loads=[Load("push", "prism", force=[500.0, 0, -1000.0])], gravity=[0, 0, -g])
    mass = m.body("prism").mass
    r = static(m, case="self-weight")
    np.testing.assert_allclose(r.body("prism")[:3], [0.0, 0.0, -mass * g / 12e4], atol=1e-15)
    assert r.case == "self-weight"
    with pytest.raises(ModelError, match="defines no gravity"):
        static(prism, case="self-weight")
    with pytest.raises(ModelError, match="case 'self-weight' is reserved"):
        Load("w", "prism", force=[0, 0, 1.0], case="self-weight")
