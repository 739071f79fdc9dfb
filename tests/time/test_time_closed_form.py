"""The modal time path's closed forms and its vectorised recursion, against independent references.

- :func:`vibss.time.phi.foh_blocks` / :func:`cs_blocks` (2x2 blocks and complex scalars in closed
  form) against ``scipy.linalg.expm`` of the augmented matrix in every regime (underdamped, critically
  damped, just off critical, overdamped, rigid undamped and damped, very low and very high
  ``omega h``), and against 50-digit ``mpmath.expm`` where ``expm`` itself is the question;
- :func:`vibss.time.recursion.scan` against the step-by-step loop it replaces (uniform steps,
  inserted odd steps, complex and real blocks, lengths that do not divide into blocks);
- the modal method end to end against ``solve_ivp`` (DOP853 at rtol 1e-13) on a model whose modes
  are rigid, lightly damped, critically damped and overdamped at once, with initial conditions, a
  sine piece and a pulse edge between samples.
"""

from __future__ import annotations

import mpmath as mp
import numpy as np
import pytest
import scipy.linalg as sl

from vibss.time.phi import cs_blocks, cs_expm, foh_blocks, foh_expm, phi_scalar
from vibss.time.recursion import LowRank, scan


def _blocks(w: np.ndarray, c: np.ndarray) -> np.ndarray:
    """The modal path's real blocks ``[[0, s], [-w^2/s, -c]]`` (s = w, or 1 for a rigid mode)."""
    s = np.where(w > 0, w, 1.0)
    A = np.zeros((w.size, 2, 2))
    A[:, 0, 1], A[:, 1, 0], A[:, 1, 1] = s, -w**2 / s, -c
    return A


REGIMES = {
    "underdamped": (np.geomspace(1e-4, 6e4, 25), 1e-3),
    "undamped": (np.geomspace(1e-3, 6e4, 8), 0.0),
    "critical": (np.geomspace(1e-3, 6e4, 12), 1.0),
    "near critical": (np.geomspace(1e-3, 6e4, 12), 1 + 1e-7),
    "just off critical": (np.geomspace(1e-3, 6e4, 12), 1 - 1e-3),
    "overdamped": (np.geomspace(1e-3, 6e4, 12), 3.0),
}
STEPS = np.array([2e-4, 1e-5, 3.7e-3])


def _regime(name: str) -> np.ndarray:
    if name == "rigid":
        return _blocks(np.zeros(5), np.array([0.0, 1e-9, 1.0, 1e3, 1e6]))
    w, zeta = REGIMES[name]
    return _blocks(w, 2 * zeta * w)


def _rel(a: np.ndarray, b: np.ndarray, axes: tuple[int, ...]) -> float:
    scale = np.maximum(np.abs(b).max(axis=axes, keepdims=True), 1e-300)
    return float((np.abs(a - b) / scale).max())


@pytest.mark.parametrize("regime", [*REGIMES, "rigid"])
@pytest.mark.parametrize("degree", [1, 3])
def test_foh_blocks_match_expm_of_the_augmented_matrix(regime: str, degree: int) -> None:
    A = _regime(regime)
    E, g = foh_blocks(A, STEPS, degree)
    E2, g2 = foh_expm(A, STEPS, degree)
    assert _rel(E, E2, (-1, -2)) < 3e-12          # expm's own error on the fast modes (see mpmath below)
    assert _rel(g, g2, (-1,)) < 3e-12
    # the displacement row on its own (small against the velocity row when omega h is small)
    assert _rel(g[..., 0], g2[..., 0], ()) < 1e-11


@pytest.mark.parametrize("regime", [*REGIMES, "rigid"])
def test_cs_blocks_match_expm_of_the_block_and_oscillator(regime: str) -> None:
    A = _regime(regime)
    for omega in (3e-4, 0.3, 62.8, 4.1e3, float(np.sqrt(-A[3, 1, 0] * A[3, 0, 1]))):   # incl. a resonance
        assert _rel(cs_blocks(A, STEPS, omega), cs_expm(A, STEPS, omega), (-1,)) < 1e-11


def test_complex_scalar_modes_match_expm() -> None:
    w = np.geomspace(1e-3, 6e4, 30)
    lam = np.concatenate([-1e-3 * w + 1j * w, -w + 0j, -0.3 * w + 0.95j * w, [0j, -1e-12 + 1e-9j]])
    A = lam.reshape(-1, 1, 1)
    E, g = foh_blocks(A, STEPS, 3)
    E2, g2 = foh_expm(A, STEPS, 3)
    assert _rel(E, E2, (-1, -2)) < 1e-13
    assert _rel(g, g2, ()) < 1e-12
    for omega in (1e-5, 0.3, 4.1e3, float(w[7]), float(w[25])):   # slow sines, resonances
        got, ref = cs_blocks(A, STEPS, omega), cs_expm(A, STEPS, omega)
        assert _rel(got, ref, ()) < 3e-12          # cos and sin each on their own (expm's own error
        #                                            at |lam h| ~ 20 is 2e-12: see the mpmath test)


@pytest.mark.parametrize("lam, omega, h", [(-1e-3 + 1.0j, 1e-5, 2e-4), (-5.0 + 5e3j, 5e3, 3.7e-3),
                                           (-300.0 + 0j, 0.1, 1e-2), (-1e-9 + 0.2j, 0.2, 1e-3),
                                           (-2.0 + 40.0j, 3.0, 0.05)])
def test_cs_blocks_against_mpmath_quadrature(lam: complex, omega: float, h: float) -> None:
    got = cs_blocks(np.array([[[lam]]]), np.array([h]), omega)[0, :, 0, 0]
    mp.mp.dps = 40
    L, H, W = mp.mpc(lam.real, lam.imag), mp.mpf(h), mp.mpf(omega)
    for k, f in enumerate((mp.cos, mp.sin)):
        ref = complex(mp.quad(lambda t: mp.exp(L * (H - t)) * f(W * t), mp.linspace(0, H, 9)))
        assert abs(got[k] - ref) <= 1e-13 * abs(ref)


def test_phi_functions_against_mpmath() -> None:
    z = np.array([0, 1e-9, -1e-5 + 2e-3j, 0.5j, -0.99, 1.01, 1j, -3 + 4j, 12j, -40.0])
    got = phi_scalar(z, 4)
    mp.mp.dps = 50
    for i, zi in enumerate(z):
        x = mp.mpc(zi.real, zi.imag)
        ref = [mp.exp(x)]
        for j in range(4):                              # phi_{j+1} by its series (no cancellation)
            ref.append(mp.nsum(lambda k, j=j: x**k / mp.factorial(k + j + 1), [0, mp.inf]))
        for j in range(5):
            assert abs(complex(ref[j]) - got[j, i]) <= 1e-14 * max(abs(complex(ref[j])), 1e-300) + 1e-300


def test_foh_blocks_against_mpmath_where_expm_is_the_question() -> None:
    """Lightly damped modes from omega h = 2e-8 to 12, and a near-critical one: 50-digit expm."""
    A = _blocks(np.array([1e-4, 0.3, 200.0, 6e4, 5e3, 5e3]),
                np.array([2e-7, 6e-4, 0.4, 120.0, 1e4 * (1 + 1e-6), 1e4 * 0.999]))
    h = 2e-4
    E, g = foh_blocks(A, np.array([h]), 1)
    mp.mp.dps = 50
    for j in range(A.shape[0]):
        aug = mp.zeros(4, 4)
        for r in range(2):
            for c in range(2):
                aug[r, c] = mp.mpf(A[j, r, c]) * mp.mpf(h)
        aug[1, 2] = aug[2, 3] = 1
        ex = mp.expm(aug)
        Eref = np.array([[float(ex[r, c]) for c in range(2)] for r in range(2)])
        gref = np.array([float(ex[r, 2]) * h for r in range(2)])
        assert np.abs(E[0, j] - Eref).max() < 1e-14 * np.abs(Eref).max()
        assert np.all(np.abs(g[0, 0, j] - gref) < 1e-13 * np.abs(gref))      # each row on its own


def _loop(E: np.ndarray, hk: np.ndarray, x0: np.ndarray, drive: np.ndarray, Y: np.ndarray) -> np.ndarray:
    x, out = x0.copy(), []
    for i, k in enumerate(hk):
        x = np.einsum("mij,jm->im", E[k], x) + drive[i]
        out.append(np.real(np.einsum("pim,im->p", Y, x)))
    return np.array(out)


@pytest.mark.parametrize("b", [1, 2])
@pytest.mark.parametrize("length", [1, 7, 64, 1000, 1031])
def test_scan_equals_the_step_by_step_recursion(b: int, length: int) -> None:
    rng = np.random.default_rng(length + b)
    nb, p = 9, 3
    theta = rng.uniform(0.01, 3.0, nb)
    if b == 1:       # stable complex modes, one nearly undamped
        mu = np.exp((-rng.uniform(0, 1e-2, (3, nb)) + 1j) * theta)
        E = mu.reshape(3, nb, 1, 1)
        x0 = rng.normal(size=(1, nb)) + 1j * rng.normal(size=(1, nb))
        Y = rng.normal(size=(p, 1, nb)) + 1j * rng.normal(size=(p, 1, nb))
        drive = rng.normal(size=(length, 1, nb)) + 1j * rng.normal(size=(length, 1, nb))
    else:            # rotations slightly damped, and one rigid-like Jordan block
        E = np.empty((3, nb, 2, 2))
        for k in range(3):
            c, s = np.cos(theta * (k + 1)), np.sin(theta * (k + 1))
            E[k] = np.stack([np.stack([c, s], -1), np.stack([-s, c], -1)], -2) * 0.999
            E[k, 0] = [[1.0, 0.1 * (k + 1)], [0.0, 1.0]]
        x0 = rng.normal(size=(2, nb))
        Y = rng.normal(size=(p, 2, nb))
        drive = rng.normal(size=(length, 2, nb))
    hk = np.zeros(length, int)
    odd = rng.choice(length, size=min(length, 5), replace=False)
    hk[odd] = rng.integers(1, 3, odd.size)
    y, x = scan(E, hk, x0, drive, Y)
    ref = _loop(E, hk, x0, drive, Y)
    assert np.abs(y - ref).max() <= 1e-12 * np.abs(ref).max()
    y2, _ = scan(E, hk[:-1], x0, drive[:-1], Y) if length > 1 else (ref[:0], None)
    assert np.abs(y2 - ref[:-1]).max() <= 1e-12 * np.abs(ref).max() if length > 1 else True


@pytest.mark.parametrize("factored_max", [None, 0])
@pytest.mark.parametrize("b", [1, 2])
@pytest.mark.parametrize("length", [1, 64, 1031, 10_000])
def test_scan_with_factored_forcing_equals_the_step_by_step_recursion(b: int, length: int, factored_max,
                                                                      monkeypatch) -> None:
    """The forcing passed as its factors ``d[i] = V[i] F`` (formed inside the scan) against the
    step-by-step loop on the product ``V F`` formed beforehand: one step length, as in a plain grid;
    through the block-Toeplitz GEMMs, and (``FACTORED_MAX = 0``, as for many outputs on a large
    model) through the per-step loop forming each step's forcing."""
    import vibss.time.recursion as recursion

    if factored_max is not None:
        monkeypatch.setattr(recursion, "FACTORED_MAX", factored_max)
    rng = np.random.default_rng(7 * length + b)
    nb, p, c = 11, 4, 5
    theta = rng.uniform(0.001, 3.0, nb)
    if b == 1:
        E = np.exp((-rng.uniform(0, 1e-3, nb) + 1j) * theta).reshape(1, nb, 1, 1)
        x0 = rng.normal(size=(1, nb)) + 1j * rng.normal(size=(1, nb))
        Y = rng.normal(size=(p, 1, nb)) + 1j * rng.normal(size=(p, 1, nb))
        F = rng.normal(size=(c, 1, nb)) + 1j * rng.normal(size=(c, 1, nb))
    else:
        cs_, sn = np.cos(theta), np.sin(theta)
        E = (np.stack([np.stack([cs_, sn], -1), np.stack([-sn, cs_], -1)], -2) * 0.9995)[None]
        E[0, 0] = [[1.0, 0.1], [0.0, 1.0]]
        x0 = rng.normal(size=(2, nb))
        Y = rng.normal(size=(p, 2, nb))
        F = rng.normal(size=(c, 2, nb))
    V = np.cumsum(rng.normal(size=(length, c)), axis=0)
    hk = np.zeros(length, int)
    drive = np.einsum("lc,cbn->lbn", V, F)
    y, x = scan(E, hk, x0, LowRank(V, F), Y)
    ref = _loop(E, hk, x0, drive, Y)
    assert np.abs(y - ref).max() <= 1e-12 * np.abs(ref).max()


def test_a_plain_grid_has_one_step_length() -> None:
    """``k dt`` in floats jitters its differences by ~1e-13 dt; every full step is still exactly dt
    (one key), so the recursion sees one regular step throughout."""
    from vibss.time.kernels import make_grid

    assert np.unique(np.rint(np.diff(2e-4 * np.arange(10_001)) / 2e-4 * 1e12)).size > 1   # the jitter
    for dt, n in ((2e-4, 10_001), (1e-3 / 3, 30_000), (0.1, 7)):
        g = make_grid(n, dt, np.zeros(0))
        assert g.steps.tolist() == [dt] and not g.hkey.any()
    g = make_grid(11, 0.1, np.array([0.25, 0.3 + 1e-12]))      # a split step, and one on a sample
    assert g.steps.round(15).tolist() == [0.05, 0.1] and np.bincount(g.hkey).tolist() == [2, 9]


def test_modal_path_against_solve_ivp_in_every_regime() -> None:
    """One body on one mount at its centre: x lightly damped, y critically damped (a Jordan block),
    z overdamped, the three rotations free (rigid, undamped); initial displacement and velocity
    (a spin), a slow sine (exact sine pieces, omega dt ~ 6e-4) and a half-sine pulse whose edges fall
    between samples; the modal path against DOP853 at rtol 1e-13."""
    from vibss import Body, Model, Mount, MountType
    from vibss.model.excitation import Excitation, HalfSine, Sine
    from vibss.time.api import simulate

    m, k = 2.0, 800.0
    crit = 2 * np.sqrt(k * m)
    t = MountType("t", [k, k, k], [0.004 * crit, crit, 3 * crit])
    model = Model([Body("b", m, [1.0, 1.0, 1.0])], [Mount("m", t, "b")])
    exc = [Excitation("s", "force", "b", Sine(7.0, 0.1), direction=[1.0, 1.0, 1.0]),
           Excitation("p", "force", "b", HalfSine(30.0, 0.01234, 0.0371), direction=[1.0, -0.5, 0.7])]
    init = {"b": {"displacement": [1e-3, -2e-3, 5e-3, 0, 0, 0], "velocity": [0.02, 0.0, -0.1, 0.3, 0, 0]}}
    kw = dict(outputs=["b.x", "b.y", "b.z", "b.rx"], t_end=1.5, dt=1e-3, initial=init)
    got = simulate(model, exc, method="modal", **kw)
    ref = simulate(model, exc, method="ivp", solver="DOP853", rtol=1e-13, atol=1e-16, **kw)
    scale = np.abs(ref.outputs).max(axis=1, keepdims=True)
    assert (np.abs(got.outputs - ref.outputs) / scale).max() < 1e-9


def test_complex_modes_refined_for_a_time_horizon_against_mpmath() -> None:
    """Stiff overdamped modes put |lam| at ~1e7 beside lightly damped ones at 1 rad/s, so ``eig``'s
    absolute error (eps max|lam|) is large for the slow poles; the time path's refinement (the root
    of x^T Q(lam) x = 0 nearest to eig's, all modes by two GEMMs) must keep the error each pole makes
    over the horizon, ``|d lam| min(horizon, 1 / |Re lam|)``, as small as the per-mode inverse
    iteration does for frequency responses (``|d lam| / |Re lam|``), against a 40-digit
    eigen-decomposition."""
    from vibss.linear.eigen.complex_modes import complex_modes

    rng = np.random.default_rng(3)
    n = 10
    w = np.geomspace(1.0, 1e4, n)
    d = np.concatenate([2e-4 * w[:6], 1e7 * np.ones(n - 6)])       # light, then heavily overdamped
    R = rng.normal(size=(n, n)) * 0.3
    G = np.diag(d) + (R + R.T) * np.sqrt(np.outer(d, d)) * 0.05
    G = 0.5 * (G + G.T)
    mp.mp.dps = 40
    N = 2 * n
    A = mp.zeros(N, N)
    for i in range(n):
        A[i, n + i] = mp.mpf(w[i])
        A[n + i, i] = -mp.mpf(w[i])
        for j in range(n):
            A[n + i, n + j] = -mp.mpf(G[i, j])
    ref = np.array([complex(x) for x in mp.eig(A, left=False, right=False)])
    slow = ref[np.abs(ref) < 1e3]
    for horizon in (2.0, np.inf):
        lam = complex_modes(w, np.arange(n), w**2, G, horizon=horizon).lam
        for z in slow:
            err = np.min(np.abs(lam - z))
            assert err * min(horizon, 1 / abs(z.real)) < 1e-10
            assert err < 1e-11 * abs(z)
