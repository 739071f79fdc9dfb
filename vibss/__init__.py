"""vibss: vibration of flexibly supported rigid multibody systems."""

from __future__ import annotations

from .assemble import Assembly, assemble
from .errors import AnalysisError, ModelError, ModelFileError, VibssError
from .geometry import Orientation
from .model import (DOF_NAMES, GROUND, Body, ControlPoint, Load, Model, Mount, MountType,
                    symmetric)

__version__ = "0.1.0"

__all__ = [
    "AnalysisError", "Assembly", "Body", "ControlPoint", "DOF_NAMES", "GROUND", "Load", "Model",
    "ModelError", "ModelFileError", "Mount", "MountType", "Orientation", "VibssError",
    "assemble", "symmetric",
]
