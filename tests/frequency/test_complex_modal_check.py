"""Issue 29: complex_modal's check sees its error near a slow resonance beside stiff modes.

Its a-posteriori estimate (:func:`vibss.frequency.kernels.complex_modal_estimated`, from the damped
pairs and the undamped basis's frequency bounds) steers the check's exact solves; every number here
is measured against the exact solve (:func:`vibss.linear.solve.exact.response`) at every frequency.
"""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np
import pytest

import vibss
from vibss.errors import VibssWarning
from vibss.frequency.contracts import check
from vibss.frequency.kernels import METHODS, complex_modal_estimated
from vibss.linear.eigen.basis import modal_basis
from vibss.linear.plant.build import build_plant
from vibss.linear.solve.exact import response

from cases.scaled import graded_chain, instrument
from frequency.test_contracts import INS as P_INS, OUTS as P_OUTS, penalty_model

INS = ["b0.fz", "b7.fx"]
OUTS = ["b0.z", "b3.y", "b7.x", "b7.rz"]
CM = METHODS["complex_modal"]


def nudged_chain() -> vibss.Model:
    """The damped graded chain with every mass and mount stiffness one ulp up (1 + 2^-52)."""
    model = graded_chain(damped=True)
    up = 1 + 2.0**-52
    types: dict[str, vibss.MountType] = {}
    for m in model.mounts:
        types.setdefault(m.type.name, dataclasses.replace(m.type, stiffness=np.asarray(m.type.stiffness) * up))
    return dataclasses.replace(model, bodies=[dataclasses.replace(b, mass=b.mass * up) for b in model.bodies],
                               mounts=[dataclasses.replace(m, type=types[m.type.name]) for m in model.mounts])


def _errors(plant, s, h) -> np.ndarray:
    ex = response(plant, s)
    return np.linalg.norm(h - ex, axis=(0, 1)) / np.linalg.norm(ex, axis=(0, 1))


@pytest.fixture(scope="module")
def chain():
    model = nudged_chain()
    plant = build_plant(model, INS, OUTS)
    basis = modal_basis(plant)
    return model, plant, basis, np.sqrt(basis.omega2[~basis.rigid])


def flank_grid(w: np.ndarray, offset: float, n: int = 300) -> np.ndarray:
    """The three slowest modes sampled ``offset`` above their frequencies, the rest on a log sweep [rad/s]."""
    return np.concatenate([[w[0] * 0.5], w[:3] * (1 + offset), [w[2] * 1.5], np.geomspace(w[3] * 0.9, w[-1] * 2, n)])


@pytest.mark.parametrize("offset", [2e-4, 3e-5, 2e-6])
def test_the_check_measures_the_slow_resonances_flank(chain, offset: float) -> None:
    """The three slowest modes (0.14-0.19 mHz, damping ratios 4-7e-7, beside modes up to 3 kHz)
    sampled on their flanks: the peaks-and-valleys check measured 3-4x below the true largest error
    (1.2e-7 / 3.2e-8, 8.0e-7 / 2.1e-7 and 1.1e-5 / 3.1e-6 measured); with the estimate it measures
    the largest. At 3e-5 that was a silent miss: 2.1e-7 within the limit 3.7e-7, the truth past it."""
    model, plant, basis, w = chain
    grid = flank_grid(w, offset)
    s = 1j * grid
    h, est = complex_modal_estimated(plant, s, basis)
    err = _errors(plant, s, h)
    old = check(CM, plant, s, h, None, basis)
    new = check(CM, plant, s, h, None, basis, est)
    assert old is not None and new is not None
    assert old.error < 0.5 * err.max()                # the miss: the old check did not look there
    assert new.error == pytest.approx(err.max(), rel=1e-6)
    if offset == 3e-5:
        assert old.ok and not new.ok


def test_named_warns_with_a_covering_bound_and_auto_falls_back(chain, monkeypatch) -> None:
    """The silent miss above (offset 3e-5, a 100-point sweep): the named method now warns with a
    bound covering its error at every frequency; auto answers by an exact solve within 1e-8
    everywhere (its costs rank the banded solve first here); with its pick forced to complex modes
    it tries them, sees the failed check and falls back, and its note says so."""
    model, plant, basis, w = chain
    hz = flank_grid(w, 3e-5, 100) / (2 * np.pi)
    s = 2j * np.pi * hz
    h = METHODS["complex_modal"].kernel(plant, s, basis)
    old = check(CM, plant, s, h, None, basis)
    assert old is not None and old.ok                 # silent before
    exact = response(plant, s)
    size = np.linalg.norm(exact, axis=(0, 1))
    with pytest.warns(VibssWarning, match="'complex_modal' missed its claim"):
        r = vibss.frequency_response(model, INS, OUTS, hz, method="complex_modal")
    err = np.linalg.norm(r.response - exact, axis=(0, 1)) / size
    bound = float(r.note.split("check failed: error ")[1].split()[0])
    assert err.max() > old.limit and bound >= 0.99 * err.max()
    import vibss.frequency.api as api

    with warnings.catch_warnings():
        warnings.simplefilter("error", VibssWarning)
        auto = vibss.frequency_response(model, INS, OUTS, hz)
        assert auto.method != "complex_modal"
        assert np.max(np.linalg.norm(auto.response - exact, axis=(0, 1)) / size) <= 1e-8
        monkeypatch.setattr(api, "choose", lambda plant, nf, basis: ("complex_modal", "forced by the test"))
        forced = vibss.frequency_response(model, INS, OUTS, hz)
    assert forced.method != "complex_modal" and "tried complex_modal check failed" in forced.note
    assert np.max(np.linalg.norm(forced.response - exact, axis=(0, 1)) / size) <= 1e-8



ESTIMATE_CASES = {
    "graded chain": (nudged_chain, INS, OUTS),
    "penalty link, mass ratio 1e6 (seed 35)": (lambda: penalty_model(35), P_INS, P_OUTS),
    "penalty link (seed 93)": (lambda: penalty_model(93), P_INS, P_OUTS),
    "instrument (mass ratio 6e3)": (instrument, ["sensor.fz", "block.fx"], ["sensor.z", "block.x", "bracket.ry"]),
}


@pytest.mark.parametrize("name", sorted(ESTIMATE_CASES))
def test_the_estimate_bounds_the_error_at_every_frequency(name: str) -> None:
    """Dense grid (+-2 % around every mode, 21 points each, and a log sweep): the estimate is at
    least the measured error wherever that is above the exact solve's own rounding (1e-11), and
    pessimistic by the factor measured in docs/robustness.md."""
    build, ins, outs = ESTIMATE_CASES[name]
    plant = build_plant(build(), ins, outs)
    basis = modal_basis(plant)
    w = np.sqrt(basis.omega2[~basis.rigid])
    grid = np.unique(np.concatenate([wk * (1 + np.linspace(-0.02, 0.02, 21)) for wk in w]
                                    + [np.geomspace(w[0] / 3, w[-1] * 3, 200)]))
    s = 1j * grid
    h, est = complex_modal_estimated(plant, s, basis)
    err = _errors(plant, s, h)
    seen = err > 1e-11
    assert np.all(est[seen] >= err[seen]), (name, float((est[seen] / err[seen]).min()))
