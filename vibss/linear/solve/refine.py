"""The solve in the mounts' forces by iterative refinement: a fast LU of the assembled matrix, the
residual in the mounts' form; the assembled matrix on one pattern kept per plant, ordered once
(:class:`Pattern`, :func:`assembled_lu`).

The assembled ``A(s) = K + iH + sC + s^2 M`` of a model with stiff links beside soft mounts rounds
every entry at its stiffest mount's level, and its LU loses the soft modes' digits (a 6,000-DOF soft
tower: 1.6e-6 of each channel's peak at 0.1 mHz). That LU is still a close approximate inverse: its
error ``E`` is of round-off size, so ``x_{k+1} = x_k + LU^-1 (r - A x_k)`` contracts by about
``||A^-1 E||`` per step, *provided the residual is computed without that round-off*. Here it is
computed in the mounts' form,

    A(s) x = R(s) x + B^T Z(s) (B x),    R(s) = K_rest + i H_rest + s C_rest + s^2 M,

mount by mount (:class:`~vibss.linear.plant.plant.MountForm`): a deflection ``B x`` is one difference of
two body motions, rounded relative to itself, and no stiff entry is summed with a soft one. Each step
costs one solve with the kept factor and the mounts' product; the iteration stops when the error it
leaves is at most :data:`TARGET`, or when it stops contracting (LAPACK ``xGERFS``'s rule). Measured on the
6,000-DOF tower against the same iteration with the residual in extended precision (64-bit
mantissa): 1e-15 ... 8e-15, where the LU of the equilibrated saddle system in the mounts' forces was
1e-6 off at 0.18 mHz. Where the iteration does not reach :data:`ACCEPT`, the caller solves that
frequency otherwise (the saddle system, itself refined the same way).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spl

from ..plant.plant import Plant

__all__ = ["STEPS", "ACCEPT", "TARGET", "CONTRACT", "STALLED", "HINT_MARGIN", "ASSEMBLED_ORDER", "PIVOT_THRESHOLD", "Contraction",
           "Pattern", "assembled_lu", "mounts_product", "refine", "RECORDED", "a_norm_bound", "assembled_times", "backward_error_of", "record_backward_error",
           "recorded_backward_errors"]

STEPS = 10
"""Most refinement steps per frequency."""
ACCEPT = 1e-11
"""Largest last correction (relative to the solution, per column, max norm) accepted when the
iteration stops contracting; above it the caller falls back."""
TARGET = 1e-13
"""The iteration stops when the error it leaves is at most this (relative, per column) [-]: its last
correction ``d_k`` (the error left is that times the contraction), or, from the second step, the
contraction measured over the last two, ``d_k^2 / (d_(k-1) - d_k)``. Measured on a 6,000-DOF soft
tower, an 11-body tower and the hanging chain (against 240 bits): the error after step k is the
correction of step k + 1 to within 2x, and the contraction per step steady (1e-4 ... 1e-6 near the
soft modes); two steps where the assembled LU is 1e-6 off, one above the soft modes."""
CONTRACT = 0.5
"""A step whose correction is not below this fraction of the one before has stopped contracting."""
STALLED = 1e-6
"""Largest last correction (relative, per column) of the saddle system's refinement in the mounts'
forces up to which a point is kept when the iteration stalls above :data:`ACCEPT`
(:mod:`vibss.linear.solve.backends`): near a lightly damped ultra-soft mode the refinement stalls at
``A(s)``'s own conditioning (the 600-DOF soft tower at its 0.46 mHz resonance: 1e-10 to 3e-10 at zeta
1e-3, about ten times that at 1e-4), and the answer's error is about that correction (a few times it
where the steps contract slowly): exact to ``A(s)``'s conditioning there, not to rounding. The stall is
recorded (:func:`record_backward_error`) and the exact methods' check reads it beside the backward error, which
is at rounding and would not see it: a named method warns that it missed its claim. A driven singular
point (an undamped resonance) does not stall there: its corrections stay of order one or the iterate
overflows."""


def mounts_product(form: Any, m_csr: sp.csr_matrix, bt: sp.csr_matrix, bat: sp.csr_matrix | None,
                   s: complex) -> Callable[[np.ndarray], np.ndarray]:
    """``x -> A(s) x`` in the mounts' form, ``R(s) x + B^T Z(s) B x`` (plus the per-axis mounts).

    Parameters
    ----------
    form : MountForm
        The plant's mounts (:class:`~vibss.linear.plant.plant.MountForm`).
    m_csr : (n, n) scipy.sparse CSR matrix
        The plant's mass matrix [kg].
    bt, bat : scipy.sparse CSR matrix
        ``B^T`` (n, 3 q) and ``Ba^T`` (n, r) (None without per-axis mounts).
    s : complex
        Laplace value [rad/s].

    Returns
    -------
    callable
        ``(n, k) -> (n, k)`` complex [N per unit of x].
    """
    z = form.kp + s * form.cp + 1j * form.hp                       # (q, 3, 3) [N/m]
    za = form.ka + s * form.ca + 1j * form.ha if bat is not None else None
    rest = [(c, a) for c, a in ((1.0, form.K), (1j, form.H), (s, form.C)) if a.nnz]

    def apply(x: np.ndarray) -> np.ndarray:
        y = (s * s) * _real_times(m_csr, x)
        for c, a in rest:
            y += c * _real_times(a, x)
        bx = _real_times(form.B, x).reshape(-1, 3, x.shape[1])
        y += _real_times(bt, np.matmul(z, bx).reshape(-1, x.shape[1]))
        if za is not None and bat is not None:
            y += _real_times(bat, za[:, None] * _real_times(form.Ba, x))
        return y
    return apply


def _real_times(a: sp.csr_matrix, x: np.ndarray) -> np.ndarray:
    """``a @ x`` for a real sparse ``a`` and complex ``x`` (n, k): on ``x``'s real and imaginary parts
    side by side (its float view, (n, 2k)), not on a complex copy of ``a`` made per call (scipy's
    upcast: 11 ms of every 14 ms product at 60,000 DOF)."""
    x = np.ascontiguousarray(x, dtype=complex)
    return np.ascontiguousarray(a @ x.view(float)).view(complex)


@dataclass
class Contraction:
    """The largest contraction per step measured where a frequency of the sweep took two steps: the
    later frequencies' bound (the LU's error changes slowly along the frequencies of one sweep)."""

    rho: float = np.inf


HINT_MARGIN = 10.0
"""A frequency's first correction is trusted with the sweep's largest measured contraction times this."""


def refine(solve: Callable[[np.ndarray], np.ndarray], apply: Callable[[np.ndarray], np.ndarray],
           r: np.ndarray, hint: Contraction | None = None) -> tuple[np.ndarray, float, bool]:
    """``A x = r`` by ``x = solve(r)`` refined with the residual ``r - apply(x)``.

    Parameters
    ----------
    solve : callable
        An approximate inverse of ``A`` (a kept LU's solve), ``(n, k) -> (n, k)``.
    apply : callable
        ``A`` itself, accurately (:func:`mounts_product`).
    r : (n, k) complex ndarray
        Right-hand sides [N].
    hint : Contraction or None
        The largest contraction measured so far in the sweep (raised here when two steps are
        taken): after the first step the error left is bounded by the correction times
        :data:`HINT_MARGIN` that contraction, and the iteration stops when that is within
        :data:`TARGET` (one solve and one product fewer where the LU is already close: above the
        soft modes). None: at least two steps, as without a sweep.

    Returns
    -------
    x : (n, k) complex ndarray
        The solution.
    correction : float
        The error left, largest over the columns (max norms, relative) [-]: the last correction,
        or what the measured contraction leaves of it (:data:`TARGET`).
    converged : bool
        The correction reached round-off, or stopped contracting at most :data:`ACCEPT`.
    """
    x = np.asarray(solve(r), dtype=complex)
    prev = np.inf
    last = np.inf
    for _ in range(STEPS):
        if not np.all(np.isfinite(x)):
            return x, np.inf, False
        dx = solve(r - apply(x))
        x = x + dx
        size = np.abs(x).max(axis=0)
        last = float(np.max(np.abs(dx).max(axis=0) / np.where(size > 0, size, 1.0), initial=0.0))
        if last <= TARGET:
            return x, last, True
        if last > CONTRACT * prev:
            return x, last, last <= ACCEPT
        if np.isfinite(prev):                   # the error left by the contraction of the last two steps
            rho = last / prev
            if hint is not None:                # the largest of the sweep: a bound, not the last value
                hint.rho = rho if not np.isfinite(hint.rho) else max(hint.rho, rho)
            left = last * rho / (1.0 - rho)
            if left <= TARGET:
                return x, left, True
        elif hint is not None and HINT_MARGIN * hint.rho < CONTRACT:
            bound = HINT_MARGIN * hint.rho
            left = last * bound / (1.0 - bound)
            if left <= TARGET:
                return x, left, True
        prev = last
    return x, last, last <= ACCEPT


RECORDED = "backward errors of the solve in the mounts' forces"
"""The plant's record (:meth:`~vibss.linear.plant.plant.Plant.cached`) of :func:`record_backward_error`."""


def _fingerprint(s: complex, r: np.ndarray) -> tuple[complex, int, tuple[int, ...]]:
    """What identifies one solve: the Laplace point and the right-hand sides (their bytes hashed)."""
    r = np.ascontiguousarray(r)
    return complex(s), hash(r.tobytes()), r.shape


def a_norm_bound(plant: Plant, s: complex) -> float:
    """``||K||_F + ||H||_F + |s| ||C||_F + |s|^2 ||M||_F``: a bound on ``||A(s)||_F`` (the backward
    errors' scale, within 2 of the norm; the four norms kept on the plant)."""
    def fro(a: Any) -> float:
        if a is None or (sp.issparse(a) and not a.nnz):
            return 0.0
        return float(sp.linalg.norm(a)) if sp.issparse(a) else float(np.linalg.norm(a))
    nk, nh, nc, nm = plant.cached("frobenius norms K H C M", lambda: [fro(getattr(plant, k)) for k in "KHCM"])
    return nk + nh + abs(s) * nc + abs(s) ** 2 * nm


def assembled_times(plant: Plant, s: np.ndarray, x: np.ndarray) -> np.ndarray:
    """(k, n, m) ``A(s_j) x_j = (K + iH + s_j C + s_j^2 M) x_j`` at every point at once, with the plant's
    own matrices (a dense one's CSR form where the plant already holds it, ``"sparse K"`` ...).

    Parameters
    ----------
    plant : Plant
    s : (k,) complex ndarray
        Laplace points [rad/s].
    x : (k, n, m) complex ndarray
        DOF solutions per unit input.
    """
    s = np.asarray(s, complex)
    k, n = s.size, plant.n
    flat = np.moveaxis(np.asarray(x), 0, 1).reshape(n, -1)
    out = np.zeros((k, n, x.shape[2]), complex)
    with np.errstate(invalid="ignore", over="ignore"):          # a singular point's inf solution
        for key, coef in (("K", np.ones(k)), ("H", np.full(k, 1j)), ("C", s), ("M", s * s)):
            a = getattr(plant, key)
            if a is None or not (a.nnz if sp.issparse(a) else np.any(a)):
                continue
            kept = plant.known(f"sparse {key}")
            a = a if kept is None else kept
            out += coef[:, None, None] * np.moveaxis(np.asarray(a @ flat).reshape(n, k, -1), 1, 0)
    return out


def backward_error_of(plant: Plant, s: complex, r: np.ndarray, x: np.ndarray, ax: np.ndarray) -> float:
    """``||r - A x||_F / (||A(s)||_F ||x||_F + ||r||_F)`` for ``ax = A(s) x`` (:func:`a_norm_bound`), 0 where
    the denominator is (the one formula of the exact solves' check and of :func:`record_backward_error`)."""
    den = a_norm_bound(plant, s) * float(np.linalg.norm(x)) + float(np.linalg.norm(r))
    return float(np.linalg.norm(r - ax)) / den if den > 0 else 0.0


def record_backward_error(plant: Plant, s: complex, r: np.ndarray, x: np.ndarray,
                          apply: Callable[[np.ndarray], np.ndarray], stall: float = 0.0) -> float:
    """The normwise backward error of the solution ``x`` of ``A(s) x = r`` that the solve returns,
    ``||r - A x||_F / (||A(s)||_F ||x||_F + ||r||_F)`` (the norm bounded above as the check bounds it),
    its residual by the mounts' product ``apply`` (one product, no solve: 2-14 ms against a 0.25 s
    factorisation at 60,000 DOF); kept on the plant for :func:`recorded_backward_errors`, with the
    last correction ``stall`` of a refinement that stalled at ``A(s)``'s conditioning (:data:`STALLED`;
    0 where it converged)."""
    eta = backward_error_of(plant, s, r, x, apply(x))
    plant.cached(RECORDED, dict)[_fingerprint(s, r)] = (eta, float(stall))
    return eta


def recorded_backward_errors(plant: Plant, s: np.ndarray, r: np.ndarray) -> tuple[np.ndarray, float] | None:
    """The (k,) backward errors the solve in the mounts' forces recorded at the points ``s`` for the
    right-hand sides ``r`` (k, n, m) (:func:`record_backward_error`) and the largest stalled correction
    among them (0 where none stalled), or None if one was not recorded."""
    kept = plant.known(RECORDED)
    if not kept:
        return None
    out = [kept.get(_fingerprint(sk, rk)) for sk, rk in zip(np.atleast_1d(s), r)]
    if any(e is None for e in out):
        return None
    return np.array([e for e, _ in out], dtype=float), max((st for _, st in out), default=0.0)


ASSEMBLED_ORDER = "MMD_AT_PLUS_A"
"""SuperLU's ordering of the assembled matrix that the mounts' form refines (:mod:`vibss.linear.solve.refine`):
minimum degree on ``A^T + A`` with diagonal pivots preferred (the matrix is symmetric): 0.040 s against
COLAMD's 0.054 s on the 6,000-DOF soft tower (fill 0.53 M against 0.74 M)."""

PIVOT_THRESHOLD = 0.1
"""SuperLU's ``diag_pivot_thresh`` for that LU: a diagonal pivot is kept unless 10x smaller than its
column's largest entry (refinement corrects what the weaker pivoting loses, or the saddle system answers)."""


def assembled_lu(plant: Plant, s: complex) -> Callable[[np.ndarray], np.ndarray]:
    """The solve with SuperLU's LU of the plant's assembled ``A(s)`` (:class:`Pattern`). The first one
    orders the pattern (:data:`ASSEMBLED_ORDER`, symmetric mode); the plant keeps that ordering, the
    pattern laid out in it, and every later frequency factors the permuted matrix without ordering it
    again (the order is structural; row pivots still follow the values): 0.24-0.26 s against 0.29 s a
    frequency at 60,000 DOF, 0.026 against 0.036 s at 6,000 (same fill)."""
    kept = plant.known("assembled pattern, ordered")
    if kept is None:
        pattern = Pattern.of(plant)              # only its ordered copy is kept
        lu = spl.splu(pattern.matrix(s), permc_spec=ASSEMBLED_ORDER, diag_pivot_thresh=PIVOT_THRESHOLD,
                      options={"SymmetricMode": True})
        q = np.argsort(lu.perm_c)                  # A[q][:, q] is the matrix in SuperLU's column order
        plant.cached("assembled pattern, ordered", lambda: (pattern.permuted(q), q))
        return lu.solve
    ordered, q = kept
    lu = spl.splu(ordered.matrix(s), permc_spec="NATURAL", diag_pivot_thresh=PIVOT_THRESHOLD,
                  options={"SymmetricMode": True})

    def solve(b: np.ndarray) -> np.ndarray:
        x = np.empty_like(b, dtype=complex)
        x[q] = lu.solve(np.ascontiguousarray(b[q]))
        return x
    return solve


@dataclass(frozen=True, eq=False)
class Pattern:
    """The assembled ``K + iH + sC + s^2 M`` on one CSC pattern, laid out once per plant: each term's
    values spread over the whole pattern (zeros where it has none), so a frequency is a few
    vector operations over the nonzeros (sparse sums per frequency took 0.1 s of the mounts' 1 s a
    frequency at 60,000 DOF, scattering the terms' values 0.012 s of 0.1 s at 6,000)."""

    indptr: np.ndarray
    indices: np.ndarray
    terms: dict

    @classmethod
    def of(cls, plant: Plant) -> Pattern:
        """The pattern of ``plant``'s ``K, H, C, M``."""
        n = plant.n
        parts = {k: sp.coo_matrix(getattr(plant, k)) for k in ("K", "H", "C", "M")}
        parts = {k: a for k, a in parts.items() if a.nnz or k == "K"}
        keys = {k: a.col.astype(np.int64) * n + a.row for k, a in parts.items()}
        every = np.unique(np.concatenate(list(keys.values())))
        indptr = np.concatenate([[0], np.cumsum(np.bincount(every // n, minlength=n))])
        terms = {}
        for k, a in parts.items():
            full = np.zeros(every.size)
            np.add.at(full, np.searchsorted(every, keys[k]), a.data)
            terms[k] = full
        return cls(indptr, (every % n).astype(np.int32), terms)

    def permuted(self, q: np.ndarray) -> Pattern:
        """The same terms on ``A[q][:, q]``'s pattern (CSC, sorted)."""
        n = self.indptr.size - 1
        where = sp.csc_matrix((np.arange(1, self.indices.size + 1, dtype=float), self.indices, self.indptr),
                              shape=(n, n))[q][:, q].tocsc()
        where.sort_indices()
        take = where.data.astype(np.int64) - 1
        return Pattern(where.indptr.copy(), where.indices.copy(), {k: v[take] for k, v in self.terms.items()})

    def matrix(self, s: complex) -> Any:
        """The matrix at ``s`` [rad/s], CSC complex."""
        data = np.empty(self.indices.size, dtype=complex)
        t = self.terms
        if s.real == 0:                   # the imaginary axis: real part K - w^2 M, imaginary w C + H
            w = s.imag
            data.real = t["K"] - (w * w) * t["M"] if "M" in t else t["K"]
            data.imag = w * t["C"] if "C" in t else 0.0
            if "H" in t:
                data.imag += t["H"]
        else:
            data[:] = t["K"]
            for k, c in (("M", s * s), ("C", s), ("H", 1j)):
                if k in t:
                    data += c * t[k]
        n = self.indptr.size - 1
        return sp.csc_matrix((data, self.indices, self.indptr), shape=(n, n))
