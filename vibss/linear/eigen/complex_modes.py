"""Complex modes of the scaled first-order modal form, with ``V^-1`` from the right eigenvectors.

The general-damping kernels (:func:`vibss.frequency.kernels.complex_modal` and the modal time path)
diagonalise ``A = [[0, P], [-Kt, -G]]`` on states ``[y1; y2]``: ``y2 = eta'`` (``nk`` modal
velocities), ``y1 = S eta`` (the ``ne`` elastic modal coordinates scaled by ``S = omega``), ``P``
places ``S`` on the elastic columns, ``Kt = Omega^2 S^-1`` (diagonal on the elastic rows) plus an
optional dense ``i Phi^T H Phi S^-1`` (hysteretic damping), and ``G = Phi^T C Phi`` symmetric.

That is the linearisation of the *symmetric* quadratic eigenproblem
``(lam^2 I + lam G + Kt P) x = 0`` (``Kt P`` is ``Omega^2 + i Phi^T H Phi``, symmetric though
complex). Its right eigenvectors are ``v = [P x; lam x]``, and because ``Q(lam)^T = Q(lam)`` its left
eigenvectors follow from the same ``x`` with no second eigenproblem:

    w^T = [-x^T Kt / lam,  x^T],    w^T v = x^T (2 lam + G) x.

So one ``eig`` without left vectors (about 12 % cheaper than with them) plus O(N^2) work gives
the rows of ``V^-1``, instead of an O(N^3) solve with ``V``. Where the structure cannot be trusted —
a zero eigenvalue, repeated eigenvalues (any basis of their eigenspace is returned, not a
bi-orthogonal one; eigenvalues merely close are checked pair by pair), or a random probe ``V^-1 (V r) = r`` that misses by more than
:data:`PROBE_TOL` — ``V`` is LU-factorised instead and the reason is recorded.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
import scipy.linalg as sl
from scipy.linalg import get_lapack_funcs
from scipy.spatial import cKDTree

from ...errors import DefectiveModesError
from ...results import ReadOnly
from ...threads import dense_threads

__all__ = ["ComplexModes", "complex_modes", "eigenpairs", "eigenvalues", "factor_vectors", "pole_errors", "PROBE_TOL"]

PROBE_TOL = 1e-10
"""Largest relative residual of ``V^-1 (V r) = r`` (random ``r``) accepted for the left
eigenvectors built from the right ones; above it ``V`` is factorised."""

COND_MAX = 1e8
"""Largest eigenvalue condition number (``||w|| ||v|| / |w^T v|``) or ``cond(V)`` accepted: above
it the eigenvectors are nearly dependent (critically damped or defective modes), a modal sum
would lose ``log10(cond)`` digits, and :func:`complex_modes` raises."""


@dataclass(frozen=True, eq=False)
class ComplexModes(ReadOnly):
    """Eigenvalues and right eigenvectors of ``A = [[0, P], [-Kt, -G]]`` and the means to apply ``V^-1``.

    Attributes
    ----------
    lam : (N,) complex ndarray
        Eigenvalues [1/s], ``N = ne + nk``.
    vectors : (N, N) complex ndarray
        Right eigenvectors ``V`` (columns), states ``[y1; y2]``.
    n_elastic : int
        ``ne``, the number of ``y1`` states.
    how : str
        How ``V^-1`` is applied: ``"left eigenvectors from the right ones (symmetric problem)"``
        or ``"LU of V (<reason>)"``.
    """

    lam: np.ndarray
    vectors: np.ndarray
    n_elastic: int
    how: str
    _x_over_norm: np.ndarray | None       # (nk, N) x_j / (w_j^T v_j)
    _kt: tuple[np.ndarray, np.ndarray, np.ndarray | None] | None   # rows, omega2/scale, coupling
    _lu: tuple[np.ndarray, np.ndarray] | None

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        """``V^-1 rhs`` for ``rhs`` of shape (N, k); returns (N, k) complex."""
        rhs = np.asarray(rhs)
        if self._lu is not None:
            return sl.lu_solve(self._lu, rhs, check_finite=False)
        assert self._x_over_norm is not None and self._kt is not None
        ne = self.n_elastic
        xn = self._x_over_norm
        rows, diag, coupling = self._kt
        kt_r1 = np.zeros((xn.shape[0],) + rhs.shape[1:], dtype=complex)
        kt_r1[rows] = diag.reshape((-1,) + (1,) * (rhs.ndim - 1)) * rhs[:ne]
        if coupling is not None:
            kt_r1 += coupling @ rhs[:ne]
        out = xn.T @ rhs[ne:]
        out -= (xn.T @ kt_r1) / self.lam.reshape((-1,) + (1,) * (rhs.ndim - 1))
        return out

    def solve_velocity(self, rhs: np.ndarray) -> np.ndarray:
        """``V^-1 [0; rhs]`` for ``rhs`` of shape (nk, k): modal forces into the velocity states.

        With left eigenvectors built from the right ones, ``V^-1`` is exact only to about the
        probe residual; one step of iterative refinement (two thin products with ``V``, O(N^2 k))
        brings the solve to the accuracy of an LU of ``V``, which matters where many modal terms
        cancel (well above the highest mode, where the response falls as 1/w^2).
        """
        rhs = np.asarray(rhs)
        n, ne = self.vectors.shape[0], self.n_elastic
        full = np.zeros((n,) + rhs.shape[1:], dtype=np.result_type(rhs, complex))
        full[ne:] = rhs
        z = self.solve(full)
        if self._lu is None:
            z += self.solve(full - self.vectors @ z)
        return z

    def velocity_rows(self) -> np.ndarray:
        """The velocity columns of ``V^-1``, ``V^-1[:, ne:]``; returns (N, nk) complex."""
        if self._x_over_norm is not None:
            return np.ascontiguousarray(self._x_over_norm.T)
        nk = self.vectors.shape[0] - self.n_elastic
        sel = np.zeros((self.vectors.shape[0], nk))
        sel[self.n_elastic:] = np.eye(nk)
        return self.solve(sel)


def eigenpairs(a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Eigenvalues and unit right eigenvectors of a small general (state) matrix, LAPACK ``geev``.

    The one general eigen solve (damped modes, complex modal FRFs); undamped modes come from
    :func:`vibss.linear.eigen.undamped.undamped`.
    """
    with dense_threads(a.shape[0]):
        return sl.eig(a, right=True, check_finite=False)


def eigenvalues(a: np.ndarray, b: np.ndarray | None = None) -> np.ndarray:
    """Eigenvalues of a small general matrix, or of the pencil ``a - lam b``: LAPACK ``geev`` /
    ``ggev`` without vectors (infinite eigenvalues of a singular ``b`` come back as ``inf``).

    The one general eigenvalue call beside :func:`eigenpairs` (the structured branch solver's first
    guesses, :mod:`vibss.linear.eigen.branch_modes`).
    """
    return sl.eig(a, b, right=False, check_finite=False)


REFINE_RISK = 1e-9
"""Refine a complex mode when ``eps max|lam| / |Re lam|`` (the relative error that ``eig``'s absolute
eigenvalue error ``eps max|lam|`` makes of its resonance peak) exceeds this."""

SLOW_PHASE = 1.0
"""A mode with ``|lam| horizon`` below this [rad] (less than a radian of phase within a time
response's horizon) gets its vector refined too: its response grows like a rigid body's, and ``eig``'s mixing of it
with its neighbours accumulates over the horizon (:func:`_refine_slow_modes`)."""

REFINE_ESTIMATE = 1e-10
"""A frequency response's mode at risk (:data:`REFINE_RISK`) gets the per-mode inverse iteration only
when its pole error, estimated a posteriori (:func:`_screen_poles`), exceeds this fraction of its
decay rate (a tenth of the target, for the estimate's spread of 0.7-1.5 of the true error where
measured); below it the estimate's root is its pole and ``eig``'s vector stays."""

REFINE_FLOPS = 1e9
"""Over a finite horizon, every mode gets the inverse iteration (vector too) when the dense solves
cost less than this (modes times ``nk^3``); above it only the slow modes at risk do."""


def _refine_slow_modes(lam: np.ndarray, v: np.ndarray, scale: np.ndarray, rows: np.ndarray,
                       omega2: np.ndarray, damping: np.ndarray,
                       coupling: np.ndarray | None, horizon: float = np.inf) -> tuple[np.ndarray, np.ndarray]:
    """Refine the lightly damped modes of ``eig`` on the quadratic problem ``Q(lam) x = 0``.

    ``lam`` and ``v`` (``eig``'s own arrays) are refined in place where they are complex already.

    ``eig`` is backward stable for ``A``: a mode decaying at ``|Re lam|`` << ``max|lam|`` feels its
    absolute error ``eps max|lam|`` as ``eps max|lam| / |Re lam|`` at its resonance (graded chain:
    8.9e-6 in the FRF at 1.001 omega_1). Inverse iteration on ``Q(lam) = lam^2 I + lam G + Kt P``
    (exact entries) and a Newton step on ``x^T Q(lam) x = 0`` give the pole to ``eps |lam|``
    (against 60 digits: 8.9e-9 -> 2.1e-12, the error of omega_1^2 itself).

    For a frequency response (infinite horizon) that bound is pessimistic (the 600-DOF tree of
    benchmarks/models.py: 220 of 1,200 modes flagged, 10 truly above 1e-10), so the modes at risk
    are screened by an a-posteriori estimate first (:func:`_screen_poles`, two GEMMs): the inverse
    iteration runs where it exceeds :data:`REFINE_ESTIMATE`, the others take the estimate's pole.

    In the time domain over ``horizon`` seconds an eigenvalue error ``d`` makes a relative error of
    at most ``|d| min(horizon, 1 / |Re lam|)``, so the amplification ``1 / |Re lam|`` is capped at
    ``horizon`` (infinite for frequency responses). The vectors matter there too: ``eig`` mixes each
    mode with its neighbours by about ``eps max|lam| / |lam_j - lam_k|``, which the structured left
    vectors ``x^T Kt / lam`` magnify by ``omega / |lam|``. A mode slower than the horizon (``|lam|
    horizon <`` :data:`SLOW_PHASE`) accumulates it (six bodies with 1e16 N/m links over 0.05 s: 3.5e-8
    off 50 digits with the pole alone, 2.0e-12 with every vector refined); so does a fast one (four
    bodies, no mode at risk by the pole: 1.1e-8 off 40 digits, 2.7e-14 refined). So over a finite
    horizon every mode gets the inverse iteration when that costs less than :data:`REFINE_FLOPS`;
    above it the modes slower than the horizon and those :func:`pole_errors` finds mixed past
    :data:`MIX_REFINE` do, and the other modes at risk :func:`_rayleigh` (the pole only, two GEMMs).
    """
    ne, nk = scale.size, damping.shape[0]
    if not ne or not lam.size:
        return lam, v
    decay = np.maximum(np.abs(lam.real), 1.0 / horizon if horizon > 0 else np.inf)
    risk = np.finfo(float).eps * float(np.abs(lam).max()) / np.maximum(decay, np.finfo(float).tiny)
    todo = np.flatnonzero((risk > REFINE_RISK) & (np.abs(lam) > 0) & np.isfinite(risk))
    every = np.flatnonzero((np.abs(lam) > 0) & np.isfinite(lam))
    mixed = np.zeros(0, int)
    if np.isfinite(horizon) and every.size * float(nk) ** 3 <= REFINE_FLOPS:
        todo = every
    elif np.isfinite(horizon):      # above the budget: the modes eig mixed past MIX_REFINE too
        mix = pole_errors(_Pairs(lam, v, ne), scale, rows, omega2, damping, coupling)[1]
        mixed = np.flatnonzero(~(mix <= MIX_REFINE) & (np.abs(lam) > 0) & np.isfinite(lam))
        mixed = mixed if mixed.size * float(nk) ** 3 <= MIX_FLOPS else mixed[:0]   # else left as they are
    if not todo.size and not mixed.size:
        return lam, v
    kp = np.zeros((nk, nk), dtype=complex if coupling is not None and np.iscomplexobj(coupling) else float)
    kp[rows, rows] = omega2
    if coupling is not None:
        kp[:, rows] += coupling * scale[None, :]
    lam, v = lam.astype(complex, copy=False), v.astype(complex, copy=False)   # eig's own arrays, refined in place
    if not np.isfinite(horizon):
        todo = _screen_poles(lam, v, todo, scale, rows, damping, kp, REFINE_ESTIMATE)
    if np.isfinite(horizon) and todo.size * float(nk) ** 3 > REFINE_FLOPS:
        slow = np.abs(lam[todo]) * horizon < SLOW_PHASE
        lam, v = _rayleigh(lam, v, np.setdiff1d(todo[~slow], mixed), scale, rows, damping, kp)
        todo = todo[slow]
    return _inverse_iteration(lam, v, np.union1d(todo, mixed).astype(int), scale, rows, damping, kp)


MIX_REFINE = 1e-9
"""Above :data:`REFINE_FLOPS`, modes mixed past this (:func:`pole_errors`) get the inverse iteration
(soft towers, general damping, 200 steps: 1.2e-7 / 7.4e-9 off Radau at 150 / 600 DOF, 1e-11 after)."""
MIX_FLOPS = 2e10  # budget of that refinement (modes x nk^3, ~2 s at one BLAS thread); past it, none


class _Pairs(NamedTuple):
    """``eig``'s poles and vectors as :func:`pole_errors` reads them, before :class:`ComplexModes` is made."""
    lam: np.ndarray
    vectors: np.ndarray
    n_elastic: int


def _inverse_iteration(lam: np.ndarray, v: np.ndarray, todo: np.ndarray, scale: np.ndarray,
                       rows: np.ndarray, damping: np.ndarray,
                       kp: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The modes ``todo`` refined, pole and vector, by two inverse-iteration steps on
    ``Q(lam) = lam^2 I + lam G + Kt P``, each followed by a Newton step on ``x^T Q(lam) x = 0`` for
    the pole. Both steps solve with one LU of ``Q`` at ``eig``'s pole (a dense factorisation per
    mode, O(nk^3); the second step's solve is O(nk^2)): that shift is within ``eps max|lam|`` of
    the pole, so the second step contracts the vector's error by ``eps max|lam| / gap`` as well as
    a fresh factorisation at the Newton pole would (measured: the graded chain's 60-digit errors
    and the tree's extended-precision ones unchanged, half the dense work). Where ``Q`` is real (no
    hysteretic coupling), the partner of a pair ``eig`` returned conjugate takes the conjugate of
    the refined mode instead of a solve of its own."""
    ne, nk = scale.size, damping.shape[0]
    real = not np.iscomplexobj(damping) and not np.any(kp.imag)
    done: dict[complex, int] = {}
    for j in todo:
        lj = lam[j]
        twin = done.get(complex(np.conj(lj))) if real and lj.imag else None
        if twin is not None:
            lam[j], v[:, j] = np.conj(lam[twin]), np.conj(v[:, twin])
            continue
        done[complex(lj)] = j
        x = v[ne:, j] / lj
        q = lj * damping                              # Q(lj) = lj^2 I + lj G + Kt P, one temporary
        q += kp
        q.flat[::nk + 1] += lj * lj
        with warnings.catch_warnings():            # an exactly singular Q: lj exact, nothing to refine
            warnings.simplefilter("ignore", sl.LinAlgWarning)
            lu = sl.lu_factor(q, overwrite_a=True, check_finite=False)
        if not np.all(np.diag(lu[0])) or not np.all(np.isfinite(lu[0])):
            continue
        for _ in range(2):
            y = sl.lu_solve(lu, 2 * lj * x + damping @ x, check_finite=False)   # Q'(lj) x: a Newton step
            if not np.all(np.isfinite(y)) or not np.any(y):
                break
            y = y / np.abs(y).max()                    # lj all but exact: y can reach 1e308
            x = y / np.linalg.norm(y)
            num = x @ (lj * lj * x + lj * (damping @ x) + kp @ x)    # x^T Q(lj) x (Q symmetric)
            den = x @ (2 * lj * x + damping @ x)
            if den == 0:
                break
            lj = lj - num / den
        vj = np.concatenate([scale * x[rows], lj * x])
        size = np.linalg.norm(vj)
        if np.isfinite(size) and size > 0 and np.isfinite(lj):     # else keep eig's pair
            lam[j], v[:, j] = lj, vj / size
    return lam, v


def _abs2(z: np.ndarray) -> np.ndarray:
    """``|z|^2`` elementwise without the square root of ``abs`` (one pass over ``z``)."""
    if not np.iscomplexobj(z):
        return z * z
    return z.real * z.real + z.imag * z.imag


def _sq(z: np.ndarray) -> np.ndarray:
    """Squared column norms of a 2-D array (no temporary: the parts are strided views)."""
    parts = (z.real, z.imag) if np.iscomplexobj(z) else (z,)
    return sum(np.einsum("ij,ij->j", p, p) for p in parts)


def _times(a: np.ndarray, x: np.ndarray) -> np.ndarray:
    """``a @ x``; a real ``a`` times a complex ``x`` as one real GEMM on ``x``'s interleaved parts
    (numpy would make ``a`` complex: four times the flops)."""
    if np.iscomplexobj(a) or not np.iscomplexobj(x):
        return a @ x
    return (a @ np.ascontiguousarray(x).view(float)).view(complex)


def _rayleigh_roots(lam: np.ndarray, v: np.ndarray, todo: np.ndarray, damping: np.ndarray,
                    kp: np.ndarray, ne: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """For the modes ``todo``: ``x = v2 / lam`` from ``eig``, the root of ``x^T Q(mu) x = 0``
    nearest to ``eig``'s pole, and where that root is finite (all modes at once: two GEMMs)."""
    X = v[ne:, todo] / lam[todo]
    a = np.einsum("ij,ij->j", X, X)
    b = np.einsum("ij,ij->j", X, _times(damping, X))
    c = np.einsum("ij,ij->j", X, _times(kp, X))
    with np.errstate(divide="ignore", invalid="ignore"):
        root = np.sqrt(b * b - 4 * a * c)
        r1 = (-b + root) / (2 * a)
        r2 = (-b - root) / (2 * a)
    ok = np.isfinite(r1) & np.isfinite(r2) & (a != 0)
    near = np.where(np.abs(r1 - lam[todo]) <= np.abs(r2 - lam[todo]), r1, r2)
    # the root nearest eig's is the accurate one; take the product form for the small of the pair
    other = np.where(near == r1, r2, r1)
    prod = c / a
    with np.errstate(divide="ignore", invalid="ignore"):
        alt = prod / other
    near = np.where(np.abs(near) < np.abs(other), np.where(np.isfinite(alt), alt, near), near)
    return X, near, ok


def _rayleigh(lam: np.ndarray, v: np.ndarray, todo: np.ndarray, scale: np.ndarray, rows: np.ndarray,
              damping: np.ndarray, kp: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The modes ``todo`` refined by the root of ``x^T Q(lam) x = 0`` nearest to ``eig``'s, with
    ``x`` from ``eig`` (all modes at once: two GEMMs)."""
    ne = scale.size
    X, near, ok = _rayleigh_roots(lam, v, todo, damping, kp, ne)
    j = todo[ok]
    lam[j] = near[ok]
    vj = np.vstack([scale[:, None] * X[rows][:, ok], near[ok][None, :] * X[:, ok]])
    v[:, j] = vj / np.linalg.norm(vj, axis=0)
    return lam, v


def _screen_poles(lam: np.ndarray, v: np.ndarray, todo: np.ndarray, scale: np.ndarray,
                       rows: np.ndarray, damping: np.ndarray, kp: np.ndarray, bound: float) -> np.ndarray:
    """Screen the modes ``todo`` (at risk by ``eps max|lam| / |Re lam|``) by an a-posteriori estimate
    of ``eig``'s pole error; return those that still need the inverse iteration.

    The estimate is the distance from ``eig``'s pole to the root of ``x^T Q(mu) x = 0`` with ``eig``'s
    ``x`` (:func:`_rayleigh_roots`; second order in the vector's error, ``Q`` exact): 0.73 to 1.5
    times the true error on every mode of the 600-DOF tree and the graded chain. A mode whose estimate
    is within ``bound`` of its decay rate takes that root as its pole (in place in ``lam``) and keeps
    ``eig``'s vector; the others (and non-finite roots) are returned. Cost: two GEMMs over ``todo``.
    """
    _, near, ok = _rayleigh_roots(lam, v, todo, damping, kp, scale.size)
    decay = np.maximum(np.abs(lam[todo].real), np.finfo(float).tiny)
    with np.errstate(invalid="ignore", over="ignore"):
        err = np.abs(near - lam[todo]) / decay
    keep = ok & (err <= bound)
    lam[todo[keep]] = near[keep]
    return todo[~keep]


def pole_errors(modes: "ComplexModes | _Pairs", scale: np.ndarray, rows: np.ndarray, omega2: np.ndarray,
                damping: np.ndarray, coupling: np.ndarray | None = None,
                relative: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """A-posteriori error bounds of each computed mode: its pole error and its eigenvector's mixing.

    The larger of two first-order pole bounds: the quadratic problem's residual ``Q(lam) x``
    (``x = v2 / lam``; entries of ``Q`` exact, as the refinement uses them) times its condition
    ``||x||^2 / |x^T Q'(lam) x|``, and the scaled first-order residual ``A v - lam v`` of the pair
    as the modal sum uses it (``eig``'s halves ``v1`` against ``S x``) times ``||w|| ||v|| /
    |w^T v|``; rounding of the products included as it falls. Undamped frequencies with a relative
    error bound ``e_i`` (``relative``: the basis's Kato-Temple bound) put ``2 e_i omega_i^2`` on
    ``Kt P``'s diagonal: ``sum_i 2 e_i omega_i^2 |x_i|^2 / |x^T Q' x|`` is added. The vector mixes
    with its nearest neighbour by about ``|d lam| / gap`` (distance to the nearest other pole).
    Cost: one GEMM ``nk^2 N`` (``G x``), a few passes over ``V``, a k-d tree of the poles.

    Parameters
    ----------
    modes : ComplexModes
        :func:`complex_modes`' answer.
    scale, rows, omega2, damping, coupling
        The arguments :func:`complex_modes` was given (``scale`` [rad/s], ``omega2`` [rad^2/s^2],
        ``damping`` [1/s], ``coupling`` [rad/s]).
    relative : (ne,) ndarray or None
        Relative error bound of each undamped frequency [-] (NaN or None: none).

    Returns
    -------
    dlam : (N,) ndarray
        Bound of each pole's error [1/s] (inf where it cannot be formed).
    mix : (N,) ndarray
        ``|d lam| / gap`` [-], the relative error of each mode's residue.
    """
    lam, v, ne = modes.lam, modes.vectors, modes.n_elastic
    rows = np.asarray(rows, int)
    sc, w2 = np.asarray(scale, float), np.asarray(omega2, float)
    kd = w2 / sc                                     # Kt's diagonal on the elastic rows [rad/s]
    v1, v2 = v[:ne], v[ne:]
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        x = v2 / lam[None, :]
        gx = _times(np.asarray(damping), x)
        den = np.abs(2 * lam * np.einsum("ij,ij->j", x, x) + np.einsum("ij,ij->j", x, gx))   # |x^T Q'(lam) x|
        r0 = np.multiply(x, lam[None, :])            # lam (G x + lam x): Q(lam) x and the first-order
        r0 += gx                                     # bottom residual less their stiffness parts
        r0 *= lam[None, :]
        xr = x[rows]
        if coupling is None:
            other = np.ones(x.shape[0], bool)
            other[rows] = False
            base = _sq(r0[other]) if other.any() else 0.0
            r0r = r0[rows]
            r2 = base + _sq(r0r + w2[:, None] * xr)                  # ||Q(lam) x||^2
            b2 = base + _sq(r0r + kd[:, None] * v1)                  # ||Kt v1 + G v2 + lam v2||^2
            wv = np.einsum("ij,ij->j", x, v2) - np.einsum("i,ij,ij->j", kd, xr, v1) / lam
            wn2 = (kd * kd) @ _abs2(xr) / _abs2(lam)                 # ||Kt^T x / lam||^2
        else:
            cp = np.asarray(coupling)
            kx = np.zeros_like(x)
            kx[rows] = w2[:, None] * xr
            kx += (cp * sc[None, :]) @ xr
            r2 = _sq(r0 + kx)
            kx[:] = 0.0
            kx[rows] = kd[:, None] * v1
            kx += cp @ v1
            b2 = _sq(r0 + kx)
            w1 = kd[:, None] * xr + cp.T @ x
            wv = np.einsum("ij,ij->j", x, v2) - np.einsum("ij,ij->j", w1, v1) / lam
            wn2 = _sq(w1) / _abs2(lam)
        x2 = _sq(x)
        dlam = np.sqrt(r2 * x2) / den
        # the first-order pair as the modal sum uses it: v1 against S x (eig's halves, a screened
        # pole with eig's vector), residual A v - lam v times the condition ||w|| ||v|| / |w^T v|
        top = sc[:, None] * v2[rows]
        top -= lam[None, :] * v1
        first = np.sqrt((_sq(top) + b2) * (wn2 + x2) * _sq(v)) / np.abs(wv)
        dlam = np.maximum(dlam, first)
        if relative is not None:
            e = np.nan_to_num(np.asarray(relative, float), nan=0.0)
            dlam = dlam + (2 * e * w2) @ _abs2(xr) / den
    dlam = np.where(np.isfinite(dlam), dlam, np.inf)
    pts = np.column_stack([lam.real, lam.imag])
    gap = cKDTree(pts).query(pts, k=2)[0][:, 1] if lam.size > 1 and np.all(np.isfinite(lam)) else np.full(lam.size, np.inf)
    with np.errstate(divide="ignore", invalid="ignore"):
        mix = np.where(gap > 0, dlam / gap, np.inf)
    return dlam, np.where(np.isnan(mix), np.inf, mix)


MAX_PAIRS = 256
"""Most pairs of close eigenvalues whose cross terms :func:`_mixed_pairs` checks; more
(a cluster of many equal modes) and ``V`` is factorised."""


def _mixed_pairs(lam: np.ndarray, v: np.ndarray, x: np.ndarray, norm: np.ndarray, rows: np.ndarray,
                 kt_diag: np.ndarray, coupling: np.ndarray | None, ne: int, tol: float) -> float:
    """Largest ``|w_j^T v_k| / |w_j^T v_j|`` over the pairs of eigenvalues within ``tol`` [1/s] of
    each other (0 when there are none): the entries of ``V^-1 V - I`` that the left vectors built
    from the right ones get wrong when ``eig`` returns an arbitrary basis of a repeated eigenvalue's
    eigenspace (not a bi-orthogonal one).

    Before, any two eigenvalues within ``tol = 1e-9 max|lam|`` sent the solve to an LU of ``V``; on
    the 600-DOF tree of benchmarks/models.py (``max|lam|`` 2.5e7 rad/s, so ``tol`` 0.025 rad/s) that
    caught four distinct pairs 0.008-0.018 rad/s apart whose cross terms are 1e-11 at most (and the
    full ``V^-1 V - I`` is 1.7e-10 at most, ``inv(V)`` 1.8e-11 from the structured inverse): the LU
    (0.3 s, a ninth of the modal time response) bought nothing there. An arbitrary basis of a
    repeated eigenvalue gives cross terms of order one. Cost: a k-d tree of the eigenvalues and
    O(N) per close pair.
    """
    if not np.all(np.isfinite(lam)):
        return np.inf
    pairs = cKDTree(np.column_stack([lam.real, lam.imag])).query_pairs(tol, output_type="ndarray")
    if not len(pairs):
        return 0.0
    if len(pairs) > MAX_PAIRS:
        return np.inf                           # a large cluster: factorise V rather than check it
    p = np.concatenate([pairs[:, 0], pairs[:, 1]])
    q = np.concatenate([pairs[:, 1], pairs[:, 0]])
    vq1 = v[:ne, q]
    wv = np.einsum("ij,ij->j", x[:, p], v[ne:, q]) - np.einsum("i,ij,ij->j", kt_diag, x[rows][:, p], vq1) / lam[p]
    if coupling is not None:
        wv -= np.einsum("ij,ij->j", x[:, p], coupling @ vq1) / lam[p]
    return float(np.abs(wv / norm[p]).max())


def factor_vectors(v: np.ndarray) -> tuple[tuple[np.ndarray, np.ndarray], float]:
    """LU factors of the eigenvectors ``V`` and the reciprocal of their 1-norm condition number
    (LAPACK ``gecon``): below ``1 / COND_MAX`` the vectors are nearly dependent.

    Parameters
    ----------
    v : (N, N) ndarray
        Right eigenvectors, one per column.

    Returns
    -------
    lu : tuple
        ``scipy.linalg.lu_factor``'s factors of ``v``.
    rcond : float
        Estimate of ``1 / cond_1(V)``.
    """
    lu = sl.lu_factor(v, check_finite=False)
    gecon = get_lapack_funcs("gecon", (lu[0],))
    rcond, _ = gecon(lu[0], np.linalg.norm(v, 1), norm="1")
    return lu, float(rcond)


def complex_modes(scale: np.ndarray, rows: np.ndarray, omega2: np.ndarray, damping: np.ndarray,
                  coupling: np.ndarray | None = None, seed: int = 0, horizon: float = np.inf) -> ComplexModes:
    """Eigen-decompose ``A = [[0, P], [-Kt, -G]]`` (see the module docstring).

    Parameters
    ----------
    scale : (ne,) ndarray
        ``S``, the scaling of the elastic displacement states [rad/s] (normally ``omega``).
    rows : (ne,) int ndarray
        Position of each elastic mode among the ``nk`` velocity states (``P[i, rows[i]] = scale[i]``).
    omega2 : (ne,) ndarray
        Squared natural frequencies of the elastic modes [rad^2/s^2].
    damping : (nk, nk) ndarray
        ``G = Phi^T C Phi`` of the velocity states [1/s], symmetric.
    coupling : (nk, ne) ndarray or None
        Extra dense part of ``Kt`` (``i Phi^T H Phi S^-1`` for hysteretic damping) [rad/s].
    seed : int
        Seed of the random probe vector (the check is deterministic).
    horizon : float
        Time span of a time response [s] (infinite for frequency responses): lightly damped modes
        are refined only as far as an error over this span needs (:func:`_refine_slow_modes`).

    Returns
    -------
    ComplexModes

    Raises
    ------
    DefectiveModesError
        ``cond(V)`` above :data:`COND_MAX` (critically damped or defective modes).

    Examples
    --------
    One mode, omega = 2 rad/s, c = 0.4: the roots of lam^2 + 0.4 lam + 4.

    >>> cm = complex_modes(np.array([2.0]), np.array([0]), np.array([4.0]), np.array([[0.4]]))
    >>> np.allclose(np.sort_complex(cm.lam), np.sort_complex(np.roots([1, 0.4, 4])))
    True
    >>> a = np.array([[0, 2.0], [-2.0, -0.4]])
    >>> np.allclose(cm.solve(a @ cm.vectors), np.diag(cm.lam))      # V^-1 A V = diag(lam)
    True
    >>> cm.how
    'left eigenvectors from the right ones (symmetric problem)'
    """
    scale, omega2 = np.asarray(scale, float), np.asarray(omega2, float)
    rows = np.asarray(rows, int)
    damping = np.asarray(damping)
    ne, nk = scale.size, damping.shape[0]
    n = ne + nk
    dtype = complex if coupling is not None and np.iscomplexobj(coupling) else float
    a = np.zeros((n, n), dtype=dtype)
    a[np.arange(ne), ne + rows] = scale
    a[ne + rows, np.arange(ne)] = -omega2 / scale
    if coupling is not None:
        a[ne:, :ne] -= coupling
    a[ne:, ne:] = -damping
    lam, v = eigenpairs(a)
    lam, v = _refine_slow_modes(lam, v, scale, rows, omega2, damping, coupling, horizon)
    kt = (rows, omega2 / scale, coupling)
    top = max(float(np.abs(lam).max()), np.finfo(float).tiny)
    tol = 1e-9 * top
    reason = ""
    if np.any(np.abs(lam) <= tol):
        reason = "a zero eigenvalue"
    else:
        x = v[ne:] / lam[None, :]
        # w^T v = x^T v2 - x^T Kt v1 / lam with the computed v1 (not P x), so that w_j^T v_j = 1
        # holds for the vectors eig returned; it needs no G x
        v1 = v[:ne]
        ktv = np.einsum("i,ij->j", omega2 / scale, x[rows] * v1)
        if coupling is not None:
            ktv = ktv + np.einsum("ij,ij->j", x, coupling @ v1)
        norm = np.einsum("ij,ij->j", x, v[ne:]) - ktv / lam
        if _mixed_pairs(lam, v, x, norm, rows, omega2 / scale, coupling, ne, tol) > PROBE_TOL:
            reason = "repeated eigenvalues"
    if not reason:
        modes = ComplexModes(lam, v, ne, "left eigenvectors from the right ones (symmetric problem)",
                             x / norm[None, :], kt, None)
        # eigenvalue condition numbers ||w|| ||v|| / |w^T v| (||v|| = 1 from eig)
        if coupling is None:        # |Kt^T x|^2 = sum_i (omega2_i / scale_i)^2 |x_i|^2: one pass over x
            ax2 = _abs2(x)
            w1n = (omega2 / scale) ** 2 @ (ax2 if rows.size == nk and np.array_equal(rows, np.arange(nk))
                                           else ax2[rows])
        else:
            w1 = (omega2 / scale)[:, None] * x[rows] + coupling.T @ x      # Kt^T x
            w1n, ax2 = _abs2(w1).sum(axis=0), _abs2(x)
        kappa = np.sqrt(w1n / _abs2(lam) + ax2.sum(axis=0)) / np.abs(norm)
        r = np.random.default_rng(seed).standard_normal(n)
        miss = float(np.linalg.norm(modes.solve(v @ r) - r) / np.linalg.norm(r))
        if miss <= PROBE_TOL and float(kappa.max()) <= COND_MAX:
            return modes
        reason = (f"probe residual {miss:.1e} > {PROBE_TOL:g}" if miss > PROBE_TOL
                  else f"eigenvalue condition number {float(kappa.max()):.1e}")
    lu, rcond = factor_vectors(v)
    if not rcond > 1.0 / COND_MAX:
        raise DefectiveModesError(f"complex modes: the eigenvectors are nearly dependent (cond(V) ~ "
                            f"{1 / max(rcond, 1e-300):.1e}: critically damped or defective modes), so a "
                            "modal sum would lose accuracy")
    return ComplexModes(lam, v, ne, f"LU of V ({reason})", None, None, lu)
