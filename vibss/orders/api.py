"""Steady-state response to rotating machinery over a speed range (order cuts, critical speeds) and a
run-up through it in the time domain.

:func:`order_response` evaluates, for each harmonic order ``k`` of the sources, the exact frequency
response at ``f = k rpm / 60`` (the one FRF path, :func:`vibss.frequency_response`, on one plant
with the sources' bodies' force and moment inputs) and multiplies it by the sources' phasors:
``X_k(rpm) = H(i 2 pi f) F_k(rpm)``. Sources of one order add as phasors (same frequency); different
orders are reported apart and combined as an overall RMS ``sqrt(sum_k |X_k|^2 / 2)``.

:func:`run_up` simulates a run-up (or run-down) at a constant rate: speed ``rpm(t)`` linear in
time, the load ``Re(F(rpm(t)) e^{i theta_k(t)})`` with ``theta_k = k 2 pi / 60 int rpm dt``, plus the
tangential force ``m e theta''`` of an accelerating unbalance, sampled and integrated by
:func:`vibss.simulate` (exact for the sampled, piecewise-linear load; ``points_per_cycle`` sets
how closely that follows the sinusoid).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from .. import _validate as v
from ..errors import ArgumentError
from ..model.model import Model
from ..nonlinear.kernels import nonlinear_mounts
from .harmonic import order_balance
from .kernels import _sources, _speeds
from .result import OrderResponse
from .sources import OrderForce, Unbalance, generalized_forces

__all__ = ["order_response", "run_up"]

_LOADS = ("fx", "fy", "fz", "mx", "my", "mz")


def order_response(model: Model, sources: Any, rpm: Any, outputs: Sequence[str] | None = None, *,
                   quantity: str = "receptance", method: str = "auto", harmonics: int = 7) -> OrderResponse:
    """Steady-state response to rotating unbalances and engine orders over a speed range.

    Parameters
    ----------
    model : Model
        The system.
    sources : Unbalance, OrderForce or sequence of them
        What rotates (:mod:`vibss.orders.sources`).
    rpm : (n,) array_like
        Shaft speeds [rpm], increasing, > 0.
    outputs : sequence of str or None
        Output signals (``'engine.z'``, ``'mount.front.fz'`` ...); default every body DOF.
    quantity : {"receptance", "mobility", "accelerance"}
        Every output as it is, or multiplied by ``i w`` / ``-w^2`` (units ``.../s``, ``.../s^2``);
        ask for ``'box.z.acc'`` to mix accelerations with forces.
    method : str
        FRF method (as :func:`vibss.frequency_response`), or ``"harmonic_balance"``, which ``"auto"``
        takes for a model with nonlinear mounts (stops, curves): the steady periodic response by
        :func:`vibss.harmonic_balance`, continued in the speed with the forcing following it (an
        unbalance's grows with rpm^2) through the turning points (:mod:`vibss.orders.harmonic`);
        the result's speeds are then the branch's points from ``rpm[0]`` to ``rpm[-1]`` (about
        ``rpm.size`` of them, in branch order), with ``stable``, ``turning_rpm`` and ``branch``.
        Sources of one order only.
    harmonics : int
        Highest harmonic kept by the harmonic balance (nonlinear mounts only).

    Returns
    -------
    OrderResponse

    Examples
    --------
    >>> import numpy as np, vibss
    >>> from vibss.orders import Unbalance, order_response
    >>> pt = vibss.load_example("powertrain")
    >>> r = order_response(pt, Unbalance("crank", "powertrain", 0.01, 0.05), np.linspace(600, 6000, 50),
    ...                    ["powertrain.z"])
    >>> r.orders, r.response.shape
    ((1.0,), (1, 1, 50))
    """
    from ..frequency.api import frequency_response
    from ..linear.plant.build import build_plant
    from ..modal.api import modes

    who = "order_response"
    srcs = _sources(sources)
    speeds = _speeds(rpm, who)
    if method == "harmonic_balance" or (method == "auto" and nonlinear_mounts(model)):
        return order_balance(model, srcs, speeds, outputs, quantity, harmonics)
    groups = generalized_forces(model, srcs, speeds)
    bodies = sorted({b for b, _ in groups})
    inputs = [f"{b}.{d}" for b in bodies for d in _LOADS]
    plant = build_plant(model, inputs, outputs)
    orders = sorted({k for _, k in groups})
    resp = np.zeros((len(orders), len(plant.outputs), speeds.size), dtype=complex)
    used = set()
    suffix = {"receptance": "", "mobility": "/s", "accelerance": "/s^2"}.get(quantity, "")
    units = tuple(u + suffix for u in plant.units)        # a load in N gives the outputs' own units
    for j, k in enumerate(orders):
        r = frequency_response(plant, frequencies=k * speeds / 60.0, quantity=quantity, method=method)
        used.add(r.method)
        for (b, kk), f in groups.items():
            if kk == k:
                c = 6 * bodies.index(b)
                resp[j] += np.einsum("pjn,jn->pn", r.response[:, c:c + 6], f)
    nat = modes(model).frequency_hz
    return OrderResponse(speeds, tuple(orders), resp, tuple(plant.outputs), units, nat,
                         tuple(s.name for s in srcs), quantity, ", ".join(sorted(used)),
                         note=f"{len(srcs)} source(s) on {', '.join(bodies)}; exact FRF at f = order x rpm / 60")


def run_up(model: Model, sources: Any, rpm_start: float, rpm_end: float, duration: float,
           outputs: Sequence[str] | None = None, *, points_per_cycle: int = 40, method: str = "auto") -> Any:
    """Run-up (or run-down) at a constant rate through a speed range, in the time domain.

    Parameters
    ----------
    model : Model
        The system (at rest at ``t = 0``).
    sources : Unbalance, OrderForce or sequence of them
        What rotates.
    rpm_start, rpm_end : float
        Shaft speed at ``t = 0`` and at ``t = duration`` [rpm], > 0.
    duration : float
        Time of the run-up [s].
    outputs : sequence of str or None
        Output signals; default every body DOF.
    points_per_cycle : int
        Load samples per cycle of the highest order at the highest speed (the load is followed
        piecewise-linearly between samples: the error is second order, 3e-4 of the peak response at
        40 points, 1.2e-5 at 200 on a run-up through a resonance).
    method : str
        Time method (as :func:`vibss.simulate`).

    Returns
    -------
    TimeResponse
        With the shaft speed of each sample in ``note``'s terms: ``rpm(t) = rpm_start + (rpm_end -
        rpm_start) t / duration``.
    """
    from ..time.api import simulate

    who = "run_up"
    srcs = _sources(sources)
    r0 = v.number(rpm_start, "rpm_start", who=who, minimum=0.0, strict=True, unit="rpm")
    r1 = v.number(rpm_end, "rpm_end", who=who, minimum=0.0, strict=True, unit="rpm")
    T = v.number(duration, "duration", who=who, minimum=0.0, strict=True, unit="s")
    ppc = v.integer(points_per_cycle, "points_per_cycle", who=who, minimum=4)
    f_max = max(s.order for s in srcs) * max(r0, r1) / 60.0
    dt = 1.0 / (ppc * f_max)
    n = int(np.ceil(T / dt))
    dt = T / n
    t = np.arange(n + 1) * dt
    rpm = r0 + (r1 - r0) * t / T
    turns = 2.0 * np.pi / 60.0 * (r0 * t + 0.5 * (r1 - r0) * t * t / T)      # shaft angle [rad]
    alpha = 2.0 * np.pi / 60.0 * (r1 - r0) / T                               # shaft angular acceleration
    loads: dict[str, np.ndarray] = {}
    lo, hi = min(r0, r1), max(r0, r1)
    for s in srcs:
        if isinstance(s, OrderForce) and s.rpm.size > 1 and (lo < s.rpm[0] or hi > s.rpm[-1]):
            raise ArgumentError(f"{who}: order force {s.name!r}: speeds {lo:g} ... {hi:g} rpm leave its "
                                f"table's {s.rpm[0]:g} ... {s.rpm[-1]:g} rpm", argument="sources")
        p = s.phasors(model, rpm)                                  # (6, ns): m e W^2 for an unbalance
        if isinstance(s, Unbalance):
            om = 2.0 * np.pi * s.order * rpm / 60.0
            p = p * (1.0 - 1j * s.order * alpha / np.maximum(om ** 2, 1e-300))   # tangential m e theta''
        u = np.real(p * np.exp(1j * s.order * turns))
        for d, row in zip(_LOADS, u):
            key = f"{s.body}.{d}"
            loads[key] = loads.get(key, 0.0) + row
    return simulate(model, inputs=loads, outputs=outputs, t_end=T, dt=dt, method=method)

