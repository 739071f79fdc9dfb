"""Harmonic balance: the steady periodic response of a model with nonlinear mounts under sine inputs.

:func:`harmonic_balance` follows the response curve over a frequency range by the alternating
frequency-time method with pseudo-arclength continuation (through the folds where a slow sweep
jumps), with the stability per point (Floquet multipliers, or Hill's method on request).
The linear part is exact: the tangent model at the
operating point, condensed onto the few nonlinear mount axes per harmonic by the core's exact
solve (:mod:`vibss.nonlinear.hb.condensed`), so the unknowns are only those axes' harmonics and
every output is recovered linearly from them.

The method states its accuracy (:data:`CLAIM`): the residual of the harmonic-balance equations
(Newton's, to about 1e-11 of the local deflections) and the truncation estimate, the share of the
two highest harmonics kept in the nonlinear axes' deflections, held to ``tolerance`` (a
:class:`~vibss.errors.VibssWarning` when it is exceeded: raise ``harmonics``).
"""

from __future__ import annotations

import dataclasses
import warnings
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np
from scipy.interpolate import CubicHermiteSpline

from .._validate import choice, is_numeric
from ..errors import ArgumentError, VibssWarning
from ..linear.plant.assemble import assemble
from ..linear.plant.build import build_plant
from ..linear.plant.names import default_outputs
from ..methods import Check, Claim
from ..model.model import Model
from ..threads import one_blas_thread
from .api import operating_point
from .hb.aft import LocalLaws, aft, basis, jacobian_blocks, samples_for, to_complex
from .hb.condensed import Condensed
from .hb.continuation import Branch, Problem, follow
from .hb.floquet import FLOQUET_MAX, floquet, piecewise_linear
from .hb.hill import HILL_MAX, Hill, hill_exponents
from .kernels import _laws, nonlinear_axes, nonlinear_mounts
from .result import HarmonicBalanceResult

__all__ = ["harmonic_balance", "CLAIM", "TOLERANCE", "STABILITY", "HILL_CHEAPER_H"]

TOLERANCE = 1e-3
"""Default limit of the truncation estimate (highest harmonic's share of the local deflections)."""

CLAIM = Claim(TOLERANCE, conditions="the highest harmonic kept carries at most the tolerance of the nonlinear axes' "
              "deflections (the truncation estimate); the equations' residual ~1e-11")
"""The harmonic balance's claim (its tolerance replaced by the call's ``tolerance``)."""


def harmonic_balance(model: Model, inputs: Mapping[str, complex], outputs: Sequence[str] | None = None,
                     frequencies: Any = (1.0, 100.0), harmonics: int = 5, *, points: int = 200,
                     samples: int | None = None, tolerance: float = TOLERANCE, stability: bool | str = True,
                     gravity: bool = True, case: str | None = None) -> HarmonicBalanceResult:
    """The steady periodic response to sine inputs along the branch, with stability and turning points.

    Parameters
    ----------
    model : Model
        The system; its nonlinear mounts (stops, curves) act about the operating point under its
        static loads (:func:`vibss.operating_point`); a linear model gives its FRF times the amplitudes.
    inputs : mapping of str to complex or callable
        Input name (force inputs ``'b.fz'``, prescribed motion ``'ground.z.acc'``, as
        :func:`vibss.frequency_response`) to its amplitude ``u`` (SI unit of the signal; complex
        for a phase): ``u(t) = Re(u exp(i omega t))``, all at the same frequency. An amplitude that
        follows the frequency (an unbalance's ``m e omega^2``) is a callable of the frequencies
        [Hz], (nf,) array to (nf,) complex amplitudes; the continuation follows it.
    outputs : sequence of str or None
        Output signals (default every body DOF's displacement); a mount or ground force output
        includes the nonlinear mounts' forces.
    frequencies : (2,) tuple or (nf,) array_like [Hz]
        A tuple ``(f_start, f_end)``: every continuation point between them (about ``points`` or
        more where the curve bends) is reported. An array (list or ndarray): the branch is
        followed from its lowest value until it first reaches its highest, and every crossing of
        each given frequency on the way is reported (three at a frequency with three solutions),
        in branch order; end the array above the folds to have every crossing.
    harmonics : int
        Highest harmonic H >= 1 kept (0th, the mean shift, always included).
    points : int
        Continuation steps over the range at the longest step (more where the branch bends).
    samples : int or None
        Time samples per period of the AFT (default :func:`~vibss.nonlinear.hb.aft.samples_for`).
    tolerance : float
        Limit of the truncation estimate [-]; exceeded: a VibssWarning.
    stability : bool or {"auto", "floquet", "hill"}
        Stability at every point (:data:`STABILITY`): True or ``"auto"`` takes the Floquet
        multipliers of the monodromy matrix (exact between contact instants when every nonlinear axis
        is a stop, fourth-order Magnus sub-steps with a convergence check for curves, Hill's method
        at a point where they do not converge), Hill's method where it costs less (curves with at
        most :data:`HILL_CHEAPER_H` harmonics); ``"hill"`` Hill's method everywhere; False skips it.
    gravity : bool
        Include self-weight in the operating point.
    case : str or None
        Load case of the operating point (as :func:`vibss.static`).

    Returns
    -------
    HarmonicBalanceResult

    Raises
    ------
    ArgumentError
        No inputs, an amplitude not a finite number, ``harmonics < 1``, frequencies not positive
        and finite, a range not increasing.
    SignalError
        An unknown input or output name (with did-you-mean).
    AnalysisError
        Newton's method fails at the first frequency, the continuation stalls, or the tangent
        model is singular (a free rigid-body motion, an undamped resonance at a harmonic).

    Examples
    --------
    >>> from vibss import Body, Model, Mount, MountType
    >>> t = MountType("snub", [4e4, 4e4, 4e4], damping=[40.0] * 3, stops={"z": (1e-3, 4e4)})
    >>> m = Model([Body("b", 10.0, [1, 1, 1])], [Mount("m", t, "b")])     # 10 Hz, a stop at 1 mm
    >>> r = harmonic_balance(m, {"b.fz": 10.0}, ["b.z"], frequencies=(5.0, 20.0), harmonics=7, points=100)
    >>> r.turning_points.round(1).tolist(), bool(r.stable.all())     # a hardening fold; its middle branch unstable
    ([12.8, 11.2], False)
    """
    if not isinstance(model, Model):
        raise ArgumentError(f"harmonic_balance: model: expected a Model, got {type(model).__name__}",
                            argument="model", received=model)
    names, u, law = _inputs(inputs)
    H = _harmonics(harmonics)
    w0, w1, targets = _frequencies(frequencies)
    if law is not None:
        u = law(np.array([w0]))[0]
    if not isinstance(points, (int, np.integer)) or isinstance(points, bool) or points < 2:
        raise ArgumentError(f"harmonic_balance: points: expected an integer >= 2, got {points!r}",
                            argument="points", received=points)
    if not (isinstance(tolerance, (int, float, np.floating)) and np.isfinite(tolerance) and tolerance > 0):
        raise ArgumentError(f"harmonic_balance: tolerance: expected a positive share [-] of the highest harmonics, "
                            f"got {tolerance!r}", argument="tolerance", received=tolerance)
    outs = tuple(default_outputs(model) if outputs is None else [str(o) for o in outputs])
    N = samples_for(H) if samples is None else int(samples)
    if N <= 2 * H:
        raise ArgumentError(f"harmonic_balance: samples: expected more than 2 H = {2 * H} time samples per "
                            f"period, got {samples!r}", argument="samples", received=samples)
    with one_blas_thread():       # small products only: threads cost a time slice each on a busy core
        lin, laws, local_names, op_note = _setup(model, names, u, outs, H, gravity, case, law)
        problem = Problem(lin, laws, basis(H, N))
        if lin.m:
            steps = points if targets is None else max(points, 4 * len(targets))
            branch = follow(problem, w0, w1, steps, targets, max_steps=40 * steps)
        else:
            grid = np.linspace(w0, w1, points) if targets is None else np.sort(targets)
            branch = Branch(omega=list(grid), X=[np.zeros(0)] * grid.size)
        return _result(problem, branch, names, u, outs, local_names, tolerance, stability, op_note)


def _inputs(inputs: Any) -> tuple[list[str], np.ndarray, Callable[[np.ndarray], np.ndarray] | None]:
    """Names, constant amplitudes, and the amplitudes' law in frequency when some input follows it."""
    if not isinstance(inputs, Mapping) or not inputs:
        raise ArgumentError("harmonic_balance: inputs: expected a mapping of input name to amplitude, e.g. "
                            f"{{'engine.fz': 100.0}}, got {inputs!r}", argument="inputs", received=inputs)
    names: list[str] = []
    amps: list[complex] = []
    funcs: dict[int, Any] = {}
    for name, a in inputs.items():
        if callable(a):
            funcs[len(names)] = a
            a = 0.0
        ok = isinstance(a, (int, float, complex, np.number)) and not isinstance(a, bool) and np.isfinite(a)
        if not ok:
            raise ArgumentError(f"harmonic_balance: inputs[{name!r}]: expected a finite amplitude (a number in "
                                f"the signal's SI unit, or a callable of the frequency [Hz]), got {a!r}",
                                argument=str(name), received=a)
        names.append(str(name))
        amps.append(complex(a))
    u = np.array(amps)
    if not funcs:
        return names, u, None

    def law(omegas: np.ndarray) -> np.ndarray:
        out = np.tile(u, (omegas.size, 1))
        for j, f in funcs.items():
            a = np.asarray(f(omegas / (2 * np.pi)), dtype=complex).reshape(-1)
            if a.size != omegas.size or not np.all(np.isfinite(a)):
                raise ArgumentError(f"harmonic_balance: inputs[{names[j]!r}]: the callable must give one finite "
                                    f"amplitude per frequency, got {a!r}", argument=names[j], received=a)
            out[:, j] = a
        return out

    return names, u, law


def _harmonics(harmonics: Any) -> int:
    if not isinstance(harmonics, (int, np.integer)) or isinstance(harmonics, bool) or harmonics < 1:
        raise ArgumentError(f"harmonic_balance: harmonics: expected an integer H >= 1 (the highest harmonic "
                            f"kept), got {harmonics!r}", argument="harmonics", received=harmonics)
    return int(harmonics)


def _frequencies(frequencies: Any) -> tuple[float, float, list[float] | None]:
    """``(w0, w1, targets)`` [rad/s]: a tuple is a range, a list or array the points to report."""
    f = np.asarray(frequencies, dtype=float) if is_numeric(frequencies) else np.array([np.nan])
    if f.ndim != 1 or f.size == 0 or not np.all(np.isfinite(f)) or np.any(f <= 0):
        raise ArgumentError(f"harmonic_balance: frequencies: expected positive finite frequencies [Hz] (a tuple "
                            f"(f_start, f_end) or an array), got {frequencies!r}", argument="frequencies",
                            received=frequencies)
    w = 2 * np.pi * f
    if isinstance(frequencies, tuple):
        if f.size != 2 or not f[1] > f[0]:
            raise ArgumentError(f"harmonic_balance: frequencies: a tuple is the range (f_start, f_end) with "
                                f"f_end > f_start [Hz], got {frequencies!r}", argument="frequencies",
                                received=frequencies)
        return float(w[0]), float(w[1]), None
    lo, hi = float(w.min()), float(w.max())
    return lo, (hi if hi > lo else lo * (1 + 1e-9)), sorted(float(x) for x in w)


def _setup(model: Model, names: list[str], u: np.ndarray, outs: tuple[str, ...], H: int, gravity: bool,
           case: str | None, law: Callable[[np.ndarray], np.ndarray] | None = None
           ) -> tuple[Condensed, LocalLaws, list[str], str]:
    """The condensed tangent plant, the local laws about the operating point and the note on it."""
    found, local_names = nonlinear_axes(model)
    where = [(i, j) for i, _, j in found]
    tangent, d0 = model, np.zeros(len(where))
    note = "linear model: the frequency response times the amplitudes"
    laws: list[Any] = []
    if where:
        op = operating_point(model, gravity=gravity, case=case)
        tangent = op.tangent
        idx = nonlinear_mounts(model)
        d = _laws(assemble(model), idx).local(op.q)
        laws = [model.mounts[p].type.laws[j] for _, p, j in found]
        d0 = np.array([d[i, j] for i, j in where])
        note = (f"about the operating point ({op.iterations} Newton steps); the linear part is the tangent model "
                f"condensed exactly onto {len(where)} nonlinear axes {local_names}")
    extra = [n for n in local_names if n not in outs]
    plant = build_plant(tangent, names, list(outs) + extra)
    local = np.array([list(plant.outputs).index(n) for n in local_names], dtype=int)
    f0 = np.array([float(law.force(x)) for law, x in zip(laws, d0)])
    kt = np.array([float(law.tangent(x)) for law, x in zip(laws, d0)])
    W = _direct(tangent, names, outs, local_names, kt, plant)
    lin = Condensed(plant, local, len(outs), u, H, W, law)
    return lin, LocalLaws(tuple(laws), d0, f0, kt), local_names, note


def _direct(tangent: Model, names: list[str], outs: tuple[str, ...], local_names: list[str], kt: np.ndarray,
            plant: Any) -> np.ndarray:
    """(p, m) each output's part per unit force beyond the tangent on each nonlinear axis.

    An output row ``Oq`` is linear in each mount axis's rate (a mount, ground or sensor force reads
    ``k delta``): raising axis ``j``'s rate by ``dk`` changes it by ``dk w_j L_j``, so ``w_j`` is
    how much of that axis's force the output carries.
    """
    p, m = len(outs), len(local_names)
    W = np.zeros((p, m))
    if not m:
        return W
    L = np.asarray(plant.Oq[[list(plant.outputs).index(n) for n in local_names]], dtype=float)
    base = np.asarray(plant.Oq[:p], dtype=float)
    for j, name in enumerate(local_names):
        mount, axis = name.split(".")[1], int(name[-1]) - 1
        dk = max(float(kt[j]), 1.0)
        new = []
        for mt in tangent.mounts:
            if mt.name == mount:
                k = np.array(mt.type.stiffness, dtype=float)
                k[axis] += dk
                mt = dataclasses.replace(mt, type=dataclasses.replace(mt.type, name=mt.type.name + "+", stiffness=k))
            new.append(mt)
        other = build_plant(dataclasses.replace(tangent, mounts=tuple(new)), names, list(outs))
        diff = np.asarray(other.Oq, dtype=float) - base
        W[:, j] = diff @ L[j] / (dk * float(L[j] @ L[j]))
    return W


def _result(problem: Problem, branch: Branch, names: list[str], u: np.ndarray, outs: tuple[str, ...],
            local_names: list[str], tolerance: float, stability: bool | str, op_note: str) -> HarmonicBalanceResult:
    lin, H, m = problem.linear, problem.basis.harmonics, problem.linear.m
    nb = len(branch.omega)
    Y = np.zeros((lin.p, H + 1, nb), dtype=complex)
    Yl = np.zeros((m, H + 1, nb), dtype=complex)
    resid, trunc = np.zeros(nb), np.zeros(nb)
    hill, how, why = _stability(problem, stability)
    fallback, hill_fits = 0, 2 * lin.plant.n * (2 * H + 1) <= HILL_MAX
    stable = None if hill is None else np.zeros(nb, dtype=bool)
    growth = None if hill is None else np.zeros(nb)
    parts = lin.outputs(np.asarray(branch.omega, dtype=float))         # every point's, batched
    for b, (w, X, c) in enumerate(zip(branch.omega, branch.X, parts)):
        assert c.T is not None and c.Y is not None
        Y[:, 1, b] = c.Y
        J = None
        if m:
            F, J, kappa = aft(problem.laws, problem.basis, X, jacobian=how == "hill")
            Fc = to_complex(F, H, m)
            Y[:, :, b] -= np.einsum("kpm,km->pk", c.T, Fc)
            Yl[:, :, b] = to_complex(X, H, m).T
            R = problem.equations(X, F, w)
            resid[b] = float(np.linalg.norm(R) / max(np.linalg.norm(X), np.finfo(float).tiny))
            trunc[b] = _truncation(Yl[:, :, b])
        if hill is not None and stable is not None and growth is not None:
            ok = how == "floquet"
            if ok:
                stable[b], growth[b], ok = floquet(hill, problem.laws, Yl[:, :, b], w, problem.basis.E.shape[0])
                fallback += not ok
            if not ok and (how == "hill" or hill_fits):
                gamma = J if J is not None else jacobian_blocks(kappa, H) if m else np.zeros((0, 2 * H + 1, 2 * H + 1))
                stable[b], growth[b] = hill_exponents(hill, gamma, w)
    if fallback:
        why += (f" (Hill's method at {fallback} points where the Magnus sub-steps did not converge)" if hill_fits else
                f" (unconverged at {fallback} points: the finest Magnus sub-steps' answer; Hill's matrix would be "
                f"{2 * lin.plant.n * (2 * H + 1)} square, limit {HILL_MAX})")
        if not hill_fits:
            warnings.warn(f"harmonic_balance: the stability at {fallback} points did not converge (Floquet's Magnus "
                          "sub-steps) and Hill's method is too large to check it: their flags may be wrong",
                          VibssWarning, stacklevel=3)
    folds = _folds(branch)
    claim = dataclasses.replace(CLAIM, tolerance=float(tolerance))
    worst = float(trunc.max(initial=0.0))
    check = Check(worst, float(tolerance), f"the highest harmonic ({H}) of the nonlinear axes, worst of {nb} points")
    if not check.ok:
        warnings.warn(f"harmonic_balance: the highest harmonic kept ({H}) carries {worst:.1e} of the nonlinear axes' "
                      f"deflection (more than the tolerance {tolerance:.0e}): raise harmonics", VibssWarning,
                      stacklevel=3)
    if not branch.complete:
        warnings.warn("harmonic_balance: the continuation stopped before the end of the range (step limit)",
                      VibssWarning, stacklevel=3)
    f = np.array(branch.omega) / (2 * np.pi)
    note = "; ".join(x for x in (op_note, f"{branch.steps} continuation steps ({branch.rejected} halved)"
                                 if m else "", why, f"residual <= {resid.max(initial=0.0):.1e}") if x)
    return HarmonicBalanceResult(
        frequencies=f, harmonics=Y, stable=stable, growth=growth, turning_points=folds[0], turning_index=folds[1],
        residual=resid, truncation=trunc, local_labels=tuple(local_names), local=Yl,
        inputs=dict(zip(names, (complex(a) for a in u))), output_names=outs,
        output_units=tuple(lin.plant.units[:lin.p]), claim=claim, check=check, note=note)


def _truncation(Yl: np.ndarray) -> float:
    """RMS of the larger of the two highest harmonics over that of all harmonics >= 1 (two: a
    symmetric law about the operating point has no even harmonics, so the highest alone may be 0;
    with H = 2 only the second, with H = 1 the estimate is 1: nothing is known)."""
    total = float(np.sum(np.abs(Yl[:, 1:]) ** 2))
    H = Yl.shape[1] - 1
    top = max(float(np.sum(np.abs(Yl[:, k]) ** 2)) for k in (range(max(2, H - 1), H + 1) if H > 1 else [1]))
    return float(np.sqrt(top / total)) if total > 0 else 0.0


HILL_CHEAPER_H = 3
"""With curves, Hill's eigenvalue problem (size ``2n (2H+1)``) costs less than the Magnus monodromy's
doubling runs up to this many harmonics: measured on the snubbed cabinet (12 states, 68-78 points)
0.07 / 0.15 / 0.18 / 0.32 s for Hill's at H = 1 / 2 / 3 / 5 against 0.32 / 0.31 / 0.25 / 0.25 s."""

STABILITY = ("auto", "floquet", "hill")
"""Stability methods: ``"floquet"`` (the monodromy matrix, exact between contact instants for stops,
fourth-order Magnus sub-steps for curves, :mod:`vibss.nonlinear.hb.floquet`), ``"hill"`` (the Hill
matrix's eigenvalues, :mod:`vibss.nonlinear.hb.hill`); ``"auto"`` (or True) is Floquet's, with Hill's
at a point where Floquet's sub-steps do not converge (where Hill's matrix fits :data:`HILL_MAX`), and
Hill's where the monodromy would exceed :data:`~vibss.nonlinear.hb.floquet.FLOQUET_MAX` states or, with
curves, at most :data:`HILL_CHEAPER_H` harmonics are kept (where Hill's costs less)."""


def _stability(problem: Problem, stability: bool | str) -> tuple[Hill | None, str, str]:
    """The tangent matrices, the method (``"floquet"``, ``"hill"`` or ``""``) and the note."""
    plant = problem.linear.plant
    if stability is False:
        return None, "", "stability not computed (stability=False)"
    how = choice("auto" if stability is True else stability, "stability", STABILITY, who="harmonic_balance")
    size = 2 * plant.n * (2 * problem.basis.harmonics + 1)
    if how == "auto":                       # Floquet's, or Hill's where only it fits or it costs less
        cheaper = not piecewise_linear(problem.laws) and problem.basis.harmonics <= HILL_CHEAPER_H
        how = "hill" if size <= HILL_MAX and (2 * plant.n > FLOQUET_MAX or cheaper) else "floquet"
    if plant.branches is not None:
        return None, "", "stability not computed: frequency-dependent mounts have internal states it lacks"
    if how == "hill" and size > HILL_MAX:
        return None, "", f"stability not computed: Hill's matrix would be {size} square (limit {HILL_MAX})"
    if how == "floquet" and 2 * plant.n > FLOQUET_MAX:
        return None, "", f"stability not computed: the monodromy matrix would be {2 * plant.n} square (limit {FLOQUET_MAX})"
    hyst = " (loss factors left out: no time-domain form)" if np.any(plant.H) else ""
    what = ("Hill's method" if how == "hill" else "Floquet multipliers (exact monodromy between the stops' "
            "contact instants)" if piecewise_linear(problem.laws) else "Floquet multipliers (fourth-order Magnus)")
    return Hill(plant, problem.linear.rows()), how, f"stability by {what}, {2 * plant.n} exponents{hyst}"


FOLD_RETREAT = 1e-3
"""A fold counts when the branch's frequency retreats from its extremum by more than this fraction:
a stop's kink makes the discretised branch zig-zag by the AFT's sampling error near a fold."""


def _folds(branch: Branch) -> tuple[np.ndarray, np.ndarray]:
    """Frequencies [Hz] of the branch's folds (extrema of the frequency along it that the branch
    leaves by more than :data:`FOLD_RETREAT`) and the recorded point nearest each.

    Between the extremal continuation point and its neighbour where ``d omega / d s`` changes sign,
    ``omega(s)`` is refined as the cubic Hermite interpolant of their frequencies and slopes (error
    O(ds^4) on a smooth branch).
    """
    w, d, s = np.array(branch.path), np.array(branch.slope) * branch.scale, np.array(branch.arc)
    freqs, where = [], []
    up, c = True, 0                  # direction of travel in frequency, and the running extremum
    for i in range(1, w.size):
        if (w[i] > w[c]) == up:
            c = i
        elif abs(w[i] - w[c]) > FOLD_RETREAT * w[c]:
            freqs.append(_refined(w, d, s, c, up) / (2 * np.pi))
            where.append(branch.near[c])
            up, c = not up, i
    return np.array(freqs), np.array(where, dtype=int)


def _refined(w: np.ndarray, d: np.ndarray, s: np.ndarray, c: int, top: bool) -> float:
    """The extremum of ``omega`` [rad/s] near path point ``c`` (a maximum when ``top``)."""
    best = float(w[c])
    for b in (c - 1, c):
        if 0 <= b < w.size - 1 and d[b] * d[b + 1] < 0:
            p = CubicHermiteSpline([0.0, s[b + 1] - s[b]], w[b:b + 2], d[b:b + 2])
            for r in p.derivative().roots(extrapolate=False):
                if 0 <= r <= s[b + 1] - s[b]:
                    val = float(p(r))
                    best = max(best, val) if top else min(best, val)
    return best
