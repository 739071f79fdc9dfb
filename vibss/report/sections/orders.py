"""The orders section: the response to rotating sources against speed, with its Campbell diagram."""

from __future__ import annotations

from typing import Any

import numpy as np

from ...model.model import Model
from ..section import TITLES, Section

def _orders_section(model: Model, figures: bool, results: dict[str, Any]) -> Section:
    spec = model.settings.get("orders")
    if not spec:
        return Section("orders", TITLES["orders"], skipped=True, note="no [orders] table in the model")
    if "rpm" not in spec:
        return Section("orders", TITLES["orders"], skipped=True,
                       note="the [orders] table gives no speed range (rpm = [low, high])")
    from ...orders import order_response
    from ...orders.sources import sources_from_settings

    lo, hi = spec["rpm"]
    r = order_response(model, sources_from_settings(model), np.linspace(lo, hi, spec.get("points", 400)),
                       spec.get("outputs"))
    results["orders"] = r
    figs = (("orders.png", r.plot()), ("campbell.png", r.campbell())) if figures else ()
    return Section("orders", TITLES["orders"], r.report(), (r.summary(), r.critical_table()), figs)
