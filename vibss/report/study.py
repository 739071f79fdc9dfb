"""The engineer's report of a model: every analysis that applies, as text, PNG figures and HTML.

:func:`study` runs, in order, the model summary, the static deflection (under the model's loads
and, where the model sets it, gravity), the undamped modes with their kinetic-energy table, the
damped modes, the design checks, the closed loop of an active model, the steady-state response to
the model's sine-sweep excitations (with the transmissibility from each swept input; without a
sweep, the isolator's own motion and force transmissibility), the harmonic balance the model file
asks for (``[analysis] harmonic_balance``), the order analysis and the time response to its transient excitations, over
the window and band of :mod:`vibss.studies` (the ones ``vibss time`` and ``vibss frf`` use). An
analysis that does not apply (no loads, no damping, no excitation of that kind) or whose module is
not installed is skipped with a one-line note; one that fails is reported with its error message
and the others still run. :meth:`Report.text` is the text report, :func:`write_report` writes the
PNG figures and one self-contained ``index.html`` (figures embedded as base64) into a folder.

This module imports matplotlib (through :mod:`vibss.plotting`) only when figures are asked for.

Examples
--------
>>> import vibss, tempfile
>>> from vibss.report import study
>>> t = vibss.MountType("t", [1e4, 2e4, 3e4])
>>> m = vibss.Model([vibss.Body("b", 1000.0, [10, 20, 30])],
...                 vibss.symmetric(vibss.Mount("m", t, "b", at=[1, 2, 0])), name="prism")
>>> r = study(m, figures=False)
>>> [s.key for s in r.sections if not s.skipped]
['model', 'modes', 'design', 'frequency']
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import replace
from typing import Any

import numpy as np

from ..errors import ArgumentError, SignalError, VibssError, did_you_mean
from ..model.model import Model
from .section import STEPS, TITLES, Progress, Report, Section
from .sections.control import _control_section
from .sections.design import _design_section
from .sections.frequency import _frequency_section
from .sections.harmonic import _harmonic_section
from .sections.model import _model_section
from .sections.modes import _damped_section, _modes_section
from .sections.orders import _orders_section
from .sections.static import _static_section
from .sections.time import _time_section

__all__ = ["study", "SECTION_ERRORS"]


SECTION_ERRORS: tuple[type[BaseException], ...] = (
    VibssError, np.linalg.LinAlgError, ValueError, ArithmeticError, RuntimeError, MemoryError)
"""Failures of the analysis itself (a refusal, a singular solve, an overflow, a solver that gave
up): the section's note says ``failed: <error>``. Any other exception (a bug in vibss) fails its
section too, with ``failed: internal error, please report: <error>``: one section never takes the
others down (:func:`study`)."""


def _failure(key: str, exc: Exception) -> Section:
    what = "" if isinstance(exc, SECTION_ERRORS) else "internal error, please report: "
    return Section(key, TITLES[key], skipped=True, failed=True, note=f"failed: {what}{type(exc).__name__}: {exc}")


_RUNNERS = {"static": _static_section, "modes": _modes_section, "damped": _damped_section,
            "design": _design_section, "control": _control_section, "frequency": _frequency_section,
            "harmonic": _harmonic_section,
            "orders": _orders_section, "time": _time_section}


def study(model: Model, figures: bool = True, progress: Progress | None = None,
          source: str = "", sections: Iterable[str] | None = None) -> Report:
    """Run every analysis that applies to ``model`` (or those of ``sections``).

    Parameters
    ----------
    model : Model
        The model (its loads, gravity, excitations and ``settings`` drive the studies).
    figures : bool
        Make the matplotlib figures too (needs matplotlib).
    progress : callable or None
        ``progress(step, total, label)`` called before each analysis (the command line prints
        ``[3/6] damped modes ...`` on stderr).
    source : str
        Where the model came from, for the heading.
    sections : iterable of str, str or None
        Keys of :data:`~vibss.report.section.STEPS` to run (in the report's order whatever the order
        given; a string: comma-separated, as ``--sections`` takes them); the others are skipped, their
        note saying they were not asked for. None: all.

    Returns
    -------
    Report

    Raises
    ------
    SignalError
        A key of ``sections`` that is not a section (the valid ones listed, with a did-you-mean).
    ArgumentError
        ``sections`` empty.
    """
    wanted = _wanted(sections)
    results: dict[str, Any] = {}
    done: list[Section] = []
    steps = [k for k in STEPS if k in wanted]
    for key in STEPS:
        if key not in wanted:
            done.append(Section(key, TITLES[key], skipped=True, note="not asked for (sections)"))
            continue
        if progress is not None:
            progress(steps.index(key) + 1, len(steps), TITLES[key].lower())
        try:
            runner = _RUNNERS.get(key)
            if runner is None:
                done.append(_model_section(model, figures))
                continue
            here, said = _linearised(model, key, results)
            section = runner(here, figures, results)
            done.append(replace(section, note="; ".join(x for x in (section.note, said) if x)) if said else section)
        except Exception as exc:        # one failed analysis is that section's note, not the report's end
            done.append(_failure(key, exc))
    return Report(model, tuple(done), source, results)


def _wanted(sections: Iterable[str] | None) -> set[str]:
    """The section keys asked for: all by default; an unknown one is refused by name."""
    if sections is None:
        return set(STEPS)
    if isinstance(sections, str):
        sections = [k.strip() for k in sections.split(",") if k.strip()]
    sections = list(sections)                   # a generator is read once
    for k in sections:
        if k not in STEPS:
            raise SignalError(f"report: no section {k!r}{did_you_mean(str(k), STEPS)}; the sections are "
                              f"{', '.join(STEPS)}", argument="sections", received=k)
    if not sections:
        raise ArgumentError(f"report: no section asked for; the sections are {', '.join(STEPS)}",
                            argument="sections", received="")
    return set(sections)


NONLINEAR_SECTIONS = ("static", "modes", "harmonic", "time")
"""The sections that take a model with stops or curves as it is (the operating point, the tangent
modes it states itself, contacts in time); every other section analyses the tangent model."""


def _linearised(model: Model, key: str, results: dict[str, Any]) -> tuple[Model, str]:
    """The model a section analyses, and what its note says about it: a model with nonlinear mounts
    is linearised at its operating point for the linear sections (the static section's, if it ran)."""
    from ..nonlinear.kernels import nonlinear_mounts

    if key in NONLINEAR_SECTIONS or not nonlinear_mounts(model):
        return model, ""
    op = results.get("operating_point")
    if op is None:
        from ..nonlinear.api import operating_point

        op = results["operating_point"] = operating_point(model)
    return op.tangent, "nonlinear mounts: the tangent model at the operating point"
