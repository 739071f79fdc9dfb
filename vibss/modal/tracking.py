"""Modes followed across a parameter sweep by their shapes, not their order.

Sorted by frequency, two modes that veer (approach and turn away) swap places: a plot of "the
third frequency" jumps from one mode to the other and its colour follows neither. :func:`track_modes`
matches each step's modes to the previous step's by the mass-weighted modal assurance criterion
(MAC) with an optimal one-to-one assignment (:func:`scipy.optimize.linear_sum_assignment`), so a
track keeps one mode's character through a veering; a match below :data:`MAC_WARN` (the mode
changed character between two steps: a finer step resolves it) is counted and named.

Examples
--------
>>> import vibss
>>> from vibss import Body, Model, Mount, MountType
>>> def model(kx):
...     t = MountType("t", [kx, 2e4, 3e4])
...     return Model([Body("b", 10.0, [1, 1, 1])], [Mount("m", t, "b")])
>>> tr = track_modes([vibss.modes(model(k)) for k in (1e4, 4e4)])    # x passes y and z: sorted order swaps
>>> tr.labels[3:], [round(float(f), 2) for f in tr.frequency_hz[-1, 3:]]   # after the three free rotations
(['x', 'y', 'z'], [10.07, 7.12, 8.72])
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import ModelError
from ..results import Result, TextTable, jsonable
from .result import Modes

__all__ = ["track_modes", "ModeTracks", "mac", "MAC_WARN"]

MAC_WARN = 0.5
"""A step's match below this MAC: the mode changed character between two steps."""


def mac(a: np.ndarray, b: np.ndarray, M: Any) -> np.ndarray:
    """(ka, kb) mass-weighted MAC ``|a^T M b|^2 / ((a^T M a)(b^T M b))`` of the columns of two shape
    matrices (n, ka) and (n, kb) [-]: 1 for the same shape, 0 for M-orthogonal ones."""
    mb = M @ b
    ab = a.T @ mb
    aa = np.einsum("ij,ij->j", a, M @ a)
    bb = np.einsum("ij,ij->j", b, mb)
    return np.abs(ab) ** 2 / np.maximum(np.outer(aa, bb), 1e-300)


@dataclass(frozen=True, eq=False)
class ModeTracks(Result):
    """Modes followed across a sweep (:func:`track_modes`).

    Attributes
    ----------
    frequency_hz : (steps, k) ndarray
        Natural frequency of each track at each step [Hz].
    order : (steps, k) int ndarray
        The mode (index into that step's frequency-sorted modes) each track holds.
    mac : (steps - 1, k) ndarray
        MAC of each track's match between a step and the next [-].
    labels : list of str
        Each track's label: its mode's label at the first step (``"z"``, ``"tank.rx"`` ...).
    """

    frequency_hz: np.ndarray
    order: np.ndarray
    mac: np.ndarray
    labels: list[str]

    @property
    def output_labels(self) -> tuple[str, ...]:
        return tuple(self.labels)

    @property
    def weak(self) -> list[tuple[int, str, float]]:
        """``(step, label, MAC)`` of every match below :data:`MAC_WARN` (step: the later one)."""
        s, k = np.nonzero(self.mac < MAC_WARN)
        return [(int(i) + 1, self.labels[j], float(self.mac[i, j])) for i, j in zip(s, k)]

    def summary(self) -> TextTable:
        """Per track: its label, first and last frequency [Hz], and its weakest match."""
        rows = [[lab, f"{self.frequency_hz[0, j]:.4g}", f"{self.frequency_hz[-1, j]:.4g}",
                 f"{self.mac[:, j].min():.3f}" if self.mac.size else "-"] for j, lab in enumerate(self.labels)]
        return TextTable(["track", "first f [Hz]", "last f [Hz]", "weakest MAC"], rows,
                         title=f"Modes tracked by MAC over {self.frequency_hz.shape[0]} steps")

    def report(self) -> str:
        weak = self.weak
        tail = ("" if not weak else f"\n{len(weak)} matches below MAC {MAC_WARN:g} (a mode changed character "
                f"between steps; a finer step resolves it): first at step {weak[0][0]} ({weak[0][1]})")
        return self.summary().render() + tail

    def to_dict(self) -> dict[str, Any]:
        return jsonable({"labels": self.labels, "frequency_hz": self.frequency_hz, "order": self.order,
                         "mac": self.mac})

    def plot(self, x: Any = None, xlabel: str = "step", ax: Any = None) -> Any:
        """Each track's frequency against the swept parameter, one colour and legend entry per track:
        :func:`vibss.plotting.modes.plot_mode_tracks`."""
        from ..plotting.modes import plot_mode_tracks

        return plot_mode_tracks(self, x, xlabel, ax)


def track_modes(steps: Sequence[Modes]) -> ModeTracks:
    """Follow the modes of a sweep by their shapes (mass-weighted MAC, optimal assignment).

    Parameters
    ----------
    steps : sequence of Modes
        The modes at each step of the sweep, in sweep order: the same DOFs and number of modes.

    Returns
    -------
    ModeTracks
        Tracks in the order of the first step's modes.

    Raises
    ------
    ModelError
        Fewer than one step, or steps whose DOFs or mode counts differ (the mode is named).
    """
    from scipy.optimize import linear_sum_assignment

    from ..linear.plant.assemble import assemble

    steps = list(steps)
    if not steps or not all(isinstance(m, Modes) for m in steps):
        raise ModelError("track_modes: steps: expected a sequence of vibss.Modes (one per sweep step)")
    k, dofs = len(steps[0]), tuple(steps[0].dofs)
    for i, m in enumerate(steps):
        if tuple(m.dofs) != dofs or len(m) != k:
            raise ModelError(f"track_modes: step {i}: {len(m)} modes of DOFs {list(m.dofs)[:3]}..., but step 0 "
                             f"has {k} modes of {list(dofs)[:3]}...: every step must have the same DOFs and modes")
    order = np.zeros((len(steps), k), dtype=int)
    order[0] = np.arange(k)
    macs = np.zeros((len(steps) - 1, k))
    for i in range(1, len(steps)):
        prev = steps[i - 1].shapes[:, order[i - 1]]
        match = mac(prev, steps[i].shapes, assemble(steps[i].model).M)
        rows, cols = linear_sum_assignment(-match)
        order[i, rows] = cols
        macs[i - 1, rows] = match[rows, cols]
    freq = np.array([s.frequency_hz[o] for s, o in zip(steps, order)])
    return ModeTracks(frequency_hz=freq, order=order, mac=macs, labels=list(steps[0].labels))
