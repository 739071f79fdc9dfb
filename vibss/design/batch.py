"""Many variants of a mount layout at once: their stiffness matrices and their checked frequencies.

Every variant's stiffness matrix is built at once (arrays over variants; a Python loop over mounts
only, :func:`batch_stiffness`), and :func:`batch_frequencies` turns the stacked problems
``K_v phi = w^2 M phi`` into standard ones with the Cholesky factor of the shared mass matrix and
solves them by one stacked ``eigh`` (:func:`~vibss.linear.eigen.small.symmetric_eigen`). Each
variant's frequencies come with a rigorous first-order bound of their rounding
(:func:`frequency_bound`), so a caller keeps the answers the bound certifies and sends the others
(graded models, rigid modes) to the one eigen path, :func:`vibss.modes`.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..linear.eigen.small import symmetric_eigen
from ..linear.plant.assemble import Assembly, assemble
from ..model.geometry import point_transfer
from ..model.model import Model
from .parameters import _ANGLE, _RATE, _RATIO, _SHIFT, Parameter, ratio_axes

__all__ = ["batch_stiffness", "batch_frequencies", "frequency_bound", "BATCH_RTOL"]

BATCH_RTOL = 1e-10
"""[-] The relative error of every frequency that a batched answer must be certified to (the eigen
path's own target, :data:`vibss.linear.eigen.undamped.FREQ_RTOL`); a variant whose bound exceeds it
is solved again by :func:`vibss.modes`."""


def _rxryrz(angle: np.ndarray) -> np.ndarray:
    """``R_x(a) R_y(b) R_z(c)`` of (..., 3) angles [rad] as (..., 3, 3) (scipy's intrinsic "XYZ")."""
    ca, cb, cc = np.cos(angle[..., 0]), np.cos(angle[..., 1]), np.cos(angle[..., 2])
    sa, sb, sc = np.sin(angle[..., 0]), np.sin(angle[..., 1]), np.sin(angle[..., 2])
    out = np.empty(angle.shape[:-1] + (3, 3))
    out[..., 0, 0], out[..., 0, 1], out[..., 0, 2] = cb * cc, -cb * sc, sb
    out[..., 1, 0] = ca * sc + sa * sb * cc
    out[..., 1, 1] = ca * cc - sa * sb * sc
    out[..., 1, 2] = -sa * cb
    out[..., 2, 0] = sa * sc - ca * sb * cc
    out[..., 2, 1] = sa * cc + ca * sb * sc
    out[..., 2, 2] = ca * cb
    return out


def variant_rates(model: Model, parameters: Sequence[Parameter], values: np.ndarray
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(nv, nm, 3) each: every variant's principal rates [N/m], mount shifts [m] and angles [rad],
    as :func:`~vibss.design.parameters.apply` sets them (ratios after rates)."""
    nv, nm = values.shape[0], len(model.mounts)
    index = {m.name: i for i, m in enumerate(model.mounts)}
    rates = np.broadcast_to(np.array([m.type.stiffness for m in model.mounts]).reshape(nm, 3), (nv, nm, 3)).copy()
    shift = np.zeros((nv, nm, 3))
    angle = np.zeros((nv, nm, 3))
    for i, p in enumerate(parameters):
        for mount, kind, factor in p.targets:
            q = index[mount]
            if kind in _RATE:
                rates[:, q, _RATE.index(kind)] = factor * values[:, i]
            elif kind in _SHIFT:
                shift[:, q, _SHIFT.index(kind)] += factor * values[:, i]
            elif kind in _ANGLE:
                angle[:, q, _ANGLE.index(kind)] += factor * values[:, i]
    for i, p in enumerate(parameters):            # ratios after rates: the denominator is final
        for mount, kind, factor in p.targets:
            if kind in _RATIO:
                num, den = ratio_axes(kind)
                rates[:, index[mount], num] = factor * values[:, i] * rates[:, index[mount], den]
    return rates, shift, angle


def batch_stiffness(model: Model, parameters: Sequence[Parameter], values: np.ndarray,
                    a: Assembly | None = None) -> np.ndarray:
    """(nv, n, n) stiffness matrix of every variant [N/m, N/rad, N m/rad].

    Parameters
    ----------
    model : Model
        Base model (shifts and angles measured from it); no coupled 6x6 mount matrices
        (:func:`~vibss.design.parameters.refuse_coupled`).
    parameters : sequence of Parameter
        The parameters.
    values : (nv, p) ndarray
        Parameter values of each variant [N/m, m, rad] (as :func:`~vibss.design.parameters.apply`).
    a : Assembly or None
        The base model's dense assembly, if already made.
    """
    a = assemble(model, sparse=False) if a is None else a
    nv = values.shape[0]
    nm, nb, n = len(model.mounts), len(model.bodies), a.n
    rates, shift, angle = variant_rates(model, parameters, values)
    t0 = np.array([m.orientation.matrix for m in model.mounts]).reshape(nm, 3, 3)
    t = np.broadcast_to(t0, (nv, nm, 3, 3)).copy()
    turned = np.flatnonzero(np.any(angle != 0, axis=(0, 2)))                       # mounts with angles
    if turned.size:
        t[:, turned] = _rxryrz(angle[:, turned]) @ t0[turned]
    kp = np.einsum("vpij,vpj,vpkj->vpik", t, rates, t)
    kr = np.array([m.type.rotational_stiffness for m in model.mounts]).reshape(nm, 3)
    krp = np.einsum("vpij,pj,vpkj->vpik", t, kr, t)                                # 6x6 mounts, turned too
    lb = point_transfer(a.r_b[None] + shift)                                      # (nv, nm, 3, 6)
    la = point_transfer(a.r_a[None] + shift)
    K = np.zeros((nv, n + a.nz, n + a.nz))
    for q in range(nm):                                                           # mounts, not variants
        sb = slice(6 * a.b_index[q], 6 * a.b_index[q] + 6)
        kb = kp[:, q] @ lb[:, q]
        lbt = lb[:, q].transpose(0, 2, 1)
        K[:, sb, sb] += lbt @ kb
        rb = slice(6 * a.b_index[q] + 3, 6 * a.b_index[q] + 6)
        ra = slice(6 * a.a_index[q] + 3, 6 * a.a_index[q] + 6)
        if np.any(kr[q]):                        # a 6x6 mount's rotational rates
            K[:, rb, rb] += krp[:, q]
            K[:, ra, ra] += krp[:, q]
            K[:, rb, ra] -= krp[:, q]
            K[:, ra, rb] -= krp[:, q]
        if a.a_index[q] >= nb:                   # to ground: the ground blocks are dropped below
            continue
        sa = slice(6 * a.a_index[q], 6 * a.a_index[q] + 6)
        ka = kp[:, q] @ la[:, q]
        lat = la[:, q].transpose(0, 2, 1)
        K[:, sa, sa] += lat @ ka
        K[:, sb, sa] -= lbt @ ka
        K[:, sa, sb] -= lat @ kb
    return K[:, :n, :n]


def frequency_bound(K: np.ndarray, li: np.ndarray, w2: np.ndarray) -> np.ndarray:
    """(nv, n) first-order bound of the relative error of each frequency of a stacked solve [-].

    Each variant's ``K`` is a sum of positive semi-definite mount terms ``K_p``, each entry a short
    sum of products, so its rounding satisfies ``|dK_ij| <= c eps sum_p |K_p,ij| <= c eps d_i d_j``
    with ``d = sqrt(diag K)`` (Cauchy-Schwarz over the mounts: no cancellation between mounts can
    hide). In the standard problem ``A = L^-1 K L^-T`` that is ``||dA|| <= c eps || |L^-1| d ||^2``;
    forming ``A`` and ``eigh`` (backward stable) add ``c n eps ||A|| <= c n eps trace(A)``. A
    symmetric perturbation moves every eigenvalue by at most its norm (Weyl), and
    ``|dw / w| = |dw2| / (2 w2)``. ``c = 10 n`` covers the sums' lengths with room.

    Parameters
    ----------
    K : (nv, n, n) ndarray
        Stiffness matrices [N/m ...].
    li : (n, n) ndarray
        Inverse Cholesky factor of the mass matrix, ``M^-1 = li^T li``.
    w2 : (nv, n) ndarray
        Computed eigenvalues [rad^2/s^2].

    Returns
    -------
    (nv, n) ndarray
        Relative error bound of each frequency (inf where ``w2 <= 0``).
    """
    n = K.shape[-1]
    d = np.sqrt(np.maximum(np.diagonal(K, axis1=1, axis2=2), 0.0))               # (nv, n)
    s = d @ np.abs(li).T                                                           # |L^-1| d per variant
    absolute = 10 * n * np.finfo(float).eps * (np.einsum("vi,vi->v", s, s) + np.abs(w2).sum(axis=1))
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = np.where(w2 > 0, 0.5 * absolute[:, None] / np.where(w2 > 0, w2, 1.0), np.inf)
    return rel


def batch_frequencies(model: Model, parameters: Sequence[Parameter], values: np.ndarray,
                      a: Assembly | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Every variant's natural frequencies by one stacked ``eigh``, and their certified bound.

    Parameters
    ----------
    model : Model
        Base model (see :func:`batch_stiffness`).
    parameters : sequence of Parameter
        The parameters.
    values : (nv, p) ndarray
        Parameter values of each variant [N/m, m, rad].
    a : Assembly or None
        The base model's dense assembly, if already made.

    Returns
    -------
    frequency_hz : (nv, n) ndarray
        Natural frequencies [Hz], ascending.
    bound : (nv, n) ndarray
        Relative error bound of each (:func:`frequency_bound`; inf where a mode may be rigid).

    Examples
    --------
    >>> import vibss
    >>> from vibss.design.parameters import parameters_of
    >>> m = vibss.load_example("powertrain")
    >>> f, b = batch_frequencies(m, parameters_of(m, ["engine.k3"]), np.array([[2e5], [3e5]]))
    >>> f.shape, bool(b.max() < BATCH_RTOL)
    ((2, 6), True)
    """
    a = assemble(model, sparse=False) if a is None else a
    K = batch_stiffness(model, parameters, values, a)
    li = np.linalg.inv(np.linalg.cholesky(a.dense("M")))
    w2, _ = symmetric_eigen(li @ K @ li.T)
    return np.sqrt(np.maximum(w2, 0.0)) / (2 * np.pi), frequency_bound(K, li, w2)
