"""Path contributions against equilibrium (the receiver's total from the body's inertia and the applied
force, solved here), an independent per-mount loop, and symmetry."""

from __future__ import annotations

import numpy as np
import pytest

import cases.models as cases
import vibss
from vibss import Body, Model, Mount, MountType, Orientation
from vibss.errors import SignalError

F = np.array([1.5, 4.0, 7.7, 12.0, 30.0])


def one_body() -> Model:
    """One body, COG off the origin, four inclined mounts with dashpots, a loss factor and one 6x6 mount."""
    ta = MountType("A", [2e5, 1.5e5, 4e5], [40.0, 30.0, 80.0], loss_factor=0.08)
    tb = MountType("B", [5e4, 8e4, 1.2e5], [300.0, 50.0, 100.0])
    tc = MountType("C", [5e4, 8e4, 1.2e5], [300.0, 50.0, 100.0], rotational_stiffness=[800.0, 500.0, 300.0])
    b = Body("b", 200.0, [[20.0, -1.0, 0.5], [-1.0, 35.0, 0.2], [0.5, 0.2, 40.0]], cog=[0.1, -0.05, 0.4])
    mounts = [Mount("fl", ta, "b", at=[0.6, 0.4, -0.3], orientation=Orientation.from_euler([0, 30, 0], degrees=True)),
              Mount("fr", ta, "b", at=[0.6, -0.45, -0.3], orientation=Orientation.from_euler([0, -25, 10], degrees=True)),
              Mount("rl", tc, "b", at=[-0.7, 0.5, -0.35], orientation=Orientation.from_euler([10, 20, 0], degrees=True)),
              Mount("rr", tb, "b", at=[-0.65, -0.5, -0.3], orientation=Orientation.from_euler([45, 0, 0], degrees=True))]
    return Model([b], mounts, name="one body")


def solve(model: Model, w: float, force: np.ndarray) -> np.ndarray:
    """(6,) DOF amplitudes under a generalised force, by a dense solve written here."""
    a = vibss.assemble(model)
    dyn = np.asarray(a.K) + 1j * np.asarray(a.H) + 1j * w * np.asarray(a.C) - w**2 * np.asarray(a.M)
    return np.linalg.solve(dyn, force)


def test_paths_sum_to_the_reaction_by_equilibrium():
    """M x'' = F - (forces into ground): the ground's wrench about the origin is F + w^2 M x, moved there."""
    m = one_body()
    p = vibss.path_contributions(m, ["b.fz", "b.mx"], F)
    cog = np.array([0.1, -0.05, 0.4])
    body = m.bodies[0]
    for j in range(2):
        for i, f in enumerate(F):
            w = 2 * np.pi * f
            gen = np.zeros(6)
            gen[2 if j == 0 else 3] = 1.0
            x = solve(m, w, gen)
            wrench = gen + w**2 * (body.mass_matrix @ x)     # about the COG
            about_origin = np.concatenate([wrench[:3], wrench[3:] + np.cross(cog, wrench[:3])])
            assert np.abs(p.total[:, j, i] - about_origin).max() < 1e-10 * np.abs(about_origin).max()
    assert np.allclose(p.share.sum(axis=0), 1.0, atol=1e-12)


def test_each_path_matches_a_per_mount_loop():
    m = one_body()
    p = vibss.path_contributions(m, ["b.fy"], F)
    cog = np.array([0.1, -0.05, 0.4])
    gen = np.array([0.0, 1.0, 0, 0, 0, 0])
    for i, f in enumerate(F):
        w = 2 * np.pi * f
        x = solve(m, w, gen)
        for q, mt in enumerate(m.mounts):
            r = np.asarray(mt.at, float)                              # from the COG (body frame)
            u = x[:3] + np.cross(x[3:], r)
            t = mt.orientation.matrix
            k = np.asarray(mt.type.stiffness, float)
            z = k * (1 + 1j * np.asarray(mt.type.loss_factor)) + 1j * w * np.asarray(mt.type.damping, float)
            force = t @ (z * (t.T @ u))
            point = cog + r
            own = t @ (np.asarray(mt.type.rotational_stiffness, float) * (t.T @ x[3:]))   # a 6x6 mount's moment
            ref = np.concatenate([force, np.cross(point, force) + own])
            assert np.abs(p.forces[q, :, 0, i] - ref).max() < 1e-10 * np.abs(ref).max()


def test_a_body_receiver_takes_the_mounts_resting_on_it():
    """two_mass_model: four identical mounts at symmetric points carry body2 on body1: a z force at
    body2's COG splits into quarters."""
    m = cases.two_mass_model()
    p = vibss.path_contributions(m, ["body2.fz"], F, receiver="body1")
    assert p.paths == ("u0", "u1", "u2", "u3")
    assert np.allclose(p.share[:, 2], 0.25, atol=1e-12)
    t = p.table("fz")
    assert t.rows[-1][0] == "total"
    fig = p.plot()
    assert fig.axes[1].get_xlabel() == "frequency [Hz]"
    assert p.to_pandas().shape[0] == 4 * 6 * F.size


def test_receivers_are_named_precisely():
    m = cases.two_mass_model()
    with pytest.raises(SignalError, match="body3"):
        vibss.path_contributions(m, ["body2.fz"], F, receiver="body3")
    with pytest.raises(SignalError, match="no mount has 'body2'"):
        vibss.path_contributions(m, ["body2.fz"], F, receiver="body2")


def test_an_actuator_into_the_receiver_is_named_not_a_path():
    from vibss.model.actuation import Actuator

    t = MountType("iso", [1e4] * 3, [20.0] * 3)
    m = Model([Body("b", 10.0, [1, 1, 1])], [Mount("m", t, "b")], actuators=[Actuator("a", mount="m", axis=3)])
    p = vibss.path_contributions(m, ["b.fz"], F)
    assert p.paths == ("m",) and "actuators ['a'] act into 'ground'" in p.note
