"""A source on a flexible foundation by frequency-based substructuring agrees with the same system
modelled whole in one vibss model (the independent reference)."""

from __future__ import annotations

import numpy as np
import pytest

import vibss
from vibss import Body, ControlPoint, Foundation, Model, Mount, MountType
from vibss.errors import ArgumentError, ModelError

CORNERS = {"m1": (0.4, 0.3, 0.0), "m2": (-0.4, 0.3, 0.0), "m3": (-0.4, -0.3, 0.0), "m4": (0.4, -0.3, 0.0)}
F = np.geomspace(2.0, 200.0, 25)
ISO = MountType("iso", [2e5, 3e5, 5e5], [40.0, 60.0, 100.0])
SOFT = MountType("floor", [4e5, 4e5, 1e6], [300.0, 300.0, 800.0])


def source(to: str = "ground") -> list[Mount]:
    return [Mount(n, ISO, "engine", at=a, frame="global", to=to) for n, a in CORNERS.items()]


def engine() -> Body:
    return Body("engine", 120.0, [4.0, 6.0, 7.0], cog=[0.05, -0.02, 0.25])


def plate() -> Body:
    return Body("plate", 400.0, [30.0, 50.0, 70.0], cog=[0.0, 0.0, -0.1])


def floor_mounts() -> list[Mount]:
    return [Mount(f"f{i}", SOFT, "plate", at=a, frame="global")
            for i, a in enumerate([(0.9, 0.7, -0.2), (-0.9, 0.7, -0.2), (-0.9, -0.7, -0.2), (0.9, -0.7, -0.2)])]


def points() -> list[ControlPoint]:
    return [ControlPoint(f"p{n}", "plate", a, frame="global") for n, a in CORNERS.items()]


INPUTS = ["engine.fz", "engine.mx", "engine.fy"]
OUTPUTS = ["engine.z", "engine.rx", "engine.y", "mount.m1.fz", "mount.m3.fx"]


@pytest.fixture(scope="module")
def coupled():
    found = Foundation.from_model(Model([plate()], floor_mounts(), control_points=points()),
                                  {n: f"p{n}" for n in CORNERS}, F)
    return vibss.frequency_response(Model([engine()], source()), INPUTS, OUTPUTS, foundation=found)


def test_fbs_agrees_with_the_whole_model(coupled):
    whole = Model([engine(), plate()], source("plate") + floor_mounts(), control_points=points())
    ref = vibss.frequency_response(whole, INPUTS, OUTPUTS + [f"p{n}.{a}" for n in CORNERS for a in "xyz"],
                                   frequencies=F)
    scale = np.abs(ref.response).max(axis=(1, 2), keepdims=True)    # per output: forces and motions apart
    err = np.abs(coupled.response[:len(OUTPUTS) + 12] - ref.response) / scale
    assert err.max() < 1e-9, err.max()
    assert coupled.outputs[len(OUTPUTS):len(OUTPUTS) + 12] == tuple(f"foundation.{n}.{a}" for n in CORNERS for a in "xyz")
    assert coupled.outputs[len(OUTPUTS) + 12:] == tuple(f"foundation.{n}.f{a}" for n in CORNERS for a in "xyz")
    assert coupled.method.endswith("+fbs") and "substructuring" in coupled.note


def test_a_rigid_foundation_is_ground(coupled):
    """A receptance of zero leaves the source on rigid ground."""
    zero = Foundation(F, np.zeros((12, 12, F.size)), list(CORNERS))
    on_zero = vibss.frequency_response(Model([engine()], source()), INPUTS, OUTPUTS, foundation=zero)
    ground = vibss.frequency_response(Model([engine()], source()), INPUTS, OUTPUTS, frequencies=F)
    np.testing.assert_allclose(on_zero.response[:len(OUTPUTS)], ground.response, rtol=1e-12, atol=0)
    assert np.all(on_zero.response[len(OUTPUTS):len(OUTPUTS) + 12] == 0)
    # the forces into a rigid foundation sum to the total force into the ground
    total = vibss.frequency_response(Model([engine()], source()), INPUTS, ["ground.fx", "ground.fy", "ground.fz"],
                                     frequencies=F).response
    into = on_zero.response[len(OUTPUTS) + 12:].reshape(4, 3, len(INPUTS), F.size).sum(axis=0)
    np.testing.assert_allclose(into, total, rtol=0, atol=1e-12 * np.abs(total).max())


def test_frequencies_must_match_and_points_must_be_mounts_to_ground():
    found = Foundation(F, np.zeros((3, 3, F.size)), ["m1"])
    m = Model([engine()], source())
    with pytest.raises(ArgumentError, match="never interpolates"):
        vibss.frequency_response(m, INPUTS, OUTPUTS, frequencies=F[:-1], foundation=found)
    with pytest.raises(ModelError, match="no mount named 'm9'"):
        vibss.frequency_response(m, INPUTS, OUTPUTS, foundation=Foundation(F, np.zeros((3, 3, F.size)), ["m9"]))
    with pytest.raises(ArgumentError, match="Foundation: receptance"):
        Foundation(F, np.zeros((5, 5, F.size)), ["m1"])


def test_a_foundation_measured_and_read_from_uff_couples_as_the_model(coupled, tmp_path):
    """The plate's receptance written to UFF 58 and read back (a "measurement") gives the same coupling."""
    pytest.importorskip("pyuff")
    from vibss.io import read_uff, write_uff

    deck = Model([plate()], floor_mounts(), control_points=points())
    cps = [f"p{n}" for n in CORNERS]
    frf = vibss.frequency_response(deck, [f"{c}.f{a}" for c in cps for a in "xyz"],
                                   [f"{c}.{a}" for c in cps for a in "xyz"], frequencies=F)
    measured = read_uff(write_uff(frf, tmp_path / "deck.uff"))
    assert measured.method == "measured"
    found = Foundation.from_response(measured, {n: f"p{n}" for n in CORNERS})
    again = vibss.frequency_response(Model([engine()], source()), INPUTS, OUTPUTS, foundation=found)
    assert np.array_equal(again.response, coupled.response)
    with pytest.raises(vibss.SignalError, match="p9.x"):
        Foundation.from_response(measured, {"m1": "p9"})


def test_blocks_of_frequencies_give_the_same_answer(coupled, monkeypatch):
    from vibss.measured import coupling as fbs

    monkeypatch.setattr(fbs, "CHUNK_BYTES", 16 * 17 * 15 * 7)     # 7 frequencies a block: 4 blocks
    found = Foundation.from_model(Model([plate()], floor_mounts(), control_points=points()),
                                  {n: f"p{n}" for n in CORNERS}, F)
    again = vibss.frequency_response(Model([engine()], source()), INPUTS, OUTPUTS, foundation=found)
    np.testing.assert_allclose(again.response, coupled.response, rtol=1e-12, atol=1e-14 * np.abs(coupled.response).max())
