"""The Python blocks of the analysis guides run, and the numbers they quote hold."""

from __future__ import annotations

import re

import matplotlib
import numpy as np
import pytest

from cases import ROOT
import vibss

matplotlib.use("Agg")

DOCS = ROOT / "docs"


def _blocks(name: str) -> list[str]:
    return re.findall(r"```python\n(.*?)```", (DOCS / name).read_text(), re.S)


def test_frequency_guide(capsys):
    scope: dict = {}
    for block in _blocks("analyses/frequency.md"):
        exec(compile(block, "frequency.md", "exec"), scope)
    out = capsys.readouterr().out
    assert "0.481 Hz" in out                     # the quoted lowest x mode of reference case 2
    import vibss

    low_x = [f for f, d in zip(vibss.modes(scope["model"]).frequency_hz,
                               vibss.modes(scope["model"]).directions) if d == "x"][0]
    assert scope["peaks"][0][0] == pytest.approx(low_x, rel=1e-3)
    np.testing.assert_allclose(abs(scope["t"].response[:, 0, 0]), 1.0, rtol=1e-9)   # 0 Hz
    # statics: all of body2's load passes into body1 through the upper mounts, then into ground
    np.testing.assert_allclose(scope["tf"].response[:, 0, 0], 1.0, rtol=1e-9)
    # the closed skyhook loop: its poles are those of the model with a 4000 N s/m damper from
    # body2 z to ground, assembled independently
    from vibss import Mount, MountType, damped_modes

    damper = Mount("sky", MountType("sky", [0.0, 0.0, 0.0], [0.0, 0.0, 4000.0]), "body2")
    ref = damped_modes(scope["model"].replace(mounts=list(scope["model"].mounts) + [damper])).poles
    got = scope["skyhook"].poles()
    got = got[got.imag > 1e-9]
    want = ref[ref.imag > 1e-9]
    got, want = got[np.argsort(got.imag)], want[np.argsort(want.imag)]   # real parts ~0: sort by imag
    assert f"{np.sum(ref.real < -1e-9) * 2} of 24 poles damped" in out   # one pair per damped mode
    np.testing.assert_allclose(got, want, rtol=1e-8, atol=1e-9 * np.abs(want).max())


def test_time_guide(capsys):
    scope: dict = {}
    for block in _blocks("analyses/time.md"):
        exec(compile(block, "time.md", "exec"), scope)
    r = scope["r"]
    assert "item.z.acc" in capsys.readouterr().out
    assert r.method.startswith("modal")


def test_api_reference_is_current_and_complete():
    """docs/api.md is what docs/make_api.py writes now, and no public object lacks a docstring."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("make_api", DOCS / "make_api.py")
    make_api = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(make_api)
    text, problems = make_api.render()
    assert problems == []
    assert (DOCS / "api.md").read_text() == text, "run: python docs/make_api.py"


def test_control_guide(capsys):
    scope: dict = {}
    for block in _blocks("analyses/control.md"):
        exec(compile(block, "control.md", "exec"), scope)
    out = capsys.readouterr().out
    assert "['actuator:fl:x:u', 'actuator:fl:y:u', 'actuator:fl:z:u'] 24" in out
    assert "bounce at 1.49 Hz: |T| 15.6 -> 0.93" in out           # the numbers the page quotes
    assert "gamma = 3.708, controller states 12" in out
    assert "1.558" in out and "0.6351" in out                     # the quarter car's body mode


def test_the_two_first_studies(tmp_path, monkeypatch, capsys):
    """docs/studies.md runs as written; its numbers against independent references."""
    from scipy.integrate import solve_ivp

    monkeypatch.chdir(tmp_path)
    first, second = _blocks("studies.md")
    ns: dict = {}
    exec(first, ns)
    # static equilibrium: the ground takes the weight of both bodies, and no horizontal force
    weight = (900.0 + 120.0) * 9.81
    np.testing.assert_allclose(ns["sag"].reaction[:3], [0.0, 0.0, -weight], atol=1e-9 * weight)
    assert {lab.split(".")[0] for lab in ns["modes"].labels} == {"genset", "tank"}
    # rigid-body limit: at 0 Hz the ground motion reaches both bodies unchanged
    t0 = vibss.transmissibility(ns["model"], ["ground.z.acc"], ["genset.z.acc", "tank.z.acc"], frequencies=[0.0])
    np.testing.assert_allclose(np.abs(t0.response[:, 0, 0]), 1.0, rtol=1e-12)
    assert (tmp_path / "genset_transmissibility.png").stat().st_size > 0
    out = capsys.readouterr().out
    assert "tank.y" in out and "10006.20" in out
    ns = {}
    exec(second, ns)
    # the box's z is a single-DOF isolator (mounts in the COG plane): z'' + c/m z' + k/m z = -a(t)
    m, k, c = 20.0, 4 * 2.0e4, 4 * 63.0
    a = ns["pulse"].value

    def rhs(t: float, x: np.ndarray) -> list[float]:
        return [x[1], -float(a(t)) - (c * x[1] + k * x[0]) / m]

    tt = ns["r"].time
    first_ = solve_ivp(rhs, (0.0, 0.011), [0.0, 0.0], rtol=1e-11, atol=1e-14, method="DOP853", dense_output=True)
    then = solve_ivp(rhs, (0.011, 0.5), first_.y[:, -1], rtol=1e-11, atol=1e-14, method="DOP853", dense_output=True)
    z, v = np.where(tt <= 0.011, first_.sol(np.minimum(tt, 0.011)), then.sol(np.maximum(tt, 0.011)))
    acc = -(c * v + k * z) / m                                  # absolute acceleration of the box
    # the half-sine is integrated exactly (its sine piece): the peaks agree to the integrator's tolerance
    assert ns["stroke_mm"] == pytest.approx(1e3 * np.abs(z).max(), rel=1e-9)
    assert ns["peak_g"] == pytest.approx(np.abs(acc).max() / 9.80665, rel=1e-9)
    assert "every input exact" in ns["r"].note
    # and the SRS filter (Smallwood), a third path, at the isolator's own frequency and Q
    fn, q = np.sqrt(k / m) / (2 * np.pi), np.sqrt(k * m) / c
    box = vibss.srs(tt, a(tt), [fn], q=q).response[0]
    assert box == pytest.approx(np.abs(acc).max(), rel=2e-3)


def test_nonlinear_guide(capsys):
    scope: dict = {}
    for block in _blocks("analyses/nonlinear.md"):
        exec(compile(block, "nonlinear.md", "exec"), scope)
    out = capsys.readouterr().out
    sag, closed = re.search(r"sag ([\d.]+) mm \(closed form ([\d.]+) mm\)", out).groups()
    assert sag == closed                                   # to the 4 printed decimals
    assert "modes of the tangent model at the operating point" in out
