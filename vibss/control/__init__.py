"""Isolator controller design on vibss models: generalized plants, designs, closed loops.

- :func:`plant`: the generalized plant ``(w, u) -> (z, y)`` from a model's actuators and sensors;
- designs returning a named :class:`Controller` ``u = K y``: :func:`skyhook`,
  :func:`velocity_feedback`, :func:`integral_force`, :func:`pid`, :func:`lqr`, :func:`lqg`,
  :func:`hinf`;
- :func:`close`: the closed loop, stability checked first, with poles, damping and margins;
- :func:`demand`: actuator force and stroke (RMS under a PSD, peak under a shock);
- :func:`tune`: fixed-structure loops tuned against goals (transmissibility, margins, damping, effort);
- :func:`noise_budget` (``ClosedLoop.noise_budget``): each sensor noise's share of the payload motion;
- :func:`robustness`: Monte Carlo and worst corners of a loop over the mounts' tolerances;
- :func:`clipped_skyhook`: semi-active skyhook simulated in time (a variable damper);
- :func:`interconnect` and :func:`feedback`: python-control's, with vibss names in and out.
"""

from .demand import Demand, demand
from .designs import integral_force, pairs, pid, skyhook, velocity_feedback
from .loop import ClosedLoop, Controller, LoopMargins, close
from .names import feedback, interconnect
from .optimal import hinf, lqg, lqr, weight
from .plant import GeneralizedPlant, plant
from .noise import NoiseBudget, noise_budget
from .robust import Robustness, robustness
from .tune import Tuning, tune
from .semiactive import SemiActiveResponse, clipped_skyhook

__all__ = ["plant", "GeneralizedPlant", "skyhook", "velocity_feedback", "integral_force", "pid",
           "lqr", "lqg", "hinf", "weight", "close", "ClosedLoop", "Controller", "LoopMargins",
           "clipped_skyhook", "SemiActiveResponse", "interconnect", "feedback", "pairs", "demand", "Demand",
           "robustness", "Robustness", "tune", "Tuning", "noise_budget", "NoiseBudget"]
