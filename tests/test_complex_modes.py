"""Left eigenvectors from the right ones (vibss.complex_modes) against an explicit inverse of V."""

import numpy as np
import pytest

from mp_reference import extended_precision_frf
from vibss.linear.eigen.complex_modes import complex_modes


def _problem(ne=8, nr=2, hysteretic=False, seed=1):
    """A random symmetric QEP in scaled modal form: ``nr`` damped rigid modes, ``ne`` elastic ones."""
    rng = np.random.default_rng(seed)
    nk = ne + nr
    w2 = np.sort(rng.uniform(1.0, 100.0, ne))
    g = rng.standard_normal((nk, nk))
    g = 0.01 * g @ g.T
    coupling = None
    rows = np.arange(ne) + nr
    if hysteretic:      # i Phi^T H Phi S^-1, H symmetric and zero on the rigid modes
        h = rng.standard_normal((nk, nk))
        h = h + h.T
        h[:nr], h[:, :nr] = 0.0, 0.0
        coupling = 0.05j * h[:, rows] / np.sqrt(w2)[None, :]
    return np.sqrt(w2), rows, w2, g, coupling


def _matrix(scale, rows, w2, g, coupling):
    ne, nk = scale.size, g.shape[0]
    a = np.zeros((ne + nk, ne + nk), dtype=complex)
    a[np.arange(ne), ne + rows] = scale
    a[ne + rows, np.arange(ne)] = -w2 / scale
    if coupling is not None:
        a[ne:, :ne] -= coupling
    a[ne:, ne:] = -g
    return a


@pytest.mark.parametrize("hysteretic", [False, True])
def test_structured_inverse_matches_explicit_inverse(hysteretic):
    args = _problem(hysteretic=hysteretic)
    cm = complex_modes(*args)
    assert cm.how.startswith("left eigenvectors")
    inv = np.linalg.inv(cm.vectors)
    ne = cm.n_elastic
    np.testing.assert_allclose(cm.solve(np.eye(inv.shape[0])), inv, atol=1e-11 * np.abs(inv).max())
    np.testing.assert_allclose(cm.velocity_rows(), inv[:, ne:], atol=1e-11 * np.abs(inv).max())
    # and they diagonalise the first-order matrix
    a = _matrix(*args)
    np.testing.assert_allclose(cm.solve(a @ cm.vectors), np.diag(cm.lam), atol=1e-10 * np.abs(cm.lam).max())


def test_repeated_eigenvalues_with_a_clean_basis_keep_the_structured_solve():
    """Two identical uncoupled modes: eig returns a bi-orthogonal basis of their eigenspace here, the
    pair check sees cross terms of zero, and the structured solve is V's inverse (numpy's inv)."""
    w2 = np.array([4.0, 4.0, 9.0])
    g = np.diag([0.1, 0.1, 0.2])
    cm = complex_modes(np.sqrt(w2), np.arange(3), w2, g)
    assert cm.how.startswith("left eigenvectors")
    np.testing.assert_allclose(cm.solve(np.eye(6)), np.linalg.inv(cm.vectors), atol=1e-12)


def test_a_mixed_basis_of_a_repeated_eigenvalue_is_caught():
    """The same pair with its two eigenvectors recombined (still eigenvectors, no longer bi-orthogonal
    under the structured left vectors): the pair check reports a cross term of order one, above
    PROBE_TOL, where an LU of V is needed; the unmixed basis reports (near) zero."""
    from vibss.linear.eigen.complex_modes import PROBE_TOL, _mixed_pairs

    w2 = np.array([4.0, 4.0, 9.0])
    s = np.sqrt(w2)
    g = np.diag([0.1, 0.1, 0.2])
    a = _matrix(s, np.arange(3), w2, g, None).real
    lam, v = np.linalg.eig(a)
    i, j = [k for k in range(6) if abs(lam[k] - (-0.05 + 1.9993749j)) < 1e-6]
    vm = v.copy()
    vm[:, i], vm[:, j] = (v[:, i] + v[:, j]) / np.sqrt(2), (v[:, i] - 2 * v[:, j]) / np.sqrt(5)
    assert np.allclose(a @ vm[:, [i, j]], vm[:, [i, j]] * lam[[i, j]])        # still eigenvectors

    def worst(vec: np.ndarray) -> float:
        x = vec[3:] / lam
        norm = np.einsum("ij,ij->j", x, vec[3:]) - np.einsum("i,ij->j", w2 / s, x * vec[:3]) / lam
        return _mixed_pairs(lam, vec, x, norm, np.arange(3), w2 / s, None, 3, 1e-9 * np.abs(lam).max())

    assert worst(vm) > 0.1 > PROBE_TOL
    assert worst(v) < PROBE_TOL


def test_zero_eigenvalue_falls_back_to_lu():
    """A damped rigid mode with a zero-stiffness 'elastic' row (the time path's layout): lam = 0."""
    w2 = np.array([0.0, 25.0])
    cm = complex_modes(np.array([1.0, 5.0]), np.arange(2), w2, np.array([[0.3, 0.05], [0.05, 0.2]]))
    assert cm.how == "LU of V (a zero eigenvalue)"
    np.testing.assert_allclose(cm.solve(np.eye(4)), np.linalg.inv(cm.vectors), atol=1e-10)


def test_probe_catches_a_broken_symmetry():
    """A non-symmetric G breaks the left/right relation; the probe sees it and V is factorised."""
    scale, rows, w2, g, _ = _problem()
    g = g + 0.05 * np.triu(np.ones_like(g), 1)
    cm = complex_modes(scale, rows, w2, g)
    assert cm.how.startswith("LU of V (probe residual")
    np.testing.assert_allclose(cm.solve(np.eye(cm.vectors.shape[0])), np.linalg.inv(cm.vectors), atol=1e-10)


@pytest.mark.parametrize("hysteretic", [False, True])
def test_refined_velocity_solve(hysteretic):
    """V^-1 [0; R] with one refinement step: the residual V z - [0; R] is at rounding level."""
    cm = complex_modes(*_problem(ne=30, nr=3, hysteretic=hysteretic, seed=4))
    r = np.random.default_rng(5).standard_normal((33, 4))
    z = cm.solve_velocity(r)
    full = np.vstack([np.zeros((30, 4)), r])
    np.testing.assert_allclose(z, np.linalg.solve(cm.vectors, full), atol=1e-12 * np.abs(z).max())
    assert np.abs(cm.vectors @ z - full).max() <= 1e-14 * np.abs(cm.vectors).max() * np.abs(z).max() * 33


def test_frf_screen_refines_only_the_poles_that_are_off(monkeypatch):
    """A random tree (every mount damped, stiff overdamped modes beside light ones): the a-priori
    bound ``eps max|lam| / |Re lam|`` flags tens of modes, the a-posteriori screen sends only the few
    whose poles are really off to the dense inverse iteration, and the FRF at the resonance of every
    flagged mode still meets 1e-9 against an extended-precision solve (no eigen-decomposition)."""
    import sys
    from pathlib import Path

    import vibss.linear.eigen.complex_modes as cmm
    from vibss.frequency.kernels import METHODS
    from vibss.linear.plant.build import build_plant

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
    from models import tree_model

    model = tree_model(30, damping="general")
    ins = ["b0.fx", "b9.fy", "b20.fz"]
    outs = [f"b{i}.{d}" for i in (0, 9, 20, 29) for d in ("x", "y", "z", "rx")]
    plant = build_plant(model, ins, outs)
    seen = {}
    screen, invit = cmm._screen_poles, cmm._inverse_iteration
    monkeypatch.setattr(cmm, "_screen_poles", lambda lam, v, todo, *a: seen.update(
        at_risk=lam[todo].copy()) or screen(lam, v, todo, *a))
    monkeypatch.setattr(cmm, "_inverse_iteration", lambda lam, v, todo, *a: seen.update(
        refined=todo.size) or invit(lam, v, todo, *a))
    METHODS["complex_modal"](plant, np.array([1j]))
    assert seen["at_risk"].size >= 20 and 0 < seen["refined"] <= seen["at_risk"].size // 4
    w = np.unique(np.abs(seen["at_risk"].imag))
    s = 1j * w[w > 0]
    h = METHODS["complex_modal"](plant, s)
    ref = extended_precision_frf(plant, s)
    err = np.linalg.norm(h - ref, axis=(0, 1)) / np.linalg.norm(ref, axis=(0, 1))
    assert err.max() <= 1e-9


def test_close_distinct_eigenvalues_keep_the_structured_solve():
    """Two modes 0.001 rad/s apart beside a 1e8 rad/s one (within 1e-9 max|lam|, the tolerance that
    used to send V to an LU, as on the 600-DOF tree): their cross terms are small, the structured
    left vectors are kept, and they invert V (numpy's inv) and diagonalise A."""
    w = np.array([1.0, 1.001, 1e8])
    w2 = w * w
    rng = np.random.default_rng(3)
    r = rng.standard_normal((3, 3))
    g = 0.001 * (r @ r.T) + np.diag([0.0, 0.0, 1e4])
    cm = complex_modes(w, np.arange(3), w2, g)
    lam = cm.lam
    d = np.abs(lam[:, None] - lam[None, :])
    np.fill_diagonal(d, np.inf)
    assert d.min() < 1e-9 * np.abs(lam).max()              # a close pair is there
    assert cm.how.startswith("left eigenvectors")
    inv = np.linalg.inv(cm.vectors)
    np.testing.assert_allclose(cm.solve(np.eye(6)), inv, atol=1e-9 * np.abs(inv).max())
    a = _matrix(w, np.arange(3), w2, g, None)
    np.testing.assert_allclose(cm.solve(a @ cm.vectors), np.diag(lam), atol=1e-9 * np.abs(lam).max())


def test_close_but_resolved_eigenvalues_keep_the_structured_inverse_for_frf_and_time():
    """Two modes 1e-10 apart in omega^2 (eigenvalues ~3e-11 max|lam| apart, well above eig's error):
    their cross terms are small, so for a frequency response and a time response alike the left
    vectors from the right ones are kept, and they invert V (against an explicit inverse)."""
    w2 = np.array([4.0, 4.0 * (1 + 1e-10), 9.0])
    g = np.diag([0.1, 0.1, 0.2])
    r = np.random.default_rng(2).standard_normal((3, 2))
    full = np.vstack([np.zeros((3, 2)), r])
    for horizon in (np.inf, 1.0):
        cm = complex_modes(np.sqrt(w2), np.arange(3), w2, g, horizon=horizon)
        assert cm.how.startswith("left eigenvectors")
        inv = np.linalg.inv(cm.vectors)
        np.testing.assert_allclose(cm.solve_velocity(r), inv @ full, atol=1e-9 * np.abs(inv @ full).max())
