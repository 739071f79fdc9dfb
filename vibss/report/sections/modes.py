"""The modal sections: undamped modes with their kinetic-energy table and, beside it, the mounts' share of
each mode's strain energy (:func:`vibss.insight.energy_distribution`); and the damped modes."""

from __future__ import annotations

from typing import Any

import numpy as np

from ...insight.api import energy_distribution
from ...modal.api import damped_modes
from ...modal.api import modes
from ...model.model import Model
from ..section import MAX_MODE_PANELS, TITLES, Section

def _modes_section(model: Model, figures: bool, results: dict[str, Any]) -> Section:
    m = modes(model)
    results["modes"] = m
    strain = energy_distribution(m, "strain")
    results["strain energy"] = strain
    figs: list[tuple[str, Any]] = []
    note = ""
    if figures:
        from ...plotting import plot_energy, plot_modes

        which = list(range(min(len(m), MAX_MODE_PANELS)))
        if len(m) > MAX_MODE_PANELS:
            note = f"figures show the lowest {MAX_MODE_PANELS} of {len(m)} modes"
        figs = [("modes.png", plot_modes(m, which=which)),
                ("modes_views.png", plot_modes(m, which=which[:6], view="three")),
                ("energy.png", plot_energy(m, which=which)),
                ("strain_energy.png", strain.plot())]
    return Section("modes", TITLES["modes"], m.report() + "\n\n" + strain.table().render(),
                   (m.frequency_table(), m.shape_table(), m.energy_table(), strain.table()), tuple(figs), note)


def _damped_section(model: Model, figures: bool, results: dict[str, Any]) -> Section:
    if not any(np.any(t.damping > 0) for t in model.mount_types.values()):
        return Section("damped", TITLES["damped"], skipped=True,
                       note="no viscous damping in the mounts: the damped modes are the undamped ones")
    d = damped_modes(model, undamped=results.get("modes"))
    results["damped"] = d
    return Section("damped", TITLES["damped"], d.report(), (d.table(),), note=d.method)
