"""The static section: the deflection under the model's loads and gravity, then each load case."""

from __future__ import annotations

from typing import Any

from ...model.model import Model
from ...results import TextTable, number_text
from ...statics import StaticResult, static
from ...nonlinear.kernels import nonlinear_mounts
from ..section import TITLES, Section

def _static_tables(r: StaticResult) -> tuple[TextTable, ...]:
    under = f" under load case {r.case!r}" if r.case else (" under the unnamed loads" if r.model.load_cases else "")
    rows = []
    for b in r.model.bodies:
        d, c = r.body(b.name), r.center_of_rotation(b.name)
        rows.append([b.name] + [f"{1e3 * v:.4f}" for v in d]
                    + ["pure translation" if c is None else "(" + ", ".join(number_text(v) for v in c) + ")"])
    out = [TextTable(["body", "x [mm]", "y [mm]", "z [mm]", "rx [mrad]", "ry [mrad]", "rz [mrad]",
                  "centre of rotation [m]"], rows, title="Bodies (COG)" + under)]
    if r.model.control_points:
        out.append(TextTable(["point", "x [mm]", "y [mm]", "z [mm]"],
                         [[k] + [f"{1e3 * v:.4f}" for v in x] for k, x in r.control_points.items()],
                         title="Control points" + under))
    if r.model.mounts:
        out.append(r.mount_table(under))
        if r.mount_moment is not None:
            out.append(r.moment_table())
    return tuple(out)


def _static_section(model: Model, figures: bool, results: dict[str, Any]) -> Section:
    if not model.loads and model.gravity is None:
        return Section("static", TITLES["static"], note="the model has no loads and no gravity",
                       skipped=True)
    cases: list[str | None] = [None, *model.load_cases]   # the unnamed loads, then each case on its own
    solved = [static(model, case=c) for c in cases]
    results["static"] = solved[0]
    what = ", ".join(x for x in (f"{len(model.loads)} load(s)" if model.loads else "",
                                 "self-weight" if model.gravity is not None else "") if x)
    if model.load_cases:
        what += "; then each load case on its own: " + ", ".join(map(repr, model.load_cases))
    tables = tuple(t for r in solved for t in _static_tables(r))
    text = "\n\n".join(r.report() for r in solved)
    if nonlinear_mounts(model):            # the operating point: tangent rates and the clearance left
        from ...nonlinear.api import operating_point

        op = operating_point(model)
        results["operating_point"] = op
        extra = (op.rates(),) + ((op.summary(),) if op.clearance else ())
        tables += extra
        text += "\n\n" + "\n\n".join(t.render() for t in extra)
    figs: tuple[tuple[str, Any], ...] = ()
    if figures:
        from ...plotting.summary import plot_mount_deflections, plot_static

        figs = (("static.png", plot_static(solved[0])),)
        if model.mounts:
            figs += (("static_mounts.png", plot_mount_deflections(solved[0])),)
    return Section("static", TITLES["static"], text, tables, figs, note=f"under {what}")
