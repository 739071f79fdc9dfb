"""Semi-active isolation: clipped skyhook with variable dampers, simulated in time.

A variable damper across a mount can only dissipate: its force is ``f = -c v_rel`` with
``c_min <= c <= c_max`` (``v_rel`` the relative velocity along the damper). The clipped skyhook law
(Karnopp) asks for the skyhook force ``-c_sky v`` (``v`` the absolute velocity at the damper) and
gives it when the damper can, else the least damping:

    c = clip(c_sky v / v_rel, c_min, c_max)   if v v_rel > 0,   c = c_min otherwise.

The law switches, so the loop is simulated in time (SciPy's ``solve_ivp``, RK45 with a step bound)
on the generalized plant's realization; the damper's power ``f v_rel`` is returned so that its
passivity can be checked.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import ControlDesignError, ModelError
from ..linear.plant.names import control_name
from ..results import Result, Table
from .designs import _find_pairs, _sign
from .plant import vibss_name

__all__ = ["clipped_skyhook", "SemiActiveResponse"]


@dataclass(frozen=True, eq=False)
class SemiActiveResponse(Result):
    """Time response of a semi-active loop.

    Attributes
    ----------
    time : (nt,) ndarray
        [s].
    outputs : (p, nt) ndarray
        Every plant output (``labels``), in SI.
    labels : tuple of str
        Output names (vibss spelling).
    force : (k, nt) ndarray
        Damper forces [N] (one per actuator, along the actuator's direction).
    damping : (k, nt) ndarray
        Damping coefficient used [N s/m].
    power : (k, nt) ndarray
        Power the dampers put into the structure, ``f v_rel`` [W] (never positive for a damper).
    dampers : tuple of str
        Actuator commands (vibss spelling).
    """

    time: np.ndarray
    outputs: np.ndarray
    labels: tuple[str, ...]
    force: np.ndarray
    damping: np.ndarray
    power: np.ndarray
    dampers: tuple[str, ...]
    name: str = "clipped skyhook"

    @property
    def output_labels(self) -> tuple[str, ...]:
        """Output names (vibss spelling)."""
        return self.labels

    def _item(self, i: int, j: int | None) -> np.ndarray:
        return self.outputs[i]

    def summary(self) -> Table:
        """Peak of every output and of the damper forces."""
        rows = [(lab, f"{np.abs(y).max():.4g}") for lab, y in zip(self.labels, self.outputs)]
        rows += [(f"{d} force [N]", f"{np.abs(f).max():.4g}") for d, f in zip(self.dampers, self.force)]
        return Table(("signal", "peak |value|"), rows, title=f"{self.name}: peaks")

    def report(self) -> str:
        """Peaks and the largest damper power (passivity check)."""
        return f"{self.summary()}\nlargest damper power {self.power.max():.3g} W (<= 0: passive)"

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready time series (SI)."""
        return {"time": self.time.tolist(), "outputs": {k: v.tolist() for k, v in zip(self.labels, self.outputs)},
                "force": {k: v.tolist() for k, v in zip(self.dampers, self.force)},
                "damping": {k: v.tolist() for k, v in zip(self.dampers, self.damping)}}


def clipped_skyhook(P: Any, disturbance: Mapping[str, Callable[[np.ndarray], Any]], end: float, step: float,
                    c_sky: float, c_min: float, c_max: float, absolute: Mapping[str, str] | None = None,
                    relative: Mapping[str, str] | None = None) -> SemiActiveResponse:
    """Simulate clipped-skyhook variable dampers (one per actuator of the plant).

    Parameters
    ----------
    P : GeneralizedPlant
        Measuring, for every actuator, the collocated absolute ``velocity`` and ``relative_velocity``.
    disturbance : mapping
        ``{disturbance signal: f(t)}``, each ``f`` vectorised over time [s] (a vibss time function,
        e.g. ``HalfSine``, works); unlisted disturbances are zero.
    end, step : float
        Simulate ``0 .. end`` [s]; results every ``step`` [s] (also the largest integration step).
    c_sky, c_min, c_max : float
        Skyhook damping and the damper's range [N s/m] (``0 <= c_min <= c_max``).
    absolute, relative : mapping or None
        ``{actuator: measurement}`` pairs; default: the collocated sensors.

    Returns
    -------
    SemiActiveResponse
    """
    from scipy.integrate import solve_ivp

    if not (0 <= c_min <= c_max) or not np.isfinite(c_max) or not c_sky >= 0:
        raise ModelError(f"need 0 <= c_min <= c_max and c_sky >= 0 [N s/m], got c_sky={c_sky!r}, "
                         f"c_min={c_min!r}, c_max={c_max!r}")
    if not (end > 0 and step > 0 and step <= end):
        raise ModelError(f"end, step: need 0 < step <= end [s], got end={end!r}, step={step!r}")
    ab = _find_pairs(P, ("velocity",), absolute)
    rl = _find_pairs(P, ("relative_velocity",), relative)
    A = np.asarray(P.A, dtype=float)
    ns = A.shape[0]
    B = np.asarray(P.B, dtype=float).reshape(ns, P.ninputs)
    C = np.asarray(P.C, dtype=float).reshape(P.noutputs, ns)
    D = np.asarray(P.D, dtype=float).reshape(P.noutputs, P.ninputs)
    iw = [P.input_labels.index(s) for s in P.groups["w"]]
    iu = [P.input_labels.index(s) for s in P.groups["u"]]
    ia = [P.output_labels.index(y) for _, y in ab]
    ir = [P.output_labels.index(y) for _, y in rl]
    if np.any(D[np.ix_(ia + ir, iu)]):
        raise ControlDesignError("clipped_skyhook: a velocity measurement feeds through from the damper "
                                 "force (D != 0); the law would be implicit")
    sa = np.array([_sign(P, u, y) for u, y in ab])
    sr = np.array([_sign(P, u, y) for u, y in rl])
    given = {control_name(str(k)): f for k, f in disturbance.items()}
    unknown = sorted(vibss_name(k) for k in set(given) - set(P.groups["w"]))
    if unknown:
        raise ModelError(f"disturbance: {unknown} are not disturbances of the plant; they are "
                         f"{[vibss_name(s) for s in P.groups['w']]}")
    funcs = [getattr(f, "value", f) for f in (given.get(s) for s in P.groups["w"])]

    def w_at(t: Any) -> np.ndarray:
        t = np.atleast_1d(np.asarray(t, dtype=float))
        return np.array([np.zeros_like(t) if f is None else np.broadcast_to(np.asarray(f(t), float), t.shape)
                         for f in funcs]).reshape(len(funcs), t.size)

    def law(x: np.ndarray, w: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        y = C @ x + D[:, iw] @ w
        v = sa[:, None] * y[ia]
        vr = sr[:, None] * y[ir]
        with np.errstate(divide="ignore", invalid="ignore"):
            want = np.where(vr != 0, c_sky * v / vr, c_min)
        c = np.where(v * vr > 0, np.clip(want, c_min, c_max), c_min)
        return -c * vr, c, vr

    def rhs(t: float, x: np.ndarray) -> np.ndarray:
        w = w_at(t)
        f, _, _ = law(x[:, None], w)
        return A @ x + B[:, iw] @ w[:, 0] + B[:, iu] @ f[:, 0]

    t = np.arange(0.0, end + 0.5 * step, step)
    sol = solve_ivp(rhs, (0.0, float(t[-1])), np.zeros(ns), t_eval=t, max_step=step, rtol=1e-8, atol=1e-12)
    if not sol.success:
        raise ControlDesignError(f"clipped_skyhook: the time integration failed: {sol.message}")
    X = sol.y
    W = w_at(t)
    f, c, vr = law(X, W)
    U = np.zeros((len(iu), t.size))
    U[:] = f
    Y = C @ X + D[:, iw] @ W + D[:, iu] @ U
    return SemiActiveResponse(t, Y, tuple(vibss_name(s) for s in P.output_labels), f, c, f * vr,
                              tuple(vibss_name(u) for u, _ in ab))
