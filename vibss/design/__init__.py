"""Mount-system design: axes and centres, the decoupling certificate, exact sensitivities, batched
Monte Carlo tolerance studies and optimisation of mount layouts.
"""

from __future__ import annotations

from .axes import (DesignAxes, ElasticAxes, TorqueResponse, design_axes, elastic_axes, plot_design_axes,
                   principal_axes, torque_response, torque_roll_axis)
from .certificate import Certificate, certificate
from .montecarlo import MonteCarlo, monte_carlo
from .optimise import Optimisation, optimise
from .parameters import Parameter
from .sensitivity import Sensitivity, sensitivity
from .study import study

__all__ = ["study", "Optimisation", "optimise", "MonteCarlo", "monte_carlo", "Parameter", "Sensitivity", "sensitivity", "Certificate", "certificate", "ElasticAxes", "TorqueResponse", "elastic_axes", "principal_axes", "torque_response",
           "torque_roll_axis", "DesignAxes", "design_axes", "plot_design_axes"]
