"""The frequency section: the steady-state response to the sine sweeps with each swept input's
transmissibility, or, without a sweep, the isolator's own motion and force transmissibility."""

from __future__ import annotations

from typing import Any

import numpy as np

from ...model.model import GROUND, Model
from ...results import TextTable
from ...studies import frequency_band, steady_sweeps
from ..section import TITLES, Section, _available, slug

def _bode(r: Any, name: str, title: str = "") -> tuple[str, Any]:
    from ...plotting.frequency import plot_frequency_response

    if tuple(r.inputs) == ("sweep",):   # a sweep's amplitudes: only its band, named as what they are
        kind = {"receptance": "displacement", "mobility": "velocity", "accelerance": "acceleration"}.get(r.quantity, r.quantity)
        return name, plot_frequency_response(
            r, what=f"{kind} amplitude",
            title=title or f"{r.name}: steady-state {kind} amplitude (method {r.method})")
    return name, plot_frequency_response(
        r, title=title or f"{r.name}: {r.quantity} from {', '.join(r.inputs)} (method {r.method})")


def _frequency_section(model: Model, figures: bool, results: dict[str, Any]) -> Section:
    sweeps = list(steady_sweeps(model))
    if not sweeps and any(m.to == "ground" for m in model.mounts) and _available("frequency"):
        return _isolation_section(model, figures, results)
    if not sweeps:
        return Section("frequency", TITLES["frequency"], skipped=True,
                       note="no steady-state sine-sweep excitation (sweep_time = 0) in the model")
    if not _available("frequency"):
        return Section("frequency", TITLES["frequency"], skipped=True,
                       note="vibss.frequency is not installed in this version")
    from ...frequency.sweep import sweep_response, transmissibility

    # the band and grid of ``vibss frf`` (vibss.studies: [analysis] frequency, else the sweeps' own
    # band), so the report's peaks are the command's
    band = frequency_band(model, results.get("modes"))
    r = sweep_response(model, sweeps, band.f1, band.f2, band.points, band.spacing)
    results["frequency"] = r
    texts = [r.report()]
    tables = [_frf_table(r, f"Steady-state sweep response of {', '.join(e.name for e in sweeps)}")]
    figs = [_bode(r, "sweep.png", f"{model.name}: steady-state amplitude under "
                  f"{', '.join(e.name for e in sweeps)}")] if figures else []
    grid = band.grid()
    for e in sweeps:
        ground = None if e.target == "ground" else [f"ground.{c}" for c in ("fx", "fy", "fz", "mx", "my", "mz")]
        tr = transmissibility(model, [e.signal], ground, frequencies=grid)
        results[f"transmissibility:{e.name}"] = tr
        texts.append(tr.report())
        tables.append(_frf_table(tr, f"Transmissibility from {e.signal} (excitation {e.name!r})"))
        if figures:
            figs.append(_bode(tr, f"transmissibility_{slug(e.name)}.png"))
    return Section("frequency", TITLES["frequency"], "\n\n".join(texts), tuple(tables), tuple(figs),
                   note=f"{band.f1:g} to {band.f2:g} Hz ({band.note}), method {r.method}")


def _frf_table(r: Any, title: str) -> TextTable:
    rows = []
    for i, y in enumerate(r.outputs):
        for j, u in enumerate(r.inputs):
            peaks = r.peaks(y, u, 1)
            f, a = peaks[0] if peaks else (float("nan"), 0.0)
            rows.append([y, u, f"{f:.4f}", f"{a:.4e}", r.channel_unit(i, j)])
    return TextTable(["output", "input", "peak f [Hz]", "amplitude", "unit"], rows, title=title)


def _isolation_section(model: Model, figures: bool, results: dict[str, Any]) -> Section:
    """An isolator model without a sine sweep: motion transmissibility from ground (x, y, z) to each
    body's COG along the same axis, and force transmissibility from a force at each body's COG into
    ground, over the report's band; with supports, from and into each ground node that carries a
    mount (the rigid ground and each support) on its own."""
    from ...frequency.sweep import transmissibility

    band = frequency_band(model, results.get("modes"))
    grid = band.grid()
    used = {m.support or GROUND for m in model.mounts if m.to == GROUND}
    nodes = [g for g in (GROUND, *model.support_names) if g in used]
    motion, force = {}, {}
    for d in "xyz":
        motion[d] = transmissibility(model, [f"{g}.{d}" for g in nodes], [f"{b}.{d}" for b in model.body_names],
                                     frequencies=grid)
        force[d] = transmissibility(model, [f"{b}.f{d}" for b in model.body_names], [f"{g}.f{d}" for g in nodes],
                                    frequencies=grid)
    results["transmissibility:motion"], results["transmissibility:force"] = motion, force
    rows, lines = [], []
    undamped = all(not np.any(m.type.damping) and not np.any(m.type.loss_factor) for m in model.mounts)
    for kind, group in (("motion", motion), ("force", force)):
        for d, r in group.items():
            for i, y in enumerate(r.outputs):
                for j, u in enumerate(r.inputs):
                    pk = r.peaks(y, u, 1)
                    f, a = pk[0] if pk else (float("nan"), float("nan"))
                    top = float(np.nanmax(np.abs(r.response[i, j])))
                    amp = np.abs(r.response[i, j])
                    over = np.flatnonzero(~(amp < 1.0))          # |T| >= 1 (or not finite)
                    iso = (np.nan if over.size and over[-1] == amp.size - 1
                           else float(r.frequency_hz[over[-1] + 1]) if over.size else float(r.frequency_hz[0]))
                    peak = "unbounded (no damping)" if undamped else f"{a:.4g}"
                    rows.append([kind, u, y, f"{f:.4g}", peak, "unbounded" if undamped else f"{top:.4g}",
                                 "-" if not np.isfinite(iso) else f"{iso:.4g}"])
    table = TextTable(["kind", "input", "output", "peak f [Hz]", "peak |T| [-]", "max |T| [-]", "|T| < 1 above [Hz]"],
                  rows, title="Transmissibility (no sine sweep in the file: unit ground motion along each axis, "
                              "unit forces at each body's COG)")
    lines.append(str(table))
    figs: list[tuple[str, Any]] = []
    if figures:
        from ...plotting.frequency import plot_transmissibility_set

        figs.append(("transmissibility.png", plot_transmissibility_set(motion, force, model.body_names)))
    return Section("frequency", "Transmissibility (isolation)", "\n".join(lines), (table,), tuple(figs),
                   note=f"{band.f1:g} to {band.f2:g} Hz ({band.note}); the file has no sine sweep, so the "
                        "report shows the isolator's own transmissibility")
