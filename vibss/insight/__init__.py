"""Which mode, which mount, which path: energy distributions, modal and path contributions (issue 31).

- :func:`energy_distribution`: each mode's strain, kinetic or dissipative energy shared among the
  mounts (and their local axes) or the bodies (and their DOFs);
- :func:`modal_contributions`: a frequency response split into the terms of the modes (undamped
  modes for classical damping, complex modes otherwise) plus a residual;
- :func:`path_contributions`: the force each mount passes into ground or a body, with its share of
  the total;
- :func:`time_contributions`: a time response split into the responses of the modes plus a
  residual: which modes make each output's peak.
"""

from __future__ import annotations

from .api import energy_distribution, modal_contributions, path_contributions
from .result import EnergyDistribution, ModalContributions, PathContributions
from .time_split import time_contributions
from .time_result import TimeContributions

__all__ = ["energy_distribution", "modal_contributions", "path_contributions", "time_contributions", "EnergyDistribution",
           "ModalContributions", "PathContributions", "TimeContributions"]
