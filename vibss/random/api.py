"""Response to stationary random excitation: output PSDs and RMS values from input PSDs and the exact
frequency response.

For inputs ``u`` with one-sided cross-spectral matrix ``S_uu(f)`` the outputs have
``S_yy(f) = H(f) S_uu(f) H(f)^H`` and mean squares ``int S_yy df``. ``H`` is the one exact FRF
(:func:`vibss.frequency_response`); the integral is adaptive in ``ln f`` (Simpson against trapezoid
on every interval, bisected until each is below ``rtol`` of the total), with the PSD breakpoints
and the natural frequencies in the band on the grid, so sharp resonances are resolved whatever the
damping. Inputs are uncorrelated unless ``correlation`` couples them
(``S_ab = rho_ab sqrt(S_aa S_bb)``, ``rho`` complex with ``|rho| <= 1``).

Miles's single-mode estimate ``sqrt(pi/2 f_n Q W(f_n))`` is shown beside the exact RMS for
acceleration outputs under one acceleration input, with ``f_n`` the output PSD's peak and ``Q``
the transmissibility there.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from .. import _validate as v
from ..errors import ArgumentError
from .kernels import adaptive_grid, coherence, kind, miles
from .psd import as_psd
from .result import RandomResponse

__all__ = ["random_response"]


def random_response(system: Any, inputs: Mapping[str, Any], outputs: Sequence[str] | None = None, *,
                    correlation: Mapping[tuple[str, str], complex] | None = None, rtol: float = 1e-6,
                    method: str = "auto", max_points: int = 200_000, foundation: Any = None) -> RandomResponse:
    """Output PSDs and RMS values under stationary random inputs.

    Parameters
    ----------
    system : Model, Assembly or Plant
        The system.
    inputs : mapping of str to PSD or (frequency_hz, level)
        Input signal (``'ground.z.acc'``, ``'engine.fz'`` ...) to its one-sided PSD: a
        :class:`~vibss.random.psd.PSD` or a ``(frequency_hz, level)`` pair in g²/Hz for
        accelerations, N²/Hz for forces, m²/Hz for displacements (log-log between breakpoints).
    outputs : sequence of str or None
        Output signals (default every body DOF's displacement).
    correlation : mapping of (str, str) to complex, or None
        Coherence ``rho_ab`` of input pairs (``S_ab = rho_ab sqrt(S_aa S_bb)``, ``S_ab`` the
        spectrum of ``u_a conj(u_b)``; ``S_ba = conj(S_ab)``); default: none.
    rtol : float
        Relative accuracy of each mean square (adaptive quadrature).
    method : str
        FRF method (as :func:`vibss.frequency_response`).
    max_points : int
        Limit on the frequencies evaluated.
    foundation : Foundation or None
        A flexible foundation under some of the mounts to ground (:class:`vibss.Foundation`),
        coupled exactly; its motions and the forces into it are appended to the outputs. A
        receptance is known at its own frequencies only: the mean squares are then the trapezoid
        rule in ``ln f`` on the foundation's frequencies inside the PSD band (which must lie within
        them), their error estimated and held to ``rtol`` with a warning
        (:mod:`vibss.measured.spectral`), not the adaptive quadrature.

    Returns
    -------
    RandomResponse

    Examples
    --------
    >>> import vibss
    >>> t = vibss.MountType("iso", [1e5, 1e5, 1e5], damping=[40.0] * 3)
    >>> m = vibss.Model([vibss.Body("box", 20.0, [1, 1, 1])], [vibss.Mount("m", t, "box")])
    >>> r = random_response(m, {"ground.z.acc": ([20, 2000], [0.04, 0.04])}, ["box.z.acc"])
    >>> r.rms.shape
    (1,)
    """
    from ..frequency.api import frequency_response
    from ..linear.plant.plant import Plant
    from ..linear.plant.build import build_plant
    from ..modal.api import modes

    who = "random_response"
    if not isinstance(inputs, Mapping) or not inputs:
        raise ArgumentError(f"{who}: inputs: expected a mapping of input signal to PSD, got {inputs!r}",
                            argument="inputs", received=inputs)
    rtol = v.number(rtol, "rtol", who=who, minimum=0.0, strict=True)
    names = list(inputs)
    psds = [as_psd(inputs[n], kind(n), n) for n in names]
    rho = coherence(names, correlation, who)
    if foundation is not None:
        from ..measured.spectral import random_on_foundation
        return random_on_foundation(system, names, psds, rho, outputs, foundation, rtol, method, bool(correlation))
    plant = system if isinstance(system, Plant) else build_plant(system, names, outputs)
    band = (min(p.band[0] for p in psds), max(p.band[1] for p in psds))
    if band[0] == band[1]:
        raise ArgumentError(f"{who}: inputs: the PSDs span no band ({band[0]} Hz)", argument="inputs")
    try:
        natural = modes(plant.model if hasattr(plant, "model") and plant.model is not None else system).frequency_hz
    except Exception:                       # a plant without its model: no modes on the grid
        natural = np.zeros(0)
    extra = sorted({f for p in psds for f in p.frequency_hz} | {float(f) for f in natural if f > 0}
                   | {float(f) * (1 + d) for f in natural if f > 0 for d in (-1e-3, 1e-3)})
    used: set[str] = set()

    def integrand(u: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        f = np.exp(u)
        r = frequency_response(plant, frequencies=f, method=method)
        used.add(r.method)
        h = r.response                                         # (p, m, nf)
        s_in = np.array([p(f) for p in psds])                  # (m, nf)
        root = np.sqrt(s_in)
        s_uu = rho[:, :, None] * root[:, None, :] * root[None, :, :]
        s_yy = np.einsum("pan,abn,pbn->pn", h, s_uu, np.conj(h)).real
        return s_yy, s_in, np.abs(h)

    u, g_y, g_in, habs = adaptive_grid(integrand, band, extra, rtol, max_points, len(plant.outputs), who)
    f = np.exp(u)
    w = g_y * f
    ms = np.sum(0.5 * (w[:, 1:] + w[:, :-1]) * np.diff(u), axis=1)
    rms = np.sqrt(np.maximum(ms, 0.0))
    return RandomResponse(f, g_y, rms, g_in, tuple(plant.outputs), tuple(names), tuple(plant.units),
                          miles(plant.outputs, names, f, g_y, g_in, habs), ", ".join(sorted(used)),
                          note=f"adaptive quadrature in ln f: {f.size} frequencies over {band[0]:g} ... "
                               f"{band[1]:g} Hz, rtol {rtol:g}; exact FRF; inputs "
                               + ("correlated as given" if correlation else "uncorrelated"),
                          input_units=tuple(p.unit for p in psds))
