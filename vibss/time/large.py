"""Large models in the time domain without a dense n x n matrix: a subspace built for the channels.

:func:`vibss.time.simulate` of a :class:`~vibss.model.model.Model` with more than
:data:`~vibss.methods.SIMULATE_LARGE_DOFS` (6,000) DOFs and ``method="auto"`` runs here first (issue 17 item 4):
computing every mode densely is O(n^3) (196 s at 6,000 DOF, 26.8 GiB of memory at 60,000), and
every mode below a cut-off is thousands of modes on a long chain, most of them localised far from
the inputs and outputs.

1. **The inputs' spectrum.** The sampled inputs ``u_j(t)`` (zero-padded 4x) give ``|U_j(w)|``
   [unit s] on the FFT bins from ``df`` to the Nyquist frequency ``1 / (2 dt)``.
2. **Subspace.** :func:`vibss.linear.project.subspace.channel_subspace` at :data:`FREQUENCIES` of those
   bins (log-spaced by index, so the low band is dense): a block rational Krylov basis from the
   input and output vectors, real shifts spread over the bins, grown greedily where an exact
   solve at a check frequency shows an error above :data:`TOLERANCE`, the error of a channel
   weighted by its input's spectrum: ``|H_r - H| |U_j|`` over ``max_w |H_r U_j|``. The plant
   (its ``M, C, K`` and every map) is projected on it (Galerkin), and the reduced plant runs
   through the exact modal path (:mod:`vibss.time.kernels`). When the greedy does not reach the
   tolerance the call is refused, never answered with a larger error unsaid.
3. **Error estimate.** For real signals and zero initial conditions,
   ``|y_i - y_r,i|(t) <= (1 / pi) sum_j int_0^inf |dH_ij(w)| |U_j(w)| dw`` (the inverse Fourier
   transform of ``dH U``, bounded by the integral of its magnitude). ``|dH|`` is known at the check
   frequencies only; between them it is taken as the larger of the two neighbouring checks', and
   the integral runs over the FFT bins up to the Nyquist frequency: **an estimate from sampled
   checks**, not a bound (the error between checks and above the Nyquist frequency is not
   measured). It is stated relative to each output's peak.

The result's ``note`` says the basis, the shifts, the checked error and the estimate; a
:class:`~vibss.errors.VibssWarning` says when the estimate exceeds :data:`WARN_ERROR`.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import AnalysisError, VibssWarning
from ..linear.plant.plant import Plant
from ..linear.plant.build import build_plant
from ..linear.solve.exact import without_hysteresis
from ..methods import SIMULATE_LARGE_DOFS
from ..model.model import Model
from .inputs import initial_state, summed
from ..linear.project.subspace import Subspace, channel_subspace

__all__ = ["FREQUENCIES", "TOLERANCE", "WARN_ERROR", "Projected", "input_spectrum", "projected_plant",
           "projected_model", "truncation_note"]

FREQUENCIES = 250
"""Most frequencies (FFT bins of the inputs' spectrum) where the subspace is built and checked."""

TOLERANCE = 1e-8
"""Checked error of each channel, weighted by its input's spectrum, relative to its peak [-]."""

WARN_ERROR = 1e-2
"""Estimated relative error above which :func:`vibss.time.simulate` warns."""


@dataclass(frozen=True, eq=False)
class Projected:
    """A large plant projected on a subspace built for its channels (see the module docstring).

    Attributes
    ----------
    plant : Plant
        Dense reduced plant: DOFs ``krylov<k>``, ``M = I``, ``K`` diagonal [rad^2/s^2].
    full : Plant
        The sparse plant it came from.
    subspace : Subspace
        The basis, its shifts and its checks.
    frequency_hz : (nb,) ndarray
        FFT bins of the inputs' spectrum [Hz], from 0 to the Nyquist frequency.
    spectrum : (m, nb) ndarray
        ``|U_j(f)|`` of each input at those bins [input unit x s].
    """

    plant: Plant
    full: Plant
    subspace: Subspace
    frequency_hz: np.ndarray
    spectrum: np.ndarray

    def describe(self) -> str:
        """What was kept, in words (for a result's note)."""
        return (f"{self.full.n} DOFs above the large-model threshold: kept sparse; "
                f"{self.subspace.describe()}, weighted by the inputs' spectra up to "
                f"{self.frequency_hz[-1]:.4g} Hz")

    def estimate(self, y: np.ndarray) -> np.ndarray:
        """(p,) estimated error of each output of ``y`` (ns, p), relative to its peak:
        ``(1 / pi) sum_j int |dH_ij| |U_j| dw`` with ``|dH|`` from the checks (module docstring)."""
        sub = self.subspace
        f = self.frequency_hz
        fc = sub.check_hz
        if fc.size == 0:
            return np.full(y.shape[1], np.inf)
        # the larger of the neighbouring checks' |dH| at every bin (the nearest one outside them)
        hi = np.clip(np.searchsorted(fc, f), 0, fc.size - 1)
        lo = np.clip(hi - 1, 0, fc.size - 1)
        dh = np.maximum(sub.check_error[:, :, lo], sub.check_error[:, :, hi])      # (p, m, nb)
        dw = 2 * np.pi * (f[1] - f[0]) if f.size > 1 else 0.0
        weights = np.full(f.size, dw)
        weights[[0, -1]] *= 0.5                                                     # trapezoid
        bound = np.einsum("pmf,mf,f->p", dh, self.spectrum, weights) / np.pi
        peak = np.abs(y).max(axis=0)
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(peak > 0, bound / peak, np.where(bound > 0, np.inf, 0.0))


def input_spectrum(samples: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """Frequencies [Hz] and amplitude spectra ``|U_j(f)|`` [unit s] of sampled inputs.

    Parameters
    ----------
    samples : (m, ns) ndarray
        The inputs sampled every ``dt``.
    dt : float
        Sample interval [s].

    Returns
    -------
    f : (nb,) ndarray
        FFT bins [Hz] from 0 to ``1 / (2 dt)`` (the samples zero-padded to 4x, a power of two).
    magnitude : (m, nb) ndarray
        ``dt |FFT|``: the Fourier transform's magnitude of the sampled signal.
    """
    ns = samples.shape[1]
    nfft = 1 << int(math.ceil(math.log2(max(4 * ns, 16))))
    return np.fft.rfftfreq(nfft, dt), np.abs(np.fft.rfft(samples, nfft, axis=1)) * dt


def projected_plant(full: Plant, samples: np.ndarray, dt: float, tol: float | None = None) -> Projected:
    """Project a sparse plant on a subspace built for its channels and the inputs' spectra.

    Parameters
    ----------
    full : Plant
        Plant with sparse ``M, C, K`` (:func:`vibss.linear.plant.build.build_plant` ``sparse=True``);
        its hysteretic part is left out (the time domain has none).
    samples : (m, ns) ndarray
        Its inputs sampled every ``dt`` [input units].
    dt : float
        Time step [s].
    tol : float or None
        Weighted checked error asked [-] (module docstring); None: :data:`TOLERANCE`.

    Returns
    -------
    Projected

    Raises
    ------
    AnalysisError
        The inputs are all zero, or the greedy did not reach ``tol`` (the answer would carry an
        error it could not state).
    """
    tol = TOLERANCE if tol is None else tol
    f, mag = input_spectrum(np.asarray(samples, float).reshape(len(full.inputs), -1), dt)
    if not np.any(mag):
        raise AnalysisError(f"simulate: the inputs {list(full.inputs)} are zero over the whole window; "
                            "the large-model path needs an input to build its subspace")
    bins = np.unique(np.round(np.geomspace(1, f.size - 1, min(FREQUENCIES, f.size - 1))).astype(int))
    plant = without_hysteresis(full)
    sub = channel_subspace(plant, 2 * np.pi * f[bins], tol, weight=mag[:, bins])
    if not sub.converged:
        raise AnalysisError(
            f"simulate: {full.n} DOFs above the large-model threshold, but the channel subspace did not "
            f"reach {tol:g} ({sub.describe()}): a projected answer could not state its error. Use "
            "method='modal' (every mode, dense: O(n^3) time, 8 n^2 bytes) or fewer inputs and outputs")
    return Projected(plant=sub.plant, full=full, subspace=sub, frequency_hz=f, spectrum=mag)


def projected_model(model: Model, sources: list[Any], outputs: Sequence[str] | None, initial: Any,
               signals: Mapping[str, Any], ts: np.ndarray, dt: float) -> Projected:
    """The large model's sparse plant (inputs ``sources``, samples of ``signals`` at ``ts``) projected on a subspace built for its channels (:mod:`vibss.time.large`)."""
    if not sources:
        raise AnalysisError(f"simulate: a free vibration of {6 * len(model.bodies)} DOFs (above "
                            f"{SIMULATE_LARGE_DOFS}) from initial conditions alone: the large-model path needs an "
                            "input to build its subspace; give method='modal' (every mode, dense) instead")
    full = build_plant(model, sources, outputs, sparse=True)
    q0, v0 = initial_state(full, initial, model)
    if np.any(q0) or np.any(v0):
        raise AnalysisError(f"simulate: initial: nonzero initial conditions on a model of {full.n} DOFs "
                            f"(above {SIMULATE_LARGE_DOFS}, kept sparse and projected) do not map to the "
                            "reduced coordinates exactly; give method='modal' (every mode, dense) instead")
    samples = np.array([np.broadcast_to(summed(signals.get(u, []))(ts), ts.shape) for u in full.inputs])
    return projected_plant(full, samples.reshape(len(full.inputs), ts.size), dt)


def truncation_note(tr: Projected, y: np.ndarray) -> str:
    """What the large-model path kept and its error estimate; warns above
    :data:`~vibss.time.large.WARN_ERROR`."""
    worst = float(tr.estimate(y).max(initial=0.0))
    text = (f"{tr.describe()}; estimated error {worst:.2g} of each output's peak ((1/pi) int |dH| |U| dw "
            "with |dH| from the checks: an estimate from sampled checks, not a bound)")
    if not worst <= WARN_ERROR:
        warnings.warn(VibssWarning(f"simulate: {text}: above {WARN_ERROR:g} (method='modal' computes every "
                                   "mode, dense)"), stacklevel=3)
    return text
