"""The order response of a model with nonlinear mounts (stops, curves): harmonic balance along the speed.

A rotating source of one order ``k`` loads the body at ``omega = 2 pi k rpm / 60`` with phasors that
follow the speed (an unbalance's ``m e omega^2``). :func:`order_balance` hands those phasors to
:func:`vibss.harmonic_balance` as amplitudes that are functions of the frequency, so the
pseudo-arclength continuation runs in the speed itself with the forcing changing along it: one
branch through the turning points (where a slow run-up or run-down jumps), not a point-by-point
solve per speed that would stop at the first fold. The speeds of the result are those of the
branch points, in branch order (not monotone through a fold).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from .._validate import choice
from ..errors import ArgumentError
from ..model.model import Model
from .result import OrderResponse
from .sources import OrderForce, Source, generalized_forces

__all__ = ["order_balance"]

_LOADS = ("fx", "fy", "fz", "mx", "my", "mz")


def _inputs(model: Model, sources: Sequence[Source], order: float, lo: float, hi: float) -> dict[str, Any]:
    """Each loaded body's force and moment inputs, as functions of the frequency [Hz]."""
    bodies = sorted({s.body for s in sources})

    def phasors(f_hz: np.ndarray) -> dict[tuple[str, float], np.ndarray]:
        rpm = np.clip(60.0 * np.asarray(f_hz, float) / order, lo, hi)   # a table ends at the range's ends
        return generalized_forces(model, sources, rpm)

    def one(body: str, d: int) -> Any:
        return lambda f: phasors(f)[(body, order)][d]

    return {f"{b}.{name}": one(b, d) for b in bodies for d, name in enumerate(_LOADS)}


def order_balance(model: Model, sources: Sequence[Source], rpm: np.ndarray, outputs: Sequence[str] | None,
                  quantity: str, harmonics: int) -> OrderResponse:
    """The first harmonic of every output along the branch over ``rpm[0] .. rpm[-1]`` [rpm] (about
    ``rpm.size`` continuation steps, more where it bends), with its stability and turning speeds.

    Raises
    ------
    ArgumentError
        Sources of more than one order (their frequencies are not harmonics of one fundamental).
    """
    from ..modal.api import modes
    from ..nonlinear.harmonic import harmonic_balance

    quantity = choice(quantity, "quantity", ("receptance", "mobility", "accelerance"), who="order_response")
    orders = sorted({float(s.order) for s in sources})
    if len(orders) != 1:
        raise ArgumentError(f"order_response: harmonic balance (nonlinear mounts) takes sources of one order, got "
                            f"orders {orders}: run one order at a time", argument="sources", received=orders)
    k = orders[0]
    lo, hi = float(rpm[0]), float(rpm[-1])
    for s in sources:
        if isinstance(s, OrderForce) and s.rpm.size > 1 and (lo < s.rpm[0] or hi > s.rpm[-1]):
            raise ArgumentError(f"order_response: order force {s.name!r}: speeds {lo:g} ... {hi:g} rpm leave its "
                                f"table's {s.rpm[0]:g} ... {s.rpm[-1]:g} rpm", argument="sources")
    hb = harmonic_balance(model, _inputs(model, sources, k, lo, hi), outputs,
                          frequencies=(k * lo / 60.0, k * hi / 60.0), harmonics=harmonics, points=max(rpm.size, 2))
    w = hb.omega
    factor = {"receptance": np.ones_like(w), "mobility": 1j * w, "accelerance": -w ** 2}[quantity]
    suffix = {"receptance": "", "mobility": "/s", "accelerance": "/s^2"}[quantity]
    resp = (hb.harmonics[:, 1, :] * factor)[None]
    folds = ", ".join(f"{60.0 * f / k:.1f}" for f in hb.turning_points) or "none"
    note = (f"{len(sources)} source(s); harmonic balance ({harmonics} harmonics) continued in the speed with the "
            f"forcing following it; turning points at {folds} rpm; {hb.check.text()}")
    return OrderResponse(60.0 * hb.frequencies / k, (k,), resp, hb.output_labels,
                         tuple(u + suffix for u in hb.units), modes(model).frequency_hz,
                         tuple(s.name for s in sources), quantity, "harmonic_balance", note=note,
                         stable=hb.stable, turning_rpm=60.0 * hb.turning_points / k, branch=hb)
