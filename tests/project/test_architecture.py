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


def _defined(path: Path) -> set[str]:
    """Top-level names a module defines (functions, classes, assignments, imports) and ``Class.attr``."""
    import ast

    out: set[str] = set()
    for node in ast.parse(path.read_text()).body:
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            out.add(node.name)
            if isinstance(node, ast.ClassDef):
                out |= {f"{node.name}.{n.name}" for n in node.body if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef))}
                out |= {f"{node.name}.{t.id}" for n in node.body if isinstance(n, ast.AnnAssign)
                        for t in [n.target] if isinstance(t, ast.Name)}
        elif isinstance(node, (ast.Assign, ast.AnnAssign)):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            out |= {t.id for t in targets if isinstance(t, ast.Name)}
        elif isinstance(node, (ast.Import, ast.ImportFrom)):
            out |= {a.asname or a.name.split(".")[0] for a in node.names}
    return out


def test_fact_table_names_existing_functions() -> None:
    """Every row of "Where each fact lives" names files that exist, and every name it gives in
    backticks beside a file is defined there (a moved or renamed function fails here)."""
    section = DOC.read_text().split("## Where each fact lives", 1)[1].split("\n## ", 1)[0]
    rows = [line for line in section.splitlines() if line.startswith("| ") and not line.startswith("| fact")]
    assert len(rows) > 20
    checked = 0
    for row in rows:
        where = row.rsplit("|", 2)[-2]
        # each file, then the backticked names in the parentheses that follow it
        for path, names in re.findall(r"`((?:vibss|benchmarks)/[\w/]+(?:\.py)?/?)`(?:\s*\(([^)]*)\))?", where):
            target = ROOT / path
            assert target.exists(), f"{path} (row: {row[:60]}...) does not exist"
            if target.suffix != ".py":
                continue
            defined = _defined(target)
            for name in re.findall(r"`([A-Za-z_][\w.]*)`", names or ""):
                if "/" in name or name.count(".") > 1:
                    continue
                assert name in defined, f"{path} defines no {name!r} (row: {row[:60]}...)"
                checked += 1
    assert checked > 20
