"""Write docs/gallery.md and its figures (docs/gallery/<example>/*.png): every built-in example run
through ``vibss report``, with the command that made it and every figure the report draws.

Run ``python docs/make_gallery.py`` (about a minute); ``tests/project/test_gallery.py`` checks that the page
lists every example with its command and that every figure it shows exists and is what the report
of that example draws today (by name), without drawing them again.
"""

from __future__ import annotations

import shutil
import sys
from pathlib import Path

DOCS = Path(__file__).parent
OUT = DOCS / "gallery.md"
FIGURES = DOCS / "gallery"
DPI = 60
"""Small images: the gallery is for browsing; ``vibss report`` writes them at 110 dpi."""


def page(entries: list[tuple[str, str, str, list[tuple[str, list[str]]]]]) -> str:
    """The Markdown page: ``(example, title, description, [(section title, [figure names])])``."""
    lines = ["# Gallery", "",
             "Every built-in example, run through `vibss report` (the same figures as the HTML report,",
             "at lower resolution). Regenerate with `python docs/make_gallery.py`.", "",
             "The HTML report's interactive 3-D mode viewer (a two-body model, as headless Chromium draws it;",
             "`VIBSS_KEEP_SCREENSHOT=1 pytest tests/report/test_browser.py` renews it):", "",
             "![the report's 3-D mode viewer](figures/report_viewer.png)", ""]
    lines += [f"- [{title}](#{name})" for name, title, _, _ in entries]
    for name, title, text, sections in entries:
        lines += ["", f'<a id="{name}"></a>', "", f"## {title}", "", text, "",
                  "```console", f"$ vibss report --example {name}", "```", ""]
        for section, figures in sections:
            lines.append(f"**{section}**")
            lines.append("")
            lines += [f"![{name}: {fig}](gallery/{name}/{fig})" for fig in figures]
            lines.append("")
    return "\n".join(lines).rstrip() + "\n"


def report_figures(name: str, figures: bool = True) -> tuple[object, list[tuple[str, list[str]]]]:
    """The report of example ``name`` and its figure names by section title."""
    import vibss
    from vibss.report import study

    rep = study(vibss.load_example(name), figures=figures)
    return rep, [(s.title, [f for f, _ in s.figures]) for s in rep.sections if s.figures]


def _shrink(folder: Path) -> None:
    """Quantise the PNGs to 128 colours (about a third of the bytes, no visible change at 60 dpi)."""
    from PIL import Image

    for png in folder.glob("*.png"):
        with Image.open(png) as im:
            small = im.convert("RGB").quantize(colors=128, method=Image.Quantize.MEDIANCUT)
        small.save(png, optimize=True)


def main() -> None:
    import vibss
    from vibss.commands.example import describe
    from vibss.report import render_report

    entries = []
    if FIGURES.exists():
        shutil.rmtree(FIGURES)
    for name in vibss.example_names():
        title, text = describe(name)
        rep, sections = report_figures(name)
        folder = FIGURES / name
        _, written = render_report(rep, folder, dpi=DPI)
        for extra in ("index.html", "report.txt"):
            (folder / extra).unlink()
        _shrink(folder)
        if written.failed:
            sys.exit(f"make_gallery: {name}: sections failed: {written.failed}")
        entries.append((name, title, text, sections))
        print(f"{name}: {sum(len(f) for _, f in sections)} figures", file=sys.stderr)
    OUT.write_text(page(entries), encoding="utf-8")
    print(f"wrote {OUT}", file=sys.stderr)


if __name__ == "__main__":
    main()
