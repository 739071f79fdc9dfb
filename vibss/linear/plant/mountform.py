"""The plant's stiffness and damping as a sum over its mounts (:class:`~vibss.linear.plant.plant.MountForm`),
and the facts that choose between it and the assembled matrices (stiffness ratio, free motions).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp
from scipy.linalg import lapack

from .assemble import Assembly
from .plant import MountForm

__all__ = ["mount_form", "FREE_MOTION_CHECK_MAX"]


def mount_form(asm: Assembly, free: np.ndarray, source: tuple, extra_c: Any = None) -> MountForm | None:
    """The plant's ``K, C, H`` as a sum over its mounts (:class:`~vibss.linear.plant.plant.MountForm`).

    Parameters
    ----------
    asm : Assembly
        The assembled model.
    free : (n,) int ndarray
        Free body DOFs (indices into ``asm.dofs``).
    source : tuple
        The plant's ``(K, C, H, M)``.
    extra_c : (n, n) array_like or None
        Damping not from the mounts (modal damping).

    Returns
    -------
    MountForm or None
        None when no mount with a positive-definite stiffness touches a free DOF.
    """
    n_body = asm.n
    every = free.size == n_body and bool(np.all(free == np.arange(n_body)))       # no column to drop
    b = asm.deflection_matrix()[:, :n_body]
    b = sp.csr_matrix(b if every else b[:, free])
    q = len(asm.b_index)
    if q == 0:
        return None
    lam = np.linalg.eigvalsh(0.5 * (asm.kp + asm.kp.transpose(0, 2, 1)))          # (q, 3)
    rows = np.diff(b.indptr).reshape(q, 3).sum(axis=1)
    # positive definite beyond round-off: an inclined zero-stiffness axis leaves lam.min ~ eps lam.max
    # > 0, and its Z(s) is singular (issue 18's fuzzer: LinAlgError in the mounts' solve)
    apart = (lam.min(axis=1) > 1e3 * np.finfo(float).eps * lam.max(axis=1)) & (rows > 0)
    # the others with diagonal local matrices are kept apart per local axis, their stiff axes only:
    # assembled, a stiff axis rounds the zero axis beside it at its own level (issue 18's fuzzer:
    # a 2 g body free along such an axis lost 1.5e-8 of its FRF at 0.1 Hz)
    mounts = asm.model.mounts
    axial = ~apart & (rows > 0)
    for p in np.flatnonzero(axial).tolist():  # only the mounts not kept apart whole are asked
        axial[p] = not mounts[p].type.coupled and bool(np.any(np.asarray(mounts[p].type.stiffness) > 0))
    if not apart.any() and not axial.any():
        return None
    idx = (3 * np.flatnonzero(apart)[:, None] + np.arange(3)).ravel()
    rest_mounts = ~apart & ~axial
    rest = (3 * np.flatnonzero(rest_mounts)[:, None] + np.arange(3)).ravel()
    br = b[rest]
    ax = _axes(mounts, b, np.flatnonzero(axial))

    def assembled(blocks: np.ndarray) -> sp.csr_matrix:
        if rest.size == 0:
            return sp.csr_matrix((free.size, free.size))
        return sp.csr_matrix(br.T @ sp.block_diag(list(blocks[rest_mounts])) @ br)

    def rotational(blocks: np.ndarray, coupling: np.ndarray | None = None) -> sp.csr_matrix:
        """6x6 mounts' rotational parts (and full matrices' coupling), assembled with the rest."""
        out = sp.csr_matrix((free.size, free.size))
        if not np.any(blocks) and (coupling is None or not np.any(coupling)):
            return out
        rr = sp.csr_matrix(asm.rotation_matrix()[:, :n_body][:, free])
        if np.any(blocks):
            out = sp.csr_matrix(rr.T @ sp.block_diag(list(blocks)) @ rr)
        if coupling is not None and np.any(coupling):
            x = sp.csr_matrix(b.T @ sp.block_diag(list(coupling)) @ rr)     # B^T kc R: both mounts' sides
            out = sp.csr_matrix(out + x + x.T)
        return out

    c_rest = assembled(asm.cp) + rotational(asm.crp, asm.ccp)
    if ax.c0.size:                                # the zero axes' dampers: one rank-1 term each
        c_rest = c_rest + sp.csr_matrix(ax.b0.T @ sp.diags(ax.c0) @ ax.b0)
    if extra_c is not None:
        c_rest = sp.csr_matrix(c_rest + sp.csr_matrix(extra_c))
    k_top = max(float(lam[apart].max()) if apart.any() else 0.0, float(ax.k.max()) if ax.k.size else 0.0)
    kept = b if idx.size == b.shape[0] else b[idx]         # every mount kept apart: all rows, no slicing
    return MountForm(B=kept, kp=asm.kp[apart], cp=asm.cp[apart], hp=asm.hp[apart],
                     K=sp.csr_matrix(assembled(asm.kp) + rotational(asm.krp, asm.kcp)), C=sp.csr_matrix(c_rest),
                     H=assembled(asm.hp), source=source,
                     stiffness_ratio=k_top / _softest(lam[rows > 0]),
                     inertia_w2=_inertia_w2(asm, free, kept, lam[apart].max(axis=1), source[3], ax.b, ax.k),
                     Ba=ax.b, ka=ax.k, ca=ax.c, ha=ax.h)


@dataclass(frozen=True)
class _Axes:
    """Rows of the mounts kept apart per local axis: ``b`` (r, n) deflections along their stiff axes
    with stiffness ``k`` [N/m], damping ``c`` [N s/m] and hysteretic stiffness ``h`` [N/m]; ``b0``, ``c0``
    the zero-stiffness axes that have a damper."""

    b: sp.csr_matrix
    k: np.ndarray
    c: np.ndarray
    h: np.ndarray
    b0: sp.csr_matrix
    c0: np.ndarray


def _axes(mounts: Sequence[Any], b: sp.csr_matrix, which: np.ndarray) -> _Axes:
    """Each mount in ``which`` in its local axes (their matrices diagonal there): ``T^T B_p`` per axis."""
    n = b.shape[1]
    stiff: list[tuple[sp.csr_matrix, float, float, float]] = []
    zero: list[tuple[sp.csr_matrix, float]] = []
    for p in which:
        t = mounts[p].type
        local = sp.csr_matrix(mounts[p].orientation.matrix.T) @ b[3 * p:3 * p + 3]
        k, c = np.asarray(t.stiffness, dtype=float), np.asarray(t.damping, dtype=float)
        h = k * np.asarray(t.loss_factor, dtype=float)
        for a in range(3):
            if k[a] > 0:
                stiff.append((local[a], k[a], c[a], h[a]))
            elif c[a] > 0:
                zero.append((local[a], c[a]))

    def stack(parts: list) -> sp.csr_matrix:
        return sp.csr_matrix(sp.vstack([x[0] for x in parts])) if parts else sp.csr_matrix((0, n))
    return _Axes(b=stack(stiff), k=np.array([x[1] for x in stiff], dtype=float),
                 c=np.array([x[2] for x in stiff], dtype=float), h=np.array([x[3] for x in stiff], dtype=float),
                 b0=stack(zero), c0=np.array([x[1] for x in zero], dtype=float))


FREE_MOTION_CHECK_MAX = 150
"""Plants up to this many free DOFs are checked for free motions when their mounts' form is built
(larger ones keep ``inertia_w2 = 0``: the stiffness ratio alone chooses their form)."""


def _free_motion(asm: Assembly, free: np.ndarray) -> bool:
    """Whether the mounts leave a motion of the free DOFs unrestrained: the stiffness factor's
    smallest singular value at round-off of its largest (or fewer rows than DOFs)."""
    factor = asm.stiffness_factor()
    every = free.size == asm.n and bool(np.all(free == np.arange(asm.n)))
    g = factor.toarray() if every else factor[:, free].toarray()
    if g.shape[0] < g.shape[1]:
        return True
    if _held(asm, free, g, every):
        return False
    sv = np.linalg.svd(g, compute_uv=False)
    return bool(sv[-1] <= g.shape[0] * np.finfo(float).eps * sv[0])


HELD_MARGIN = 1e6
"""How far above the free-motion threshold the Cholesky bound of :func:`_held` must put the smallest
singular value of the factor (squared) before the SVD is skipped."""


def _held(asm: Assembly, free: np.ndarray, g: np.ndarray, every: bool = False) -> bool:
    """Whether the Cholesky factor of the assembled ``K`` (free DOFs) *proves* that no motion is free,
    so that :func:`_free_motion` needs no SVD of the factor ``G`` (150 DOF: about 1 ms against 3 ms).

    With ``K = L L^T`` computed, ``lambda_min(L L^T) = 1 / ||L^-1||_2^2 >= 1 / ||L^-1||_F^2``; ``L L^T``
    is the assembled ``K`` within ``gamma_(n+1) ||L||_F^2`` (the Cholesky's backward error), and that
    is ``G^T G`` within ``gamma_m || |G|^T |G| ||`` (the sums of the assembly), both at most
    ``(n + m + 2) eps ||G||_F^2`` (``trace(L L^T) = trace K``). So ``sigma_min(G)^2`` is at least
    ``lower = 1 / (2 ||L^-1||_F^2) - 4 (n + m + 2) eps ||G||_F^2`` (a factor 2 and 4 for the
    rounding of ``L^-1`` and of the norms), and ``sigma_max^2 <= ||G||_F^2``: the SVD's test
    ``sigma_min <= m eps sigma_max`` cannot hold when ``lower`` exceeds :data:`HELD_MARGIN` times
    ``(m eps)^2 ||G||_F^2``. A Cholesky that fails or a bound below that: False (the SVD decides)."""
    m, n = g.shape
    eps = float(np.finfo(float).eps)
    k = asm.dense("K") if every else asm.dense("K")[np.ix_(free, free)]
    try:
        low = np.linalg.cholesky(k)
    except np.linalg.LinAlgError:
        return False
    inv, info = lapack.dtrtri(low, lower=1)
    if info != 0 or not np.all(np.isfinite(inv)):
        return False
    g2 = float(np.einsum("ij,ij->", g, g))
    lower = 0.5 / float(np.einsum("ij,ij->", inv, inv)) - 4 * (n + m + 2) * eps * g2
    return bool(lower > HELD_MARGIN * (m * eps) ** 2 * g2)


def _inertia_w2(asm: Assembly, free: np.ndarray, b: sp.csr_matrix, kmax: np.ndarray, mass: Any,
                b_axes: sp.csr_matrix | None = None, k_axes: np.ndarray | None = None) -> float:
    """:attr:`MountForm.inertia_w2` [rad^2/s^2]: ``max_p k_max,p lambda_max(B_p M^-1 B_p^T)`` over the
    mounts kept apart (``b``: their (3 q, n) deflection rows, ``kmax``: their largest principal
    stiffness [N/m]) when the mounts leave a motion free; 0 otherwise or above
    :data:`FREE_MOTION_CHECK_MAX` free DOFs.

    ``B_p M^-1 B_p^T`` [1/kg] is the compliance of the inertia a unit deflection of mount p moves
    (a moment of inertia counted at the mount's lever arm), so the value is units-independent: a
    frequency squared. A free motion is held by nothing but inertia, and the assembled ``K``'s
    round-off of its stiffest mounts swamps it at low frequencies: a 13 g body with no stiffness to
    ground, linked by 8e13 N/m to a free 4.6 t body, lost 1.6e-3 of its FRF at 1.9 Hz in the
    assembled form (issue 18's long run) while its stiffness ratio (3.7) chose that form."""
    if free.size == 0 or free.size > FREE_MOTION_CHECK_MAX or not _free_motion(asm, free):
        return 0.0
    m = mass.toarray() if sp.issparse(mass) else np.asarray(mass, dtype=float)
    bd = b.toarray()
    ba = np.zeros((0, free.size)) if b_axes is None else b_axes.toarray()
    try:
        x = np.linalg.solve(m, np.vstack([bd, ba]).T)                  # M^-1 [B; Ba]^T, (n, 3 q + r)
    except np.linalg.LinAlgError:
        return float(np.inf)
    q = kmax.size
    top = 0.0
    if q:
        comp = (bd @ x[:, :3 * q]).reshape(q, 3, q, 3)[np.arange(q), :, np.arange(q), :]     # (q, 3, 3) blocks
        lam = np.linalg.eigvalsh(0.5 * (comp + comp.transpose(0, 2, 1))).max(axis=1)
        top = float(np.max(kmax * np.maximum(lam, 0.0)))
    if ba.shape[0]:                                                      # per-axis rows: 1 x 1 blocks
        assert k_axes is not None
        top = max(top, float(np.max(k_axes * np.maximum(np.einsum("ij,ji->i", ba, x[:, 3 * q:]), 0.0))))
    return top


def _softest(lam: np.ndarray) -> float:
    """The smallest nonzero principal stiffness [N/m] of mounts (``lam``: (q, 3) eigenvalues of their
    ``kp``), zero axes (below round-off of their mount's largest) left out.

    The mounts' form pays off when the mounts kept apart are stiff *against any soft mount*, those
    with a zero axis (assembled with the rest) included: a 13 g body held by one single-axis
    4.6e5 N/m mount and linked by 8e13 N/m to a free 4.6 t body lost 5e-3 of its FRF in the
    assembled form while the links alone spanned a ratio of 3.7 (issue 18's long run)."""
    pos = lam[lam > 1e3 * np.finfo(float).eps * lam.max(axis=1, keepdims=True)]
    return float(pos.min()) if pos.size else float(lam.max())
