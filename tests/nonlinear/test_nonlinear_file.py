"""Stops and curves in model files: read in the file's units, written back, the same laws."""

from __future__ import annotations

import numpy as np
import pytest

from vibss import Body, Model, Mount, MountType, symmetric
from vibss.errors import ModelFileError
from vibss.io.modelfile import dumps_model, loads_model

POINTS = [(-6e-3, -1500.0), (-3e-3, -500.0), (0.0, 0.0), (2e-3, 300.0), (6e-3, 2000.0)]


def _model() -> Model:
    snub = MountType("snub", [1.5e5, 1.5e5, 2e5], damping=[10.0, 10.0, 20.0], stops={"z": ((1e-3, 2.5e-3), 2e6)})
    curved = MountType("curved", [2e5, 2e5, 0.0], curve={"z": POINTS})
    return Model([Body("b", 100.0, [2.0, 2.5, 3.0])],
                 [*symmetric(Mount("m", snub, "b", at=[0.3, 0.2, 0.0])), Mount("c", curved, "b", at=[0.0, 0.0, 0.1])],
                 gravity=[0.0, 0.0, -9.81], name="nl")


@pytest.mark.parametrize("units", ["SI", {"length": "mm"}, {"length": "mm", "force": "kN"}])
def test_stops_and_curves_round_trip(units: object) -> None:
    model = _model()
    back = loads_model(dumps_model(model, units=units))
    for name in ("snub", "curved"):
        a, b = model.mount_types[name], back.mount_types[name]
        d = np.linspace(-8e-3, 8e-3, 41)
        for la, lb in zip(a.laws, b.laws):
            assert np.allclose(la.force(d), lb.force(d), rtol=1e-13, atol=1e-9)
    assert back.mount_types["snub"].stops == {"z": ((1e-3, 2.5e-3), 2e6)}


def test_file_stops_in_the_file_units() -> None:
    text = dumps_model(_model(), units={"length": "mm"})
    assert "clearance = [1.0, 2.5]" in text and "stiffness = 2000.0" in text      # mm and N/mm
    bad = text.replace("clearance = [1.0, 2.5]", "clearance = [-1.0, 2.5]")
    with pytest.raises(ModelFileError, match="clearance must be finite and not negative"):
        loads_model(bad)
