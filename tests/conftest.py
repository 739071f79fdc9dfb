"""Fixtures shared by the tests."""

from __future__ import annotations

import pytest

from cases import models
from cases.models import asymmetric_model, prism_model, two_mass_model
from vibss import Model


@pytest.fixture
def prism() -> Model:
    return prism_model()


@pytest.fixture
def two_mass() -> Model:
    return two_mass_model()


@pytest.fixture
def asym() -> Model:
    return asymmetric_model()


@pytest.fixture(scope="module")
def powertrain() -> Model:
    """The bundled powertrain example, once per test module (it is frozen data)."""
    return models.powertrain()
