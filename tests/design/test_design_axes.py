"""vibss.design axes: torque-roll axis, elastic centre and axes, torque response — against closed forms."""

from __future__ import annotations

import numpy as np
import pytest

import vibss
from vibss.design import elastic_axes, principal_axes, torque_response, torque_roll_axis
from vibss.errors import AnalysisError, ArgumentError

J_FULL = np.array([[6.5, -0.3, 1.5], [-0.3, 17.0, -0.2], [1.5, -0.2, 15.0]])


def _cramer_inverse(j: np.ndarray) -> np.ndarray:
    """3x3 inverse by cofactors (independent of numpy.linalg)."""
    cof = np.empty((3, 3))
    for r in range(3):
        for c in range(3):
            minor = np.delete(np.delete(j, r, 0), c, 1)
            cof[r, c] = (-1) ** (r + c) * (minor[0, 0] * minor[1, 1] - minor[0, 1] * minor[1, 0])
    det = sum(j[0, c] * cof[0, c] for c in range(3))
    return cof.T / det


def _four(a=0.4, b=0.25, h=-0.15, k=(1e5, 2e5, 5e5), inertia=(2.0, 4.0, 5.0)):
    t = vibss.MountType("t", list(k))
    body = vibss.Body("b", 120.0, list(inertia) if np.ndim(inertia) == 1 else inertia, cog=[1.0, 2.0, 0.5])
    return vibss.Model([body], vibss.symmetric(vibss.Mount("m", t, "b", at=[a, b, h])))


@pytest.mark.parametrize("axis", ["x", [0.3, -1.0, 0.2]])
def test_tra_is_inverse_inertia_times_axis_by_hand(axis):
    model = _four(inertia=J_FULL)
    e = np.array([1.0, 0, 0]) if axis == "x" else np.array(axis) / np.linalg.norm(axis)
    d = _cramer_inverse(J_FULL) @ e
    expected = d / np.sqrt(d @ d)
    np.testing.assert_allclose(torque_roll_axis(model, "b", axis), expected, rtol=1e-12, atol=1e-14)


def test_principal_axes_diagonalise_the_tensor():
    w, v = principal_axes(_four(inertia=J_FULL))
    np.testing.assert_allclose(v.T @ J_FULL @ v, np.diag(w), atol=1e-12)
    assert np.linalg.det(v) == pytest.approx(1.0)
    # the characteristic polynomial's roots by trace and invariants
    assert w.sum() == pytest.approx(np.trace(J_FULL))
    assert np.prod(w) == pytest.approx(np.linalg.det(J_FULL))


def test_elastic_centre_of_symmetric_four_mounts_closed_form():
    a, b, h, (kx, ky, kz) = 0.4, 0.25, -0.15, (1e5, 2e5, 5e5)
    ea = elastic_axes(_four(a, b, h, (kx, ky, kz)))
    assert ea.exists and ea.axes_exist, ea.note
    np.testing.assert_allclose(ea.center, [0, 0, h], atol=1e-12)
    np.testing.assert_allclose(ea.center_global, [1.0, 2.0, 0.5 + h], atol=1e-12)
    expected = sorted([4 * kz * b**2, 4 * kz * a**2, 4 * (kx * b**2 + ky * a**2)])
    np.testing.assert_allclose(ea.rotational_stiffness, expected, rtol=1e-10)
    np.testing.assert_allclose(ea.translational_stiffness, sorted([4 * kx, 4 * ky, 4 * kz]), rtol=1e-12)


@pytest.mark.parametrize("axis", [0, 1, 2])
def test_torque_about_an_elastic_axis_turns_the_body_about_it(axis):
    model = _four()
    ea = elastic_axes(model)
    e = ea.axes[:, axis]
    tr = torque_response(model, "b", e, torque=100.0)
    u, theta = tr.displacement[:3], tr.displacement[3:]
    # rotation parallel to the torque, and the elastic centre does not move
    assert np.linalg.norm(np.cross(theta, e)) <= 1e-10 * np.linalg.norm(theta)
    centre_motion = u + np.cross(theta, ea.center)
    assert np.linalg.norm(centre_motion) <= 1e-10 * np.linalg.norm(theta) * 0.5
    assert np.linalg.norm(theta) == pytest.approx(100.0 / ea.rotational_stiffness[axis], rel=1e-10)


def test_inclined_corner_mount_has_no_elastic_centre():
    t = vibss.MountType("t", [1e5, 2e5, 5e5])
    mounts = list(vibss.symmetric(vibss.Mount("m", t, "b", at=[0.4, 0.25, -0.15])))
    mounts[0] = vibss.Mount("m", t, "b", at=[0.4, 0.25, 0.2],
                            orientation=vibss.Orientation.from_euler([0.3, 0.5, 0.2]))
    ea = elastic_axes(vibss.Model([vibss.Body("b", 10.0, [1, 2, 3])], mounts))
    assert not ea.exists and "no elastic centre" in ea.note


def test_torque_misalignment_closed_form():
    a, b, kz = 0.4, 0.25, 5e5
    model = _four(a, b, 0.0, (1e5, 2e5, kz), inertia=(1.0, 2.0, 3.0))
    e = np.array([1.0, 1.0, 0.0]) / np.sqrt(2)
    tr = torque_response(model, "b", e)
    rot = np.array([1 / (4 * kz * b**2), 1 / (4 * kz * a**2), 0.0])
    tra = np.array([1.0, 0.5, 0.0])
    cosang = rot @ tra / np.linalg.norm(rot) / np.linalg.norm(tra)
    assert tr.misalignment == pytest.approx(np.arccos(cosang), rel=1e-9)
    assert torque_response(model, "b", "x").misalignment == pytest.approx(0.0, abs=1e-12)


def test_refusals():
    with pytest.raises(ArgumentError, match="axis"):
        torque_roll_axis(_four(), "b", "w")
    with pytest.raises(ArgumentError, match="did you mean"):
        elastic_axes(_four(), "bb")
    one = vibss.Model([vibss.Body("b", 1.0, [1, 1, 1])], [vibss.Mount("m", vibss.MountType("t", [1, 1, 1]), "b")])
    with pytest.raises(AnalysisError, match="singular"):
        elastic_axes(one)


def test_axes_drawn_on_the_layout():
    from vibss.design import plot_design_axes

    fig = plot_design_axes(vibss.load_example("powertrain"))
    labels = [t.get_text() for t in fig.legends[-1].get_texts()]
    assert "torque-roll axis" in labels and "static rotation under torque" in labels
    assert "no elastic centre" in fig._suptitle.get_text()
