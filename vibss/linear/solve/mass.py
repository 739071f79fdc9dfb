"""The mass solve ``M x = b``: one Cholesky factorisation of a plant's mass, kept on the plant.

The physical state space (``M^-1 K``, ``M^-1 C``), the diagnostics' ``||A||`` and the eigen path's
residual norms all solve with the mass matrix. :func:`mass_solver` factorises it once per plant
(the plant is frozen, so the factor never goes stale) and is the one place that does.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, cast

import numpy as np
import scipy.linalg as sl
import scipy.sparse as sp
import scipy.sparse.linalg as spl

from ..plant.plant import Plant

__all__ = ["mass_solver", "MassSolver"]

MassSolver = Callable[[Any], np.ndarray]
"""``solve(b) -> M^-1 b`` for ``b`` of shape (n,) or (n, k)."""


def mass_solver(mass: Plant | Any) -> MassSolver:
    """``b -> M^-1 b`` by the Cholesky factor of the mass matrix [1/kg, 1/(kg m^2)].

    Parameters
    ----------
    mass : Plant or (n, n) array_like or sparse matrix
        A plant, whose ``M`` is factorised once and the solver kept in its cache
        (:meth:`~vibss.linear.plant.plant.Plant.cached`, key ``"mass solve"``); or a mass matrix
        [kg, kg m^2], factorised on each call (an eigenproblem's or a reduced model's mass that
        belongs to no plant).

    Returns
    -------
    callable
        ``solve(b)`` for ``b`` (n,) or (n, k): ``M^-1 b``. A dense M is solved by LAPACK
        ``potrf``/``potrs`` (:func:`scipy.linalg.cho_factor`), a sparse one by SuperLU.

    Raises
    ------
    numpy.linalg.LinAlgError
        ``M`` is not positive definite (dense) or is singular (sparse).

    Examples
    --------
    >>> solve = mass_solver(np.diag([4.0, 16.0]))
    >>> solve(np.array([1.0, 1.0])).tolist()
    [0.25, 0.0625]
    """
    if isinstance(mass, Plant):
        plant = mass
        return cast(MassSolver, plant.cached("mass solve", lambda: _factor(plant.M)))
    return _factor(mass)


def _factor(M: Any) -> MassSolver:
    if sp.issparse(M):
        try:
            lu = spl.splu(sp.csc_matrix(M))
        except RuntimeError as exc:             # SuperLU: "Factor is exactly singular"
            raise np.linalg.LinAlgError(f"singular mass matrix ({exc})") from None
        return lambda b: lu.solve(np.asarray(b, float))
    cho = sl.cho_factor(M)
    return lambda b: sl.cho_solve(cho, b)
