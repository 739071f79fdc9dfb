"""docs/analyses/design.md: its Python blocks run, and the numbers it quotes hold."""

from __future__ import annotations

import re

import matplotlib
import pytest
from cases import ROOT

matplotlib.use("Agg")

DOCS = ROOT / "docs"


@pytest.mark.slow
def test_design_guide(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)               # the guide writes powertrain-optimised.toml
    scope: dict = {}
    for block in re.findall(r"```python\n(.*?)```", (DOCS / "analyses/design.md").read_text(), re.S):
        exec(compile(block, "design.md", "exec"), scope)
    out = capsys.readouterr().out
    assert "TRA [ 0.995  0.016 -0.099]; static roll axis 11.5 deg off it" in out
    assert "no elastic centre: a torque gives a screw (rotation plus translation along the axis)" in out
    assert "min purity 0.51 -> 0.92" in out
    assert "P(all six modes >= 90 % pure and in window) = 0.28" in out
    assert "P(all targets) 0.28 -> 0.75" in out
    assert (tmp_path / "powertrain-optimised.toml").exists()
    cert, opt = scope["cert"], scope["opt"]
    assert cert.purity[5] == pytest.approx(0.60, abs=0.005) and cert.frequency_hz[5] == pytest.approx(13.0, abs=0.05)
    assert sorted(cert.purity.round(2))[:3] == [0.51, 0.6, 0.75]
    assert opt.evaluations == 72 and all(opt.after.in_window) and opt.after.purity.min() >= 0.9
    assert scope["df"]["error"].isna().all()
    rel = scope["reliable"].reliability
    assert rel.deterministic.probability["window 1"] == pytest.approx(0.50, abs=0.03)
    assert rel.reliable.probability["window 1"] >= 0.95 and rel.reliable.probability["all"] > 0.5
    assert "(6, 2)" in out
