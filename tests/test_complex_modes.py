"""Left eigenvectors from the right ones (vibss.complex_modes) against an explicit inverse of V."""

import numpy as np
import pytest

from mp_reference import extended_precision_frf
from vibss.linear.complex_modes import complex_modes


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


def test_repeated_eigenvalues_fall_back_to_lu():
    """Two identical uncoupled modes: any basis of the eigenspace is returned, so V is factorised."""
    w2 = np.array([4.0, 4.0, 9.0])
    g = np.diag([0.1, 0.1, 0.2])
    cm = complex_modes(np.sqrt(w2), np.arange(3), w2, g)
    assert cm.how == "LU of V (repeated eigenvalues)"
    np.testing.assert_allclose(cm.solve(np.eye(6)), np.linalg.inv(cm.vectors), atol=1e-12)


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

    import vibss.linear.complex_modes as cmm
    from vibss.frequency.kernels import METHODS
    from vibss.linear.signals import build_plant

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


def test_close_but_resolved_eigenvalues_keep_the_structured_inverse_for_an_frf():
    """Two modes 1e-10 apart in omega^2 (eigenvalues ~3e-11 max|lam| apart, well above eig's error):
    for a frequency response they are not 'repeated' (REPEATED_TOL) and the left vectors from the
    right ones still invert V (against an explicit inverse); a time response keeps the LU there."""
    w2 = np.array([4.0, 4.0 * (1 + 1e-10), 9.0])
    g = np.diag([0.1, 0.1, 0.2])
    cm = complex_modes(np.sqrt(w2), np.arange(3), w2, g)
    assert cm.how.startswith("left eigenvectors")
    inv = np.linalg.inv(cm.vectors)
    r = np.random.default_rng(2).standard_normal((3, 2))
    full = np.vstack([np.zeros((3, 2)), r])
    np.testing.assert_allclose(cm.solve_velocity(r), inv @ full, atol=1e-9 * np.abs(inv @ full).max())
    timed = complex_modes(np.sqrt(w2), np.arange(3), w2, g, horizon=1.0)
    assert timed.how == "LU of V (repeated eigenvalues)"
