"""Figures: mode shapes, their animation, the kinetic-energy table and the model layout.

This subpackage is the only part of vibss that imports matplotlib; the core never imports it
(result objects import it lazily inside their ``.plot()`` methods). Figures are made with
:class:`matplotlib.figure.Figure` and an Agg canvas, not through :mod:`matplotlib.pyplot`, so
they do not pile up in pyplot's global state; show one in a notebook by leaving it as the cell's
value, or save it with ``fig.savefig("modes.png")``.

Lengths are drawn in metres (the model's SI units).
"""

from __future__ import annotations

from .energy import plot_energy
from .layout import plot_model
from .modes import animate_mode, mode_title, plot_modes
from .mounts import plot_dynamic_stiffness
from .frequency import plot_frequency_response, plot_test_overlay
from .response import plot_sweep_envelope, plot_time_groups, plot_time_response
from .summary import plot_poles, plot_reduction, plot_static

__all__ = ["plot_modes", "animate_mode", "plot_energy", "plot_model", "plot_time_groups", "mode_title",
           "plot_frequency_response", "plot_time_response", "plot_sweep_envelope", "plot_static",
           "plot_poles", "plot_reduction", "plot_test_overlay", "plot_dynamic_stiffness"]
