"""Fixtures shared by the tests, and their order."""

from __future__ import annotations

import pytest


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """The tests marked slow first (stable otherwise): the two workers of ``make test`` start on them and
    end on short ones, so no long test is left for one worker while the other has finished."""
    items.sort(key=lambda item: item.get_closest_marker("slow") is None)

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
