"""A flexible foundation known by its receptance at the ground ends of some of the source's mounts:
:class:`Foundation`, from a measurement (:meth:`Foundation.from_response`) or from another vibss
model (:meth:`Foundation.from_model`). The coupling is :mod:`vibss.measured.coupling`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from .._validate import array, name_index
from ..errors import ArgumentError
from ..frequency.api import frequency_response
from ..frequency.result import FrequencyResponse
from ..model.model import Model
from ..results import ReadOnly

__all__ = ["Foundation", "AXES", "ROTATIONS", "FORCES", "MOMENTS", "components"]

AXES = ("x", "y", "z")
"""The translations of each foundation point, in this order."""

ROTATIONS = ("rx", "ry", "rz")
"""The rotations of each foundation point (a (6 m, 6 m, nf) receptance), after its translations."""

FORCES = ("fx", "fy", "fz")
"""The forces into each foundation point."""

MOMENTS = ("mx", "my", "mz")
"""The moments into each foundation point, about the point (a (6 m, 6 m, nf) receptance)."""


def components(rotations: bool) -> tuple[tuple[str, ...], tuple[str, ...], tuple[str, ...], tuple[str, ...]]:
    """A foundation point's DOFs, its loads, and their units: translations and forces, with the
    rotations and moments after them when ``rotations``."""
    if rotations:
        return AXES + ROTATIONS, FORCES + MOMENTS, ("m",) * 3 + ("rad",) * 3, ("N",) * 3 + ("N m",) * 3
    return AXES, FORCES, ("m",) * 3, ("N",) * 3


@dataclass(frozen=True, eq=False)
class Foundation(ReadOnly):
    """A flexible foundation by its receptance at the ground ends of named mounts.

    The points are the mounts' own points (a vibss mount acts at one point: its ``at``), on the
    foundation's side. The receptance holds, per frequency, the foundation's motion at the points
    per force at the points, in global axes:

    - (3 m, 3 m, nf): translations x, y, z of point ``i`` per force x, y, z at point ``j``. The
      foundation's rotation at a point still moves the others (the receptance of a rigid or flexible
      body includes it), and it couples the source wherever a mount has only translational rates;
      only a mount's own moment (rotational rates, or a full 6x6 matrix) needs the rotations.
    - (6 m, 6 m, nf): x, y, z, rx, ry, rz of each point per fx, fy, fz, mx, my, mz at each point
      (moments about the point itself, rotations in rad, global axes): the mounts' rotational
      stiffness then couples the foundation's rotation under them.

    Rows and columns run point by point in the order of ``points``.

    Parameters
    ----------
    frequencies : (nf,) array_like
        Frequencies [Hz], increasing, > 0; a response with a foundation is computed at exactly these.
    receptance : (3 m, 3 m, nf) or (6 m, 6 m, nf) array_like
        Complex receptance [m/N, m/(N m), rad/N, rad/(N m)] as above.
    points : sequence of str
        Names of the source's mounts to ground whose ground ends stand on the foundation.
    name : str
        Name of the foundation (outputs ``foundation.<mount>.x|y|z``, forces ``foundation.<mount>.fx|fy|fz``).

    Examples
    --------
    >>> import numpy as np
    >>> f = np.array([10.0, 20.0])
    >>> Foundation(f, np.tile(1e-7 * np.eye(3)[:, :, None], (1, 1, 2)), ["m1"]).receptance.shape
    (3, 3, 2)
    """

    frequencies: Any
    receptance: Any
    points: Sequence[str]
    name: str = "foundation"

    def __post_init__(self) -> None:
        who = "Foundation"
        f = array(self.frequencies, "frequencies", (None,), who=who, unit="Hz")
        if f.size == 0 or f[0] <= 0 or np.any(np.diff(f) <= 0):
            raise ArgumentError(f"{who}: frequencies: expected increasing frequencies > 0 [Hz], got {f.tolist()}",
                                argument="frequencies", received=self.frequencies, expected="increasing, > 0")
        if isinstance(self.points, str) or not all(isinstance(p, str) and p for p in self.points):
            raise ArgumentError(f"{who}: points: expected a list of mount names, got {self.points!r}",
                                argument="points", received=self.points)
        points = tuple(self.points)
        if len(set(points)) != len(points) or not points:
            raise ArgumentError(f"{who}: points: expected distinct mount names, got {list(points)}",
                                argument="points", received=self.points)
        if not isinstance(self.name, str) or not self.name or "." in self.name:
            raise ArgumentError(f"{who}: name: expected a non-empty name without '.', got {self.name!r}",
                                argument="name", received=self.name)
        try:
            y = np.array(self.receptance, dtype=complex)
        except (TypeError, ValueError):
            raise ArgumentError(f"{who}: receptance: expected complex numbers [m/N]", argument="receptance",
                                received=type(self.receptance).__name__) from None
        m = len(points)
        if y.shape not in ((3 * m, 3 * m, f.size), (6 * m, 6 * m, f.size)) or not np.all(np.isfinite(y)):
            raise ArgumentError(f"{who}: receptance: expected finite values of shape ({3 * m}, {3 * m}, {f.size}) "
                                f"(x, y, z of {m} points by {f.size} frequencies) or ({6 * m}, {6 * m}, {f.size}) "
                                f"(with rx, ry, rz) [m/N], got shape {y.shape}", argument="receptance",
                                received=y.shape, expected=(3 * m, 3 * m, f.size))
        object.__setattr__(self, "frequencies", f)
        object.__setattr__(self, "receptance", y)
        object.__setattr__(self, "points", points)
        super().__post_init__()

    @property
    def frequency_hz(self) -> np.ndarray:
        """(nf,) frequencies [Hz]."""
        return np.asarray(self.frequencies)

    @property
    def rotations(self) -> bool:
        """Whether the receptance holds the points' rotations (6 DOFs a point)."""
        return bool(self.receptance.shape[0] == 6 * len(self.points))

    @property
    def dofs(self) -> tuple[str, ...]:
        """The DOFs of each point: ``x y z`` (and ``rx ry rz``)."""
        return components(self.rotations)[0]

    @property
    def outputs(self) -> tuple[str, ...]:
        """The foundation's motion at each point: ``foundation.<mount>.x|y|z`` (with its name)."""
        return tuple(f"{self.name}.{p}.{a}" for p in self.points for a in self.dofs)

    @property
    def forces(self) -> tuple[str, ...]:
        """The force (and moment) into each point: ``foundation.<mount>.fx|fy|fz`` (``mx|my|mz``)."""
        return tuple(f"{self.name}.{p}.{c}" for p in self.points for c in components(self.rotations)[1])

    @property
    def units(self) -> tuple[str, ...]:
        """The units of :attr:`outputs` then :attr:`forces`, point by point (m, rad; N, N m)."""
        _, _, motion, load = components(self.rotations)
        return motion * len(self.points) + load * len(self.points)

    @classmethod
    def from_model(cls, model: Model, points: Mapping[str, str], frequencies: npt.ArrayLike,
                   name: str = "foundation", rotations: bool = False) -> Foundation:
        """The receptance of another vibss model at its control points.

        Parameters
        ----------
        model : Model
            The foundation, with a control point at each mount's ground end.
        points : mapping of str to str
            Source mount name -> the foundation model's control point under it.
        frequencies : (nf,) array_like
            Frequencies [Hz], > 0.
        name : str
            Name of the foundation.
        rotations : bool
            Also the rotations (6 DOFs a point): the rotation and moment of a rigid body are those
            of the control point's body (``<body>.rx`` by ``<body>.mx``).

        Returns
        -------
        Foundation
        """
        cps = list(_points(points, "Foundation.from_model").values())
        bodies = {c.name: c.body for c in model.control_points}
        outs, ins = [], []
        for c in cps:
            outs += [f"{c}.{a}" for a in AXES]
            ins += [f"{c}.{a}" for a in FORCES]
            if rotations:
                body = bodies.get(c, c)
                outs += [f"{body}.{a}" for a in ROTATIONS]
                ins += [f"{body}.{a}" for a in MOMENTS]
        uo, ui = list(dict.fromkeys(outs)), list(dict.fromkeys(ins))     # a body's rotation once
        r = frequency_response(model, ui, uo, frequencies=np.asarray(frequencies, dtype=float))
        y = np.asarray(r.response)[np.ix_([uo.index(o) for o in outs], [ui.index(i) for i in ins])]
        return cls(r.frequency_hz, y, list(points), name)

    @classmethod
    def from_response(cls, response: FrequencyResponse, points: Mapping[str, str],
                      name: str = "foundation", rotations: bool = False) -> Foundation:
        """The receptance in a frequency response (measured, read from UFF or CSV, or computed) whose
        channels are named ``<point>.x|y|z`` (outputs, displacement) by ``<point>.fx|fy|fz`` (inputs),
        and with ``rotations`` also ``<point>.rx|ry|rz`` by ``<point>.mx|my|mz``.

        Parameters
        ----------
        response : FrequencyResponse
            A receptance [m/N] holding every such channel (others are ignored).
        points : mapping of str to str
            Source mount name -> the point's name in the response.
        name : str
            Name of the foundation.
        rotations : bool
            Also the rotations and moments.

        Returns
        -------
        Foundation

        Raises
        ------
        SignalError
            A channel the response does not have (named, with did-you-mean).
        """
        cps = list(_points(points, "Foundation.from_response").values())
        dofs, loads, _, _ = components(rotations)
        rows = [name_index(f"{c}.{a}", response.outputs, "outputs", who="Foundation.from_response")
                for c in cps for a in dofs]
        cols = [name_index(f"{c}.{a}", response.inputs, "inputs", who="Foundation.from_response")
                for c in cps for a in loads]
        return cls(response.frequency_hz, np.asarray(response.response)[np.ix_(rows, cols)], list(points), name)


def _points(points: Any, who: str) -> Mapping[str, str]:
    if not isinstance(points, Mapping) or not points:
        raise ArgumentError(f"{who}: points: expected a mapping {{mount: point}}, got {points!r}",
                            argument="points", received=points)
    return points
