"""The engineer's report of a model: every analysis that applies, as text, PNG figures and HTML.

:func:`study` runs, in order, the model summary, the static deflection (under the model's loads
and, where the model sets it, gravity), the undamped modes with their kinetic-energy table, the
damped modes, the design checks, the closed loop of an active model, the steady-state response to
the model's sine-sweep excitations (with the transmissibility from each swept input; without a
sweep, the isolator's own motion and force transmissibility), the order analysis and the time response to its transient excitations, over
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

import base64
import datetime
import html
import importlib.util
import re
import sys
from collections.abc import Callable
import dataclasses
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .modal.damped import damped_modes
from .errors import SignalError, VibssError, did_you_mean
from .modal.undamped import modes
from .model.model import GROUND, Model
from .results import Table, number_text
from .statics import StaticResult, static
from .studies import frequency_band, steady_sweeps, time_outputs, time_window, transient_excitations

__all__ = ["Section", "Report", "study", "write_report", "render_report", "html_table", "slug", "default_folder",
           "progress_on_stderr", "STEPS", "MAX_MODE_PANELS"]

STEPS = ("model", "static", "modes", "damped", "design", "control", "frequency", "orders", "time")
"""The report's sections, in order."""

TITLES = {"model": "Model", "static": "Static deflection", "modes": "Undamped modes",
          "damped": "Damped modes", "design": "Mount-system design (decoupling)",
          "orders": "Rotating machinery (orders against speed)", "control": "Active isolation (closed loop)", "frequency": "Frequency response (sine sweeps)",
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
    tables : tuple of Table
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
    tables: tuple[Table, ...] = ()
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


# -- the analyses ---------------------------------------------------------------------------------
def _model_section(model: Model, figures: bool) -> Section:
    bodies = Table(["body", "mass [kg]", "Ixx", "Iyy", "Izz", "Ixy", "Ixz", "Iyz", "COG x [m]",
                    "COG y [m]", "COG z [m]"],
                   [[b.name, " ".join(f"{m:.4g}" for m in np.unique(b.masses))]
                    + [f"{b.tensor[i, j]:.4g}" for i, j in ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))]
                    + [f"{c:.4g}" for c in b.cog] for b in model.bodies],
                   title="Bodies (inertia tensor about the COG in global axes [kg m^2]; "
                         "off-diagonals are minus the products of inertia)")
    rotational = any(t.rotational for t in model.mount_types.values())
    types = Table(["mount type", "k1 [N/m]", "k2 [N/m]", "k3 [N/m]", "c1 [N s/m]", "c2 [N s/m]",
                   "c3 [N s/m]", "loss factor", "rheology"]
                  + (["kr1 [N m/rad]", "kr2 [N m/rad]", "kr3 [N m/rad]", "cr1 [N m s/rad]", "cr2 [N m s/rad]",
                      "cr3 [N m s/rad]"] if rotational else []),
                  [[t.name] + [f"{v:.4g}" for v in t.stiffness] + [f"{v:.4g}" for v in t.damping]
                   + [" ".join(f"{v:.3g}" for v in np.unique(t.loss_factor)), _rheology_text(t)]
                   + ([f"{v:.4g}" for v in np.concatenate([t.rotational_stiffness, t.rotational_damping])]
                      if rotational else [])
                   for t in model.mount_types.values()],
                  title="Mount types (k: static stiffness; rheology: frequency-dependent, its ladder's "
                        "fit error)")
    mounts = Table(["mount", "type", "joins", "x [m]", "y [m]", "z [m]", "orientation"],
                   [[m.name, m.type.name, f"{m.body}->{m.support or m.to}"]
                    + [f"{v:.4g}" for v in model.mount_point(m)] + [_describe(m.orientation)]
                    for m in model.mounts],
                   title="Mounts (attachment points in global coordinates; Euler angles in "
                         "scipy's spelling, upper case = intrinsic)")
    tables = [bodies, types, mounts] if model.mounts else [bodies]
    full = [(t, key) for t in model.mount_types.values() if t.coupled
            for key in ("stiffness", "damping") if getattr(t, f"{key}_matrix") is not None]
    if full:
        labels = ("d1", "d2", "d3", "r1", "r2", "r3")
        tables.append(Table(["mount type", "matrix", "row"] + list(labels),
                            [[t.name, key, labels[i]] + [f"{v:.4g}" for v in t.local_matrix(key)[i]]
                             for t, key in full for i in range(6)],
                            title="Full 6x6 mount matrices in local axes (on d1..d3 [m], r1..r3 [rad]: "
                                  "N/m, N m/rad, coupling N/rad; damping N s/m, N m s/rad, N s/rad)"))
    if model.supports:
        tables.append(Table(["support", "mounts", "description"],
                            [[g.name, ", ".join(m.name for m in model.mounts if m.support == g.name), g.description]
                             for g in model.supports],
                            title="Supports (ground points moved on their own: inputs <support>.<dof>.disp|vel|acc)"))
    if model.control_points:
        pts = [[c.name, c.body] + [f"{v:.4g}" for v in model.body(c.body).cog + model.point(c.body, c.at, c.frame)]
               for c in model.control_points]
        tables.append(Table(["point", "body", "x [m]", "y [m]", "z [m]"], pts, title="Control points"))
    if model.excitations:
        rows = [[e.name, e.kind, e.target, e.dof or "direction " + str(np.round(e.direction, 3).tolist()),
                 type(e.function).__name__, _function_parameters(e.function.to_dict(), e.unit), e.unit]
                for e in model.excitations]
        tables.append(Table(["excitation", "kind", "target", "dof", "function", "parameters", "unit"], rows,
                            title="Excitations (amplitudes in the unit column, times in s, frequencies in Hz)"))
    nb = len(model.bodies)
    text = (f"{nb} bod{'y' if nb == 1 else 'ies'}, {len(model.mounts)} mounts, total mass "
            f"{model.total_mass:.4g} kg" + ("" if model.gravity is None else
                                             f", gravity {model.gravity.tolist()} m/s^2"))
    figs: tuple[tuple[str, Any], ...] = ()
    if figures:
        from .plotting import plot_model

        figs = (("model.png", plot_model(model)), ("model_views.png", plot_model(model, view="three")))
        if any(t.rheology is not None for t in model.mount_types.values()):
            from .plotting import plot_dynamic_stiffness

            figs += (("mount_stiffness.png", plot_dynamic_stiffness(list(model.mount_types.values()))),)
    return Section("model", TITLES["model"], text + "\n\n" + "\n\n".join(t.render() for t in tables),
                   tuple(tables), figs)


def _rheology_text(t: Any) -> str:
    """``zener``, ``table (fit 0.031)`` or ``-``."""
    if t.rheology is None:
        return "-"
    return t.rheology.kind + (f" (fit {t.fit_error:.2g})" if t.fit_error else "")


def _describe(o: Any) -> str:
    """An orientation as Euler angles in the default sequence, also when given as a matrix."""
    text = o.describe()
    if text != "matrix":
        return text
    from scipy.spatial.transform import Rotation

    from .model.geometry import DEFAULT_SEQUENCE

    a = Rotation.from_matrix(o.matrix).as_euler(DEFAULT_SEQUENCE, degrees=True)
    return f"{DEFAULT_SEQUENCE} ({a[0]:.2f}, {a[1]:.2f}, {a[2]:.2f}) deg"


def _static_tables(r: StaticResult) -> tuple[Table, ...]:
    under = f" under load case {r.case!r}" if r.case else (" under the unnamed loads" if r.model.load_cases else "")
    rows = []
    for b in r.model.bodies:
        d, c = r.body(b.name), r.centre_of_rotation(b.name)
        rows.append([b.name] + [f"{1e3 * v:.4f}" for v in d]
                    + ["pure translation" if c is None else "(" + ", ".join(number_text(v) for v in c) + ")"])
    out = [Table(["body", "x [mm]", "y [mm]", "z [mm]", "rx [mrad]", "ry [mrad]", "rz [mrad]",
                  "centre of rotation [m]"], rows, title="Bodies (COG)" + under)]
    if r.model.control_points:
        out.append(Table(["point", "x [mm]", "y [mm]", "z [mm]"],
                         [[k] + [f"{1e3 * v:.4f}" for v in x] for k, x in r.control_points.items()],
                         title="Control points" + under))
    if r.model.mounts:
        out.append(Table(["mount", "joins", "dx [mm]", "dy [mm]", "dz [mm]", "d1 [mm]", "d2 [mm]", "d3 [mm]",
                          "Fx [N]", "Fy [N]", "Fz [N]"],
                         [[m.name, f"{m.body}->{m.support or m.to}"] + [f"{1e3 * v:.4f}" for v in r.mount_deflection[p]]
                          + [f"{1e3 * v:.4f}" for v in r.mount_deflection_local[p]]
                          + [f"{v:.2f}" for v in r.mount_force[p]] for p, m in enumerate(r.model.mounts)],
                         title="Mounts" + under + " (deflection = body side minus other side; force into the other side)"))
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
    figs: tuple[tuple[str, Any], ...] = ()
    if figures:
        from .plotting.summary import plot_mount_deflections, plot_static

        figs = (("static.png", plot_static(solved[0])),)
        if model.mounts:
            figs += (("static_mounts.png", plot_mount_deflections(solved[0])),)
    return Section("static", TITLES["static"], "\n\n".join(r.report() for r in solved), tables, figs,
                   note=f"under {what}")


def _modes_section(model: Model, figures: bool, results: dict[str, Any]) -> Section:
    m = modes(model)
    results["modes"] = m
    figs: list[tuple[str, Any]] = []
    note = ""
    if figures:
        from .plotting import plot_energy, plot_modes

        which = list(range(min(len(m), MAX_MODE_PANELS)))
        if len(m) > MAX_MODE_PANELS:
            note = f"figures show the lowest {MAX_MODE_PANELS} of {len(m)} modes"
        figs = [("modes.png", plot_modes(m, which=which)),
                ("modes_views.png", plot_modes(m, which=which[:6], view="three")),
                ("energy.png", plot_energy(m, which=which))]
    return Section("modes", TITLES["modes"], m.report(),
                   (m.frequency_table(), m.shape_table(), m.energy_table()), tuple(figs), note)


def _damped_section(model: Model, figures: bool, results: dict[str, Any]) -> Section:
    if not any(np.any(t.damping > 0) for t in model.mount_types.values()):
        return Section("damped", TITLES["damped"], skipped=True,
                       note="no viscous damping in the mounts: the damped modes are the undamped ones")
    d = damped_modes(model, undamped=results.get("modes"))
    results["damped"] = d
    return Section("damped", TITLES["damped"], d.report(), (d.table(),), note=d.method)


def _design_section(model: Model, figures: bool, results: dict[str, Any]) -> Section:
    given = "design" in model.settings
    if not given and len(model.bodies) != 1:
        return Section("design", TITLES["design"], skipped=True,
                       note="no [design] table: the decoupling certificate of a multi-body model needs "
                            "its targets (docs/model-file.md)")
    from .design.filespec import run_design

    run = run_design(model)
    results["design"] = run
    done = [r for r in (run.certificate, run.optimisation, run.tolerance) if r is not None]
    tables: list[Table] = [run.certificate.summary(), run.certificate.ke_table()]
    if run.optimisation is not None:
        tables += [run.optimisation.summary(), run.optimisation.comparison()]
    if run.tolerance is not None:
        tables.append(run.tolerance.summary())
    figs = tuple((f"design_{k}.png", r.plot()) for k, r in
                 zip(("certificate", "optimisation", "tolerance"), (run.certificate, run.optimisation, run.tolerance))
                 if r is not None) if figures else ()
    note = ("targets, variables and tolerances from the file's [design] table" if given else
            "default targets (purity 0.9, global axes, no windows); a [design] table sets them")
    return Section("design", TITLES["design"], "\n\n".join(r.report() for r in done), tuple(tables), figs, note)


def _orders_section(model: Model, figures: bool, results: dict[str, Any]) -> Section:
    spec = model.settings.get("orders")
    if not spec:
        return Section("orders", TITLES["orders"], skipped=True, note="no [orders] table in the model")
    if "rpm" not in spec:
        return Section("orders", TITLES["orders"], skipped=True,
                       note="the [orders] table gives no speed range (rpm = [low, high])")
    from .orders import order_response
    from .orders.sources import sources_from_settings

    lo, hi = spec["rpm"]
    r = order_response(model, sources_from_settings(model), np.linspace(lo, hi, spec.get("points", 400)),
                       spec.get("outputs"))
    results["orders"] = r
    figs = (("orders.png", r.plot()), ("campbell.png", r.campbell())) if figures else ()
    return Section("orders", TITLES["orders"], r.report(), (r.summary(), r.critical_table()), figs)


def _control_section(model: Model, figures: bool, results: dict[str, Any]) -> Section:
    if "control" not in model.settings:
        note = ("the model has actuators but no [control] table (design, gain, disturbances, performance)"
                if model.actuators else "no actuators and no [control] table in the model")
        return Section("control", TITLES["control"], skipped=True, note=note)
    from .control.filespec import run_control

    r = run_control(model)
    results["control"] = r
    figs = (("control.png", r.plot()),) if figures else ()
    return Section("control", TITLES["control"], r.report(),
                   (r.summary(), r.loop.margin_table(), r.loop.summary()), figs,
                   note=f"{model.settings['control']['design']} loops from the file's [control] table; margins "
                        "loop-at-a-time at the actuator commands")


def _available(module: str) -> bool:
    return importlib.util.find_spec(f"vibss.{module}") is not None


_PARAMETER_UNITS = {"start": "s", "end": "s", "duration": "s", "sweep_time": "s", "f1": "Hz", "f2": "Hz",
                    "frequency": "Hz", "phase": "rad"}


def _function_parameters(d: dict[str, Any], unit: str) -> str:
    """A time function's parameters as one line: ``amplitude 490.5 m/s^2 (50 g), duration 0.011 s``."""
    from .model.units import STANDARD_GRAVITY

    if d.get("type") == "sum":
        return " + ".join(_function_parameters(t, unit) for t in d.get("terms", []))
    parts = []
    for k, v in d.items():
        if k == "type":
            continue
        if isinstance(v, (int, float)):
            u = _PARAMETER_UNITS.get(k, unit if k in ("amplitude", "a1", "a2", "slope") else "")
            text = f"{k} {v:.6g}" + (f" {u}" if u else "")
            if u == "m/s^2" and v:
                text += f" ({v / STANDARD_GRAVITY:.4g} g)"
            parts.append(text)
        elif isinstance(v, list):
            parts.append(f"{k} [{len(v)} values]")
        else:
            parts.append(f"{k} {v}")
    return ", ".join(parts)


def _bode(r: Any, name: str, title: str = "") -> tuple[str, Any]:
    from .plotting.frequency import plot_frequency_response

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
    from .frequency.sweep import sweep_response, transmissibility

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


def _frf_table(r: Any, title: str) -> Table:
    rows = []
    for i, y in enumerate(r.outputs):
        for j, u in enumerate(r.inputs):
            peaks = r.peaks(y, u, 1)
            f, a = peaks[0] if peaks else (float("nan"), 0.0)
            rows.append([y, u, f"{f:.4f}", f"{a:.4e}", r.channel_unit(i, j)])
    return Table(["output", "input", "peak f [Hz]", "amplitude", "unit"], rows, title=title)


def _isolation_section(model: Model, figures: bool, results: dict[str, Any]) -> Section:
    """An isolator model without a sine sweep: motion transmissibility from ground (x, y, z) to each
    body's COG along the same axis, and force transmissibility from a force at each body's COG into
    ground, over the report's band; with supports, from and into each ground node that carries a
    mount (the rigid ground and each support) on its own."""
    from .frequency.sweep import transmissibility

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
    table = Table(["kind", "input", "output", "peak f [Hz]", "peak |T| [-]", "max |T| [-]", "|T| < 1 above [Hz]"],
                  rows, title="Transmissibility (no sine sweep in the file: unit ground motion along each axis, "
                              "unit forces at each body's COG)")
    lines.append(str(table))
    figs: list[tuple[str, Any]] = []
    if figures:
        from .plotting.frequency import plot_transmissibility_set

        figs.append(("transmissibility.png", plot_transmissibility_set(motion, force, model.body_names)))
    return Section("frequency", "Transmissibility (isolation)", "\n".join(lines), (table,), tuple(figs),
                   note=f"{band.f1:g} to {band.f2:g} Hz ({band.note}); the file has no sine sweep, so the "
                        "report shows the isolator's own transmissibility")


def _time_section(model: Model, figures: bool, results: dict[str, Any]) -> Section:
    transient = list(transient_excitations(model))
    if not transient:
        return Section("time", TITLES["time"], skipped=True,
                       note="no transient excitation (pulse, step, sine, table or timed sweep) in the model")
    if not _available("time"):
        return Section("time", TITLES["time"], skipped=True, note="vibss.time is not installed in this version")
    from .time.api import simulate

    window = time_window(model, results.get("modes"))     # the window of ``vibss time``
    chosen = time_outputs(model, transient)
    r = simulate(model, transient, outputs=list(chosen.outputs), t_end=window.end, dt=window.step,
                 record_from=window.record_from, rtol=window.tolerance)
    results["time"] = r
    in_g = (model.settings or {}).get("units", {}).get("acceleration") == "g"   # the file asks for g
    summary = (r.in_g() if in_g else r).summary()
    table = Table(summary.header, summary.rows,
                  title=f"Peaks of the response to {', '.join(e.name for e in transient)} "
                        "(body motions absolute; mount deflection = body side minus other side)"
                        + summary.title.removeprefix(f"method {r.method}"))
    figs: list[tuple[str, Any]] = []
    if figures:
        from .plotting import plot_time_groups

        figs.append(("time.png", plot_time_groups(r, order=list(chosen.lead), show_inputs=True,
                                                  acceleration="g" if in_g else "m/s^2")))
    head = "\n".join(r.report().split("\n")[:2])
    return Section("time", TITLES["time"], f"{head}\n\n{table}", (table,), tuple(figs),
                   note=f"0 to {window.end:g} s, step {window.step:g} s ({window.note}), method {r.method}")


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
            "orders": _orders_section, "time": _time_section}


def study(model: Model, figures: bool = True, progress: Progress | None = None,
          source: str = "") -> Report:
    """Run every analysis that applies to ``model``.

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

    Returns
    -------
    Report
    """
    results: dict[str, Any] = {}
    sections = []
    for n, key in enumerate(STEPS, start=1):
        if progress is not None:
            progress(n, len(STEPS), TITLES[key].lower())
        try:
            runner = _RUNNERS.get(key)
            sections.append(_model_section(model, figures) if runner is None else runner(model, figures, results))
        except Exception as exc:        # one failed analysis is that section's note, not the report's end
            sections.append(_failure(key, exc))
    return Report(model, tuple(sections), source, results)


# -- HTML -----------------------------------------------------------------------------------------
_NUMBER = re.compile(r"^[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$")


def html_table(table: Table, shade_from: int | None = None) -> str:
    """An HTML ``<table>`` of a :class:`~vibss.results.Table` (numbers right-aligned).

    Parameters
    ----------
    table : Table
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
    from ._version import __version__

    parts = ["<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8">',
             f"<title>vibss report: {html.escape(m.name)}</title><style>{_CSS}</style></head><body>",
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
        for name, _ in s.figures:
            data = base64.b64encode(images[name]).decode("ascii")
            parts.append(f'<img src="data:image/png;base64,{data}" alt="{html.escape(name)}" '
                         f'title="{html.escape(name)}">')
        for t in s.tables:
            energy = t.title.startswith("Modal kinetic-energy")
            parts.append(html_table(t, shade_from=3 if energy else None))
    parts.append("</body></html>")
    return "\n".join(parts)


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
                fig.savefig(path, dpi=dpi)
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


def default_folder(source: str, model: Model) -> Path:
    """``./vibss-report-<name>``: the file's stem or example name, else the model's name."""
    stem = Path(source).stem if source else model.name
    return Path(f"vibss-report-{slug(stem)}")


def progress_on_stderr() -> Progress:
    """The command line's progress display (``[3/6] damped modes ...`` on stderr)."""
    return _stderr_progress

