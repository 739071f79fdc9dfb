"""Time functions against closed forms, breakpoints, building from data, and Excitation signals."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

import vibss
from vibss.errors import AnalysisError, ModelError
from vibss.model.excitation import (FUNCTIONS, Excitation, HalfSine, Haversine, Ramp, Rectangular,
                              Sawtooth, Sine, SineSweep, Step, Sum, Table, Triangle,
                              amplitude_quantity, function_from_dict)

A, T0, D = 3.0, 0.2, 0.05


def _area(f, a, b):
    return quad(lambda t: float(f.value(t)), a, b, points=f.breakpoints, limit=200)[0]


@pytest.mark.parametrize("cls, area, peak_at", [
    (Rectangular, A * D, None),
    (HalfSine, 2 * A * D / math.pi, T0 + D / 2),
    (Haversine, A * D / 2, T0 + D / 2),
    (Triangle, A * D / 2, T0 + D / 2),
    (Sawtooth, A * D / 2, None),
])
def test_pulses_closed_forms(cls, area, peak_at):
    f = cls(amplitude=A, start=T0, duration=D)
    assert _area(f, 0.0, 1.0) == pytest.approx(area, rel=1e-9)
    if peak_at is not None:
        assert float(f.value(peak_at)) == pytest.approx(A, rel=1e-12)
    assert f.value([T0 - 1e-9, T0 + D + 1e-9, 10.0]).tolist() == [0.0, 0.0, 0.0]
    assert f.end_time == pytest.approx(T0 + D)
    assert f.breakpoints[0] == T0 and f.breakpoints[-1] == pytest.approx(T0 + D)


def test_pulse_shapes_at_quarter_points():
    t = T0 + D * np.array([0.25, 0.75])
    np.testing.assert_allclose(HalfSine(A, T0, D).value(t), A * np.sqrt(0.5) * np.ones(2))
    np.testing.assert_allclose(Haversine(A, T0, D).value(t), [A / 2, A / 2])
    np.testing.assert_allclose(Triangle(A, T0, D).value(t), [A / 2, A / 2])
    np.testing.assert_allclose(Sawtooth(A, T0, D).value(t), [A / 4, 3 * A / 4])
    assert Triangle(A, T0, D).breakpoints == pytest.approx((T0, T0 + D / 2, T0 + D))


def test_sawtooth_terminal_peak():
    f = Sawtooth(amplitude=A, start=T0, duration=D)
    assert float(f.value(T0 + D - 1e-12)) == pytest.approx(A, rel=1e-9)
    assert float(f.value(T0 + D)) == 0.0


def test_step_and_ramp():
    s = Step(2.0, start=1.0, end=3.0)
    assert s.value([0.5, 1.0, 2.9, 3.0]).tolist() == [0.0, 2.0, 2.0, 0.0]
    assert s.breakpoints == (1.0, 3.0) and s.end_time == 3.0
    forever = Step(2.0, start=1.0)
    assert forever.breakpoints == (1.0,) and forever.end_time == 1.0   # constant from 1 s on
    r = Ramp(slope=4.0, start=1.0, end=2.0)
    assert r.value([0.0, 1.5, 2.0, 9.0]).tolist() == [0.0, 2.0, 4.0, 4.0]
    assert r.breakpoints == (1.0, 2.0) and Ramp(1.0).end_time == math.inf


def test_sine():
    f = Sine(amplitude=2.0, frequency=5.0, phase=math.pi / 2, start=1.0, end=2.0)
    t = np.array([0.9, 1.0, 1.05, 1.1, 2.0])
    np.testing.assert_allclose(f.value(t), [0.0, 2.0, 0.0, -2.0, 0.0], atol=1e-12)
    assert f.breakpoints == (1.0, 2.0)


@pytest.mark.parametrize("law", ["linear", "log"])
def test_sweep_instantaneous_frequency_is_the_phase_rate(law):
    s = SineSweep(f1=2.0, f2=40.0, a1=1.0, a2=1.0, sweep_time=4.0, law=law, start=0.5)
    t = np.linspace(0.6, 4.4, 2001)
    h = 1e-6
    f_fd = (s.phase_at(t + h) - s.phase_at(t - h)) / (2 * h) / (2 * np.pi)
    np.testing.assert_allclose(f_fd, s.frequency_at(t), rtol=1e-6)
    assert float(s.frequency_at(0.5)) == pytest.approx(2.0)
    assert float(s.frequency_at(4.5)) == pytest.approx(40.0)
    if law == "log":  # exponential in time: geometric mean at mid-sweep
        assert float(s.frequency_at(2.5)) == pytest.approx(math.sqrt(80.0))
    else:
        assert float(s.frequency_at(2.5)) == pytest.approx(21.0)
    assert s.breakpoints == (0.5, 4.5) and s.end_time == 4.5
    assert s.value([0.4, 4.5]).tolist() == [0.0, 0.0]


def test_sweep_amplitude_linear_in_frequency():
    s = SineSweep(f1=10.0, f2=20.0, a1=100.0, a2=300.0, sweep_time=0.0)
    np.testing.assert_allclose(s.amplitude_at([10.0, 12.5, 20.0, 5.0, 25.0]), [100, 150, 300, 0, 0])
    moving = SineSweep(f1=10.0, f2=20.0, a1=100.0, a2=300.0, sweep_time=1.0)
    t = np.linspace(0.0, 0.999, 50)   # envelope: amplitude at the instantaneous frequency
    np.testing.assert_allclose(moving.value(t), (100 + 200 * t) * np.sin(moving.phase_at(t)))


def test_steady_state_sweep_has_no_time_history():
    s = SineSweep(f1=1.0, f2=5.0, a1=1.0, a2=1.0, sweep_time=0.0)
    assert s.steady_state and s.breakpoints == ()
    assert Excitation("e", "force", "b", s, dof="x").steady_state
    assert not Excitation("e", "force", "b", Step(1.0), dof="x").steady_state
    assert not SineSweep(1.0, 5.0, 1.0, 1.0, 2.0).steady_state
    with pytest.raises(AnalysisError, match="sweep_time"):
        s.value([0.0])


def test_table_interpolation_and_extrapolation():
    f = Table([1.0, 2.0, 4.0], [10.0, 20.0, -20.0])
    assert f.value([0.0, 1.5, 3.0, 4.0, 5.0]).tolist() == [0.0, 15.0, 0.0, -20.0, 0.0]
    assert f.breakpoints == (1.0, 2.0, 4.0) and f.end_time == 4.0
    held = Table([1.0, 2.0], [10.0, 20.0], extrapolate="hold")
    assert held.value([0.0, 3.0]).tolist() == [10.0, 20.0]


def test_sum_adds_values_and_merges_breakpoints():
    f = Step(1.0, start=0.5) + HalfSine(2.0, 1.0, 1.0) + Ramp(1.0, 3.0, 4.0)
    assert isinstance(f, Sum) and len(f.terms) == 3
    assert f.value([0.25, 1.5, 5.0]).tolist() == pytest.approx([0.0, 3.0, 2.0])
    assert f.breakpoints == (0.5, 1.0, 2.0, 3.0, 4.0)
    assert f.end_time == 4.0


@pytest.mark.parametrize("f", [
    Step(1.5, 0.1, 0.4), Rectangular(2.0, 0.1, 0.2), HalfSine(1.0, 0.0, 0.01), Haversine(1.0, 0.2, 0.3),
    Triangle(4.0, 0.0, 1.0), Sawtooth(-1.0, 0.5, 0.5), Ramp(3.0, 0.1), Sine(1.0, 2.0, 0.3, 0.1, 0.9),
    SineSweep(1.0, 9.0, 1.0, 2.0, 3.0, "log"), Table([0.0, 0.5, 1.0], [0.0, 1.0, 0.0], "hold"),
    Sum((Step(1.0), Sine(1.0, 3.0))),
])
def test_to_dict_round_trip(f):
    g = function_from_dict(f.to_dict())
    t = np.linspace(-0.5, 3.5, 401)
    np.testing.assert_array_equal(g.value(t), f.value(t))
    assert g.breakpoints == f.breakpoints


def test_function_from_dict_converts_units():
    f = function_from_dict({"type": "half_sine", "amplitude": 50.0, "start": 10.0, "duration": 11.0},
                           value_scale=9.81, time_scale=1e-3)
    assert (f.amplitude, f.start, f.duration) == pytest.approx((490.5, 0.01, 0.011))
    r = function_from_dict({"type": "ramp", "slope": 2.0}, value_scale=1e-3, time_scale=1e-3)
    assert r.slope == pytest.approx(2.0)                   # mm/ms = m/s
    s = function_from_dict({"type": "sine", "amplitude": 1.0, "frequency": 5.0, "phase": 90.0},
                           angle_scale=math.pi / 180, time_scale=1e-3)
    assert s.phase == pytest.approx(math.pi / 2) and s.frequency == 5.0   # frequencies stay Hz
    assert isinstance(function_from_dict([{"type": "step", "amplitude": 1.0}] * 2), Sum)


def test_table_from_file(tmp_path):
    (tmp_path / "rec.csv").write_text("time, accel\n# comment\n0.0, 0.0\n0.01, 2.0\n\n0.02, 0.0\n")
    f = function_from_dict({"type": "table", "file": "rec.csv"}, base=tmp_path, value_scale=0.5)
    assert f.value([0.005, 0.01]).tolist() == pytest.approx([0.5, 1.0])
    (tmp_path / "bad.csv").write_text("0 0\n1 2 3\n")
    bad = function_from_dict({"type": "table", "file": "bad.csv"}, base=tmp_path, who="m.toml: e")
    with pytest.raises(ModelError, match="m.toml: e: .*line 2.*two columns"):   # read on first use
        bad.value(0.5)
    with pytest.raises(ModelError, match="cannot read the file"):
        function_from_dict({"type": "table", "file": "missing.csv"}, base=tmp_path)


@pytest.mark.parametrize("data, words", [
    ({"type": "half_sine", "amplitude": 1.0, "start": 0.0, "duration": -1.0},
     ["half_sine", "duration", "> 0"]),
    ({"type": "half_sine", "amplitude": 1.0, "start": 0.0, "duration": 0.0}, ["half_sine", "duration"]),
    ({"type": "rectangular", "amplitude": 1.0, "duraton": 1.0},
     ["rectangular", "duraton", "did you mean 'duration'"]),
    ({"type": "halfsine", "amplitude": 1.0}, ["type", "did you mean 'half_sine'"]),
    ({"amplitude": 1.0}, ["type"]),
    ({"type": "triangle", "start": 0.0, "duration": 1.0}, ["triangle", "missing", "amplitude"]),
    ({"type": "step", "amplitude": "big"}, ["step", "amplitude", "number"]),
    ({"type": "step", "amplitude": float("nan")}, ["step", "amplitude", "finite"]),
    ({"type": "step", "amplitude": 1.0, "start": 2.0, "end": 1.0}, ["step", "end"]),
    ({"type": "sine", "amplitude": 1.0, "frequency": -1.0}, ["sine", "frequency"]),
    ({"type": "sine_sweep", "f1": 0.0, "f2": 5.0, "a1": 1, "a2": 1, "law": "log"}, ["sine_sweep", "log"]),
    ({"type": "sine_sweep", "f1": 1.0, "f2": 5.0, "a1": 1, "a2": 1, "law": "cubic"}, ["sine_sweep", "law"]),
    ({"type": "sine_sweep", "f1": 1.0, "f2": 5.0, "a1": 1, "a2": 1, "sweep_time": -1},
     ["sine_sweep", "sweep_time"]),
    ({"type": "table", "time": [0.0, 1.0, 1.0], "value": [0, 1, 2]}, ["table", "time", "increasing"]),
    ({"type": "table", "time": [0.0, 1.0], "value": [0, 1, 2]}, ["table", "lengths"]),
    ({"type": "table", "file": "x.csv", "time": [0, 1]}, ["table", "file"]),
    ([], ["function"]),
    ("half_sine", ["function"]),
])
def test_bad_parameters_name_the_type_and_key(data, words):
    with pytest.raises(ModelError) as info:
        function_from_dict(data, who="shock")
    assert str(info.value).startswith("shock")
    for w in words:
        assert w in str(info.value)


def test_registry_names_match_types():
    assert set(FUNCTIONS) >= {"step", "rectangular", "half_sine", "haversine", "triangle",
                              "sawtooth", "ramp", "sine", "sine_sweep", "table"}
    assert all(cls.type == name for name, cls in FUNCTIONS.items())


@pytest.mark.parametrize("kind, dof, at, direction, signal", [
    ("force", "x", None, None, "eng.fx"),
    ("force", "z", None, None, "eng.fz"),
    ("force", "ry", None, None, "eng.my"),
    ("displacement", "x", None, None, "eng.x.disp"),
    ("velocity", "rz", None, None, "eng.rz.vel"),
    ("acceleration", "z", None, None, "eng.z.acc"),
    ("force", "z", [0.1, 0.0, 0.0], None, "e1"),
    ("force", None, None, [0.0, 3.0, 4.0], "e1"),
    ("acceleration", None, None, [1.0, 1.0, 0.0], "e1"),
])
def test_signal_names(kind, dof, at, direction, signal):
    e = Excitation("e1", kind, "eng", Step(1.0), dof=dof, at=at, direction=direction)
    assert e.signal == signal
    if direction is not None:
        assert np.linalg.norm(e.direction) == pytest.approx(1.0)


def test_ground_motion_signal_and_units():
    e = Excitation("quake", "acceleration", "ground", Step(1.0), dof="x")
    assert e.signal == "ground.x.acc" and e.unit == "m/s^2"
    assert Excitation("m", "force", "b", Step(1.0), dof="rx").unit == "N m"
    assert amplitude_quantity("displacement", "ry") == "angle"
    assert amplitude_quantity("velocity", None) == "velocity"


@pytest.mark.parametrize("kwargs, words", [
    (dict(kind="force", target="ground", dof="z"), ["force", "ground"]),
    (dict(kind="force", target="b", dof="rx", at=[1, 0, 0]), ["at", "moment"]),
    (dict(kind="displacement", target="b", dof="x", at=[1, 0, 0]), ["at"]),
    (dict(kind="force", target="b", dof="x", direction=[1, 0, 0]), ["exactly one"]),
    (dict(kind="force", target="b"), ["exactly one"]),
    (dict(kind="force", target="b", dof="w"), ["dof"]),
    (dict(kind="force", target="b", direction=[0, 0, 0]), ["direction", "zero"]),
    (dict(kind="force", target="b", direction=[1, 0]), ["direction", "3"]),
    (dict(kind="push", target="b", dof="x"), ["kind"]),
    (dict(kind="force", target="b", dof="x", frame="local"), ["frame"]),
])
def test_excitation_validation(kwargs, words):
    with pytest.raises(ModelError) as info:
        Excitation("e1", function=Step(1.0), **kwargs)
    assert "excitation 'e1'" in str(info.value)
    for w in words:
        assert w in str(info.value)


@pytest.mark.parametrize("make, kind", [(lambda: Step(1.0, start=2.0, end=1.0), "step"),
                                        (lambda: Ramp(1.0, start=2.0, end=2.0), "ramp"),
                                        (lambda: Sine(1.0, 5.0, start=3.0, end=1.0), "sine")])
def test_window_end_must_follow_start(make, kind):
    with pytest.raises(ModelError, match=rf"{kind} function: end: must be after start"):
        make()


def test_pulses_need_a_duration():
    """Issue 16: HalfSine(amplitude) used to be a silent 1 s 'shock'; the duration is now required, in
    Python and in files (the message names the function and the key)."""
    import pytest

    from vibss import HalfSine, ModelError

    with pytest.raises(ModelError, match="half_sine function: duration: missing"):
        HalfSine(100.0)
    assert HalfSine(100.0, 0.0, 0.011).end_time == pytest.approx(0.011)
    text = ('[[body]]\nname = "b"\nmass = 1.0\ninertia = [1, 1, 1]\n[[mount_type]]\nname = "t"\n'
            'stiffness = [1e4, 1e4, 1e4]\n[[mount]]\nname = "m"\ntype = "t"\nbody = "b"\n'
            '[[excitation]]\nname = "shock"\nkind = "acceleration"\ntarget = "ground"\ndof = "z"\n'
            'function = { type = "half_sine", amplitude = 100.0 }\n')
    with pytest.raises(ModelError, match=r"excitation\[1\] \('shock'\).*duration: missing"):
        vibss.loads_model(text)
