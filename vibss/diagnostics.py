"""Checks vibss applies before it runs a method: where a numerical method fails, and why.

Every check returns a :class:`Finding` (``ok``, a message naming the cause and the numbers, the
measured value and the limit). ``finding.warn()`` issues a :class:`VibssWarning` when the finding
is not ok; analyses use the findings to warn or to steer an automatic method choice. The checks
are cheap next to the analysis they guard (an ``eigvalsh`` of the model at most, which the modal
methods compute anyway and can pass in through ``omega``).

Checks
------
- :func:`check_central_difference` — explicit central difference is stable only for
  ``dt < 2 / omega_max``.
- :func:`check_explicit_rk` — explicit Runge-Kutta on a stiff model (``omega_max / omega_min``
  large): the step is set by stability at ``omega_max``, not by accuracy; estimates the number of
  steps against the number accuracy needs.
- :func:`check_sampling` — a fixed sampling step that smears pulse edges (pulse shorter than a few
  steps, edges between samples) or aliases a fast sweep (``f_max`` against the Nyquist frequency).
- :func:`conditioning` — condition numbers of M and K in the user's units and after
  equilibration (symmetric diagonal scaling); unit choices (mm vs m, g vs t) are diagonal scalings
  that equilibration removes exactly.
- :func:`check_static` — a (nearly) singular stiffness: names the free motion.
- :func:`repeated_frequencies` / :func:`check_repeated` — clusters of equal frequencies, whose
  individual mode shapes are arbitrary unless a direction is chosen (vibss aligns them).
- :func:`check_damping_resolution` — whether the damping ratios of lightly damped modes survive
  an eigen-decomposition of the physical state matrix (error about ``eps ||A|| / (zeta omega)``).
- :func:`blas_threads` — the BLAS/OpenMP thread pools in use (benchmarks print this).

Examples
--------
>>> import numpy as np
>>> M, K = np.diag([1.0, 1.0]), np.diag([1e2, 1e6])       # omega = 10 and 1000 rad/s
>>> f = check_central_difference(M, K, dt=3e-3)
>>> f.ok, round(f.limit, 6)
(False, 0.002)
"""

from __future__ import annotations

import warnings
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from threadpoolctl import threadpool_info

from .linear.eigen.directions import cluster_slices
from .linear.eigen.undamped import symmetric_eigen, undamped
from .linear.solve.mass import mass_solver
from .errors import VibssWarning

__all__ = ["VibssWarning", "Finding", "Conditioning", "natural_frequencies",
           "check_central_difference", "check_explicit_rk", "check_sampling", "check_excitations",
           "conditioning", "equilibrate", "check_static", "repeated_frequencies", "check_repeated",
           "check_damping_resolution", "blas_threads", "RK_IMAG_BOUND"]


RK_IMAG_BOUND = {"RK23": 1.73, "RK45": 3.3, "DOP853": 4.6}
"""Approximate extent ``|h omega|`` of each explicit solver's stability region along the imaginary
axis (lightly damped modes lie next to it). Measured: ``bench_stability.py``, stiff-model chart."""

RK_ORDER = {"RK23": 3, "RK45": 5, "DOP853": 8}


@dataclass(frozen=True)
class Finding:
    """Outcome of one check.

    Attributes
    ----------
    check : str
        Name of the check (e.g. ``"central_difference"``).
    ok : bool
        False when the method is expected to fail or lose accuracy.
    message : str
        What was found, with the numbers and the cause.
    value : float
        The measured quantity (see each check).
    limit : float
        The limit it was compared with.
    data : dict of str to float
        Further numbers of the check (e.g. the estimated step counts), by name.
    """

    check: str
    ok: bool
    message: str
    value: float = float("nan")
    limit: float = float("nan")
    data: dict[str, float] = field(default_factory=dict)

    def warn(self, stacklevel: int = 3) -> None:
        """Issue a :class:`VibssWarning` with the message if the finding is not ok.

        Parameters
        ----------
        stacklevel : int
            Passed to :func:`warnings.warn` (3: the caller of the analysis that checks).
        """
        if not self.ok:
            warnings.warn(f"{self.check}: {self.message}", VibssWarning, stacklevel=stacklevel)


def natural_frequencies(M: Any, K: Any) -> np.ndarray:
    """Undamped natural frequencies [rad/s], ascending (rigid-body modes as 0).

    Parameters
    ----------
    M, K : (n, n) array_like
        Mass and stiffness (SI, dense; a sparse matrix is densified).
    """
    M = M.toarray() if hasattr(M, "toarray") else np.asarray(M, float)
    K = K.toarray() if hasattr(K, "toarray") else np.asarray(K, float)
    return np.sqrt(undamped(K, M).omega2)


def _omega(M: Any, K: Any, omega: Any) -> np.ndarray:
    return np.asarray(omega, float) if omega is not None else natural_frequencies(M, K)


def check_central_difference(M: Any, K: Any, dt: float, omega: Any = None) -> Finding:
    """Explicit central difference: stable only for ``dt < 2 / omega_max``.

    Parameters
    ----------
    M, K : (n, n) array_like
        Mass [kg, kg m^2] and stiffness [N/m, N m/rad].
    dt : float
        Step [s].
    omega : (n,) array_like or None
        Natural frequencies [rad/s], if known.

    Returns
    -------
    Finding
        ``value`` = dt [s], ``limit`` = 2 / omega_max [s].
    """
    w = _omega(M, K, omega)
    wmax = float(w.max()) if w.size else 0.0
    limit = 2.0 / wmax if wmax > 0 else np.inf
    ok = dt < limit
    msg = (f"dt = {dt:.3g} s {'<' if ok else '>='} 2/omega_max = {limit:.3g} s (highest mode "
           f"{wmax / (2 * np.pi):.4g} Hz); " + ("stable" if ok else
           "the explicit scheme is unstable and the response grows without bound: use a step "
           f"below {limit:.3g} s, or an implicit or exact method (Newmark, modal)"))
    return Finding("central_difference", bool(ok), msg, float(dt), float(limit))


def check_explicit_rk(M: Any, K: Any, t_end: float, rtol: float = 1e-6, solver: str = "RK45",
                      omega: Any = None, ratio_limit: float = 10.0, C: Any = None) -> Finding:
    """Explicit Runge-Kutta on a stiff model: estimate the step-count explosion.

    An explicit solver must keep ``h |lambda|_max`` inside its stability region (about
    ``RK_IMAG_BOUND[solver]``; lightly damped poles lie next to the imaginary axis, overdamped ones
    on the negative real axis where the bound is similar) whatever the accuracy needs, so it takes
    at least ``t_end |lambda|_max / bound`` steps. ``|lambda|_max`` is ``omega_max`` without damping;
    with ``C`` it is the largest pole magnitude of the (modally projected) damped modes, which for
    an overdamped stiff mode is ``omega (zeta + sqrt(zeta^2 - 1))``. Accuracy alone would need about
    ``t_end omega_min / (2 pi) * 2 pi rtol^(-1/order) / 3`` steps (a few steps per period of the
    slowest mode at the tolerance). The ratio of the two is the explosion factor.

    Parameters
    ----------
    M, K : (n, n) array_like
        Mass and stiffness (SI).
    t_end : float
        Simulated time [s].
    rtol : float
        Relative tolerance of the solver.
    solver : {"RK23", "RK45", "DOP853"}
        Explicit solve_ivp method.
    omega : array_like or None
        Natural frequencies [rad/s], if known (ignored when ``C`` is given).
    ratio_limit : float
        Explosion factor above which the finding is not ok.
    C : (n, n) array_like or None
        Viscous damping [N s/m]; its modal diagonal sets the pole magnitude of overdamped modes.

    Returns
    -------
    Finding
        ``value`` = estimated explosion factor, ``limit`` = ``ratio_limit``; the message gives the
        stiffness ratio and both step counts.
    """
    if C is not None:
        Md, Kd, Cd = (np.asarray(x.toarray() if hasattr(x, "toarray") else x, float) for x in (M, K, C))
        spec = undamped(Kd, Md)
        w, phi = np.sqrt(spec.omega2), spec.phi
        cm = np.einsum("ij,ij->j", phi, Cd @ phi)                 # modal damping 2 zeta omega
        zeta = np.divide(cm, 2 * w, out=np.zeros_like(w), where=w > 0)
        radius = np.where(zeta > 1, w * (zeta + np.sqrt(np.maximum(zeta**2 - 1, 0.0))), w)
        radius = np.where(w > 0, radius, cm)                      # damped rigid mode: pole -c
    else:
        w = _omega(M, K, omega)
        radius = w
    el = w[w > 0]
    if el.size == 0:
        return Finding("explicit_rk", True, "no elastic modes", 1.0, ratio_limit)
    bound = RK_IMAG_BOUND.get(solver, 3.3)
    order = RK_ORDER.get(solver, 5)
    wmin, wmax = float(el.min()), float(radius.max())
    n_stab = t_end * wmax / bound
    n_acc = max(t_end * wmin * rtol ** (-1.0 / order) / 3.0, 1.0)
    ratio = n_stab / n_acc
    ok = ratio <= ratio_limit
    msg = (f"stiffness ratio |lambda|_max/omega_min = {wmax / wmin:.3g}; {solver} needs about "
           f"{n_stab:.3g} steps for stability against about {n_acc:.3g} for accuracy "
           f"(x{ratio:.3g})" + ("" if ok else ": the model is stiff for an explicit solver; use the "
                                 "exact modal method, or an implicit solver (Radau, BDF, LSODA)"))
    return Finding("explicit_rk", bool(ok), msg, float(ratio), float(ratio_limit),
                   {"stiffness_ratio": wmax / wmin, "steps_stability": n_stab, "steps_accuracy": n_acc,
                    "pole_radius_max": wmax, "omega_min": wmin})


def check_sampling(dt: float, *, pulses: Iterable[tuple[float, float]] = (),
                   breakpoints: Iterable[float] = (), f_max: float | None = None,
                   min_steps: float = 5.0, points_per_period: float = 10.0,
                   inserts_breakpoints: bool = False) -> list[Finding]:
    """Fixed-step sampling of the inputs: smeared pulse edges, aliased sweeps.

    Parameters
    ----------
    dt : float
        Sampling step [s].
    pulses : iterable of (start, duration)
        Pulses [s]; flagged when shorter than ``min_steps`` steps.
    breakpoints : iterable of float
        Times where an input jumps or kinks [s]; flagged when they fall between samples.
    f_max : float or None
        Highest input frequency [Hz] (e.g. the end of a sweep); flagged above the Nyquist
        frequency ``1 / (2 dt)`` (aliasing) and, as a loss of accuracy, above
        ``1 / (points_per_period dt)``.
    min_steps : float
        Fewest steps per pulse for a sampled method.
    points_per_period : float
        Samples per period for an accurate interpolation of a sine.
    inserts_breakpoints : bool
        True for methods that add the breakpoints to their grid (vibss's modal method, ivp): edges
        and short pulses are then exact, only ``f_max`` is checked.

    Returns
    -------
    list of Finding
        One per check made (``sampling_pulse``, ``sampling_edges``, ``sampling_frequency``).
    """
    out = []
    if not inserts_breakpoints:
        pulses = list(pulses)
        if pulses:
            shortest = min(d for _, d in pulses)
            ok = shortest >= min_steps * dt
            out.append(Finding("sampling_pulse", bool(ok),
                               f"shortest pulse {shortest:.3g} s = {shortest / dt:.3g} steps of {dt:.3g} s"
                               + ("" if ok else f" (< {min_steps:g}): the sampled pulse misses its "
                                  "shape and area; use the modal method (exact at the edges) or "
                                  f"dt <= {shortest / min_steps:.3g} s"), shortest / dt, min_steps))
        bp = np.asarray(list(breakpoints), float)
        bp = bp[bp > 0]
        if bp.size:
            off = np.abs(bp / dt - np.rint(bp / dt))
            between = int(np.sum(off > 1e-6))
            ok = between == 0
            out.append(Finding("sampling_edges", ok,
                               f"{between} of {bp.size} input edges fall between samples"
                               + ("" if ok else ": a sampled method interpolates each across a "
                                  "step (smeared edge, shifted timing); the modal method inserts "
                                  "them into its grid"), float(between), 0.0))
    if f_max is not None:
        nyq = 1.0 / (2.0 * dt)
        acc = 1.0 / (points_per_period * dt)
        ok = f_max <= acc
        if f_max > nyq:
            msg = (f"input frequency {f_max:.4g} Hz exceeds the Nyquist frequency {nyq:.4g} Hz of "
                   f"dt = {dt:.3g} s: the sampled input is aliased; use dt <= "
                   f"{1.0 / (points_per_period * f_max):.3g} s")
        else:
            msg = (f"input frequency {f_max:.4g} Hz, {1.0 / (f_max * dt) if f_max > 0 else np.inf:.3g} "
                   f"samples per period" + ("" if ok else f" (< {points_per_period:g}): the "
                                            "piecewise-linear interpolation of the sine loses accuracy"))
        out.append(Finding("sampling_frequency", bool(ok), msg, float(f_max), float(acc)))
    return out


def check_excitations(excitations: Sequence[Any], dt: float,
                      inserts_breakpoints: bool = False) -> list[Finding]:
    """:func:`check_sampling` for vibss excitations (pulses, sweeps, sines, tables).

    Parameters
    ----------
    excitations : sequence of Excitation (or of TimeFunction)
        Inputs of a simulation.
    dt : float
        Sampling step [s].
    inserts_breakpoints : bool
        As :func:`check_sampling`.
    """
    pulses, bps, fmax = [], [], None
    for e in excitations:
        fn = getattr(e, "function", e)
        parts = getattr(fn, "terms", None) or getattr(fn, "parts", None) or [fn]
        for f in parts:
            bps += list(getattr(f, "breakpoints", ()))
            if hasattr(f, "duration") and hasattr(f, "amplitude") and hasattr(f, "start"):
                pulses.append((float(f.start), float(f.duration)))
            for key in ("f2", "f1", "frequency"):
                v = getattr(f, key, None)
                if isinstance(v, (int, float)):
                    fmax = max(fmax or 0.0, float(v))
    return check_sampling(dt, pulses=pulses, breakpoints=bps, f_max=fmax,
                          inserts_breakpoints=inserts_breakpoints)


def equilibrate(A: Any) -> tuple[np.ndarray, np.ndarray]:
    """Symmetric diagonal scaling ``D A D`` with ``D = diag(A)^-1/2`` (unit diagonal).

    Parameters
    ----------
    A : (n, n) array_like
        Symmetric matrix with a non-negative diagonal.

    Returns
    -------
    scaled : (n, n) ndarray
    d : (n,) ndarray
        The scale factors (1 where the diagonal is zero).
    """
    A = A.toarray() if hasattr(A, "toarray") else np.asarray(A, float)
    diag = np.diag(A)
    d = 1.0 / np.sqrt(np.where(diag > 0, diag, 1.0))
    return d[:, None] * A * d[None, :], d


def _cond(A: np.ndarray) -> float:
    s = np.linalg.svd(A, compute_uv=False)
    return float(s[0] / s[-1]) if s[-1] > 0 else np.inf


@dataclass(frozen=True)
class Conditioning:
    """2-norm condition numbers before and after equilibration.

    Attributes
    ----------
    cond_M, cond_K : float
        Of M and K as given (user units).
    cond_M_eq, cond_K_eq : float
        Of ``D M D`` and ``D K D`` with ``D = diag(.)^-1/2`` (invariant to the choice of units).
    finding : Finding
        Not ok when equilibration leaves K or M close to singular in double precision.
    """

    cond_M: float
    cond_K: float
    cond_M_eq: float
    cond_K_eq: float
    finding: Finding


def conditioning(M: Any, K: Any, limit: float = 1e12) -> Conditioning:
    """Condition numbers of M and K in the given units and after equilibration.

    A change of units (mm for m, g for kg, per DOF) is ``S M S`` and ``S K S`` with diagonal S: it
    changes the raw condition numbers by up to ``(max S / min S)^2`` but not the equilibrated ones,
    nor vibss's results (frequencies, responses in SI), which are computed on equilibrated or
    mass-normalised forms.

    Parameters
    ----------
    M, K : (n, n) array_like
        Mass and stiffness in any consistent units.
    limit : float
        Equilibrated condition number above which results lose digits visibly (``eps * cond``).

    Returns
    -------
    Conditioning
    """
    M = M.toarray() if hasattr(M, "toarray") else np.asarray(M, float)
    K = K.toarray() if hasattr(K, "toarray") else np.asarray(K, float)
    cm, ck = _cond(M), _cond(K)
    cme, cke = _cond(equilibrate(M)[0]), _cond(equilibrate(K)[0])
    ok = cke < limit and cme < limit
    msg = (f"cond(M) = {cm:.3g}, cond(K) = {ck:.3g} as given; after equilibration {cme:.3g}, "
           f"{cke:.3g}" + (f" (about {np.finfo(float).eps * max(cke, cme):.1g} relative error to "
                           "expect)" if np.isfinite(max(cke, cme)) else "")
           + ("" if ok else ": ill-conditioned even after scaling; look for very stiff elements "
              "(lever-arm links) or nearly free motions"))
    return Conditioning(cm, ck, cme, cke, Finding("conditioning", bool(ok), msg, max(cke, cme), limit))


def check_static(K: Any, dofs: Sequence[str] | None = None, rcond: float = 1e-12) -> Finding:
    """A (nearly) singular stiffness: which motion is (almost) free.

    Parameters
    ----------
    K : (n, n) array_like
        Stiffness of the free DOFs [N/m, N m/rad].
    dofs : sequence of str or None
        DOF labels (``'engine.z'``) to name the motion.
    rcond : float
        Smallest eigenvalue of the equilibrated K, relative to the largest, for a restrained system.

    Returns
    -------
    Finding
        ``value`` = smallest relative eigenvalue; the message names the dominant DOFs of its vector.
    """
    ks, d = equilibrate(K)
    w, v = symmetric_eigen(ks)
    rel = float(w[0] / w[-1]) if w[-1] > 0 else 0.0
    ok = rel > rcond
    vec = d * v[:, 0]
    vec = vec / np.abs(vec).max()
    names = list(dofs) if dofs is not None else [f"dof {i}" for i in range(len(vec))]
    main = [f"{names[i]} {vec[i]:+.2f}" for i in np.argsort(-np.abs(vec))[:3] if abs(vec[i]) > 0.1]
    msg = (f"smallest equilibrated stiffness eigenvalue {rel:.2g} of the largest"
           + (f"; nearly free motion: {', '.join(main)}" if not ok else ""))
    return Finding("static", bool(ok), msg, rel, rcond)


def repeated_frequencies(omega: Any, rtol: float = 1e-6) -> list[np.ndarray]:
    """Groups of (nearly) equal natural frequencies.

    Parameters
    ----------
    omega : (n,) array_like
        Natural frequencies, ascending [rad/s].
    rtol : float
        Relative gap below which neighbours belong to one group.

    Returns
    -------
    list of (k,) int ndarray
        Indices of each group with k >= 2 elastic modes.
    """
    w = np.asarray(omega, float)
    first = int(np.searchsorted(w, 0.0, side="right"))          # skip the zero (rigid) modes
    return [np.arange(g.start, g.stop) + first for g in cluster_slices(w[first:], rtol, 0.0)]


def check_repeated(omega: Any, rtol: float = 1e-6) -> Finding:
    """Finding for :func:`repeated_frequencies` (not ok: shapes within a group are not unique).

    Parameters
    ----------
    omega : (n,) array_like
        Natural frequencies, ascending [rad/s].
    rtol : float
        Relative gap below which neighbours belong to one group.

    Returns
    -------
    Finding
        ``value`` = number of groups.
    """
    groups = repeated_frequencies(omega, rtol)
    w = np.asarray(omega, float)
    if not groups:
        return Finding("repeated_frequencies", True, "no repeated frequencies", 0.0, 1.0)
    desc = ", ".join(f"{w[g[0]] / (2 * np.pi):.5g} Hz x{len(g)}" for g in groups)
    return Finding("repeated_frequencies", False,
                   f"repeated frequencies {desc}: any combination of their shapes is a mode; "
                   "vibss aligns each group with the global directions", float(len(groups)), 0.0)


def check_damping_resolution(M: Any, K: Any, C: Any, zeta_tol: float = 1e-3) -> Finding:
    """Whether damping ratios survive an eigen-decomposition of the physical state matrix.

    ``eig`` of ``A = [[0, I], [-M^-1 K, -M^-1 C]]`` has absolute pole errors about
    ``eps ||A||``; a mode's ``zeta`` is ``-Re(p) / |p|``, so its relative error is about
    ``eps ||A|| / (zeta omega)``. (vibss's :func:`vibss.damped_modes` works on the modal form
    and does not have this error.)

    Parameters
    ----------
    M, K, C : (n, n) array_like
        Mass, stiffness, damping (SI).
    zeta_tol : float
        Acceptable relative error of zeta.

    Returns
    -------
    Finding
        ``value`` = predicted worst relative zeta error of ``eig(A)``.
    """
    M, K, C = (np.asarray(x.toarray() if hasattr(x, "toarray") else x, float) for x in (M, K, C))
    spec = undamped(K, M)
    w2, phi = spec.omega2, spec.phi
    keep = ~spec.rigid
    w = np.sqrt(w2[keep])
    zeta = np.diag(phi.T @ C @ phi)[keep] / (2 * w)
    solve = mass_solver(M)
    norm_a = max(1.0, np.abs(solve(K)).sum(0).max(), np.abs(solve(C)).sum(0).max())
    with np.errstate(divide="ignore"):
        err = np.finfo(float).eps * norm_a / (np.abs(zeta) * w)
    worst = float(err.max()) if err.size else 0.0
    ok = worst <= zeta_tol
    msg = (f"predicted relative damping-ratio error of eig(A) up to {worst:.2g} (||A||_1 = "
           f"{norm_a:.3g}, smallest zeta*omega = {float((np.abs(zeta) * w).min()):.3g} 1/s)"
           + ("" if ok else ": lightly damped modes lose their damping in eig of the physical "
              "state matrix; use vibss.damped_modes (modal form)"))
    return Finding("damping_resolution", bool(ok), msg, worst, zeta_tol)


def blas_threads() -> str:
    """One line per BLAS/OpenMP thread pool in use: library, API, version, number of threads."""
    rows = [f"{i.get('internal_api', '?')} {i.get('version', '?')} ({i.get('user_api', '?')}): "
            f"{i.get('num_threads', '?')} threads" for i in threadpool_info()]
    return "; ".join(rows) if rows else "no BLAS thread pool detected"
