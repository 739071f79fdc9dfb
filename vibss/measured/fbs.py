"""A flexible foundation by frequency-based substructuring: :class:`Foundation` and the coupling
:func:`couple` behind ``frequency_response(..., foundation=...)``.

The foundation (a car body, a ship deck, a floor) is known by its receptance ``Y_B`` [m/N] at the
ground ends of some of the source's mounts: translations x, y, z of each point in global axes,
point by point, per frequency (shape (3 m, 3 m, nf)). The source is solved with those mounts on
supports of their own (:class:`vibss.model.mounts.Support`), so one exact solve gives its outputs
and the forces into the supports for the inputs ``u`` and for the support motions ``z``::

    y = H_yu u + H_yz z,      g = H_gu u + H_gz z       (g: forces into the foundation [N])

The foundation moves by ``z = Y_B g``; eliminating ``z`` couples the two exactly:

    z = (I - Y_B H_gz)^-1 Y_B H_gu u,    y = H_yu u + H_yz z

This is the LM-FBS coupling (compatibility at the points, equilibrium of the interface forces),
written with the source's blocked dynamic stiffness ``-H_gz`` instead of its free-interface
receptance, so nothing singular is inverted when a mount is stiff.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from .._validate import array
from ..errors import ArgumentError, ModelError
from ..frequency.api import frequency_response
from ..frequency.result import FrequencyResponse
from ..model.model import DOF_NAMES, GROUND, Model
from ..model.mounts import Support
from ..results import ReadOnly

__all__ = ["Foundation", "couple", "AXES"]

AXES = ("x", "y", "z")
"""The translations of each foundation point, in this order."""

CHUNK_BYTES = 2**28
"""The source's mixed response (outputs and interface forces by inputs and interface motions) is
computed a block of frequencies at a time, each block at most this size [B] (256 MB)."""


@dataclass(frozen=True, eq=False)
class Foundation(ReadOnly):
    """A flexible foundation by its receptance at the ground ends of named mounts.

    Parameters
    ----------
    frequencies : (nf,) array_like
        Frequencies [Hz], increasing, > 0; a response with a foundation is computed at exactly these.
    receptance : (3 m, 3 m, nf) array_like
        Complex receptance [m/N]: displacement x, y, z of point ``i`` per force x, y, z at point
        ``j``, global axes, rows and columns point by point in the order of ``points``.
    points : sequence of str
        Names of the source's mounts to ground whose ground ends stand on the foundation.
    name : str
        Name of the foundation (outputs ``foundation.<mount>.x|y|z``).

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
        try:
            y = np.array(self.receptance, dtype=complex)
        except (TypeError, ValueError):
            raise ArgumentError(f"{who}: receptance: expected complex numbers [m/N]", argument="receptance",
                                received=type(self.receptance).__name__) from None
        n = 3 * len(points)
        if y.shape != (n, n, f.size) or not np.all(np.isfinite(y)):
            raise ArgumentError(f"{who}: receptance: expected finite values of shape ({n}, {n}, {f.size}) "
                                f"(x, y, z of {len(points)} points by {f.size} frequencies) [m/N], got shape "
                                f"{y.shape}", argument="receptance", received=y.shape, expected=(n, n, f.size))
        object.__setattr__(self, "frequencies", f)
        object.__setattr__(self, "receptance", y)
        object.__setattr__(self, "points", points)
        super().__post_init__()

    @property
    def frequency_hz(self) -> np.ndarray:
        """(nf,) frequencies [Hz]."""
        return np.asarray(self.frequencies)

    @property
    def outputs(self) -> tuple[str, ...]:
        """The foundation's motion at each point: ``foundation.<mount>.x|y|z`` (with its name)."""
        return tuple(f"{self.name}.{p}.{a}" for p in self.points for a in AXES)

    @classmethod
    def from_model(cls, model: Model, points: Mapping[str, str], frequencies: npt.ArrayLike,
                   name: str = "foundation") -> Foundation:
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

        Returns
        -------
        Foundation
        """
        cps = list(_points(points, "Foundation.from_model").values())
        r = frequency_response(model, [f"{c}.f{a}" for c in cps for a in AXES], [f"{c}.{a}" for c in cps for a in AXES],
                               frequencies=np.asarray(frequencies, dtype=float))
        return cls.from_response(r, points, name)

    @classmethod
    def from_response(cls, response: FrequencyResponse, points: Mapping[str, str],
                      name: str = "foundation") -> Foundation:
        """The receptance in a frequency response (measured, read from UFF or CSV, or computed) whose
        channels are named ``<point>.x|y|z`` (outputs, displacement) by ``<point>.fx|fy|fz`` (inputs).

        Parameters
        ----------
        response : FrequencyResponse
            A receptance [m/N] holding every such channel (others are ignored).
        points : mapping of str to str
            Source mount name -> the point's name in the response.
        name : str
            Name of the foundation.

        Returns
        -------
        Foundation

        Raises
        ------
        SignalError
            A channel the response does not have (named, with did-you-mean).
        """
        from .._validate import name_index

        cps = list(_points(points, "Foundation.from_response").values())
        rows = [name_index(f"{c}.{a}", response.outputs, "outputs", who="Foundation.from_response")
                for c in cps for a in AXES]
        cols = [name_index(f"{c}.f{a}", response.inputs, "inputs", who="Foundation.from_response")
                for c in cps for a in AXES]
        return cls(response.frequency_hz, np.asarray(response.response)[np.ix_(rows, cols)], list(points), name)


def _points(points: Any, who: str) -> Mapping[str, str]:
    if not isinstance(points, Mapping) or not points:
        raise ArgumentError(f"{who}: points: expected a mapping {{mount: point}}, got {points!r}",
                            argument="points", received=points)
    return points


def _on_supports(model: Model, foundation: Foundation) -> tuple[Model, list[str]]:
    """The source with each foundation mount on a support of its own, and the supports' names."""
    mounts = {m.name: m for m in model.mounts}
    names = []
    for p in foundation.points:
        m = mounts.get(p)
        if m is None:
            from ..errors import did_you_mean
            raise ModelError(f"frequency_response: foundation: no mount named {p!r}{did_you_mean(p, mounts)}",
                             argument="foundation", received=p, expected=tuple(mounts))
        if m.to != GROUND:
            raise ModelError(f"frequency_response: foundation: mount {p!r} joins {m.body!r} to {m.to!r}; a "
                             "foundation point must be the ground end of a mount to ground",
                             argument="foundation", received=p)
        names.append(f"fbs_{p}")
    taken = {s.name for s in model.supports} | {b.name for b in model.bodies}
    clash = [s for s in names if s in taken]
    if clash:
        raise ModelError(f"frequency_response: foundation: the names {clash} are taken in the model",
                         argument="foundation", received=clash)
    support = dict(zip(foundation.points, names))
    new = [dataclasses.replace(m, support=support[m.name]) if m.name in support else m for m in model.mounts]
    return model.replace(mounts=new, supports=[*model.supports, *(Support(s) for s in names)]), names


def couple(model: Any, foundation: Foundation, inputs: Sequence[Any] | None, outputs: Sequence[str] | None,
           frequencies: Any, quantity: str, method: Any) -> FrequencyResponse:
    """The frequency response of ``model`` standing on ``foundation`` (see the module docstring).

    Parameters
    ----------
    model : Model
        The source.
    foundation : Foundation
        Its receptance at the ground ends of some of the source's mounts to ground.
    inputs, outputs : sequence of str
        As :func:`vibss.frequency_response` (outputs default: every body DOF); the foundation's
        motions ``foundation.<mount>.x|y|z`` are appended to the outputs.
    frequencies : (nf,) array_like or None
        Must be the foundation's (None: those); a mismatch is an error, never an interpolation.
    quantity : str
        ``"receptance"``, ``"mobility"`` or ``"accelerance"``.
    method : str or callable
        Method of the source's solve.

    Returns
    -------
    FrequencyResponse
    """
    if not isinstance(model, Model):
        raise ArgumentError("frequency_response: foundation: needs the source as a Model (its mounts are named), "
                            f"got {type(model).__name__}", argument="system", received=type(model).__name__)
    f = foundation.frequency_hz
    if frequencies is not None:
        given = np.asarray(frequencies, dtype=float)
        if given.shape != f.shape or not np.array_equal(given, f):
            raise ArgumentError("frequency_response: frequencies: a foundation is known at its own "
                                f"{f.size} frequencies ({f[0]:g} to {f[-1]:g} Hz); give those (or None), got "
                                f"{given.size} others: FBS never interpolates a receptance",
                                argument="frequencies", received=given.size, expected=f.size)
    if inputs is None:
        raise ArgumentError("frequency_response: inputs: required", argument="inputs", received=None)
    src, supports = _on_supports(model, foundation)
    zin = [f"{s}.{a}.disp" for s in supports for a in AXES]
    gout = [f"{s}.f{a}" for s in supports for a in AXES]
    outs = [f"{b.name}.{d}" for b in model.bodies for d in DOF_NAMES] if outputs is None else list(outputs)
    n = len(zin)
    cells = (len(outs) + n) * (len(list(inputs)) + n)
    step = max(1, int(CHUNK_BYTES // (16 * cells)))         # the source's solve, a block of frequencies at a time
    out: np.ndarray | None = None
    for lo in range(0, f.size, step):
        part = slice(lo, lo + step)
        mixed = frequency_response(src, [*inputs, *zin], [*outs, *gout], frequencies=f[part], method=method)
        p, m = len(outs), len(mixed.inputs) - n
        if out is None:
            out = np.empty((p + n, m, f.size), dtype=complex)
        h = np.moveaxis(mixed.response, 2, 0)                 # (nf, rows, columns): one stacked solve
        hyu, hyz, hgu, hgz = h[:, :p, :m], h[:, :p, m:], h[:, p:, :m], h[:, p:, m:]
        yb = np.moveaxis(foundation.receptance[:, :, part], 2, 0)
        z = np.linalg.solve(np.eye(n)[None] - yb @ hgz, yb @ hgu)
        out[:p, :, part] = np.moveaxis(hyu + hyz @ z, 0, 2)
        out[p:, :, part] = np.moveaxis(z, 0, 2)
    assert out is not None
    power = {"receptance": 0, "mobility": 1, "accelerance": 2}[quantity]
    out *= (2j * np.pi * f) ** power
    from ..model.units import times_s

    units = tuple(times_s(u, power) for u in (*mixed.units[:p], *("m",) * n))
    note = (f"{mixed.note}; coupled to {foundation.name!r} at {len(foundation.points)} points by "
            "frequency-based substructuring (exact at the foundation's frequencies)")
    return FrequencyResponse(f, out, (*mixed.outputs[:p], *foundation.outputs), mixed.inputs[:m], units, quantity,
                             f"{mixed.method}+fbs", note, np.zeros(0), model.name, mixed.input_units[:m])
