"""Complex modes of classically damped modes plus a few Maxwell branches, without the dense augmented matrix.

In the undamped modes of the plant's static stiffness (``Phi^T M Phi = I``, ``Phi^T K Phi = W^2``,
``Phi^T C Phi = diag(c)``: classical damping) with ``Bphi = B Phi`` (r x n, the branches'
deflections per mode), the branch forces ``f_i = k_i (delta_i - u_i)`` as states make the augmented
state matrix on ``x = [eta; eta'; f]``

    A = [[0,     I,           0      ],
         [-W^2,  -diag(c),    -Bphi^T],
         [0,     diag(k) Bphi, -diag(1/tau)]]

block-diagonal (the modes' 2x2 blocks and the branch relaxations ``-1/tau``) plus a coupling of
rank ``<= 2r``. An eigenpair ``A v = lam v`` has ``v = [eta; lam eta; f]`` with

    q(lam) eta = -Bphi^T f,    q_k(lam) = lam^2 + c_k lam + w_k^2,
    (lam + 1/tau) f = lam diag(k) Bphi eta,

so ``f`` solves the r x r *secular* system ``S(lam) f = 0``,
``S(lam) = diag((lam + 1/tau) / k) + lam Bphi diag(1 / q(lam)) Bphi^T`` (complex symmetric). Each
root is found by Newton from its uncoupled value, all at once:

- near mode ``k`` (pole ``d_k``, a root of ``q_k``), with mode ``k`` kept out of ``S``
  (``S_-k``, no pole there), the scalar ``E(lam) = q_k(lam) + lam v^T S_-k(lam)^-1 v = 0``,
  ``v = Bphi[:, k]``; the sums over the other modes for all roots are two GEMMs per iteration,
  ``(1 / q_j(lam_i)) @ P`` with ``P[j, (a, b)] = Bphi[a, j] Bphi[b, j]`` (``a <= b``), then r x r
  solves;
- the branches' roots, together with a set ``C`` of modes (those whose poles coincide, whose runs
  met on one root or did not converge, or, in a second attempt, the strongly coupled ones with
  guesses from their small dense system): the (c + r) x (c + r) matrix ``T(lam)`` of
  ``q_C(lam) eta_C + Bphi_C^T f = 0``, ``-lam Bphi_C eta_C + S_-C(lam) f = 0``, by Newton on
  ``log det T`` with the roots already found divided out (their conjugates too), so that no root
  is taken twice unless it is repeated; real and complex roots alike (a pair of branch roots may
  be complex);
- if that fails, the coupling is grown from zero in 4, then 16 steps, Newton at each.
Eigenvectors follow in O(n r) each (``f`` from the secular solve, ``eta_j = -(Bphi^T f)_j / q_j``),
and because the problem is symmetric the left eigenvectors come from the right ones,
``w = [-W^2 eta / lam; eta; -f / (lam k)]``, ``w^T v = lam eta.eta - eta.W^2 eta / lam - f.(f/k) / lam``.

Nothing here is trusted unchecked (:func:`branch_modes` raises :class:`DefectiveModesError`, and the
time response then takes the dense path): every root is certified by its backward error
``||A v - lam v|| / (||A|| ||v||)`` in the balanced coordinates ``[W eta; eta'; f / sqrt(k)]``
(computed in the structured form), the eigenvalue condition numbers ``||w|| ||v|| / |w^T v|`` bound
how far each root can be from an eigenvalue, and the 2n + r roots (with the conjugates) must be
pairwise separated by more than those bounds: then they are all the eigenvalues of ``A`` and its
eigenvectors are a basis. Sums of ``lam`` and ``lam^2`` against ``trace A`` and ``trace A^2``
(closed forms in the structured blocks) check the count once more. Rigid modes and nearly
critically damped ones (a Jordan block of their own) are refused before any Newton step; an
overdamped mode gives two real poles, each a root of its own.
"""

# Over 600 lines on purpose (issue 28): one algorithm: the r x r secular equation of classically
# damped modes plus Maxwell branches, its root bracketing, refinement and certificate; its steps
# share private state and are not used elsewhere.

from __future__ import annotations

from collections.abc import Callable
import dataclasses
from dataclasses import dataclass

import numpy as np

from ...errors import DefectiveModesError
from .complex_modes import eigenvalues
from ...results import ReadOnly

__all__ = ["BranchModes", "branch_modes", "RESIDUAL_TOL", "COND_MAX"]

RESIDUAL_TOL = 1e-11
"""Largest backward error ``||A v - lam v|| / (||A|| ||v||)`` accepted for a root (balanced states)."""

COND_MAX = 1e8
"""Largest eigenvalue condition number ``||w|| ||v|| / |w^T v|`` accepted (as in
:data:`vibss.linear.eigen.complex_modes.COND_MAX`)."""

CLUSTER = 1e-6
"""Modes whose undamped poles lie within this fraction of their magnitude are solved together."""

MAX_NEWTON = 60
"""Newton iterations per root before it counts as not converged."""

MAX_CLUSTER_NEWTON = 200
"""The same for the roots of a cluster (linear convergence towards a repeated root)."""


@dataclass(frozen=True, eq=False)
class BranchModes(ReadOnly):
    """The eigen-decomposition of the augmented modal state matrix (module docstring).

    Attributes
    ----------
    lam : (N,) complex ndarray
        One eigenvalue per underdamped mode (upper half plane), two per overdamped mode (real), one
        per branch (real) [1/s]; the others are the conjugates of those with ``weight`` 2.
        ``N = n + r`` plus the number of overdamped modes.
    eta : (n, N) complex ndarray
        Modal coordinates of each right eigenvector (its ``eta'`` part is ``lam eta``).
    force : (r, N) complex ndarray
        Branch forces of each right eigenvector [N per unit modal coordinate].
    norm : (N,) complex ndarray
        ``w^T v`` (left eigenvector built from the right one).
    weight : (N,) ndarray
        2 for a root with its conjugate left out, 1 for a real root.
    how : str
        What was solved and the certificate (largest backward error and condition number).
    omega2 : (n,) ndarray
        Squared undamped frequencies [rad^2/s^2].
    k : (r,) ndarray
        Branch stiffnesses [N/m].
    groups : tuple of (indices, (g, g) ndarray)
        Repeated roots: their indices and the inverse of their Gram matrix ``w_i^T v_j``.
    """

    lam: np.ndarray
    eta: np.ndarray
    force: np.ndarray
    norm: np.ndarray
    weight: np.ndarray
    how: str
    omega2: np.ndarray
    k: np.ndarray
    groups: tuple[tuple[np.ndarray, np.ndarray], ...] = ()

    def dual(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The rows of ``V^-1`` for the kept roots, split by state block.

        Returns
        -------
        de, dd : (n, N) complex ndarray
            Columns ``i``: the weights of ``eta`` and ``eta'`` in the modal coordinate of root ``i``.
        df : (r, N) complex ndarray
            The weights of the branch forces.
        """
        lam = self.lam[None]
        de = -self.omega2[:, None] * self.eta / lam
        dd = self.eta.copy()
        df = -self.force / (lam * self.k[:, None])
        blocks = [de, dd, df]
        for b in blocks:
            b /= self.norm[None]
        for g, inv in self.groups:
            for b, y in zip(blocks, (-self.omega2[:, None] * self.eta[:, g] / self.lam[g][None],
                                     self.eta[:, g], -self.force[:, g] / (self.lam[g][None] * self.k[:, None]))):
                b[:, g] = y @ inv.T
        return de, dd, df


def _gram(bphi: np.ndarray) -> np.ndarray:
    """(n, r (r + 1) / 2) real: ``P[j, (a, b)] = Bphi[a, j] Bphi[b, j]`` for ``a <= b`` (the upper
    triangle, row by row: :func:`numpy.triu_indices`)."""
    a, b = np.triu_indices(bphi.shape[0])
    return (bphi[a] * bphi[b]).T.copy()


def _cmul(h: np.ndarray, p: np.ndarray) -> np.ndarray:
    """Complex (J, n) times real (n, q) as two real GEMMs."""
    return (h.real @ p) + 1j * (h.imag @ p)


class _Secular:
    """``S(lam)`` and ``S'(lam)`` for a batch of ``lam`` with chosen modes left out."""

    def __init__(self, w2: np.ndarray, c: np.ndarray, bphi: np.ndarray, k: np.ndarray, tau: np.ndarray):
        self.w2, self.c, self.bphi, self.k, self.tau = w2, c, bphi, k, tau
        self.r = bphi.shape[0]
        self.P = _gram(bphi)

    def h(self, lam: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(J, n) ``1 / q_j(lam_i)`` and its derivative."""
        la = lam[:, None]
        q = la + self.c[None]                             # in place from here: q = lam (lam + c) + w^2
        q *= la
        q += self.w2[None]
        h = np.reciprocal(q, out=q)
        hd = 2.0 * la + self.c[None]
        hd *= h
        hd *= h
        np.negative(hd, out=hd)
        return h, hd

    def S(self, lam: np.ndarray, out: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """(J, r, r) ``S(lam)`` and ``S'(lam)``, the modes marked True in ``out`` (J, n) left out."""
        h, hd = self.h(lam)
        if out is not None:
            h[out] = 0.0
            hd[out] = 0.0
        r = self.r
        a, b = np.triu_indices(r)
        G = np.empty((lam.size, r, r), complex)
        Gd = np.empty((lam.size, r, r), complex)
        G[:, a, b] = G[:, b, a] = _cmul(h, self.P)                 # symmetric: the upper triangle
        Gd[:, a, b] = Gd[:, b, a] = _cmul(hd, self.P)
        lv = lam[:, None, None]
        S = lv * G
        Sd = G + lv * Gd
        ii = np.arange(r)
        S[:, ii, ii] += (lam[:, None] + 1.0 / self.tau[None]) / self.k[None]
        Sd[:, ii, ii] += 1.0 / self.k[None]
        return S, Sd


def _newton_singletons(sec: _Secular, lam0: np.ndarray, home: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Roots of the isolated modes ``home`` from ``lam0``: scalar Newton on
    ``E(lam) = q_k(lam) + lam v^T S_-k(lam)^-1 v`` for all at once.

    Returns the roots, ``S_-k^-1 v`` at each, and which did not converge in :data:`MAX_NEWTON` steps.
    """
    J = lam0.size
    lam = lam0.astype(complex).copy()
    out = np.zeros((J, sec.w2.size), bool)
    out[np.arange(J), home] = True
    v = sec.bphi[:, home].T.astype(complex)                    # (J, r)
    c, w2 = sec.c[home], sec.w2[home]
    active = np.ones(J, bool)
    x = np.zeros((J, sec.r), complex)
    it = 0
    for it in range(1, MAX_NEWTON + 1):
        idx = np.flatnonzero(active)
        la = lam[idx]
        S, Sd = sec.S(la, out[idx])
        xa = np.linalg.solve(S, v[idx][:, :, None])[:, :, 0]
        vx = np.einsum("ja,ja->j", v[idx], xa)
        E = la * la + c[idx] * la + w2[idx] + la * vx
        Ed = 2 * la + c[idx] + vx - la * np.einsum("ja,jab,jb->j", xa, Sd, xa)
        step = E / Ed
        lam[idx] = la - step
        x[idx] = xa                                  # at the root to the last step's size (round-off)
        done = ~(np.abs(step) > 4 * np.finfo(float).eps * np.abs(la))
        active[idx[done]] = False
        if not active.any():
            break
    return lam, x, active


def _newton_cluster(fun: Callable[[complex], tuple[np.ndarray, np.ndarray]], lam0: np.ndarray,
                    real: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Roots of ``det E(lam) = 0`` from the guesses ``lam0``, one after the other: Newton on
    ``log det E`` with the roots already found divided out (Maehly's deflation), so that no root is
    found twice unless it is a repeated one. ``real``: stay on the real axis (``E`` real there).
    (Roots of the other clusters are not divided out: ``det E`` has poles next to them, the roots of
    the structure without this cluster.)
    Returns the roots and their null vectors (columns)."""
    found: list[complex] = []
    for lam in lam0:
        lam = complex(lam.real) if real else complex(lam)
        if any(lam == f for f in found):                 # on a root already found: step off it
            lam += 1e-6 * abs(lam)
        for _ in range(MAX_CLUSTER_NEWTON):
            E, Ed = fun(lam)
            try:
                t = np.trace(np.linalg.solve(E, Ed))
            except np.linalg.LinAlgError:
                break                                     # exactly on a root (a repeated one is checked below)
            t -= sum(1.0 / (lam - f) for f in found if f != lam)
            if not real:                                  # the conjugates are roots too
                t -= sum(1.0 / (lam - f.conjugate()) for f in found if f.imag != 0 and f.conjugate() != lam)
            if t == 0:
                break
            step = 1.0 / t
            if real:
                step = step.real
            lam -= step
            if not real and lam.imag < 0:                 # a root's conjugate: take the root
                lam = lam.conjugate()
            if not abs(step) > 4 * np.finfo(float).eps * abs(lam):
                break
        else:
            raise DefectiveModesError(f"structured branch eigen-solve: a root near {lam:.6g} did not converge")
        found.append(lam)
    lam_all = np.array(found, complex)
    X = np.zeros((fun(lam_all[0])[0].shape[0], lam_all.size), complex)
    # the null vectors at the roots; a root found g times is given the g-dimensional null space of
    # E (a repeated eigenvalue of a symmetric structure), or stays g equal copies that the
    # certificate then refuses
    for grp in _coincident(lam_all, 1e-7):
        la = complex(np.mean(lam_all[grp]))
        E, _ = fun(la)
        # equilibrate rows then columns (mode and branch equations differ by decades), SVD, and one
        # step of inverse iteration on the scaled matrix
        rs = 1.0 / np.maximum(np.abs(E).max(axis=1), np.finfo(float).tiny)
        cs = 1.0 / np.maximum(np.abs(E * rs[:, None]).max(axis=0), np.finfo(float).tiny)
        Es = E * rs[:, None] * cs[None]
        _, sv, vh = np.linalg.svd(Es)
        Y = vh[-grp.size:].conj().T
        try:                                        # keep the step only where it lowers the residual
            Z = np.linalg.qr(np.linalg.solve(Es, Y))[0]
            if np.all(np.isfinite(Z)) and np.linalg.norm(Es @ Z) < np.linalg.norm(Es @ Y):
                Y = Z
        except np.linalg.LinAlgError:
            pass
        X[:, grp] = cs[:, None] * Y
        if grp.size > 1 and sv[-grp.size] <= 1e-8 * sv[0]:
            lam_all[grp] = la
    return lam_all, X


def _meeting(lam: np.ndarray, tol: float, atol: float = 0.0) -> list[tuple[int, int]]:
    """Pairs ``(i, j)``, ``i != j``, with ``|lam_i - lam_j| <= atol + tol max(|lam_i|, |lam_j|)``
    (sorted by real part, so only neighbours that close in it are compared: about O(N log N))."""
    order = np.argsort(lam.real, kind="stable")
    ls = lam[order]
    mag = np.abs(ls)
    out: list[tuple[int, int]] = []
    for step in range(1, lam.size):
        lim = atol + tol * np.maximum(mag[step:], mag[:-step])
        near = np.abs(ls[step:] - ls[:-step]) <= lim
        if near.any():
            out.extend((int(order[i]), int(order[i + step])) for i in np.flatnonzero(near))
        if not np.any(ls[step:].real - ls[:-step].real <= lim):
            break
    return out


def _coincident(lam: np.ndarray, tol: float = 1e-9) -> list[np.ndarray]:
    """Groups of indices of ``lam`` equal to ``tol`` of their magnitude (singletons included)."""
    close = np.abs(lam[:, None] - lam[None]) <= tol * np.maximum(np.abs(lam)[:, None], np.abs(lam)[None])
    seen = np.zeros(lam.size, bool)
    out = []
    for i in range(lam.size):
        if not seen[i]:
            grp = np.flatnonzero(close[i] & ~seen)
            seen[grp] = True
            out.append(grp)
    return out


def _linearised(fun: Callable[[complex], tuple[np.ndarray, np.ndarray]], d: complex,
                count: int) -> np.ndarray:
    """``count`` first guesses near ``d`` from ``E(d) + (lam - d) E'(d)`` and their vectors."""
    E0, Ed0 = fun(d)
    mu = eigenvalues(E0, -Ed0)
    finite = np.isfinite(mu)
    order = np.argsort(np.where(finite, np.abs(mu), np.inf))[:count]
    if not np.all(finite[order]):
        raise DefectiveModesError("structured branch eigen-solve: a cluster's linearisation is singular")
    return d + mu[order]


def _joint_fun(sec: _Secular, modes: np.ndarray) -> Callable[[complex], tuple[np.ndarray, np.ndarray]]:
    """``T(lam)``, ``T'(lam)`` of the modes ``modes`` solved together with every branch: unknowns
    ``(eta_C, f)``, equations ``q_C(lam) eta_C + Bphi_C^T f = 0`` and
    ``-lam Bphi_C eta_C + S_-C(lam) f = 0`` (the other modes eliminated, their poles kept out)."""
    mask = np.zeros(sec.w2.size, bool)
    mask[modes] = True
    V = sec.bphi[:, modes]
    cs, r = modes.size, sec.r

    def fun(la: complex) -> tuple[np.ndarray, np.ndarray]:
        S, Sd = sec.S(np.array([la]), mask[None])
        T = np.zeros((cs + r, cs + r), complex)
        Td = np.zeros((cs + r, cs + r), complex)
        T[:cs, :cs] = np.diag(la * la + sec.c[modes] * la + sec.w2[modes])
        T[:cs, cs:] = V.T
        T[cs:, :cs] = -la * V
        T[cs:, cs:] = S[0]
        Td[:cs, :cs] = np.diag(2 * la + sec.c[modes])
        Td[cs:, :cs] = -V
        Td[cs:, cs:] = Sd[0]
        return T, Td

    return fun


@dataclass(frozen=True)
class _Poles:
    """The uncoupled roots: one per underdamped mode (upper half plane), two real ones per
    overdamped mode; ``home`` the mode of each."""

    d: np.ndarray
    home: np.ndarray


def _poles(omega: np.ndarray, c: np.ndarray) -> _Poles:
    disc = (c / 2) ** 2 - omega ** 2
    over = disc > 0
    root = np.sqrt(np.abs(disc))
    if np.any(2 * root < 1e-2 * np.maximum(omega, c)):
        raise DefectiveModesError("structured branch eigen-solve: a nearly critically damped mode (a Jordan block "
                                  "of its own)")
    under = np.flatnonzero(~over)
    ov = np.flatnonzero(over)
    d = np.concatenate([-c[under] / 2 + 1j * root[under], -c[ov] / 2 + root[ov], -c[ov] / 2 - root[ov]])
    return _Poles(d=d.astype(complex), home=np.concatenate([under, ov, ov]))


def _strong_guesses(omega: np.ndarray, c: np.ndarray, bphi: np.ndarray, k: np.ndarray,
                    tau: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The strongly coupled modes and first guesses of the roots they share with the branches.

    The modes whose branch stiffness ``sum_i k_i Bphi_ik^2`` is at least :data:`STRONG` of their
    own ``omega^2`` (at most :data:`MAX_CLUSTER`, the strongest) with every branch: one small dense
    ``eig``; its roots in the closed upper half plane are the guesses."""
    ratio = (k[:, None] * bphi ** 2).sum(axis=0) / omega ** 2
    order = np.argsort(-ratio, kind="stable")[:MAX_CLUSTER]
    modes = np.sort(order[ratio[order] >= STRONG])
    cs, r = modes.size, k.size
    A = np.zeros((2 * cs + r, 2 * cs + r))
    A[:cs, cs:2 * cs] = np.eye(cs)
    A[cs:2 * cs, :cs] = -np.diag(omega[modes] ** 2)
    A[cs:2 * cs, cs:2 * cs] = -np.diag(c[modes])
    A[cs:2 * cs, 2 * cs:] = -bphi[:, modes].T
    A[2 * cs:, cs:2 * cs] = k[:, None] * bphi[:, modes]
    A[2 * cs:, 2 * cs:] = -np.diag(1.0 / tau)
    ev = eigenvalues(A)
    real = np.abs(ev.imag) <= 1e-9 * np.abs(ev)
    return modes, np.concatenate([ev[real].real, ev[~real & (ev.imag > 0)]]).astype(complex)


def _upper(lam: np.ndarray) -> np.ndarray:
    """Roots in the closed upper half plane, the real ones (to 1e-9) made real."""
    real = np.abs(lam.imag) <= 1e-9 * np.abs(lam)
    return np.concatenate([lam[real].real, lam[~real & (lam.imag > 0)]]).astype(complex)


def _track(omega: np.ndarray, c: np.ndarray, bphi: np.ndarray, k: np.ndarray, tau: np.ndarray,
           stages: int, seed: bool = False) -> tuple[np.ndarray, np.ndarray, np.ndarray, int]:
    """Every root followed from its uncoupled value as the coupling grows to full in ``stages`` equal
    steps (``Bphi`` scaled by ``sqrt(t)``), Newton at each; then the eigenvectors at full coupling.

    The branches' roots are found jointly with a set ``C`` of modes (:func:`_joint_fun`), every
    other pole alone (:func:`_newton_singletons`). ``C`` starts empty, or (``seed``) with the
    strongly coupled modes and guesses from their small dense system (:func:`_strong_guesses`);
    where two poles' runs meet on one root, or one does not converge, their modes join ``C`` (at
    most :data:`MAX_CLUSTER`). Returns the roots (closed upper half plane; the others are the
    conjugates of the complex ones), their ``eta`` and ``f``, and the number of rounds."""
    n, r = omega.size, k.size
    w2 = omega * omega
    po = _poles(omega, c)
    sec = _Secular(w2, c, bphi, k, tau)
    if seed:
        joint, guess = _strong_guesses(omega, c, bphi, k, tau)
    else:
        joint = np.zeros(0, int)
        guess = np.concatenate([_upper(_linearised(_joint_fun(sec, joint), complex(-1.0 / t), int(np.sum(tau == t))))
                                for t in np.unique(tau)])
    lam = po.d.copy()                                     # the single poles' roots
    sx = np.zeros((po.d.size, r), complex)
    X = np.zeros((0, 0), complex)
    rounds = 0
    for t in np.arange(1, stages + 1) / stages:
        sec = _Secular(w2, c, np.sqrt(t) * bphi, k, tau)
        start = lam.copy()
        fresh = np.ones(po.d.size, bool)
        while True:
            rounds += 1
            if joint.size > MAX_CLUSTER:
                raise DefectiveModesError(f"structured branch eigen-solve: {joint.size} modes interact too closely "
                                          f"with the branches to be solved apart (more than {MAX_CLUSTER})")
            alone = np.flatnonzero(~np.isin(po.home, joint))
            todo = alone[fresh[alone]]
            stuck = np.zeros(0, int)
            if todo.size:
                lam[todo], sx[todo], bad = _newton_singletons(sec, start[todo], po.home[todo])
                fresh[todo] = False
                stuck = todo[bad]
            fun = _joint_fun(sec, joint)
            guess, X = _newton_cluster(fun, guess)
            guess = np.where(np.abs(guess.imag) <= 1e-9 * np.abs(guess), guess.real, guess)
            # poles whose run failed or met another root (a single's or a joint one) join C
            failed = set(stuck.tolist())
            la = lam[alone]
            for i, j in _meeting(np.concatenate([la, guess]), 1e-9):
                for q in (i, j):
                    if q < alone.size:
                        failed.add(int(alone[q]))
            if not failed:
                break
            if rounds > 8 + stages:
                raise DefectiveModesError("structured branch eigen-solve: roots kept meeting after joining their "
                                          "modes to the branches")
            new = np.unique(po.home[sorted(failed)])
            joint = np.union1d(joint, new)
            # the joined modes' poles (where they started) are the new roots' guesses
            guess = np.concatenate([guess, _upper(start[np.isin(po.home, new)])])
    alone = np.flatnonzero(~np.isin(po.home, joint))
    m = alone.size + guess.size
    roots = np.concatenate([lam[alone], guess])
    eta = np.zeros((n, m), complex)
    force = np.zeros((r, m), complex)
    if alone.size:
        la = lam[alone]
        f = la[:, None] * sx[alone]
        h, _ = sec.h(la)
        e = -h * (f @ bphi)
        e[np.arange(alone.size), po.home[alone]] = 1.0
        eta[:, :alone.size] = e.T
        force[:, :alone.size] = f.T
    cs = joint.size
    mask = np.zeros(n, bool)
    mask[joint] = True
    for j, (la, x) in enumerate(zip(guess, X.T)):
        f = x[cs:]
        h, _ = sec.h(np.array([la]))
        e = -h[0] * (f @ bphi)
        e[joint] = x[:cs]
        eta[:, alone.size + j], force[:, alone.size + j] = e, f
    return roots, eta, force, rounds


STAGES = ((1, False), (1, True), (4, False), (16, False))
"""Tried in turn until the roots certify: (number of equal coupling steps of the continuation,
whether the strongly coupled part's small dense ``eig`` gives the first guesses)."""

STRONG = 0.05
"""A mode whose branch stiffness is this fraction of its own stiffness is strongly coupled."""

MAX_CLUSTER = 48
"""Most modes solved together (one root at a time, each an O(n r^2 + c^3) Newton step)."""


def branch_modes(omega: np.ndarray, c: np.ndarray, bphi: np.ndarray, k: np.ndarray,
                 tau: np.ndarray) -> BranchModes:
    """Eigenvalues and eigenvectors of the augmented modal state matrix (module docstring), certified.

    Parameters
    ----------
    omega : (n,) ndarray
        Undamped natural frequencies of the static stiffness, all > 0 [rad/s].
    c : (n,) ndarray
        Modal damping ``2 zeta omega`` (diagonal of ``Phi^T C Phi``), each below ``2 omega`` [1/s].
    bphi : (r, n) ndarray
        Branch deflections per unit modal coordinate [m].
    k : (r,) ndarray
        Branch stiffnesses, > 0 [N/m].
    tau : (r,) ndarray
        Relaxation times, > 0 [s].

    Returns
    -------
    BranchModes

    Raises
    ------
    DefectiveModesError
        When the roots cannot be certified (see the module docstring); the message says which check
        failed.

    Examples
    --------
    One mode (10 rad/s) and one branch: the dense matrix's eigenvalues, found without it.

    >>> import numpy as np
    >>> bm = branch_modes(np.array([10.0]), np.array([0.0]), np.array([[1.0]]), np.array([100.0]),
    ...                   np.array([0.1]))
    >>> A = np.array([[0, 1, 0], [-100.0, 0, -1], [0, 100.0, -10]])
    >>> ev = np.linalg.eigvals(A)
    >>> lam = np.concatenate([bm.lam, bm.lam[bm.weight == 2].conj()])       # with the conjugates
    >>> bool(np.allclose(np.sort_complex(lam), np.sort_complex(ev), rtol=1e-12))
    True
    """
    omega, c, bphi = np.asarray(omega, float), np.asarray(c, float), np.asarray(bphi, float)
    k, tau = np.asarray(k, float), np.asarray(tau, float)
    if np.any(omega <= 0) or not np.all(np.isfinite(omega)):
        raise DefectiveModesError("structured branch eigen-solve: a rigid-body (zero-frequency) mode")
    if np.any(c < 0):
        raise DefectiveModesError("structured branch eigen-solve: negative modal damping")
    refusals = []
    for stages, seed in STAGES:
        try:
            with np.errstate(divide="ignore", invalid="ignore", over="ignore"):   # a failed run is refused below
                lam, eta, force, iters = _track(omega, c, bphi, k, tau, stages, seed)
                bm = _certify(lam, eta, force, omega, c, bphi, k, tau, iters)
        except DefectiveModesError as exc:
            refusals.append(f"{stages} step(s){', strong part seeded' if seed else ''}: {exc}")
            continue
        how = bm.how + (f", coupling grown in {stages} steps" if stages > 1 else "") \
            + (f", after {len(refusals)} refused attempt(s)" if refusals else "")
        return dataclasses.replace(bm, how=how)
    raise DefectiveModesError("; ".join(refusals))


def _certify(lam: np.ndarray, eta: np.ndarray, force: np.ndarray, omega: np.ndarray, c: np.ndarray,
             bphi: np.ndarray, k: np.ndarray, tau: np.ndarray, iters: int) -> BranchModes:
    """The checks of the module docstring; raises :class:`DefectiveModesError` naming the failed one.
    ``lam``: roots in the closed upper half plane (the complex ones stand for their conjugates too)."""
    n, r = omega.size, k.size
    fail = "structured branch eigen-solve not certified: "
    if not np.all(np.isfinite(lam)) or not np.all(np.isfinite(eta)) or not np.all(np.isfinite(force)):
        raise DefectiveModesError(fail + "a root or eigenvector is not finite")
    up = lam.imag > 1e-10 * np.abs(lam)
    if np.any(lam[~up].imag < -1e-10 * np.abs(lam[~up])):
        raise DefectiveModesError(fail + "a root in the lower half plane")
    lam = np.where(up, lam, lam.real)
    if 2 * int(up.sum()) + int((~up).sum()) != 2 * n + r:
        raise DefectiveModesError(fail + f"{2 * int(up.sum()) + int((~up).sum())} roots with the conjugates, "
                                  f"not 2n + r = {2 * n + r}")
    # backward errors in the balanced states [W eta; lam eta; f / sqrt(k)]
    sk = np.sqrt(k)
    qeta = (lam[None] ** 2 + c[:, None] * lam[None] + (omega ** 2)[:, None]) * eta
    r2 = -qeta - bphi.T @ force
    r3 = sk[:, None] * lam[None] * (bphi @ eta) - (lam[None] + 1.0 / tau[:, None]) * force / sk[:, None]
    vnorm = np.sqrt(np.sum(np.abs(omega[:, None] * eta) ** 2 + np.abs(lam[None] * eta) ** 2, axis=0)
                    + np.sum(np.abs(force / sk[:, None]) ** 2, axis=0))
    anorm = max(float(omega.max()), float(c.max()), float(np.max(1.0 / tau)),
                float(np.linalg.norm(sk[:, None] * bphi, 2)))
    back = np.sqrt(np.sum(np.abs(r2) ** 2, axis=0) + np.sum(np.abs(r3) ** 2, axis=0)) / (anorm * vnorm)
    worst = float(back.max())
    if not worst <= RESIDUAL_TOL:
        raise DefectiveModesError(fail + f"eigen-residual {worst:.2g} of ||A|| above {RESIDUAL_TOL:g}")
    # left eigenvectors from the right ones; condition numbers; a repeated root's group is
    # bi-orthogonalised by the inverse of its Gram matrix w_i^T v_j
    norm = _pairing(lam, eta, force, omega ** 2, k)
    wnorm = np.sqrt(np.sum(np.abs(omega[:, None] * eta / lam[None]) ** 2 + np.abs(eta) ** 2, axis=0)
                    + np.sum(np.abs(force / (lam[None] * sk[:, None])) ** 2, axis=0))
    kappa = wnorm * vnorm / np.abs(norm)
    groups = [g for g in _coincident(lam, 0.0) if g.size > 1]
    inverses = []
    for g in groups:
        gram = _pairing(lam[g], eta[:, g], force[:, g], omega ** 2, k, gram=True)
        try:
            inv = np.linalg.inv(gram)
        except np.linalg.LinAlgError:
            raise DefectiveModesError(fail + f"a root near {lam[g[0]]:.8g} found {g.size} times with dependent "
                                      "eigenvectors (found twice, or defective)") from None
        kappa[g] = float(np.max(wnorm[g]) * np.max(vnorm[g]) * np.linalg.norm(inv, 2)) * np.sqrt(g.size)
        inverses.append((g, inv))
    if not float(kappa.max()) <= COND_MAX:
        raise DefectiveModesError(fail + f"eigenvalue condition number {float(kappa.max()):.2g} above {COND_MAX:g} "
                                  "(nearly defective)")
    # all 2n + r roots (those of a certified repeated group once) distinct beyond their error
    # bounds: then, with the multiplicities, they are the whole spectrum
    full = np.concatenate([lam, lam[up].conj()])
    bound = np.concatenate([kappa * back, kappa[up] * back[up]]) * anorm
    for i, j in _meeting(full, 1e-12, 200 * float(bound.max())):
        if full[i] != full[j] and abs(full[i] - full[j]) <= (100 * (bound[i] + bound[j])
                                                            + 1e-12 * max(abs(full[i]), abs(full[j]))):
            raise DefectiveModesError(fail + f"two roots coincide ({full[i]:.8g} and {full[j]:.8g}): a root found "
                                      "twice or a repeated eigenvalue")
    # trace invariants
    s1 = float(np.sum(full).real)
    t1 = -float(np.sum(c)) - float(np.sum(1.0 / tau))
    s2 = float(np.sum(full * full).real)
    t2 = -2 * float(np.sum(omega ** 2)) + float(np.sum(c * c)) + float(np.sum(1.0 / tau ** 2)) \
        - 2 * float(np.sum(k[:, None] * bphi * bphi))
    a1, a2 = float(np.sum(np.abs(full))), float(np.sum(np.abs(full) ** 2))
    if not (abs(s1 - t1) <= 1e-9 * a1 and abs(s2 - t2) <= 1e-9 * a2):
        raise DefectiveModesError(fail + f"trace invariants missed: sum lam {s1:.10g} vs trace A {t1:.10g}, "
                                  f"sum lam^2 {s2:.10g} vs trace A^2 {t2:.10g}")
    weight = np.where(up, 2.0, 1.0)
    how = (f"{n} modes and {r} branch states: the 2n + r = {2 * n + r} roots of the r x r secular equation "
           f"by Newton ({iters} round(s)), backward error <= {worst:.1g}, condition number <= "
           f"{float(kappa.max()):.2g}, trace invariants met")
    if groups:
        how += f", {len(groups)} repeated root(s) (largest multiplicity {max(g.size for g in groups)})"
    return BranchModes(lam=lam, eta=eta, force=force, norm=norm, weight=weight, how=how, omega2=omega ** 2,
                       k=k, groups=tuple(inverses))


def _pairing(lam: np.ndarray, eta: np.ndarray, force: np.ndarray, w2: np.ndarray, k: np.ndarray,
             gram: bool = False) -> np.ndarray:
    """``w_i^T v_i`` (or the Gram matrix ``w_i^T v_j`` of roots all equal to ``lam[0]``) with the left
    eigenvectors built from the right ones."""
    if gram:
        la = lam[0]
        return la * eta.T @ eta - (eta.T * w2[None]) @ eta / la - (force.T / k[None]) @ force / la
    return (lam * np.sum(eta * eta, axis=0) - np.sum(w2[:, None] * eta * eta, axis=0) / lam
            - np.sum(force * force / k[:, None], axis=0) / lam)
