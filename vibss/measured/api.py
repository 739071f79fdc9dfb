"""Measured data in, models out: :func:`fit_rheology` (a mount's rheology from its measured
dynamic stiffness, as a supplier's ISO 10846 table gives it)."""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np
import numpy.typing as npt

from .._validate import array, choice, integer, number
from ..errors import ArgumentError, VibssWarning
from ..methods import Check, Claim
from .kernels import LAWS, fit_axis, log_error
from .result import RheologyFit

__all__ = ["fit_rheology", "FIT_TOLERANCE", "CLAIM"]

FIT_TOLERANCE = 0.01
"""Default RMS of ``|log(k_fit / k_data)|`` a fit is held to: about 1 % in magnitude and 0.01 rad
(0.6 deg) in loss angle, the repeatability of a good ISO 10846 measurement."""

CLAIM = Claim(1e-6, conditions="noise-free data from the law fitted (then its parameters come back to "
                               "1e-6 relative; measured 1e-10); otherwise the RMS log error is reported and "
                               "checked against the tolerance")
"""What :func:`fit_rheology` promises."""

_WHO = "fit_rheology"


def _stiffness(frequencies: Any, dynamic_stiffness: Any, loss_factor: Any) -> tuple[np.ndarray, np.ndarray]:
    """Frequencies [Hz] (nf,) and the complex stiffness (3, nf) [N/m], checked."""
    f = array(frequencies, "frequencies", (None,), who=_WHO, unit="Hz")
    if f.size < 2 or f[0] <= 0 or np.any(np.diff(f) <= 0):
        raise ArgumentError(f"{_WHO}: frequencies: expected at least 2 increasing frequencies > 0 [Hz], "
                            f"got {f.tolist()}", argument="frequencies", received=frequencies,
                            expected="increasing, > 0")
    if loss_factor is None:
        try:
            k = np.array(dynamic_stiffness, dtype=complex)
        except (TypeError, ValueError):
            raise ArgumentError(f"{_WHO}: dynamic_stiffness: expected complex numbers [N/m], got "
                                f"{dynamic_stiffness!r}", argument="dynamic_stiffness",
                                received=dynamic_stiffness) from None
    else:
        kr = array(dynamic_stiffness, "dynamic_stiffness", who=_WHO, unit="N/m")
        eta = array(loss_factor, "loss_factor", who=_WHO)
        try:
            k = kr * (1 + 1j * np.broadcast_to(eta, kr.shape))
        except ValueError:
            raise ArgumentError(f"{_WHO}: loss_factor: shape {eta.shape} does not match the storage "
                                f"stiffness' {kr.shape}", argument="loss_factor", received=eta.shape,
                                expected=kr.shape) from None
    if k.shape == (f.size,):
        k = np.broadcast_to(k, (3, f.size))
    if k.shape != (3, f.size) or not np.all(np.isfinite(k)):
        raise ArgumentError(f"{_WHO}: dynamic_stiffness: expected finite values of shape ({f.size},) or "
                            f"(3, {f.size}) (per axis) [N/m], got shape {k.shape}", argument="dynamic_stiffness",
                            received=k.shape, expected=(3, f.size))
    bad = np.argwhere(k.real <= 0)
    if bad.size:
        j, i = bad[0]
        raise ArgumentError(f"{_WHO}: dynamic_stiffness: the storage stiffness on axis {j + 1} at {f[i]:g} Hz is "
                            f"{k.real[j, i]:g} N/m; a mount's must be positive", argument="dynamic_stiffness",
                            received=float(k.real[j, i]), expected="> 0")
    return f, k.copy()


def _other(kind: str, order: int) -> str:
    """What to try when ``kind`` misses the data."""
    if kind == "prony":
        return f"more terms (order={order + 1}) or type='fractional'"
    return "type='prony' (Maxwell terms, order=...)" + (" or type='fractional'" if kind == "zener" else "")


def fit_rheology(frequencies: npt.ArrayLike, dynamic_stiffness: npt.ArrayLike, type: str = "zener",
                 order: int | None = None, *, loss_factor: npt.ArrayLike | None = None,
                 tolerance: float = FIT_TOLERANCE) -> RheologyFit:
    """Fit a rheology (Zener, Prony series or fractional Zener) to a measured dynamic stiffness.

    Per axis, :func:`scipy.optimize.least_squares` minimises the complex log error
    ``log(k_fit / k_data)`` at the given frequencies: its real part is the log-magnitude error,
    its imaginary part the loss-angle error [rad], so a stiffness spanning decades is fitted
    evenly. Stiffnesses and times are fitted by their logarithms (they stay positive, and the
    Zener's ``k_inf >= k_0``: the fit is passive). On noise-free data from the law itself the
    parameters come back to ~1e-10; on other data the fit reports how far it is (``rms_error``)
    and warns when that exceeds ``tolerance``.

    Parameters
    ----------
    frequencies : (nf,) array_like
        Frequencies of the data [Hz], increasing, > 0.
    dynamic_stiffness : (nf,) or (3, nf) array_like
        Complex stiffness ``k' + i k''`` [N/m] (one row: every axis alike; three: per principal axis);
        with ``loss_factor``, the storage stiffness ``k'`` [N/m] alone.
    type : {"zener", "prony", "fractional"}
        The law: ``zener`` (k_0, k_inf, tau), ``prony`` (k_0 and ``order`` Maxwell terms k_i,
        tau_i) or ``fractional`` (fractional Zener: k_0, k_inf, tau, alpha).
    order : int or None
        Number of Maxwell terms of a Prony series (default: one per decade of the data, at least
        1); only for ``type="prony"``.
    loss_factor : float, (nf,) or (3, nf) array_like or None
        Loss factor ``eta = k'' / k'`` [-] when ``dynamic_stiffness`` is the storage stiffness.
    tolerance : float
        RMS of ``|log(k_fit / k_data)|`` above which the fit warns [-] (default 0.01).

    Returns
    -------
    RheologyFit
        ``.rheology`` for ``MountType(rheology=...)``, ``.error`` per frequency, ``.rms_error``
        per axis, ``.plot()`` against the data.

    Raises
    ------
    ArgumentError
        Bad frequencies or stiffness (named, with the axis and frequency), an unknown type, an
        ``order`` for a law that has none, fewer data than parameters.

    Warns
    -----
    VibssWarning
        The RMS error of an axis exceeds ``tolerance``: the data is not from this law.

    Examples
    --------
    >>> import numpy as np
    >>> from vibss.model.rheology import Zener
    >>> f = np.geomspace(1.0, 1e4, 30)
    >>> k = Zener(1e5, 3e5, 1e-3).dynamic_stiffness(2 * np.pi * f)[:, 0]
    >>> fit = fit_rheology(f, k, "zener")
    >>> [round(float(v), 6) for v in (fit.rheology.k_0[0], fit.rheology.k_inf[0], fit.rheology.tau[0])]
    [100000.0, 300000.0, 0.001]
    """
    f, k = _stiffness(frequencies, dynamic_stiffness, loss_factor)
    kind = choice(type, "type", list(LAWS), who=_WHO)
    law = LAWS[kind]
    decades = np.log10(f[-1] / f[0])
    if kind == "prony":
        n = integer(order, "order", who=_WHO, minimum=1) if order is not None else max(1, int(round(decades)))
    elif order is not None:
        raise ArgumentError(f"{_WHO}: order: only a Prony series has an order; the {kind} law has fixed "
                            f"parameters (got order={order!r})", argument="order", received=order, expected=None)
    else:
        n = 1 if kind == "zener" else 0
    tol = number(tolerance, "tolerance", who=_WHO, minimum=0.0, strict=True)
    if 2 * f.size < law.size(n):
        raise ArgumentError(f"{_WHO}: frequencies: {f.size} frequencies give {2 * f.size} real data per axis "
                            f"for {law.size(n)} parameters of the {kind} law; give more frequencies",
                            argument="frequencies", received=f.size, expected=f"at least {-(-law.size(n) // 2)}")
    w = 2 * np.pi * f
    xs, spent, done = [], 0, {}
    for j in range(3):
        key = k[j].tobytes()
        if key not in done:                            # axes with the same data: fitted once
            done[key] = fit_axis(law, w, k[j], n)
            spent += done[key][1]
        xs.append(done[key][0])
    rheology = law.rheology(xs, f[[0, -1]])
    fitted = np.asarray(rheology.dynamic_stiffness(w)).T
    error = log_error(fitted, k)
    rms = np.sqrt(np.mean(error**2, axis=1))
    check = Check(float(rms.max()), tol, f"{f.size} frequencies, {f[0]:g} to {f[-1]:g} Hz")
    note = f"{kind}: {check.text()} (RMS of |log(k_fit / k_data)|)"
    if not rheology.exact:
        note += f"; the Maxwell ladder the analyses use is within {rheology.ladder().fit_error:.2g} of the law"
    if not check.ok:
        j = int(np.argmax(rms))
        warnings.warn(f"{_WHO}: the {kind} law misses the data: RMS log error {rms[j]:.3g} on axis {j + 1} "
                      f"(up to {error[j].max():.3g} at {f[int(np.argmax(error[j]))]:g} Hz) exceeds the tolerance "
                      f"{tol:g}; the data is not from this law: try {_other(kind, n)}", VibssWarning, stacklevel=2)
    return RheologyFit(rheology, kind, n, f, k, fitted, error, rms, tol, spent, note=note)
