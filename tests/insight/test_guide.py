"""docs/analyses/insight.md: its Python blocks run and print the tables quoted under them."""

from __future__ import annotations

import re

from cases import ROOT

GUIDE = ROOT / "docs" / "analyses" / "insight.md"


def test_insight_guide_prints_what_it_quotes(capsys):
    text = GUIDE.read_text()
    scope: dict = {}
    for block in re.findall(r"```python\n(.*?)```", text, re.S):
        exec(compile(block, "insight.md", "exec"), scope)
    out = capsys.readouterr().out
    quoted = re.findall(r"```text\n(.*?)```", text, re.S)
    assert len(quoted) == 5
    for q in quoted:
        assert q.strip() in out
