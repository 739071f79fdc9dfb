"""The substituted plant every time method runs on (``p = q + G z``, :mod:`vibss.time.kernels`)."""

from __future__ import annotations

from dataclasses import dataclass, fields
from typing import cast

import numpy as np

from ...linear.solve.mass import mass_solver
from ...linear.eigen.checks import _six_blocks
from ...linear.plant.plant import Plant

__all__ = ["Prepared", "prepare"]


@dataclass(frozen=True, eq=False)
class Prepared:
    """Plant after the substitution ``p = q + G z`` (see the module docstring); SI, n DOFs, m inputs."""

    plant: Plant
    G: np.ndarray     # (n, m)
    Kt: np.ndarray    # (n, m)
    Ct: np.ndarray    # (n, m)
    Cp: np.ndarray    # (p, n)
    Cv: np.ndarray    # (p, n)
    D0: np.ndarray    # (p, m) per z
    D1: np.ndarray    # (p, m) per z'
    D2: np.ndarray    # (p, m) per z''
    Df: np.ndarray    # (p, m) per f
    force: np.ndarray  # (m,) bool
    kinds: tuple[str, ...]


def prepare(plant: Plant) -> Prepared:
    """Substituted matrices of ``plant`` (see the module docstring); computed once per plant (the
    plant is frozen), its arrays read-only."""
    return cast(Prepared, plant.cached("prepared", lambda: _prepare(plant)))


def _prepare(plant: Plant) -> Prepared:
    M = np.asarray(plant.M, float)
    blocks = _six_blocks(M) if M.shape[0] > 150 else None
    if blocks is not None:       # rigid bodies: M^-1 by the 6x6 blocks' Cholesky factors
        lib = np.linalg.inv(np.linalg.cholesky(blocks))
        lit = np.ascontiguousarray(np.swapaxes(lib, 1, 2))
        inv = lambda X: np.matmul(lit, np.matmul(lib, np.asarray(X, float).reshape(lib.shape[0], 6, -1))  # noqa: E731
                                  ).reshape(np.shape(X))
    else:
        solve = mass_solver(plant)
        inv = lambda X: solve(np.asarray(X, float))  # noqa: E731
    motion = np.array([k != "force" for k in plant.kinds])
    G = inv(plant.Mz) * motion
    K, C = np.asarray(plant.K, float), np.asarray(plant.C, float)
    Kt = plant.Kz - K @ G
    Ct = plant.Cz - C @ G
    Oa = np.asarray(plant.Oa, float)
    has_oa = bool(np.any(Oa))
    OaMi = inv(Oa.T).T if has_oa else np.zeros_like(Oa)
    Cp = plant.Oq - OaMi @ K
    Cv = plant.Ov - OaMi @ C
    out = Prepared(
        plant=plant, G=G, Kt=Kt, Ct=Ct, Cp=Cp, Cv=Cv,
        D0=plant.Pz - Cp @ G - OaMi @ plant.Kz,
        D1=plant.Pv - Cv @ G - OaMi @ plant.Cz,
        D2=plant.Pa - OaMi @ plant.Mz,
        Df=plant.Pf + OaMi @ plant.F,
        force=~motion, kinds=tuple(plant.kinds))
    for f in fields(out):
        value = getattr(out, f.name)
        if isinstance(value, np.ndarray):
            value.flags.writeable = False
    return out
