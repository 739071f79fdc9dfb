"""The result of :func:`vibss.orders.order_response`: order cuts against shaft speed."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np

from ..results import Result, TextTable, jsonable, require_pandas
from .kernels import critical_speeds

__all__ = ["OrderResponse"]


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
    stable : (n,) bool ndarray or None
        With nonlinear mounts (harmonic balance): the stability of each point of the branch; None
        for a linear model.
    turning_rpm : (k,) ndarray
        With nonlinear mounts: the speeds of the branch's turning points [rpm] (a slow run-up, then a
        run-down, jumps there); empty otherwise.
    branch : HarmonicBalanceResult or None
        With nonlinear mounts: the harmonic balance itself (every harmonic; ``.plot()``).
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
    stable: np.ndarray | None = None
    turning_rpm: np.ndarray = field(default_factory=lambda: np.zeros(0))
    branch: Any = None

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

    def summary(self) -> TextTable:
        """Peak amplitude of each output and order, and the speed where it occurs."""
        rows = []
        for i, out in enumerate(self.outputs):
            for j, k in enumerate(self.orders):
                a = np.abs(self.response[j, i])
                n = int(np.argmax(a))
                rows.append([out, f"{k:g}", f"{a[n]:.4g}", self.units[i], f"{self.rpm[n]:.0f}",
                             f"{self.frequency_hz[j, n]:.3f}"])
        return TextTable(["output", "order", "peak amplitude", "unit", "at [rpm]", "f [Hz]"], rows,
                     title=f"Order response over {self.rpm[0]:.0f} ... {self.rpm[-1]:.0f} rpm "
                           f"({', '.join(self.sources)})")

    def critical_table(self) -> TextTable:
        """Critical speeds: where each order crosses each natural frequency."""
        rows = [[f"{k:g}", str(i), f"{fn:.3f}", f"{r:.0f}"] for k, i, fn, r in self.critical_speeds()]
        return TextTable(["order", "mode", "f_n [Hz]", "speed [rpm]"], rows,
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
        df.attrs["units"] = {"by output": dict(zip(self.outputs, self.units))}
        return df

    def plot(self, ax: Any = None, **kwargs: Any) -> Any:
        """Order cuts: amplitude against speed, :func:`vibss.plotting.orders.plot_order_cuts`."""
        from ..plotting.orders import plot_order_cuts

        return plot_order_cuts(self, ax=ax, **kwargs)

    def campbell(self, ax: Any = None, **kwargs: Any) -> Any:
        """Campbell diagram: :func:`vibss.plotting.orders.plot_campbell`."""
        from ..plotting.orders import plot_campbell

        return plot_campbell(self, ax=ax, **kwargs)
