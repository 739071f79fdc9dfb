"""Mount-system design: axes and centres, the decoupling certificate, exact sensitivities, batched
Monte Carlo tolerance studies and optimization of mount layouts.
"""

from __future__ import annotations

from .._deprecated import module_aliases
from .axes import (DesignAxes, ElasticAxes, TorqueResponse, design_axes, elastic_axes, plot_design_axes,
                   principal_axes, torque_response, torque_roll_axis)
from .certificate import Certificate, certificate
from .montecarlo import MonteCarlo, monte_carlo
from .optimize import Optimization, optimize
from .parameters import Parameter
from .sensitivity import Sensitivity, sensitivity
from .grid import grid_study

__all__ = ["grid_study", "Optimization", "optimize", "MonteCarlo", "monte_carlo", "Parameter", "Sensitivity", "sensitivity", "Certificate", "certificate", "ElasticAxes", "TorqueResponse", "elastic_axes", "principal_axes", "torque_response",
           "torque_roll_axis", "DesignAxes", "design_axes", "plot_design_axes"]



__getattr__ = module_aliases(__name__, {
    "Optimisation": ("vibss.design.Optimization", lambda: Optimization),
    "optimise": ("vibss.design.optimize", lambda: optimize),
    "study": ("vibss.design.grid_study (vibss.report.study is the report)", lambda: grid_study)})
