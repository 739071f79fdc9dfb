"""simulate on a large model stays sparse (issue 17 item 4): projected on a subspace built for its
channels and its input's spectrum, with an error estimate, checked against the exact dense modal
path on models small enough for both."""

from __future__ import annotations

import sys
import warnings

import numpy as np
import pytest

from cases import ROOT
import vibss.time.methods as time_api
from vibss import simulate
from vibss.errors import AnalysisError, VibssWarning
from vibss.model.excitation import Excitation
from vibss.model.timefunctions import HalfSine
from vibss.time.large import input_spectrum

sys.path.insert(0, str(ROOT / "benchmarks"))
from models import chain_model  # noqa: E402


def _both(model, excitation, outputs, monkeypatch, **kw):
    """The large-model path (threshold lowered below the model) and the exact dense modal path."""
    monkeypatch.setattr(time_api, "SIMULATE_LARGE_DOFS", 100)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", VibssWarning)
        large = simulate(model, [excitation], outputs=outputs, **kw)
    exact = simulate(model, [excitation], outputs=outputs, method="modal", **kw)
    return large, exact


def _stated(note: str) -> float:
    return float(note.split("estimated error ")[1].split(" ")[0])


@pytest.mark.parametrize("damping, n_bodies", [("classical", 100), ("none", 150)])
def test_projected_path_is_within_its_stated_estimate_of_the_dense_modal_path(monkeypatch, damping,
                                                                                n_bodies) -> None:
    """Chains of 600 and 900 DOF (classical damping; undamped), a 0.5 s half-sine force: the
    subspace built for the channels and the input's spectrum against every mode (the exact modal
    FOH path on the full model); every output's measured error lies below the estimate the note
    states, and the estimate is small."""
    model = chain_model(n_bodies, damping=damping, seed=3)
    shock = Excitation("shock", "force", "b0", HalfSine(100.0, duration=0.5), dof="z")
    outputs = ["b0.z", "b1.z", "b2.x", "b0.z.acc"]
    large, exact = _both(model, shock, outputs, monkeypatch, t_end=1.0, dt=1e-3)
    assert large.method == "modal" and "kept sparse" in large.note and "channel subspace of" in large.note
    assert exact.note.count("kept sparse") == 0
    err = np.abs(large.outputs - exact.outputs).max(axis=1) / np.abs(exact.outputs).max(axis=1)
    assert err.max() <= _stated(large.note) < 1e-6


def test_initial_conditions_and_free_vibration_are_refused_on_the_large_path(monkeypatch) -> None:
    monkeypatch.setattr(time_api, "SIMULATE_LARGE_DOFS", 30)
    model = chain_model(6, damping="none", seed=2)
    shock = Excitation("shock", "force", "b0", HalfSine(1.0, duration=0.01), dof="z")
    with pytest.raises(AnalysisError, match="initial.*method='modal'"):
        simulate(model, [shock], outputs=["b0.z"], t_end=0.1, dt=1e-3,
                 initial={"b1": {"displacement": [0.001, 0, 0, 0, 0, 0]}})
    with pytest.raises(AnalysisError, match="free vibration.*method='modal'"):
        simulate(model, [], outputs=["b0.z"], t_end=0.1, dt=1e-3,
                 initial={"b1": {"displacement": [0.001, 0, 0, 0, 0, 0]}})


def test_an_unreached_tolerance_is_refused_not_answered(monkeypatch) -> None:
    """When the greedy cannot reach the tolerance (here an unreachable one, in one round) simulate
    refuses, naming the dense path, rather than answer with an error it cannot state."""
    import vibss.linear.project.subspace as subspace
    import vibss.time.large as large

    monkeypatch.setattr(time_api, "SIMULATE_LARGE_DOFS", 100)
    monkeypatch.setattr(large, "TOLERANCE", 1e-30)
    monkeypatch.setattr(subspace, "MAX_ROUNDS", 0)
    model = chain_model(30, damping="none", seed=3)
    shock = Excitation("shock", "force", "b0", HalfSine(100.0, duration=0.5), dof="z")
    with pytest.raises(AnalysisError, match="did not reach 1e-30.*method='modal'"):
        simulate(model, [shock], outputs=["b0.z"], t_end=1.0, dt=1e-3)


def test_input_spectrum_is_the_half_sine_fourier_transform() -> None:
    """``dt |FFT|`` of a sampled half-sine of amplitude A and length tau against its transform in
    closed form, ``|U(w)| = 2 A (pi / tau) |cos(w tau / 2)| / |(pi / tau)^2 - w^2|``."""
    dt, tau, a = 1e-4, 0.02, 3.0
    t = dt * np.arange(4001)
    f, mag = input_spectrum(HalfSine(a, duration=tau).value(t)[None, :], dt)
    w = 2 * np.pi * f
    k = np.pi / tau
    with np.errstate(divide="ignore", invalid="ignore"):
        closed = 2 * a * k * np.abs(np.cos(w * tau / 2)) / np.abs(k * k - w * w)
    pick = (f > 1.0) & (f < 400.0) & (np.abs(f - 1 / (2 * tau)) > 5.0)
    np.testing.assert_allclose(mag[0, pick], closed[pick], rtol=1e-2, atol=1e-6 * closed.max())   # a sum, not the integral
