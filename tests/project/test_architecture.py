"""docs/architecture.md stays true: its code runs, and its layer table names every module that
tests/project/test_api.py places in a layer, in the same layer."""

from __future__ import annotations

import re
import sys
from pathlib import Path

from cases import ROOT

sys.path.insert(0, str(Path(__file__).resolve().parent))   # test_api, beside this file
from test_api import LAYERS  # noqa: E402

DOC = ROOT / "docs" / "architecture.md"


def test_architecture_code_runs(capsys) -> None:
    for block in re.findall(r"```python\n(.*?)```", DOC.read_text(), re.S):
        scope: dict = {}
        exec(compile(block, "architecture.md", "exec"), scope)
    assert "skipped steady sweep(s) ['firing-torque']" in scope["r"].note
    assert capsys.readouterr().out.split()[-1] == "['firing-torque']"


def test_layer_table_matches_the_layering_test() -> None:
    rows = re.findall(r"^\| (\d+) \| (.*?) \|", DOC.read_text(), re.M)
    table = {int(n): {m.strip("`/").replace("/", ".") for m in re.findall(r"`[^`]+`", cells)}
             for n, cells in rows}
    assert sorted(table) == list(range(len(LAYERS))), "one row per layer of tests/project/test_api.py"
    for i, names in enumerate(LAYERS):
        missing = set(names) - table[i]
        assert not missing, f"docs/architecture.md layer {i} does not name {sorted(missing)}"
