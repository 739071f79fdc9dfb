"""Validation of the Python API: every bad input is a ModelError naming entity and field."""

from __future__ import annotations

import numpy as np
import pytest

from vibss import Body, ControlPoint, Load, Model, ModelError, Mount, MountType, Orientation, symmetric

T = MountType("t", [1.0, 1.0, 1.0])


@pytest.mark.parametrize("kwargs,pattern", [
    (dict(mass=-1.0), r"body 'b': mass must be positive"),
    (dict(mass=0.0), r"body 'b': mass must be positive"),
    (dict(mass=float("nan")), r"body 'b': mass must be finite"),
    (dict(mass=[1.0, 2.0]), r"body 'b': mass: expected a number or 3 numbers"),
    (dict(inertia=[1.0, -2.0, 3.0]), r"body 'b': inertia is not positive definite"),
    (dict(inertia=[1.0, 1.0, 5.0]), r"body 'b': .*triangle inequality"),
    (dict(inertia=[[1, 0.5, 0], [0, 1, 0], [0, 0, 1]]), r"body 'b': inertia tensor must be symmetric"),
    (dict(inertia=[[1, 2, 0], [2, 1, 0], [0, 0, 1]]), r"body 'b': inertia is not positive definite"),
    (dict(inertia=[1.0, 1.0]), r"body 'b': inertia: expected 3 principal moments or a 3x3"),
    (dict(cog=[0.0, 1.0]), r"body 'b': cog: expected 3 numbers"),
    (dict(cog=[0.0, np.inf, 0.0]), r"body 'b': cog: values must be finite"),
])
def test_bad_body(kwargs, pattern):
    args = dict(name="b", mass=1.0, inertia=[1.0, 1.0, 1.0]) | kwargs
    with pytest.raises(ModelError, match=pattern):
        Body(**args)


@pytest.mark.parametrize("kwargs,pattern", [
    (dict(stiffness=[1.0, -1.0, 1.0]), r"mount type 'rubber': stiffness must not be negative"),
    (dict(stiffness=[1.0, 1.0]), r"mount type 'rubber': stiffness: expected 3 numbers"),
    (dict(stiffness=[1.0, 1.0, 1.0], damping=[0.0, -2.0, 0.0]), r"damping must not be negative"),
    (dict(stiffness=[1.0, np.nan, 1.0]), r"stiffness: values must be finite"),
    (dict(stiffness=[1.0, 1.0, 1.0], loss_factor=-0.1), r"loss_factor must be finite and not negative"),
])
def test_bad_mount_type(kwargs, pattern):
    with pytest.raises(ModelError, match=pattern):
        MountType("rubber", **kwargs)


def test_bad_mounts():
    with pytest.raises(ModelError, match=r"mount 'm': joins body 'b' to itself"):
        Mount("m", T, "b", to="b")
    with pytest.raises(ModelError, match=r"mount 'm': .*not orthogonal"):
        Mount("m", T, "b", orientation=[[1, 0.1, 0], [0, 1, 0], [0, 0, 1]])
    with pytest.raises(ModelError, match=r"mount 'm': .*left-handed"):
        Mount("m", T, "b", orientation=np.diag([1.0, 1.0, -1.0]))
    with pytest.raises(ModelError, match=r"mount 'm': at: expected 3 numbers"):
        Mount("m", T, "b", at=[1, 2])
    with pytest.raises(ModelError, match=r"unknown symmetry 'diagonal'"):
        symmetric(Mount("m", T, "b"), "diagonal")
    with pytest.raises(ModelError, match=r"frame must be 'body' or 'global'"):
        Mount("m", T, "b", frame="local")


def test_model_cross_references():
    b = Body("engine", 1.0, [1, 1, 1])
    with pytest.raises(ModelError, match=r"mount 'm': to: unknown body 'engin'.*did you mean 'engine'"):
        Model([b, Body("x", 1.0, [1, 1, 1])], [Mount("m", T, "x", to="engin")])
    with pytest.raises(ModelError, match=r"mount 'm': body: unknown body 'motor'"):
        Model([b], [Mount("m", T, "motor")])
    with pytest.raises(ModelError, match=r"body name 'engine' is used twice"):
        Model([b, b])
    with pytest.raises(ModelError, match=r"control point 'cp': unknown body"):
        Model([b], control_points=[ControlPoint("cp", "engin", [0, 0, 0])])
    with pytest.raises(ModelError, match=r"load .*unknown body"):
        Model([b], loads=[Load("nobody", force=[1, 0, 0])])
    with pytest.raises(ModelError, match=r"needs at least one body"):
        Model([])


def test_euler_sequence_errors():
    with pytest.raises(ModelError, match="sequence"):
        Orientation.from_euler([0, 0, 0], sequence="ZYx")


def test_inputs_not_mutated():
    inertia = [[2.0, 0.1, 0.0], [0.1, 3.0, 0.0], [0.0, 0.0, 4.0]]
    at = [0.1, 0.2, 0.3]
    b = Body("b", 1.0, inertia)
    m = Mount("m", T, "b", at=at)
    assert inertia == [[2.0, 0.1, 0.0], [0.1, 3.0, 0.0], [0.0, 0.0, 4.0]] and at == [0.1, 0.2, 0.3]
    with pytest.raises(ValueError):
        m.at[0] = 5.0          # frozen arrays
    with pytest.raises(AttributeError):
        b.mass = 3.0           # frozen dataclass


def test_symmetric_names_and_points():
    ms = symmetric(Mount("front", T, "b", at=[1.0, 2.0, 3.0]), "double")
    assert [m.name for m in ms] == ["front", "front.xz", "front.yz", "front.xz.yz"]
    np.testing.assert_array_equal([m.at for m in ms], [[1, 2, 3], [1, -2, 3], [-1, 2, 3], [-1, -2, 3]])


def test_mirrored_orientation_mirrors_stiffness():
    t = MountType("t", [1.0, 2.0, 5.0])
    o = Orientation.from_euler([30, 20, 10], degrees=True)
    m = Mount("m", t, "b", orientation=o).mirrored(["xz"])
    s = np.diag([1.0, -1.0, 1.0])
    k = o.matrix @ np.diag(t.stiffness) @ o.matrix.T
    km = m.orientation.matrix @ np.diag(t.stiffness) @ m.orientation.matrix.T
    np.testing.assert_allclose(km, s @ k @ s, atol=1e-14)
    assert np.linalg.det(m.orientation.matrix) == pytest.approx(1.0)
