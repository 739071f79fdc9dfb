"""Shock pulses and the SRS against closed forms and an independent solve_ivp of the SDOF."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import vibss
from vibss import shock

T = 0.01
DT = 1e-6


def _half_sine_record(t_end=0.05):
    t = np.arange(0.0, t_end, DT)
    return t, np.where(t < T, np.sin(np.pi * t / T), 0.0)


def test_half_sine_undamped_maximax_closed_forms():
    t, x = _half_sine_record()
    r = shock.srs(t, x, [0.810 / T, 0.5 / T], q=np.inf)
    assert r.response[0] == pytest.approx(1.7685, abs=2e-4)     # published peak of the half-sine SRS
    assert r.response[1] == pytest.approx(np.pi / 2, rel=1e-6)


@pytest.mark.parametrize("fnt", [0.3, 0.81, 1.3, 2.0, 3.7])
def test_half_sine_undamped_residual_closed_form(fnt):
    # residual amplitude of an undamped SDOF after a unit half-sine: 4 fT |cos(pi fT)| / |1 - 4 (fT)^2|
    t, x = _half_sine_record()
    r = shock.srs(t, x, [fnt / T], q=np.inf, kind="residual")
    exact = 4 * fnt * abs(np.cos(np.pi * fnt)) / abs(1 - 4 * fnt ** 2)
    assert r.response[0] == pytest.approx(exact, rel=1e-5, abs=1e-6)


@pytest.mark.parametrize("fn", [30.0, 81.0, 250.0, 700.0])
def test_q10_against_solve_ivp(fn):
    t, x = _half_sine_record(0.06)
    w, z = 2 * np.pi * fn, 1 / 20

    def base(s):
        return np.sin(np.pi * s / T) if s < T else 0.0

    def rhs(s, y):  # relative displacement u: u'' + 2 z w u' + w^2 u = -base
        return [y[1], -2 * z * w * y[1] - w * w * y[0] - base(s)]

    sol = solve_ivp(rhs, (0, t[-1]), [0.0, 0.0], t_eval=t, rtol=1e-11, atol=1e-14, max_step=T / 50)
    acc = -(2 * z * w * sol.y[1] + w * w * sol.y[0])      # absolute acceleration
    r = shock.srs(t, x, [fn], q=10.0, kind="maximax")
    assert r.response[0] == pytest.approx(np.max(np.abs(acc)), rel=1e-6)
    pos = shock.srs(t, x, [fn], q=10.0, kind="positive").response[0]
    neg = shock.srs(t, x, [fn], q=10.0, kind="negative").response[0]
    assert pos == pytest.approx(np.max(acc), rel=1e-6)
    assert neg == pytest.approx(-np.min(acc), rel=1e-6)


def test_kinds_consistent_and_pseudo_quantities():
    t, x = _half_sine_record()
    f = np.geomspace(10, 2000, 25)
    get = {k: shock.srs(t, x, f, q=10.0, kind=k).response for k in shock.srs.__globals__["KINDS"]}
    np.testing.assert_allclose(get["maximax"], np.maximum(get["positive"], get["negative"]), rtol=1e-12)
    np.testing.assert_allclose(get["maximax"], np.maximum(get["primary"], get["residual"]), rtol=1e-12)
    pv = shock.srs(t, x, f, quantity="pseudo_velocity").response
    d = shock.srs(t, x, f, quantity="displacement").response
    np.testing.assert_allclose(pv * 2 * np.pi * f, get["maximax"], rtol=1e-12)
    np.testing.assert_allclose(d * (2 * np.pi * f) ** 2, get["maximax"], rtol=1e-12)


def test_pulses_in_g():
    hs = shock.half_sine(50.0, 0.011)
    assert float(hs.value(0.0055)) == pytest.approx(50 * 9.80665)
    assert float(shock.haversine(2.0, 1.0).value(0.5)) == pytest.approx(2 * 9.80665)
    assert float(shock.sawtooth(10.0, 0.02).value(0.01)) == pytest.approx(5 * 9.80665)
    tr = shock.trapezoid(10.0, 0.01, 0.002)
    np.testing.assert_allclose(tr.value([0.001, 0.005, 0.009, 0.02]), np.array([5, 10, 5, 0]) * 9.80665)


def test_errors_and_result_protocol():
    t, x = _half_sine_record()
    with pytest.raises(vibss.ArgumentError):
        shock.srs(t, x, [1e6])
    with pytest.raises(vibss.ArgumentError):
        shock.srs(t, x, [100.0], kind="peak")
    with pytest.raises(vibss.ArgumentError):
        shock.half_sine(10.0, 0.0)
    r = shock.srs(t, x, [100.0, 200.0])
    assert "Shock response spectrum" in r.report()
    assert r.to_dict()["kind"] == "maximax"
    assert vibss.srs is shock.srs


def test_envelope_check_margins_against_the_closed_form_peak():
    """Undamped maximax SRS of a half-sine peaks at 1.7685 A near fn T = 0.81: a flat spec at that
    level gives a 0 dB margin there and negative margins elsewhere."""
    import numpy as np

    from vibss.shock import check_envelope, srs

    T, A = 0.01, 1.0
    t = np.arange(0, 0.05, 1e-6)
    x = np.where(t < T, A * np.sin(np.pi * t / T), 0.0)
    f = np.array([40.0, 81.0, 200.0])
    r = srs(t, x, f, q=np.inf)
    c = check_envelope(r, [10.0, 1000.0], [1.7685, 1.7685], lower_db=-np.inf, upper_db=0.01)
    assert c.margin_db[1] == pytest.approx(0.0, abs=0.01)
    assert c.passed and np.all(c.margin_db[[0, 2]] < -0.5)
    tight = check_envelope(r, [10.0, 1000.0], [1.7685, 1.7685], lower_db=-0.5, upper_db=0.5)
    assert not tight.passed and "FAIL" in tight.report()
    with pytest.raises(ValueError, match="spec needs"):
        check_envelope(r, [100.0, 10.0], [1.0, 1.0])


def test_tripartite_plots_pseudo_velocity():
    import numpy as np

    from vibss.shock import srs

    t = np.arange(0, 0.05, 1e-5)
    r = srs(t, np.where(t < 0.011, 100 * np.sin(np.pi * t / 0.011), 0.0), [20.0, 100.0, 500.0])
    fig = r.tripartite()
    line = fig.axes[0].lines[0]
    np.testing.assert_allclose(line.get_ydata(), r.response / (2 * np.pi * r.frequency_hz), rtol=1e-12)
    assert fig.axes[0].get_ylabel() == "pseudo-velocity [m/s]"


def test_srs_takes_a_damping_ratio_instead_of_q():
    import numpy as np
    from vibss import shock

    t = np.arange(0, 0.03, 1e-5)
    x = np.where(t < 0.01, np.sin(np.pi * t / 0.01), 0.0)
    f = [40.0, 81.0, 200.0]
    np.testing.assert_array_equal(shock.srs(t, x, f, zeta=0.05).response, shock.srs(t, x, f, q=10.0).response)
    np.testing.assert_array_equal(shock.srs(t, x, f, zeta=0.0).response, shock.srs(t, x, f, q=np.inf).response)
    with pytest.raises(vibss.ModelError, match="q or zeta, not both"):
        shock.srs(t, x, f, q=5.0, zeta=0.1)
    with pytest.raises(vibss.ModelError, match=r"zeta must be in \[0, 1\)"):
        shock.srs(t, x, f, zeta=1.5)


def test_a_spectrum_of_an_input_in_g_is_drawn_at_its_true_level() -> None:
    """Issue 33 item 1: an input in g was drawn 9.81 x too low on the tripartite axes."""
    from vibss.model.units import STANDARD_GRAVITY

    t = np.arange(0.0, 0.03, 1e-5)
    pulse_g = np.where(t < 0.011, 30.0 * np.sin(np.pi * t / 0.011), 0.0)     # 30 g, 11 ms
    f = [10.0, 45.0, 200.0]
    in_g = shock.srs(t, pulse_g, f, unit="g")
    in_si = shock.srs(t, pulse_g * STANDARD_GRAVITY, f)
    assert in_g.units == ("g",) and in_si.units == ("m/s^2",)
    # the filter is linear: the same spectrum to the rounding of its recursion over 3,000 samples
    np.testing.assert_allclose(in_g.response * STANDARD_GRAVITY, in_si.response, rtol=1e-10)
    drawn = [fig.axes[0].lines[0].get_ydata() for fig in (in_g.tripartite(), in_si.tripartite())]
    np.testing.assert_allclose(drawn[0], drawn[1], rtol=1e-10)           # pseudo-velocity [m/s] both
    np.testing.assert_allclose(drawn[1], in_si.response / (2 * np.pi * np.asarray(f)), rtol=1e-12)
