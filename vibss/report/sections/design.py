"""The design section: the decoupling certificate, and the optimization and tolerance study a
``[design]`` table asks for."""

from __future__ import annotations

from typing import Any

from ...model.model import Model
from ...results import TextTable
from ..section import TITLES, Section

def _design_section(model: Model, figures: bool, results: dict[str, Any]) -> Section:
    given = "design" in model.settings
    if not given and len(model.bodies) != 1:
        return Section("design", TITLES["design"], skipped=True,
                       note="no [design] table: the decoupling certificate of a multi-body model needs "
                            "its targets (docs/model-file.md)")
    from ...design.filespec import run_design

    run = run_design(model)
    results["design"] = run
    done = [r for r in (run.certificate, run.optimization, run.tolerance) if r is not None]
    tables: list[TextTable] = [run.certificate.summary(), run.certificate.ke_table()]
    if run.optimization is not None:
        tables += [run.optimization.summary(), run.optimization.comparison()]
    if run.tolerance is not None:
        tables.append(run.tolerance.summary())
    figs = tuple((f"design_{k}.png", r.plot()) for k, r in
                 zip(("certificate", "optimisation", "tolerance"), (run.certificate, run.optimization, run.tolerance))
                 if r is not None) if figures else ()
    note = ("targets, variables and tolerances from the file's [design] table" if given else
            "default targets (purity 0.9, global axes, no windows); a [design] table sets them")
    return Section("design", TITLES["design"], "\n\n".join(r.report() for r in done), tuple(tables), figs, note)
