"""transmissibility, random_response and path_contributions on a flexible foundation, and the source's
blocked forces, against the same system modelled whole in one vibss model (a plate on its own mounts
as the foundation) and against closed forms."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy.integrate import simpson

import vibss
from vibss import Body, ControlPoint, Foundation, Model, Mount, MountType, Support
from vibss.errors import ArgumentError, SignalError, VibssWarning

CORNERS = {"m1": (0.4, 0.3, 0.0), "m2": (-0.4, 0.3, 0.02), "m3": (-0.4, -0.3, 0.0), "m4": (0.4, -0.3, -0.01)}
F = np.geomspace(2.0, 200.0, 31)
ISO = MountType("iso", [2e5, 3e5, 5e5], [40.0, 60.0, 100.0])
SOFT = MountType("floor", [4e5, 4e5, 1e6], [300.0, 300.0, 800.0])
ROD = MountType("rod", [1e5, 1e4, 1e4], [30.0, 5.0, 5.0])          # a torque rod to rigid ground, off the plate
INPUTS = ["engine.fz", "engine.mx", "engine.fy"]
OUTPUTS = ["engine.z", "engine.rx", "mount.m1.fz", "mount.rod.fx"]
XYZ = [f"p{n}.{a}" for n in CORNERS for a in "xyz"]


def engine() -> Body:
    return Body("engine", 120.0, [4.0, 6.0, 7.0], cog=[0.05, -0.02, 0.25])


def plate() -> Body:
    return Body("plate", 400.0, [30.0, 50.0, 70.0], cog=[0.0, 0.0, -0.1])


def source_mounts(to: str = "ground") -> list[Mount]:
    return ([Mount(n, ISO, "engine", at=a, frame="global", to=to) for n, a in CORNERS.items()]
            + [Mount("rod", ROD, "engine", at=(0.6, 0.0, 0.3), frame="global")])


def floor() -> list[Mount]:
    """The plate's mounts on a support of their own (still): a ground motion moves only the rod."""
    return [Mount(f"f{i}", SOFT, "plate", at=a, frame="global", support="floor")
            for i, a in enumerate([(0.9, 0.7, -0.2), (-0.9, 0.7, -0.2), (-0.9, -0.7, -0.2), (0.9, -0.7, -0.2)])]


def points() -> list[ControlPoint]:
    return [ControlPoint(f"p{n}", "plate", a, frame="global") for n, a in CORNERS.items()]


SOURCE = Model([engine()], source_mounts())
WHOLE = Model([engine(), plate()], source_mounts("plate") + floor(), control_points=points(), supports=[Support("floor")])


@pytest.fixture(scope="module")
def found() -> Foundation:
    deck = Model([plate()], floor(), control_points=points(), supports=[Support("floor")])
    return Foundation.from_model(deck, {n: f"p{n}" for n in CORNERS}, F)


def _err(h: np.ndarray, ref: np.ndarray) -> float:
    """Max over channels of the error relative to each channel's largest value."""
    scale = np.abs(ref).max(axis=tuple(range(1, ref.ndim)), keepdims=True)
    return float((np.abs(h - ref) / np.where(scale > 0, scale, 1.0)).max())


def test_force_transmissibility_into_the_foundation(found):
    t = vibss.transmissibility(SOURCE, ["engine.fz", "engine.fy"], ["mount.rod.fx", "ground.fx"], foundation=found)
    ref = vibss.frequency_response(WHOLE, ["engine.fz", "engine.fy"], ["mount.rod.fx", "ground.fx"]
                                   + [f"mount.{n}.f{a}" for n in CORNERS for a in "xyz"], frequencies=F)
    assert t.quantity == "transmissibility" and t.outputs[2:] == found.forces
    assert _err(t.response, ref.response) < 1e-9        # a mount's force is the force into its ground end


def test_motion_transmissibility_moves_only_the_mounts_off_the_foundation(found):
    t = vibss.transmissibility(SOURCE, ["ground.z"], ["engine.z", "engine.rx"], foundation=found)
    ref = vibss.frequency_response(WHOLE, ["ground.z.disp"], ["engine.z", "engine.rx"] + XYZ, frequencies=F)
    assert t.outputs[2:] == found.outputs
    assert _err(t.response, ref.response) < 1e-9


def test_random_response_on_the_foundation_grid(found):
    """On the foundation's frequencies in the band: the PSDs are those of the whole model's FRF there,
    the RMS their trapezoid in ln f."""
    spec = {"engine.fz": ([5.0, 150.0], [4.0, 4.0]), "engine.fy": ([5.0, 150.0], [1.0, 1.0])}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", VibssWarning)           # 31 frequencies: coarse, and it says so
        r = vibss.random_response(SOURCE, spec, ["engine.z", "mount.m1.fz"], foundation=found)
    inside = F[(F >= 5.0) & (F <= 150.0)]
    assert np.array_equal(r.frequency_hz, inside)
    h = vibss.frequency_response(WHOLE, ["engine.fz", "engine.fy"], ["engine.z", "mount.m1.fz"] + XYZ,
                                 frequencies=inside).response
    s_yy = 4.0 * np.abs(h[:, 0]) ** 2 + 1.0 * np.abs(h[:, 1]) ** 2
    assert _err(r.psd[:14], s_yy) < 1e-9
    w = s_yy * inside
    ms = np.sum(0.5 * (w[:, 1:] + w[:, :-1]) * np.diff(np.log(inside)), axis=1)
    np.testing.assert_allclose(r.rms[:14], np.sqrt(ms), rtol=1e-9)
    assert r.outputs[2:14] == found.outputs and r.outputs[14:] == found.forces
    assert "trapezoid" in r.note and "never interpolated" in r.note


def test_random_response_states_its_grid_error(found):
    """A fine foundation grid meets the whole model's adaptive RMS within the error it estimates; a
    coarse one warns; a band beyond the foundation's frequencies is an error naming both."""
    spec = {"engine.fz": ([5.0, 150.0], [4.0, 4.0])}
    deck = Model([plate()], floor(), control_points=points(), supports=[Support("floor")])
    fine = Foundation.from_model(deck, {n: f"p{n}" for n in CORNERS}, np.geomspace(5.0, 150.0, 500))
    with warnings.catch_warnings():
        warnings.simplefilter("error", VibssWarning)
        r = vibss.random_response(SOURCE, spec, ["engine.z"], foundation=fine, rtol=1e-3)
    ff = np.geomspace(5.0, 150.0, 8001)          # the reference: Simpson on the whole model, 16x finer
    h = vibss.frequency_response(WHOLE, ["engine.fz"], ["engine.z"], frequencies=ff).response[0, 0]
    ms = simpson(4.0 * np.abs(h) ** 2 * ff, x=np.log(ff))
    est = float(r.note.split("estimated relative error ")[1].split(" ")[0])
    assert abs(r.rms[0] ** 2 / ms - 1) <= est <= 1e-3               # measured 1.6e-7 <= 9.6e-5
    with pytest.warns(VibssWarning, match="integrated on its"):
        vibss.random_response(SOURCE, spec, ["engine.z"], foundation=found)
    with pytest.raises(ArgumentError, match=r"5 to 400 Hz reaches outside .*\(2 to 200 Hz\)"):
        vibss.random_response(SOURCE, {"engine.fz": ([5.0, 400.0], [1.0, 1.0])}, foundation=found)


def test_transfer_paths_sum_to_the_coupled_motion_and_match_the_whole_model(found):
    tpa = vibss.path_contributions(SOURCE, INPUTS, receiver="m2", foundation=found)
    coupled = vibss.frequency_response(SOURCE, INPUTS, OUTPUTS, foundation=found)
    rows = [coupled.outputs.index(f"foundation.m2.{a}") for a in "xyz"]
    assert tpa.paths == tuple(CORNERS) and tpa.components == ("x", "y", "z") and tpa.units == ("m",) * 3
    assert _err(tpa.total, coupled.response[rows]) < 1e-9
    # each path from the whole model: the plate's receptance times that mount's force into the plate
    whole = vibss.frequency_response(WHOLE, INPUTS, [f"mount.{n}.f{a}" for n in CORNERS for a in "xyz"]
                                     + [f"pm2.{a}" for a in "xyz"], frequencies=F)
    g = whole.response[:12].reshape(4, 3, len(INPUTS), F.size)
    y = found.receptance[3:6].reshape(3, 4, 3, F.size)
    ref = np.einsum("apbn,pbin->pain", y, g)
    assert _err(tpa.forces, ref) < 1e-9
    assert _err(tpa.total, whole.response[12:]) < 1e-9
    np.testing.assert_allclose(tpa.share.sum(axis=0)[np.abs(tpa.total) > 0], 1.0, atol=1e-9)
    assert "checked" in tpa.note and tpa.receiver == "foundation.m2"
    with pytest.raises(SignalError, match="one of its points"):
        vibss.path_contributions(SOURCE, INPUTS, receiver="ground", foundation=found)


def test_blocked_forces_on_rigid_ground_are_the_mount_forces():
    b = vibss.blocked_forces(SOURCE, INPUTS, F)
    names = [m.name for m in SOURCE.mounts]
    assert b.outputs == tuple(f"{n}.f{a}" for n in names for a in "xyz") and b.units == ("N",) * 15
    ref = vibss.frequency_response(SOURCE, INPUTS, [f"mount.{n}.f{a}" for n in names for a in "xyz"], frequencies=F)
    assert _err(b.response, ref.response) < 1e-9
    total = vibss.frequency_response(SOURCE, INPUTS, ["ground.fx", "ground.fy", "ground.fz"], frequencies=F)
    assert _err(b.response.reshape(5, 3, len(INPUTS), F.size).sum(axis=0), total.response) < 1e-9


def test_blocked_forces_of_one_mass_on_one_spring_closed_form():
    k, c, mass = 1e4, 20.0, 10.0
    m = Model([Body("b", mass, [1, 1, 1])], [Mount("s", MountType("t", [k] * 3, [c] * 3), "b")])
    f = np.array([0.0, 1.0, 5.03, 40.0])
    w = 2 * np.pi * f
    b = vibss.blocked_forces(m, ["b.fz"], f)
    np.testing.assert_allclose(b.response[2, 0], (k + 1j * w * c) / (k - mass * w**2 + 1j * w * c), rtol=1e-12)


def test_the_blocked_force_identity_gives_the_foundation_motion(found):
    """z = (I - Y H_gz)^-1 Y f_blocked: blocked forces and the source's blocked dynamic stiffness (here
    from the source's mounts on supports of their own, built in the test) give the whole model's motion."""
    fb = vibss.blocked_forces(SOURCE, INPUTS, F, points=list(CORNERS)).response
    held = SOURCE.replace(mounts=[m if m.name == "rod" else Mount(m.name, ISO, "engine", at=m.at, frame="global",
                                                                   support=f"s{m.name}") for m in SOURCE.mounts],
                          supports=[Support(f"s{n}") for n in CORNERS])
    hgz = vibss.frequency_response(held, [f"s{n}.{a}.disp" for n in CORNERS for a in "xyz"],
                                   [f"s{n}.f{a}" for n in CORNERS for a in "xyz"], frequencies=F).response
    y = found.receptance
    z = np.stack([np.linalg.solve(np.eye(12) - y[:, :, i] @ hgz[:, :, i], y[:, :, i] @ fb[:, :, i])
                  for i in range(F.size)], axis=2)
    ref = vibss.frequency_response(WHOLE, INPUTS, XYZ, frequencies=F).response
    assert _err(z, ref) < 1e-9
    with pytest.raises(vibss.ModelError, match="no mount named 'm9'"):
        vibss.blocked_forces(SOURCE, INPUTS, F, points=["m9"])
