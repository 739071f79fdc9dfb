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

from .linear.assemble import Assembly, assemble
from .modal.damped import DampedModes, damped_modes
from .errors import (AnalysisError, ArgumentError, DefectiveModesError, MissingDependencyError, ModelError,
                     ModelFileError, SignalError, VibssError, VibssWarning)
from .model.excitation import Excitation
from .model.geometry import Orientation
from .io.modelfile import (dump_model, dumps_model, example_names, load_example, load_model,
                 loads_model)
from .modal.undamped import Modes, modes
from .model.model import (DOF_NAMES, GROUND, Body, ControlPoint, Load, Model, Mount, MountType,
                    symmetric)
from .frequency.api import FrequencyGrid, FrequencyResponse, frequency_grid, frequency_response
from .frequency.sweep import sweep_response, transmissibility
from .linear.plant import Plant
from .reduction.api import Reduction, reduce
from .reduction.scope import Scope
from .linear.signals import build_plant
from .linear.statespace import NamedStateSpace, statespace
from .statics import StaticResult, static
from .studies import StudyDefaults, study_defaults
from .time.api import TimeResponse, simulate
from .time.sweep import SweepEnvelope, sweep_envelope
from . import design  # vibss.design.*: mount-system design
from .design.study import study
from . import shock
from . import orders  # vibss.orders.*: rotating unbalance and engine orders
from .shock import srs

__version__ = "0.1.0"

__all__ = [
    "AnalysisError", "ArgumentError", "Assembly", "DefectiveModesError", "Body", "ControlPoint", "DOF_NAMES", "DampedModes", "Excitation",
    "FrequencyGrid", "FrequencyResponse", "GROUND", "Load", "MissingDependencyError", "Model", "ModelError", "ModelFileError", "Modes", "Mount", "MountType", "NamedStateSpace",
    "Orientation", "Plant", "Reduction", "Scope", "SignalError", "StaticResult", "StudyDefaults", "SweepEnvelope", "TimeResponse", "VibssError", "VibssWarning", "assemble", "build_plant", "damped_modes", "dump_model",
    "dumps_model", "example_names", "frequency_grid", "frequency_response", "load_example", "load_model", "loads_model", "modes", "orders", "reduce", "shock", "simulate", "srs", "static",
    "statespace", "study", "study_defaults", "sweep_envelope", "sweep_response", "symmetric", "transmissibility",
]
