"""The control section: the closed loop an active model's ``[control]`` table designs."""

from __future__ import annotations

from typing import Any

from ...model.model import Model
from ..section import TITLES, Section

def _control_section(model: Model, figures: bool, results: dict[str, Any]) -> Section:
    if "control" not in model.settings:
        note = ("the model has actuators but no [control] table (design, gain, disturbances, performance)"
                if model.actuators else "no actuators and no [control] table in the model")
        return Section("control", TITLES["control"], skipped=True, note=note)
    from ...control.filespec import run_control

    r = run_control(model)
    results["control"] = r
    figs = (("control.png", r.plot()),) if figures else ()
    return Section("control", TITLES["control"], r.report(),
                   (r.summary(), r.loop.margin_table(), r.loop.summary()), figs,
                   note=f"{model.settings['control']['design']} loops from the file's [control] table; margins "
                        "loop-at-a-time at the actuator commands")
