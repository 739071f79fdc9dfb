"""simulate on a large model stays sparse (issue 17 item 4): kept modes + residual vectors, with
an error estimate, checked against the exact dense modal path on a model small enough for both."""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

import vibss.time.api as time_api
from vibss import simulate
from vibss.errors import AnalysisError, VibssWarning
from vibss.model.excitation import Excitation
from vibss.model.timefunctions import HalfSine, Step
from vibss.time.large import error_estimate, input_frequency

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "benchmarks"))
from models import chain_model  # noqa: E402


def _both(model, excitation, outputs, monkeypatch, **kw):
    """The large-model path (threshold lowered below the model) and the exact dense modal path."""
    monkeypatch.setattr(time_api, "LARGE_DOFS", 100)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", VibssWarning)
        large = simulate(model, [excitation], outputs=outputs, **kw)
    exact = simulate(model, [excitation], outputs=outputs, method="modal", **kw)
    return large, exact


def _stated(note: str) -> float:
    return float(note.split("estimated error ")[1].split(" ")[0])


def test_truncated_path_is_within_its_stated_error_of_the_dense_modal_path(monkeypatch) -> None:
    """A 100-body chain (600 DOF, classical damping), a 0.5 s half-sine force: the modes up to
    8 x 2 Hz plus residual vectors against every mode (the exact modal FOH path); the measured error
    of every output lies below the estimate the note states, and the static part is exact."""
    model = chain_model(100, damping="classical", seed=3)
    shock = Excitation("shock", "force", "b0", HalfSine(100.0, duration=0.5), dof="z")
    outputs = ["b0.z", "b1.z", "b2.x", "b0.z.acc"]
    large, exact = _both(model, shock, outputs, monkeypatch, t_end=1.0, dt=1e-3)
    assert large.method == "modal" and "kept sparse" in large.note and "residual static vectors" in large.note
    assert exact.note.count("kept sparse") == 0
    err = np.abs(large.outputs - exact.outputs).max(axis=1) / np.abs(exact.outputs).max(axis=1)
    assert err.max() <= _stated(large.note)
    assert err[0] < 0.1                       # the driven point's displacement


def test_every_mode_kept_matches_the_dense_path_to_round_off(monkeypatch) -> None:
    """A model whose modes all lie below the cut-off keeps them all (n - 2 by shift-invert, and the
    residual directions): the same answer as the dense modal path (the estimate, from the coarser
    answers with half and a quarter of the cut-off, stays above it)."""
    model = chain_model(20, damping="classical", seed=1)
    shock = Excitation("shock", "force", "b3", HalfSine(50.0, duration=0.01), dof="x")
    large, exact = _both(model, shock, ["b3.x", "b10.y"], monkeypatch, t_end=0.2, dt=5e-4)
    err = np.abs(large.outputs - exact.outputs).max() / np.abs(exact.outputs).max()
    assert err < 1e-9
    assert "the 118 modes" in large.note and err <= _stated(large.note)


def test_initial_conditions_and_free_vibration_are_refused_on_the_large_path(monkeypatch) -> None:
    monkeypatch.setattr(time_api, "LARGE_DOFS", 30)
    model = chain_model(6, damping="none", seed=2)
    shock = Excitation("shock", "force", "b0", HalfSine(1.0, duration=0.01), dof="z")
    with pytest.raises(AnalysisError, match="initial.*method='modal'"):
        simulate(model, [shock], outputs=["b0.z"], t_end=0.1, dt=1e-3,
                 initial={"b1": {"displacement": [0.001, 0, 0, 0, 0, 0]}})
    with pytest.raises(AnalysisError, match="free vibration.*method='modal'"):
        simulate(model, [], outputs=["b0.z"], t_end=0.1, dt=1e-3,
                 initial={"b1": {"displacement": [0.001, 0, 0, 0, 0, 0]}})


def test_too_many_modes_below_the_cut_off_is_refused_not_truncated(monkeypatch) -> None:
    """A 100-body chain's modes are dense from 2.3 Hz (about 160 below 16 Hz): with at most 20
    modes allowed a 0.5 s pulse's cut-off is out of reach, and simulate says so instead of
    answering with modes that may not be the ones the outputs see."""
    import vibss.time.large as large

    monkeypatch.setattr(time_api, "LARGE_DOFS", 100)
    monkeypatch.setattr(large, "MAX_MODES", 20)
    monkeypatch.setattr(large, "FIRST_MODES", 10)
    model = chain_model(100, damping="none", seed=3)
    shock = Excitation("shock", "force", "b0", HalfSine(100.0, duration=0.5), dof="z")
    with pytest.raises(AnalysisError, match="modes reach only .* of the cut-off 16 Hz.*method='modal'.*krylov"):
        simulate(model, [shock], outputs=["b0.z"], t_end=1.0, dt=1e-3)


def test_input_frequency_from_the_pulse_and_from_the_spectrum() -> None:
    """A pulse states its content (1 / duration); a step does not, and the sampled spectrum's
    L1 tail sets it, capped by the Nyquist frequency."""
    dt = 1e-3
    t = dt * np.arange(2001)
    pulse = HalfSine(1.0, duration=0.02)
    assert input_frequency([pulse], pulse.value(t)[None, :], dt) == pytest.approx(50.0)
    step = Step(1.0)
    f = input_frequency([step], step.value(t)[None, :], dt)
    assert 0 < f <= 500.0
    # a slow Gaussian bump (sampled input, no function): its spectrum is exp(-(2 pi f s)^2 / 2),
    # so the L1 tail beyond f_in is 1e-3 of the total near f_in = 3.29 / (2 pi s) (erfc inverse)
    s = 0.05
    bump = np.exp(-0.5 * ((t - 1.0) / s) ** 2)
    assert input_frequency([None], bump[None, :], dt) == pytest.approx(3.29 / (2 * np.pi * s), rel=0.05)


def test_error_estimate_is_the_geometric_tail() -> None:
    """Answers converging geometrically (ratio 1/4): the estimate d2 / (1 - r) with r raised to 0.5
    bounds the last answer's true error (d2 / 3) from above."""
    truth = np.ones((5, 1))
    e = 0.1
    y_q, y_h, y = truth + e, truth + e / 4, truth + e / 16
    est = error_estimate(y, y_h, y_q)[0]
    d2, r = e / 4 - e / 16, 0.5          # the ratio 1/4 is raised to RATIO_MIN = 0.5
    assert est == pytest.approx(d2 / (1 - r) / (1 + e / 16))
    assert est >= (e / 16) / (1 + e / 16)
