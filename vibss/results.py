"""Plain-text tables for the reports, in the style engineers expect."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

__all__ = ["Table"]


@dataclass(frozen=True)
class Table:
    """A titled table of strings that renders as aligned text.

    Parameters
    ----------
    header : sequence of str
        Column names.
    rows : sequence of sequence of str
        Cells, already formatted.
    title : str
        Printed above the table.
    """

    header: Sequence[str]
    rows: Sequence[Sequence[str]]
    title: str = ""
    notes: Sequence[str] = field(default_factory=tuple)

    def render(self) -> str:
        """The table as aligned text (numbers right-aligned)."""
        cols = list(zip(*([list(self.header)] + [list(r) for r in self.rows])))
        widths = [max(len(c) for c in col) for col in cols]
        def line(cells: Sequence[str]) -> str:
            return "  ".join(c.rjust(w) for c, w in zip(cells, widths)).rstrip()
        out = []
        if self.title:
            out.append(self.title)
        out.append(line(self.header))
        out.append("  ".join("-" * w for w in widths))
        out.extend(line(r) for r in self.rows)
        out.extend(self.notes)
        return "\n".join(out)

    def __str__(self) -> str:
        return self.render()
