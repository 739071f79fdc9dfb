"""Unit tables: factors against exact definitions, labels, and errors that list the valid units."""

from __future__ import annotations

import math

import numpy as np
import pytest

from vibss.errors import ModelError
from vibss.model.units import Units


@pytest.mark.parametrize("units, quantity, expected", [
    (Units(length="mm"), "length", 1e-3),
    (Units(length="mm"), "stiffness", 1e3),                    # 1 N/mm = 1000 N/m
    (Units(length="mm"), "damping", 1e3),                      # 1 N s/mm = 1000 N s/m
    (Units(length="mm"), "inertia", 1e-6),                     # 1 kg mm^2
    (Units(length="mm"), "moment", 1e-3),                      # 1 N mm
    (Units(length="mm"), "acceleration", 1e-3),
    (Units(length="mm", time="ms"), "acceleration", 1e3),      # 1 mm/ms^2 = 1000 m/s^2
    (Units(length="in", force="lbf"), "stiffness", 4.4482216152605 / 0.0254),
    (Units(mass="lb", length="ft"), "inertia", 0.45359237 * 0.3048**2),
    (Units(mass="t"), "mass", 1000.0),
    (Units(mass="g"), "mass", 1e-3),
    (Units(force="kN", length="cm"), "stiffness", 1e5),
    (Units(angle="deg"), "angle", math.pi / 180),
    (Units(angle="deg", time="ms"), "angular_velocity", math.pi / 180 * 1e3),
    (Units(), "dimensionless", 1.0),
])
def test_factors(units, quantity, expected):
    assert units.factor(quantity) == pytest.approx(expected, rel=1e-14)


def test_to_si_converts_arrays():
    np.testing.assert_allclose(Units(length="mm").to_si([1.0, 2.0, 3.0], "stiffness"), [1e3, 2e3, 3e3])


@pytest.mark.parametrize("quantity, label", [
    ("stiffness", "N/mm"), ("damping", "N s/mm"), ("inertia", "kg mm^2"), ("moment", "N mm"),
    ("acceleration", "mm/s^2"), ("angular_velocity", "deg/s"), ("dimensionless", "-"),
])
def test_labels(quantity, label):
    assert Units(length="mm", angle="deg").label(quantity) == label


def test_unknown_unit_lists_valid_ones():
    with pytest.raises(ModelError, match=r"length.*'furlong'.*\['m', 'cm', 'mm', 'in', 'ft'\]"):
        Units(length="furlong")
    with pytest.raises(ModelError, match="did you mean 'mm'"):
        Units(length="MM")


def test_from_mapping_defaults_to_degrees_and_rejects_unknown_keys():
    assert Units.from_mapping(None) == Units(angle="deg")
    assert Units.from_mapping({"angle": "rad", "length": "mm"}) == Units(length="mm")
    with pytest.raises(ModelError, match="did you mean 'length'"):
        Units.from_mapping({"lenght": "mm"})
    with pytest.raises(ModelError, match="expected a table"):
        Units.from_mapping("mm")


def test_unknown_quantity():
    with pytest.raises(ModelError, match="did you mean 'stiffness'"):
        Units().factor("stifness")
