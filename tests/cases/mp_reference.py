"""Extended-precision (mpmath, 60 digits) reference answers for small models.

Assembles M, K, C from the model's fields with a loop per mount (the formulation of
shared/spec/formulation.md, sharing no code with vibss), then solves in 60-digit arithmetic:
undamped eigenvalues, static deflections and receptances. Float inputs are taken exactly, so the
only rounding is mpmath's own.
"""

from __future__ import annotations

from functools import lru_cache
from typing import Any

import mpmath as mp
import numpy as np

from vibss import GROUND, Model

DPS = 60


def _lever(r) -> mp.matrix:
    """3x6 map from (u, theta) to u + theta x r."""
    x, y, z = r
    return mp.matrix([[1, 0, 0, 0, z, -y], [0, 1, 0, -z, 0, x], [0, 0, 1, y, -x, 0]])


def matrices(model: Model, key: str = "stiffness") -> mp.matrix:
    """K (or C with key='damping') as an mpmath matrix, summed mount by mount (at :data:`DPS` digits;
    assembled once per model, a copy returned)."""
    return _matrices(model, key).copy()


@lru_cache(maxsize=64)
def _matrices(model: Model, key: str) -> mp.matrix:
    with mp.workdps(DPS):
        return _assemble(model, key)


def _assemble(model: Model, key: str) -> mp.matrix:
    names = model.body_names
    n = 6 * len(names)
    out = mp.zeros(n, n)
    cog = {b.name: [mp.mpf(float(v)) for v in b.cog] for b in model.bodies}
    for m in model.mounts:
        at = [mp.mpf(float(v)) for v in m.at]
        p = [at[k] + cog[m.body][k] for k in range(3)] if m.frame == "body" else at
        t = mp.matrix([[mp.mpf(float(v)) for v in row] for row in m.orientation.matrix])
        d = mp.diag([mp.mpf(float(v)) for v in getattr(m.type, key)])
        kp = t * d * t.T
        ends = [(names.index(m.body), _lever([p[k] - cog[m.body][k] for k in range(3)]), 1)]
        if m.to != GROUND:
            ends.append((names.index(m.to), _lever([p[k] - cog[m.to][k] for k in range(3)]), -1))
        for i, li, si in ends:                      # the blocks of b^T kp b, b = [l_i, -l_j]: 6 x 6 each
            for j, lj, sj in ends:
                blk = li.T * kp * lj
                for r in range(6):
                    for c in range(6):
                        out[6 * i + r, 6 * j + c] += si * sj * blk[r, c]
    return out


def mass(model: Model) -> mp.matrix:
    """Block-diagonal mass matrix in mpmath."""
    return _mass(model).copy()


@lru_cache(maxsize=64)
def _mass(model: Model) -> mp.matrix:
    n = 6 * len(model.bodies)
    out = mp.zeros(n, n)
    for i, b in enumerate(model.bodies):
        for k in range(3):
            out[6 * i + k, 6 * i + k] = mp.mpf(float(b.masses[k]))
        for r in range(3):
            for c in range(3):
                out[6 * i + 3 + r, 6 * i + 3 + c] = mp.mpf(float(b.tensor[r, c]))
    return out


@lru_cache(maxsize=None)
def _omega2(model: Model) -> tuple:
    with mp.workdps(DPS):
        M, K = mass(model), matrices(model)
        L = mp.cholesky(M)
        Li = mp.inverse(L)
        A = Li * K * Li.T
        A = (A + A.T) / 2
        w2 = mp.eigsy(A, eigvals_only=True)
        return tuple(sorted(w2[i] for i in range(A.rows)))


def omega2(model: Model) -> np.ndarray:
    """(n,) undamped eigenvalues w^2 [rad^2/s^2], ascending, to 60 digits then rounded to float.

    Rigid-body modes come out as |w^2| at the 1e-50 level (relative to the largest).
    """
    return np.array([float(v) for v in _omega2(model)])


def natural_frequencies(model: Model) -> np.ndarray:
    """(n,) undamped natural frequencies [rad/s]; rigid modes (|w^2| below 1e-40 of the top) as 0."""
    w2 = _omega2(model)
    top = max(abs(v) for v in w2)
    return np.array([0.0 if abs(v) <= mp.mpf(10) ** -40 * top else float(mp.sqrt(v)) for v in w2])


def static(model: Model, load: np.ndarray) -> np.ndarray:
    """K^-1 f for a (n,) generalised load [N, N m] (K must be nonsingular)."""
    with mp.workdps(DPS):
        K = matrices(model)
        x = mp.lu_solve(K, mp.matrix([mp.mpf(float(v)) for v in load]))
        return np.array([float(x[i]) for i in range(K.rows)])


def receptance(model: Model, s: complex) -> np.ndarray:
    """(n, n) complex receptance (K + s C + s^2 M)^-1 at the Laplace variable s [1/s]: the 60-digit
    matrices solved in ball arithmetic (python-flint's acb, 240 bits; the answer's certified radius
    below 1e-30 of its largest entry is asserted). mpmath's 60-digit inverse took 0.5 s a frequency on
    48 DOF, acb takes 0.02 s."""
    import flint

    K, C, M = _acb(model)
    old = flint.ctx.prec
    flint.ctx.prec = BITS
    try:
        sa = flint.acb(repr(float(s.real)), repr(float(s.imag)))
        X = (K + C * sa + M * (sa * sa)).inv()
        n = K.nrows()
        out = np.array([[complex(X[i, j].mid()) for j in range(n)] for i in range(n)])
        rad = max(float(abs(X[i, j]).rad()) for i in range(n) for j in range(n))
    finally:
        flint.ctx.prec = old
    assert rad <= 1e-30 * np.abs(out).max(), "the ball-arithmetic receptance lost its digits"
    return out


BITS = 240
"""Precision of the ball-arithmetic solves [bits] (72 digits: past the 60 of the matrices)."""


@lru_cache(maxsize=64)
def _acb(model: Model) -> tuple:
    import flint

    old = flint.ctx.prec
    flint.ctx.prec = BITS
    try:
        with mp.workdps(DPS):
            mats = matrices(model), matrices(model, "damping"), mass(model)
            return tuple(flint.acb_mat([[flint.acb(mp.nstr(a[i, j], DPS)) for j in range(a.cols)]
                                        for i in range(a.rows)]) for a in mats)
    finally:
        flint.ctx.prec = old


@lru_cache(maxsize=None)
def _poles(model: Model) -> tuple:
    """The first-order matrix of the 60-digit M, C, K and its eigenvalues in ball arithmetic (acb, 240
    bits; every enclosure's radius below 1e-30 of the largest is asserted): 5.6 s on the 48-DOF graded
    chain where mpmath's ``eig`` took 76 s, the same poles to 4e-58."""
    import flint

    K, C, M = _acb(model)
    old = flint.ctx.prec
    flint.ctx.prec = BITS
    try:
        n = K.nrows()
        Mi = M.inv()
        MK, MC = Mi * K, Mi * C
        A = flint.acb_mat(2 * n, 2 * n)
        for i in range(n):
            A[i, n + i] = 1
            for j in range(n):
                A[n + i, j] = -MK[i, j]
                A[n + i, n + j] = -MC[i, j]
        ev = A.eig()
        lam = [complex(e.mid()) for e in ev]
        rad = max(float(abs(e).rad()) for e in ev)
    finally:
        flint.ctx.prec = old
    assert rad <= 1e-30 * max(abs(v) for v in lam), "the ball-arithmetic poles lost their digits"
    return tuple(lam)


def poles(model: Model) -> np.ndarray:
    """(2n,) poles [1/s] of ``M q'' + C q' + K q = 0`` (eigenvalues of the first-order matrix),
    computed in 60 digits, sorted by imaginary part then real part."""
    lam = np.array(_poles(model))
    return lam[np.lexsort((lam.real, lam.imag))]


def step_response_undamped(model: Model, load: np.ndarray, t: np.ndarray) -> np.ndarray:
    """(len(t), n) response of an undamped model at rest to a step load [N, N m] applied at t = 0:
    ``q(t) = sum_k phi_k phi_k^T f (1 - cos w_k t) / w_k^2`` with 60-digit modes (no rigid modes)."""
    with mp.workdps(DPS):
        M, K = mass(model), matrices(model)
        Li = mp.inverse(mp.cholesky(M))
        A = Li * K * Li.T
        w2, U = mp.eigsy((A + A.T) / 2)
        phi = Li.T * U
        f = mp.matrix([mp.mpf(float(v)) for v in load])
        n = K.rows
        out = np.zeros((len(t), n))
        for k in range(n):
            col = phi[:, k]
            g = (col.T * f)[0] / w2[k]
            wk = mp.sqrt(w2[k])
            for it, tt in enumerate(t):
                a = g * (1 - mp.cos(wk * mp.mpf(float(tt))))
                for i in range(n):
                    out[it, i] += float(col[i] * a)
        return out


def step_response(model: Model, load: np.ndarray, dt: float, steps: int, rows: int = 6,
                  dps: int = 40) -> np.ndarray:
    """(rows, steps + 1) response of ``M q'' + C q' + K q = f`` at rest to a step load ``f``
    [N, N m] applied at t = 0, first ``rows`` DOFs at ``t = k dt`` [s]: the state advanced by
    ``expm`` of the first-order matrix augmented with the constant load, in ``dps`` digits (rigid
    modes and non-proportional damping included; no hysteresis, as in the time domain)."""
    with mp.workdps(dps):
        K, C, M = matrices(model), matrices(model, "damping"), mass(model)
        n = K.rows
        Mi = mp.inverse(M)
        MK, MC = Mi * K, Mi * C
        mf = Mi * mp.matrix([mp.mpf(float(v)) for v in load])
        A = mp.zeros(2 * n + 1, 2 * n + 1)
        for i in range(n):
            A[i, n + i] = 1
            A[n + i, 2 * n] = mf[i]
            for j in range(n):
                A[n + i, j] = -MK[i, j]
                A[n + i, n + j] = -MC[i, j]
        E = mp.expm(A * mp.mpf(float(dt)))
        x = mp.zeros(2 * n + 1, 1)
        x[2 * n] = 1
        out = np.zeros((rows, steps + 1))
        for k in range(steps + 1):
            out[:, k] = [float(x[i]) for i in range(rows)]
            x = E * x
        return out


def step_response_certified(model: Model, load: np.ndarray, dt: float, steps: int, rows: int = 6,
                            bits: int = 800) -> tuple[np.ndarray, float]:
    """:func:`step_response` in ball arithmetic (python-flint's arb, ``bits`` of precision): the same
    augmented ``expm``, each entry carried with a rigorous error radius. Returns the response
    (rows, steps + 1) and its largest radius relative to its largest entry: a reference that states
    its own error. The matrices come from :func:`matrices` and :func:`mass` at 60 digits (exact for
    the model's floats up to 1e-60). A 36-DOF model with modes from 1.7 to 1e11 rad/s: 800 bits give
    a radius of 7e-68 in 3 s, where the 40-digit ``mp.expm`` took 24 s (500 bits: radius 3e19, the
    squarings' growth)."""
    import flint

    old = flint.ctx.prec
    flint.ctx.prec = bits
    try:
        with mp.workdps(DPS):
            K, C, M = matrices(model), matrices(model, "damping"), mass(model)

            def arb(a: mp.matrix) -> Any:
                return flint.arb_mat([[flint.arb(mp.nstr(a[i, j], DPS)) for j in range(a.cols)]
                                      for i in range(a.rows)])

            Ka, Ca, Mi = arb(K), arb(C), arb(M).inv()
            f = arb(mp.matrix([mp.mpf(float(v)) for v in load]))
        n = K.rows
        MK, MC, mf = Mi * Ka, Mi * Ca, Mi * f
        A = flint.arb_mat(2 * n + 1, 2 * n + 1)
        for i in range(n):
            A[i, n + i] = 1
            A[n + i, 2 * n] = mf[i, 0]
            for j in range(n):
                A[n + i, j] = -MK[i, j]
                A[n + i, n + j] = -MC[i, j]
        E = (A * flint.arb(repr(float(dt)))).exp()
        x = flint.arb_mat(2 * n + 1, 1)
        x[2 * n, 0] = 1
        out, rad = np.zeros((rows, steps + 1)), 0.0
        for k in range(steps + 1):
            for i in range(rows):
                out[i, k] = float(x[i, 0].mid())
                rad = max(rad, float(x[i, 0].rad()))
            x = E * x
        return out, rad / max(float(np.abs(out).max()), 1e-300)
    finally:
        flint.ctx.prec = old


def extended_precision_frf(plant: Any, s: np.ndarray) -> np.ndarray:
    """Receptance ``Oq (K + s^2 M + s C)^-1 F`` of a plant, (p, m, nf): a dense LU refined three
    times with the residual formed in long double (80-bit on x86), independent of any
    eigen-decomposition (the tree's reference in tests/linear/test_complex_modes.py and
    benchmarks/bench_tree_refine.py)."""
    import scipy.linalg as sl
    import scipy.sparse as sps

    def dense(x: Any) -> np.ndarray:
        return np.asarray(x.toarray() if sps.issparse(x) else x, dtype=float)

    M, C, K, F, O = (dense(x) for x in (plant.M, plant.C, plant.K, plant.F, plant.Oq))
    Ml, Cl, Kl, Fl, Ol = (x.astype(np.longdouble) for x in (M, C, K, F, O))
    out = []
    for sk in s:
        lu = sl.lu_factor(K + sk * sk * M + sk * C)
        x = sl.lu_solve(lu, F.astype(complex)).astype(np.clongdouble)
        z = np.clongdouble(sk)
        a = Kl + z * z * Ml + z * Cl
        for _ in range(3):
            x = x + sl.lu_solve(lu, (Fl - a @ x).astype(complex)).astype(np.clongdouble)
        out.append((Ol @ x).astype(complex))
    return np.stack(out, axis=-1)
