"""Rotational interface DOFs: mounts with rotational rates on a foundation whose rotation under them
matters, coupled with a (6m, 6m, nf) receptance, against the same system modelled whole."""

from __future__ import annotations

import numpy as np
import pytest

import vibss
from vibss import Body, ControlPoint, Foundation, Model, Mount, MountType

CORNERS = {"m1": (0.4, 0.3, 0.05), "m2": (-0.4, 0.3, 0.0), "m3": (-0.4, -0.3, -0.03)}
F = np.geomspace(2.0, 200.0, 21)
# rotational rates: each mount passes a moment, so the plate's rotation under it loads the source
ISO = MountType("iso", [2e5, 3e5, 5e5], [40.0, 60.0, 100.0], rotational_stiffness=[3e3, 2e3, 4e3],
                rotational_damping=[1.0, 0.8, 1.5])
SOFT = MountType("floor", [4e5, 4e5, 1e6], [300.0, 300.0, 800.0])
INPUTS = ["engine.fz", "engine.mx", "engine.fy"]
OUTPUTS = ["engine.z", "engine.rx", "engine.y", "mount.m1.mz", "mount.m3.fx"]


def engine() -> Body:
    return Body("engine", 120.0, [4.0, 6.0, 7.0], cog=[0.05, -0.02, 0.25])


def plate() -> Body:
    return Body("plate", 60.0, [3.0, 5.0, 7.0], cog=[0.1, 0.0, -0.1])


def mounts(to: str = "ground") -> list[Mount]:
    return [Mount(n, ISO, "engine", at=a, frame="global", to=to) for n, a in CORNERS.items()]


def floor() -> list[Mount]:
    return [Mount(f"f{i}", SOFT, "plate", at=a, frame="global")
            for i, a in enumerate([(0.9, 0.7, -0.2), (-0.9, 0.7, -0.2), (-0.9, -0.7, -0.2), (0.9, -0.7, -0.2)])]


def points() -> list[ControlPoint]:
    return [ControlPoint(f"p{n}", "plate", a, frame="global") for n, a in CORNERS.items()]


def foundation(rotations: bool) -> Foundation:
    return Foundation.from_model(Model([plate()], floor(), control_points=points()), {n: f"p{n}" for n in CORNERS},
                                 F, rotations=rotations)


@pytest.fixture(scope="module")
def whole():
    m = Model([engine(), plate()], mounts("plate") + floor(), control_points=points())
    return vibss.frequency_response(m, INPUTS, OUTPUTS + [f"p{n}.{a}" for n in CORNERS for a in "xyz"], frequencies=F)


def _err(h: np.ndarray, ref: np.ndarray) -> float:
    return float((np.abs(h - ref) / np.abs(ref).max(axis=(1, 2), keepdims=True)).max())


def test_six_dofs_a_point_couple_the_mounts_moments(whole):
    found = foundation(True)
    assert found.receptance.shape == (18, 18, F.size) and found.rotations
    r = vibss.frequency_response(Model([engine()], mounts()), INPUTS, OUTPUTS, foundation=found)
    p = len(OUTPUTS)
    rows = [p + 6 * i + k for i in range(3) for k in range(3)]          # the points' translations
    assert _err(r.response[:p], whole.response[:p]) < 1e-9
    assert _err(r.response[rows], whole.response[p:]) < 1e-9
    assert r.outputs[p:p + 6] == tuple(f"foundation.m1.{a}" for a in ("x", "y", "z", "rx", "ry", "rz"))
    assert r.outputs[p + 18:p + 24] == tuple(f"foundation.m1.{a}" for a in ("fx", "fy", "fz", "mx", "my", "mz"))
    # the moment into the plate at m1's point is the mount's own moment (the point is the mount's)
    whole_m = vibss.frequency_response(Model([engine(), plate()], mounts("plate") + floor(), control_points=points()),
                                       INPUTS, ["plate.rx", "plate.ry", "plate.rz"], frequencies=F)
    assert _err(r.response[p + 3:p + 6], whole_m.response) < 1e-9      # every point turns with the plate


def test_without_the_rotations_the_moments_are_lost(whole):
    """The same mounts coupled with translations only miss the plate's rotation under them: the error
    is physical (far above rounding), which is what the 6m receptance is for."""
    r = vibss.frequency_response(Model([engine()], mounts()), INPUTS, OUTPUTS, foundation=foundation(False))
    assert _err(r.response[:len(OUTPUTS)], whole.response[:len(OUTPUTS)]) > 1e-3
