"""Frequency grids: the :class:`FrequencyGrid` specification and the refined grid around the modes
(:func:`frequency_grid`) that :func:`vibss.frequency_response` uses by default."""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validate import choice, integer, number
from ..errors import ModelError
from ..linear.eigen.basis import projected_damping
from ..linear.eigen.basis import ModalBasis, modal_basis
from ..linear.plant.plant import Plant

__all__ = ["FrequencyGrid", "frequency_grid"]

_REFINE = (-4.0, -2.0, -1.0, -0.5, 0.0, 0.5, 1.0, 2.0, 4.0)
_UNDAMPED_ZETA = 1e-4


@dataclass(frozen=True)
class FrequencyGrid:
    """A frequency grid specification.

    Parameters
    ----------
    f1, f2 : float or None
        Band [Hz]; None: from a tenth of the lowest to twice the highest natural frequency.
    points : int
        Number of base points.
    spacing : {"log", "linear"}
        Base spacing. A log grid with ``f1 = 0`` keeps 0 Hz and starts its log part at ``f2 / 1e4``.
    refine : bool
        Add points at each natural frequency ``f_r`` in the band and at ``f_r (1 + k zeta_r)``,
        k = +-0.5, +-1, +-2, +-4 (``zeta_r`` from the modal damping estimate; 1e-4 for undamped
        modes, which then get no point exactly at ``f_r``), so lightly damped peaks are resolved.
    """

    f1: float | None = None
    f2: float | None = None
    points: int = 1000
    spacing: str = "log"
    refine: bool = True

    def _checked(self) -> FrequencyGrid:
        """This grid with its values checked and converted (a ModelError names the bad key)."""
        vals: dict[str, Any] = {}
        for key in ("f1", "f2"):
            v = getattr(self, key)
            vals[key] = v if v is None else number(v, key, who="frequencies", minimum=0.0,
                                                   what="a frequency >= 0 [Hz] or None")
        pts = integer(self.points, "points", who="frequencies", minimum=2)
        choice(self.spacing, "spacing", ("log", "linear"), who="frequencies", expected="'log' or 'linear'")
        return dataclasses.replace(self, f1=vals["f1"], f2=vals["f2"], points=pts,
                                   refine=bool(self.refine))

    @classmethod
    def coerce(cls, spec: Any) -> FrequencyGrid:
        """From a FrequencyGrid, a mapping (keys f1, f2, points, spacing, refine) or None."""
        if spec is None:
            return cls()
        if isinstance(spec, cls):
            return spec._checked()
        if isinstance(spec, Mapping):
            unknown = set(spec) - {"f1", "f2", "points", "spacing", "refine"}
            if unknown:
                raise ModelError(f"frequencies: unknown grid key(s) {sorted(unknown)}; expected "
                                 "f1, f2, points, spacing, refine")
            return cls(**dict(spec))._checked()
        raise ModelError(f"frequencies: expected frequencies in Hz, a grid mapping or None, got {spec!r}")


def frequency_grid(plant: Plant, spec: Any = None, basis: ModalBasis | None = None) -> np.ndarray:
    """Frequencies [Hz] of a grid spec for a plant (sorted, unique, refined at resonances).

    Parameters
    ----------
    plant : Plant
    spec : FrequencyGrid, mapping or None
        See :class:`FrequencyGrid`.
    basis : ModalBasis or None
        Undamped modes, if already computed.

    Returns
    -------
    (nf,) ndarray
        Frequencies [Hz].
    """
    g = FrequencyGrid.coerce(spec)
    basis = basis or modal_basis(plant)
    fr = basis.omega[~basis.rigid] / (2 * np.pi)
    f1 = g.f1 if g.f1 is not None else (0.1 * fr.min() if fr.size else 0.01)
    f2 = g.f2 if g.f2 is not None else (2.0 * fr.max() if fr.size else 100.0)
    if not (np.isfinite(f1) and np.isfinite(f2) and 0 <= f1 < f2) or int(g.points) < 2:
        raise ModelError(f"frequencies: need 0 <= f1 < f2 and points >= 2, got f1={f1}, f2={f2}, "
                         f"points={g.points}")
    if g.spacing == "linear":
        f = np.linspace(f1, f2, int(g.points))
    elif g.spacing == "log":
        lo = f1 if f1 > 0 else f2 * 1e-4
        f = np.geomspace(lo, f2, int(g.points) - (f1 == 0))
        f = np.concatenate([[0.0], f]) if f1 == 0 else f
    else:
        raise ModelError(f"frequencies: spacing must be 'log' or 'linear', got {g.spacing!r}")
    if g.refine and fr.size:
        zeta = _modal_zeta(plant, basis)[~basis.rigid]
        z = np.where(zeta > 0, zeta, _UNDAMPED_ZETA)
        k = np.array(_REFINE)
        extra = fr[:, None] * (1 + k[None, :] * z[:, None])
        extra = np.where((zeta[:, None] == 0) & (k[None, :] == 0), np.nan, extra).ravel()
        extra = extra[np.isfinite(extra) & (extra >= f1) & (extra <= f2)]
        f = np.union1d(f, extra)
    return np.unique(f)


def _modal_zeta(plant: Plant, basis: ModalBasis) -> np.ndarray:
    """Modal damping-ratio estimate per mode: diag(Phi^T C Phi) / 2w + eta / 2."""
    w = np.where(basis.rigid, 1.0, basis.omega)
    gamma, eta = projected_damping(plant, basis)
    return np.abs(np.diag(gamma) / (2 * w) + np.diag(eta) / (2 * w**2))
