"""The ``[design]`` and ``[study]`` tables of a model file: read in the file's units, written back,
refused with a located message when wrong, and run by ``vibss design FILE`` / ``vibss study FILE``;
``study(scheduler=address)`` on a running Dask scheduler."""

from __future__ import annotations

import io

import numpy as np
import pytest

import vibss
from vibss.cli import main
from vibss.design import certificate
from vibss.design.parameters import apply, parameters_of
from vibss.errors import ArgumentError, ModelFileError

DESIGN = '''
[design]
purity = 0.85
frame = "tra"
windows = [5.0, 18.9]
modes = ["rx", 3]
max_sag = 4.0                 # mm
samples = 300
sampling = "sobol"
[design.variables]
"engine.k3" = [150.0, 400.0]  # N/mm
"engine.k1/k3" = [0.2, 0.6]
"gearbox.rx" = [-10.0, 10.0]  # deg
[design.catalogue]
"engine.k3" = [200.0, 250.0, 300.0]
[design.tolerances]
"engine.k3" = 0.15
"gearbox.z" = 2.0             # mm, absolute
'''

STUDY = '''
[study]
analysis = "modes"
[study.grid]
"engine.k3" = [200.0, 300.0]  # N/mm
"gearbox.z" = [0.0, 10.0]     # mm
'''


@pytest.fixture(scope="module")
def text():
    from vibss.io.modelfile import example_path

    # the packaged powertrain without its own [design] table (tested on its own below)
    return example_path("powertrain").read_text().split("\n[design]")[0]


def test_design_table_read_in_file_units(text):
    model = vibss.loads_model(text + DESIGN)
    d = model.settings["design"]
    assert d["variables"]["engine.k3"] == pytest.approx([1.5e5, 4.0e5], rel=1e-15)      # N/mm -> N/m
    assert d["variables"]["engine.k1/k3"] == [0.2, 0.6]
    assert d["variables"]["gearbox.rx"] == pytest.approx(np.radians([-10.0, 10.0]), rel=1e-15)
    assert d["catalogue"]["engine.k3"] == pytest.approx([2e5, 2.5e5, 3e5], rel=1e-15)
    assert d["tolerances"] == pytest.approx({"engine.k3": 0.15, "gearbox.z": 2e-3}, rel=1e-15)
    assert d["max_sag"] == pytest.approx(4e-3, rel=1e-15)
    assert (d["purity"], d["frame"], d["modes"], d["samples"]) == (0.85, "tra", ["rx", 3], 300)


def test_tables_survive_a_round_trip(text):
    model = vibss.loads_model(text + DESIGN + STUDY)
    again = vibss.loads_model(vibss.dumps_model(model))
    assert again.settings["design"] == model.settings["design"]
    assert again.settings["study"] == model.settings["study"]
    again = vibss.loads_model(vibss.dumps_model(model, "json"), "json")
    assert again.settings["study"] == model.settings["study"]


@pytest.mark.parametrize("bad, message", [
    ('[design]\nwindow = [1, 2]\n', r"\[design\]: window: unknown key.*did you mean 'windows'"),
    ('[design.variables]\n"engine.k3" = [400.0, 150.0]\n', r"engine.k3.*lower < upper"),
    ('[design.variables]\n"engine.k3" = [150.0]\n', r"engine.k3: expected 2 numbers \[N/mm\]"),
    ('[design.catalogue]\n"engine.k3" = [200.0]\n', r"catalogue: 'engine.k3' is not in \[design.variables\]"),
    ('[design]\npurity = 90\n', r"purity: expected a fraction"),
    ('[design]\nmodes = ["roll"]\n', r"modes: expected a list of mode numbers"),
    ('[study.grid]\n"engine.k3" = [1.0]\n[study.table]\n"engine.k3" = [1.0]\n', r"exactly one of"),
    ('[study.table]\n"engine.k3" = [1.0, 2.0]\n"gearbox.z" = [1.0]\n', r"same length"),
    ('[study]\nanalysis = "mode"\n[study.grid]\n"engine.k3" = [1.0]\n', r"did you mean 'modes'"),
])
def test_bad_tables_are_located(text, bad, message):
    with pytest.raises(ModelFileError, match=message):
        vibss.loads_model(text + bad, source="pt.toml")


def test_design_command_uses_the_file(text, tmp_path, capsys):
    src, out = tmp_path / "pt.toml", tmp_path / "opt.toml"
    src.write_text(text + DESIGN)
    assert main(["design", str(src), "--format", "json"]) == 0
    import json

    data = json.loads(capsys.readouterr().out)
    expected = certificate(vibss.load_model(src), purity=0.85, frame="tra", windows=(5.0, 18.9))
    np.testing.assert_allclose(data["ke_matrix"], expected.ke_matrix, atol=1e-12)
    assert main(["design", str(src), "--optimize", "--output", str(out), "--tolerance"]) == 0
    text_out = capsys.readouterr().out
    assert "engine.k1/k3" in text_out and "gearbox.rx" in text_out and "Tolerance study" in text_out
    assert "300 variants (sobol" in text_out
    k = {m.name: m.type.stiffness for m in vibss.load_model(out).mounts}["engine"]
    assert np.isclose(k[2], [2e5, 2.5e5, 3e5], rtol=1e-12).any(), k         # a catalogue value
    assert 0.2 - 1e-9 <= k[0] / k[2] <= 0.6 + 1e-9


def test_tolerance_without_value_needs_the_table(capsys):
    assert main(["design", "--example", "prism", "--tolerance"]) == 2
    assert "[design.tolerances]" in capsys.readouterr().err


def test_study_command_uses_the_file(text, tmp_path, capsys):
    import pandas as pd

    src = tmp_path / "pt.toml"
    src.write_text(text + STUDY)
    assert main(["study", str(src)]) == 0
    df = pd.read_csv(io.StringIO(capsys.readouterr().out), index_col="variant")
    base = vibss.load_model(src)
    params = parameters_of(base, ["engine.k3", "gearbox.z"])
    assert len(df) == 4
    for _, row in df.iterrows():
        ref = vibss.modes(apply(base, params, [row["engine.k3"], row["gearbox.z"]])).frequency_hz
        np.testing.assert_allclose(row[[f"f{i}_hz" for i in range(1, 7)]].to_numpy(float), ref, rtol=1e-12)
    assert sorted(set(df["engine.k3"])) == pytest.approx([2e5, 3e5]) and sorted(set(df["gearbox.z"])) == [0.0, 0.01]
    assert main(["study", "--example", "powertrain"]) == 2
    assert "nothing to vary" in capsys.readouterr().err


def test_scheduler_address_equals_in_process():
    distributed = pytest.importorskip("distributed")
    pt = vibss.load_example("powertrain")
    grid = {"engine.k3": [2e5, 3e5], "gearbox.z": [0.0, 0.01]}
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster:
        remote = vibss.grid_study(pt, grid=grid, scheduler=cluster.scheduler_address)
    import pandas as pd

    pd.testing.assert_frame_equal(remote, vibss.grid_study(pt, grid=grid))
    with pytest.raises(ArgumentError, match="client= or scheduler="):
        vibss.grid_study(pt, grid=grid, client="local", scheduler="tcp://127.0.0.1:1")


def test_packaged_powertrain_design_passes_after_optimisation(capsys):
    """The example's [design] table (15 variables, windows 5-18.88 Hz in TRA axes): the optimised
    layout's certificate, recomputed from the written model file, passes every target."""
    from vibss.design.filespec import design_spec, run_design

    pt = vibss.load_example("powertrain")
    spec = design_spec(pt)
    assert len(spec.variables) == 15 and spec.frame == "tra" and spec.windows == [5.0, 18.88]
    run = run_design(pt, tolerance=False)
    assert not run.certificate.passed
    again = vibss.loads_model(vibss.dumps_model(run.optimization.model))
    after = certificate(again, purity=0.9, frame="tra", windows=(5.0, 18.88))
    assert after.passed and after.purity.min() >= 0.9 - 1e-9
