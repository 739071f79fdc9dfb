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
    err = np.abs(coupled.response - ref.response) / scale
    assert err.max() < 1e-9, err.max()
    assert coupled.outputs[len(OUTPUTS):] == tuple(f"foundation.{n}.{a}" for n in CORNERS for a in "xyz")
    assert coupled.method.endswith("+fbs") and "substructuring" in coupled.note


def test_a_rigid_foundation_is_ground(coupled):
    """A receptance of zero leaves the source on rigid ground."""
    zero = Foundation(F, np.zeros((12, 12, F.size)), list(CORNERS))
    on_zero = vibss.frequency_response(Model([engine()], source()), INPUTS, OUTPUTS, foundation=zero)
    ground = vibss.frequency_response(Model([engine()], source()), INPUTS, OUTPUTS, frequencies=F)
    np.testing.assert_allclose(on_zero.response[:len(OUTPUTS)], ground.response, rtol=1e-12, atol=0)
    assert np.all(on_zero.response[len(OUTPUTS):] == 0)


def test_frequencies_must_match_and_points_must_be_mounts_to_ground():
    found = Foundation(F, np.zeros((3, 3, F.size)), ["m1"])
    m = Model([engine()], source())
    with pytest.raises(ArgumentError, match="never interpolates"):
        vibss.frequency_response(m, INPUTS, OUTPUTS, frequencies=F[:-1], foundation=found)
    with pytest.raises(ModelError, match="no mount named 'm9'"):
        vibss.frequency_response(m, INPUTS, OUTPUTS, foundation=Foundation(F, np.zeros((3, 3, F.size)), ["m9"]))
    with pytest.raises(ArgumentError, match="Foundation: receptance"):
        Foundation(F, np.zeros((6, 6, F.size)), ["m1"])
