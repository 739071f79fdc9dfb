"""Random vibration (vibss.random_response): a single-DOF isolator under a flat base PSD against the
exact integral (pi/2) fn W0 (Q + 1/Q) (7.9662 g RMS at fn = 100 Hz, Q = 10, W0 = 0.04 g^2/Hz) and
Miles beside it; PSD breakpoints and their exact integral; correlated inputs against a brute-force
integral of the FRF; errors."""

from __future__ import annotations

import numpy as np
import pytest

from cases import ROOT
import vibss
from vibss.errors import ArgumentError
from vibss.random import G, PSD, random_response

FN, Q, W0, MASS = 100.0, 10.0, 0.04, 10.0


def isolator():
    k = MASS * (2 * np.pi * FN) ** 2
    c = 2 * (1 / (2 * Q)) * np.sqrt(k * MASS)
    t = vibss.MountType("iso", [k / 4] * 3, damping=[c / 4] * 3)
    return vibss.Model([vibss.Body("box", MASS, [1.0, 1.0, 1.0])],
                       vibss.symmetric(vibss.Mount("m", t, "box", at=[0.3, 0.2, 0.0])))


def test_flat_base_psd_matches_the_exact_integral():
    r = random_response(isolator(), {"ground.z.acc": ([1e-3, 1e6], [W0, W0])}, ["box.z.acc"])
    exact = np.sqrt(np.pi / 2 * FN * W0 * (Q + 1 / Q))
    assert exact == pytest.approx(7.9662, abs=5e-5)
    assert r.rms[0] / G == pytest.approx(exact, rel=1e-6)
    # Miles beside it: sqrt(pi/2 f_peak |T(f_peak)| W0), the peak of |T|^2 from the closed form
    f = np.linspace(95, 105, 200_001)
    zeta, rr = 1 / (2 * Q), f / FN
    t2 = (1 + (2 * zeta * rr) ** 2) / ((1 - rr ** 2) ** 2 + (2 * zeta * rr) ** 2)
    k = np.argmax(t2)
    assert r.miles[0] / G == pytest.approx(np.sqrt(np.pi / 2 * f[k] * np.sqrt(t2[k]) * W0), rel=2e-4)
    assert r.three_sigma[0] == pytest.approx(3 * r.rms[0], rel=1e-15)
    assert "7.966 g" in r.report()


def test_psd_breakpoints_log_log_and_exact_integral():
    p = PSD([20, 80, 350, 2000], [0.01, 0.04, 0.04, 0.007])
    assert p(np.sqrt(20 * 80)) == pytest.approx(np.sqrt(0.01 * 0.04) * G ** 2, rel=1e-12)   # geometric mean
    assert p(10.0) == 0.0 and p(3000.0) == 0.0
    f = np.geomspace(20, 2000, 400_001)
    assert p.mean_square == pytest.approx(np.trapezoid(p(f), f), rel=1e-8)
    assert p.rms_g == pytest.approx(np.sqrt(np.trapezoid(p(f), f)) / G, rel=1e-8)


def test_correlated_inputs_against_brute_force():
    """Two force inputs driving one mount force: rho = 0, 1 and 0.5j against a fine-grid integral
    of |H|^2-combinations from vibss.frequency_response."""
    model = isolator()
    spec = ([20.0, 400.0], [1.0, 1.0])                            # N^2/Hz and (N m)^2/Hz
    out = ["mount.m.fz"]
    f = np.geomspace(20, 400, 200_001)
    h = vibss.frequency_response(model, ["box.fz", "box.mx"], out, f).response[0]
    for rho in (0.0, 1.0, 0.5j):
        r = random_response(model, {"box.fz": spec, "box.mx": spec}, out,
                            correlation={("box.fz", "box.mx"): rho})
        s = np.abs(h[0]) ** 2 + np.abs(h[1]) ** 2 + 2 * np.real(rho * h[0] * np.conj(h[1]))   # S_ab ~ E[u_a conj(u_b)]
        assert r.rms[0] == pytest.approx(np.sqrt(np.trapezoid(s, f)), rel=1e-6), rho


def test_result_protocol_and_plot(tmp_path):
    r = random_response(isolator(), {"ground.z.acc": ([5, 500], [0.01, 0.01])}, ["box.z.acc", "mount.m.dz"])
    assert r.units == ("m/s^2", "m") and r.psd_units() == ("(m/s^2)^2/Hz", "m^2/Hz")
    df = r.to_pandas()
    assert df.attrs["units"]["mount.m.dz"] == "m^2/Hz" and r.to_json()
    r.plot().savefig(tmp_path / "random.png")
    assert (tmp_path / "random.png").stat().st_size > 10_000


@pytest.mark.parametrize("call, message", [
    (lambda m: random_response(m, {"ground.z.acc": ([10, 5], [1, 1])}), "positive and increasing"),
    (lambda m: random_response(m, {"ground.z.acc": PSD([10, 100], [1, 1], unit="G^2/Hz")}), "unknown 'G\\^2/Hz'"),
    (lambda m: random_response(m, {"ground.z.acc": ([10, 100], [1, -1])}), "must not be negative"),
    (lambda m: random_response(m, {"ground.z.acc": 0.04}), "expected a PSD or a \\(frequency_hz, level\\) pair"),
    (lambda m: random_response(m, {"box.fz": ([10, 100], [1, 1])}, correlation={("box.fz", "box.fy"): 1}), "correlation"),
    (lambda m: random_response(m, {"box.fz": ([10, 100], [1, 1]), "box.fy": ([10, 100], [1, 1])},
                               correlation={("box.fz", "box.fy"): 2}), r"\|rho\| must be <= 1"),
])
def test_bad_input_named(call, message):
    with pytest.raises(ArgumentError, match=message):
        call(isolator())


def test_random_guide(capsys):
    """The random-vibration block of docs/analyses/shock-and-random.md runs and prints what it says."""
    import re
    from pathlib import Path

    text = (ROOT / "docs/analyses/shock-and-random.md").read_text()
    block = re.findall(r"```python\n(.*?)```", text.split("## Random vibration", 1)[1], re.S)[0]
    scope: dict = {}
    exec(compile(block, "shock-and-random.md", "exec"), scope)
    out = capsys.readouterr().out
    assert "(7.966 g)" in out and "(7.941 g)" in out
    assert scope["r"].rms[0] / G == pytest.approx(np.sqrt(np.pi / 2 * 100 * 0.04 * 10.1), rel=1e-7)
