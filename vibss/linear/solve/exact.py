"""The one exact solve of a plant: ``(K + iH + sC + s^2 M) X = R`` for a batch of Laplace values ``s``.

Frequency-dependent mounts add ``sum_tau tau s / (1 + tau s) K_tau`` to the matrix (and their
terms to the inputs and outputs): their Maxwell branches eliminated exactly
(:func:`vibss.linear.plant.branches.groups`); every back-end takes them.

Every path that claims an *exact* response (the ``direct`` and ``sparse`` FRF kernels, pruning,
Krylov checks, the sweep envelope's steady state, reduction responses) goes through
:func:`response` (outputs) or :func:`states` (the DOF solution). They share three rules:

- **the** ``s^-order`` **rule** (:func:`zfactor`): a motion input ``u`` of order 0, 1, 2 (displacement,
  velocity, acceleration) prescribes ``z = u / s^order``; a force input enters as it is;
- **one 0 Hz limit** (:func:`zero_frequency_limit`): at ``s = 0`` the value is the limit
  ``w -> 0+``: finite where it exists (the static deflection, a transmissibility of 1), ``inf`` where
  the response diverges (a rigid-body mode under a force, a displacement under a constant velocity);
- **one policy at singular frequencies**: where ``A(s) = K + iH + sC + s^2 M`` is exactly singular
  (an undamped model exactly at a natural frequency) an output/input pair is ``inf`` only when the
  resonant mode is both seen by the output and driven by the input; every other pair keeps its
  finite limit ``s -> s0`` (:func:`_at_singular`).

Three back-ends solve the same equations (``backend=``):

- ``"dense"``: batched LAPACK LU (``numpy.linalg.solve`` on a stack of frequencies); a plant of 12 to
  30 DOFs asked for many frequencies on the imaginary axis takes its complex-mode solutions where
  their backward error, checked at every frequency, is at most ``n eps`` (:mod:`vibss.linear.solve.certified`);
- ``"banded"``: reverse Cuthill-McKee ordering + LAPACK ``zgbsv`` (:mod:`vibss.linear.solve.banded`), O(n b^2);
- ``"superlu"``: :func:`scipy.sparse.linalg.splu` per frequency;
- ``"sparse"``: ``"banded"`` or ``"superlu"`` by the structure (half-bandwidth <= ``BAND_MAX``);
- ``"auto"``: ``"dense"`` for dense plants up to :data:`DENSE_MAX` DOFs or whose pattern is
  :data:`DENSE_FILL` full, else ``"sparse"``.

All are LU with partial pivoting on the assembled matrices, backward stable for ``A(s)``. On models
with stiffness ratios of 1e5 and more that is not enough: the entries of ``K`` themselves carry
round-off of the stiffest mount they hold, and the soft modes are sensitive to it (measured against
a 60-digit reference: 2.6e-3 relative error on a graded chain, 1e-3 on two bodies joined by 1e16 N/m
links, whatever the LU or a diagonal scaling of ``A``). ``form="mounts"`` (chosen by ``"auto"`` above
:data:`MOUNTS_RATIO`) keeps the mounts apart (:class:`~vibss.linear.plant.plant.MountForm`) and solves for
their forces too: 1e-12 ... 1e-16 on the same cases (:func:`_mounts`); a large plant's assembled LU
refined with the residual computed mount by mount instead (:mod:`vibss.linear.solve.refine`).
"""

# Over 600 lines on purpose (issue 28): the one exact solve's entry points (states, response, the
# zero-frequency limit, singular frequencies) and the form/back-end choice they share; the back-ends
# themselves live in backends.py.

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np
import scipy.linalg as sl
import scipy.sparse as sp
import scipy.sparse.linalg as spl

from ...costs import constant
from ...errors import AnalysisError, ModelError
from .backends import SOLVERS
from .banded import structure
from ..plant.branches import groups
from ..eigen.basis import modal_basis
from ..plant.plant import Plant
from ..plant.terms import plant_terms

__all__ = ["BACKENDS", "FORMS", "MOUNTS_RATIO", "DENSE_MAX", "DENSE_FILL", "zfactor", "states", "response", "zero_frequency_limit",
           "lu_solver", "statespace_plant", "without_hysteresis", "SingularMatrixError", "forcing", "mounts_form_possible",
           "observe", "observed_dofs", "output_map", "output_columns"]

BACKENDS = ("auto", "dense", "sparse", "banded", "superlu")
"""Names accepted by ``backend=``."""

DENSE_MAX = 300
"""``backend="auto"``: dense plants up to this many DOFs are solved by the batched dense LU."""

_K_DENSE = constant("frequency.K_DENSE_LU", 3e-10)
"""[s] per n^3 of one complex dense LU and solve (the frequency methods' cost model's constant)."""

DENSE_FILL = 0.2
"""``backend="auto"``: a dense plant above :data:`DENSE_MAX` DOFs takes the batched dense LU too when
the nonzero pattern of its matrices fills at least this fraction of n x n (a plant projected on a
basis, whose ``C`` and ``H`` are full: the channel subspace's reduced plants in Ritz coordinates):
a sparse LU fills such a pattern in to dense and pays its overhead on every entry (subspace of a
200-body grid, 160-656 vectors, 200 frequencies: 33 s of reduced solves by SuperLU). A plant
assembled from mounts fills a few per cent at 300 DOF and less above, and stays sparse."""

FORMS = ("auto", "assembled", "mounts")
"""Names accepted by ``form=``: the assembled ``K, C, H``, or the sum over mounts (:class:`MountForm`)."""

MOUNTS_RATIO = 1e3
"""``form="auto"`` solves in the mounts' forces when their stiffness ratio exceeds this."""

POLE_DELTA = 1e-6
"""Relative offset ``s0 (1 +- delta)`` at which a singular frequency's finite limit is evaluated."""

NULL_RTOL = 1e-8
"""A resonant mode counts as seen (driven) when ``|O v|`` (``|u^H R|``) exceeds this fraction of
``|O| |v|`` (``|u| |R|``)."""



class SingularMatrixError(AnalysisError):
    """A matrix to factorise is exactly singular (a zero pivot)."""


def zfactor(s: np.ndarray, order: np.ndarray) -> np.ndarray:
    """The ``s^-order`` rule: ``z / u`` of each input at each ``s`` (1 for forces and displacements).

    Parameters
    ----------
    s : (nf,) complex array_like
        Laplace values [rad/s].
    order : (m,) int array_like
        :attr:`Plant.order` (-1 force, 0 displacement, 1 velocity, 2 acceleration).

    Returns
    -------
    (nf, m) complex ndarray
        ``s^-order`` (``inf`` at ``s = 0`` for velocity and acceleration inputs).

    Examples
    --------
    >>> zfactor(np.array([2j]), np.array([-1, 0, 1, 2]))
    array([[ 1.  +0.j ,  1.  +0.j ,  0.  -0.5j, -0.25-0.j ]])
    """
    s = np.atleast_1d(np.asarray(s, dtype=complex))
    order = np.asarray(order)
    if not np.any(order > 0):       # forces and displacements: ones, as np.where would give them
        return np.ones((s.size, order.size), dtype=complex)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(order[None, :] > 0, s[:, None] ** (-np.maximum(order, 0))[None, :], 1.0 + 0j)


def _hyst(a: np.ndarray | None) -> Any:
    return 0.0 if a is None or not np.any(a) else a


def forcing(plant: Plant, s: np.ndarray, zf: np.ndarray) -> np.ndarray:
    """Right-hand sides ``F - (Kz + iHz + s Cz + s^2 Mz + sum g_tau(s) Kz_tau) Z(s)`` of the inputs
    (``Kz_tau``: frequency-dependent mounts, :func:`vibss.linear.plant.branches.groups`).

    Parameters
    ----------
    plant : Plant
    s : (nf,) complex ndarray
        Laplace values [rad/s].
    zf : (nf, m) complex ndarray
        :func:`zfactor` at ``s``.

    Returns
    -------
    (nf, n, m) complex ndarray
        Generalised forces per unit input [N, N m].
    """
    motion = plant_terms(plant).motion
    sc = s[:, None, None]
    relax = [g for g in groups(plant) if np.any(g.Kz)]
    f = plant_terms(plant).forces[None]
    if not motion and not relax:          # force inputs only: one read-only view for every s
        return np.broadcast_to(f, (s.size,) + plant.F.shape)
    out = np.broadcast_to(f, (s.size,) + plant.F.shape).copy()
    for power, c in motion:
        out -= (sc**power) * c[None] * zf[:, None, :]
    for g in relax:                       # frequency-dependent mounts' branches
        out -= g.factor(s)[:, None, None] * g.Kz[None] * zf[:, None, :]
    return out


def output_map(plant: Plant, s: complex) -> np.ndarray:
    """(p, n) ``O(s) = Oq + i Oh + s Ov + s^2 Oa (+ sum g_tau(s) Oq_tau)`` at one Laplace value ``s`` [rad/s]."""
    out = plant.Oq + 1j * _hyst(plant.Oh) + s * plant.Ov + s**2 * plant.Oa
    for g in groups(plant):
        out = out + g.factor(np.array(s)) * g.Oq
    return out


def output_columns(plant: Plant, s: np.ndarray, phi: np.ndarray) -> np.ndarray:
    """(p, k) ``O(s_k) phi_k`` for each column of ``phi`` (n, k) at its own Laplace value ``s_k``
    [rad/s] (:func:`output_map`, one product per term instead of a map per column)."""
    s = np.asarray(s, dtype=complex)
    out = np.asarray(plant.Oq @ phi, dtype=complex)
    if np.any(oh := _hyst(plant.Oh)):
        out = out + 1j * (oh @ phi)
    if np.any(plant.Ov):
        out = out + (plant.Ov @ phi) * s[None, :]
    if np.any(plant.Oa):
        out = out + (plant.Oa @ phi) * (s * s)[None, :]
    for g in groups(plant):
        out = out + (g.Oq @ phi) * g.factor(s)[None, :]
    return out


def observed_dofs(plant: Plant) -> np.ndarray:
    """(q,) sorted DOFs that some output reads (a nonzero column of ``Oq, Oh, Ov, Oa`` or of a
    branch group's ``Oq``): the rows of the solution that :func:`observe` needs."""
    cols = [plant.Oq, _hyst(plant.Oh), plant.Ov, plant.Oa] + [g.Oq for g in groups(plant)]
    used = np.zeros(plant.n, dtype=bool)
    for o in cols:
        if sp.issparse(o):
            used |= np.asarray(abs(o).sum(axis=0)).ravel() > 0
        elif np.ndim(o) == 2:
            used |= np.any(np.asarray(o) != 0, axis=0)
    return np.flatnonzero(used)


def observe(plant: Plant, s: np.ndarray, x: np.ndarray, zf: np.ndarray,
            rows: np.ndarray | None = None) -> np.ndarray:
    """Outputs ``O(s) X + P(s) Z(s) + Pf`` from DOF solutions.

    Parameters
    ----------
    plant : Plant
    s : (nf,) complex ndarray
        Laplace values [rad/s].
    x : (nf, n, m) complex ndarray
        DOF solutions per unit input (:func:`states`); (nf, q, m) with ``rows``.
    zf : (nf, m) complex ndarray
        :func:`zfactor` at ``s``.
    rows : (q,) int ndarray or None
        The DOFs that ``x`` holds (at least :func:`observed_dofs`); None: all of them.

    Returns
    -------
    (nf, p, m) complex ndarray
    """
    def cut(o: np.ndarray) -> np.ndarray:
        return o if rows is None else o[:, rows]

    terms = plant_terms(plant)
    sc = s[:, None, None]
    y = np.zeros((s.size, len(plant.outputs), x.shape[2]), dtype=complex)
    for power, o in terms.outputs:
        y += (sc**power) * (cut(o) @ x) if power else cut(o) @ x
    if terms.feedthrough:
        y += (terms.p0[None] + sc * plant.Pv[None] + sc**2 * plant.Pa[None]) * zf[:, None, :]
    for g in groups(plant):               # the branch forces seen by mount and ground force outputs
        if np.any(g.Oq) or np.any(g.Pz):
            y += g.factor(s)[:, None, None] * (cut(g.Oq) @ x + g.Pz[None] * zf[:, None, :])
    return y + plant.Pf[None]


def _filled(plant: Plant) -> bool:
    """Whether a dense plant's ``K, C, M, H`` (and branch stiffnesses) together fill at least
    :data:`DENSE_FILL` of the n x n pattern."""
    def fill() -> float:
        mats = [plant.K, plant.C, plant.M, plant.H] + [g.K for g in groups(plant)]
        hit = np.zeros((plant.n, plant.n), dtype=bool)
        for a in mats:
            hit |= np.asarray(a) != 0
        return float(np.count_nonzero(hit)) / max(plant.n, 1) ** 2
    return bool(plant.cached("pattern fill", fill) >= DENSE_FILL)


def _pick(plant: Plant, backend: str) -> str:
    if backend not in BACKENDS:
        raise ModelError(f"backend: expected one of {list(BACKENDS)}, got {backend!r}")
    if backend == "auto":
        backend = "dense" if not sp.issparse(plant.K) and (plant.n <= DENSE_MAX or _filled(plant)) else "sparse"
        st = plant.known("band structure")
        if backend == "dense" and st is not None and st.banded and st.seconds_per_frequency < _K_DENSE * plant.n ** 3:
            # a band already found (a cost model asked for it): cheaper than the dense LU from some
            # tens of DOFs on (150-DOF chain, 18 frequencies: 2.2 ms against 10.4 ms)
            backend = "banded"
    if backend == "sparse":
        st = plant.cached("band structure", lambda: structure(plant))
        backend = "banded" if st.banded else "superlu"
    return backend


def _use_mounts(plant: Plant, form: str) -> bool:
    if form not in FORMS:
        raise ModelError(f"form: expected one of {list(FORMS)}, got {form!r}")
    mf = plant.mounts
    if plant.branches is not None:            # the mounts' form holds no branches
        if form == "mounts":
            raise ModelError("form: 'mounts' does not hold the branches of frequency-dependent mounts "
                             f"{list(plant.branches.mounts)}; use 'assembled' or 'auto'")
        return False
    if mf is None or not mf.matches(plant):
        if form == "mounts":
            raise ModelError("form: 'mounts' needs a plant built by build_plant whose K, C, H are its own "
                             "(this one has none, or was derived with new matrices)")
        return False
    return form == "mounts" or (form == "auto" and mf.stiffness_ratio > MOUNTS_RATIO)


def states(plant: Plant, s: np.ndarray, rhs: np.ndarray | None = None,
           backend: str = "auto", form: str = "auto",
           rows: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """DOF solutions ``X(s) = A(s)^-1 R`` of ``A(s) = K + iH + sC + s^2 M`` at each ``s``.

    Parameters
    ----------
    plant : Plant
        Dense or scipy.sparse ``K, C, M, H``.
    s : (nf,) complex array_like
        Laplace values [rad/s].
    rhs : (n, k) or (nf, n, k) array_like or None
        Right-hand sides; default the plant's inputs, ``F - (Kz + iHz + s Cz + s^2 Mz) s^-order``
        (:func:`zfactor`).
    backend : str
        One of :data:`BACKENDS` (for the assembled form).
    form : str
        One of :data:`FORMS`: ``"auto"`` solves in the mounts' forces when the plant carries
        its :class:`~vibss.linear.plant.plant.MountForm` and their stiffness ratio exceeds
        :data:`MOUNTS_RATIO`, or, for a model with a free motion, at frequencies where inertia
        alone would not hold it against the assembled ``K``'s round-off (:func:`_mounts_at`); else
        the assembled matrices with ``backend``.
    rows : (q,) int array_like or None
        The DOFs to return of each solution (the outputs' DOFs, :func:`observed_dofs`); None: all.

    Returns
    -------
    x : (nf, n, k) complex ndarray
        Solutions (zeros where singular); (nf, q, k) with ``rows``.
    singular : (nf,) bool ndarray
        Where ``A(s)`` is exactly singular (a zero pivot).

    Examples
    --------
    >>> from ... import Body, Model, Mount, MountType
    >>> from ..plant.build import build_plant
    >>> m = Model([Body("b", 1.0, [1, 1, 1])], [Mount("m", MountType("t", [1e4, 1e4, 1e4]), "b")])
    >>> x, bad = states(build_plant(m, ["b.fz"], ["b.z"]), [50j, 100j])
    >>> float(x[0, 2, 0].real) * 7500, bool(bad[1])     # 1 / (k - m w^2); singular at w_n = 100 rad/s
    (1.0, True)
    """
    s = np.atleast_1d(np.asarray(s, dtype=complex))
    if rhs is None:
        r_full = forcing(plant, s, zfactor(s, plant.order))
        def get(part: slice | np.ndarray) -> np.ndarray:
            return r_full[part]
    else:
        r = np.asarray(rhs, dtype=complex)
        def get(part: slice | np.ndarray) -> np.ndarray:
            return r[part] if r.ndim == 3 else np.broadcast_to(r, (len(s[part]),) + r.shape).copy()
    keep = None if rows is None else np.asarray(rows, dtype=int)
    name = _pick(plant, backend)
    apart = _mounts_at(plant, form, s)
    if apart is None or not apart.any():
        return SOLVERS[name](plant, s, get, keep)
    if apart.all():
        return SOLVERS["mounts"](plant, s, get, keep)
    x, bad = None, np.zeros(s.size, dtype=bool)
    for which, solver in ((apart, "mounts"), (~apart, name)):       # each frequency in its own form
        idx = np.flatnonzero(which)

        def part_of(part: slice, idx: np.ndarray = idx) -> np.ndarray:
            return get(idx[part])
        xi, bad[idx] = SOLVERS[solver](plant, s[idx], part_of, keep)
        if x is None:
            x = np.zeros((s.size,) + xi.shape[1:], dtype=complex)
        x[idx] = xi
    assert x is not None
    return x, bad


def _mounts_at(plant: Plant, form: str, s: np.ndarray) -> np.ndarray | None:
    """(nf,) bool: where ``form`` (one of :data:`FORMS`) solves in the mounts' forces at each ``s``;
    None for nowhere without a test per frequency.

    ``"auto"``: everywhere when the stiffness ratio exceeds :data:`MOUNTS_RATIO` (:func:`_use_mounts`);
    else, when the mounts leave a motion free, below the frequency where the stiffest mount's
    round-off in the assembled ``K`` would swamp the inertia holding that motion:
    ``|s|^2 MOUNTS_RATIO < inertia_w2`` (:attr:`~vibss.linear.plant.plant.MountForm.inertia_w2`). An undamped
    resonance of such a model above that frequency keeps the assembled form's exact-singularity
    detection (:func:`_at_singular`).
    """
    if _use_mounts(plant, form):
        return np.ones(s.size, dtype=bool)
    mf = plant.mounts
    if form != "auto" or mf is None or plant.branches is not None or not mf.matches(plant) or mf.inertia_w2 <= 0:
        return None
    return np.abs(s) ** 2 * MOUNTS_RATIO < mf.inertia_w2


def mounts_form_possible(plant: Plant, form: str = "auto") -> bool:
    """Whether ``form`` (one of :data:`FORMS`) solves some frequency of ``plant`` in the mounts' forces
    (everywhere, or below a frequency: :func:`_mounts_at`), so that not every answer comes from the
    assembled back-ends."""
    return _mounts_at(plant, form, np.zeros(0)) is not None


def _plain(plant: Plant, s: np.ndarray, backend: str, form: str = "auto") -> tuple[np.ndarray, np.ndarray]:
    """(nf, p, m) response by the plain solve, and where ``A(s)`` is singular (values there: 0)."""
    zf = zfactor(s, plant.order)         # once for the right-hand sides and the outputs
    rows = plant.cached("observed dofs", lambda: observed_dofs(plant))   # the solutions' rows the outputs read
    x, bad = states(plant, s, rhs=forcing(plant, s, zf), backend=backend, form=form, rows=rows)
    return observe(plant, s, x, zf, rows), bad


def response(plant: Plant, s: np.ndarray, backend: str = "auto", form: str = "auto") -> np.ndarray:
    """Exact response ``Y(s)`` of a plant at Laplace values ``s``; returns (p, m, nf) complex.

    ``Y = O(s) X + P(s) Z + Pf`` with ``A(s) X = F - (Kz + iHz + s Cz + s^2 Mz) Z``,
    ``Z = diag(s^-order)`` (module docstring). At ``s = 0`` the value is the 0 Hz limit
    (:func:`zero_frequency_limit`); where ``A(s)`` is exactly singular, ``inf`` only where the
    resonant mode is seen and driven.

    Parameters
    ----------
    plant : Plant
    s : (nf,) complex array_like
        Laplace values [rad/s] (``i w`` on the frequency axis).
    backend : str
        One of :data:`BACKENDS`.
    form : str
        One of :data:`FORMS` (see :func:`states`).

    Returns
    -------
    (p, m, nf) complex ndarray
        Outputs (their SI units) per unit input.

    Examples
    --------
    An undamped 1 kg / 1e4 N/m body: the static deflection at 0 Hz, an unbounded response exactly
    at 100 rad/s, and the closed form ``1 / (k - m w^2)`` elsewhere:

    >>> from ... import Body, Model, Mount, MountType
    >>> from ..plant.build import build_plant
    >>> m = Model([Body("b", 1.0, [1, 1, 1])], [Mount("m", MountType("t", [1e4, 1e4, 1e4]), "b")])
    >>> y = response(build_plant(m, ["b.fz"], ["b.z"]), [0j, 100j, 200j])[0, 0]
    >>> y.real.round(8).tolist()
    [0.0001, inf, -3.333e-05]
    """
    s = np.atleast_1d(np.asarray(s, dtype=complex))
    zero = s == 0
    if s.size and not zero.any():            # no 0 Hz (every frequency response): no masked copy
        y, bad = _plain(plant, s, backend, form)
        for k in np.flatnonzero(bad):
            y[k] = _at_singular(plant, complex(s[k]), backend, form)
        return y.transpose(1, 2, 0)
    out = np.zeros((s.size, len(plant.outputs), len(plant.inputs)), dtype=complex)
    if np.any(~zero):
        y, bad = _plain(plant, s[~zero], backend, form)
        for k in np.flatnonzero(bad):
            y[k] = _at_singular(plant, complex(s[~zero][k]), backend, form)
        out[~zero] = y
    if np.any(zero):
        out[zero] = zero_frequency_limit(plant, backend=backend, form=form)[None]
    return np.moveaxis(out, 0, -1)


def _dense_matrix(plant: Plant, s0: complex, derivative: bool = False) -> np.ndarray:
    """Dense ``A(s0) = K + iH + s0 C + s0^2 M``, or its derivative ``C + 2 s0 M``."""
    d = {k: (getattr(plant, k).toarray() if sp.issparse(getattr(plant, k)) else np.asarray(getattr(plant, k)))
         for k in ("K", "H", "C", "M")}
    extra = sum((g.factor(np.array(s0), derivative) * (g.K.toarray() if sp.issparse(g.K) else g.K)
                 for g in groups(plant)), np.zeros_like(d["K"], dtype=complex))
    if derivative:
        return d["C"] + 2 * s0 * d["M"] + extra
    return d["K"] + 1j * d["H"] + s0 * d["C"] + s0**2 * d["M"] + extra


def _at_singular(plant: Plant, s0: complex, backend: str, form: str = "auto") -> np.ndarray:
    """(p, m) response at an ``s0 != 0`` where ``A(s0)`` is exactly singular.

    The null vectors ``V`` (right) and ``U`` (left) of ``A(s0)`` come from its SVD: the resonant
    modes. A pair (output i, input j) is ``inf`` when the pole's residue
    ``O(s0) V (U^H A'(s0) V)^-1 U^H R`` is nonzero there (the output sees a mode the input drives;
    exact for repeated frequencies, whose null space SVD mixes arbitrarily); every other pair is the
    finite limit, evaluated as the mean of the responses at ``s0 (1 +- POLE_DELTA)`` (the pole's
    part changes sign across ``s0``, the regular part does not; error ``O(delta^2)``).
    """
    a = _dense_matrix(plant, s0)
    u, sig, vh = np.linalg.svd(a)
    null = sig <= max(sig[0], np.finfo(float).tiny) * a.shape[0] * np.finfo(float).eps
    v, ul = vh[null].conj().T, u[:, null]
    zf = zfactor(np.array([s0]), plant.order)
    r = forcing(plant, np.array([s0]), zf)[0]
    o0 = output_map(plant, s0)
    drive = ul.conj().T @ r
    tiny = np.finfo(float).tiny
    d1 = ul.conj().T @ _dense_matrix(plant, s0, derivative=True) @ v   # U^H A'(s0) V
    try:                                   # a simple pole: residue O V (U^H A' V)^-1 U^H R
        g = np.linalg.inv(d1)
        res = np.abs((o0 @ v) @ g @ drive)
        scale = np.outer(np.linalg.norm(o0, axis=1), np.linalg.norm(r, axis=0)) * np.linalg.norm(g, 2)
        unbounded = res > NULL_RTOL * (scale + tiny)
    except np.linalg.LinAlgError:          # a higher-order pole: seen and driven at all
        seen = np.linalg.norm(o0 @ v, axis=1) > NULL_RTOL * (np.linalg.norm(o0, axis=1) + tiny)
        driven = np.linalg.norm(drive, axis=0) > NULL_RTOL * (np.linalg.norm(r, axis=0) + tiny)
        unbounded = seen[:, None] & driven[None, :]
    pair = np.array([s0 * (1 + POLE_DELTA), s0 * (1 - POLE_DELTA)])
    y, bad = _plain(plant, pair, backend, form)
    regular = 0.5 * (y[0] + y[1]) if not bad.any() else np.full_like(y[0], np.nan)
    return np.where(unbounded, complex(np.inf, 0.0), regular)


def zero_frequency_limit(plant: Plant, power: int = 0, n_points: int = 32, backend: str = "auto",
                         form: str = "auto") -> np.ndarray:
    """The limit ``w -> 0+`` of ``s^power Y(s)`` (p, m): finite values, or ``inf`` where it diverges.

    Where every input is a force or a displacement and ``K + iH`` is regular, this is the solve at
    ``s = 0`` itself (the static deflection; ``s^power Y -> 0`` for ``power > 0``). Otherwise it
    comes from the Laurent series of the exact response about ``s = 0`` (trapezoidal rule on two
    small circles of radius a twentieth of the lowest elastic frequency of
    :func:`vibss.linear.eigen.basis.modal_basis`; ``i H`` is held at its ``w > 0`` value), so rigid-body
    modes, velocity and acceleration inputs and mobility/accelerance are all handled exactly.

    Parameters
    ----------
    plant : Plant
    power : int
        Extra factor ``s^power`` (1 mobility, 2 accelerance).
    n_points : int
        Points per circle.
    backend : str
        One of :data:`BACKENDS`.
    form : str
        One of :data:`FORMS` (see :func:`states`).

    Returns
    -------
    (p, m) complex ndarray
        ``complex(inf, 0)`` where the response is unbounded at 0 Hz (e.g. a displacement output
        of a constant-velocity input, or receptance of an unrestrained rigid-body motion).

    Examples
    --------
    >>> from ... import Body, Model, Mount, MountType
    >>> from ..plant.build import build_plant
    >>> m = Model([Body("b", 1.0, [1, 1, 1])], [Mount("m", MountType("t", [1e4, 1e4, 1e4]), "b")])
    >>> zero_frequency_limit(build_plant(m, ["b.fz", "ground.z.vel"], ["b.z"])).real.round(8).tolist()
    [[0.0001, inf]]
    """
    if np.all(plant.order <= 0):             # forces and displacements: A(0) itself, when regular
        y, bad = _plain(plant, np.zeros(1, dtype=complex), backend, _static_form(plant, form))
        if not bad[0]:
            return y[0] if power == 0 else np.zeros_like(y[0])
    dense = plant if not (sp.issparse(plant.K) or sp.issparse(plant.M)) else replace(
        plant, **{key: sp.csr_matrix(getattr(plant, key)).toarray() for key in ("K", "C", "M", "H")})
    basis = modal_basis(dense)
    elastic = basis.omega2[~basis.rigid]
    rho0 = 0.05 * (float(np.sqrt(elastic.min())) if elastic.size else 1.0)
    theta = 2 * np.pi * (np.arange(n_points) + 0.5) / n_points

    def laurent(r: float) -> tuple[np.ndarray, np.ndarray]:
        z = r * np.exp(1j * theta)
        y, bad = _plain(plant, z, backend, form)
        if bad.any():
            raise AnalysisError("the 0 Hz limit: the dynamic matrix is singular on the sampling circle")
        t = np.moveaxis(y, 0, -1) * z[None, None, :] ** power         # (p, m, N)
        coef = {k: np.mean(t * z[None, None, :] ** (-k), axis=-1) for k in range(-4, 1)}
        sing = sum(np.abs(coef[k]) * r**k for k in range(-4, 0))
        big = np.abs(t).max(axis=-1)
        return np.where(sing > 1e-6 * big, complex(np.inf, 0.0), coef[0]), big

    for shrink in (1.0, 1e-1, 1e-2, 1e-3):   # a heavily damped (slow) pole may need a smaller circle
        (a, _), (b, big) = laurent(rho0 * shrink), laurent(rho0 * shrink / 4)
        finite = np.isfinite(a) & np.isfinite(b)
        scale = max(float(big[finite].max()) if np.any(finite) else 0.0, 1e-300)
        if np.all(np.isfinite(a) == np.isfinite(b)) and np.all(np.abs(a[finite] - b[finite]) <= 1e-7 * scale):
            return b
    raise AnalysisError("the 0 Hz limit of the response could not be resolved (a pole lies very "
                        "close to 0 Hz); start the frequency grid above 0")


def _static_form(plant: Plant, form: str) -> str:
    """``form="auto"`` at ``s = 0``: the mounts' form whenever the plant carries it.

    At 0 Hz no mass term holds a nearly free motion, so its stiffness is whatever the assembled K
    keeps of it: mounts nearly in line (a rotation restrained by lever arms of 1e-5 m beside 0.5 m)
    cancel in K's entries to ``eps (L / d)^2`` (1e-7 measured against 60 digits, where statics,
    solved from the stiffness factor, kept 1e-11 and the mounts' form 2e-13; issue 18's fuzzer:
    FRF at 0 Hz 3.8e-8 off statics). One solve, so the larger system costs nothing that matters.
    """
    if form == "auto" and _use_mounts(plant, "auto") is False and plant.branches is None \
            and plant.mounts is not None and plant.mounts.matches(plant):
        return "mounts"
    return form


def lu_solver(a: Any) -> Callable[..., np.ndarray]:
    """``b -> a^-1 b`` (and ``b, trans="T" -> a^-T b``) by one LU of a dense or sparse matrix.

    Parameters
    ----------
    a : (n, n) ndarray or scipy.sparse matrix

    Returns
    -------
    callable
        ``solve(b, trans="N")``.

    Raises
    ------
    SingularMatrixError
        ``a`` is exactly singular (a zero pivot).
    """
    if sp.issparse(a):
        try:
            lu = spl.splu(sp.csc_matrix(a))
        except RuntimeError as exc:
            raise SingularMatrixError(f"the matrix is exactly singular ({exc})") from None

        def solve_sparse(b: np.ndarray, trans: str = "N") -> np.ndarray:
            b = np.asarray(b)
            if np.iscomplexobj(b) and not np.iscomplexobj(lu.U.data):
                return lu.solve(np.ascontiguousarray(b.real), trans=trans) + 1j * lu.solve(
                    np.ascontiguousarray(b.imag), trans=trans)
            return lu.solve(np.asarray(b, dtype=np.result_type(b, lu.U.dtype)), trans=trans)
        return solve_sparse
    fac = sl.lu_factor(a, check_finite=False)
    if np.any(np.diag(fac[0]) == 0):
        raise SingularMatrixError("the matrix is exactly singular")

    def solve_dense(b: np.ndarray, trans: str = "N") -> np.ndarray:
        return sl.lu_solve(fac, b, trans={"N": 0, "T": 1}[trans], check_finite=False)
    return solve_dense


def statespace_plant(a: np.ndarray, b: np.ndarray, c: np.ndarray, d: np.ndarray,
                     inputs: tuple[str, ...], outputs: tuple[str, ...], name: str = "vibss") -> Plant:
    """A first-order system ``x' = A x + B u, y = C x + D u`` as a plant (``K = -A, C = I, M = 0``).

    Its exact response ``C (sI - A)^-1 B + D`` is then :func:`response` like any other plant's.

    Parameters
    ----------
    a, b, c, d : ndarray
        State-space matrices, shapes (ns, ns), (ns, m), (p, ns), (p, m).
    inputs, outputs : tuple of str
        Signal names.
    name : str
        System name.

    Returns
    -------
    Plant
        Force inputs, displacement-like outputs, feedthrough ``Pf = D``; units ``"-"``.
    """
    a, b, c, d = (np.asarray(v, dtype=float) for v in (a, b, c, d))
    ns, m, p = a.shape[0], b.shape[1], c.shape[0]
    zn, zp = np.zeros((ns, m)), np.zeros((p, m))
    return Plant(dofs=tuple(f"x{k + 1}" for k in range(ns)), M=np.zeros((ns, ns)), C=np.eye(ns), K=-a,
                 H=np.zeros((ns, ns)), inputs=tuple(inputs), kinds=("force",) * m, F=b, Kz=zn, Cz=zn,
                 Mz=zn, Hz=zn, outputs=tuple(outputs), units=("-",) * p, Oq=c, Ov=np.zeros_like(c),
                 Oa=np.zeros_like(c), Pz=zp, Pv=zp, Pa=zp, Pf=d, name=name)


def without_hysteresis(plant: Plant) -> Plant:
    """The plant with its hysteretic parts removed (the time domain has none)."""
    return replace(plant, H=np.zeros_like(plant.H) if not sp.issparse(plant.H) else sp.csr_matrix(plant.H.shape),
                   Hz=np.zeros_like(plant.Hz), Oh=None, Ph=None)
