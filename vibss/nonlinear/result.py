"""The operating point's result: the static equilibrium of nonlinear mounts and its tangent model."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from ..model.model import Model
from ..results import Result, TextTable
from ..statics import StaticResult

__all__ = ["OperatingPoint"]


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
        """Units of the DOFs (m, rad)."""
        return self.static.units

    def _item(self, i: int, j: int | None) -> float:
        return float(self.static.q[i])

    def rates(self) -> TextTable:
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
        return TextTable(["mount", "axis", "unloaded [N/m]", "tangent [N/m]", "ratio"], rows,
                     title="Tangent rates at the operating point")

    def summary(self) -> TextTable:
        rows = [[key, f"{1e3 * c:.3f}", f"{self.stop_force[key]:.4g}"] for key, c in self.clearance.items()]
        return TextTable(["stop", "clearance left [mm]", "stop force [N]"], rows, title="Stops at the operating point")

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
        """The static deflection's DataFrame (:meth:`StaticResult.to_pandas`)."""
        return self.static.to_pandas()

    def plot(self, ax: Any = None) -> Any:
        """The static deflection's bar chart (:meth:`StaticResult.plot`)."""
        return self.static.plot(ax=ax)
