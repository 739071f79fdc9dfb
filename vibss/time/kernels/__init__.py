"""Numerical methods of the time response (:mod:`vibss.time`): the substituted plant (:mod:`.prepared`),
input kinematics (:mod:`.grid`), the modal exact-FOH recursion (:mod:`.modal`), the z-only state-space
realization with ``forced_response`` (:mod:`.realization`) and ``solve_ivp`` (:mod:`.ivp`).

Formulation shared by every method
----------------------------------
The plant (:class:`vibss.linear.plant.plant.Plant`) is ``M q'' + C q' + K q = F f - (Kz z + Cz z' + Mz z'')``
with outputs ``y = Oq q + Ov q' + Oa q'' + Pz z + Pv z' + Pa z'' + Pf f``. The mass coupling to the
prescribed coordinates is removed by the substitution ``p = q + G z`` with ``G = M^-1 Mz``:

    M p'' + C p' + K p = F f - Kt z - Ct z',   Kt = Kz - K G,  Ct = Cz - C G,

so that no input is ever differentiated twice. The outputs become

    y = Cp p + Cv p' + D0 z + D1 z' + D2 z'' + Df f,
    Cp = Oq - Oa M^-1 K,  Cv = Ov - Oa M^-1 C,
    D0 = Pz - Cp G - Oa M^-1 Kz,  D1 = Pv - Cv G - Oa M^-1 Cz,  D2 = Pa - Oa M^-1 Mz,
    Df = Pf + Oa M^-1 F.

Initial conditions are the state at ``t = 0-``, with every prescribed coordinate at rest at zero;
an input that is nonzero at ``t = 0`` acts as a jump at ``t = 0``. A jump of a prescribed
*displacement* through a damper is an impulse (``p'`` jumps by ``-M^-1 Ct dz``); the modal method
applies it exactly, and in the z-only realization (``xi = p' + M^-1 Ct z``) the state does not jump
at all. At a sample time where an input jumps or kinks, outputs take the right-hand limit (the
left-hand limit at the last sample).
"""

from __future__ import annotations

from .grid import Grid, Kinematics, direct_terms, kinematics, make_grid, nudge
from .ivp import run_ivp
from .modal import channels, run_modal
from ...threads import one_blas_thread
from .prepared import Prepared, prepare
from .realization import Realization, realization, run_forced_response

__all__ = ["Prepared", "Grid", "Kinematics", "prepare", "make_grid", "nudge", "kinematics",
           "run_modal", "run_forced_response", "run_ivp", "realization", "Realization", "channels",
           "direct_terms", "one_blas_thread"]
