"""The time section: the response to the transient excitations over the window of ``vibss time``."""

from __future__ import annotations

from typing import Any

from ...model.model import Model
from ...results import TextTable
from ...studies import time_outputs, time_window, transient_excitations
from ...time.drift import ground_drifts
from ..section import TITLES, Section, _available

def _time_section(model: Model, figures: bool, results: dict[str, Any]) -> Section:
    transient = list(transient_excitations(model))
    if not transient:
        return Section("time", TITLES["time"], skipped=True,
                       note="no transient excitation (pulse, step, sine, table or timed sweep) in the model")
    if not _available("time"):
        return Section("time", TITLES["time"], skipped=True, note="vibss.time is not installed in this version")
    from ...time.api import simulate

    window = time_window(model, results.get("modes"))     # the window of ``vibss time``
    chosen = time_outputs(model, transient)
    r = simulate(model, transient, outputs=list(chosen.outputs), t_end=window.end, dt=window.step,
                 record_from=window.record_from, rtol=window.tolerance)
    results["time"] = r
    in_g = (model.settings or {}).get("units", {}).get("acceleration") == "g"   # the file asks for g
    summary = (r.in_g() if in_g else r).summary()
    table = TextTable(summary.header, summary.rows,
                  title=f"Peaks of the response to {', '.join(e.name for e in transient)} "
                        f"(body motions {'relative to the ground' if chosen.relative else 'absolute'}; "
                        "mount deflection = body side minus other side)"
                        + summary.title.removeprefix(f"method {r.method}"))
    figs: list[tuple[str, Any]] = []
    if figures:
        from ...plotting import plot_time_groups

        figs.append(("time.png", plot_time_groups(r, order=list(chosen.lead), show_inputs=True,
                                                  acceleration="g" if in_g else "m/s^2")))
    head = "\n".join(r.report().split("\n")[:2])
    drifts = "".join(f"\nDrift: {d.text()}" for d in ground_drifts(transient, window.end))
    tables: tuple[TextTable, ...] = (table,)
    body = f"{head}{drifts}\n\n{table}"
    if r.contacts is not None:            # nonlinear mounts: which stops were hit, when, how hard
        tables += (r.contacts.table,)
        body += f"\n\n{r.contacts.table.render()}"
    return Section("time", TITLES["time"], body, tables, tuple(figs),
                   note=f"0 to {window.end:g} s, step {window.step:g} s ({window.note}), method {r.method}")
