"""The nonlinear mounts' arithmetic: which mounts are nonlinear, their local deflections from the
DOFs, their forces, tangents and energies, and the tangent model at given deflections."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp

from ..errors import AnalysisError, ModelError
from ..linear.plant.assemble import Assembly, assemble
from ..linear.solve.static import static_solve
from ..model.model import Model
from ..model.mounts import MountType

__all__ = ["nonlinear_mounts", "nonlinear_axes", "tangent_model", "equilibrium", "Equilibrium", "TOLERANCE", "MAX_ITERATIONS"]


def nonlinear_mounts(model: Model) -> list[int]:
    """Indices of the mounts whose type has stops or curves."""
    return [p for p, m in enumerate(model.mounts) if getattr(m.type, "nonlinear", False)]


def nonlinear_axes(model: Model) -> tuple[list[tuple[int, int, int]], list[str]]:
    """The nonlinear mount axes (position among :func:`nonlinear_mounts`, mount index, local axis)
    and their deflection outputs ``mount.<name>.d1|d2|d3``, mount by mount."""
    axes = [(i, p, j) for i, p in enumerate(nonlinear_mounts(model))
            for j, law in enumerate(model.mounts[p].type.laws) if not law.linear]
    return axes, [f"mount.{model.mounts[p].name}.d{j + 1}" for _, p, j in axes]


@dataclass(frozen=True)
class _Laws:
    """The nonlinear mounts' axis laws and the map from q to their local deflections."""

    mounts: np.ndarray            # (k,) mount indices
    rows: Any                     # (3k, n) sparse: local deflections of those mounts from q
    k0: np.ndarray                # (k, 3) the rates the linear assembly used

    def local(self, q: np.ndarray) -> np.ndarray:
        return np.asarray(self.rows @ q).reshape(-1, 3)


def _laws(a: Assembly, idx: list[int]) -> _Laws:

    model = a.model
    B = a.deflection_matrix()[:, :a.n].tocsr()
    blocks = []
    for p in idx:
        t = model.mounts[p].orientation.matrix
        blocks.append(sp.csr_matrix(t.T) @ B[3 * p:3 * p + 3])
    rows = sp.vstack(blocks).tocsr() if blocks else sp.csr_matrix((0, a.n))
    k0 = np.array([model.mounts[p].type.stiffness for p in idx], dtype=float).reshape(-1, 3)
    return _Laws(np.array(idx, dtype=int), rows, k0)


def _evaluate(model: Model, laws: _Laws, d: np.ndarray, what: str) -> np.ndarray:
    """(k, 3) force, tangent or energy of each nonlinear mount axis at local deflections ``d``."""
    out = np.empty_like(d)
    for i, p in enumerate(laws.mounts):
        for j, law in enumerate(model.mounts[p].type.laws):
            out[i, j] = float(getattr(law, what)(d[i, j]))
    return out


def tangent_model(model: Model, local: np.ndarray, mounts: np.ndarray | None = None,
                  floor: float = 0.0) -> Model:
    """The linear model whose nonlinear mounts take their tangent rates at local deflections ``local``.

    Parameters
    ----------
    model : Model
        A model with nonlinear mounts.
    local : (k, 3) ndarray
        Local deflections [m] of its nonlinear mounts (in :func:`nonlinear_mounts` order).
    mounts : (k,) array of int or None
        Their indices (default :func:`nonlinear_mounts`).
    floor : float
        Smallest rate kept on an axis, relative to its unloaded rate (Newton's steps use a small
        floor so that a curve's flat end gives a long step, not a singular matrix).

    Returns
    -------
    Model
        Same bodies, mounts and names; each nonlinear mount gets its own linear type
        ``"<type>@<mount>"`` with the tangent stiffness [N/m] per axis (damping, loss factor and
        rotational rates kept).
    """
    idx = nonlinear_mounts(model) if mounts is None else [int(p) for p in mounts]
    new = list(model.mounts)
    for i, p in enumerate(idx):
        m = model.mounts[p]
        kt = np.array([max(float(law.tangent(local[i, j])), floor * law.stiffness)
                       for j, law in enumerate(m.type.laws)])
        t = m.type
        lin = MountType(f"{t.name}@{m.name}", np.maximum(kt, 0.0), damping=t.damping, loss_factor=t.loss_factor,
                        rotational_stiffness=t.rotational_stiffness, rotational_damping=t.rotational_damping)
        new[p] = dataclasses.replace(m, type=lin)
    return dataclasses.replace(model, mounts=tuple(new))


def _internal(a0: Assembly, model: Model, laws: _Laws, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """Internal force ``f_int(q)`` [N, N m], the nonlinear local deflections and the stored energy [J]."""
    d = laws.local(q)
    kq = a0.K @ q
    f_nl = _evaluate(model, laws, d, "force") - laws.k0 * d          # beyond the linear rate
    e_nl = _evaluate(model, laws, d, "energy") - 0.5 * laws.k0 * d * d
    f = np.asarray(kq).ravel() + np.asarray(laws.rows.T @ f_nl.ravel()).ravel()
    return f, d, float(0.5 * q @ kq + e_nl.sum())


TOLERANCE = 1e-12
"""Converged when the Newton step's energy ``|r^T dq|`` is below this times ``|F^T q|`` (the work
of the loads): about ``TOLERANCE^(1/2)`` relative in q, and the last Newton step, taken, squares it
(it had been left out: the snubbed cabinet's sag was 4.8e-10 off, the floor of its time response
against an event-driven reference)."""

MAX_ITERATIONS = 60
"""Newton steps before the search gives up (a smooth monotone model needs 3-10; a stop that
engages adds a few)."""

_ARMIJO = 1e-4
_FLOOR = 1e-9      # Newton's tangent keeps this fraction of an axis's unloaded rate (a flat curve end)


@dataclass(frozen=True)
class Equilibrium:
    """The static equilibrium of the nonlinear mounts: DOFs [m, rad], their local deflections [m],
    the laws, the Newton steps taken and the last step's energy relative to the loads' work."""

    q: np.ndarray
    d: np.ndarray
    laws: _Laws
    steps: int
    residual: float


def equilibrium(a0: Assembly, f_ext: np.ndarray, where: str = "static") -> Equilibrium:
    """``f_int(q) = f_ext`` for a model with nonlinear mounts: Newton with an Armijo line search on the
    potential (convex for monotone laws), each step the core's static solve of the tangent model.

    Parameters
    ----------
    a0 : Assembly
        The model's assembly (linear mounts, nonlinear ones at their unloaded rates).
    f_ext : (n,) ndarray
        Generalised load [N, N m].
    where : str
        The public function, for messages.

    Returns
    -------
    Equilibrium

    Raises
    ------
    ModelError
        A load beyond a curve's flat end (names the mount and axis).
    AnalysisError
        No convergence in :data:`MAX_ITERATIONS` steps.
    """
    model = a0.model
    laws = _laws(a0, nonlinear_mounts(model))
    q = np.zeros(a0.n)
    f_int, d, energy = _internal(a0, model, laws, q)
    residual, steps = np.inf, 0
    for steps in range(1, MAX_ITERATIONS + 1):
        r = f_ext - f_int
        at = assemble(tangent_model(model, d, laws.mounts, floor=_FLOOR))
        dq = static_solve(at, r).x
        slope = float(r @ dq)                             # -dPi/dalpha at alpha = 0 (> 0: descent)
        work = max(abs(float(f_ext @ q)), abs(slope), np.finfo(float).tiny)
        residual = abs(slope) / work
        if residual <= TOLERANCE and steps > 1 or not np.any(r):
            if np.any(r):           # the step is solved already: taking it squares the error in q
                q = q + dq
                f_int, d, energy = _internal(a0, model, laws, q)
            break
        pi0 = energy - float(f_ext @ q)
        alpha = 1.0
        for _ in range(40):
            trial = q + alpha * dq
            f_t, d_t, e_t = _internal(a0, model, laws, trial)
            if e_t - float(f_ext @ trial) <= pi0 - _ARMIJO * alpha * slope:
                break
            alpha *= 0.5
        q, f_int, d, energy = trial, f_t, d_t, e_t
        _no_equilibrium(model, laws, d, where)
    else:
        raise AnalysisError(f"{where}: Newton's method did not converge in {MAX_ITERATIONS} steps "
                            f"(last step energy {residual:.1e} of the loads' work)")
    return Equilibrium(q, d, laws, steps, residual)


def _no_equilibrium(model: Model, laws: _Laws, d: np.ndarray, where: str) -> None:
    """Refuse when a curved axis has run far past its points where its end slope carries no more force."""
    for i, p in enumerate(laws.mounts):
        m = model.mounts[p]
        for j, law in enumerate(m.type.laws):
            if law.curve is None:
                continue
            lo, hi = law.span
            width = hi - lo
            slope = float(law.tangent(d[i, j]))
            if (d[i, j] > hi + 100 * width or d[i, j] < lo - 100 * width) and slope <= 1e-9 * max(law.stiffness, 1.0):
                end = float(law.force(hi if d[i, j] > hi else lo))
                raise ModelError(f"{where}: mount {m.name!r} axis {'xyz'[j]!r}: the load needs more than "
                                 f"its curve's end force {end:.6g} N (its end slope is zero): no static "
                                 f"equilibrium carries it", argument=m.name, received=float(d[i, j]))



