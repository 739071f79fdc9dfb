"""Issue 30: the operating point in `vibss static` and the report, and the linear sections and
commands on the tangent model, for the example with snubbers (vibss/examples/snubbed_cabinet.toml).

Independent numbers: the vertical sag solves ``F(d) = m g / 4`` on the isolator's curve, built here
with scipy's PchipInterpolator from the same points and solved with brentq (not vibss's Newton);
the tangent rate is that interpolant's slope there; the clearance left is the 4 mm compression
clearance minus the sag.
"""

from __future__ import annotations

import json
from functools import lru_cache

import numpy as np
import pytest
from scipy.interpolate import PchipInterpolator
from scipy.optimize import brentq

import vibss
from vibss.cli import main
from vibss.report.section import Report
from vibss.report.study import study

POINTS = np.array([[-4.0, -300.0], [-3.0, -210.0], [-2.0, -125.0], [-1.0, -60.0], [0.0, 0.0], [1.0, 60.0],
                   [2.0, 120.0], [4.0, 240.0]])        # mm, N: the file's curve


def sag_mm() -> tuple[float, float]:
    """The isolator's compression [mm] under a quarter of the cabinet's weight, and its rate [N/mm]."""
    curve = PchipInterpolator(POINTS[:, 0], POINTS[:, 1])
    d = brentq(lambda x: curve(x) + 40.0 * 9.81 / 4, -3.9, 0.0, xtol=1e-14)
    return float(d), float(curve.derivative()(d))


def test_vibss_static_shows_the_operating_point(capsys: pytest.CaptureFixture[str]) -> None:
    d, k = sag_mm()
    assert main(["static", "--example", "snubbed_cabinet", "--format", "json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["static"]["bodies"]["cabinet"]["deflection"][2] == pytest.approx(d * 1e-3, rel=1e-7)
    assert out["clearance"]["foot.z"] == pytest.approx((4.0 + d) * 1e-3, rel=1e-7)
    assert main(["static", "--example", "snubbed_cabinet"]) == 0
    text = capsys.readouterr().out
    assert "Tangent rates at the operating point" in text and f"{k * 1e3:.4g}" in text
    assert "Stops at the operating point" in text and f"{4.0 + d:.3f}" in text


@lru_cache(maxsize=1)
def cabinet_report() -> Report:
    """The example's report without figures, made once for the two tests that read it (14 s each)."""
    return study(vibss.load_example("snubbed_cabinet"), figures=False)


def test_the_report_linearises_the_linear_sections_and_says_so() -> None:
    rep = cabinet_report()
    static = rep.section("static")
    assert any(t.title == "Tangent rates at the operating point" for t in static.tables)
    for key in ("damped", "frequency"):
        s = rep.section(key)
        assert not s.skipped and "tangent model at the operating point" in s.note, key
    d, k = sag_mm()
    op = rep.results["operating_point"]
    kz = {m.name: m.type.stiffness[2] for m in op.tangent.mounts}
    assert kz["foot"] == pytest.approx(k * 1e3, rel=1e-6)


def test_linear_commands_analyse_the_tangent_model(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["frf", "--example", "snubbed_cabinet", "--input", "cabinet.fz", "--output", "cabinet.z",
                 "--format", "json"]) == 0
    captured = capsys.readouterr()
    assert "nonlinear mounts: analysing the tangent model" in captured.err
    out = json.loads(captured.out)
    _, k = sag_mm()
    low = out["outputs"]["cabinet.z"]["amplitude"][0]        # at 1 Hz, well below the 12.8 Hz bounce: ~ 1 / k
    f0 = np.sqrt(4 * k * 1e3 / 40.0) / (2 * np.pi)
    quasi_static = 1.0 / (4 * k * 1e3) / (1 - (out["frequency_hz"][0] / f0) ** 2)
    assert out["outputs"]["cabinet.z"]["unit"] == "m/N"
    assert low == pytest.approx(quasi_static, rel=1e-2)           # damping shifts it by ~0.1 %


def test_a_shock_into_the_snubbers_of_a_symmetric_cabinet_is_located_quickly() -> None:
    """Its lateral axes stay at rest by symmetry: their round-off peaks (1e-20 m) once failed the
    step-doubling check relative to themselves, and auto refined to thousands of steps per sample.
    Independent number: the base's 30 g half-sine of 11 ms leaves it moving at 2 A T / pi."""
    import time

    m = vibss.load_example("snubbed_cabinet")
    t0 = time.perf_counter()
    r = vibss.simulate(m, list(m.excitations), outputs=["cabinet.z.rel", "cabinet.x.rel"], t_end=0.05, dt=2e-4)
    assert time.perf_counter() - t0 < 60                     # a hang guard, not a benchmark
    assert r.method == "nonlinear_modal" and np.abs(r["cabinet.x.rel"]).max() < 1e-12
    text = r.contacts.table.render()
    assert "foot" in text and " z " in f" {text} "


def test_the_report_lists_the_stop_contacts() -> None:
    rep = cabinet_report()
    s = rep.section("time")
    assert not s.skipped and any(t.title == "stop contacts" for t in s.tables)
    assert "stop contacts" in s.text and "foot" in s.text
