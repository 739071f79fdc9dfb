"""The operating point: where a model with nonlinear mounts sits under its static loads.

The equilibrium minimises the potential ``Pi(q) = sum of the mounts' stored energies - F^T q``
(gravity and the model's static loads ``F``), which is convex when every force-deflection law is
monotone: Newton's method with an Armijo line search on ``Pi`` converges from ``q = 0``. Each
Newton step solves the tangent model's ``K_t dq = F - f_int(q)`` with the static solve of the core
(the mounts' form, so stiff links beside soft mounts keep their digits); the internal force is
summed mount by mount from each axis's law.

:func:`operating_point` returns an :class:`OperatingPoint`: the static result at the equilibrium,
the clearance left per stop, and :attr:`OperatingPoint.tangent`, a linear :class:`~vibss.Model`
with the same body and mount names whose nonlinear mounts are replaced by their tangent rates
there, so every linear analysis applies to the loaded model unchanged.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from ..errors import AnalysisError, ModelError
from ..linear.plant.assemble import Assembly, assemble
from ..model.model import Model
from ..model.mounts import Mount, MountType
from ..results import Result, Table
from ..linear.solve.static import static_solve
from ..statics import StaticResult, static

__all__ = ["OperatingPoint", "operating_point", "nonlinear_mounts", "tangent_model", "TOLERANCE", "MAX_ITERATIONS"]

TOLERANCE = 1e-12
"""Converged when the Newton step's energy ``|r^T dq|`` is below this times ``|F^T q|`` (the work
of the loads): about ``TOLERANCE^(1/2)`` relative in q, and Newton's next step squares it."""

MAX_ITERATIONS = 60
"""Newton steps before the search gives up (a smooth monotone model needs 3-10; a stop that
engages adds a few)."""

_ARMIJO = 1e-4
_FLOOR = 1e-9      # Newton's tangent keeps this fraction of an axis's unloaded rate (a flat curve end)


def nonlinear_mounts(model: Model) -> list[int]:
    """Indices of the mounts whose type has stops or curves."""
    return [p for p, m in enumerate(model.mounts) if getattr(m.type, "nonlinear", False)]


@dataclass(frozen=True)
class _Laws:
    """The nonlinear mounts' axis laws and the map from q to their local deflections."""

    mounts: np.ndarray            # (k,) mount indices
    rows: Any                     # (3k, n) sparse: local deflections of those mounts from q
    k0: np.ndarray                # (k, 3) the rates the linear assembly used

    def local(self, q: np.ndarray) -> np.ndarray:
        return np.asarray(self.rows @ q).reshape(-1, 3)


def _laws(a: Assembly, idx: list[int]) -> _Laws:
    import scipy.sparse as sp

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


@dataclass(frozen=True, eq=False)
class OperatingPoint(Result):
    """The static equilibrium of a model with nonlinear mounts, and its tangent model.

    Follows the result protocol: ``op['engine.z']`` is a DOF's deflection [m or rad].

    Attributes
    ----------
    model : Model
        The nonlinear model.
    static : StaticResult
        Deflections, mount deflections and forces at the equilibrium (forces from each axis's law).
    tangent : Model
        Linear model with the tangent rates there (same names): every linear analysis applies.
    clearance : dict of str to float
        Clearance left per stop, ``"<mount>.<axis>"`` -> [m] (negative: in contact, by that much).
    stop_force : dict of str to float
        Force each stop carries [N] (0 when not in contact).
    iterations : int
        Newton steps taken.
    residual : float
        Final ``|r^T dq| / |F^T q|`` [-].
    note : str
        How it was found.
    """

    signal_kind: ClassVar[str] = "DOF"

    model: Model
    static: StaticResult
    tangent: Model
    clearance: dict
    stop_force: dict
    iterations: int
    residual: float
    note: str = ""
    method: str = "newton"

    @property
    def q(self) -> np.ndarray:
        """(n,) deflection of every body DOF at the equilibrium [m, rad]."""
        return self.static.q

    @property
    def output_labels(self) -> tuple[str, ...]:
        return self.static.output_labels

    @property
    def units(self) -> tuple[str, ...]:
        return self.static.units

    def _item(self, i: int, j: int | None) -> float:
        return float(self.static.q[i])

    def rates(self) -> Table:
        """Tangent rates of the nonlinear mounts against their unloaded rates [N/m]."""
        rows = []
        tangent = {m.name: m for m in self.tangent.mounts}
        for m in self.model.mounts:
            if not getattr(m.type, "nonlinear", False):
                continue
            kt = tangent[m.name].type.stiffness
            for j, ax in enumerate("xyz"):
                k0 = m.type.stiffness[j]
                rows.append([m.name, ax, f"{k0:.4g}", f"{kt[j]:.4g}", f"{kt[j] / k0:.3f}" if k0 else "-"])
        return Table(["mount", "axis", "unloaded [N/m]", "tangent [N/m]", "ratio"], rows,
                     title="Tangent rates at the operating point")

    def summary(self) -> Table:
        rows = [[key, f"{1e3 * c:.3f}", f"{self.stop_force[key]:.4g}"] for key, c in self.clearance.items()]
        return Table(["stop", "clearance left [mm]", "stop force [N]"], rows, title="Stops at the operating point")

    def report(self) -> str:
        head = f"Operating point of {self.model.name!r}: {self.iterations} Newton steps, residual {self.residual:.1e}"
        parts = [head, self.static.summary().render(), self.rates().render()]
        if self.clearance:
            parts.append(self.summary().render())
        return "\n\n".join(parts)

    def to_dict(self) -> dict[str, Any]:
        return {"static": self.static.to_dict(), "clearance": dict(self.clearance),
                "stop_force": dict(self.stop_force), "iterations": self.iterations,
                "residual": self.residual, "note": self.note}

    def to_pandas(self) -> Any:
        return self.static.to_pandas()

    def plot(self, ax: Any = None) -> Any:
        """The static deflection's bar chart (:meth:`StaticResult.plot`)."""
        return self.static.plot(ax=ax)


def _internal(a0: Assembly, model: Model, laws: _Laws, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """Internal force ``f_int(q)`` [N, N m], the nonlinear local deflections and the stored energy [J]."""
    d = laws.local(q)
    kq = a0.K @ q
    f_nl = _evaluate(model, laws, d, "force") - laws.k0 * d          # beyond the linear rate
    e_nl = _evaluate(model, laws, d, "energy") - 0.5 * laws.k0 * d * d
    f = np.asarray(kq).ravel() + np.asarray(laws.rows.T @ f_nl.ravel()).ravel()
    return f, d, float(0.5 * q @ kq + e_nl.sum())


def operating_point(model: Model, load: np.ndarray | None = None, *, gravity: bool = True,
                    case: str | None = None) -> OperatingPoint:
    """The static equilibrium of a model with nonlinear mounts (stops, curves), and its tangent model.

    Parameters
    ----------
    model : Model
        The system; linear mounts stay linear.
    load : (n,) array_like or None
        Generalised static load [N, N m]; default the model's loads (and self-weight).
    gravity : bool
        Include self-weight when the model defines gravity (with ``load=None``).
    case : str or None
        Load case, as :func:`vibss.static`.

    Returns
    -------
    OperatingPoint

    Raises
    ------
    ModelError
        A load no equilibrium can carry: the message names the mount and axis whose curve ran out
        of force.
    AnalysisError
        Newton's method did not converge in :data:`MAX_ITERATIONS` steps.

    Examples
    --------
    >>> from vibss import Body, Mount, MountType, Model
    >>> t = MountType("snub", [1e5, 1e5, 1e5], stops={"z": (1e-3, 1e6)})
    >>> m = Model([Body("b", 100.0, [1, 1, 1])], [Mount("m", t, "b", at=[0, 0, 0])], gravity=[0, 0, -9.81])
    >>> op = operating_point(m)       # 981 N: 100 N in the free travel, 881 N on 1.1e6 N/m
    >>> round(float(op.q[2]) * 1e3, 6)
    -1.800909
    """
    if not isinstance(model, Model):
        raise ModelError(f"operating_point: model: expected a Model, got {type(model).__name__}",
                         argument="model", received=model)
    idx = nonlinear_mounts(model)
    lin = static(model, load, gravity=gravity, case=case)
    if not idx:
        return OperatingPoint(model=model, static=lin, tangent=model, clearance={}, stop_force={},
                              iterations=0, residual=0.0, note="linear model: the static deflection")
    a0 = assemble(model)
    f_ext = np.asarray(lin.load, dtype=float)
    laws = _laws(a0, idx)
    q = np.zeros(a0.n)
    f_int, d, energy = _internal(a0, model, laws, q)
    scale = max(float(np.abs(f_ext).max()), np.finfo(float).tiny)
    residual, steps = np.inf, 0
    for steps in range(1, MAX_ITERATIONS + 1):
        r = f_ext - f_int
        at = assemble(tangent_model(model, d, laws.mounts, floor=_FLOOR))
        dq = static_solve(at, r).x
        slope = float(r @ dq)                             # -dPi/dalpha at alpha = 0 (> 0: descent)
        work = max(abs(float(f_ext @ q)), abs(slope), np.finfo(float).tiny)
        residual = abs(slope) / work
        if residual <= TOLERANCE and steps > 1 or not np.any(r):
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
        _no_equilibrium(model, laws, d, f_ext, scale)
    else:
        raise AnalysisError(f"operating_point: Newton's method did not converge in {MAX_ITERATIONS} steps "
                            f"(last step energy {residual:.1e} of the loads' work)")
    return _result(model, a0, laws, q, d, lin, steps, residual)


def _no_equilibrium(model: Model, laws: _Laws, d: np.ndarray, f_ext: np.ndarray, scale: float) -> None:
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
                raise ModelError(f"operating_point: mount {m.name!r} axis {'xyz'[j]!r}: the load needs more than "
                                 f"its curve's end force {end:.6g} N (its end slope is zero): no static "
                                 f"equilibrium carries it", argument=m.name, received=float(d[i, j]))


def _result(model: Model, a0: Assembly, laws: _Laws, q: np.ndarray, d: np.ndarray, lin: StaticResult,
            steps: int, residual: float) -> OperatingPoint:
    tangent = tangent_model(model, d, laws.mounts)
    delta = (a0.deflection_matrix()[:, :a0.n] @ q).reshape(-1, 3)
    t = np.array([m.orientation.matrix for m in model.mounts]).reshape(-1, 3, 3)
    local = np.einsum("pji,pj->pi", t, delta)
    force = np.einsum("pij,pj->pi", a0.kp, delta)
    clearance: dict[str, float] = {}
    stop_force: dict[str, float] = {}
    for i, p in enumerate(laws.mounts):
        m = model.mounts[p]
        f_local = np.array([float(law.force(d[i, j])) for j, law in enumerate(m.type.laws)])
        force[p] = t[p] @ f_local
        for j, law in enumerate(m.type.laws):
            if law.stop:
                key = f"{m.name}.{'xyz'[j]}"
                room = float(law.room(d[i, j]))
                clearance[key] = room
                stop_force[key] = float(law.stop * max(-room, 0.0))
    st = dataclasses.replace(lin, q=q.copy(), mount_deflection=delta, mount_deflection_local=local,
                             mount_force=force, method="Newton on the mounts' laws",
                             note="; ".join(x for x in (f"nonlinear mounts {[model.mounts[p].name for p in laws.mounts]}: "
                                                       f"operating point by Newton ({steps} steps)", lin.note) if x))
    contact = [k for k, c in clearance.items() if c < 0]
    note = (f"Newton with a line search on the potential, {steps} steps; "
            + (f"stops in contact: {contact}" if contact else "no stop in contact"))
    return OperatingPoint(model=model, static=st, tangent=tangent, clearance=clearance, stop_force=stop_force,
                          iterations=steps, residual=residual, note=note)
