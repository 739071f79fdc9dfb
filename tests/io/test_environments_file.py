"""``[shock]`` and ``[random]`` tables, ``vibss srs`` and ``vibss random``."""

from __future__ import annotations

import json

import numpy as np
import pytest

import vibss
from vibss.cli import main
from vibss.errors import ModelError
from vibss.io.modelfile import dumps_model, load_example, loads_model
from vibss.model.units import STANDARD_GRAVITY

SDOF = """
[model]
units = {{ acceleration = "g" }}
[[body]]
name = "m"
mass = 1.0
inertia = [1, 1, 1]
[[mount_type]]
name = "k"
stiffness = [{k}, {k}, {k}]
damping = [{c}, {c}, {c}]
[[mount]]
type = "k"
body = "m"
[random]
input = "ground.z.acc"
psd = {{ frequency = [1.0, 10000.0], level = [0.04, 0.04] }}
outputs = ["m.z.acc"]
"""


def test_random_table_gives_the_exact_sdof_rms(tmp_path, capsys) -> None:
    """Flat base PSD W0 on a single-DOF isolator: RMS absolute acceleration sqrt((pi/2) fn W0 (Q + 1/Q));
    7.9662 g at fn = 100 Hz, Q = 10, W0 = 0.04 g^2/Hz (the band 1 .. 10,000 Hz leaves out < 1e-3 of it)."""
    w = 2 * np.pi * 100.0
    path = tmp_path / "sdof.toml"
    path.write_text(SDOF.format(k=w * w, c=w / 10.0))
    assert main(["random", str(path), "--format", "json"]) == 0
    data = json.loads(capsys.readouterr().out)
    rms_g = data["outputs"]["m.z.acc"]["rms"] / STANDARD_GRAVITY
    assert rms_g == pytest.approx(np.sqrt(np.pi / 2 * 100 * 0.04 * (10 + 0.1)), rel=1e-3)


def test_shock_table_runs_and_checks_its_spec(capsys) -> None:
    m = load_example("packaged_item")
    assert m.settings["shock"]["spec"]["level"][0] == pytest.approx(100.0)          # 100,000 mm/s^2 in SI
    assert main(["srs", "--example", "packaged_item", "--format", "json"]) == 0
    data = json.loads(capsys.readouterr().out)
    check = data["checks"]["ground.z.acc"]
    assert check["passed"]
    # the input's spectrum is the SRS of the file's pulse, independently sampled
    t = np.arange(0.0, 0.2, 1e-5)
    pulse = np.where(t < 0.011, 490.5 * np.sin(np.pi * t / 0.011), 0.0)
    f = np.array(data["spectra"]["ground.z.acc"]["frequency_hz"])
    ref = vibss.srs(t, pulse, f[[0, 20, 40]], q=10.0)
    got = np.array(data["spectra"]["ground.z.acc"]["response"])[[0, 20, 40]]
    np.testing.assert_allclose(got, ref.response, rtol=2e-3)
    assert main(["srs", "--example", "prism"]) == 2
    assert "no [shock] table" in capsys.readouterr().err


def test_tables_round_trip_and_bad_entries() -> None:
    for name in ("packaged_item", "ground_shake"):
        m = load_example(name)
        again = loads_model(dumps_model(m))
        for key in ("shock", "random"):
            assert again.settings.get(key) == m.settings.get(key)
    base = SDOF.format(k=1e4, c=10.0)
    for bad, msg in ((base.replace('input = "ground.z.acc"\n', ''), r"\[random\].*input"),
                     (base.replace("[1.0, 10000.0]", "[10.0, 1.0]"), r"psd: frequency.*increasing"),
                     (base.replace("level = [0.04, 0.04]", "level = [0.04]"), r"psd: level"),
                     (base + '[shock]\nexcitation = "x"\nq = 0.2\n', r"\[shock\].*q.*> 0.5")):
        with pytest.raises(ModelError, match=msg):
            loads_model(bad)
