"""The harmonic-balance section: the steady periodic response curve the model file asks for
(``[analysis] harmonic_balance``), with its unstable branches and turning points."""

from __future__ import annotations

from typing import Any

from ...io.harmonicfile import harmonic_balance_arguments, input_quantity
from ...model.units import Units
from ...model.model import Model
from ..section import TITLES, Section


def _harmonic_section(model: Model, figures: bool, results: dict[str, Any]) -> Section:
    spec = (model.settings or {}).get("harmonic_balance")
    if not spec:
        return Section("harmonic", TITLES["harmonic"], skipped=True,
                       note="the model file asks for none ([analysis] harmonic_balance)")
    from ...nonlinear.harmonic import harmonic_balance

    args = harmonic_balance_arguments(spec, model.excitations)
    r = harmonic_balance(model, **args)
    results["harmonic_balance"] = r
    folds = r.turning_table()
    amplitudes = ", ".join(f"{k} = {abs(v):.4g} {Units().label(input_quantity(k) or 'dimensionless')}"
                           for k, v in r.inputs.items())
    figs = (("harmonic_balance.png", r.plot()),) if figures else ()
    return Section("harmonic", TITLES["harmonic"], f"{r.report()}\n\n{folds.render()}", (r.summary(), folds), figs,
                   note=f"sine inputs {amplitudes}, {spec['f1']:g} to {spec['f2']:g} Hz, "
                        f"{spec['harmonics']} harmonics")
