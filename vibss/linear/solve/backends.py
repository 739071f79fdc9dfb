"""The back-ends of the exact solve (:mod:`vibss.linear.solve.exact`): one function per way of factorising.

Each takes ``(plant, s, rhs, rows=None)`` -- ``rhs(part)`` gives the right-hand sides ``(k, n, m)``
of the frequencies ``s[part]``, ``rows`` the DOFs to keep of each solution -- and returns the DOF
solutions ``(nf, n, m)`` (``(nf, len(rows), m)``) and a ``(nf,)`` mask of the frequencies where the
matrix is exactly singular (a zero pivot; solutions there are zeros).

Frequency-dependent mounts add ``g_tau(s) K_tau`` per relaxation time (:func:`vibss.linear.plant.branches.groups`).

- :func:`_dense`: LAPACK LU of the assembled ``K + iH + sC + s^2 M``, batched for a small plant (its
  certified complex-mode solutions first, :mod:`vibss.linear.solve.certified`), one frequency at a
  time from :data:`LOOP_DOFS` DOFs;
- :func:`_banded`: RCM ordering and LAPACK ``zgbsv`` (:mod:`vibss.linear.solve.banded`);
- :func:`_superlu`: :func:`scipy.sparse.linalg.splu`;
- :func:`_mounts`: the mounts kept apart (:class:`~vibss.linear.plant.plant.MountForm`), their forces
  unknowns of their own.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from functools import partial
from typing import Any

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spl
from scipy.linalg.lapack import dgbsv, zgbsv

from ...methods import Method
from .banded import structure
from ..plant.branches import groups
from .certified import CERTIFY_TOL, applies, certified_states, modal_inverse
from .refine import (ASSEMBLED_ORDER, PIVOT_THRESHOLD, STALLED, Contraction, assembled_lu, mounts_product,
                     record_backward_error, refine)
from ..plant.plant import Plant

__all__ = ["SOLVERS", "SolveBackend", "LOOP_DOFS", "MOUNTS_DENSE_MAX", "MOUNTS_ORDER", "ASSEMBLED_ORDER",
           "PIVOT_THRESHOLD", "dynamic_stiffness", "certified_note"]

MOUNTS_DENSE_MAX = 300
"""The mounts' system (n + 3 q unknowns) is solved by dense LU up to this size; above, the assembled
matrix's SuperLU refined in the mounts' form (:mod:`vibss.linear.solve.refine`)."""

MOUNTS_ORDER = "COLAMD"
"""SuperLU's column ordering of the mounts' saddle system (where the refinement of the assembled LU
does not converge; refined itself the same way, which removes the ordering's effect on the digits:
the saddle LU alone was 1e-6 off an extended-precision reference at 0.18 mHz on a 6,000-DOF tower)."""

_CHUNK_BYTES = 64 * 2**20
"""Memory per batch of the dense back-end."""


_KEEP_DOFS = 150
"""Plants up to this many DOFs keep their dense ``K + iH``, ``C``, ``M`` in their cache (a few
hundred kilobytes at most; a larger one converts per call rather than hold another n x n)."""


def _make_dense_terms(plant: Plant) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    mats = {k: (getattr(plant, k).toarray() if sp.issparse(getattr(plant, k)) else getattr(plant, k))
            for k in ("K", "H", "C", "M")}
    k0 = mats["K"] + 1j * mats["H"] if np.any(mats["H"]) else mats["K"]
    for a in (k0, mats["C"], mats["M"]):
        a.flags.writeable = False       # the plant's own arrays already are; new ones made so
    return k0, mats["C"], mats["M"]


def _dense_terms(plant: Plant) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Dense ``(K + iH, C, M)`` of a small plant, found once (the plant is frozen)."""
    return plant.cached("dense K + iH, C, M", lambda: _make_dense_terms(plant))


def dynamic_stiffness(k0: np.ndarray, c: np.ndarray, m: np.ndarray, s: np.ndarray) -> np.ndarray:
    """``A(s) = k0 + s C + s^2 M`` at each Laplace value, (nf, n, n) complex.

    On the imaginary axis (``s = i w``, every frequency response) it is built as its real part
    ``Re k0 - w^2 M`` and imaginary part ``Im k0 + w C`` in real arithmetic: the same bits as the
    complex expression (whose ``s C`` and ``s^2 M`` have exactly zero real and imaginary parts
    there, so each entry is the same one rounding of the same operands) at about half the work;
    ``tests/linear/test_small_model_overhead.py`` compares the two.

    Parameters
    ----------
    k0 : (n, n) ndarray
        ``K + iH`` [N/m] (real without hysteretic damping).
    c, m : (n, n) ndarray
        Damping [N s/m] and mass [kg] matrices.
    s : (nf,) complex ndarray
        Laplace values [rad/s].

    Returns
    -------
    (nf, n, n) complex ndarray
    """
    if s.size and not np.any(s.real):
        w = s.imag[:, None, None]
        out = np.empty((s.size,) + c.shape, dtype=complex)
        parts = out.view(float).reshape(out.shape + (2,))
        re, im = parts[..., 0], parts[..., 1]
        np.multiply(w * w, m, out=re)
        np.subtract(k0.real, re, out=re)
        np.multiply(w, c, out=im)
        if np.iscomplexobj(k0):
            np.add(k0.imag, im, out=im)
        return out
    sc = s[:, None, None]
    return k0[None] + sc * c[None] + sc**2 * m[None]


def _dense(plant: Plant, s: np.ndarray, rhs: Callable[[slice], np.ndarray],
           rows: np.ndarray | None = None, certify: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """Dense LU: batched by numpy below :data:`LOOP_DOFS`, one LAPACK call per frequency from it
    (:func:`_dense_each`); the solutions where ``A(s)`` is exactly singular come back as zeros, flagged;
    only the DOFs ``rows`` of each solution are kept (all by default).

    A small plant on the imaginary axis first takes its complex-mode solutions where their backward
    error is at LU's level, frequency by frequency (:mod:`vibss.linear.solve.certified`; ``certify=False``
    skips them); the LU solves the frequencies that miss."""
    k0, c, m = _dense_terms(plant) if plant.n <= _KEEP_DOFS else _make_dense_terms(plant)
    if certify and plant.n <= _KEEP_DOFS and applies(plant, s):
        r_all = rhs(slice(None))
        got = certified_states(plant, s, r_all, k0, c, m)
        if got is not None:
            x, bad = got[0], np.zeros(s.size, dtype=bool)
            miss = np.flatnonzero(~got[1])
            if miss.size:                           # the LU where the certificate missed

                def part_of(part: slice) -> np.ndarray:
                    return r_all[miss[part]]
                x[miss], bad[miss] = _dense(plant, s[miss], part_of, None, certify=False)
            return (x if rows is None else x[:, rows]), bad

        def asked(part: slice, r_all: np.ndarray = r_all) -> np.ndarray:    # the right-hand sides asked once
            return r_all[part]
        rhs = asked
    relax = [g if not sp.issparse(g.K) else replace(g, K=g.K.toarray()) for g in groups(plant)]
    n = plant.n
    if n >= LOOP_DOFS:
        return _dense_each(k0, c, m, relax, s, rhs, rows)
    chunk = max(1, _CHUNK_BYTES // (16 * max(n, 1) ** 2))
    if not relax and s.size <= chunk:      # one batch (every small model): no chunk bookkeeping
        dyn = dynamic_stiffness(k0, c, m, s)
        try:
            x = np.linalg.solve(dyn, rhs(slice(None)))
            return (x if rows is None else x[:, rows]), np.zeros(s.size, dtype=bool)
        except np.linalg.LinAlgError:      # some frequency exactly singular: the loop below
            pass
    xs, bad = [], np.zeros(s.size, dtype=bool)
    for lo in range(0, s.size, chunk):
        part = slice(lo, lo + chunk)
        dyn = dynamic_stiffness(k0, c, m, s[part])
        for g in relax:
            dyn += g.factor(s[part])[:, None, None] * g.K[None]
        r = rhs(part)
        try:
            x = np.linalg.solve(dyn, r)
        except np.linalg.LinAlgError:      # some frequency exactly singular: one by one
            x = np.zeros(r.shape, dtype=complex)
            for k in range(dyn.shape[0]):
                try:
                    x[k] = np.linalg.solve(dyn[k], r[k])
                except np.linalg.LinAlgError:
                    bad[lo + k] = True
        xs.append(x if rows is None else x[:, rows])
    return np.concatenate(xs), bad


LOOP_DOFS = 100
"""Plants from this many DOFs are solved by :func:`_dense_each` (one LAPACK ``zgesv`` per frequency on
a matrix built in place), smaller ones by numpy's batched LU (fewer calls: 0.73x at 40 DOFs the other
way round; 1.35-1.5x faster at 150-600 DOFs, the same bits: ``benchmarks/bench_dense_loop.py``)."""


def _dense_each(k0: np.ndarray, c: np.ndarray, m: np.ndarray, relax: list[Any], s: np.ndarray,
                rhs: Callable[[slice], np.ndarray], rows: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The dense LU frequency by frequency: ``A(s)`` written straight into one Fortran-ordered buffer
    (its transpose's C order, so a non-symmetric plant is solved as it is) and factorised there by
    LAPACK ``zgesv``, the routine numpy's batched solve calls on its own copy of each matrix: the
    same matrix, pivots and solution, without the ``(chunk, n, n)`` stack of :func:`dynamic_stiffness`
    and numpy's copy of it (two passes over memory per frequency saved; the buffer stays in cache).
    Exactly singular frequencies (a zero pivot, ``info > 0``) come back as zeros, flagged; only the
    DOFs ``rows`` of each solution are kept (all by default)."""
    from scipy.linalg.lapack import zgesv

    n, nf = c.shape[0], s.size
    r_all = rhs(slice(None))
    x = np.zeros((nf, n if rows is None else len(rows), r_all.shape[2]), dtype=complex)
    bad = np.zeros(nf, dtype=bool)
    a = np.empty((n, n), dtype=complex, order="F")
    parts = a.T.view(float).reshape(n, n, 2)            # a.T is C-ordered: a.T[j, i] = A[i, j]
    re, im = parts[..., 0], parts[..., 1]
    kr = np.ascontiguousarray(k0.real.T)
    ki = np.ascontiguousarray(k0.imag.T) if np.iscomplexobj(k0) else None
    ct, mt = np.ascontiguousarray(c.T), np.ascontiguousarray(m.T)
    gt = [np.ascontiguousarray(g.K.T) for g in relax]
    gf = [g.factor(s) for g in relax]
    on_axis = not np.any(s.real)
    for i, sk in enumerate(s):
        if on_axis:                                     # the same roundings as dynamic_stiffness
            w = sk.imag
            np.multiply(w * w, mt, out=re)
            np.subtract(kr, re, out=re)
            np.multiply(w, ct, out=im)
            if ki is not None:
                np.add(ki, im, out=im)
        else:
            a.T[...] = (k0.T if ki is not None else kr) + sk * ct + (sk * sk) * mt
        for g, f in zip(gt, gf):
            a.T[...] += f[i] * g
        _, _, xi, info = zgesv(a, r_all[i], overwrite_a=1)
        if info > 0:
            bad[i] = True
        else:
            x[i] = xi if rows is None else xi[rows]
    return x, bad


def certified_note(plant: Plant, nf: int) -> str:
    """What the dense exact solve of ``plant`` at ``nf`` frequencies (> 0 Hz) does beside its LU: the
    certified complex-mode solutions (:mod:`vibss.linear.solve.certified`), or ``""`` where it does not
    try them (too large or too few frequencies, frequency-dependent mounts, nearly dependent
    eigenvectors such as undamped rigid-body modes). The caller asks only where the assembled form
    solves every frequency (:func:`vibss.linear.solve.exact.mounts_form_possible` is false)."""
    if sp.issparse(plant.K) or not applies(plant, np.zeros(nf, dtype=complex)):
        return ""
    return plant.cached("certified note", lambda: "" if modal_inverse(plant, *_dense_terms(plant)) is None else (
        "complex-mode solutions kept at each frequency where their backward error "
        f"||b - A x|| / (||A|| ||x|| + ||b||) is at most n eps = {CERTIFY_TOL * plant.n * np.finfo(float).eps:.1e} "
        "(LU's level; checked at every frequency), the batched LU at the others"))


def _banded(plant: Plant, s: np.ndarray, rhs: Callable[[slice], np.ndarray],
            rows: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """RCM-ordered banded LU (``zgbsv``), ``K + iH + sC + s^2 M (+ g(s) K_tau)`` built per frequency
    by one GEMM of its coefficients against the stacked band parts; only the DOFs ``rows`` of each
    solution are kept (all by default)."""
    st = plant.cached("band structure", lambda: structure(plant))
    parts, band, perm = st.parts, st.band, st.perm
    relax = [(f"G{j}", g) for j, g in enumerate(groups(plant))]
    inv = np.argsort(perm)
    if rows is not None:                    # where the kept DOFs sit in the band's order
        inv = inv[rows]
    r_all = rhs(slice(None))
    # force inputs only: the same right-hand side (a broadcast view) at every s, reordered once
    fixed = np.asfortranarray(r_all[0][perm]) if s.size and r_all.strides[0] == 0 else None
    x = np.zeros((s.size, inv.size, r_all.shape[2]), dtype=complex)
    bad = np.zeros(s.size, dtype=bool)
    shape = (3 * band + 1, plant.n)
    if (not relax and "C" not in parts and "H" not in parts and not np.any(s.real)
            and not np.any(r_all.imag if np.iscomplexobj(r_all) else 0.0)):
        return _banded_real(parts["K"], parts["M"], band, perm, inv, shape, s, r_all, fixed)
    # each frequency's band by one real GEMM of its coefficients' real and imaginary parts against the
    # stacked band parts, written below LAPACK's fill rows; the band is stored transposed (n, 3b+1),
    # so its transpose is the Fortran band (3b+1, n) that zgbsv takes
    keys = [key for key in ("K", "M", "C", "H") if key in parts] + [key for key, _ in relax]
    stack = np.stack([np.ascontiguousarray(parts[key].T) for key in keys]).reshape(len(keys), -1)
    coef = np.empty((s.size, len(keys)), complex)
    for j, key in enumerate(keys):
        coef[:, j] = {"K": 1.0, "M": s * s, "C": s, "H": 1j}.get(key, 0.0)
    for j, (_, g) in enumerate(relax):
        coef[:, len(keys) - len(relax) + j] = g.factor(s)
    c2 = np.ascontiguousarray(np.stack([coef.real, coef.imag], axis=1))      # (nf, 2, parts)
    n, width = plant.n, shape[0]
    two = np.empty((2, stack.shape[1]))
    ab = np.empty((n, width), dtype=complex)
    abv = ab.view(float).reshape(n, width, 2)
    for i in range(s.size):
        np.dot(c2[i], stack, out=two)
        ab[:, :band] = 0.0                              # LAPACK's room for the pivoting fill
        abv[:, band:, 0] = two[0].reshape(n, width - band)
        abv[:, band:, 1] = two[1].reshape(n, width - band)
        b = fixed.copy(order="F") if fixed is not None else np.asfortranarray(r_all[i][perm])
        _, _, xi, info = zgbsv(band, band, ab.T, b, overwrite_ab=1, overwrite_b=1)
        if info > 0:
            bad[i] = True
        else:
            x[i] = xi[inv]
    return x, bad


def _banded_real(k: np.ndarray, m: np.ndarray, band: int, perm: np.ndarray, inv: np.ndarray,
                 shape: tuple[int, int], s: np.ndarray, r_all: np.ndarray,
                 fixed: np.ndarray | None) -> tuple[np.ndarray, np.ndarray]:
    """The same banded LU in real arithmetic (``dgbsv``): an undamped model on the imaginary axis
    has the real matrix ``K - w^2 M`` and, under forces, a real right-hand side. The same pivots and
    digits as ``zgbsv`` on it, at a quarter of the flops. ``inv``: the band positions of the DOFs kept."""
    x = np.zeros((s.size, inv.size, r_all.shape[2]), dtype=complex)
    bad = np.zeros(s.size, dtype=bool)
    fixed_re = None if fixed is None else np.asfortranarray(fixed.real)
    for i, sk in enumerate(s):
        ab = np.empty(shape, dtype=float, order="F")
        ab[:band] = 0.0                                 # LAPACK's room for the pivoting fill
        np.multiply(m, (sk * sk).real, out=ab[band:])
        ab[band:] += k
        b = fixed_re.copy(order="F") if fixed_re is not None else np.asfortranarray(r_all[i][perm].real)
        _, _, xi, info = dgbsv(band, band, ab, b, overwrite_ab=1, overwrite_b=1)
        if info > 0:
            bad[i] = True
        else:
            x[i] = xi[inv]
    return x, bad


def _superlu(plant: Plant, s: np.ndarray, rhs: Callable[[slice], np.ndarray],
             rows: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """SuperLU (COLAMD ordering) per frequency; only the DOFs ``rows`` kept (all by default)."""
    mats = {k: plant.cached(f"csc {k}", partial(sp.csc_matrix, getattr(plant, k))) for k in ("K", "H", "C", "M")}
    relax = [replace(g, K=sp.csc_matrix(g.K)) for g in groups(plant)]
    r_all = rhs(slice(None))
    x = np.zeros(r_all.shape, dtype=complex)
    bad = np.zeros(s.size, dtype=bool)
    for i, sk in enumerate(s):
        a = mats["K"] + sk * sk * mats["M"]
        if mats["C"].nnz:
            a = a + sk * mats["C"]
        if mats["H"].nnz:
            a = a + 1j * mats["H"]
        for g in relax:
            a = a + complex(g.factor(np.array(sk))) * g.K
        try:
            x[i] = spl.splu(sp.csc_matrix(a, dtype=complex)).solve(r_all[i])
        except RuntimeError:                              # "Factor is exactly singular"
            bad[i] = True
    return (x if rows is None else x[:, rows]), bad


def _mounts(plant: Plant, s: np.ndarray, rhs: Callable[[slice], np.ndarray],
            rows: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The solve in the mounts' forces (:class:`~vibss.linear.plant.plant.MountForm`), per frequency
    (only the DOFs ``rows`` of each solution kept; all by default).

    With ``lam = Z(s) B x`` (``Z = k_p + s c_p + i h_p`` per mount) as unknowns,

        [ R(s)  B^T      ] [x  ]   [r]
        [ B    -Z(s)^-1  ] [lam] = [0],   R(s) = K_rest + i H_rest + s C_rest + s^2 M,

    whose entries are masses, lever arms and compliances: nothing large is summed, so LU with
    partial pivoting keeps the soft modes that the assembled ``K`` loses. The system is scaled
    symmetrically first (:func:`_equilibrate`). Dense LU up to :data:`MOUNTS_DENSE_MAX` unknowns.

    Larger: SuperLU of the assembled ``A(s)`` (:data:`ASSEMBLED_ORDER`), refined with the residual
    computed in the mounts' form (:mod:`vibss.linear.solve.refine`): n unknowns, not n + 3 q, and
    the digits the assembled LU loses are recovered (a 6,000-DOF soft tower: 4e-15 from an
    extended-precision reference where SuperLU of the saddle system above was 1e-6 off). A frequency
    where the refinement does not converge takes SuperLU of the saddle system, refined the same way.
    """
    form = plant.mounts
    assert form is not None
    fb = form.rows                                  # the mount forces' B
    n, q3 = plant.n, fb.shape[0]
    m_csr = plant.cached("csr M", lambda: sp.csr_matrix(plant.M))
    bt = fb.T.tocsr()
    r_all = rhs(slice(None))
    x = np.zeros(r_all.shape, dtype=complex)
    bad = np.zeros(s.size, dtype=bool)
    dense = n + q3 <= MOUNTS_DENSE_MAX
    if dense:
        bd, btd, md = fb.toarray(), bt.toarray(), m_csr.toarray()
        kd, cd, hd = form.K.toarray(), form.C.toarray(), form.H.toarray()
    else:
        bat = form.Ba.T.tocsr() if form.Ba is not None and form.Ba.shape[0] else None
        b_t = form.B.T.tocsr()
    zeros = np.zeros((q3, r_all.shape[2]), dtype=complex)
    hint = Contraction()
    for i, sk in enumerate(s):
        if not dense:
            z = form.z_blocks(sk)
            if z is None:
                bad[i] = True
                continue
        else:
            r = np.vstack([r_all[i], zeros])
            zi = form.z_inverse(sk)
            if zi is None:
                bad[i] = True
                continue
            a = np.zeros((n + q3, n + q3), dtype=complex)
            a[:n, :n] = kd + 1j * hd + sk * cd + sk * sk * md
            a[:n, n:], a[n:, :n] = btd, bd
            a[n:, n:] = -zi
            d = _equilibrate(form, fb, np.diag(a[:n, :n]), sk)
            try:
                x[i] = d[:n, None] * np.linalg.solve(d[:, None] * a * d[None, :], d[:, None] * r)[:n]
            except np.linalg.LinAlgError:
                bad[i] = True
            continue
        apply = mounts_product(form, m_csr, b_t, bat, sk)
        try:                    # the assembled LU, refined by the residual in the mounts' form
            got, _, ok = refine(assembled_lu(plant, sk), apply, r_all[i], hint)
        except RuntimeError:                              # "Factor is exactly singular"
            ok = False
        if ok:
            x[i] = got
            record_backward_error(plant, sk, r_all[i], got, apply)      # the check reads it: no solve again
            continue
        lay = plant.cached("mounts layout", lambda: _Layout.of(form, m_csr))   # else the saddle system,
        a, top = lay.matrix(z, sk)                                              # refined the same way
        d = _equilibrate(form, fb, top, sk)
        a.data *= d[lay.row] * d[lay.col]
        try:
            saddle = spl.splu(a, permc_spec=MOUNTS_ORDER)
        except RuntimeError:
            bad[i] = True
            continue

        def solve(b: np.ndarray, saddle: Any = saddle, d: np.ndarray = d) -> np.ndarray:
            return d[:n, None] * saddle.solve(d[:, None] * np.vstack([b, zeros[:, :b.shape[1]]]))[:n]
        x[i], left, ok = refine(solve, apply, r_all[i])
        # stalled at A(s)'s own conditioning (a damped ultra-soft resonance): kept, the stall recorded
        stall = left if not ok and left <= STALLED else 0.0
        bad[i] = not (ok or stall)      # singular (0 Hz with a free motion, a resonance): the caller's limit path
        if not bad[i]:
            record_backward_error(plant, sk, r_all[i], x[i], apply, stall)
    return (x if rows is None else x[:, rows]), bad


@dataclass(frozen=True, eq=False)
class _Layout:
    """The mounts' system ``[[R(s), B^T], [B, -Z(s)^-1]]`` as one CSC pattern, laid out once per plant:
    where each term's entries go (``pos``), so a frequency only sums values into ``data``.

    Attributes
    ----------
    indptr, indices : ndarray
        The CSC pattern of the (N, N) system, N = n + rows of B.
    row, col : ndarray
        Row and column of each stored entry (for the symmetric scaling).
    terms : dict of str to (ndarray, ndarray)
        ``"K"``, ``"H"``, ``"C"``, ``"M"``, ``"BT"``, ``"B"``: positions and values of each term.
    diag : dict of str to ndarray
        The diagonals of ``K``, ``H``, ``C``, ``M`` (the scaling reads ``diag R(s)``).
    zpos, apos : ndarray
        Positions of the 3 x 3 blocks of ``Z^-1`` (row-major per mount) and of the per-axis scalars.
    """

    indptr: np.ndarray
    indices: np.ndarray
    row: np.ndarray
    col: np.ndarray
    terms: dict
    diag: dict
    zpos: np.ndarray
    apos: np.ndarray
    size: int

    @classmethod
    def of(cls, form: Any, m_csr: Any) -> _Layout:
        """The layout of ``form``'s system (``m_csr`` the plant's mass matrix, CSR)."""
        n = m_csr.shape[0]
        fb = sp.coo_matrix(form.rows)
        big = n + fb.shape[0]
        q = form.kp.shape[0]
        parts = {k: sp.coo_matrix(a) for k, a in (("K", form.K), ("H", form.H), ("C", form.C), ("M", m_csr))}
        parts = {k: a for k, a in parts.items() if a.nnz or k == "K"}
        keys: dict[str, tuple[np.ndarray, np.ndarray]] = {
            k: (a.col.astype(np.int64) * big + a.row, a.data) for k, a in parts.items()}
        keys["BT"] = ((fb.row.astype(np.int64) + n) * big + fb.col, fb.data)
        keys["B"] = (fb.col.astype(np.int64) * big + fb.row + n, fb.data)
        base = n + 3 * np.arange(q)
        zr = (base[:, None, None] + np.arange(3)[None, :, None]) + 0 * np.arange(3)[None, None, :]
        zc = (base[:, None, None] + np.arange(3)[None, None, :]) + 0 * np.arange(3)[None, :, None]
        zkey = zc.ravel().astype(np.int64) * big + zr.ravel()
        ax = n + 3 * q + np.arange(fb.shape[0] - 3 * q)
        akey = ax.astype(np.int64) * big + ax
        every = np.unique(np.concatenate([k for k, _ in keys.values()] + [zkey, akey]))
        col, row = every // big, every % big
        indptr = np.concatenate([[0], np.cumsum(np.bincount(col, minlength=big))])
        terms = {k: (np.searchsorted(every, key), val) for k, (key, val) in keys.items()}
        diag = {k: a.diagonal() for k, a in (("K", form.K), ("H", form.H), ("C", form.C), ("M", m_csr))}
        return cls(indptr, row.astype(np.int32), row, col, terms, diag, np.searchsorted(every, zkey),
                   np.searchsorted(every, akey), big)

    def matrix(self, z: tuple[np.ndarray, np.ndarray], s: complex) -> tuple[Any, np.ndarray]:
        """The system at ``s`` (CSC; ``z`` from :meth:`~vibss.linear.plant.plant.MountForm.z_blocks` at ``s``) and ``diag R(s)``."""
        coef = {"K": 1.0, "H": 1j, "C": s, "M": s * s, "BT": 1.0, "B": 1.0}
        data = np.zeros(self.row.size, dtype=complex)
        for k, (pos, val) in self.terms.items():
            data[pos] += coef[k] * val
        zi, za = z
        data[self.zpos] -= zi.ravel()
        data[self.apos] -= za
        top = sum(coef[k] * d for k, d in self.diag.items())
        a = sp.csc_matrix((data, self.indices, self.indptr), shape=(self.size, self.size))
        return a, np.asarray(top)


def _equilibrate(form: Any, rows: Any, top: np.ndarray, sk: complex) -> np.ndarray:
    """Symmetric diagonal scaling of the mounts' system: ``|diag A(s)|^-1/2`` on the DOFs
    (``A = R + B^T Z B``; ``top`` is ``diag R(s)``, ``rows`` the mount forces' ``B``), ``|Z_pp|^1/2``
    on the mount forces, so both diagonals are ~ 1. Measured on the instrument: 1.7e-8 unscaled,
    2e-14 scaled."""
    zd = form.z_diagonal(sk)
    bz = np.asarray(abs(rows).power(2).T @ zd).ravel()           # diag(B^T |Z| B), no cancellation
    dx = 1.0 / np.sqrt(np.maximum(np.abs(top) + bz, np.finfo(float).tiny))
    return np.concatenate([dx, np.sqrt(zd)])


@dataclass(frozen=True)
class SolveBackend(Method):
    """A way of factorising the dynamic stiffness per frequency: ``kernel(plant, s, rhs, keep) -> (x, bad)``.

    Attributes
    ----------
    sparse_ok : bool
        Takes a plant with sparse matrices.
    form : str
        The form it solves: ``"assembled"`` (``K + iH + sC + s^2 M``) or ``"mounts"`` (the mounts
        kept apart, :class:`~vibss.linear.plant.plant.MountForm`).
    """

    sparse_ok: bool = False
    form: str = "assembled"


SOLVERS: dict[str, SolveBackend] = {b.name: b for b in (
    SolveBackend("dense", _dense, exact=True, summary="dense LU of the assembled matrix (batched; per frequency from LOOP_DOFS)"),
    SolveBackend("banded", _banded, exact=True, sparse_ok=True,
                 summary="banded LU in a bandwidth-reducing order (LAPACK gbsv)"),
    SolveBackend("superlu", _superlu, exact=True, sparse_ok=True, summary="sparse LU (SuperLU) per frequency"),
    SolveBackend("mounts", _mounts, exact=True, sparse_ok=True, form="mounts",
                 summary="the mounts' form, equilibrated: stiff links beside soft mounts keep their digits"),
)}
"""The exact solve's back-ends as Method objects (the choice among them: :func:`vibss.linear.solve.exact.states`)."""
