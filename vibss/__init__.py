"""vibss: vibration of flexibly supported rigid multibody systems.

Describe rigid bodies and the mounts between them and ground; vibss assembles M, C, K and runs
static deflection, undamped and damped modes, frequency and time responses on them.

Examples
--------
>>> import vibss
>>> t = vibss.MountType("rubber", stiffness=[1e4, 2e4, 3e4])
>>> body = vibss.Body("prism", mass=1000.0, inertia=[10.0, 20.0, 30.0])
>>> model = vibss.Model([body], vibss.symmetric(vibss.Mount("m", t, "prism", at=[1, 2, 0])))
>>> vibss.modes(model).frequency_hz.round(2)
array([ 1.01,  1.42,  1.74, 12.33, 14.24, 34.87])
"""

from __future__ import annotations

import importlib
import importlib.util
from typing import TYPE_CHECKING, Any

from .errors import (AnalysisError, ArgumentError, ControlDesignError, DefectiveModesError,
                     MissingDependencyError, ModelError, ModelFileError, SignalError, VibssError, VibssWarning)

# Public names, loaded on first use (PEP 562) so that ``import vibss`` stays light: python-control,
# matplotlib, pandas and the heavy SciPy submodules load only when a function needs them.
# A new public name: one line here (name -> module) and one in __all__ (tests/project/test_startup.py
# checks that every name resolves).
_LAZY: dict[str, str] = {
    "Assembly": ".linear.plant.assemble", "assemble": ".linear.plant.assemble",
    "DampedModes": ".modal.result", "damped_modes": ".modal.api",
    "Excitation": ".model.excitation",
    # time functions of excitations (vibss.model.timefunctions)
    "TimeFunction": ".model.timefunctions",
    "Step": ".model.timefunctions",
    "Rectangular": ".model.timefunctions",
    "HalfSine": ".model.timefunctions",
    "Haversine": ".model.timefunctions",
    "Triangle": ".model.timefunctions",
    "Sawtooth": ".model.timefunctions",
    "Ramp": ".model.timefunctions",
    "Sine": ".model.timefunctions",
    "SineSweep": ".model.timefunctions",
    "Table": ".model.timefunctions",
    "Sum": ".model.timefunctions",

    "Orientation": ".model.geometry",
    "dump_model": ".io.modelfile", "dumps_model": ".io.modelfile", "example_names": ".io.modelfile",
    "load_example": ".io.modelfile", "load_model": ".io.modelfile", "loads_model": ".io.modelfile",
    "Modes": ".modal.result", "modes": ".modal.api",
    "track_modes": ".modal.tracking",
    "DOF_NAMES": ".model.model", "GROUND": ".model.model", "Body": ".model.model",
    "ControlPoint": ".model.model", "Load": ".model.model", "Model": ".model.model",
    "Mount": ".model.model", "MountType": ".model.model", "Support": ".model.model",
    "symmetric": ".model.model",
    "Actuator": ".model.actuation", "Sensor": ".model.actuation",
    "FrequencyGrid": ".frequency.grid", "FrequencyResponse": ".frequency.result",
    "frequency_grid": ".frequency.grid", "frequency_response": ".frequency.api",
    "sweep_response": ".frequency.sweep", "transmissibility": ".frequency.sweep",
    "Plant": ".linear.plant.plant",
    "Reduction": ".reduction.result", "reduce": ".reduction.api",
    "Scope": ".reduction.scope",
    "build_plant": ".linear.plant.build",
    "NamedStateSpace": ".linear.statespace", "statespace": ".linear.statespace",
    "StaticResult": ".statics", "static": ".statics",
    "operating_point": ".nonlinear.api", "OperatingPoint": ".nonlinear.result",
    "harmonic_balance": ".nonlinear.harmonic", "HarmonicBalanceResult": ".nonlinear.result",
    "StudyDefaults": ".studies", "study_defaults": ".studies", "causal_loss": ".studies",
    "TimeResponse": ".time.result", "simulate": ".time.api",
    "SweepEnvelope": ".time.sweep", "sweep_envelope": ".time.sweep",
    "grid_study": ".design.grid",
    "energy_distribution": ".insight.api", "modal_contributions": ".insight.api",
    "path_contributions": ".insight.api", "time_contributions": ".insight.time_split",
    "srs": ".shock.api", "ShockResponseSpectrum": ".shock.result",
    "random_response": ".random", "PSD": ".random",
    "fit_rheology": ".measured.api", "Foundation": ".measured.fbs", "blocked_forces": ".measured.blocked",
    "update": ".measured.update", "MeasuredModes": ".measured.modes",
    # subpackages
    "design": ".design",            # vibss.design.*: mount-system design
    "shock": ".shock",              # vibss.shock.*: shock pulses and the SRS
    "orders": ".orders",            # vibss.orders.*: rotating unbalance and engine orders
    "random": ".random",            # vibss.random.*: random vibration
    "control": ".control",          # vibss.control.*: isolator controller design
}
_MODULES = {"design", "shock", "orders", "random", "control"}


_RENAMED = {"study": "grid_study"}
"""Old public names, kept for one release with a DeprecationWarning (issue 28)."""


def __getattr__(name: str) -> Any:
    if name in _RENAMED:
        from ._deprecated import warn
        warn(f"vibss.{name}", f"vibss.{_RENAMED[name]}")
        return __getattr__(_RENAMED[name])
    module = _LAZY.get(name)
    if module is None:                     # a subpackage (vibss.io, vibss.linear, vibss.plotting ...)
        if name.startswith("_") or importlib.util.find_spec(f"{__name__}.{name}") is None:
            raise AttributeError(f"module 'vibss' has no attribute {name!r}")
        module = f".{name}"
    mod = importlib.import_module(module, __name__)
    value = mod if name in _MODULES or module == f".{name}" else getattr(mod, name)
    globals()[name] = value                # later lookups skip __getattr__
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY))


if TYPE_CHECKING:                          # what static checkers and IDEs see
    from . import control, design, orders, random, shock
    from .model.actuation import Actuator, Sensor
    from .shock.result import ShockResponseSpectrum
    from .design.grid import grid_study
    from .insight.api import energy_distribution, modal_contributions, path_contributions
    from .insight.time_split import time_contributions
    from .frequency.api import frequency_response
    from .measured.api import fit_rheology
    from .measured.fbs import Foundation
    from .measured.modes import MeasuredModes
    from .measured.update import update
    from .measured.blocked import blocked_forces
    from .frequency.grid import FrequencyGrid, frequency_grid
    from .frequency.result import FrequencyResponse
    from .frequency.sweep import sweep_response, transmissibility
    from .io.modelfile import dump_model, dumps_model, example_names, load_example, load_model, loads_model
    from .linear.plant.assemble import Assembly, assemble
    from .linear.plant.plant import Plant
    from .linear.plant.build import build_plant
    from .linear.statespace import NamedStateSpace, statespace
    from .modal.api import damped_modes, modes
    from .modal.result import DampedModes, Modes
    from .modal.tracking import track_modes
    from .model.excitation import Excitation
    from .model.timefunctions import (HalfSine, Haversine, Ramp, Rectangular, Sawtooth, Sine, SineSweep, Step,
                                      Sum, Table, TimeFunction, Triangle)
    from .model.geometry import Orientation
    from .model.model import DOF_NAMES, GROUND, Body, ControlPoint, Load, Model, Mount, MountType, Support, symmetric
    from .reduction.api import reduce
    from .reduction.result import Reduction
    from .reduction.scope import Scope
    from .random import PSD, random_response
    from .shock.api import srs
    from .nonlinear.api import operating_point
    from .nonlinear.harmonic import harmonic_balance
    from .nonlinear.result import HarmonicBalanceResult, OperatingPoint
    from .statics import StaticResult, static
    from .studies import StudyDefaults, causal_loss, study_defaults
    from .time.api import simulate
    from .time.result import TimeResponse
    from .time.sweep import SweepEnvelope, sweep_envelope

from ._version import __version__  # noqa: E402  (written once, in vibss/_version.py)

__all__ = [
    "HalfSine", "Haversine", "Ramp", "Rectangular", "Sawtooth", "Sine", "SineSweep", "Step", "Sum", "Table",
    "TimeFunction", "Triangle", "Actuator", "Sensor", "ShockResponseSpectrum", "ControlDesignError", "control",
    "AnalysisError", "ArgumentError", "Assembly", "DefectiveModesError", "Body", "ControlPoint", "DOF_NAMES", "DampedModes", "Excitation",
    "Foundation", "FrequencyGrid", "MeasuredModes", "update", "FrequencyResponse", "GROUND", "Load", "MissingDependencyError", "Model", "ModelError", "ModelFileError", "Modes", "Mount", "MountType", "NamedStateSpace",
    "Orientation", "PSD", "Plant", "Reduction", "Scope", "SignalError", "StaticResult", "StudyDefaults", "Support", "SweepEnvelope", "TimeResponse", "VibssError", "VibssWarning", "assemble", "build_plant", "damped_modes", "dump_model",
    "blocked_forces", "dumps_model", "energy_distribution", "example_names", "fit_rheology", "frequency_grid", "frequency_response", "load_example", "load_model", "loads_model", "modal_contributions", "modes", "operating_point", "OperatingPoint", "harmonic_balance", "HarmonicBalanceResult", "orders", "path_contributions", "random", "random_response", "reduce", "shock", "simulate", "srs", "static", "time_contributions", "track_modes",
    "statespace", "grid_study", "study_defaults", "causal_loss", "sweep_envelope", "sweep_response", "symmetric", "transmissibility",
]
