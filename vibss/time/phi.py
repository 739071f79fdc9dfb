"""Closed-form exact discretisation of modal blocks: the phi functions of scalars and of 2x2 blocks.

The exact response of ``x' = A x + b g(tau)`` over a step ``h`` to polynomial forcing
``g = tau^k / k!`` is ``h^(k+1) phi_(k+1)(A h) b`` and the transition matrix is ``phi_0(A h) =
expm(A h)``, with ``phi_j(z) = sum_i z^i / (i + j)!``; a forcing ``exp(i omega tau)`` gives
``h exp(i omega h) phi_1((A - i omega) h) b``.

For a scalar (a complex mode) these are evaluated directly: a Taylor series (then the downward
recurrence ``phi_j = z phi_(j+1) + 1/j!``) for ``|z| < 1``, the upward recurrence
``phi_(j+1) = (phi_j - 1/j!) / z`` from ``exp(z)`` beyond. For a 2x2 block ``X = A h`` every function
is ``f(X) = alpha I + beta X`` (Cayley-Hamilton); with ``z1, z2`` the eigenvalues of ``X``:

- spectral radius <= 1: ``X^i = p_i I + q_i X`` with ``p_(i+1) = -det q_i``, ``q_(i+1) = p_i + tr q_i``
  (only the trace and determinant: no cancellation, exact for defective blocks such as the double
  integrator of a rigid mode, and for critical damping);
- beyond: Sylvester's formula ``beta = (f(z1) - f(z2)) / (z1 - z2)``, ``alpha = (z1 f(z2) - z2 f(z1)) /
  (z1 - z2)``, whose round-off is about ``eps rho / |z1 - z2|``: blocks with ``|z1 - z2| <`` :data:`SEPARATION`
  ``rho`` (damping ratio within about 1e-5 of 1 *and* ``omega h > 1``) are flagged for
  ``scipy.linalg.expm``.
"""

from __future__ import annotations

from math import factorial

import numpy as np

__all__ = ["phi_scalar", "phi_pair", "SEPARATION"]

SEPARATION = 1e-2
"""Smallest relative eigenvalue separation ``|z1 - z2| / max|z|`` of a 2x2 block (spectral radius
above 1) evaluated by Sylvester's formula; closer pairs are left to ``expm``."""

_TERMS = 30   # Taylor terms for |z| <= 1: 1/30! ~ 4e-33


def _terms(rho: float, order: int) -> int:
    """Taylor terms of ``phi_order`` for ``|z| <= rho < 1``: the remainder after term ``N`` is below
    ``rho^(N+1) / (N+1+order)! / (1 - rho)``; the first ``N`` where that is under 1e-17 of
    ``1 / order!`` (short steps of slow modes need a few terms, not 30)."""
    if rho == 0.0:
        return 0
    bound = factorial(order) / (1.0 - rho)
    for n in range(_TERMS):
        bound *= rho / (n + 1 + order)
        if bound < 1e-17:
            return n
    return _TERMS


def phi_scalar(z: np.ndarray, order: int) -> np.ndarray:
    """``phi_0(z) .. phi_order(z)`` of complex scalars.

    Parameters
    ----------
    z : (n,) array_like
        Arguments (dimensionless, ``lambda h``).
    order : int
        Highest ``j``.

    Returns
    -------
    (order + 1, n) complex ndarray

    Examples
    --------
    >>> float(phi_scalar(np.array([0.0]), 2)[2, 0].real)
    0.5
    """
    z = np.asarray(z, complex).reshape(-1)
    out = np.empty((order + 1, z.size), complex)
    small = np.abs(z) < 1.0
    if small.any():
        zs = z[small]
        top = np.zeros_like(zs)
        for i in range(_terms(float(np.abs(zs).max()), order), -1, -1):   # Horner: sum_i zs^i / (i + order)!
            top = top * zs + 1.0 / factorial(i + order)
        out[order, small] = top
        for j in range(order - 1, -1, -1):
            out[j, small] = zs * out[j + 1, small] + 1.0 / factorial(j)
    big = ~small
    if big.any():
        zb = z[big]
        out[0, big] = np.exp(zb)
        for j in range(order):
            out[j + 1, big] = (out[j, big] - 1.0 / factorial(j)) / zb
    return out


def phi_pair(tr: np.ndarray, det: np.ndarray, disc: np.ndarray, order: int,
             shift: complex = 0.0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``phi_j(X - shift I) = alpha_j I + beta_j X`` for 2x2 matrices ``X`` given by their invariants.

    Parameters
    ----------
    tr, det : (n,) array_like
        Trace and determinant of ``X`` (dimensionless, ``A h``).
    disc : (n,) array_like
        ``tr^2 / 4 - det``, computed by the caller in a form without cancellation.
    order : int
        Highest ``j``.
    shift : complex
        A scalar shift (``i omega h`` for sinusoidal forcing).

    Returns
    -------
    alpha, beta : (order + 1, n) complex ndarray
    ok : (n,) bool ndarray
        False where the eigenvalues are too close for Sylvester's formula (use ``expm`` there).
    """
    tr = np.asarray(tr, complex).reshape(-1) - 2 * shift
    det = np.asarray(det, complex).reshape(-1)
    det = det - shift * (np.asarray(tr) + 2 * shift) + shift * shift   # det(X - s) = det - s tr_X + s^2
    root = np.sqrt(np.asarray(disc, complex).reshape(-1))
    z1, z2 = tr / 2 + root, tr / 2 - root
    rho = np.maximum(np.abs(z1), np.abs(z2))
    n = tr.size
    alpha = np.empty((order + 1, n), complex)
    beta = np.empty((order + 1, n), complex)
    small = rho <= 1.0
    ok = np.ones(n, bool)
    if small.any():
        t, d = tr[small], det[small]
        p = np.empty((_TERMS + 1, t.size), complex)
        q = np.empty_like(p)
        p[0], q[0] = 1.0, 0.0
        for i in range(_TERMS):
            p[i + 1] = -d * q[i]
            q[i + 1] = p[i] + t * q[i]
        w = np.array([[1.0 / factorial(i + j) for i in range(_TERMS + 1)] for j in range(order + 1)])
        alpha[:, small] = w @ p
        beta[:, small] = w @ q
    big = ~small
    if big.any():
        a, b = z1[big], z2[big]
        sep = np.abs(a - b)
        good = sep >= SEPARATION * rho[big]
        ok[np.flatnonzero(big)[~good]] = False
        fa, fb = phi_scalar(a, order), phi_scalar(b, order)
        with np.errstate(divide="ignore", invalid="ignore"):
            diff = np.where(good, a - b, 1.0)
            beta[:, big] = (fa - fb) / diff
            alpha[:, big] = (a * fb - b * fa) / diff
    # the block is X - shift I: f(X - s) = alpha I + beta (X - s) = (alpha - s beta) I + beta X
    alpha -= shift * beta
    return alpha, beta, ok


def _invariants(A: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Trace, determinant and ``tr^2/4 - det`` of (nb, 2, 2) blocks (the last without ``tr^2``)."""
    a, b, c, d = A[:, 0, 0], A[:, 0, 1], A[:, 1, 0], A[:, 1, 1]
    return a + d, a * d - b * c, ((a - d) / 2) ** 2 + b * c


def foh_blocks(A: np.ndarray, steps: np.ndarray, degree: int) -> tuple[np.ndarray, np.ndarray]:
    """Exact discretisation of ``x' = A x + b g(tau)`` for polynomial ``g`` of ``degree``, closed form.

    Parameters
    ----------
    A : (nb, b, b) ndarray
        Per-mode blocks [1/s]: b = 1 (complex modes), or b = 2 (real, forcing into the second row).
    steps : (nh,) ndarray
        Step lengths [s].
    degree : int

    Returns
    -------
    E : (nh, nb, b, b) ndarray
        Transition matrices ``expm(A h)``.
    gamma : (nh, degree + 1, nb, b) ndarray
        ``gamma[:, k]`` = response at ``h`` to the forcing ``tau^k / k!`` (zero initial state).

    Examples
    --------
    >>> E, g = foh_blocks(np.array([[[0.0, 1.0], [0.0, 0.0]]]), np.array([0.5]), 1)   # double integrator
    >>> E[0, 0].tolist(), g[0, 1, 0].tolist()                                         # h^3/6, h^2/2
    ([[1.0, 0.5], [0.0, 1.0]], [0.020833333333333332, 0.125])
    """
    nb, b = A.shape[:2]
    E = np.empty((len(steps), nb, b, b), dtype=A.dtype)
    gam = np.empty((len(steps), degree + 1, nb, b), dtype=A.dtype)
    if b == 1:
        lam = A[:, 0, 0]
        for i, h in enumerate(steps):
            ph = phi_scalar(lam * h, degree + 1)
            E[i, :, 0, 0] = ph[0]
            for k in range(degree + 1):
                gam[i, k, :, 0] = ph[k + 1] * h ** (k + 1)
        return E, gam
    tr, det, disc = _invariants(A)
    bad = np.zeros(nb, bool)
    for i, h in enumerate(steps):
        al, be, ok = phi_pair(tr * h, det * h * h, disc * h * h, degree + 1)
        al, be = al.real, be.real
        bad |= ~ok
        E[i] = be[0][:, None, None] * (A * h)
        E[i, :, 0, 0] += al[0]
        E[i, :, 1, 1] += al[0]
        for k in range(degree + 1):
            hk = h ** (k + 1)
            gam[i, k, :, 0] = hk * be[k + 1] * A[:, 0, 1] * h
            gam[i, k, :, 1] = hk * (al[k + 1] + be[k + 1] * A[:, 1, 1] * h)
    if bad.any():
        E[:, bad], gam[:, :, bad] = foh_expm(A[bad], steps, degree)
    return E, gam


SMALL_ANGLE = 0.05
"""Below this ``omega h`` the sine response is not taken as ``(r(w) - r(-w)) / 2i`` (which loses
``eps / (omega h)``) but from a series or a form without cancellation (see :func:`cs_blocks`)."""


def cs_blocks(A: np.ndarray, steps: np.ndarray, omega: float) -> np.ndarray:
    """Exact response of ``x' = A x + b g(tau)`` over each step to ``g = cos(omega tau)`` and
    ``g = sin(omega tau)`` from rest, closed form: (nh, 2, nb, b).

    With ``r(w) = h exp(i w h) phi_1((A - i w) h) b``, the response to ``exp(i w tau)``, ``cos`` gives
    ``(r(w) + r(-w)) / 2``. For ``sin`` and ``theta = omega h`` below :data:`SMALL_ANGLE` (a slow sine on
    a short step), a scalar mode ``z = lam h`` uses the series ``h sum_k (-1)^k theta^(2k+1)
    phi_(2k+2)(z)`` for ``|z| < 1`` and ``h theta (z^2 phi_2(z) + theta^2 c2 + z theta^2 s3) / (z^2 +
    theta^2)`` (``c2 = (1 - cos theta) / theta^2``, ``s3 = (1 - sin theta / theta) / theta^2``) beyond;
    a real 2x2 block takes ``expm`` there (only rigid and nearly critical modes are 2x2 blocks).

    Parameters
    ----------
    A : (nb, b, b) ndarray
        As :func:`foh_blocks` [1/s].
    steps : (nh,) ndarray
        Step lengths [s].
    omega : float
        Angular frequency [rad/s].
    """
    nb, b = A.shape[:2]
    out = np.empty((len(steps), 2, nb, b), dtype=A.dtype)
    for i, h in enumerate(steps):
        theta = omega * h
        if b == 2:
            if theta < SMALL_ANGLE:
                out[i] = cs_expm(A, np.array([h]), omega)[0]
                continue
            tr, det, disc = _invariants(A)
            al, be, ok = phi_pair(tr * h, det * h * h, disc * h * h, 1, shift=1j * theta)
            r = h * np.exp(1j * theta) * np.stack([be[1] * A[:, 0, 1] * h, al[1] + be[1] * A[:, 1, 1] * h], axis=-1)
            out[i, 0], out[i, 1] = r.real, r.imag          # A real: cos and sin are Re and Im of r(w)
            if not ok.all():
                out[i][:, ~ok] = cs_expm(A[~ok], np.array([h]), omega)[0]
            continue
        z = A[:, 0, 0] * h
        rp = h * np.exp(1j * theta) * phi_scalar(z - 1j * theta, 1)[1]
        rm = h * np.exp(-1j * theta) * phi_scalar(z + 1j * theta, 1)[1]
        out[i, 0, :, 0] = (rp + rm) / 2
        if theta >= SMALL_ANGLE:
            out[i, 1, :, 0] = (rp - rm) / 2j
            continue
        sn = np.empty(nb, complex)
        small = np.abs(z) < 1.0
        if small.any():
            ph = phi_scalar(z[small], 16)
            sn[small] = h * sum((-1) ** k * theta ** (2 * k + 1) * ph[2 * k + 2] for k in range(8))
        if (~small).any():
            zb = z[~small]
            t2 = theta * theta
            c2 = 0.5 * (np.sin(theta / 2) / (theta / 2)) ** 2 if theta > 0 else 0.5
            s3 = 1 / 6 - t2 / 120 + t2**2 / 5040 - t2**3 / 362880 + t2**4 / 39916800
            sn[~small] = h * theta * (zb * zb * phi_scalar(zb, 2)[2] + t2 * c2 + zb * t2 * s3) / (zb * zb + t2)
        out[i, 1, :, 0] = sn
    return out


def foh_expm(A: np.ndarray, steps: np.ndarray, degree: int) -> tuple[np.ndarray, np.ndarray]:
    """:func:`foh_blocks` by ``scipy.linalg.expm`` of the block augmented with the polynomial chain
    (the reference, and the fallback for nearly defective blocks with ``omega h > 1``)."""
    import scipy.linalg as sl

    nb, b, _ = A.shape
    size = b + degree + 1
    E = np.empty((len(steps), nb, b, b), dtype=A.dtype)
    gam = np.empty((len(steps), degree + 1, nb, b), dtype=A.dtype)
    for i, h in enumerate(steps):
        aug = np.zeros((nb, size, size), dtype=A.dtype)
        aug[:, :b, :b] = A * h
        aug[:, b - 1, b] = 1.0
        for k in range(degree):
            aug[:, b + k, b + k + 1] = 1.0
        ex = sl.expm(aug)
        E[i] = ex[:, :b, :b]
        for k in range(degree + 1):
            gam[i, k] = ex[:, :b, b + k] * h ** (k + 1)
    return E, gam


def cs_expm(A: np.ndarray, steps: np.ndarray, omega: float) -> np.ndarray:
    """:func:`cs_blocks` by ``scipy.linalg.expm`` of the block augmented with the harmonic oscillator
    ``c' = -omega s``, ``s' = omega c`` (``cos`` from ``(c, s) = (1, 0)``, ``-sin`` from ``(0, 1)``)."""
    import scipy.linalg as sl

    nb, b, _ = A.shape
    out = np.empty((len(steps), 2, nb, b), dtype=A.dtype)
    for i, h in enumerate(steps):
        aug = np.zeros((nb, b + 2, b + 2), dtype=A.dtype)
        aug[:, :b, :b] = A * h
        aug[:, b - 1, b] = h
        aug[:, b, b + 1] = -omega * h
        aug[:, b + 1, b] = omega * h
        ex = sl.expm(aug)
        out[i, 0] = ex[:, :b, b]
        out[i, 1] = -ex[:, :b, b + 1]
    return out
