"""Which terms of a plant's inputs and outputs are nonzero, found once per plant.

The exact solve (:mod:`vibss.linear.solve.exact`) skips the zero terms of ``F - (Kz + iHz + s Cz + s^2 Mz) Z``
and ``O(s) X + P(s) Z + Pf``; testing each map with ``np.any`` on every call cost about twenty small
reductions per frequency response (a tenth of a 12-DOF call). A plant is frozen (its arrays are
read-only in place, :class:`~vibss.linear.plant.plant.Plant`), so the tests are made once and kept in its
cache; the arithmetic on the kept terms is the same as before, in the same order.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...results import ReadOnly
from .plant import Plant

__all__ = ["PlantTerms", "plant_terms"]


@dataclass(frozen=True)
class PlantTerms(ReadOnly):
    """The nonzero terms of a plant's input and output maps (read-only, like the plant's arrays).

    Attributes
    ----------
    kz : (n, m) ndarray
        ``Kz + i Hz`` where ``Hz`` is nonzero, else ``Kz`` [N/m].
    motion : tuple of (int, ndarray)
        ``(power, map)`` of the nonzero motion-input maps ``kz, Cz, Mz`` (powers 0, 1, 2 of ``s``).
    outputs : tuple of (int, ndarray)
        ``(power, map)`` of the nonzero output maps ``Oq (+ i Oh), Ov, Oa``.
    p0 : (p, m) ndarray
        ``Pz + i Ph`` where ``Ph`` is nonzero, else ``Pz``.
    feedthrough : bool
        ``p0``, ``Pv`` or ``Pa`` is nonzero.
    forces : (n, m) complex ndarray
        ``F`` as complex [N, N m per unit input].
    """

    kz: np.ndarray
    motion: tuple[tuple[int, np.ndarray], ...]
    outputs: tuple[tuple[int, np.ndarray], ...]
    p0: np.ndarray
    feedthrough: bool
    forces: np.ndarray


def _hyst(a: np.ndarray | None) -> np.ndarray | float:
    return 0.0 if a is None or not np.any(a) else a


def plant_terms(plant: Plant) -> PlantTerms:
    """The :class:`PlantTerms` of ``plant``, computed once and kept in its cache.

    Parameters
    ----------
    plant : Plant

    Returns
    -------
    PlantTerms
    """
    return plant.cached("nonzero terms", lambda: _make(plant))


def _make(plant: Plant) -> PlantTerms:
    kz = plant.Kz + 1j * plant.Hz if np.any(plant.Hz) else plant.Kz
    motion = tuple((power, c) for power, c in ((0, kz), (1, plant.Cz), (2, plant.Mz)) if np.any(c))
    oh, ph = _hyst(plant.Oh), _hyst(plant.Ph)
    oq = plant.Oq + 1j * oh if np.any(oh) else plant.Oq
    outputs = tuple((power, o) for power, o in ((0, oq), (1, plant.Ov), (2, plant.Oa)) if np.any(o))
    p0 = plant.Pz + 1j * ph if np.any(ph) else plant.Pz
    feed = bool(np.any(p0) or np.any(plant.Pv) or np.any(plant.Pa))
    return PlantTerms(kz, motion, outputs, p0, feed,
                      np.asarray(plant.F, dtype=complex))
