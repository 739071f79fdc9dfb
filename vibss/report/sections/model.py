"""The model section: bodies, mount types, mounts, supports, control points and excitations, with
the layout figures."""

from __future__ import annotations

from typing import Any

import numpy as np

from ...model.model import Model
from ...results import TextTable
from ..section import TITLES, Section

def _model_section(model: Model, figures: bool) -> Section:
    bodies = TextTable(["body", "mass [kg]", "Ixx", "Iyy", "Izz", "Ixy", "Ixz", "Iyz", "COG x [m]",
                    "COG y [m]", "COG z [m]"],
                   [[b.name, " ".join(f"{m:.4g}" for m in np.unique(b.masses))]
                    + [f"{b.tensor[i, j]:.4g}" for i, j in ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))]
                    + [f"{c:.4g}" for c in b.cog] for b in model.bodies],
                   title="Bodies (inertia tensor about the COG in global axes [kg m^2]; "
                         "off-diagonals are minus the products of inertia)")
    rotational = any(t.rotational for t in model.mount_types.values())
    types = TextTable(["mount type", "k1 [N/m]", "k2 [N/m]", "k3 [N/m]", "c1 [N s/m]", "c2 [N s/m]",
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
    mounts = TextTable(["mount", "type", "joins", "x [m]", "y [m]", "z [m]", "orientation"],
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
        tables.append(TextTable(["mount type", "matrix", "row"] + list(labels),
                            [[t.name, key, labels[i]] + [f"{v:.4g}" for v in t.local_matrix(key)[i]]
                             for t, key in full for i in range(6)],
                            title="Full 6x6 mount matrices in local axes (on d1..d3 [m], r1..r3 [rad]: "
                                  "N/m, N m/rad, coupling N/rad; damping N s/m, N m s/rad, N s/rad)"))
    if model.supports:
        tables.append(TextTable(["support", "mounts", "description"],
                            [[g.name, ", ".join(m.name for m in model.mounts if m.support == g.name), g.description]
                             for g in model.supports],
                            title="Supports (ground points moved on their own: inputs <support>.<dof>.disp|vel|acc)"))
    if model.control_points:
        pts = [[c.name, c.body] + [f"{v:.4g}" for v in model.body(c.body).cog + model.point(c.body, c.at, c.frame)]
               for c in model.control_points]
        tables.append(TextTable(["point", "body", "x [m]", "y [m]", "z [m]"], pts, title="Control points"))
    if model.excitations:
        rows = [[e.name, e.kind, e.target, e.dof or "direction " + str(np.round(e.direction, 3).tolist()),
                 type(e.function).__name__, _function_parameters(e.function.to_dict(), e.unit), e.unit]
                for e in model.excitations]
        tables.append(TextTable(["excitation", "kind", "target", "dof", "function", "parameters", "unit"], rows,
                            title="Excitations (amplitudes in the unit column, times in s, frequencies in Hz)"))
    nb = len(model.bodies)
    text = (f"{nb} bod{'y' if nb == 1 else 'ies'}, {len(model.mounts)} mounts, total mass "
            f"{model.total_mass:.4g} kg" + ("" if model.gravity is None else
                                             f", gravity {model.gravity.tolist()} m/s^2"))
    figs: tuple[tuple[str, Any], ...] = ()
    if figures:
        from ...plotting import plot_model

        figs = (("model.png", plot_model(model)), ("model_views.png", plot_model(model, view="three")))
        if any(t.rheology is not None for t in model.mount_types.values()):
            from ...plotting import plot_dynamic_stiffness

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

    from ...model.geometry import DEFAULT_SEQUENCE

    a = Rotation.from_matrix(o.matrix).as_euler(DEFAULT_SEQUENCE, degrees=True)
    return f"{DEFAULT_SEQUENCE} ({a[0]:.2f}, {a[1]:.2f}, {a[2]:.2f}) deg"


_PARAMETER_UNITS = {"start": "s", "end": "s", "duration": "s", "sweep_time": "s", "f1": "Hz", "f2": "Hz",
                    "frequency": "Hz", "phase": "rad"}


def _function_parameters(d: dict[str, Any], unit: str) -> str:
    """A time function's parameters as one line: ``amplitude 490.5 m/s^2 (50 g), duration 0.011 s``."""
    from ...model.units import STANDARD_GRAVITY

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
