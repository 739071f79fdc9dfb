"""The result of a reduction: :class:`Reduction` (the reduced model with its measured error, what was
removed and why) and the error measure it reports (:func:`relative_error`)."""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace
from typing import Any, cast

import control
import numpy as np

from ..linear.plant.plant import Plant
from ..linear.solve.exact import statespace_plant
from ..linear.statespace import NamedStateSpace, statespace
from ..model.model import Model
from ..results import Result, TextTable, jsonable, require_pandas
from .methods import Reduced, _floor, check_grid
from .prune import Removal, frf
from .scope import Scope

__all__ = ["Reduction", "relative_error"]


def relative_error(h_full: np.ndarray, h_red: np.ndarray) -> float:
    """``max_ij max_w |dH_ij| / max_j max_w |H_full,ij|`` of (p, m, nf) responses.

    Each output's error is relative to its largest response to any of the scope's inputs over the
    band (an output that does not respond at all: relative to the largest response of all).
    """
    peak = np.abs(h_full).max(axis=2)
    err = np.abs(h_red - h_full).max(axis=2)
    return float((err / _floor(peak)).max()) if err.size else 0.0


@dataclass(frozen=True, eq=False)
class Reduction(Result):
    """A reduced model and what was done to get it.

    Follows the result protocol (:mod:`vibss.results`): ``output_labels`` / ``input_labels`` are
    the scope's; ``r.control`` is the reduced system as a python-control state space
    (:class:`~vibss.linear.statespace.NamedStateSpace`) and ``r['b.z', 'b.fz']`` its sub-system.

    Attributes
    ----------
    method : str
        Method used.
    scope : Scope
        What the reduced model must reproduce.
    plant : Plant or None
        The reduced plant (None for ``"balanced"``, which gives :attr:`system`).
    system : NamedStateSpace or None
        The balanced-truncated system (``"balanced"`` only), indexable by vibss names.
    full : Plant
        The full plant of the scope (for verification); for ``"krylov"`` its ``M, C, K, H`` are
        scipy.sparse CSR matrices (no dense n x n).
    dofs_before, dofs_after : int
        Second-order DOFs before and after (``dofs_after`` = 0 for ``"balanced"``).
    states_before, states_after : int
        First-order states (2 per DOF, plus input integrators) before and after.
    removed : tuple of Removal
        What was removed and why.
    estimate : float
        Estimated relative error over the band [-] (0 for exact pruning).
    estimate_kind : str
        ``"exact"``, ``"bound ..."`` or ``"estimate ..."``.
    correction : str
        Which outputs/inputs get the static correction.
    kept_hz : (k,) ndarray
        Natural frequencies of the kept modes [Hz] (modal methods).
    hsv : (ns,) ndarray or None
        Hankel singular values of the channel-scaled system (``"balanced"``).
    hsv_bound : float or None
        ``2 sum(discarded HSV)``: bound on the H-inf error of the scaled system ``diag(1/a) G diag(1/b)``.
    io_scale : tuple of (p,) and (m,) ndarray, or None
        The output and input scales ``a``, ``b`` (units of the outputs per unit input).
    reduce_s : float
        Wall time of the reduction [s].
    measured : float or None
        Measured relative error over the band (``verify``).
    full_s, reduced_s : float or None
        Wall time of the verification FRF on the full and the reduced model [s].
    n_check : int
        Frequencies in the verification grid.
    notes : tuple of str
        Caveats.
    note : str
        Why that method (for ``method="auto"``).
    details : dict
        Method-specific figures (``"krylov"``: basis size, shifts [Hz], moments, interpolation and
        check frequencies [Hz], rounds, timings [s]).
    """

    method: str
    scope: Scope
    plant: Plant | None
    system: NamedStateSpace | None
    full: Plant = field(repr=False)
    dofs_before: int = 0
    dofs_after: int = 0
    states_before: int = 0
    states_after: int = 0
    removed: tuple[Removal, ...] = ()
    estimate: float = 0.0
    estimate_kind: str = "exact"
    correction: str = ""
    kept_hz: np.ndarray = field(default_factory=lambda: np.zeros(0))
    hsv: np.ndarray | None = None
    hsv_bound: float | None = None
    io_scale: tuple[np.ndarray, np.ndarray] | None = None
    reduce_s: float = 0.0
    measured: float | None = None
    full_s: float | None = None
    reduced_s: float | None = None
    n_check: int = 0
    notes: tuple[str, ...] = ()
    details: dict[str, Any] = field(default_factory=dict)
    note: str = ""

    @property
    def output_labels(self) -> tuple[str, ...]:
        """Output signal names of the scope."""
        return tuple(self.scope.outputs)

    @property
    def input_labels(self) -> tuple[str, ...]:
        """Input signal names of the reduced system (the scope's sources)."""
        return tuple(self.full.inputs)

    @property
    def units(self) -> tuple[str, ...]:
        """SI unit of each output."""
        return tuple(self.full.units)

    @property
    def control(self) -> NamedStateSpace:
        """The reduced system as a python-control state space (indexable by vibss names)."""
        if self.system is not None:
            return self.system
        return statespace(cast(Plant, self.plant))

    def _item(self, i: int, j: int | None) -> NamedStateSpace:
        return self.control[i, :] if j is None else self.control[i, j]

    def response(self, s: np.ndarray) -> np.ndarray:
        """Reduced response ``Y(s)`` (p, m, nf) at Laplace points ``s`` [rad/s] (``s = i w``)."""
        s = np.atleast_1d(np.asarray(s, complex))
        if self.plant is not None:
            return frf(self.plant, s)
        sys = cast("control.StateSpace", self.system)  # no plant: reduce() set the system
        return frf(statespace_plant(sys.A, sys.B, sys.C, sys.D, tuple(sys.input_labels),
                                    tuple(sys.output_labels)), s)

    def verify(self, n_points: int = 400) -> Reduction:
        """A copy with the measured error against the full model over the band, and timings.

        Parameters
        ----------
        n_points : int
            Evenly spaced frequencies over the band; the kept modes' resonances (and their
            half-power points) in the band are added.

        Returns
        -------
        Reduction
        """
        w = check_grid(self.scope, n_points, self.kept_hz * 2 * np.pi)
        t0 = time.perf_counter()
        hf = frf(self.full, 1j * w)
        t1 = time.perf_counter()
        hr = self.response(1j * w)
        t2 = time.perf_counter()
        return replace(self, measured=relative_error(hf, hr), full_s=t1 - t0, reduced_s=t2 - t1,
                       n_check=int(w.size))

    def compare(self, n_points: int = 200) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Full and reduced response over the band (the verification grid, see :meth:`verify`).

        Parameters
        ----------
        n_points : int
            Evenly spaced frequencies over the band (the kept resonances' neighbours are added).

        Returns
        -------
        frequency_hz : (nf,) ndarray
        full, reduced : (p, m, nf) complex ndarray
        """
        w = check_grid(self.scope, n_points, self.kept_hz * 2 * np.pi)
        return w / (2 * np.pi), frf(self.full, 1j * w), self.response(1j * w)

    def summary(self) -> TextTable:
        """Sizes, error estimate and timing as a two-column table."""
        rows = [["method", self.method], ["DOFs", f"{self.dofs_before} -> {self.dofs_after}"],
                ["states", f"{self.states_before} -> {self.states_after}"],
                ["estimate", f"{self.estimate:.3g} ({self.estimate_kind})"],
                ["measured", "-" if self.measured is None else f"{self.measured:.3g}"],
                ["tolerance", f"{self.scope.tolerance:g}"], ["reduction [s]", f"{self.reduce_s:.3g}"]]
        return TextTable(["quantity", "value"], rows, title="Model reduction")

    def to_pandas(self) -> Any:
        """DataFrame of what was removed: one row per removal (what, names, reason, exact)."""
        pd = require_pandas()
        df = pd.DataFrame([{"what": r.what, "names": ", ".join(r.names), "reason": r.reason,
                            "exact": r.exact} for r in self.removed], columns=["what", "names", "reason", "exact"])
        df.attrs["units"] = {c: "-" for c in df.columns}                  # words, not quantities
        return df

    def plot(self, ax: Any = None) -> Any:
        """Full against reduced response over the band: :func:`vibss.plotting.plot_reduction`.

        Parameters
        ----------
        ax : (2,) sequence of Axes or None
            Axes for the magnitudes and the relative error; default: a new figure.

        Returns
        -------
        matplotlib.figure.Figure
        """
        from ..plotting import plot_reduction

        return plot_reduction(self, ax)

    def report(self) -> str:
        """Printable summary: sizes, removals, errors, timings."""
        s = self.scope
        lines = [f"Model reduction ({self.method}) for {len(s.inputs)} input(s), {len(s.outputs)} "
                 f"output(s), band {s.f1:g}-{s.f2:g} Hz ({s.origin}), tolerance {s.tolerance:g}",
                 f"  DOFs   {self.dofs_before} -> {self.dofs_after}",
                 f"  states {self.states_before} -> {self.states_after}"]
        if self.kept_hz.size:
            lines.append(f"  kept {self.kept_hz.size} modes, {self.kept_hz.min():.4g}-{self.kept_hz.max():.4g} Hz")
        for r in self.removed:
            names = ", ".join(r.names[:12]) + (f", ... ({len(r.names)} in all)" if len(r.names) > 12 else "")
            lines.append(f"  removed {r.what}: {names}: {r.reason}" + ("" if r.exact else " (approximate)"))
        if self.correction:
            lines.append(f"  static correction: {self.correction}")
        if self.hsv is not None:
            lines.append(f"  Hankel singular values: {self.hsv.size} (largest {self.hsv.max():.4g})")
        d = self.details
        if d.get("basis_size") is not None:
            lines.append(f"  Krylov basis: {d['basis_size']} vectors ({'input and output' if d['two_sided'] else 'input'}"
                         f" blocks), real shifts at {', '.join(f'{f:.4g}' for f in d['shifts_hz'])} Hz, "
                         f"{d['moments']} moments each, {len(d['interpolation_hz'])} exact solutions "
                         f"added, {len(d['check_hz'])} check frequencies, rounds (size, checks, error): "
                         + "; ".join(f"{a}, {b}, {c:.3g}" for a, b, c in d["history"]))
            lines.append("  timings: " + ", ".join(f"{k} {v:.3g} s" for k, v in d["timings"].items()))
        lines.append(f"  error over the band (relative per output): {self.estimate:.3g} ({self.estimate_kind})")
        if self.measured is not None:
            ok = "within" if self.measured <= s.tolerance else "ABOVE"
            lines.append(f"  measured error: {self.measured:.3g} on {self.n_check} frequencies ({ok} tolerance)")
        lines.append(f"  reduction took {self.reduce_s:.3g} s")
        if self.full_s is not None:
            lines.append(f"  FRF on {self.n_check} frequencies: full {self.full_s:.3g} s, reduced "
                         f"{self.reduced_s:.3g} s (+ reduction {self.reduce_s:.3g} s): "
                         f"{self.full_s / max(cast(float, self.reduced_s) + self.reduce_s, 1e-12):.3g}x")
        lines += [f"  note: {n}" for n in self.notes]
        return "\n".join(lines)

    def to_dict(self) -> dict[str, Any]:
        """Plain data (sizes, removals, errors, timings)."""
        return jsonable({"method": self.method, "note": self.note, "scope": self.scope.to_dict(),
                "dofs_before": self.dofs_before, "dofs_after": self.dofs_after,
                "states_before": self.states_before, "states_after": self.states_after,
                "removed": [{"what": r.what, "names": list(r.names), "reason": r.reason, "exact": r.exact}
                            for r in self.removed],
                "estimate": self.estimate, "estimate_kind": self.estimate_kind,
                "correction": self.correction, "kept_hz": self.kept_hz.tolist(),
                "hsv": None if self.hsv is None else self.hsv.tolist(), "hsv_bound": self.hsv_bound,
                "reduce_s": self.reduce_s,
                "measured": self.measured, "full_s": self.full_s, "reduced_s": self.reduced_s,
                "n_check": self.n_check, "notes": list(self.notes),
                "details": self.details})
