"""Sampling is a fact of the time response: inputs finer than the step, and peaks between samples.

Two checks that :func:`vibss.time.simulate` makes on every run (issue 29 item 5):

- :func:`probe_input` -- a plain callable ``u(t)`` (or a time function that is not piecewise
  linear between its breakpoints) is sampled by the methods and taken linear between the samples.
  It is probed cheaply between them (:data:`PROBES_PER_STEP` points per step, vectorised, at most
  :data:`PROBE_BUDGET` evaluations in all); where it departs from the line between its samples by
  more than :data:`INPUT_TOLERANCE` of its peak, the input is reported, with the step that takes the
  departure to :data:`PEAK_TOLERANCE` (the departure of a smooth input falls like ``dt^2``: it is
  ``|u''| dt^2 / 8``).
- :func:`output_sampling` -- the outputs are stored every ``dt`` only, so a peak between two samples
  reads low: a sinusoid of frequency ``f`` sampled every ``dt`` reads up to ``1 - cos(pi f dt)``
  low (the worst phase puts the crest half a step from the nearest samples). The frequencies that
  carry response are estimated from the plant and the inputs: each undamped mode with the
  oscillation the inputs leave in it (``|phi^T G(i w)| |u(0) + int u' e^(-i w t) dt| / w^2``, the
  quasi-static part that follows the input left out, plus the initial conditions), seen through the
  outputs; and each
  input's own content (its sine pieces, or the curvature of a sampled input) through the frequency
  response. A component's share of the output's peak times ``1 - cos(pi f dt)`` is the expected
  peak error; above :data:`OUTPUT_WARN` the run warns with it and with the step that bounds it to
  :data:`PEAK_TOLERANCE`.

Examples
--------
>>> round(float(peak_loss(8.0, 0.05)), 3)   # an 8 Hz crest sampled every 50 ms: up to 69 % low
0.691
>>> round(resolving_step(8.0, 1.0), 5)      # the step that bounds it to 1 %
0.00563
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from ..linear.eigen.basis import modal_basis
from ..linear.plant.plant import Plant
from ..linear.solve.exact import forcing, output_columns, response, zfactor

__all__ = ["PEAK_TOLERANCE", "INPUT_TOLERANCE", "OUTPUT_WARN", "PROBES_PER_STEP", "PROBE_BUDGET",
           "InputProbe", "probe_input", "fine_input", "modal_amplitudes", "SamplingEstimate", "output_sampling", "peak_loss", "resolving_step"]

PEAK_TOLERANCE = 0.01
"""Peak error [-] that the step named in a sampling warning bounds (1 % of the peak)."""

INPUT_TOLERANCE = 0.02
"""Departure [-] of a sampled input from the line between its samples, relative to its peak, above
which it is reported (a half-sine at 11 samples per pulse departs 1 %: linear between samples is
then a fair reading, and the note says so)."""

OUTPUT_WARN = 0.05
"""Expected peak error [-] of the stored outputs above which :func:`vibss.time.simulate` warns: a
component carrying the whole peak at fewer than 10 samples per period (``1 - cos(pi / 10)`` is
4.9 %); the step the warning names bounds the error to :data:`PEAK_TOLERANCE`."""

PROBES_PER_STEP = 4
"""Probe points per step of a sampled input (at 1/5 ... 4/5 of the step)."""

PROBE_BUDGET = 200_000
"""Most probe evaluations of one input; beyond it a stride of the steps is probed."""

TRANSFORM_BUDGET = 20_000_000
"""Most (mode, input point) pairs of the inputs' transforms (:func:`modal_amplitudes`); beyond it only the highest
modes are weighed (a cost cap: they lose most between samples)."""

MAX_REFINED = 1_000_000
"""Most samples of a refined probing grid (the step found is then left as first estimated)."""

MAX_MODES_DOFS = 1500
"""Largest plant [DOF] whose modes the output check computes (a dense eigen-solve)."""


def peak_loss(f: float | np.ndarray, dt: float) -> np.ndarray:
    """Worst relative reading low of a crest of frequency ``f`` [Hz] sampled every ``dt`` [s]:
    ``1 - cos(pi f dt)`` (1 at and beyond the Nyquist frequency: the crest may be missed)."""
    return np.asarray(1.0 - np.cos(np.pi * np.minimum(np.asarray(f, float) * dt, 0.5)))


def resolving_step(f: float, share: float, tolerance: float = PEAK_TOLERANCE) -> float:
    """The step [s] at which a component of frequency ``f`` [Hz] carrying ``share`` of the peak
    reads at most ``tolerance`` low."""
    x = min(1.0, tolerance / max(share, 1e-300))
    return float(np.arccos(1.0 - x) / (np.pi * f)) if x < 1.0 else float("inf")


@dataclass(frozen=True)
class InputProbe:
    """What probing one sampled input between its samples found.

    Attributes
    ----------
    name : str
        The input signal.
    departure : float
        Largest departure from the line between its samples, relative to its peak [-].
    step : float
        Step [s] that takes the departure to :data:`PEAK_TOLERANCE` (inf: none needed; 0: none
        does, the input jumps between samples).
    omega : float
        Its own content: ``sqrt(max|u''| / max|u|)`` [rad/s] (0 for a linear input).
    """

    name: str
    departure: float
    step: float
    omega: float

    @property
    def ok(self) -> bool:
        """Linear between samples is a fair reading (departure at most :data:`INPUT_TOLERANCE`)."""
        return self.departure <= INPUT_TOLERANCE

    def message(self, dt: float, method: str = "") -> str:
        """One line naming the input, what it loses and the step that resolves it.

        Parameters
        ----------
        dt : float
            The step [s].
        method : str
            The method when it samples every input (one that does not hit edges); empty: the input
            is a plain callable (or a sweep), sampled by every method.
        """
        if method:
            why = f"method {method!r} takes every input linear between its samples"
            alt = "or method='modal' (exact for time functions at any step)"
        else:
            why = "a plain callable is taken linear between samples"
            alt = ("or give it as a TimeFunction (vibss.model.timefunctions), whose edges are hit and whose "
                   "sine pieces are exact")
        fix = (f"use dt <= {self.step:.3g} s, {alt}" if self.step > 0 else
               f"it jumps between samples, which no step resolves: {alt.removeprefix('or ')}")
        return (f"simulate: input {self.name!r} departs from the line between its samples every {dt:g} s "
                f"by up to {self.departure:.0%} of its peak (features shorter than the step: {why}); {fix}")


def _probe_times(grid: np.ndarray, per_step: int, budget: int) -> np.ndarray:
    """Interior points of the intervals of ``grid``, ``per_step`` each, striding to stay in ``budget``."""
    lo, hi = grid[:-1], grid[1:]
    stride = max(1, int(np.ceil(lo.size * per_step / budget)))
    lo, hi = lo[::stride], hi[::stride]
    frac = np.arange(1, per_step + 1) / (per_step + 1)
    return (lo[:, None] + (hi - lo)[:, None] * frac[None, :]).ravel()


def _jumps(fn: Callable[[np.ndarray], np.ndarray], grid: np.ndarray, at: float, size: float) -> bool:
    """Whether ``fn`` jumps inside the interval of ``grid`` around ``at``: 256 points across it, one
    difference of neighbours above half the departure ``size`` (a smooth feature spreads over them)."""
    i = int(np.clip(np.searchsorted(grid, at) - 1, 0, grid.size - 2))
    t = np.linspace(grid[i], grid[i + 1], 257)
    u = np.broadcast_to(np.asarray(fn(t), float), t.shape)
    return bool(np.abs(np.diff(u)).max() > 0.5 * size)


def probe_input(name: str, fn: Callable[[np.ndarray], np.ndarray], ts: np.ndarray,
                breakpoints: npt.ArrayLike = (), refine: int = 3) -> InputProbe:
    """Probe one sampled input between its samples (see the module docstring).

    Parameters
    ----------
    name : str
        The input signal, for the message.
    fn : callable
        ``u(t)``, vectorised [SI].
    ts : (ns,) ndarray
        Sample times [s].
    breakpoints : sequence of float
        Other points of the method's grid [s] (inserted breakpoints).
    refine : int
        How many times the step found is checked by probing again at that step (the first
        estimate is rough when the probes straddle a feature shorter than the step).

    Returns
    -------
    InputProbe
    """
    bps = np.asarray(breakpoints, float).ravel()
    grid = np.unique(np.concatenate([ts, bps[(bps >= ts[0]) & (bps <= ts[-1])]]))
    dt = float(ts[1] - ts[0])
    tp = _probe_times(grid, PROBES_PER_STEP, PROBE_BUDGET)
    ug = np.broadcast_to(np.asarray(fn(grid), float), grid.shape)
    up = np.broadcast_to(np.asarray(fn(tp), float), tp.shape)
    scale = max(float(np.abs(ug).max(initial=0.0)), float(np.abs(up).max(initial=0.0)))
    if not scale > 0 or not np.all(np.isfinite(up)):
        return InputProbe(name, 0.0, float("inf"), 0.0)
    departure = float(np.abs(up - np.interp(tp, grid, ug)).max()) / scale
    # curvature from the fine sequence (samples and probes of the probed intervals)
    fine_t = np.concatenate([grid, tp])
    order = np.argsort(fine_t, kind="stable")
    ft, fu = fine_t[order], np.concatenate([ug, up])[order]
    h = np.diff(ft)
    ok = (h[:-1] > 0) & (h[1:] > 0) & np.isclose(h[:-1], h[1:], rtol=1e-6)
    d2 = np.zeros(0)
    if ft.size > 2:                      # u''/u where |u| is near its peak (not at the edges' kinks)
        slope = np.diff(fu) / np.where(h > 0, h, 1.0)
        crest = np.abs(fu[1:-1]) >= 0.5 * scale
        d2 = np.abs(np.diff(slope) / np.where(ok, 0.5 * (h[:-1] + h[1:]), 1.0))[ok & crest]
    omega = float(np.sqrt(float(d2.max(initial=0.0)) / scale))
    step = float("inf")
    if departure > INPUT_TOLERANCE and _jumps(fn, grid, tp[int(np.argmax(np.abs(up - np.interp(tp, grid, ug))))],
                                            departure * scale):
        return InputProbe(name, departure, 0.0, 0.0)
    if departure > PEAK_TOLERANCE:
        step = dt * float(np.sqrt(PEAK_TOLERANCE / departure))      # departure ~ |u''| dt^2 / 8
        span = float(ts[-1] - ts[0])
        if refine > 0 and step < dt / 1.5 and span / step < MAX_REFINED:   # the estimate is rough when
            finer = probe_input(name, fn, ts[0] + step * np.arange(int(span / step) + 2), breakpoints,
                                refine=refine - 1)       # the probes miss the feature: probe at that step
            step = min(step, finer.step)
            omega = max(omega, finer.omega)
    return InputProbe(name, departure, step, omega)


@dataclass(frozen=True)
class SamplingEstimate:
    """The expected peak error of the stored outputs (:func:`output_sampling`).

    Attributes
    ----------
    error : float
        Largest expected peak error [-] over the outputs.
    output : str
        The output it is in.
    frequency : float
        Frequency [Hz] of the component that sets it.
    source : str
        ``"mode"`` or the input whose own content it is.
    step : float
        Step [s] that bounds every output's error to :data:`PEAK_TOLERANCE`.
    """

    error: float
    output: str = ""
    frequency: float = 0.0
    source: str = ""
    step: float = float("inf")

    @property
    def ok(self) -> bool:
        """At most :data:`OUTPUT_WARN`."""
        return self.error <= OUTPUT_WARN

    def message(self, dt: float) -> str:
        """One line for the warning: what is missed, by how much, and the step that resolves it."""
        what = (f"the {self.frequency:.4g} Hz mode" if self.source == "mode"
                else f"the {self.frequency:.4g} Hz content of input {self.source!r}")
        return (f"simulate: the output step dt = {dt:g} s is coarse for {what} in output {self.output!r} "
                f"({1.0 / (self.frequency * dt):.2g} samples per period): peaks between samples are missed, "
                f"reading up to {self.error:.1%} low (1 - cos(pi f dt) of its share of the peak); "
                f"dt <= {self.step:.3g} s bounds it to {PEAK_TOLERANCE:.0%}")


def fine_input(fn: Callable[[np.ndarray], np.ndarray], ts: np.ndarray, breakpoints: npt.ArrayLike = (),
               pieces: Sequence[object] = ()) -> tuple[np.ndarray, np.ndarray]:
    """Times [s] and values [SI] of one input fine enough to stand for it, linear between them: the
    samples, the breakpoints, :data:`PROBES_PER_STEP` points per step and 16 per period of each sine
    piece (within :data:`PROBE_BUDGET` points each).

    Parameters
    ----------
    fn : callable
        ``u(t)``, vectorised [SI].
    ts : (ns,) ndarray
        Sample times [s].
    breakpoints : sequence of float
        Times where it jumps or kinks [s].
    pieces : sequence of Sinusoid
        Its sine/cosine pieces (``t0``, ``t1``, ``omega``).
    """
    t0, t1 = float(ts[0]), float(ts[-1])
    bps = np.asarray(breakpoints, float).ravel()
    parts = [ts, bps[(bps >= t0) & (bps <= t1)]]
    parts.append(_probe_times(ts, PROBES_PER_STEP, PROBE_BUDGET))
    for p in pieces:
        a, b, w = max(float(getattr(p, "t0")), t0), min(float(getattr(p, "t1")), t1), float(getattr(p, "omega"))
        if b > a and w > 0:
            n = int(min(PROBE_BUDGET, np.ceil((b - a) * w / (2 * np.pi) * 16)))
            parts.append(np.linspace(a, b, max(n, 2)))
    t = np.unique(np.concatenate(parts))
    return t, np.broadcast_to(np.asarray(fn(t), float), t.shape).copy()


def _transform(t: np.ndarray, u: np.ndarray, w: np.ndarray) -> np.ndarray:
    """``|u(0) + int u'(s) e^(-i w s) ds| / w`` over the window, ``s`` from its start [unit s]: the
    oscillation an undamped mode of frequency ``w`` keeps from the input (per unit modal force ``b``, its
    amplitude is ``b`` times this over ``w``), the quasi-static part that follows the input left out (it is the input's own content);
    exact for the piecewise-linear interpolant of ``u`` on ``t`` (a step gives ``1 / w``, not the ``2 / w``
    of the window's Fourier transform).

    The integral is ``sum_j c_j e^(-i w t_j)`` with ``c_j`` the slope's jump at ``t_j``. The points within
    1e-10 rad of phase of a uniform grid ``t_0 + k h`` (the most common step, refitted to the farthest
    grid point) are summed as a polynomial in ``z = e^(-i w h)``, by
    blocks of ``L ~ sqrt(N)`` powers: one GEMM against ``z^j`` (j < L) and the blocks' ``z^(L b)``, each
    power from ``exp`` directly (round-off ``eps`` per term, not ``N eps``), ``(L + B)`` exponentials per
    mode instead of ``N`` (at 10,000 samples and 600 modes 0.3 s became a few ms); points off the grid
    (breakpoints, probes) are summed directly."""
    h = np.diff(t)
    keep = h > 0
    ta, h = t[:-1][keep], h[keep]
    slope = np.diff(u)[keep] / h
    u0 = float(u[0]) if u.size else 0.0
    if not slope.size:
        return np.abs(np.full(w.size, u0)) / w
    t0 = float(ta[0])
    pts, c = np.concatenate([ta, ta + h]) - t0, np.concatenate([slope, -slope])      # from the window's start
    step = float(np.median(h))
    k = np.rint(pts / step)
    near = np.abs(pts - k * step) <= 1e-6 * step
    far = int(np.flatnonzero(near)[np.argmax(k[near])])
    if k[far] > 0:                # the step from the farthest grid point: the median's round-off not k times over
        step = float(pts[far] / k[far])
        k = np.rint(pts / step)
    on = np.abs(pts - k * step) * float(w.max()) <= 1e-10          # snapped within 1e-10 rad of phase
    if on.any() and k[on].max() >= 4 * pts.size:          # a grid much finer than the points: all direct
        on[:] = False
    C = np.bincount(k[on].astype(np.int64), weights=c[on])                 # jumps per grid point
    n = C.size
    L = max(1, int(np.ceil(np.sqrt(n))))
    B = -(-n // L)
    C = np.concatenate([C, np.zeros(B * L - n)]).reshape(B, L)
    zj = np.exp(-1j * np.outer(np.arange(L) * step, w))                      # (L, K) z^j
    inner = np.ascontiguousarray(C @ zj.view(float)).view(complex)           # (B, K)
    total = (np.exp(-1j * np.outer(np.arange(B) * (L * step), w)) * inner).sum(axis=0)
    off, c_off = pts[~on], c[~on]
    chunk = max(1, 2**20 // w.size)                  # (K, chunk) exponentials at a time: 16 MB
    for i in range(0, off.size, chunk):
        total += np.exp(-1j * np.outer(w, off[i:i + chunk])) @ c_off[i:i + chunk]
    return np.abs(u0 + total / (1j * w)) / w


def modal_amplitudes(plant: Plant, inputs: Sequence[tuple[np.ndarray, np.ndarray]], q0: np.ndarray,
                     v0: np.ndarray, f_min: float = 0.0) -> list[tuple[float, np.ndarray]]:
    """The undamped modes above ``f_min`` [Hz] with the amplitude the inputs and the initial
    conditions leave in each output: ``|O(i w) phi| (sum_j |phi^T G_j(i w)| R_j(w) / w + |(q0, v0 / w)|_M)`` with
    ``R_j = |u_j(0) + int u_j' e^(-i w t) dt| / w`` (the oscillation input ``j`` leaves in the mode).

    Parameters
    ----------
    plant : Plant
        The plant (at most :data:`MAX_MODES_DOFS` DOFs; an empty list above).
    inputs : sequence of ((k,) ndarray, (k,) ndarray)
        Per input, times [s] and values [SI], linear between them (:func:`fine_input`).
    q0, v0 : (n,) ndarray
        Initial displacement and velocity [m, rad, m/s, rad/s].
    f_min : float
        Lowest frequency weighed [Hz] (rigid modes never are).

    Returns
    -------
    list of (float, (p,) ndarray)
        Frequency [Hz] and amplitude per output [output units], ascending in frequency.
    """
    if not 0 < plant.n <= MAX_MODES_DOFS:
        return []
    spec = modal_basis(plant)                         # the modal path's own (cached on the plant)
    w = np.sqrt(np.maximum(spec.omega2, 0.0))
    sel = np.flatnonzero(~spec.rigid & (w / (2 * np.pi) > f_min))
    points = max(1, sum(t.size for t, _ in inputs))
    if sel.size * points > TRANSFORM_BUDGET:                  # keep it cheap: the highest modes
        sel = sel[-max(1, TRANSFORM_BUDGET // points):]
    if not sel.size:
        return []
    w, phi = w[sel], spec.phi[:, sel]
    s = 1j * w
    G = forcing(plant, s, zfactor(s, plant.order))                          # (r, n, m)
    b = np.abs(np.einsum("nr,rnm->rm", phi, G))                               # modal force per unit input
    U = np.array([_transform(t, u, w) for t, u in inputs]).T if inputs else np.zeros((w.size, 0))
    drive = (b * U).sum(axis=1) / w                                           # modal amplitude
    if np.any(q0) or np.any(v0):                      # phi^T M q0: two products, not M phi
        drive = drive + np.hypot(phi.T @ np.asarray(plant.M @ q0, float), (phi.T @ np.asarray(plant.M @ v0, float)) / w)
    amp = np.abs(output_columns(plant, s, phi)) * drive[None, :]
    return [(float(wk / (2 * np.pi)), amp[:, k]) for k, wk in enumerate(w)]


def output_sampling(plant: Plant, time: np.ndarray, inputs: Sequence[tuple[np.ndarray, np.ndarray]],
                    own: Sequence[float], y: np.ndarray, q0: np.ndarray, v0: np.ndarray) -> SamplingEstimate:
    """Expected peak error of outputs stored every ``dt`` (see the module docstring).

    Parameters
    ----------
    plant : Plant
        The plant simulated (m inputs, p outputs).
    time : (ns,) ndarray
        Sample times ``k dt`` [s].
    inputs : sequence of ((k,) ndarray, (k,) ndarray)
        Per input, times [s] and values [SI] fine enough to stand for it (piecewise linear between).
    own : sequence of float
        Per input, the angular frequency [rad/s] of its own content (0: none beyond its edges).
    y : (ns, p) ndarray
        The computed outputs (their peaks are the reference of each share).
    q0, v0 : (n,) ndarray
        Initial displacement and velocity [m, rad, m/s, rad/s].

    Returns
    -------
    SamplingEstimate
    """
    dt = float(time[1] - time[0])
    peak = np.abs(y).max(axis=0) if y.size else np.zeros(0)
    live = peak > 0
    if not np.any(live):
        return SamplingEstimate(0.0)
    f_min = resolving_step(1.0, 1.0, PEAK_TOLERANCE) / dt        # f below it reads < 1 % low at any share
    comps = [(f, amp, "mode") for f, amp in modal_amplitudes(plant, inputs, q0, v0, f_min)]
    for j, wj in enumerate(own):
        if wj / (2 * np.pi) > f_min and inputs:
            H = np.abs(response(plant, np.array([1j * wj]))[:, j, 0])
            top = float(np.abs(inputs[j][1]).max(initial=0.0))
            comps.append((wj / (2 * np.pi), H * top, plant.inputs[j]))
    best = SamplingEstimate(0.0)
    step = float("inf")
    for f, amp, source in comps:
        share = np.where(live, np.minimum(1.0, np.nan_to_num(amp) / np.where(live, peak, 1.0)), 0.0)
        err = share * peak_loss(f, dt)
        i = int(np.argmax(err))
        step = min(step, resolving_step(f, float(share.max())))
        if err[i] > best.error:
            best = SamplingEstimate(float(err[i]), plant.outputs[i], float(f), source)
    return SamplingEstimate(best.error, best.output, best.frequency, best.source, step)
