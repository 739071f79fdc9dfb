"""The exact discretisation of a step under a cubic Hermite local force (:mod:`.contact`'s steps).

Over a step ``h`` the modal blocks propagate exactly (:func:`vibss.time.phi.foh_blocks`) under local
forces that are cubic in time, given by their end values and rates. :func:`discretise` returns what a
step needs: the transitions, the local rows after them and the maps from the forces' end values to the
local deflections and velocities at the step's end; the blocks' response to the force polynomial
(:meth:`Step.G`) is formed only for the steps taken, not for the trial sub-steps of a location.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..phi import foh_blocks
from ..recursion import RealProduct

__all__ = ["Step", "discretise", "coefficients"]


@dataclass(frozen=True, eq=False)
class Step:
    """One step's discretisation: ``h`` [s]; per modal set the transitions ``E``, the responses ``gam``
    to each Taylor coefficient of a local force, the forcing ``F`` and the local rows after the
    transition ``HE``; ``Wg``, ``Wc`` the local end values per (g, dg) at the end and at the start."""

    h: float
    E: tuple[np.ndarray, ...]        # (nb, b, b)
    gam: tuple[np.ndarray, ...]      # (4, nb, b): response to each Taylor coefficient (tau^k/k!) of a force
    F: tuple[np.ndarray, ...]        # (nb, r): the system's forcing (not copied)
    HE: tuple[np.ndarray, ...]       # (2r, nb * b): local rows after the transition
    Wg: np.ndarray                   # (2r, 2r) per (g1, dg1) at the end
    Wc: np.ndarray                   # (2r, 2r) per (g0, dg0) at the start
    inverse: dict = field(default_factory=dict, repr=False)   # Newton's inverse per regime (stops only)
    forcing: list = field(default_factory=list, repr=False)

    def G(self) -> list[np.ndarray]:
        """Per set the state per Taylor coefficient of each force, (nb b, 4 r) k-major: formed for the steps
        taken only, not for a location's trial sub-steps."""
        if not self.forcing:        # gam (4, nb, b) F (nb, r) -> (nb, b, 4, r)
            self.forcing[:] = [np.ascontiguousarray(np.moveaxis(gam[:, :, :, None] * F[None, :, None, :], 0, 2)
                                                    .reshape(-1, 4 * F.shape[1])) for gam, F in zip(self.gam, self.F)]
        return self.forcing


def _prepare(sys: Any) -> list[tuple[np.ndarray, np.ndarray, RealProduct]]:
    """Per set, kept on ``sys``: the blocks ``A``, the local rows ``H`` ((2r, nb) for b = 1) and
    ``X -> Re(X @ F)`` as one real GEMM (:class:`~vibss.time.recursion.RealProduct`: half the flops of
    the complex product)."""
    if not sys.prepared:
        sys.prepared[:] = [(A, np.ascontiguousarray(H[:, :, 0]) if A.shape[1] == 1 else H,
                            RealProduct(np.asarray(F).T, np.dtype(complex))) for A, F, H in zip(sys.A, sys.F, sys.H)]
    return sys.prepared


def discretise(sys: Any, h: float) -> Step:
    """The exact discretisation of :class:`~vibss.time.kernels.contact.ContactSystem` ``sys`` over ``h`` [s]."""
    E, gams, HE = [], [], []
    r = sys.D.shape[1]
    S = np.zeros((4, 2 * r, r))
    for A, H, re_F in _prepare(sys):
        e, gam = foh_blocks(A, np.array([h]), 3)
        nb, b = A.shape[:2]
        # S[k]: the local end values per Taylor coefficient k, H gam_k F summed over the blocks
        Hg = H[None] * gam[0][:, None, :, 0] if b == 1 else np.einsum("anj,knj->kan", H, gam[0])
        S += re_F(Hg.reshape(4 * 2 * r, nb)).reshape(4, 2 * r, r)
        HE.append(H * e[0][:, 0, 0] if b == 1 else np.einsum("anc,ncb->anb", H, e[0]).reshape(H.shape[0], -1))
        E.append(e[0])
        gams.append(gam[0])
    # the cubic Hermite force's Taylor coefficients from its end values: a0 = g0, a1 = dg0,
    # a2 = 6 (g1 - g0) / h^2 - (4 dg0 + 2 dg1) / h, a3 = 12 (g0 - g1) / h^3 + 6 (dg0 + dg1) / h^2
    S0, S1, S2, S3 = S
    Wg = np.hstack([6 / h**2 * S2 - 12 / h**3 * S3, -2 / h * S2 + 6 / h**2 * S3])
    Wc = np.hstack([S0 - 6 / h**2 * S2 + 12 / h**3 * S3, S1 - 4 / h * S2 + 6 / h**2 * S3])
    return Step(h, tuple(E), tuple(gams), sys.F, tuple(HE), Wg, Wc)


def coefficients(h: float, g0: np.ndarray, d0: np.ndarray, g1: np.ndarray, d1: np.ndarray) -> np.ndarray:
    """(4, r) Taylor coefficients (per tau^k / k!) of the cubic Hermite force on a step."""
    out = np.empty((4, g0.size))
    out[0], out[1] = g0, d0
    dg = g1 - g0
    out[2] = (6 / h**2) * dg - (4 * d0 + 2 * d1) / h
    out[3] = (-12 / h**3) * dg + (6 / h**2) * (d0 + d1)
    return out
