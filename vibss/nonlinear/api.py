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


import numpy as np

from ..errors import ModelError
from ..linear.plant.assemble import Assembly, assemble
from ..model.model import Model
from .kernels import _internal, _laws, _Laws, nonlinear_mounts, tangent_model
from .result import OperatingPoint
from ..statics import StaticResult, static

__all__ = ["operating_point"]

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
        Newton's method did not converge in :data:`~vibss.nonlinear.kernels.MAX_ITERATIONS` steps.

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
    laws = _laws(a0, idx)
    d = laws.local(lin.q)
    return _result(model, a0, laws, lin, d)


def _result(model: Model, a0: Assembly, laws: _Laws, st: StaticResult, d: np.ndarray) -> OperatingPoint:
    tangent = tangent_model(model, d, laws.mounts)
    f_int, _, _ = _internal(a0, model, laws, st.q)
    residual = float(np.linalg.norm(st.load - f_int) / max(np.linalg.norm(st.load), np.finfo(float).tiny))
    clearance: dict[str, float] = {}
    stop_force: dict[str, float] = {}
    for i, p in enumerate(laws.mounts):
        m = model.mounts[p]
        for j, law in enumerate(m.type.laws):
            if law.stop:
                key = f"{m.name}.{'xyz'[j]}"
                room = float(law.room(d[i, j]))
                clearance[key] = room
                stop_force[key] = float(law.stop * max(-room, 0.0))
    contact = [k for k, c in clearance.items() if c < 0]
    note = (f"Newton with a line search on the potential, {st.iterations} steps; force balance "
            f"{residual:.1e} of the load; " + (f"stops in contact: {contact}" if contact else "no stop in contact"))
    return OperatingPoint(model=model, static=st, tangent=tangent, clearance=clearance, stop_force=stop_force,
                          iterations=st.iterations, residual=residual, note=note)
