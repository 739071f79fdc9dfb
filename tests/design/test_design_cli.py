"""``vibss design``: certificate, optimisation with the model written, tolerance study, JSON."""

from __future__ import annotations

import json

import numpy as np

import vibss
from vibss.cli import main
from vibss.design import certificate


def test_certificate_text_and_json(capsys):
    assert main(["design", "--example", "powertrain", "--frame", "tra", "--window", "5", "18.9"]) == 0
    out = capsys.readouterr().out
    assert "Decoupling certificate" in out and "FAILED" in out
    assert main(["design", "--example", "powertrain", "--frame", "global", "--format", "json"]) == 0
    data = json.loads(capsys.readouterr().out)
    expected = certificate(vibss.load_example("powertrain"))
    np.testing.assert_allclose(data["ke_matrix"], expected.ke_matrix, atol=1e-12)


def test_optimise_writes_a_better_model_and_checks_tolerances(tmp_path, capsys):
    path = tmp_path / "opt.toml"
    assert main(["design", "--example", "powertrain", "--frame", "tra", "--window", "5", "18.9",
                 "--optimize", "--output", str(path), "--tolerance", "0.15", "--samples", "500"]) == 0
    out = capsys.readouterr().out
    assert "Optimised layout" in out and "Tolerance study" in out
    before = certificate(vibss.load_example("powertrain"), frame="tra")
    after = certificate(vibss.load_model(path), frame="tra")
    assert after.purity.mean() > before.purity.mean() + 0.1


def test_study_command_csv_and_json(capsys):
    import io

    import pandas as pd

    assert main(["study", "--example", "powertrain", "--vary", "engine.k3=2e5,3e5", "--vary", "gearbox.z=0,0.01",
                 "--analysis", "certificate"]) == 0
    df = pd.read_csv(io.StringIO(capsys.readouterr().out), index_col="variant")
    direct = vibss.grid_study(vibss.load_example("powertrain"), "certificate",
                         grid={"engine.k3": [2e5, 3e5], "gearbox.z": [0.0, 0.01]})
    np.testing.assert_allclose(df["purity6"], direct["purity6"], rtol=1e-12)
    assert main(["study", "--example", "powertrain", "--vary", "engine.k3=2e5", "--format", "json"]) == 0
    assert json.loads(capsys.readouterr().out)[0]["engine.k3"] == 2e5
    assert main(["study", "--example", "powertrain", "--vary", "engine.k3=a"]) == 2
