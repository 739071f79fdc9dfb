"""The result protocol (vibss/results.py): every public result type is walked and checked.

Each result is built on a small model whose answers have closed forms: one 10 kg body on four
identical mounts at (+-a, +-b, 0) (x, y, z decoupled from the rotations' translations only
through the layout, z is a pure single-DOF motion: k_z = 4 k, m = 10 kg), so indexing by signal
name can be checked against 1 / (4 k), m g / (4 k), 1 / sqrt(m), 2 F / (4 k).
"""

from __future__ import annotations

import json
import pickle
import sys

import control
import numpy as np
import pytest
from matplotlib.figure import Figure

import cases.models as cases
import vibss
from vibss import (Body, Excitation, Model, Mount, MountType, Scope, damped_modes, frequency_response,
                   modes, reduce, simulate, static, sweep_envelope)
from vibss.errors import MissingDependencyError, SignalError, VibssError
from vibss.model.excitation import SineSweep, Step
from vibss.results import Result, TextTable as Table, jsonable

MASS, KZ, CZ, G = 10.0, 1e4, 20.0, 9.81


def box() -> Model:
    return cases.box(MASS, [1.0, 1.2, 1.5], KZ, CZ, at=[0.3, 0.2, 0.0], gravity=[0.0, 0.0, -G], name="box")


@pytest.fixture(scope="module")
def results() -> dict[str, Result]:
    m = box()
    und = modes(m)
    sweep = Excitation("sw", "force", "b", SineSweep(f1=2.0, f2=6.0, a1=1.0, a2=1.0, sweep_time=2.0), dof="z")
    return {
        "static": static(m),
        "modes": und,
        "damped": damped_modes(m, und),
        "frequency": frequency_response(m, ["b.fz"], ["b.z", "b.x"], frequencies=[0.0, 1.0, 3.0]),
        "time": simulate(m, [Excitation("s", "force", "b", Step(5.0), dof="z")], outputs=["b.z", "b.x"],
                         t_end=0.5, dt=1e-3),
        "sweep": sweep_envelope(m, sweep, outputs=["b.z"], points=50),
        "reduction": reduce(m, Scope(["b.fz"], ["b.z"], 0.0, 20.0, 1e-6), method="modal"),
        "srs": _half_sine_srs(),
        "operating": vibss.operating_point(Model([Body("b", MASS, [1.0, 1.2, 1.5])], vibss.symmetric(Mount(
            "m", MountType("snub", [KZ, KZ, KZ], [CZ, CZ, CZ], stops={"z": (1e-3, 1e6)}), "b", at=[0.3, 0.2, 0.0])),
            gravity=[0.0, 0.0, -G], name="box")),
        "harmonic": vibss.harmonic_balance(Model([Body("b", MASS, [1.0, 1.2, 1.5])], [Mount(
            "m", MountType("snub", [KZ, KZ, KZ], [CZ, CZ, CZ], stops={"z": (1e-3, 1e6)}), "b")], name="box"),
            {"b.fz": 5.0}, ["b.z", "b.x"], frequencies=[1.0, 3.0], harmonics=3),
    }


def _half_sine_srs() -> Result:
    """SRS of a 1 m/s^2, 10 ms half-sine, named like a body signal so the name checks apply."""
    t = np.arange(0.0, 0.02, 1e-5)
    return vibss.srs(t, np.where(t < 0.01, np.sin(np.pi * t / 0.01), 0.0), [20.0, 81.0, 300.0],
                     q=np.inf, name="b.z")


KINDS = ["static", "modes", "damped", "frequency", "time", "sweep", "reduction", "srs", "operating", "harmonic"]


def test_every_public_result_type_is_walked(results: dict[str, Result]) -> None:
    public = {name for name in vibss.__all__ if isinstance(getattr(vibss, name), type)
              and issubclass(getattr(vibss, name), Result)}
    assert {type(r).__name__ for r in results.values()} == public
    assert public == {"StaticResult", "Modes", "DampedModes", "FrequencyResponse", "TimeResponse",
                      "SweepEnvelope", "Reduction", "ShockResponseSpectrum", "OperatingPoint",
                      "HarmonicBalanceResult"}


@pytest.mark.parametrize("kind", KINDS)
def test_text_html_and_names(results: dict[str, Result], kind: str) -> None:
    r = results[kind]
    text = r.report()
    assert text and str(r) == text
    page = r._repr_html_()
    assert page.count("<table>") == len(r.html_tables()) >= 1 and "</table>" in page
    assert isinstance(r.output_labels, tuple) and r.output_labels
    assert all(isinstance(x, str) for x in r.output_labels + r.input_labels)
    assert len(r.units) == len(r.output_labels)                  # type: ignore[attr-defined]
    assert isinstance(r.method, str) and r.method                # type: ignore[attr-defined]
    assert isinstance(r.note, str)                               # type: ignore[attr-defined]


@pytest.mark.parametrize("kind", KINDS)
def test_strict_json(results: dict[str, Result], kind: str) -> None:
    r = results[kind]
    d = r.to_dict()
    text = json.dumps(d, allow_nan=False)                        # to_dict is JSON-ready itself
    assert json.loads(r.to_json()) == json.loads(text)
    assert "NaN" not in r.to_json(indent=1) and "Infinity" not in r.to_json()


@pytest.mark.parametrize("kind", KINDS)
def test_pandas_and_its_absence(results: dict[str, Result], kind: str, monkeypatch: pytest.MonkeyPatch) -> None:
    import pandas as pd

    r = results[kind]
    assert isinstance(r.to_pandas(), pd.DataFrame)               # type: ignore[attr-defined]
    monkeypatch.setitem(sys.modules, "pandas", None)             # import pandas -> ImportError
    with pytest.raises(MissingDependencyError, match=r"vibss\[pandas\]") as err:
        r.to_pandas()                                            # type: ignore[attr-defined]
    assert isinstance(err.value, ImportError) and err.value.argument == "pandas"


@pytest.mark.parametrize("kind", KINDS)
def test_plot_returns_a_figure_without_pyplot(results: dict[str, Result], kind: str,
                                             monkeypatch: pytest.MonkeyPatch) -> None:
    r = results[kind]
    monkeypatch.setitem(sys.modules, "matplotlib.pyplot", None)  # any pyplot import fails
    kwargs = {"which": [0]} if kind == "modes" else {}
    fig = r.plot(ax=None, **kwargs)                              # type: ignore[attr-defined]
    assert isinstance(fig, Figure) and fig.axes


def test_plot_draws_into_given_axes(results: dict[str, Result]) -> None:
    from vibss.plotting._draw import new_figure

    for kind, count in (("frequency", 2), ("static", 2), ("damped", 1), ("time", 1), ("sweep", 1)):
        fig = new_figure(6, 4)
        axes = fig.subplots(count, 1, squeeze=False)[:, 0]
        got = results[kind].plot(ax=axes if count > 1 else axes[0])  # type: ignore[attr-defined]
        assert got is fig and all(a.has_data() for a in axes)


def test_indexing_by_signal_name_gives_closed_forms(results: dict[str, Result]) -> None:
    k4 = 4 * KZ
    assert results["static"]["b.z"] == pytest.approx(-MASS * G / k4, rel=1e-12)
    assert results["static"]["b.x"] == pytest.approx(0.0, abs=1e-15)
    fr = results["frequency"]
    assert fr["b.z", "b.fz"][0] == pytest.approx(1 / k4, rel=1e-12)             # 0 Hz: 1 / k
    s = 2j * np.pi * 3.0
    np.testing.assert_allclose(fr["b.z", "b.fz"][2], 1 / (k4 + 4 * CZ * s + MASS * s**2), rtol=1e-10)
    assert fr["b.z"].shape == (1, 3) and fr["b.z"][0, 1] == fr["b.z", "b.fz"][1]
    und = results["modes"]
    z_mode = int(np.argmax(np.abs(und["b.z"])))
    assert abs(und["b.z"][z_mode]) == pytest.approx(1 / np.sqrt(MASS), rel=1e-10)   # mass-normalised
    assert und.omega[z_mode] == pytest.approx(np.sqrt(k4 / MASS), rel=1e-10)
    zeta = 4 * CZ / (2 * np.sqrt(k4 * MASS))
    dm = results["damped"]
    j = int(np.argmax(np.abs(dm["b.z"])))
    assert dm.damping_ratio[j] == pytest.approx(zeta, rel=1e-9)               # type: ignore[attr-defined]
    tr = results["time"]
    assert np.abs(tr["b.z"]).max() == pytest.approx(2 * 5.0 / k4 * 1.0, rel=0.2)   # < 2F/k (damped)
    assert np.abs(tr["b.z"]).max() <= 2 * 5.0 / k4
    assert results["sweep"]["b.z"].shape == (50,)
    # undamped half-sine SRS at fn T = 0.81: the closed-form primary maximum 1.768 (Harris, table 8.1)
    assert results["srs"]["b.z"][1] == pytest.approx(1.768, abs=2e-3)
    red = results["reduction"]
    sub = red["b.z", "b.fz"]
    assert isinstance(sub, control.StateSpace)
    assert float(np.real(sub.dcgain())) == pytest.approx(1 / k4, rel=1e-9)


@pytest.mark.parametrize("kind", KINDS)
def test_unknown_names_say_did_you_mean(results: dict[str, Result], kind: str) -> None:
    r = results[kind]
    with pytest.raises(SignalError, match=r"did you mean 'b.z'") as err:
        r["b.zz"]
    assert isinstance(err.value, KeyError) and isinstance(err.value, VibssError)
    assert err.value.received == "b.zz" and "b.z" in err.value.expected
    back = pickle.loads(pickle.dumps(err.value))
    assert str(back) == str(err.value) and back.expected == err.value.expected


def test_results_without_inputs_refuse_an_input_index(results: dict[str, Result]) -> None:
    for kind in ("static", "modes", "damped"):
        with pytest.raises(SignalError, match="no inputs"):
            results[kind]["b.z", "b.fz"]
    with pytest.raises(VibssError, match="index by output only"):
        results["time"]["b.z", "b.fz"]


def test_python_control_twins(results: dict[str, Result]) -> None:
    fr = results["frequency"].control
    assert isinstance(fr, control.FrequencyResponseData)
    assert fr.output_labels == ["b:z", "b:x"] and fr.input_labels == ["b:fz"]
    np.testing.assert_allclose(fr.omega, 2 * np.pi * np.array([0.0, 1.0, 3.0]))  # 0 Hz is finite here
    tr = results["time"].control
    assert isinstance(tr, control.TimeResponseData)
    assert list(tr.output_labels) == ["b.z", "b.x"]
    assert isinstance(results["reduction"].control, control.StateSpace)
    for kind in ("static", "modes", "damped", "sweep", "srs"):
        assert results[kind].control is None


def test_python_control_names_agree_with_the_twins(results: dict[str, Result]) -> None:
    fr = results["frequency"]
    twin = fr.control
    assert (fr.noutputs, fr.ninputs) == (twin.noutputs, twin.ninputs) == (2, 1)
    np.testing.assert_allclose(fr.phase, twin.phase, atol=1e-12)          # radians, both
    np.testing.assert_allclose(fr.magnitude, twin.magnitude, rtol=1e-14)
    tr = results["time"]
    assert (tr.noutputs, tr.ninputs) == (tr.control.noutputs, tr.control.ninputs) == (2, 1)
    np.testing.assert_array_equal(tr.outputs, tr.control.outputs)        # type: ignore[attr-defined]


def test_old_names_stay_as_aliases(results: dict[str, Result]) -> None:
    fr, tr = results["frequency"], results["time"]
    assert fr.outputs == fr.output_labels and fr.inputs == fr.input_labels      # type: ignore[attr-defined]
    assert fr.reason == fr.note                                                  # type: ignore[attr-defined]
    assert isinstance(fr.frd, control.FrequencyResponseData)                     # type: ignore[attr-defined]
    assert tr.output_names == tr.output_labels and tr.input_names == tr.input_labels  # type: ignore[attr-defined]
    assert isinstance(tr.data, control.TimeResponseData)                         # type: ignore[attr-defined]
    assert results["modes"].dofs == results["modes"].output_labels              # type: ignore[attr-defined]


def test_non_finite_numbers_become_null() -> None:
    """A free body's receptance diverges at 0 Hz: inf in the data, null in the JSON."""
    m = Model([Body("f", 2.0, [1.0, 1.0, 1.0])], [Mount("m", MountType("t", [0.0, 0.0, 1e3]), "f")])
    r = frequency_response(m, ["f.fx"], ["f.x"], frequencies=[0.0, 2.0])
    assert np.isinf(r.response[0, 0, 0])
    data = json.loads(r.to_json())
    assert data["outputs"]["f.x"]["amplitude"][0] is None
    assert data["outputs"]["f.x"]["amplitude"][1] == pytest.approx(1 / (2.0 * (2 * np.pi * 2.0) ** 2))
    assert jsonable({"a": (np.nan, 1 + 2j), 3: np.float32(0.5)}) == {"a": [None, [1.0, 2.0]], "3": 0.5}


def test_auto_says_why(results: dict[str, Result]) -> None:
    assert results["frequency"].note and results["time"].note.startswith("auto")  # type: ignore[attr-defined]
    assert results["modes"].note.startswith("auto")                              # type: ignore[attr-defined]
    assert reduce(box(), Scope(["b.fz"], ["b.z"], 0.0, 20.0, 1e-6)).note.startswith("auto: 6 DOFs")


def test_html_is_escaped() -> None:
    t = Table(["<b>"], [["a & b"]], title="x<y", notes=("<script>",))
    page = t.to_html()
    assert "<b>" not in page and "&lt;b&gt;" in page and "a &amp; b" in page and "&lt;script&gt;" in page


def test_results_are_not_iterable(results: dict[str, Result]) -> None:
    with pytest.raises(TypeError):
        iter(results["frequency"])
