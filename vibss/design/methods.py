"""The optimizers :func:`vibss.design.optimize` can choose from: a registry of :class:`Optimizer`
objects (``METHODS``), each carrying its kernel and the facts the driver reads.

One kernel signature for every entry, so a user's callable gets what the built-ins get::

    kernel(problem, z0, bounds, maxiter) -> scipy.optimize.OptimizeResult

``problem`` is the scaled design problem (:class:`Problem`: objective, its gradient, the
inequality constraints ``g(z) >= 0`` and their Jacobians, on the unit box), ``z0`` the start,
``bounds`` one ``(lower, upper)`` pair per variable, ``maxiter`` the iteration limit.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import scipy.optimize as so

from ..errors import VibssError
from ..methods import Method, callable_name, resolve

__all__ = ["Optimizer", "Problem", "METHODS", "resolve_method", "penalized", "differential_evolution"]


@dataclass
class Problem:
    """The scaled design problem a kernel solves: minimize ``fun`` on the unit box subject to
    ``g(z) >= 0`` for every ``g`` in ``constraints``.

    Attributes
    ----------
    fun : callable
        Objective ``fun(z) -> float`` (minus the mean purity).
    jac : callable or "2-point"
        Its gradient ``jac(z) -> (p,) ndarray``, or scipy's finite differences.
    constraints : list of callable
        Inequality constraints ``g(z) -> (m,) ndarray``, feasible where every entry is >= 0.
    jacobians : list of callable or "2-point"
        Their Jacobians (one per constraint), or scipy's finite differences.
    """

    fun: Callable[[np.ndarray], float]
    jac: Any
    constraints: list[Callable[[np.ndarray], Any]] = field(default_factory=list)
    jacobians: list[Any] = field(default_factory=list)


@dataclass(frozen=True)
class Optimizer(Method):
    """A registry entry of :data:`METHODS`.

    Attributes
    ----------
    global_search : bool
        The driver first runs a penalized differential evolution on the unit box (seeded, the
        given layout among its members) and starts the kernel from its best point.
    label : str
        How results name it (``Optimization.method``); default: its name.
    """

    global_search: bool = False
    label: str = ""


def _slsqp(problem: Problem, z0: np.ndarray, bounds: list[tuple[float, float]], maxiter: int) -> Any:
    constraints = [{"type": "ineq", "fun": f, **({} if j == "2-point" else {"jac": j})}
                   for f, j in zip(problem.constraints, problem.jacobians)]
    return so.minimize(problem.fun, z0, jac=problem.jac, bounds=bounds, constraints=constraints,
                       method="SLSQP", options={"maxiter": maxiter, "ftol": 1e-10})


def _trust_constr(problem: Problem, z0: np.ndarray, bounds: list[tuple[float, float]], maxiter: int) -> Any:
    nl = [so.NonlinearConstraint(f, 0.0, np.inf, jac=j) for f, j in zip(problem.constraints, problem.jacobians)]
    return so.minimize(problem.fun, z0, jac=problem.jac, bounds=bounds, constraints=nl,
                       method="trust-constr", options={"maxiter": maxiter})


METHODS: dict[str, Optimizer] = {m.name: m for m in (
    Optimizer("SLSQP", _slsqp, summary="scipy's SLSQP from each start, exact gradients"),
    Optimizer("trust-constr", _trust_constr, summary="scipy's trust-constr from each start"),
    Optimizer("global", _slsqp, global_search=True, label="differential evolution + SLSQP",
              summary="differential evolution with a quadratic penalty for the constraints (seeded, "
                      "15 x p members, the given layout among them), then SLSQP from its best point"),
)}
"""The optimizers by name (``method=`` of :func:`vibss.design.optimize`)."""


def resolve_method(method: Any) -> Optimizer:
    """The registry entry for ``method``: a name of :data:`METHODS`, an :class:`Optimizer`, or a
    callable with the kernel signature (see the module docstring).

    Parameters
    ----------
    method : str, Optimizer or callable
        What the user passed.

    Returns
    -------
    Optimizer
    """
    return resolve(method, METHODS, where="optimize",
                   custom=lambda fn: Optimizer(callable_name(fn), fn, summary="user callable"))


def penalized(problem: Problem, z: np.ndarray) -> float:
    """Objective plus a quadratic penalty of the violated constraints (1e6 where the layout fails)."""
    try:
        g = (np.concatenate([np.atleast_1d(c(z)) for c in problem.constraints]) if problem.constraints
             else np.zeros(0))
        return float(problem.fun(z)) + 1e3 * float(np.sum(np.minimum(g, 0.0) ** 2))
    except VibssError:
        return 1e6


def differential_evolution(problem: Problem, z0: np.ndarray, seed: int | None, maxiter: int) -> np.ndarray:
    """Best point of a penalized differential evolution on the unit box (modes that repeat or a
    layout that fails count as bad points)."""
    p = len(z0)
    rng = np.random.default_rng(seed)
    init = np.vstack([z0, rng.random((15 * p - 1, p))])
    r = so.differential_evolution(lambda z: penalized(problem, z), [(0.0, 1.0)] * p, init=init, seed=seed,
                                  polish=False, maxiter=maxiter, tol=1e-8)
    return np.asarray(r.x)
