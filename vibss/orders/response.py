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
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from .. import _validate as v
from ..errors import ArgumentError
from ..model.model import Model
from ..results import Result, Table, jsonable, require_pandas
from .sources import OrderForce, Source, Unbalance, generalised_forces

__all__ = ["OrderResponse", "order_response", "run_up", "critical_speeds"]

_LOADS = ("fx", "fy", "fz", "mx", "my", "mz")


def _sources(sources: Any) -> list[Source]:
    if isinstance(sources, (Unbalance, OrderForce)):
        sources = [sources]
    out = list(sources) if isinstance(sources, Sequence) else []
    if not out or not all(isinstance(s, (Unbalance, OrderForce)) for s in out):
        raise ArgumentError(f"sources: expected Unbalance / OrderForce objects, got {sources!r}",
                            argument="sources", received=sources)
    names = [s.name for s in out]
    if len(set(names)) != len(names):
        raise ArgumentError(f"sources: names must be unique, got {names}", argument="sources", received=names)
    return out


def _speeds(rpm: Any, who: str) -> np.ndarray:
    r = np.atleast_1d(v.array(rpm, "rpm", None, who=who))
    if r.ndim != 1 or np.any(r <= 0) or np.any(np.diff(r) <= 0):
        raise ArgumentError(f"{who}: rpm: expected increasing positive shaft speeds [rpm], got {rpm!r}",
                            argument="rpm", received=rpm)
    return r


def critical_speeds(natural_hz: np.ndarray, orders: Sequence[float], rpm: np.ndarray) -> list[tuple[float, int, float, float]]:
    """``(order, mode, f_n [Hz], rpm)`` where an order line ``f = k rpm / 60`` crosses a natural
    frequency inside the speed range (mode 1-based)."""
    out = []
    for k in orders:
        for i, fn in enumerate(natural_hz):
            r = 60.0 * fn / k
            if rpm[0] <= r <= rpm[-1] and fn > 0:
                out.append((float(k), i + 1, float(fn), float(r)))
    return sorted(out, key=lambda x: x[3])


@dataclass(frozen=True)
class OrderResponse(Result):
    """Steady-state response to rotating sources over a speed range.

    ``r['engine.z']`` is the (orders, n) complex response of one output; ``r['engine.z', 'order 2']``
    the (n,) response to one order.

    Attributes
    ----------
    rpm : (n,) ndarray
        Shaft speeds [rpm].
    orders : tuple of float
        The harmonic orders present.
    response : (o, p, n) complex ndarray
        Complex amplitude of each output for each order and speed [output units].
    outputs : tuple of str
        Output signals.
    units : tuple of str
        Their units.
    natural_hz : (k,) ndarray
        Undamped natural frequencies [Hz] (for the Campbell diagram and critical speeds).
    sources : tuple of str
        Names of the sources.
    quantity : str
        ``receptance`` (displacement), ``mobility`` or ``accelerance`` of the motion outputs.
    method, note : str
        The FRF method and how the result was made.
    """

    signal_kind: ClassVar[str] = "output"

    rpm: np.ndarray
    orders: tuple[float, ...]
    response: np.ndarray
    outputs: tuple[str, ...]
    units: tuple[str, ...]
    natural_hz: np.ndarray
    sources: tuple[str, ...]
    quantity: str = "receptance"
    method: str = ""
    note: str = ""

    @property
    def output_labels(self) -> tuple[str, ...]:
        return self.outputs

    @property
    def input_labels(self) -> tuple[str, ...]:
        """``"order 2"`` ... one per harmonic order."""
        return tuple(f"order {k:g}" for k in self.orders)

    def _item(self, i: int, j: int | None) -> Any:
        return self.response[:, i] if j is None else self.response[j, i]

    @property
    def frequency_hz(self) -> np.ndarray:
        """(o, n) excitation frequency of each order at each speed [Hz]."""
        return np.outer(self.orders, self.rpm) / 60.0

    @property
    def overall(self) -> np.ndarray:
        """(p, n) overall RMS of each output over all orders, ``sqrt(sum |X_k|^2 / 2)``."""
        return np.sqrt(0.5 * np.sum(np.abs(self.response) ** 2, axis=0))

    def critical_speeds(self) -> list[tuple[float, int, float, float]]:
        """``(order, mode, f_n [Hz], rpm)`` crossings inside the speed range (Campbell diagram)."""
        return critical_speeds(self.natural_hz, self.orders, self.rpm)

    def summary(self) -> Table:
        """Peak amplitude of each output and order, and the speed where it occurs."""
        rows = []
        for i, out in enumerate(self.outputs):
            for j, k in enumerate(self.orders):
                a = np.abs(self.response[j, i])
                n = int(np.argmax(a))
                rows.append([out, f"{k:g}", f"{a[n]:.4g}", self.units[i], f"{self.rpm[n]:.0f}",
                             f"{self.frequency_hz[j, n]:.3f}"])
        return Table(["output", "order", "peak amplitude", "unit", "at [rpm]", "f [Hz]"], rows,
                     title=f"Order response over {self.rpm[0]:.0f} ... {self.rpm[-1]:.0f} rpm "
                           f"({', '.join(self.sources)})")

    def critical_table(self) -> Table:
        """Critical speeds: where each order crosses each natural frequency."""
        rows = [[f"{k:g}", str(i), f"{fn:.3f}", f"{r:.0f}"] for k, i, fn, r in self.critical_speeds()]
        return Table(["order", "mode", "f_n [Hz]", "speed [rpm]"], rows,
                     title="Critical speeds (order line crosses a natural frequency)")

    def report(self) -> str:
        """Text: peaks per output and order, then critical speeds."""
        return "\n\n".join([self.summary().render(), self.critical_table().render()]
                           + ([self.note] if self.note else []))

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: speeds, orders, amplitude and phase per order and output."""
        return jsonable({"rpm": self.rpm, "orders": list(self.orders), "sources": list(self.sources),
                         "quantity": self.quantity, "natural_hz": self.natural_hz,
                         "outputs": {o: {"unit": u, **{f"order {k:g}": {"amplitude": np.abs(self.response[j, i]),
                                                                         "phase_deg": np.degrees(np.angle(self.response[j, i]))}
                                                       for j, k in enumerate(self.orders)}}
                                     for i, (o, u) in enumerate(zip(self.outputs, self.units))},
                         "critical_speeds": [dict(zip(("order", "mode", "natural_hz", "rpm"), c))
                                             for c in self.critical_speeds()],
                         "method": self.method, "note": self.note})

    def to_pandas(self) -> Any:
        """DataFrame of amplitudes indexed by speed [rpm], columns (order, output)."""
        pd = require_pandas()
        data = {(f"order {k:g}", o): np.abs(self.response[j, i])
                for j, k in enumerate(self.orders) for i, o in enumerate(self.outputs)}
        df = pd.DataFrame(data, index=pd.Index(self.rpm, name="rpm"))
        df.columns.names = ["order", "output"]
        df.attrs["units"] = dict(zip(self.outputs, self.units))
        return df

    def plot(self, ax: Any = None, **kwargs: Any) -> Any:
        """Order cuts: amplitude against speed, :func:`vibss.plotting.orders.plot_order_cuts`."""
        from ..plotting.orders import plot_order_cuts

        return plot_order_cuts(self, ax=ax, **kwargs)

    def campbell(self, ax: Any = None, **kwargs: Any) -> Any:
        """Campbell diagram: :func:`vibss.plotting.orders.plot_campbell`."""
        from ..plotting.orders import plot_campbell

        return plot_campbell(self, ax=ax, **kwargs)


def order_response(model: Model, sources: Any, rpm: Any, outputs: Sequence[str] | None = None, *,
                   quantity: str = "receptance", method: str = "auto") -> OrderResponse:
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
        FRF method (as :func:`vibss.frequency_response`).

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
    from ..modal.undamped import modes

    who = "order_response"
    srcs = _sources(sources)
    speeds = _speeds(rpm, who)
    groups = generalised_forces(model, srcs, speeds)
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

