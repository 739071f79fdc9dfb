"""Model updating: mount rates (and, from measured modes, positions and angles) fitted to a measured
frequency response or to measured modes, with exact gradients: :func:`update`.

The residuals and their exact derivatives are in :mod:`vibss.measured.update_kernels`; this
module checks the arguments, runs :func:`scipy.optimize.least_squares` (``trf``, bounds) on the
parameters scaled by their starting values, and states what came out: the values, their standard
deviations ``s^2 (J^T J)^-1`` (``s^2`` the residual's variance per degree of freedom), the
correlation before and after, and which parameters the data cannot tell apart (the singular
vectors of the scaled Jacobian with singular values below :data:`RANK_RTOL` of the largest).
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from typing import Any

import numpy as np
from scipy.optimize import least_squares

from .._validate import array
from ..design.parameters import Parameter, apply, current_values, parameters_of
from ..errors import ArgumentError, ModelError, VibssWarning, did_you_mean
from ..frequency.api import QUANTITIES, frequency_response
from ..frequency.compare import frac
from ..frequency.result import FrequencyResponse
from ..linear.plant.assemble import assemble
from ..linear.plant.build import build_plant
from ..linear.plant.names import output_row
from ..methods import Check, Claim
from ..model.model import Model
from .modes import MeasuredModes
from .update_kernels import FrfProblem, ModesProblem
from .update_result import UpdateResult

__all__ = ["update", "CLAIM", "RANK_RTOL", "GRADIENT_RTOL", "RATE_RANGE"]

_WHO = "update"

CLAIM = Claim(1e-8, conditions="noise-free data from the model with these parameters free and identifiable "
                               "(full-rank Jacobian): the parameters come back to 1e-8 relative; with noise, "
                               "within a few of the stated standard deviations (first-order statistics)")
"""What :func:`update` promises."""

RANK_RTOL = 1e-6
"""A singular value of the scaled Jacobian (columns of unit norm) below this fraction of the largest:
the data cannot tell the parameters loading its singular vector apart."""

GRADIENT_RTOL = 1e-5
"""The check after the fit: a central difference of the residual along one direction (step 1e-5 of
the scaled parameters) agrees with the exact Jacobian to this relative error."""

RATE_RANGE = 1e3
"""Default bounds of a rate or rate ratio: its starting value divided and multiplied by this."""

SCAN = np.geomspace(0.25, 4.0, 25)
"""Common factors of the rates tried before a frequency-response fit (1 included): the start is the
one with the smallest log-magnitude error, within the bounds."""

_POWER = {"frf": 0, "transmissibility": 0, **QUANTITIES}
_QUANTITY = {v: k for k, v in QUANTITIES.items()}


def _frf_problem(model: Model, measured: FrequencyResponse, params: tuple[Parameter, ...],
                 weights: Any) -> FrfProblem:
    for p in params:
        if not p.is_rate:
            raise ArgumentError(f"{_WHO}: parameter {p.name!r} is a {p.unit} quantity; a frequency response is "
                                "updated in mount rates and rate ratios only (the response is linear in them, "
                                "so their exact derivative is known); fit positions and angles to measured modes",
                                argument="parameters", received=p.name, expected="rates, rate ratios")
    power = _POWER.get(measured.quantity)
    if power is None:
        raise ArgumentError(f"{_WHO}: measured: a {measured.quantity!r} response cannot be compared with the "
                            f"model; give one of {list(_POWER)}", argument="measured", received=measured.quantity,
                            expected=list(_POWER))
    f = np.asarray(measured.frequency_hz, dtype=float)
    if np.any(f <= 0):
        raise ArgumentError(f"{_WHO}: measured: frequency {f[f <= 0][0]:g} Hz; give frequencies > 0 (leave "
                            "0 Hz out: its limit is not differentiated here)", argument="measured",
                            received=float(f[f <= 0][0]))
    try:
        build_plant(model, list(measured.inputs), list(measured.outputs))
    except ModelError as e:
        raise ArgumentError(f"{_WHO}: measured: its channels are matched to the model's signals by name: {e}",
                            argument="measured", received=(measured.inputs, measured.outputs)) from None
    shape = (len(measured.outputs), len(measured.inputs))
    w = _channel_weights(weights, measured, shape)
    data = np.asarray(measured.response)
    bad = np.argwhere((w[:, :, None] > 0) & ~(np.isfinite(data) & (data != 0)))
    if bad.size:
        i, j, k = bad[0]
        raise ArgumentError(f"{_WHO}: measured: channel {measured.outputs[i]}/{measured.inputs[j]} is "
                            f"{data[i, j, k]} at {f[k]:g} Hz; the relative residual divides by finite, nonzero "
                            "values (leave the channel out with weight 0)", argument="measured",
                            received=f"{measured.outputs[i]}/{measured.inputs[j]}")
    return FrfProblem(model, params, tuple(measured.inputs), tuple(measured.outputs), 2j * np.pi * f, power,
                      data, w)


def _channel_weights(weights: Any, measured: FrequencyResponse, shape: tuple[int, int]) -> np.ndarray:
    """(p, m) weights: None (ones), a mapping ``"<output>/<input>" -> weight`` (others 1) or an array."""
    if weights is None:
        return np.ones(shape)
    if isinstance(weights, Mapping):
        names = [f"{y}/{u}" for y in measured.outputs for u in measured.inputs]
        w = np.ones(shape)
        for key, value in weights.items():
            if key not in names:
                raise ArgumentError(f"{_WHO}: weights: unknown channel {key!r}" + did_you_mean(str(key), names)
                                    + f"; expected '<output>/<input>' of {names}", argument="weights",
                                    received=key, expected=names)
            i = names.index(key)
            w[i // shape[1], i % shape[1]] = array(value, "weights", (), who=_WHO)
    else:
        w = array(weights, "weights", shape, who=_WHO)
    if np.any(w < 0) or not np.any(w > 0):
        raise ArgumentError(f"{_WHO}: weights: expected weights >= 0, some > 0, got {w.tolist()}",
                            argument="weights", received=w.tolist())
    return w


def _rows(model: Model, outputs: tuple[str, ...]) -> np.ndarray:
    """(q, n) displacement (or velocity, or acceleration) map of each measured output."""
    asm = assemble(model, sparse=False)
    rows: list[np.ndarray] = []
    cache: dict[str, Any] = {}
    for name in outputs:
        if name.startswith("mount."):
            raise ArgumentError(f"{_WHO}: measured: output {name!r}: a mode shape is read at body DOFs and control "
                                "points (a mount's output moves with its rate)", argument="measured", received=name)
        try:
            r, _ = output_row(asm, name, cache)
        except ModelError as e:
            raise ArgumentError(f"{_WHO}: measured: {e}", argument="measured", received=name) from None
        parts = [np.asarray(x)[:asm.n] for x in (r.d, r.v, r.a) if np.any(x)]
        if len(parts) != 1 or np.any(r.h):
            raise ArgumentError(f"{_WHO}: measured: output {name!r} is not a displacement, velocity or "
                                "acceleration of the model's DOFs", argument="measured", received=name)
        rows.append(parts[0])
    return np.array(rows)


def _modes_problem(model: Model, measured: MeasuredModes, params: tuple[Parameter, ...],
                   weights: Any) -> ModesProblem:
    k = len(measured)
    n_model = 6 * len(model.bodies)
    if k > n_model:
        raise ArgumentError(f"{_WHO}: measured: {k} measured modes, but the model has {n_model}", argument="measured",
                            received=k, expected=f"at most {n_model}")
    w = np.ones((2, k))
    if weights is not None:
        if not isinstance(weights, Mapping) or set(weights) - {"frequency", "shape"}:
            raise ArgumentError(f"{_WHO}: weights: for measured modes, a mapping with keys 'frequency' and/or "
                                f"'shape' (a number or one per mode), got {weights!r}", argument="weights",
                                received=weights, expected={"frequency", "shape"})
        for i, key in enumerate(("frequency", "shape")):
            if key in weights:
                v = array(weights[key], f"weights[{key!r}]", who=_WHO)
                if v.shape not in ((), (k,)) or np.any(v < 0):
                    raise ArgumentError(f"{_WHO}: weights[{key!r}]: expected a number >= 0 or {k} of them, got "
                                        f"{v.tolist()}", argument="weights", received=v.tolist())
                w[i] = v
    return ModesProblem(model, params, _rows(model, tuple(measured.outputs)), measured.frequency_hz,
                        np.asarray(measured.shapes), w)


def _bounds(bounds: Any, params: tuple[Parameter, ...], x0: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper bounds [parameter units]: rates within :data:`RATE_RANGE` of their start,
    positions and angles free, unless ``bounds`` names them."""
    lo = np.array([v / RATE_RANGE if p.is_rate else -np.inf for p, v in zip(params, x0)])
    hi = np.array([v * RATE_RANGE if p.is_rate else np.inf for p, v in zip(params, x0)])
    if bounds is None:
        return lo, hi
    names = [p.name for p in params]
    if not isinstance(bounds, Mapping):
        b = array(bounds, "bounds", (2, len(params)), who=_WHO, finite=False)
        lo, hi = b[0].copy(), b[1].copy()
    else:
        for key, pair in bounds.items():
            if key not in names:
                raise ArgumentError(f"{_WHO}: bounds: unknown parameter {key!r}" + did_you_mean(str(key), names),
                                    argument="bounds", received=key, expected=names)
            lo[names.index(key)], hi[names.index(key)] = array(pair, f"bounds[{key!r}]", (2,), who=_WHO, finite=False)
    for i, name in enumerate(names):
        if not lo[i] < hi[i] or (params[i].is_rate and lo[i] < 0):
            raise ArgumentError(f"{_WHO}: bounds: parameter {name!r}: expected lower < upper (>= 0 for a rate), got "
                                f"({lo[i]:g}, {hi[i]:g})", argument="bounds", received=(float(lo[i]), float(hi[i])))
    return lo, hi


def _identifiability(jac: np.ndarray, names: list[str]) -> tuple[np.ndarray, list[list[str]], np.ndarray]:
    """Singular values of the column-normalised Jacobian, the groups of parameters loading its null
    vectors, and the mask of parameters in some group."""
    norms = np.linalg.norm(jac, axis=0)
    jn = jac / np.where(norms > 0, norms, 1.0)
    _, sv, vt = np.linalg.svd(jn, full_matrices=False)
    null = (sv < RANK_RTOL * sv[0]) if sv.size and sv[0] > 0 else np.ones(sv.size, dtype=bool)
    blind = norms <= RANK_RTOL * norms.max() if norms.size else norms == 0
    groups: list[list[str]] = [[names[i]] for i in np.flatnonzero(blind)]
    sets: list[set[int]] = []
    for v in vt[null]:                      # parameters loading a null vector, joined where they share one
        load = set(np.flatnonzero((np.abs(v) > 0.1 * np.abs(v).max()) & ~blind).tolist())
        for other in [g for g in sets if g & load]:
            load |= other
            sets.remove(other)
        if load:
            sets.append(load)
    for g in sets:
        groups.append([names[i] for i in sorted(g)])
        blind[sorted(g)] = True
    return sv, groups, blind


def update(model: Model, measured: FrequencyResponse | MeasuredModes, parameters: Any,
           weights: Any = None, bounds: Any = None) -> UpdateResult:
    """Update a model's mount parameters to a measured frequency response or measured modes.

    Least squares (:func:`scipy.optimize.least_squares`, ``trf`` with bounds) with exact gradients:
    for a frequency response, the derivative of the exact solve ``dH/dp = -Z^-1 (dZ/dp) Z^-1``
    (with the input and output maps' derivatives), residuals the complex relative errors
    ``H_model / H_measured - 1`` per channel and frequency; for modes, the design sensitivities, residuals the relative
    frequency errors and the MAC-paired, best-scaled shape errors
    (:mod:`vibss.measured.update_kernels`).

    Parameters
    ----------
    model : Model
        The model to update (its values are the starting point; it is not changed).
    measured : FrequencyResponse or MeasuredModes
        A measured response (:meth:`FrequencyResponse.from_measurement`, :func:`vibss.io.read_uff`)
        whose inputs and outputs are the model's signal names, at frequencies > 0 [Hz]; or measured
        modes (:class:`MeasuredModes`) at named outputs.
    parameters : str, Parameter or sequence of them
        :mod:`vibss.design` parameters (``"front.k3"`` [N/m], tied :class:`~vibss.design.parameters.Parameter`);
        for measured modes also positions [m], angles [rad] and rate ratios [-].
    weights : mapping, array_like or None
        Frequency response: ``{"<output>/<input>": weight}`` or a (p, m) array per channel [-] (0
        leaves a channel out). Modes: ``{"frequency": w, "shape": w}``, a number or one per mode
        [-]. Weight each residual by 1 / its noise (relative) so the standard deviations hold.
        None: all 1.
    bounds : mapping, (2, k) array_like or None
        ``{name: (lower, upper)}`` or the arrays of lower and upper bounds [parameter units].
        Default: rates and ratios within a factor :data:`RATE_RANGE` of their start, positions
        and angles free.

    Returns
    -------
    UpdateResult
        ``.values``, ``.std`` (dicts name -> value [unit]), the updated ``.model``, the correlation
        before and after (FRAC per channel, or MAC and frequencies per mode), ``.plot()``.

    Raises
    ------
    ArgumentError
        An unknown parameter, channel or output name (named, with did-you-mean), a position or
        angle with a frequency response, bad weights or bounds, fewer residuals than parameters,
        zero or non-finite measured values.

    Warns
    -----
    VibssWarning
        The Jacobian is rank-deficient (the parameters the data cannot tell apart are named; their
        standard deviations are infinite); the solver did not converge; the gradient check missed.

    Examples
    --------
    >>> import vibss
    >>> from vibss import Body, Model, Mount, MountType
    >>> def box(k):
    ...     t = MountType("t", [k, k, 2 * k], [20.0, 20.0, 20.0])
    ...     return Model([Body("b", 10.0, [1, 1, 1])], [Mount("m", t, "b")])
    >>> h = vibss.frequency_response(box(1e4), ["b.fz"], ["b.z"], frequencies=[3.0, 5.0, 8.0])
    >>> test = vibss.FrequencyResponse.from_measurement(h.frequency_hz, h.response, ["b.fz"], ["b.z"], "m/N")
    >>> r = update(box(1.3e4), test, ["m.k3"])
    >>> round(r.values["m.k3"])
    20000
    """
    if not isinstance(model, Model):
        raise ArgumentError(f"{_WHO}: model: expected a vibss.Model, got {type(model).__name__}", argument="model",
                            received=type(model).__name__)
    params = parameters_of(model, parameters)
    if isinstance(measured, FrequencyResponse):
        problem: FrfProblem | ModesProblem = _frf_problem(model, measured, params, weights)
    elif isinstance(measured, MeasuredModes):
        problem = _modes_problem(model, measured, params, weights)
    else:
        raise ArgumentError(f"{_WHO}: measured: expected a FrequencyResponse or MeasuredModes, got "
                            f"{type(measured).__name__}", argument="measured", received=type(measured).__name__)
    x0 = current_values(model, params)
    for p, v in zip(params, x0):
        if p.is_rate and not v > 0:
            raise ArgumentError(f"{_WHO}: parameter {p.name!r} starts at {v:g} {p.unit}; a rate is updated from a "
                                "value > 0 (it sets the scale)", argument="parameters", received=p.name)
    lo, hi = _bounds(bounds, params, x0)
    scale = np.array([abs(v) if p.is_rate else 1.0 for p, v in zip(params, x0)])
    return _solve(model, measured, problem, params, x0, lo, hi, scale)


def _solve(model: Model, measured: Any, problem: FrfProblem | ModesProblem, params: tuple[Parameter, ...],
           x0: np.ndarray, lo: np.ndarray, hi: np.ndarray, scale: np.ndarray) -> UpdateResult:
    """The least-squares run and what it states (see :func:`update`)."""
    memo: dict[bytes, tuple[np.ndarray, np.ndarray | None]] = {}

    def both(xs: np.ndarray) -> tuple[np.ndarray, np.ndarray | None]:
        key = xs.tobytes()
        if key not in memo:
            memo.clear()
            memo[key] = problem.residual(xs * scale, True)
        return memo[key]

    def fun(xs: np.ndarray) -> np.ndarray:
        return both(xs)[0]

    def jac(xs: np.ndarray) -> np.ndarray:
        j = both(xs)[1]
        assert j is not None
        return j * scale[None]

    r0, _ = problem.residual(x0, False)
    n, k = r0.size, len(params)
    if n <= k:
        raise ArgumentError(f"{_WHO}: measured: {n} residuals for {k} parameters; give more data (frequencies, "
                            "channels, modes) than parameters", argument="measured", received=n, expected=f"> {k}")
    start = np.clip(x0, np.nextafter(lo, np.inf), np.nextafter(hi, -np.inf))
    factor = _scan(problem, start, lo, hi) if isinstance(problem, FrfProblem) else 1.0
    rates = np.array([p.targets[0][1] in ("k1", "k2", "k3") for p in params])
    start = np.where(rates, start * factor, start) / scale
    sol = least_squares(fun, start, jac=jac, bounds=(lo / scale, hi / scale), method="trf", x_scale=1.0,
                        xtol=1e-12, ftol=1e-12, gtol=1e-12, max_nfev=200)
    values = sol.x * scale
    r, jp = problem.residual(values, True)
    assert jp is not None
    names = [p.name for p in params]
    js = jp * scale[None]
    sv, groups, blind = _identifiability(js, names)
    s2 = float(r @ r) / (n - k)
    cov = s2 * np.linalg.pinv(js.T @ js)
    std = np.where(blind, np.inf, np.sqrt(np.maximum(np.diag(cov), 0.0)) * scale)
    check = _gradient_check(problem, sol.x, scale, js, r)
    if groups:
        warnings.warn(f"{_WHO}: the Jacobian is rank-deficient: the data cannot tell apart "
                      + "; ".join(" and ".join(repr(x) for x in g) if len(g) > 1 else f"{g[0]!r} (no effect)"
                                  for g in groups)
                      + " (their standard deviations are infinite); tie them (vibss.design.Parameter), fix one, "
                      "or measure where they differ", VibssWarning, stacklevel=3)
    if sol.status <= 0:
        warnings.warn(f"{_WHO}: least_squares stopped before converging ({sol.message}); the values are its last "
                      "iterate", VibssWarning, stacklevel=3)
    if not check.ok:
        warnings.warn(f"{_WHO}: the gradient check missed: {check.text()}", VibssWarning, stacklevel=3)
    before = _correlation(model, measured, problem, x0)
    after = _correlation(model, measured, problem, values)
    kind = "frequency response" if isinstance(problem, FrfProblem) else "modes"
    labels = (tuple(f"{y}/{u}" for y in problem.outputs for u in problem.inputs) if isinstance(problem, FrfProblem)
              else tuple(f"mode {i + 1}" for i in range(len(measured))))
    note = (f"claim: {CLAIM.text()}; " + (f"started from the rates times {factor:.3g} (the scan's best "
            "log-magnitude error); " if factor != 1.0 else "") + f"{n} residuals, {k} parameters, {sol.nfev} evaluations"
            f" ({sol.message.rstrip('.')}); gradient "
            f"{check.text()}; std = s (J^T J)^-1/2 with s = {np.sqrt(s2):.3g} (the residual RMS per degree of freedom)")
    return UpdateResult(model=apply(model, params, values), initial_model=model, parameters=tuple(names),
                        parameter_units=tuple(p.unit for p in params), initial=x0, estimate=values,
                        standard_deviation=std, kind=kind, labels=labels, measured=measured,
                        correlation_before=before[1], correlation_after=after[1],
                        response_before=before[0], response_after=after[0],
                        frequency_before=before[2], frequency_after=after[2],
                        residual_rms=np.array([np.sqrt(np.mean(r0 ** 2)), np.sqrt(np.mean(r ** 2))]),
                        singular_values=sv, unidentifiable=tuple(" and ".join(g) for g in groups),
                        check=check, evaluations=int(sol.nfev), note=note)


def _scan(problem: FrfProblem, start: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> float:
    """The factor of :data:`SCAN` (or 1) by which the rates of ``start`` give the smallest
    :meth:`~vibss.measured.update_kernels.FrfProblem.log_misfit`, the scaled rates within the bounds."""
    rates = np.array([p.targets[0][1] in ("k1", "k2", "k3") for p in problem.parameters])
    if not rates.any():
        return 1.0
    best, cost = 1.0, problem.log_misfit(start)
    for c in SCAN:
        x = np.where(rates, start * c, start)
        if np.all((x > lo) & (x < hi)):
            trial = problem.log_misfit(x)
            if trial < cost:
                best, cost = float(c), trial
    return best


def _gradient_check(problem: FrfProblem | ModesProblem, xs: np.ndarray, scale: np.ndarray, js: np.ndarray,
                    r: np.ndarray) -> Check:
    """A central difference of the residual along the diagonal direction against ``J d``."""
    d = np.ones(xs.size) / np.sqrt(xs.size)
    h = 1e-5
    rp, _ = problem.residual((xs + h * d) * scale, False)
    rm, _ = problem.residual((xs - h * d) * scale, False)
    exact = js @ d
    err = float(np.linalg.norm((rp - rm) / (2 * h) - exact) / max(float(np.linalg.norm(exact)), 1e-300))
    return Check(err, GRADIENT_RTOL, f"{r.size} residuals, central difference of step {h:g} (scaled)")


def _correlation(model: Model, measured: Any, problem: FrfProblem | ModesProblem,
                 values: np.ndarray) -> tuple[Any, np.ndarray, np.ndarray]:
    """For a frequency response: the model's response at the measured frequencies and the FRAC per
    channel; for modes: (None, MAC per mode, the paired model frequencies [Hz])."""
    updated = apply(model, problem.parameters, values)
    if isinstance(problem, FrfProblem):
        h = frequency_response(updated, list(problem.inputs), list(problem.outputs),
                               frequencies=measured.frequency_hz, quantity=_QUANTITY[problem.power])
        score = frac(measured, h)
        return h, np.array([score[f"{y}/{u}"] for y in problem.outputs for u in problem.inputs]), np.zeros(0)
    md = problem.modal(values, jacobian=False)
    return None, md["mac"], md["f"]
