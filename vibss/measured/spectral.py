"""Random response of a source on a flexible foundation: :func:`random_on_foundation`, behind
``random_response(..., foundation=...)``.

A foundation is known at its own frequencies only, so the adaptive quadrature of
:func:`vibss.random_response` (which bisects wherever it needs) cannot be used: the coupled FRF
(:func:`vibss.measured.coupling.coupled`, exact) is evaluated at the foundation's frequencies inside
the PSD band, and each mean square ``int S_yy df = int S_yy f d(ln f)`` is the trapezoid rule in
``ln f`` on them. That grid is the method's accuracy; it states it: the trapezoid against the
trapezoid on every other point (Richardson: ``|T_h - T_2h| / 3``) plus the slivers between the band's
edges and the nearest foundation frequency inside it (integrand there taken flat), relative to the
mean square, held to ``rtol`` (a :class:`~vibss.errors.VibssWarning` when missed).
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from typing import Any

import numpy as np

from ..errors import ArgumentError, VibssWarning
from ..methods import Check, Claim, Method
from ..random.kernels import miles
from ..random.psd import PSD
from ..random.result import RandomResponse
from .coupling import coupled
from .fbs import Foundation

__all__ = ["random_on_foundation", "ON_GRID"]

ON_GRID = Method("trapezoid on the foundation's frequencies", coupled, exact=False, claim=Claim(
    1e-6, conditions="the PSD band inside the foundation's frequencies and resolved by them: the error "
    "estimated by Richardson (every other point) plus the band-edge slivers, held to rtol"))
"""How :func:`random_on_foundation` integrates, and what it claims (``rtol`` replaces the tolerance)."""

_WHO = "random_response"


def _grid(foundation: Foundation, band: tuple[float, float]) -> np.ndarray:
    """The mask of the foundation's frequencies inside the PSD band; an error when the band leaves them."""
    f = foundation.frequency_hz
    lo, hi = band
    if lo < f[0] * (1 - 1e-12) or hi > f[-1] * (1 + 1e-12):
        raise ArgumentError(f"{_WHO}: inputs: the PSD band {lo:g} to {hi:g} Hz reaches outside the frequencies of "
                            f"the foundation {foundation.name!r} ({f[0]:g} to {f[-1]:g} Hz); a receptance is never "
                            "extrapolated: narrow the PSDs or give the foundation over the band",
                            argument="inputs", received=(lo, hi), expected=(float(f[0]), float(f[-1])))
    sel = (f >= lo * (1 - 1e-12)) & (f <= hi * (1 + 1e-12))
    if sel.sum() < 3:
        raise ArgumentError(f"{_WHO}: inputs: the PSD band {lo:g} to {hi:g} Hz holds {int(sel.sum())} of the "
                            f"foundation {foundation.name!r}'s frequencies; at least 3 are needed to integrate",
                            argument="inputs", received=int(sel.sum()), expected=3)
    return sel


def _trapezoid(w: np.ndarray, u: np.ndarray) -> np.ndarray:
    return np.sum(0.5 * (w[:, 1:] + w[:, :-1]) * np.diff(u), axis=1)


def estimate(w: np.ndarray, u: np.ndarray, band: tuple[float, float]) -> tuple[np.ndarray, np.ndarray]:
    """Mean squares (trapezoid in ``u = ln f`` of ``w = S f``) and their estimated relative error."""
    ms = _trapezoid(w, u)
    half = _trapezoid(w[:, ::2], u[::2])
    if (u.size - 1) % 2:            # an odd number of intervals: the last one closes the coarse rule
        half = half + 0.5 * (w[:, -2] + w[:, -1]) * (u[-1] - u[-2])
    sliver = w[:, 0] * (u[0] - np.log(band[0])) + w[:, -1] * (np.log(band[1]) - u[-1])
    err = (np.abs(ms - half) / 3.0 + np.abs(sliver)) / np.maximum(np.abs(ms), 1e-300)
    return ms, err


def random_on_foundation(model: Any, names: Sequence[str], psds: Sequence[PSD], rho: np.ndarray,
                         outputs: Sequence[str] | None, foundation: Foundation, rtol: float, method: Any,
                         correlated: bool) -> RandomResponse:
    """Output PSDs and RMS values of ``model`` on ``foundation`` (see the module docstring).

    Parameters
    ----------
    model : Model
        The source.
    names : sequence of str
        Input signals.
    psds : sequence of PSD
        Their one-sided PSDs.
    rho : (m, m) complex ndarray
        Input coherences.
    outputs : sequence of str or None
        The source's outputs (default every body DOF); the foundation's motions and the forces into
        it are appended.
    foundation : Foundation
        The flexible foundation.
    rtol : float
        Relative accuracy each mean square is checked against.
    method : str or callable
        Method of the source's solve.
    correlated : bool
        Whether coherences were given (for the note).

    Returns
    -------
    RandomResponse
    """
    band = (min(p.band[0] for p in psds), max(p.band[1] for p in psds))
    sel = _grid(foundation, band)
    c = coupled(model, foundation, names, outputs, sel, method, _WHO)
    f = c.frequency_hz
    h = np.concatenate([c.y, c.z, c.g])                              # (p, m, nf)
    s_in = np.array([p(f) for p in psds])
    root = np.sqrt(s_in)
    s_uu = rho[:, :, None] * root[:, None, :] * root[None, :, :]
    s_yy = np.einsum("pan,abn,pbn->pn", h, s_uu, np.conj(h)).real
    u = np.log(f)
    ms, err = estimate(s_yy * f, u, band)
    check = Check(float(err.max()), rtol, f"Richardson and the band-edge slivers on {f.size} frequencies")
    if not check.ok:
        worst = int(np.argmax(err))
        outs_all = (*c.outputs, *foundation.outputs, *foundation.forces)
        warnings.warn(f"{_WHO}: on the foundation {foundation.name!r} the mean squares are integrated on its "
                      f"{f.size} frequencies in the band, estimated error {err.max():.1e} (of "
                      f"{outs_all[worst]!r}) > rtol = {rtol:g}: give the foundation at more frequencies, or "
                      "loosen rtol", VibssWarning, stacklevel=3)
    units = (*c.units, *foundation.units)
    outs = (*c.outputs, *foundation.outputs, *foundation.forces)
    note = (f"{ON_GRID.name}: {f.size} of its frequencies over {band[0]:g} ... {band[1]:g} Hz (a receptance is "
            f"never interpolated), estimated relative error {err.max():.1e} ({check.text()}); coupled exactly "
            "by frequency-based substructuring; inputs " + ("correlated as given" if correlated else "uncorrelated"))
    return RandomResponse(f, s_yy, np.sqrt(np.maximum(ms, 0.0)), s_in, outs, tuple(names), units,
                          miles(outs, names, f, s_yy, s_in, np.abs(h)), c.method, note=note,
                          input_units=tuple(p.unit for p in psds))
