"""The report's parts: a :class:`Section` per analysis, the :class:`Report` that holds them, their
order and titles, and the small helpers every section shares."""

from __future__ import annotations

import importlib.util
import re
import sys
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..errors import SignalError, did_you_mean
from ..model.model import Model
from ..results import TextTable

__all__ = ["Section", "Report", "STEPS", "TITLES", "MAX_MODE_PANELS", "Progress", "slug", "default_folder", "progress_on_stderr"]

STEPS = ("model", "static", "modes", "damped", "design", "control", "frequency", "harmonic", "orders", "time")
"""The report's sections, in order."""


TITLES = {"model": "Model", "static": "Static deflection", "modes": "Undamped modes",
          "damped": "Damped modes", "design": "Mount-system design (decoupling)",
          "orders": "Rotating machinery (orders against speed)", "control": "Active isolation (closed loop)", "frequency": "Frequency response (sine sweeps)",
          "harmonic": "Harmonic balance (steady periodic response with nonlinear mounts)",
          "time": "Time response (transient excitations)"}


MAX_MODE_PANELS = 12
"""At most this many modes are drawn (the lowest); the tables list them all."""


Progress = Callable[[int, int, str], None]


@dataclass(frozen=True)
class Section:
    """One part of the report.

    Attributes
    ----------
    key : str
        One of :data:`STEPS`.
    title : str
        Heading.
    text : str
        Text report of the analysis ('' when skipped).
    tables : tuple of TextTable
        The same results as tables (rendered as HTML tables).
    figures : tuple of (str, Any)
        ``(file name, matplotlib Figure)`` pairs; empty without figures.
    note : str
        One line: why the section was skipped, or a remark on how it was run.
    skipped : bool
        Whether the analysis did not run.
    failed : bool
        Whether it was attempted and failed (``note`` says how); the other sections are unaffected.
    """

    key: str
    title: str
    text: str = ""
    tables: tuple[TextTable, ...] = ()
    figures: tuple[tuple[str, Any], ...] = ()
    note: str = ""
    skipped: bool = False
    failed: bool = False


@dataclass(frozen=True)
class Report:
    """Results of :func:`study`.

    Attributes
    ----------
    model : Model
        The model studied.
    sections : tuple of Section
        In the order of :data:`STEPS`.
    source : str
        Where the model came from (file name or example).
    results : dict
        The result objects by section key (``Modes``, ``StaticResult`` ...).
    """

    model: Model
    sections: tuple[Section, ...]
    source: str = ""
    results: dict[str, Any] = field(default_factory=dict)

    def text(self) -> str:
        """The whole report as text: each section's heading and its text report or note."""
        head = f"vibss report: {self.model.name}" + (f"  ({self.source})" if self.source else "")
        parts = [head, "=" * len(head)]
        for s in self.sections:
            parts.append(f"\n== {s.title} ==")
            if s.note:
                parts.append(("FAILED: " + s.note.removeprefix("failed: ")) if s.failed else
                             ("skipped: " if s.skipped else "note: ") + s.note)
            if s.text:
                parts.append(s.text)
        return "\n".join(parts) + "\n"

    @property
    def failed(self) -> tuple[str, ...]:
        """Keys of the sections that failed (the command line then exits with status 3)."""
        return tuple(s.key for s in self.sections if s.failed)

    def section(self, key: str) -> Section:
        """The section called ``key``."""
        for s in self.sections:
            if s.key == key:
                return s
        keys = [s.key for s in self.sections]
        raise SignalError(f"section: no section {key!r}{did_you_mean(key, keys)}; sections are {keys}",
                          argument="section", received=key, expected=tuple(keys))


def slug(name: str) -> str:
    """A file-name-safe version of ``name`` (letters, digits, ``-`` and ``_``)."""
    s = re.sub(r"[^A-Za-z0-9_-]+", "-", name).strip("-")
    return s or "model"


def _stderr_progress(step: int, total: int, label: str) -> None:
    print(f"[{step}/{total}] {label} ...", file=sys.stderr, flush=True)


def _available(module: str) -> bool:
    return importlib.util.find_spec(f"vibss.{module}") is not None


def default_folder(source: str, model: Model) -> Path:
    """``./vibss-report-<name>``: the file's stem or example name, else the model's name."""
    stem = Path(source).stem if source else model.name
    return Path(f"vibss-report-{slug(stem)}")


def progress_on_stderr() -> Progress:
    """The command line's progress display (``[3/6] damped modes ...`` on stderr)."""
    return _stderr_progress
