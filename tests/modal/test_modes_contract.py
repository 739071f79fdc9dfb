"""The eigen routes' contract (issue 29 item 3): a claim per route, the Kato-Temple bound as its
check in the note, a warning with the bound where it passes the claim, and the bound covers the
60-digit error (also across the whole campaign: tests/robustness/test_contract_campaign.py)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from cases import contract_models, mp_reference
import vibss
from vibss.errors import VibssWarning
from vibss.modal.methods import FREQUENCY_CLAIM, METHODS


def test_every_eigen_route_states_its_claim() -> None:
    for name, route in METHODS.items():
        assert route.claim is not None and route.claim.tolerance == FREQUENCY_CLAIM, name


@pytest.mark.parametrize("method", ["auto", "jacobi", "dense"])
def test_the_note_carries_the_bound_and_the_bound_covers_60_digits(method: str) -> None:
    model = contract_models.family("near_repeated", 1).model          # frequencies 1e-8 apart
    with warnings.catch_warnings():
        warnings.simplefilter("error", VibssWarning)                   # within the claim: no word
        md = vibss.modes(model, method=method)
    assert "checked: error" in md.note and "Kato-Temple" in md.note
    ref = np.sqrt(mp_reference.omega2(model))
    err = np.abs(md.omega - ref) / ref
    assert np.all(err <= md.error_estimate)
    assert np.nanmax(md.error_estimate) <= FREQUENCY_CLAIM


def test_a_bound_past_the_claim_is_a_warning_that_states_it() -> None:
    """A 1e13 N/m link beside 1e3 N/m mounts: the softest mode's bound is 4.5e-5 (its 60-digit error
    1.6e-16); the answer is given, with a VibssWarning and the bound in the note."""
    model = contract_models.family("penalty", 25).model
    with pytest.warns(VibssWarning, match=r"missed its claim .*error 4\.\de-05 > 1e-06"):
        md = vibss.modes(model, method="jacobi")
    assert "check failed: error 4." in md.note
    w2 = mp_reference.omega2(model)
    el = ~md.rigid
    assert np.all(np.abs(md.omega[el] - np.sqrt(w2[el])) / np.sqrt(w2[el]) <= md.error_estimate[el])
