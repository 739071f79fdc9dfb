"""``[analysis] harmonic_balance`` (issue 30, "Also"): the model-file key, the report's section and
``vibss frf`` on it.

Independent numbers: the file is written in mm and g (acceleration) and its amplitudes are converted
to SI here by hand (1 mm = 1e-3 m, 1 g = 9.80665 m/s^2); the report's and the command's numbers are
those of a direct :func:`vibss.harmonic_balance` call with them; at the start of the range, far below
the stop, the response is the one-DOF closed form ``|X| = m a / |k - m w^2 + i c w|``.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

import vibss
from vibss.cli import main
from vibss.errors import ModelFileError
from vibss.io.modelfile import dumps_model, loads_model
from vibss.report.study import study

FILE = """
[model]
name = "one body on a snubbered mount"
units = { length = "mm", mass = "kg", force = "N", acceleration = "g" }

[[body]]
name = "b"
mass = 10.0
inertia = [1e6, 1e6, 1e6]

[[mount_type]]
name = "snub"
stiffness = [40.0, 40.0, 40.0]                     # N/mm: 10 Hz
damping = [0.04, 0.04, 0.04]                       # N s/mm
stops = { z = { clearance = 1.0, stiffness = 40.0 } }

[[mount]]
name = "m"
type = "snub"
body = "b"

[[excitation]]
name = "shaker"
kind = "acceleration"
target = "ground"
dof = "z"
function = { type = "sine", amplitude = 0.05, frequency = 10.0 }

[analysis]
harmonic_balance = { inputs = { "shaker" = 0.05 }, outputs = ["b.z.rel", "mount.m.d3"], f1 = 5.0, f2 = 20.0, harmonics = 9, points = 40 }
"""

A_SI = 0.05 * 9.80665           # 0.05 g in m/s^2


def _direct() -> vibss.HarmonicBalanceResult:
    return vibss.harmonic_balance(loads_model(FILE), {"ground.z.acc": A_SI}, ["b.z.rel", "mount.m.d3"],
                                  frequencies=(5.0, 20.0), harmonics=9, points=40)


def test_the_key_reads_in_si_and_round_trips() -> None:
    model = loads_model(FILE)
    spec = model.settings["harmonic_balance"]
    assert spec["inputs"] == {"shaker": pytest.approx(A_SI, rel=1e-15)}
    assert (spec["f1"], spec["f2"], spec["harmonics"], spec["points"]) == (5.0, 20.0, 9, 40)
    for units in ("SI", {"length": "mm", "acceleration": "g"}):
        back = loads_model(dumps_model(model, units=units))
        assert back.settings["harmonic_balance"]["inputs"]["shaker"] == pytest.approx(A_SI, rel=1e-13)
        assert back.settings["harmonic_balance"]["outputs"] == ["b.z.rel", "mount.m.d3"]
    assert 'inputs = { shaker = 0.05 }' in dumps_model(model)        # written in the file's own units


@pytest.mark.parametrize("edit, match", [
    ("f1 = 5.0", "harmonic_balance: fl: unknown key"),
    ('"shaker" = 0.05', "inputs: shakr: neither an input signal"),
    ("f2 = 20.0", "f2: must be greater than f1"),
    ("harmonics = 9", "harmonics: expected a whole number >= 1"),
    ('outputs = ["b.z.rel", "mount.m.d3"], ', "f1: missing"),
])
def test_bad_keys_name_the_key(edit: str, match: str) -> None:
    bad = {"f1 = 5.0": "fl = 5.0", '"shaker" = 0.05': '"shakr" = 0.05', "f2 = 20.0": "f2 = 4.0",
           "harmonics = 9": "harmonics = 0", 'outputs = ["b.z.rel", "mount.m.d3"], ':
           'outputs = ["b.z.rel", "mount.m.d3"], fl = 1.0, '}[edit]
    text = FILE.replace(edit, bad)
    if edit.startswith("outputs"):
        text = text.replace("fl = 1.0, f1 = 5.0, ", "")
    with pytest.raises(ModelFileError, match=match):
        loads_model(text)


def test_report_section_equals_a_direct_call() -> None:
    rep = study(loads_model(FILE), figures=False)
    s = rep.section("harmonic")
    assert not s.skipped and not s.failed, s.note
    r, direct = rep.results["harmonic_balance"], _direct()
    assert r.turning_points.size == 2                      # a hardening fold
    np.testing.assert_allclose(r.turning_points, direct.turning_points, rtol=1e-12)
    np.testing.assert_allclose(r.amplitude, direct.amplitude, rtol=1e-12)
    folds = next(t for t in s.tables if "turning points" in t.title)
    assert [row[1] for row in folds.rows] == [f"{f:.6g}" for f in direct.turning_points]
    assert folds.rows[0][2] == "upward sweep jumps" and folds.rows[1][2] == "downward sweep jumps"
    w, m, k, c = 2 * np.pi * 5.0, 10.0, 4e4, 40.0        # far below the stop: the closed form
    assert r.amplitude[1, 0] == pytest.approx(m * A_SI / abs(k - m * w**2 + 1j * c * w), rel=1e-9)
    assert study(vibss.load_example("prism"), figures=False).section("harmonic").skipped


def test_vibss_frf_prints_the_files_harmonic_balance(tmp_path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "snub.toml"
    path.write_text(FILE)
    assert main(["frf", str(path), "--format", "json"]) == 0      # the file asks for one: the default
    out = json.loads(capsys.readouterr().out)
    np.testing.assert_allclose(out["turning_points"], _direct().turning_points, rtol=1e-12)
    assert main(["frf", str(path), "--harmonic-balance", "--f2", "25", "--save", str(tmp_path / "hb.csv")]) == 0
    assert "upward sweep jumps" in capsys.readouterr().out
    rows = (tmp_path / "hb.csv").read_text().splitlines()
    assert rows[0] == "frequency [Hz],b.z.rel,mount.m.d3,stable" and float(rows[-1].split(",")[0]) == pytest.approx(25.0)
    assert main(["frf", "--example", "prism", "--harmonic-balance"]) != 0     # no table: a clear error
    assert "no [analysis] harmonic_balance table" in capsys.readouterr().err
