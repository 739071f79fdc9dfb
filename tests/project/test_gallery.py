"""docs/gallery.md is in step with the examples and the report: every example with its command and
description, every figure the report of that example draws today shown (by name), every image file
present and non-trivial — without redrawing the images (docs/make_gallery.py does that)."""

from __future__ import annotations

import importlib.util
import re

import matplotlib
import pytest

from cases import ROOT
import vibss
from vibss.commands.example import describe

matplotlib.use("Agg")
DOCS = ROOT / "docs"
spec = importlib.util.spec_from_file_location("make_gallery", DOCS / "make_gallery.py")
make_gallery = importlib.util.module_from_spec(spec)
spec.loader.exec_module(make_gallery)


@pytest.mark.parametrize("name", vibss.example_names())
@pytest.mark.slow
def test_gallery_entry_is_current(name):
    text = (DOCS / "gallery.md").read_text(encoding="utf-8")
    title, description = describe(name)
    _, sections = make_gallery.report_figures(name)
    expected = make_gallery.page([(name, title, description, sections)])
    entry = expected.split(f'<a id="{name}"></a>', 1)[1]
    assert entry in text, f"docs/gallery.md is stale for {name!r}: run python docs/make_gallery.py"
    for _, figures in sections:
        for fig in figures:
            assert (DOCS / "gallery" / name / fig).stat().st_size > 2_000


def test_gallery_has_nothing_extra():
    text = (DOCS / "gallery.md").read_text(encoding="utf-8")
    shown = set(re.findall(r"\]\(gallery/([^)]+)\)", text))
    on_disk = {str(p.relative_to(DOCS / "gallery")) for p in (DOCS / "gallery").rglob("*.png")}
    assert shown == on_disk
    assert re.findall(r'<a id="([^"]+)"></a>', text) == vibss.example_names()
