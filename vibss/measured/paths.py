"""Transfer path analysis on a flexible foundation: :func:`transfer_paths`, behind
``path_contributions(..., foundation=...)``.

The coupled solve (:func:`vibss.measured.coupling.coupled`) gives the force ``g_j`` (and moment)
each mount passes into the foundation at its point ``j``. The foundation's receptance carries each
to the receiver point ``r``: path ``j`` contributes ``Y_B[r, j] g_j`` to the receiver's motion, and
the paths sum to it (``z_r = sum_j Y_B[r, j] g_j``, the coupling's compatibility), which is the
check: the sum against the coupled solve's own ``z_r``.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from ..errors import SignalError, did_you_mean
from ..insight.result import PathContributions
from ..methods import Check, Claim, Method, decide
from .coupling import coupled, matching
from .fbs import Foundation, components

__all__ = ["transfer_paths", "TPA"]

TPA = Method("transfer path analysis", coupled, exact=True, claim=Claim(
    1e-9, exact=True, conditions="the paths (receptance times each mount's coupled force) summed against the "
    "receiver's coupled motion"))
"""How :func:`transfer_paths` works, and what it claims."""

_WHO = "path_contributions"


def _receiver(foundation: Foundation, receiver: Any) -> int:
    """Position of the receiver point among the foundation's points (``m1`` or ``foundation.m1``)."""
    name = receiver[len(foundation.name) + 1:] if isinstance(receiver, str) and receiver.startswith(
        f"{foundation.name}.") else receiver
    if name not in foundation.points:
        raise SignalError(f"{_WHO}: receiver: on a foundation the receiver is one of its points "
                          f"{list(foundation.points)} (or '{foundation.name}.<point>'), got {receiver!r}"
                          f"{did_you_mean(str(receiver), foundation.points)}", argument="receiver",
                          received=receiver, expected=foundation.points)
    return foundation.points.index(name)


def transfer_paths(model: Any, inputs: Sequence[Any], frequencies: Any, receiver: Any, method: Any,
                   foundation: Foundation) -> PathContributions:
    """Each mount path's contribution to the motion of a foundation point (see the module docstring).

    Parameters
    ----------
    model : Model
        The source.
    inputs : sequence of str or Excitation
        Input signals.
    frequencies : (nf,) array_like or None
        The foundation's frequencies [Hz] (None: those); others are an error.
    receiver : str
        A foundation point (a mount name in ``foundation.points``, or ``foundation.<mount>``).
    method : str or callable
        Method of the source's solve.
    foundation : Foundation
        The flexible foundation.

    Returns
    -------
    PathContributions
        ``paths`` the foundation's points, ``components`` the receiver's ``x y z`` (``rx ry rz``),
        ``forces`` (paths, components, inputs, frequencies) [m, rad per input unit].
    """
    matching(foundation, frequencies, _WHO)
    r = _receiver(foundation, receiver)
    c = coupled(model, foundation, inputs, None, None, method, _WHO)
    k, m = len(foundation.dofs), len(foundation.points)
    rows = slice(k * r, k * (r + 1))
    y = foundation.receptance[rows].reshape(k, m, k, -1)                 # (k, paths, k, nf)
    g = c.g.reshape(m, k, c.g.shape[1], -1)                              # (paths, k, inputs, nf)
    contributions = np.einsum("apbn,pbin->pain", y, g)
    decision = decide([TPA], lambda _: contributions, where=_WHO, auto=False,
                      check=lambda _, a: _check(a, c.z[rows]))
    units = components(foundation.rotations)[2]
    note = f"{c.note}; the paths into {foundation.name!r} carried to {foundation.points[r]!r}; {decision.note()}"
    return PathContributions(receiver=f"{foundation.name}.{foundation.points[r]}", frequency=c.frequency_hz,
                             paths=tuple(foundation.points), components=foundation.dofs, forces=contributions,
                             input_names=c.inputs, method=c.method, note=note, component_units=units)


def _check(contributions: np.ndarray, motion: np.ndarray) -> Check:
    """The paths' sum against the receiver's coupled motion, per component (relative to its largest)."""
    scale = np.abs(motion).max(axis=(1, 2), keepdims=True)
    scale = np.where(scale > 0, scale, 1.0)
    err = float((np.abs(contributions.sum(axis=0) - motion) / scale).max())
    return Check(err, TPA.claim.tolerance if TPA.claim else 0.0, "the receiver's coupled motion")
