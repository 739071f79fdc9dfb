"""The Python blocks of the "Model updating" section of docs/analyses/test-data.md run, and the
numbers the text quotes are what they print."""

from __future__ import annotations

import re

import numpy as np

import vibss
from cases import ROOT


def test_model_updating_guide(capsys):
    text = (ROOT / "docs" / "analyses" / "test-data.md").read_text()
    section = text.split("## Model updating\n")[1].split("\n## ")[0]
    scope: dict = {"np": np, "vibss": vibss}
    for block in re.findall(r"```python\n(.*?)```", section, re.S):
        exec(compile(block, "test-data.md", "exec"), scope)
    out = capsys.readouterr().out
    quoted = re.findall(r"(\d+) \+- (\d+) N/m", out)
    assert len(quoted) == 4
    assert ", ".join(f"{v} ± {s}" for v, s in quoted[:2]) in section.replace("\n", " ")
    assert all(abs(int(v) - t) < 3 * int(s) for (v, s), t in zip(quoted, (20000, 30000, 25000, 35000)))
    before, after = re.search(r"FRAC of c.z/b.fz: ([\d.]+) before, ([\d.]+) after", out).groups()
    assert f"from {before} to" in section.replace("\n", " ") and f"to {after}" in section.replace("\n", " ")
    assert "from modes: [20000.0, 30000.0, 25000.0, 35000.0]" in out
