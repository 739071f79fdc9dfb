"""The report as files: PNG figures, one self-contained ``index.html`` (figures embedded as base64)
and ``report.txt``."""

from __future__ import annotations

import base64
import dataclasses
import datetime
import html
import re
from pathlib import Path
from typing import Any

from ..results import TextTable
from .section import Report
from .viewer import ERROR_HOOK, VIEWER_CSS, viewer_html

__all__ = ["html_table", "write_report", "render_report"]

_NUMBER = re.compile(r"^[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$")


def html_table(table: TextTable, shade_from: int | None = None) -> str:
    """An HTML ``<table>`` of a :class:`~vibss.results.TextTable` (numbers right-aligned).

    Parameters
    ----------
    table : TextTable
        The table.
    shade_from : int or None
        Shade numeric cells from this column on by their value as a percentage (energy tables).
    """
    out = ["<table>"]
    if table.title:
        out.append(f"<caption>{html.escape(table.title)}</caption>")
    out.append("<thead><tr>" + "".join(f"<th>{html.escape(h)}</th>" for h in table.header) + "</tr></thead>")
    out.append("<tbody>")
    for row in table.rows:
        cells = []
        for j, c in enumerate(row):
            num = bool(_NUMBER.match(c.strip()))
            style = ""
            if shade_from is not None and j >= shade_from and num:
                v = min(max(float(c) / 100.0, 0.0), 1.0)
                style = f' style="background: rgba(31, 119, 180, {0.85 * v:.2f}){"; color: #fff" if v > 0.6 else ""}"'
            cells.append(f'<td class="{"n" if num else "t"}"{style}>{html.escape(c)}</td>')
        out.append("<tr>" + "".join(cells) + "</tr>")
    out.append("</tbody>")
    out.extend(f'<tfoot><tr><td colspan="{len(table.header)}">{html.escape(n)}</td></tr></tfoot>'
               for n in table.notes)
    out.append("</table>")
    return "\n".join(out)


_CSS = """
body { font-family: system-ui, -apple-system, "Segoe UI", sans-serif; margin: 2em auto; max-width: 1200px;
       color: #222; padding: 0 1em; }
h1 { font-size: 1.6em; margin-bottom: 0.2em; } h2 { border-bottom: 2px solid #1f77b4; padding-bottom: 0.2em;
       margin-top: 2em; } .meta { color: #666; } .note { color: #555; font-style: italic; }
.skipped { color: #999; } .failed { color: #b00020; font-weight: bold; } nav a { margin-right: 1em; }
table { border-collapse: collapse; margin: 1em 0; font-size: 0.85em; }
caption { text-align: left; font-weight: bold; padding: 0.3em 0; }
th, td { border: 1px solid #ccc; padding: 0.2em 0.5em; } th { background: #eef3f8; }
td.n { text-align: right; font-variant-numeric: tabular-nums; } td.t { text-align: left; }
img { max-width: 100%; border: 1px solid #eee; margin: 0.5em 0; display: block; }
"""


def _html(report: Report, images: dict[str, bytes]) -> str:
    m = report.model
    now = datetime.datetime.now().strftime("%Y-%m-%d %H:%M")
    from .._version import __version__

    modes = report.results.get("modes")
    shown = {s.key for s in report.sections if not s.skipped}
    viewer = viewer_html(modes) if modes is not None and "modes" in shown else ""

    parts = ["<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8">',
             f"<title>vibss report: {html.escape(m.name)}</title><style>{_CSS}{VIEWER_CSS if viewer else ''}</style>"
             + (ERROR_HOOK if viewer else "") + "</head><body>",
             f"<h1>{html.escape(m.name)}</h1>",
             f'<p class="meta">vibss {__version__} report, {now}'
             + (f", model {html.escape(report.source)}" if report.source else "")
             + ". SI units unless a column says otherwise.</p>",
             "<nav>" + "".join(f'<a href="#{s.key}">{html.escape(s.title)}</a>' for s in report.sections)
             + "</nav>"]
    for s in report.sections:
        parts.append(f'<h2 id="{s.key}">{html.escape(s.title)}</h2>')
        if s.note:
            cls = "failed" if s.failed else "skipped" if s.skipped else "note"
            head = "Failed: " if s.failed else "Skipped: " if s.skipped else ""
            parts.append(f'<p class="{cls}">{head}{html.escape(s.note.removeprefix("failed: "))}</p>')
        if s.key == "model" and s.text:
            parts.append(f"<p>{html.escape(s.text.splitlines()[0])}</p>")
        if s.key == "modes" and viewer:
            parts.append(viewer)
        for name, _ in s.figures:
            data = base64.b64encode(images[name]).decode("ascii")
            parts.append(f'<img src="data:image/png;base64,{data}" alt="{html.escape(name)}" '
                         f'title="{html.escape(name)}">')
        for t in s.tables:
            energy = t.title.startswith("Modal kinetic-energy")
            parts.append(html_table(t, shade_from=3 if energy else None))
    parts.append("</body></html>")
    return "\n".join(parts)


PNG_COMPRESSION = 3
"""zlib level of the PNG files: about 25 % less encoding time than Pillow's default 6, file sizes
within a few per cent of it (some smaller)."""


def _save_png(fig: Any, path: Path, dpi: int) -> None:
    """``fig.savefig(path, dpi=dpi)`` drawn once: the same pixels, without the extra draw.

    With a layout engine, ``savefig`` draws the figure twice: once (not rendered) to run the layout,
    once to render. Here the layout runs alone at the file's resolution, then the figure is
    rendered once with its engine set aside (and put back, so the figure stays as it was).
    """
    engine = fig.get_layout_engine()
    if engine is not None:
        shown = fig.dpi
        fig.dpi = dpi                   # the layout measures text at the file's resolution
        try:
            engine.execute(fig)
        finally:
            fig.dpi = shown
        fig.set_layout_engine("none")    # a placeholder that does nothing (None may install rcParams' engine)
    try:
        fig.savefig(path, dpi=dpi, pil_kwargs={"compress_level": PNG_COMPRESSION})
    finally:
        if engine is not None:
            fig.set_layout_engine(engine)


def write_report(report: Report, out: str | Path, dpi: int = 110) -> Path:
    """Write the figures (PNG) and ``index.html`` of a report into folder ``out``
    (:func:`render_report` without the updated report)."""
    return render_report(report, out, dpi)[0]


def render_report(report: Report, out: str | Path, dpi: int = 110) -> tuple[Path, Report]:
    """Write the figures (PNG), ``index.html`` and ``report.txt`` of a report into folder ``out``.

    A figure that fails to save is left out and its section marked failed with a note; the rest is
    written.

    Parameters
    ----------
    report : Report
        From :func:`study` (with figures).
    out : str or Path
        Folder, created if needed; existing files of the same names are replaced.
    dpi : int
        Resolution of the PNG files [dots per inch].

    Returns
    -------
    index : Path
        The ``index.html`` written.
    report : Report
        The report as written (figure failures noted).
    """
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    images: dict[str, bytes] = {}
    sections = []
    for s in report.sections:
        kept = []
        for name, fig in s.figures:
            path = out / name
            try:
                _save_png(fig, path, dpi)
            except Exception as exc:    # a figure that cannot be drawn is noted; the rest is written
                s = dataclasses.replace(s, failed=True, note=(s.note + "; " if s.note else "")
                                        + f"figure {name} failed: {type(exc).__name__}: {exc}")
                continue
            images[name] = path.read_bytes()
            kept.append((name, fig))
        sections.append(dataclasses.replace(s, figures=tuple(kept)))
    report = dataclasses.replace(report, sections=tuple(sections))
    index = out / "index.html"
    index.write_text(_html(report, images), encoding="utf-8")
    (out / "report.txt").write_text(report.text(), encoding="utf-8")
    return index, report
