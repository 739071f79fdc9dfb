"""Rotating machinery (vibss.orders): unbalance response of a one-DOF-like isolator against
m e W^2 H(W); phasor direction and moment arm against hand calculation; engine-order tables;
critical speeds against 60 f_n / k; a run-up against solve_ivp of the same equations with the
analytic load; errors."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from cases import ROOT
import vibss
from vibss.errors import ArgumentError, ModelError
from vibss.orders import OrderForce, Unbalance, order_response, run_up

M, K, C = 50.0, 2.0e5, 150.0            # kg, N/m per direction (4 mounts), N s/m


def isolator():
    """A 50 kg cube on four identical mounts symmetric about the COG: z decouples from the rest."""
    t = vibss.MountType("iso", stiffness=[K / 4] * 3, damping=[C / 4] * 3)
    body = vibss.Body("box", M, [2.0, 2.0, 2.0])
    return vibss.Model([body], vibss.symmetric(vibss.Mount("m", t, "box", at=[0.3, 0.2, 0.0])))


def test_unbalance_matches_m_e_w2_h():
    model = isolator()
    mu, e = 0.02, 0.05                                      # kg, m: 1e-3 kg m
    rpm = np.linspace(300, 6000, 400)
    r = order_response(model, Unbalance("fan", "box", mu, e, axis="x"), rpm, ["box.y", "box.z"])
    w = 2 * np.pi * rpm / 60
    h = 1.0 / (K - M * w ** 2 + 1j * C * w)
    expected = mu * e * w ** 2 * h
    # axis x: the force starts along u = x cross z = -y ... (u, v, x) right-handed; |y| = |z| = |F H|
    np.testing.assert_allclose(np.abs(r["box.z", "order 1"]), np.abs(expected), rtol=1e-10)
    np.testing.assert_allclose(np.abs(r["box.y", "order 1"]), np.abs(expected), rtol=1e-10)
    # the two components are 90 degrees apart (a circular orbit)
    ratio = r["box.z", "order 1"] / r["box.y", "order 1"]
    np.testing.assert_allclose(np.abs(ratio), 1.0, rtol=1e-10)
    np.testing.assert_allclose(np.abs(np.angle(ratio)), np.pi / 2, atol=1e-10)
    assert r.units == ("m", "m")
    fn = np.sqrt(K / M) / (2 * np.pi)
    crit = [c for c in r.critical_speeds() if abs(c[2] - fn) < 1e-6]
    assert crit and crit[0][3] == pytest.approx(60 * fn, rel=1e-12)


def test_unbalance_moment_about_the_cog():
    model = isolator()
    ub = Unbalance("disc", "box", 0.01, 0.1, axis="z", at=[0.0, 0.0, 0.25])
    f = ub.phasors(model, np.array([1200.0]))[:, 0]
    w = 2 * np.pi * 20.0
    # axis z: u = z x x = y, v = z x u = -x; F = m e W^2 (u - i v)
    np.testing.assert_allclose(f[:3], 0.01 * 0.1 * w ** 2 * np.array([1j, 1.0, 0.0]), rtol=1e-14)
    np.testing.assert_allclose(f[3:], np.cross([0.0, 0.0, 0.25], f[:3]), rtol=1e-14)


def test_order_force_table_interpolated_and_refused_outside():
    model = isolator()
    src = OrderForce("2nd", "box", 2.0, rpm=[1000, 3000], force=[[0, 0, 10.0], [0, 0, 30.0]])
    r = order_response(model, src, [1000.0, 2000.0, 3000.0], ["box.z"], quantity="accelerance")
    w = 2 * np.pi * 2 * np.array([1000.0, 2000.0, 3000.0]) / 60
    expected = np.array([10.0, 20.0, 30.0]) * (-w ** 2) / (K - M * w ** 2 + 1j * C * w)
    np.testing.assert_allclose(r["box.z", "order 2"], expected, rtol=1e-10)
    assert r.units == ("m/s^2",)
    with pytest.raises(ArgumentError, match="leave the table"):
        order_response(model, src, [500.0, 2000.0], ["box.z"])


def test_two_orders_kept_apart_and_overall_rms():
    model = isolator()
    srcs = [Unbalance("crank", "box", 0.01, 0.05, axis="x"),
            OrderForce("2nd", "box", 2.0, rpm=1000.0, force=[0, 0, 5.0])]
    r = order_response(model, srcs, np.linspace(600, 3000, 50), ["box.z"])
    assert r.orders == (1.0, 2.0) and r.input_labels == ("order 1", "order 2")
    np.testing.assert_allclose(r.overall[0] ** 2, 0.5 * (np.abs(r.response[0, 0]) ** 2 + np.abs(r.response[1, 0]) ** 2),
                               rtol=1e-14)
    df = r.to_pandas()
    assert df.shape == (50, 2) and df.attrs["units"] == {"by output": {"box.z": "m"}}
    assert r.to_json()


def test_run_up_matches_solve_ivp():
    """A run-up 600 -> 3000 rpm in 4 s through the 10.1 Hz bounce: the sampled-load exact modal path
    against solve_ivp (rtol 1e-10) of m z'' + c z' + k z = F_z(t), the z component of the unbalance
    load written out from the mass's path."""
    model = isolator()
    mu, e, T, r0, r1 = 0.02, 0.05, 4.0, 600.0, 3000.0
    ub = Unbalance("fan", "box", mu, e, axis="x")
    tr = run_up(model, ub, r0, r1, T, ["box.z"], points_per_cycle=200)
    a = 2 * np.pi / 60 * (r1 - r0) / T

    def load_z(t):
        th = 2 * np.pi / 60 * (r0 * t + 0.5 * (r1 - r0) * t * t / T)
        om = 2 * np.pi / 60 * (r0 + (r1 - r0) * t / T)
        # the mass moves on r = e (u cos th + v sin th), u = x cross z = -y, v = x cross u = -z; the
        # shaft carries -m r'' = m e (th'^2 (u cos th + v sin th) + th'' (u sin th - v cos th)):
        # z component m e (-th'^2 sin th + th'' cos th)
        return mu * e * (-(om ** 2) * np.sin(th) + a * np.cos(th))

    sol = solve_ivp(lambda t, y: [y[1], (load_z(t) - C * y[1] - K * y[0]) / M], (0, T), [0.0, 0.0],
                    t_eval=tr.time, rtol=1e-10, atol=1e-14, method="DOP853")
    z = tr["box.z"]
    scale = np.abs(sol.y[0]).max()
    err = np.abs(z - sol.y[0]).max() / scale
    assert err <= 3e-5                           # measured 1.2e-5: the load sampled 200 x per cycle
    # the error is the piecewise-linear load's: second order in the step
    coarse = run_up(model, ub, r0, r1, T, ["box.z"], points_per_cycle=100)
    sol2 = solve_ivp(lambda t, y: [y[1], (load_z(t) - C * y[1] - K * y[0]) / M], (0, T), [0.0, 0.0],
                     t_eval=coarse.time, rtol=1e-10, atol=1e-14, method="DOP853")
    assert 3.5 <= (np.abs(coarse["box.z"] - sol2.y[0]).max() / scale) / err <= 4.5
    # the run-up's peak comes after the steady-state critical speed (the resonance lags the sweep)
    fn = np.sqrt(K / M) / (2 * np.pi)
    t_peak = tr.time[np.argmax(np.abs(z))]
    assert r0 + (r1 - r0) * t_peak / T > 60 * fn


def test_bad_sources_named():
    model = isolator()
    with pytest.raises(ModelError, match="unknown body 'bx'"):
        order_response(model, Unbalance("u", "bx", 1.0, 0.1), [1000.0])
    with pytest.raises(ArgumentError, match="mass"):
        Unbalance("u", "box", -1.0, 0.1)
    with pytest.raises(ArgumentError, match="axis"):
        Unbalance("u", "box", 1.0, 0.1, axis="w")
    with pytest.raises(ArgumentError, match="force=, moment="):
        OrderForce("o", "box", 2.0, rpm=1000.0)
    with pytest.raises(ArgumentError, match="increasing"):
        order_response(model, Unbalance("u", "box", 1.0, 0.1), [2000.0, 1000.0])
    with pytest.raises(ArgumentError, match="unique"):
        order_response(model, [Unbalance("u", "box", 1.0, 0.1)] * 2, [1000.0])


def test_figures(tmp_path):
    model = vibss.load_example("powertrain")
    srcs = [OrderForce("2nd order torque", "powertrain", 2.0, rpm=[800, 6000], moment=[[60.0, 0, 0], [60.0, 0, 0]]),
            Unbalance("crank", "powertrain", 0.005, 0.05, axis="x")]
    r = order_response(model, srcs, np.linspace(800, 6000, 300), ["powertrain.z", "powertrain.rx", "mount.engine.fz"])
    r.plot().savefig(tmp_path / "cuts.png")
    r.campbell().savefig(tmp_path / "campbell.png")
    assert (tmp_path / "cuts.png").stat().st_size > 10_000


def test_orders_guide(capsys):
    """docs/analyses/orders.md runs and the numbers it quotes hold."""
    import re
    from pathlib import Path

    text = (ROOT / "docs/analyses/orders.md").read_text()
    scope: dict = {}
    for block in re.findall(r"```python\n(.*?)```", text, re.S):
        exec(compile(block, "orders.md", "exec"), scope)
    out = capsys.readouterr().out
    r = scope["r"]
    crit = r.critical_speeds()
    assert [c[1] for c in crit if c[0] == 1.0] == [1, 2, 3, 4, 5, 6]
    assert max(c[3] for c in crit if c[0] == 1.0) == pytest.approx(782, abs=1)
    assert "285.5 N at most" in out
    a = np.abs(r["mount.engine.fz", "order 2"])
    assert a[np.searchsorted(r.rpm, 800)] == pytest.approx(17.7, abs=0.05)
    assert "peak engine-mount force at" in out
    assert "[652.3 619.9]" in out                   # the snubbered body's turning speeds (harmonic balance)


ORDERS = '''
[orders]
rpm = [300.0, 3000.0]
points = 200
outputs = ["powertrain.rx", "mount.engine.fz"]

[[orders.unbalance]]
name = "crank"
body = "powertrain"
mass = 0.005
radius = 50.0                           # mm
axis = "x"

[[orders.force]]
name = "2nd order torque"
body = "powertrain"
order = 2.0
rpm = [300.0, 6000.0]
moment = [[6.0e4, 0.0, 0.0], [6.0e4, 0.0, 0.0]]     # N mm
'''


def _powertrain_text():
    from vibss.io.modelfile import example_path

    return example_path("powertrain").read_text().split("\n[orders]")[0]     # without its own


def test_orders_table_read_in_file_units_and_written_back():
    model = vibss.loads_model(_powertrain_text() + ORDERS)
    spec = model.settings["orders"]
    assert spec["unbalance"][0]["radius"] == pytest.approx(0.05, rel=1e-15)
    assert spec["force"][0]["moment"][0] == pytest.approx([60.0, 0.0, 0.0], rel=1e-15)
    again = vibss.loads_model(vibss.dumps_model(model))
    assert again.settings["orders"] == spec


@pytest.mark.parametrize("bad, message", [
    ("[orders]\nrpm = [3000.0, 300.0]\n[[orders.unbalance]]\nname='u'\nbody='powertrain'\nmass=1.0\nradius=1.0\n",
     r"rpm: expected \[low, high\]"),
    ("[orders]\nrpm = [300.0, 3000.0]\n", r"no \[\[orders.unbalance\]\] or \[\[orders.force\]\] source"),
    ("[[orders.unbalance]]\nname='u'\nbody='powertrain'\nmass=1.0\n", r"unbalance\[1\] \('u'\): radius: missing"),
    ("[[orders.force]]\nname='f'\nbody='powertrain'\norder=2.0\nrpm=[1.0, 2.0]\n", r"force\[1\] \('f'\): give force, moment"),
    ("[[orders.force]]\nname='f'\nbody='powertrain'\norder=2.0\nrpm=[1.0, 2.0]\nforce=[[1.0, 2.0, 3.0]]\n",
     r"force: expected 3 numbers or a 2x3 array"),
])
def test_bad_orders_tables_located(bad, message):
    with pytest.raises(vibss.ModelFileError, match=message):
        vibss.loads_model(_powertrain_text() + bad, source="pt.toml")


def test_orders_command(tmp_path, capsys):
    from vibss.cli import main

    src = tmp_path / "pt.toml"
    src.write_text(_powertrain_text() + ORDERS)
    png = tmp_path / "cuts.png"
    assert main(["orders", str(src), "--format", "json", "--plot", str(png)]) == 0
    import json

    data = json.loads(capsys.readouterr().out)
    model = vibss.load_model(src)
    ref = order_response(model, [Unbalance("crank", "powertrain", 0.005, 0.05, axis="x"),
                                 OrderForce("2nd order torque", "powertrain", 2.0, rpm=[300, 6000],
                                            moment=[[60.0, 0, 0], [60.0, 0, 0]])],
                         np.linspace(300, 3000, 200), ["powertrain.rx", "mount.engine.fz"])
    np.testing.assert_allclose(data["outputs"]["mount.engine.fz"]["order 2"]["amplitude"],
                               np.abs(ref["mount.engine.fz", "order 2"]), rtol=1e-12)
    assert len(data["critical_speeds"]) == 8 and png.stat().st_size > 10_000
    assert main(["orders", "--example", "prism"]) == 2
    assert "no [orders] table" in capsys.readouterr().err


@pytest.mark.slow
def test_report_has_an_orders_section(tmp_path):
    from vibss.report import study, write_report

    model = vibss.loads_model(_powertrain_text() + ORDERS)
    rep = study(model, figures=True)
    sec = rep.section("orders")
    assert not sec.skipped and "Critical speeds" in sec.text and len(sec.figures) == 2
    ref = order_response(model, [Unbalance("crank", "powertrain", 0.005, 0.05, axis="x"),
                                 OrderForce("2nd order torque", "powertrain", 2.0, rpm=[300, 6000],
                                            moment=[[60.0, 0, 0], [60.0, 0, 0]])],
                         np.linspace(300, 3000, 200), ["powertrain.rx", "mount.engine.fz"])
    np.testing.assert_allclose(rep.results["orders"].response, ref.response, rtol=1e-12)
    write_report(dataclasses.replace(rep, sections=(sec,)), tmp_path / "out")      # its figures, not the others'
    assert (tmp_path / "out" / "campbell.png").exists() and (tmp_path / "out" / "orders.png").exists()
    assert study(vibss.load_example("prism"), figures=False).section("orders").skipped


def test_packaged_powertrain_orders():
    """The example's [orders] table: the 2nd-order vertical force table is 0.0258 kg m x w^2 at its
    speeds; above 600 rpm order 1 meets only modes 5 and 6 (10.8 Hz at 650 rpm, 13.0 Hz at 782 rpm)."""
    pt = vibss.load_example("powertrain")
    force = pt.settings["orders"]["force"][1]
    w = 2 * np.pi * 2 * np.array(force["rpm"]) / 60 / 2           # crank speed [rad/s]
    np.testing.assert_allclose([row[2] for row in force["force"]], 0.0258 * w ** 2, rtol=0.005)
    from vibss.orders.sources import sources_from_settings

    r = order_response(pt, sources_from_settings(pt), np.linspace(600, 6000, 100), ["powertrain.z"])
    assert [(c[0], c[1]) for c in r.critical_speeds()] == [(1.0, 5), (1.0, 6)]


def test_order_table_follows_a_power_law_exactly():
    """Between table speeds a column of positive amplitudes is interpolated log-log: a force
    c w^2 given at two speeds is exact at every speed between."""
    src = OrderForce("f", "box", 2.0, rpm=[1000.0, 4000.0], force=[[0, 0, 1.0], [0, 0, 16.0]])
    rpm = np.linspace(1000, 4000, 31)
    np.testing.assert_allclose(src.phasors(isolator(), rpm)[2].real, (rpm / 1000) ** 2, rtol=1e-13)
