"""Regression tests of reviewed defects (time, sweep envelope, frequency grid and peaks, Krylov at
undamped resonances, report band and per-section failures). Closed forms wherever a value is checked."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from vibss import Body, Model, Mount, MountType, frequency_response, load_example, symmetric
from vibss.errors import AnalysisError, ModelError
from vibss.model.excitation import Excitation
from vibss.io import loads_model
from vibss.linear.signals import build_plant
from vibss.time.api import simulate
from vibss.time.sweep import _frf, sweep_envelope
from vibss.model.timefunctions import SineSweep

K, M, C = 1e4, 10.0, 20.0
WN = np.sqrt(K / M)


def sdof(c: float = C) -> Model:
    return Model([Body("b", M, [1, 1, 1])], [Mount("m", MountType("t", [K] * 3, [c] * 3), "b")])


def chain() -> Model:
    k1, k2 = 1e4, 2e3
    return Model([Body("a", 10.0, [1, 1, 1]), Body("b", 2.0, [1, 1, 1])],
                 [Mount("m1", MountType("t", [k1] * 3), "a"),
                  Mount("m2", MountType("t2", [k2] * 3, [3.0] * 3), "b", to="a")])


# 1 -- derivatives of prescribed motions --------------------------------------------------------

@pytest.mark.parametrize("method", ["modal", "forced_response", "ivp"])
def test_acceleration_of_a_prescribed_displacement_is_refused(method: str) -> None:
    with pytest.raises(AnalysisError, match=r"output 'a\.z\.acc' depends on the second derivative "
                                            r"of input 'a\.z\.disp'.*\(a\.z\.acc\)"):
        simulate(chain(), inputs={"a.z.disp": lambda t: np.sin(2 * np.pi * 3 * np.asarray(t))},
                 outputs=["a.z.acc"], t_end=0.5, dt=1e-3, method=method)


@pytest.mark.parametrize("method", ["modal", "forced_response", "ivp"])
def test_representable_derivatives_of_prescribed_motions(method: str) -> None:
    # z = V t: z' = V (piecewise constant, kept); velocity u = A t: z'' = A (kept)
    V, A = 0.02, 3.0
    r = simulate(chain(), inputs={"a.z.disp": lambda t: V * np.asarray(t)}, outputs=["a.z.vel"],
                 t_end=0.2, dt=1e-3, method=method)
    np.testing.assert_allclose(r.output("a.z.vel")[1:], V, rtol=1e-6)
    r = simulate(chain(), inputs={"a.z.vel": lambda t: A * np.asarray(t)}, outputs=["a.z.acc"],
                 t_end=0.2, dt=1e-3, method=method)
    np.testing.assert_allclose(r.output("a.z.acc")[1:], A, rtol=1e-6)


# 2 -- initial conditions ------------------------------------------------------------------------

@pytest.mark.parametrize("initial, message", [
    ({"b": [[0, 0, 0.01, 0, 0, 0]]}, r"initial\['b'\]: expected \{'displacement'"),
    ({"b": (1, 2, 3)}, r"initial\['b'\]: expected \{'displacement'"),
    ({"b": 5}, r"initial\['b'\]: expected .* got 5"),
    ({"c": {"displacement": [0] * 6}}, r"initial: unknown body 'c'; bodies are \['b'\]"),
    ({"b": {"disp": [0] * 6}}, r"initial\['b'\]: unknown key\(s\) \['disp'\]"),
    ({"b": {"velocity": [1, 2]}}, r"initial\['b'\]: velocity: expected 6 finite numbers"),
    ({"b": {"displacement": "abc"}}, r"initial\['b'\]: displacement: expected 6 finite numbers"),
])
def test_malformed_initial_conditions_are_refused(initial: object, message: str) -> None:
    with pytest.raises(ModelError, match=message):
        simulate(sdof(), inputs={"b.fz": lambda t: 0 * t}, outputs=["b.z"], t_end=0.1, dt=1e-3,
                 initial=initial)


# 3 -- other arguments -----------------------------------------------------------------------------

@pytest.mark.parametrize("kwargs, message", [
    ({"t_end": "abc"}, r"t_end: expected a number of seconds, got 'abc'"),
    ({"dt": None}, r"dt: expected a number of seconds, got None"),
    ({"method": "ivp", "rtol": -1}, r"rtol: expected a positive relative tolerance, got -1"),
    ({"method": "ivp", "atol": -1.0}, r"atol: expected None or an absolute tolerance >= 0"),
    ({"solver": "foo"}, r"solver: expected one of .* got 'foo'"),
    ({"t_end": 1e6, "dt": 1e-9}, r"is 1e\+15 samples, more than 5e\+07"),
    ({"dt": 0.0}, r"dt: must be a positive time step"),
    ({"dt": -1e-3}, r"dt: must be a positive time step"),
    ({"t_end": 0.0}, r"t_end: must be at least dt"),
    ({"method": "nope"}, r"method: unknown 'nope'"),
])
def test_bad_simulate_arguments_are_model_errors(kwargs: dict, message: str) -> None:
    args = {"t_end": 0.1, "dt": 1e-3, **kwargs}
    with pytest.raises(ModelError, match=message):
        simulate(sdof(), inputs={"b.fz": lambda t: 0 * t}, outputs=["b.z"], **args)


# 4 -- free vibration ------------------------------------------------------------------------------

@pytest.mark.parametrize("method", ["modal", "forced_response", "ivp"])
def test_free_decay_from_initial_conditions_alone(method: str) -> None:
    x0, v0 = 0.01, -0.2
    r = simulate(sdof(), outputs=["b.z"], t_end=1.0, dt=1e-3, method=method, rtol=1e-10, atol=1e-14,
                 initial={"b": {"displacement": [0, 0, x0, 0, 0, 0], "velocity": [0, 0, v0, 0, 0, 0]}})
    zeta = C / (2 * np.sqrt(K * M))
    wd = WN * np.sqrt(1 - zeta**2)
    t = r.time
    x = np.exp(-zeta * WN * t) * (x0 * np.cos(wd * t) + (v0 + zeta * WN * x0) / wd * np.sin(wd * t))
    assert np.abs(r.output("b.z") - x).max() < 1e-7 * x0
    assert r.input_names == () and r.inputs.shape == (0, t.size)
    assert r.note.startswith("free vibration")


def test_free_vibration_from_the_model_file_initial_conditions() -> None:
    k = (2 * np.pi) ** 2      # 1 Hz with 1 kg
    model = loads_model(f"""
[[body]]
name = "b"
mass = 1.0
inertia = [1.0, 1.0, 1.0]
initial = {{ displacement = [0, 0, 0.01, 0, 0, 0] }}
[[mount_type]]
name = "t"
stiffness = [{k!r}, {k!r}, {k!r}]
[[mount]]
type = "t"
body = "b"
""")
    r = simulate(model, [], outputs=["b.z"], t_end=0.5, dt=1e-3)
    np.testing.assert_allclose(r.output("b.z"), 0.01 * np.cos(2 * np.pi * r.time), atol=1e-12)
    with pytest.raises(ModelError, match="nothing drives the response"):
        simulate(sdof(), outputs=["b.z"], t_end=0.1, dt=1e-3)


# 5 -- sweep envelope at 0 Hz and on an undamped resonance ------------------------------------------

@pytest.mark.parametrize("kind", ["acceleration", "velocity"])
def test_sweep_envelope_from_zero_hz(kind: str) -> None:
    e = Excitation("g", kind, "ground", SineSweep(f1=0.0, f2=20.0, a1=1.0, a2=1.0, sweep_time=5.0), dof="z")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = sweep_envelope(sdof(), e, outputs=["b.z", "mount.m.dz"])
    assert r.frequency_hz[0] == 0.0
    assert np.isinf(r.steady[0, 0])          # absolute displacement under a constant acc / vel
    # relative deflection per unit input at 0 Hz: -m/k for acceleration, -m s/(...) -> 0 for velocity
    expected = M / K if kind == "acceleration" else 0.0
    assert abs(r.steady[1, 0] - expected) <= 1e-9 * M / K
    assert np.all(np.isfinite(r.steady[:, 1:]))


def test_steady_state_exactly_on_an_undamped_resonance() -> None:
    und = sdof(0.0)
    p = build_plant(und, ["b.fz"], ["b.z", "b.x"])
    h = _frf(p, np.array([WN, 0.5 * WN]))
    assert np.isinf(h[0, 0]) and h[1, 0] == 0.0    # the z mode drives b.z, not b.x
    np.testing.assert_allclose(h[0, 1].real, 1 / (K - M * (0.5 * WN) ** 2), rtol=1e-12)
    # the reviewer's case: the envelope grid lands on the 5 Hz natural frequency
    k = (2 * np.pi * 5) ** 2 / 4
    m0 = Model([Body("b", 1.0, [1, 1, 1])], symmetric(Mount("m", MountType("t", [k] * 3), "b", at=[0.5, 0.5, 0.0])))
    e = Excitation("sw", "force", "b", SineSweep(f1=0.0, f2=10.0, a1=1.0, a2=1.0, sweep_time=10.0), dof="z")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = sweep_envelope(m0, e, outputs=["b.z", "b.x"], points=401)
    j = int(np.argmin(np.abs(r.frequency_hz - 5.0)))
    assert r.frequency_hz[j] == 5.0            # the z mode: 4 k on 1 kg, exactly 5 Hz
    assert np.isinf(r.steady[0, j]) and r.steady[1, j] == 0.0
    w = 2 * np.pi * r.frequency_hz[j + 1]
    np.testing.assert_allclose(r.steady[0, j + 1], 1 / abs(4 * k - w**2), rtol=1e-9)


# 6 -- frequencies argument ------------------------------------------------------------------------

@pytest.mark.parametrize("frequencies, message", [
    ([], r"frequencies: got an empty list"),
    ({"f1": 1, "f2": 5, "points": "x"}, r"frequencies: points: expected an integer >= 2, got 'x'"),
    ({"f1": "a", "f2": 5}, r"frequencies: f1: expected a frequency >= 0 \[Hz\] or None, got 'a'"),
    ({"f1": 1, "f2": 5, "points": 2.5}, r"frequencies: points: expected an integer >= 2, got 2.5"),
    ({"f1": 1, "f2": 5, "points": 1}, r"frequencies: points: expected an integer >= 2, got 1"),
    ({"f1": 1, "f2": 5, "spacing": "lin"}, r"frequencies: spacing: expected 'log' or 'linear'"),
    ("abc", r"frequencies: expected finite frequencies >= 0"),
])
def test_bad_frequencies_are_model_errors(frequencies: object, message: str) -> None:
    with pytest.raises(ModelError, match=message):
        frequency_response(sdof(), ["b.fz"], ["b.z"], frequencies=frequencies)


def test_integral_float_points_are_accepted() -> None:
    r = frequency_response(sdof(), ["b.fz"], ["b.z"],
                           frequencies={"f1": 1, "f2": 5, "points": 10.0, "spacing": "linear", "refine": False})
    np.testing.assert_allclose(r.frequency_hz, np.linspace(1, 5, 10))


# 7 -- peaks beside an infinite 0 Hz value ----------------------------------------------------------

def test_no_peak_beside_an_infinite_zero_hz_value() -> None:
    f = np.concatenate([[0.0, 0.005, 0.01], np.linspace(1, 10, 901)])
    r = frequency_response(sdof(), ["ground.z.acc"], ["b.z"], frequencies=f)
    assert np.isinf(r.channel("b.z")[0])
    peaks = r.peaks("b.z")
    assert len(peaks) == 1
    fp, a = peaks[0]
    w = 2 * np.pi * fp
    np.testing.assert_allclose(a, abs((K + 1j * w * C) / (K - M * w**2 + 1j * w * C)) / w**2, rtol=1e-10)
    assert abs(fp - WN / (2 * np.pi)) < 0.02
    assert "infinite" in r.report()


# 8 -- Krylov reduction of an undamped model from 0 Hz -----------------------------------------------

def test_krylov_undamped_from_zero_hz() -> None:
    from vibss.reduction.api import reduce
    from vibss.reduction.prune import frf
    from vibss.reduction.scope import Scope

    model = load_example("two_mass")
    red = reduce(model, Scope(["body1.fz"], ["body2.z"], 0, 50, 1e-4), "krylov")
    full = build_plant(model, ["body1.fz"], ["body2.z"])
    s = 2j * np.pi * np.array([0.0, 0.3, 1.2, 10.0, 40.0])
    want = np.array([np.linalg.solve(full.K + si * full.C + si**2 * full.M, full.F[:, 0]) @ full.Oq[0]
                     for si in s])
    np.testing.assert_allclose(frf(red.plant, s)[0, 0], want, rtol=1e-6)
    # exactly on an undamped pole: inf, not LinAlgError
    p = build_plant(sdof(0.0), ["b.fz"], ["b.z"])
    h = frf(p, np.array([1j * WN, 0.5j * WN]))[0, 0]
    assert np.isinf(h[0])
    np.testing.assert_allclose(h[1].real, 1 / (K - M * (0.5 * WN) ** 2), rtol=1e-12)


# 9, 10 -- report ---------------------------------------------------------------------------------

def test_report_sweep_uses_the_file_band() -> None:
    from vibss.frequency.api import sweep_response
    from vibss.report import study

    model = load_example("powertrain")
    spec = model.settings["frequency"]
    rep = study(model, figures=False)
    r = rep.results["frequency"]
    assert r.frequency_hz.min() == spec["f1"] and r.frequency_hz.max() == spec["f2"]
    cli = sweep_response(model, None, spec.get("f1"), spec.get("f2"), int(spec.get("points", 1000)),
                         spec.get("spacing", "log"))       # what ``vibss frf`` computes
    np.testing.assert_array_equal(r.frequency_hz, cli.frequency_hz)
    for y in r.outputs:
        assert r.peaks(y, "sweep") == cli.peaks(y, "sweep")


def test_report_survives_a_numerical_failure_in_one_section(monkeypatch: pytest.MonkeyPatch) -> None:
    from vibss import report

    def broken(*args: object) -> object:
        raise np.linalg.LinAlgError("Singular matrix")

    monkeypatch.setitem(report._RUNNERS, "damped", broken)
    rep = report.study(load_example("two_mass"), figures=False)
    sec = rep.section("damped")
    assert sec.skipped and sec.note == "failed: LinAlgError: Singular matrix"
    assert not rep.section("modes").skipped and "modes" in rep.results

    def typo(*args: object) -> object:
        raise TypeError("a programming error")

    monkeypatch.setitem(report._RUNNERS, "damped", typo)
    with pytest.raises(TypeError, match="a programming error"):
        report.study(load_example("two_mass"), figures=False)
