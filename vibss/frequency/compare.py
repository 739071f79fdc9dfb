"""How a computed frequency response compares with a measured one: the frequency response
assurance criterion per channel (:func:`frac`) and the frequency scale that best aligns them
(:func:`frequency_shift`).

Both take two :class:`~vibss.frequency.api.FrequencyResponse` (e.g. :func:`vibss.io.read_uff` of a
test and :func:`vibss.frequency_response` of the model) and read only their arrays and labels: they
solve nothing, so a figure may show their scores (``tests/project/test_api.py`` places this module low).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..errors import ModelError

__all__ = ["frac", "frequency_shift"]


def frac(measured: Any, computed: Any) -> dict[str, float]:
    """Frequency response assurance criterion per common channel: ``|sum H_m conj(H_c)|^2 /
    (sum |H_m|^2 sum |H_c|^2)`` on the measured frequencies (the computed response interpolated
    there, real and imaginary parts linearly); 1 = same shape.

    Parameters
    ----------
    measured, computed : FrequencyResponse

    Returns
    -------
    dict of str to float
        ``{"<output>/<input>": FRAC}`` for every channel both have.
    """
    out = {}
    fm = np.asarray(measured.frequency_hz, dtype=float)
    fc = np.asarray(computed.frequency_hz, dtype=float)
    for i, y in enumerate(measured.outputs):
        for j, u in enumerate(measured.inputs):
            if y not in computed.outputs or u not in computed.inputs:
                continue
            hc = computed.response[computed.outputs.index(y), computed.inputs.index(u)]
            hci = np.interp(fm, fc, hc.real) + 1j * np.interp(fm, fc, hc.imag)
            hm = measured.response[i, j]
            num = abs(np.vdot(hci, hm)) ** 2
            den = float(np.vdot(hm, hm).real * np.vdot(hci, hci).real)
            out[f"{y}/{u}"] = float(num / den) if den > 0 else float("nan")
    return out


def frequency_shift(measured: Any, computed: Any, span: float = 0.25) -> dict[str, tuple[float, float]]:
    """Frequency scale factor that best aligns the computed response with the measured one, per
    common channel, and the FRAC there.

    ``alpha`` maximises the FRAC of ``H_m(f)`` against ``H_c(alpha f)`` over ``1/(1 + span) <= alpha
    <= 1 + span`` (bounded scalar search from a scan of 201 points): the model's frequencies are
    ``alpha`` times the test's (a model 4 % too stiff has ``alpha`` = 1.02), so dividing its
    stiffnesses by ``alpha^2`` is the first correction to try. The computed response is interpolated
    (real and imaginary parts, linearly) at ``alpha f``: compute it on a grid finer than the
    resonances' half-power bandwidths, over the measured band stretched by ``1 + span``.

    Parameters
    ----------
    measured, computed : FrequencyResponse
    span : float
        Largest relative shift searched (> 0).

    Returns
    -------
    dict of str to (float, float)
        ``{"<output>/<input>": (alpha, FRAC at alpha)}`` for every channel both have.

    Raises
    ------
    ModelError
        ``span`` not in (0, 1), or the computed frequencies do not cover the shifted band.
    """
    from scipy.optimize import minimize_scalar

    if not 0.0 < float(span) < 1.0:
        raise ModelError(f"frequency_shift: span must be in (0, 1), got {span!r}")
    fm = np.asarray(measured.frequency_hz, dtype=float)
    fc = np.asarray(computed.frequency_hz, dtype=float)
    lo, hi = 1.0 / (1.0 + span), 1.0 + span
    if fc.min() > fm.min() * lo * (1 + 1e-12) or fc.max() < fm.max() * hi * (1 - 1e-12):
        raise ModelError(f"frequency_shift: the computed response covers {fc.min():g} .. {fc.max():g} Hz; "
                         f"a shift of {span:g} needs {fm.min() * lo:g} .. {fm.max() * hi:g} Hz")
    out = {}
    for i, y in enumerate(measured.outputs):
        for j, u in enumerate(measured.inputs):
            if y not in computed.outputs or u not in computed.inputs:
                continue
            hc = computed.response[computed.outputs.index(y), computed.inputs.index(u)]
            hm = measured.response[i, j]

            def score(alpha: float, hc: np.ndarray = hc, hm: np.ndarray = hm) -> float:
                x = alpha * fm
                h = np.interp(x, fc, hc.real) + 1j * np.interp(x, fc, hc.imag)
                den = float(np.vdot(hm, hm).real * np.vdot(h, h).real)
                return float(abs(np.vdot(h, hm)) ** 2 / den) if den > 0 else 0.0

            grid = np.geomspace(lo, hi, 201)
            k = int(np.argmax([score(a) for a in grid]))
            a0, a1 = grid[max(k - 1, 0)], grid[min(k + 1, grid.size - 1)]
            best = minimize_scalar(lambda a: -score(a), bounds=(a0, a1), method="bounded",
                                   options={"xatol": 1e-10 * grid[k]})
            alpha = float(best.x) if -best.fun >= score(grid[k]) else float(grid[k])
            out[f"{y}/{u}"] = (alpha, score(alpha))
    return out
