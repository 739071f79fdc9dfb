"""The modal basis of a plant, the damping projected on it, and the one test of classical damping.

- :func:`modal_basis`: the mass-normalised undamped modes of a :class:`~vibss.linear.plant.plant.Plant`
  (:func:`~vibss.linear.eigen.undamped.undamped` on its free DOFs), with the low modes refined to
  relative accuracy where a light damping would amplify their error; computed once per plant;
- :func:`projected_damping`: ``Phi^T C Phi`` and ``Phi^T H Phi`` on that basis, computed once per
  plant and basis and kept in the plant's cache (the plant is frozen, so it never goes stale). The
  frequency kernels (``modal``, ``complex_modal``), ``auto``'s choice (classical damping, the
  complex-mode risk), the frequency grid's damping estimate and the modal state space all need it;
  :func:`damping_factors` and :func:`damping_rank` give the same as an exact low-rank product;
- :func:`classical_damping` and :func:`damping_coupling`: whether the projected damping is diagonal
  (classical), the one test damped modes, frequency and time responses share;
- :func:`proportional`: ``C = a M + b K`` (or ``H``) read off the matrices themselves, where the
  projection is known without one (``Phi^T C Phi = a I + b Omega^2``).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial
from typing import Any, cast

import numpy as np
import scipy.linalg as sl
import scipy.sparse as sp

from ...results import ReadOnly
from .checks import fast_matrix, stiffness_solver
from .undamped import undamped
from ..plant.plant import Plant

__all__ = ["ModalBasis", "modal_basis", "REFINE_TOL", "projected_damping", "damping_factors", "damping_rank",
           "classical_damping", "damping_coupling", "CLASSICAL_RTOL", "proportional", "PROPORTIONAL_RTOL",
           "classical_by_construction", "nonzero"]


@dataclass(frozen=True, eq=False)
class ModalBasis(ReadOnly):
    """Undamped modes of a plant's free DOFs.

    Attributes
    ----------
    omega2 : (n,) ndarray
        Squared natural frequencies [rad^2/s^2], ascending; exactly 0 for rigid-body modes.
    phi : (n, n) ndarray
        Mass-normalised mode shapes (columns), ``phi.T @ M @ phi = I``.
    rigid : (n,) bool ndarray
        Rigid-body (zero-frequency) modes.
    scale : (n,) ndarray
        State scaling S [rad/s]: omega, or the lowest elastic omega for rigid modes.
    error : (n,) ndarray or None
        Relative error bound of each frequency (NaN for rigid modes), see :func:`error_estimate`.
    method : str
        Eigen-solver used (see :func:`undamped`).
    """

    omega2: np.ndarray
    phi: np.ndarray
    rigid: np.ndarray
    scale: np.ndarray
    error: np.ndarray | None = None
    method: str = ""

    @property
    def omega(self) -> np.ndarray:
        """(n,) natural frequencies [rad/s]."""
        return np.sqrt(self.omega2)


def modal_basis(plant: Plant) -> ModalBasis:
    """Mass-normalised undamped modes of the free DOFs (:func:`undamped` on the plant).

    Uses the plant's stiffness factor ``Kf`` when it has one (exact on badly scaled models). On the
    ``eigh`` path (large models) a mode is also refined when its error estimate, amplified at its
    resonance by ``1 / 2 zeta`` (from the diagonal of ``Phi^T C Phi`` and ``Phi^T H Phi``), would
    exceed :data:`REFINE_TOL` in the FRF.

    Parameters
    ----------
    plant : Plant

    Returns
    -------
    ModalBasis
        Computed once per plant (the plant is frozen; repeated FRF calls on it share it).
    """
    return cast(ModalBasis, plant.cached("modal basis", lambda: _modal_basis(plant)))


def _modal_basis(plant: Plant) -> ModalBasis:
    # the modes a light resonance would amplify are refined in undamped's own sweep (one inverse
    # iteration, one Ritz step for both needs)
    # K factorised at most once per plant: the refinement and the static solves of the
    # mode-acceleration form (:func:`vibss.frequency.terms.static`) share the plant's "solve K"
    def solve(b: np.ndarray) -> np.ndarray:
        return plant.cached("solve K", lambda: stiffness_solver(plant.K))(b)
    spec = undamped(plant.K, plant.M, plant.Kf, also=partial(_needs_refinement, plant),
                    solve=None if sp.issparse(plant.K) else solve)
    w2, phi, rigid, est, method = spec.omega2, spec.phi, spec.rigid, spec.error, spec.method
    elastic = np.sqrt(w2[~rigid & (w2 > 0)])
    floor = float(elastic.min()) if elastic.size else 1.0
    # a zero w2 the rigid test did not flag (issue 18's fuzzer: a free motion whose stiffness norms
    # are both round-off) must not divide the realization by zero
    scale = np.where(rigid | ~(w2 > 0), floor, np.sqrt(np.maximum(w2, 0.0)))
    return ModalBasis(w2, phi, rigid, scale, est, method)


REFINE_TOL = 1e-10
"""Refine a low mode when its predicted relative FRF error at resonance exceeds this."""


def _needs_refinement(plant: Plant, w2: np.ndarray, phi: np.ndarray, est: np.ndarray,
                      level: np.ndarray | None = None) -> np.ndarray:
    """Modes whose error estimate, amplified at their resonance, would exceed :data:`REFINE_TOL`.

    At resonance a damping ratio zeta_r amplifies a relative frequency error by 1 / (2 zeta_r);
    zeta_r comes from the diagonal of Phi^T C Phi (and eta_r / 2 from Phi^T H Phi). ``level``
    [rad^2/s^2] is the absolute error of each shape's coupling to the others (default
    ``eps w2_max``, ``eigh``'s); a coupling ``e`` between modes r and s shows in the response by
    ``e / max(|w2_r - w2_s| / 2, 2 zeta_r w2_r)`` to first order, so the modes up to ``2 e /
    REFINE_TOL`` above the highest one flagged are flagged too: refined together, their coupling goes.
    """
    w2c = np.maximum(w2, np.finfo(float).tiny)
    zeta = np.full(w2.shape, 1e-6)
    for key, hyst in (("C", False), ("H", True)):
        mat = getattr(plant, key)
        if np.any(mat):
            ab = proportional(plant, key)     # a + b w2 on mass-normalised modes: no product
            g = ab[0] + ab[1] * np.maximum(w2, 0.0) if ab is not None else \
                np.einsum("ij,ij->j", phi, plant.cached(f"sparse {key}", partial(fast_matrix, mat)) @ phi)
            zeta = np.maximum(zeta, g / (2 * w2c) if hyst else g / (2 * np.sqrt(w2c)))
    # a shape's first-order error (eps w2_max / w2 of eigh) shows at resonance: through a damping
    # that couples the modes, and, with a M + b K, through the residual's components along a mode
    # within the half-power band (a close pair: the Rayleigh quotient removes the diagonal part only)
    if level is None:
        level = np.full(w2.shape, np.finfo(float).eps * float(np.max(w2)))
    need = np.maximum(np.nan_to_num(est, nan=0.0), level / w2c) / (2 * np.minimum(zeta, 0.5)) > REFINE_TOL
    if np.any(need):
        top = int(np.flatnonzero(need).max())
        reach = 2 * np.maximum(float(np.max(level[:top + 1])), level[top:]) / REFINE_TOL    # pairwise
        need[top:] |= w2[top:] <= w2[top] + reach
    return need


CLASSICAL_RTOL = 1e-10
"""Damping is classical when every off-diagonal of Phi^T C Phi is below this times sqrt(g_ii g_jj)."""


def damping_coupling(projected: np.ndarray) -> np.ndarray:
    """How far each off-diagonal of a projected damping matrix exceeds the classical bound.

    The one test of classical damping that damped modes, frequency and time responses share: modes
    i and j are coupled when ``|g_ij| > CLASSICAL_RTOL * sqrt(|g_ii g_jj|) + 64 eps max|g_kk|``
    (the second term is the round-off of ``Phi^T C Phi`` itself).

    Parameters
    ----------
    projected : (k, k) ndarray
        ``Phi^T C Phi`` (or ``Phi^T H Phi``) with mass-normalised shapes.

    Returns
    -------
    (k, k) ndarray
        Off-diagonal magnitude minus its bound: positive where modes are coupled (diagonal negative).
    """
    d = np.abs(np.diag(projected))
    off = np.abs(projected - np.diag(np.diag(projected)))
    bound = CLASSICAL_RTOL * np.sqrt(np.outer(d, d)) + 64 * np.finfo(float).eps * d.max(initial=0.0)
    return off - bound - np.diag(np.ones_like(d))




def projected_damping(plant: Plant, basis: ModalBasis) -> tuple[np.ndarray, np.ndarray]:
    """``Phi^T C Phi`` and ``Phi^T H Phi`` on the modes ``basis.phi`` (zeros when absent), cached.

    Parameters
    ----------
    plant : Plant
        Its ``C`` and ``H`` (dense or scipy.sparse) are projected.
    basis : ModalBasis
        Undamped modes of the plant (columns ``phi``, n x k).

    Returns
    -------
    gamma, eta : (k, k) ndarray
        Projected viscous [1/s] and hysteretic [1/s^2] damping, symmetrised, read-only (copy
        before changing them). The same objects for the same plant and basis.

    Examples
    --------
    >>> from ... import Body, Model, Mount, MountType
    >>> from ..plant.build import build_plant
    >>> m = Model([Body("b", 4.0, [1, 1, 1])], [Mount("m", MountType("t", [1e3] * 3, [8.0] * 3), "b")])
    >>> p = build_plant(m, ["b.fz"], ["b.z"])
    >>> b = modal_basis(p)
    >>> g, h = projected_damping(p, b)
    >>> round(float(g[-1, -1]), 12), projected_damping(p, b)[0] is g      # c / m for a z mode
    (2.0, True)
    """
    # the basis is kept in the cached value, so its id cannot be reused while the entry lives
    return plant.cached(f"projected damping {id(basis)}", partial(_project, plant, basis))[1]


PROPORTIONAL_RTOL = 64 * np.finfo(float).eps
"""``C = a M + b K`` holds when every entry ``(i, j)`` of ``C - a M - b K`` is within this times
``|a| sqrt(M_ii M_jj) + |b| sqrt(K_ii K_jj)``: each mount adds a positive semi-definite block, so the
magnitudes summed into an entry of ``K`` are at most ``sqrt(K_ii K_jj)`` (Cauchy-Schwarz), and the
assembly's rounding of ``C = beta K`` mount by mount stays a few dozen eps of that, entry by entry,
whatever the units or the grading of the DOFs."""

PROPORTIONAL_BLOCK = 2**21
"""Entries of a dense matrix handled at once by :func:`proportional` (16 MB temporaries, not n^2)."""


def proportional(plant: Plant, key: str = "C") -> tuple[float, float] | None:
    """``(a, b)`` with the plant's ``C`` (``key="C"``, a [1/s], b [s]) or ``H`` (``"H"``, a [1/s^2], b [-])
    equal to ``a M + b K`` to the assembly's rounding (:data:`PROPORTIONAL_RTOL`), else None.

    Damping proportional to stiffness in every mount (``c = beta k``, a loss factor ``H = eta K``) and
    Rayleigh damping are classical by construction: on mass-normalised modes ``Phi^T C Phi = a I + b
    Omega^2``, known without the projection's two ``n^2 k`` GEMMs (0.017 s of a 0.20 s time response
    at 600 DOF). ``C = b K`` and ``C = a M`` are tried first (exact zeros); else the pair is fitted by
    least squares on the entries (the Frobenius Gram of ``M`` and ``K``, each scaled to unit norm) and
    refused when it inflates (``|a| max M_ii + |b| max K_ii`` over 4 ``max C_ii``, which a non-negative
    pair never passes). Every candidate is then verified entry by entry, so a wrong fit only costs the
    projection. Cost: a few passes over the three matrices' entries, by blocks of rows. Cached on the
    plant.

    Parameters
    ----------
    plant : Plant
    key : {"C", "H"}

    Returns
    -------
    (float, float) or None
    """
    return cast("tuple[float, float] | None", plant.cached(f"proportional {key}", partial(_proportional, plant, key)))


def nonzero(a: Any) -> bool:
    """Whether a plant matrix (dense, scipy.sparse or None) has a nonzero entry."""
    if a is None:
        return False
    return bool(a.count_nonzero()) if sp.issparse(a) else bool(np.any(a))


def classical_by_construction(plant: Plant) -> bool:
    """Whether ``C`` and ``H`` are each zero or ``a M + b K`` (:func:`proportional`): classical
    damping known from the matrices, before and without the modes."""
    return all(not nonzero(getattr(plant, key)) or proportional(plant, key) is not None for key in ("C", "H"))


def _row_blocks(mats: list[Any], n: int) -> list[tuple[slice, list[Any]]]:
    """The matrices by blocks of rows: sparse ones (CSR) whole, dense ones :data:`PROPORTIONAL_BLOCK`
    entries at a time."""
    if any(sp.issparse(x) for x in mats):
        csr = [sp.csr_matrix(x) for x in mats]
        return [(slice(0, n), csr)]
    step = max(1, PROPORTIONAL_BLOCK // max(n, 1))
    return [(slice(i, min(i + step, n)), [np.asarray(x, float)[i:i + step] for x in mats]) for i in range(0, n, step)]


def _proportional(plant: Plant, key: str) -> tuple[float, float] | None:
    mats = [getattr(plant, k) for k in ("M", "K", key)]
    if any(x is None for x in mats) or plant.n == 0:
        return None
    n = plant.n
    blocks = _row_blocks(mats, n)
    sparse = sp.issparse(blocks[0][1][0])

    def inner(i: int, j: int) -> float:
        return float(sum((b[i].multiply(b[j]).sum() if sparse else np.einsum("ij,ij->", b[i], b[j]))
                         for _, b in blocks))

    diag = [np.abs(np.asarray(x.diagonal() if sp.issparse(x) else np.diag(np.asarray(x)), float)) for x in mats]
    root = [np.sqrt(d) for d in diag[:2]]
    nm, nk = np.sqrt(inner(0, 0)), np.sqrt(inner(1, 1))
    if not (nm > 0 and nk > 0 and np.isfinite(nm * nk)):
        return None
    mk, mc, kc = inner(0, 1), inner(0, 2), inner(1, 2)

    def holds(a: float, b: float) -> bool:
        if not abs(a) * diag[0].max() + abs(b) * diag[1].max() <= 4 * diag[2].max():
            return False                            # an inflated fit (M and K nearly parallel)
        for rows, (m, k, c) in blocks:
            rest = c - a * m - b * k
            if sparse:
                q = sp.coo_matrix(rest)
                i, j, r = q.row, q.col, np.abs(q.data)
            else:
                i, j, r = slice(None), slice(None), np.abs(rest)
                ra, rb = root[0][rows], root[1][rows]
            bound = (abs(a) * root[0][i] * root[0][j] + abs(b) * root[1][i] * root[1][j]) if sparse else \
                abs(a) * np.outer(ra, root[0]) + abs(b) * np.outer(rb, root[1])
            if not np.all(r <= PROPORTIONAL_RTOL * bound):
                return False
        return True

    for a, b in ((0.0, kc / nk**2), (mc / nm**2, 0.0)):       # C = b K, C = a M: exact zeros
        if holds(a, b):
            return a, b
    gram = np.array([[1.0, mk / (nm * nk)], [mk / (nm * nk), 1.0]])
    coef = np.linalg.lstsq(gram, np.array([mc / nm, kc / nk]), rcond=1e-12)[0]
    a, b = float(coef[0] / nm), float(coef[1] / nk)
    return (a, b) if holds(a, b) else None


def _project(plant: Plant, basis: ModalBasis) -> tuple[ModalBasis, tuple[np.ndarray, np.ndarray]]:
    phi = basis.phi
    k = phi.shape[1]
    out = []
    for key in ("C", "H"):
        mat = getattr(plant, key)
        if nonzero(mat):
            ab = proportional(plant, key)
            if ab is not None:      # a I + b Omega^2 on mass-normalised modes: no projection
                g = np.diag(ab[0] + ab[1] * np.where(basis.rigid, 0.0, np.maximum(basis.omega2, 0.0)))
            else:
                g = phi.T @ (plant.cached(f"sparse {key}", partial(fast_matrix, mat)) @ phi)
                g = 0.5 * (g + g.T)
        else:
            g = np.zeros((k, k))
        g.setflags(write=False)
        out.append(g)
    return basis, (out[0], out[1])


def damping_factors(plant: Plant, basis: ModalBasis) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The damping as a low-rank product on the modes: ``Phi^T (C + i H / s) Phi = U (Zc + Zh / s) U^T``.

    Dampers live in mounts: with the plant's :class:`~vibss.linear.plant.plant.MountForm`, every mount
    with a viscous or hysteretic part contributes the three columns ``Phi^T B_p^T`` of its
    deflection map and its (3, 3) damping blocks, and the rest of ``C`` and ``H`` (mounts with a
    zero stiffness axis, rotational parts, added damping) the rows of the DOFs it touches, with its
    own block. Without a mount form the DOFs that ``C`` or ``H`` touch are used directly. No
    factorisation is made (no rank is guessed): the product is exact.

    Parameters
    ----------
    plant : Plant
        Its ``C`` and ``H`` (dense or scipy.sparse), and ``mounts`` when it matches the plant.
    basis : ModalBasis
        Undamped modes of the plant (columns ``phi``, n x k).

    Returns
    -------
    U : (k, r) ndarray
        The modes' deflections at the dampers [m, rad per unit modal coordinate].
    Zc : (r, r) ndarray
        Viscous damping of those deflections [N s/m] (block diagonal, symmetric).
    Zh : (r, r) ndarray
        Hysteretic stiffness [N/m] (block diagonal, symmetric; zeros when absent).

    Examples
    --------
    >>> from ... import Body, Model, Mount, MountType
    >>> from ..plant.build import build_plant
    >>> t = MountType("t", [1e3] * 3, [8.0] * 3)
    >>> m = Model([Body("b", 4.0, [1, 1, 1])], [Mount("m", t, "b"), Mount("n", MountType("u", [1e3] * 3), "b", at=[1, 0, 0])])
    >>> p = build_plant(m, ["b.fz"], ["b.z"])
    >>> u, zc, zh = damping_factors(p, modal_basis(p))
    >>> u.shape, bool(np.allclose(u @ zc @ u.T, projected_damping(p, modal_basis(p))[0]))   # one damped mount
    ((6, 3), True)
    """
    return plant.cached(f"damping factors {id(basis)}", partial(_factors, plant, basis))[1]


def _dense(mat: Any) -> np.ndarray:
    return mat.toarray() if sp.issparse(mat) else np.asarray(mat, dtype=float)


def _touched(mats: list[Any], n: int) -> np.ndarray:
    """Indices of the DOFs (rows) that any of ``mats`` touches."""
    hit = np.zeros(n, bool)
    for mat in mats:
        if sp.issparse(mat):
            coo = sp.coo_matrix(mat)
            hit[coo.row[coo.data != 0]] = True
        else:
            hit |= np.any(np.asarray(mat) != 0, axis=1)
    return np.flatnonzero(hit)


def _pieces(plant: Plant) -> tuple[Any, np.ndarray, np.ndarray, list[Any], np.ndarray]:
    """Where the damping sits: the plant's mount form (None when it does not match), its damped
    mounts, its per-axis mounts, the rest of ``C`` and ``H`` and the DOFs that rest touches."""
    form = plant.mounts
    if form is not None and form.matches(plant):
        damped = np.flatnonzero(np.any(form.cp != 0, axis=(1, 2)) | np.any(form.hp != 0, axis=(1, 2)))
        axes = np.flatnonzero((form.ca != 0) | (form.ha != 0))        # the mounts kept apart per axis
        rest = [form.C, form.H]
    else:
        form, damped, axes, rest = None, np.zeros(0, int), np.zeros(0, int), [plant.C, plant.H]
    return form, damped, axes, rest, _touched(rest, plant.n)


def damping_rank(plant: Plant) -> int:
    """The number of columns of :func:`damping_factors`' ``U`` (3 per damped mount, one per damped
    mount axis kept apart, one per DOF the rest of the damping touches), counted without forming
    it: ``auto`` costs the low-rank update by it (:mod:`vibss.frequency.methods`), and forming ``U``
    (a product with every mode) only to count its columns cost 0.08-0.10 s at 600 DOF.

    Parameters
    ----------
    plant : Plant

    Returns
    -------
    int
    """
    def count() -> int:
        _, damped, axes, _, idx = _pieces(plant)
        return 3 * damped.size + axes.size + idx.size

    return plant.cached("damping rank", count)


def _factors(plant: Plant, basis: ModalBasis) -> tuple[ModalBasis, tuple[np.ndarray, np.ndarray, np.ndarray]]:
    phi = basis.phi
    cols: list[np.ndarray] = []          # (k, r_i) blocks of U
    zc: list[np.ndarray] = []
    zh: list[np.ndarray] = []
    form, damped, axes, rest, idx = _pieces(plant)
    if form is not None:
        if damped.size:
            rows = (3 * damped[:, None] + np.arange(3)).ravel()
            cols.append(np.asarray(form.B[rows] @ phi).T)
            zc.append(sl.block_diag(*form.cp[damped]))
            zh.append(sl.block_diag(*form.hp[damped]))
        if axes.size:
            cols.append(np.asarray(form.Ba[axes] @ phi).T)
            zc.append(np.diag(form.ca[axes]))
            zh.append(np.diag(form.ha[axes]))
    if idx.size:
        cols.append(phi[idx].T)
        zc.append(_dense(rest[0])[np.ix_(idx, idx)])
        zh.append(_dense(rest[1])[np.ix_(idx, idx)])
    if not cols:
        k = phi.shape[1]
        out = (np.zeros((k, 0)), np.zeros((0, 0)), np.zeros((0, 0)))
    else:
        c, h = sl.block_diag(*zc), sl.block_diag(*zh)
        out = (np.hstack(cols), 0.5 * (c + c.T), 0.5 * (h + h.T))
    for a in out:
        a.setflags(write=False)
    return basis, out


def classical_damping(plant: Plant, basis: ModalBasis | None = None,
                      projected: tuple[np.ndarray, np.ndarray] | None = None) -> tuple[bool, str]:
    """Whether ``Phi^T C Phi`` and ``Phi^T H Phi`` are diagonal (classical damping), and why not.

    Parameters
    ----------
    plant : Plant
    basis : ModalBasis or None
        Undamped modes (computed if None).
    projected : (Phi^T C Phi, Phi^T H Phi) or None
        The projected damping matrices, if already computed.

    Returns
    -------
    ok : bool
    reason : str
    """
    basis = basis or modal_basis(plant)
    projected = projected or projected_damping(plant, basis)
    if classical_by_construction(plant):
        return True, "classical damping (C and H proportional to M and K: Phi^T C Phi and Phi^T H Phi diagonal)"
    for name, g in zip(("viscous damping", "hysteretic damping"), projected):
        if not np.any(g):
            continue
        excess = damping_coupling(g)
        if np.any(excess > 0):
            i, j = np.unravel_index(np.argmax(excess), excess.shape)
            return False, (f"{name} is not classical: modes {i + 1} and {j + 1} are coupled "
                           f"(Phi^T C Phi off-diagonal {abs(g[i, j]):.3g} vs diagonal {abs(g[i, i]):.3g}, "
                           f"{abs(g[j, j]):.3g})")
    return True, "classical damping (Phi^T C Phi and Phi^T H Phi diagonal)"
