"""The source coupled to a :class:`~vibss.measured.fbs.Foundation` by frequency-based substructuring:
:func:`coupled` (the one coupling path) and :func:`couple` behind ``frequency_response(..., foundation=)``.

The source is solved with the foundation's mounts on supports of their own
(:class:`vibss.model.mounts.Support`), so one exact solve gives its outputs and the forces (and
moments) into the supports for the inputs ``u`` and for the supports' motions ``z``, both taken at
the mounts' points::

    y = H_yu u + H_yz z,      g = H_gu u + H_gz z       (g: forces into the foundation [N])

``H_gu`` holds the source's blocked forces (``z = 0``), ``-H_gz`` its blocked dynamic stiffness at
the points. The foundation moves by ``z = Y_B g``; eliminating ``z`` couples the two exactly::

    z = (I - Y_B H_gz)^-1 Y_B H_gu u,    y = H_yu u + H_yz z,    g = H_gu u + H_gz z

This is the LM-FBS coupling (compatibility at the points, equilibrium of the interface forces),
written with the blocked dynamic stiffness instead of the source's free-interface receptance, so
nothing singular is inverted when a mount is stiff. A support's six DOFs are about the global
origin; with rotations (a (6 m, 6 m, nf) receptance) its motion and load are taken to the mount's
point ``p``: ``[t; r]_origin = T [u; r]_p`` with ``T = [[I, S(p)], [0, I]]`` (``S(p) v = p x v``),
and ``g_p = T^T g_origin`` (moments about ``p``).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import ArgumentError, ModelError, did_you_mean
from ..methods import Check, Claim, Method, decide
from ..frequency.api import QUANTITIES, frequency_response
from ..frequency.result import FrequencyResponse
from ..model.model import DOF_NAMES, GROUND, Model
from ..model.mounts import Support
from ..linear.plant.build import build_plant
from ..linear.plant.plant import Plant
from ..model.units import input_unit, times_s
from .fbs import Foundation, components
from .interface import blocks

__all__ = ["Coupled", "coupled", "couple", "on_supports", "source_response", "matching", "CHUNK_BYTES", "FBS"]

FBS = Method("lm-fbs", lambda *a: None, exact=True, claim=Claim(
    1e-9, exact=True, conditions="the source's exact solve split at the interface (low rank plus the mounts' own "
    "blocks) and one LU per frequency; checked at three frequencies against the dense coupling of the source's "
    "frequency response"))
"""How the coupling works, and what it claims."""

CHUNK_BYTES = 2**25
"""The source's mixed response (outputs and interface forces by inputs and interface motions) is
computed a block of frequencies at a time, each block at most this size [B] (32 MB: the per-frequency n x n arrays stay near the cache; measured 2x faster than 256 MB at 600 interface DOFs)."""


@dataclass(frozen=True)
class Coupled:
    """The coupled receptances (per unit input, before any mobility or accelerance factor).

    Attributes
    ----------
    frequency_hz : (nf,) ndarray
        Frequencies [Hz] (the foundation's, or those selected from them).
    y : (p, m, nf) complex ndarray
        The source's outputs.
    z : (n, m, nf) complex ndarray
        The foundation's motion at the points [m, rad].
    g : (n, m, nf) complex ndarray
        The forces (and moments about the points) into the foundation [N, N m].
    outputs, inputs, units, input_units : tuple of str
        The source's outputs and inputs with their units.
    method, note : str
        The source's solve.
    """

    frequency_hz: np.ndarray
    y: np.ndarray
    z: np.ndarray
    g: np.ndarray
    outputs: tuple[str, ...]
    inputs: tuple[str, ...]
    units: tuple[str, ...]
    input_units: tuple[str, ...]
    method: str
    note: str


def on_supports(model: Any, points: Sequence[str], who: str) -> tuple[Model, list[str]]:
    """The source with each of the mounts ``points`` on a support of its own, and the supports' names."""
    if not isinstance(model, Model):
        raise ArgumentError(f"{who}: needs the source as a Model (its mounts are named), got "
                            f"{type(model).__name__}", argument="system", received=type(model).__name__)
    mounts = {m.name: m for m in model.mounts}
    for p in points:
        m = mounts.get(p)
        if m is None:
            raise ModelError(f"{who}: points: no mount named {p!r}{did_you_mean(p, mounts)}",
                             argument="points", received=p, expected=tuple(mounts))
        if m.to != GROUND:
            raise ModelError(f"{who}: points: mount {p!r} joins {m.body!r} to {m.to!r}; a point must be the "
                             "ground end of a mount to ground", argument="points", received=p)
    names = [f"fbs_{p}" for p in points]
    taken = {s.name for s in model.supports} | {b.name for b in model.bodies}
    clash = [s for s in names if s in taken]
    if clash:
        raise ModelError(f"{who}: points: the names {clash} are taken in the model", argument="points",
                         received=clash)
    support = dict(zip(points, names))
    new = [dataclasses.replace(m, support=support[m.name]) if m.name in support else m for m in model.mounts]
    return model.replace(mounts=new, supports=[*model.supports, *(Support(s) for s in names)]), names


def _skews(model: Model, points: Sequence[str]) -> np.ndarray:
    """(m, 3, 3) ``S(p)`` of each point: ``S(p) v = p x v``."""
    mounts = {m.name: m for m in model.mounts}
    p = np.array([model.mount_point(mounts[n]) for n in points], dtype=float).reshape(len(points), 3)
    s = np.zeros((len(points), 3, 3))
    s[:, 0, 1], s[:, 0, 2], s[:, 1, 2] = -p[:, 2], p[:, 1], -p[:, 0]
    return s - np.transpose(s, (0, 2, 1))


def to_points(h: np.ndarray, skews: np.ndarray, rows: slice | None, cols: slice | None) -> None:
    """In place: rows ``g_p = T^T g_origin`` and columns ``H T`` of ``h`` (..., rows, cols), the
    interface rows/columns six a point (see the module docstring)."""
    m = skews.shape[0]
    if cols is not None:
        c = h[..., cols].reshape(*h.shape[:-1], m, 6)
        c[..., 3:] += np.einsum("...ki,kij->...kj", c[..., :3], skews)
        h[..., cols] = c.reshape(*h.shape[:-1], 6 * m)
    if rows is not None:
        r = np.swapaxes(h[..., rows, :], -1, -2).reshape(*h.shape[:-2], h.shape[-1], m, 6)
        r[..., 3:] -= np.einsum("kij,...kj->...ki", skews, r[..., :3])
        h[..., rows, :] = np.swapaxes(r.reshape(*h.shape[:-2], h.shape[-1], 6 * m), -1, -2)


def signals(supports: Sequence[str], rotations: bool) -> tuple[list[str], list[str]]:
    """The supports' motion inputs and force outputs, point by point."""
    dofs, loads, _, _ = components(rotations)
    return ([f"{s}.{a}.disp" for s in supports for a in dofs], [f"{s}.{a}" for s in supports for a in loads])


def source_response(src: Model, inputs: Sequence[Any], outputs: Sequence[str], f: np.ndarray,
                    method: Any) -> Iterator[tuple[slice, FrequencyResponse]]:
    """The source's response a block of frequencies at a time (:data:`CHUNK_BYTES` each)."""
    cells = max(1, len(outputs) * len(inputs))
    step = max(1, int(CHUNK_BYTES // (16 * cells)))
    for lo in range(0, f.size, step):
        part = slice(lo, lo + step)
        yield part, frequency_response(src, inputs, outputs, frequencies=f[part], method=method)


def matching(foundation: Foundation, frequencies: Any, who: str) -> None:
    """Raise unless ``frequencies`` are the foundation's (None passes): a receptance is never interpolated."""
    if frequencies is None:
        return
    f = foundation.frequency_hz
    given = np.atleast_1d(np.asarray(frequencies, dtype=float))
    if given.shape != f.shape or not np.array_equal(given, f):
        raise ArgumentError(f"{who}: frequencies: the foundation {foundation.name!r} is known at its own "
                            f"{f.size} frequencies ({f[0]:g} to {f[-1]:g} Hz); give those (or None), got "
                            f"{given.size} others ({given.min():g} to {given.max():g} Hz): FBS never "
                            "interpolates a receptance", argument="frequencies", received=given.size,
                            expected=f.size)


def coupled(model: Any, foundation: Foundation, inputs: Sequence[Any] | None, outputs: Sequence[str] | None,
            select: Any = None, method: Any = "auto", who: str = "frequency_response") -> Coupled:
    """The source ``model`` on ``foundation``, exactly, at the foundation's frequencies.

    Parameters
    ----------
    model : Model
        The source.
    foundation : Foundation
        Its receptance at the ground ends of some of the source's mounts to ground.
    inputs, outputs : sequence of str
        As :func:`vibss.frequency_response` (outputs default: every body DOF).
    select : index or None
        Which of the foundation's frequencies (a boolean mask or indices; None: all).
    method : str or callable
        Method of the source's solve.
    who : str
        The public function, for messages.

    Returns
    -------
    Coupled
    """
    if not isinstance(foundation, Foundation):
        raise ArgumentError(f"{who}: foundation: expected a vibss.Foundation, got {type(foundation).__name__}",
                            argument="foundation", received=type(foundation).__name__)
    if inputs is None:
        raise ArgumentError(f"{who}: inputs: required", argument="inputs", received=None)
    if not (isinstance(method, str) and method in ("auto", "direct")):
        raise ArgumentError(f"{who}: method: on a foundation the source is solved exactly and split at the "
                            f"interface ('auto' or 'direct'), got {method!r}", argument="method",
                            received=method, expected=("auto", "direct"))
    src, supports = on_supports(model, foundation.points, f"{who}: foundation")
    zin, gout = signals(supports, foundation.rotations)
    outs = [f"{b.name}.{d}" for b in model.bodies for d in DOF_NAMES] if outputs is None else list(outputs)
    idx = np.arange(foundation.frequency_hz.size) if select is None else np.arange(foundation.frequency_hz.size)[select]
    f = foundation.frequency_hz[idx]
    skews = _skews(model, foundation.points) if foundation.rotations else None
    n, p = len(zin), len(outs)
    plant = build_plant(src, [*inputs, *zin], [*outs, *gout])
    m = len(plant.inputs) - n
    y, z, g = (np.empty((k, m, f.size), dtype=complex) for k in (p, n, n))
    step = max(1, int(CHUNK_BYTES // (16 * max(1, n * (n + m) + p * (n + m)))))
    for lo in range(0, f.size, step):                   # a block of frequencies at a time
        part = slice(lo, lo + step)
        b = blocks(plant, 2j * np.pi * f[part], p, m, skews)
        yb = np.moveaxis(foundation.receptance[:, :, idx[part]], 2, 0)
        zz = np.linalg.solve(b.operator(yb), yb @ b.hgu)
        y[:, :, part] = np.moveaxis(b.hy[:, :, :m] + b.hy[:, :, m:] @ zz, 0, 2)
        z[:, :, part] = np.moveaxis(zz, 0, 2)
        g[:, :, part] = np.moveaxis(b.hgu + b.gz_times(zz), 0, 2)
    sample = np.unique([0, f.size // 2, f.size - 1])
    dense = _dense(src, [*inputs, *zin], [*outs, *gout], f[sample], foundation.receptance[:, :, idx[sample]],
                   p, m, skews)
    decision = decide([FBS], lambda _: (y, z, g), where=who, auto=False,
                      check=lambda _, a: _check(a, dense, sample))
    note = (f"the source's exact solve ({plant.n} DOFs) split at the interface; coupled to {foundation.name!r} "
            f"at {len(foundation.points)} points by frequency-based substructuring (exact at the foundation's "
            f"frequencies); {decision.note()}")
    return Coupled(f, y, z, g, plant.outputs[:p], plant.inputs[:m], _units(plant, p), _input_units(plant, m),
                   "direct+fbs", note)


def _dense(src: Model, inputs: list[Any], outputs: list[str], f: np.ndarray, receptance: np.ndarray, p: int,
           m: int, skews: np.ndarray | None) -> tuple[np.ndarray, ...]:
    """``y, z, g`` (per frequency first) by the dense coupling of the source's frequency response at ``f``."""
    h = np.array(np.moveaxis(frequency_response(src, inputs, outputs, frequencies=f, method="direct").response, 2, 0))
    if skews is not None:
        to_points(h, skews, slice(p, None), slice(m, None))
    hyu, hyz, hgu, hgz = h[:, :p, :m], h[:, :p, m:], h[:, p:, :m], h[:, p:, m:]
    yb = np.moveaxis(receptance, 2, 0)
    zz = np.linalg.solve(np.eye(hgz.shape[1])[None] - yb @ hgz, yb @ hgu)
    return hyu + hyz @ zz, zz, hgu + hgz @ zz


def _check(fast: tuple[np.ndarray, ...], dense: tuple[np.ndarray, ...], sample: np.ndarray) -> Check:
    """The coupled ``y, z, g`` at the sampled frequencies against the dense coupling, each row
    relative to its largest value over the band."""
    err = 0.0
    for a, b in zip(fast, dense):
        scale = np.abs(a).max(axis=(1, 2))
        scale = np.where(scale > 0, scale, 1.0)
        err = max(err, float((np.abs(np.moveaxis(a[:, :, sample], 2, 0) - b) / scale[None, :, None]).max(initial=0.0)))
    return Check(err, FBS.claim.tolerance if FBS.claim else 0.0,
                 f"the dense coupling of the source's frequency response at {sample.size} frequencies")


def _units(plant: Plant, p: int) -> tuple[str, ...]:
    return tuple(plant.units[:p])


def _input_units(plant: Plant, m: int) -> tuple[str, ...]:
    return tuple(input_unit(u, k) for u, k in zip(plant.inputs[:m], plant.kinds[:m]))


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
        motions ``foundation.<mount>.x|y|z`` and the forces into it ``foundation.<mount>.fx|fy|fz``
        (with rotations also ``rx|ry|rz`` and ``mx|my|mz``, moments about the point) are appended.
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
    matching(foundation, frequencies, "frequency_response")
    c = coupled(model, foundation, inputs, outputs, None, method)
    f = c.frequency_hz
    power = QUANTITIES[quantity]
    out = np.concatenate([c.y, c.z, c.g]) * (2j * np.pi * f) ** power
    units = tuple(times_s(u, power) for u in (*c.units, *foundation.units))
    return FrequencyResponse(f, out, (*c.outputs, *foundation.outputs, *foundation.forces), c.inputs, units,
                             quantity, c.method, c.note, np.zeros(0), model.name, c.input_units)
