"""The exact solution at a check's points from the undamped modes (:mod:`vibss.linear.solve.from_modes`):
the same numbers as the exact solve where it certifies them, and the exact solve where it cannot."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from vibss import Body, Model, Mount, MountType
from vibss.linear.eigen.basis import modal_basis, projected_damping
from vibss.linear.plant.build import build_plant
from vibss.linear.solve.exact import response
from vibss.linear.solve.from_modes import reference, refined_response


def _plant(kind: str = "random", damping: str = "classical"):
    from models import topology_model

    return build_plant(topology_model(kind, 40, damping=damping, zeta=1e-3, seed=3),
                       ["b3.fz", "b20.fx"], ["b3.z", "b20.x", "b33.ry"])


def _diag(plant, basis):
    gam, hys = projected_damping(plant, basis)
    return np.where(basis.rigid, 0.0, basis.omega2), np.diag(gam).copy(), np.diag(hys).copy()


def _relative(y: np.ndarray, exact: np.ndarray) -> np.ndarray:
    return np.linalg.norm(y - exact, axis=(1, 2)) / np.linalg.norm(exact, axis=(1, 2))


def test_refined_from_the_modes_is_the_exact_solve_at_resonances_and_between():
    """A 240-DOF random graph, damping 1e-3 of critical: at each of its first resonances and between
    them every point is certified and matches the exact solve (LU with partial pivoting, a second
    method) to 1e-9 of each point's response."""
    p = _plant()
    b = modal_basis(p)
    w = np.sqrt(b.omega2[~b.rigid][:8])
    s = 1j * np.sort(np.concatenate([w, 0.5 * (w[:-1] + w[1:])]))
    y, ok = refined_response(p, s, b.phi, *_diag(p, b))
    assert ok.all()
    assert _relative(y, np.moveaxis(response(p, s), -1, 0)).max() < 1e-9


def test_ground_motion_loss_factor_and_acceleration_outputs():
    """Three bodies on mounts with c = 1e-3 k and a loss factor 0.02 (C and H proportional to K):
    a prescribed ground displacement (its right-hand side and the outputs' feedthrough from
    ``zfactor``), a force, a displacement and an acceleration output: certified, and the exact
    solve's numbers to 1e-9."""
    t = MountType("t", [1e5, 1.2e5, 2e5], [100.0, 120.0, 200.0], loss_factor=0.02)
    bodies = [Body(f"b{i}", 3.0 + i, [0.05, 0.06, 0.07], cog=[0.4 * i, 0.0, 0.0]) for i in range(3)]
    mounts = [Mount("g", t, "b0", at=[0.1, 0.05, -0.1])] + [
        Mount(f"m{i}", t, f"b{i}", to=f"b{i - 1}", at=[0.4 * i - 0.2, -0.04, 0.06]) for i in (1, 2)]
    p = build_plant(Model(bodies, mounts), ["ground.z.disp", "b2.fx"], ["b2.z", "b1.y.acc"])
    b = modal_basis(p)
    s = 1j * np.sqrt(b.omega2[~b.rigid])[[0, 3, 7]] * np.array([1.0, 1.01, 0.97])
    y, ok = refined_response(p, s, b.phi, *_diag(p, b))
    assert ok.all()
    assert _relative(y, np.moveaxis(response(p, s), -1, 0)).max() < 1e-9


def test_a_wrong_basis_is_not_certified_and_the_exact_solve_answers():
    """Two modes swapped in frequency (their shapes kept): the modal inverse is no longer A(s)^-1,
    its correction does not converge at the points near them, and :func:`reference` answers there
    with the exact solve, the same numbers, and says so."""
    p = _plant()
    b = modal_basis(p)
    el = np.flatnonzero(~b.rigid)
    bad = b.omega2.copy()
    bad[el[[2, 3]]] = bad[el[[3, 2]]]
    s = 1j * np.sqrt(b.omega2[el[[2, 3, 20]]]) * 1.001
    _, ok = refined_response(p, s, b.phi, np.where(b.rigid, 0.0, bad), *_diag(p, b)[1:])
    assert not ok[:2].any()
    y, how = reference(p, s, replace(b, omega2=bad))
    exact = response(p, s)
    np.testing.assert_array_equal(y[:, :, ~ok], exact[:, :, ~ok])
    assert f"the exact solve at {int((~ok).sum())} of them" in how if ok.any() else how == " against the exact solve"


def test_non_classical_damping_goes_to_the_exact_solve():
    """General damping (Phi^T C Phi not diagonal): no modal inverse; the exact solve's own numbers."""
    p = _plant(damping="general")
    b = modal_basis(p)
    s = 1j * np.sqrt(b.omega2[~b.rigid][[0, 5]])
    y, how = reference(p, s, b)
    assert how == " against the exact solve"
    np.testing.assert_array_equal(y, response(p, s))


def test_static_from_the_modes_is_the_sparse_lu_solve_and_a_wrong_basis_is_refused():
    """``K^-1 rb`` from the modes of a 240-DOF random graph, refined once with ``K``: the same as
    SuperLU's solve (a second method) to 1e-12. The refinement is certified by its next correction,
    so a basis with one shape disturbed by 1e-6 still gives the solve to 1e-11 (one refinement
    squares the error), and one disturbed by 1e-2 is refused (None: the caller solves with ``K``);
    rigid modes or a loss factor: None."""
    import scipy.sparse as sp
    import scipy.sparse.linalg as spl

    from vibss.linear.solve.from_modes import static_from_modes

    p = _plant()
    b = modal_basis(p)
    rb = np.random.default_rng(1).standard_normal((p.n, 3))
    x = static_from_modes(p, b, rb)
    ref = spl.splu(sp.csc_matrix(p.K)).solve(rb)
    assert x is not None
    assert np.linalg.norm(x - ref, axis=0).max() <= 1e-12 * np.linalg.norm(ref, axis=0).min()
    for size, kept in ((1e-6, True), (1e-2, False)):
        phi = b.phi.copy()
        phi[:, 5] += size * phi[:, 6]
        out = static_from_modes(p, replace(b, phi=phi), rb)
        assert (out is not None) == kept
        assert out is None or np.linalg.norm(out - ref, axis=0).max() <= 1e-11 * np.linalg.norm(ref, axis=0).min()
    twin = b.phi.copy()
    twin[:, 6] = twin[:, 5]              # a rank-deficient modal inverse: its correction cannot converge
    assert static_from_modes(p, replace(b, phi=twin), rb) is None
    w2 = b.omega2.copy()
    w2[3] = 1e-320                          # subnormal: 1 / w2 is not finite
    assert static_from_modes(p, replace(b, omega2=w2), rb) is None
    one = static_from_modes(p, b, rb[:, 0], [np.eye(p.n)[:2]])             # 1-D, certified on outputs
    assert one is not None and np.allclose(one, ref[:, 0], rtol=0, atol=1e-12 * np.linalg.norm(ref[:, 0]))
    assert static_from_modes(p, replace(b, rigid=np.arange(p.n) == 0), rb) is None
    assert static_from_modes(replace(p, H=0.01 * np.asarray(p.K)), b, rb) is None


def test_a_large_models_static_part_comes_from_the_modes_without_factorising_k():
    """A 1,200-DOF random graph (past STATIC_FROM_MODES) whose K is not factorised yet: the
    mode-acceleration form's static part (:func:`vibss.frequency.terms.static`) comes from the modes,
    no factorisation of K is made, and it is SuperLU's solve (a second method) to 1e-12."""
    import scipy.sparse as sp
    import scipy.sparse.linalg as spl
    from models import topology_model

    from vibss.frequency.terms import static
    from vibss.linear.solve.exact import MOUNTS_RATIO
    from vibss.linear.solve.from_modes import STATIC_FROM_MODES

    model = topology_model("random", 200, damping="classical", zeta=1e-3, seed=3)
    fresh = build_plant(model, ["b3.fz", "b150.fx"], ["b3.z", "b150.x", "b77.ry"])
    assert fresh.n >= STATIC_FROM_MODES
    basis = modal_basis(build_plant(model, ["b3.fz"], ["b3.z"]))       # a twin plant's modes
    rb = np.random.default_rng(2).standard_normal((fresh.n, 2))
    assert fresh.mounts is None or fresh.mounts.stiffness_ratio <= MOUNTS_RATIO     # not the mounts' form
    import vibss.frequency.terms as terms
    calls = []
    real = terms.static_from_modes

    def counted(*a, **k):
        out = real(*a, **k)
        calls.append(out is not None)
        return out
    terms.static_from_modes = counted
    try:
        x = static(fresh, rb, basis)
    finally:
        terms.static_from_modes = real
    assert calls == [True] and fresh.known("solve K") is None
    ref = spl.splu(sp.csc_matrix(fresh.K)).solve(rb)
    assert np.linalg.norm(x - ref, axis=0).max() <= 1e-12 * np.linalg.norm(ref, axis=0).min()


def test_the_modal_superposition_hands_its_basis_to_the_static_part(monkeypatch):
    """``kernels.modal`` passes its complete basis to the mode-acceleration form's static part (so a
    large model may take it from the modes), and the answer is the exact solve's to 1e-10."""
    from models import topology_model

    import vibss
    import vibss.frequency.kernels as kernels

    seen = []
    real = kernels._static

    def spy(plant, rb, basis=None):
        seen.append(basis is not None and basis.phi.shape == (plant.n, plant.n))
        return real(plant, rb, basis)
    monkeypatch.setattr(kernels, "_static", spy)
    model = topology_model("random", 40, damping="classical", zeta=1e-3, seed=3)
    f = np.array([0.05, 0.5, 2.0])
    got = vibss.frequency_response(model, ["b3.fz"], ["b3.z", "b20.x"], frequencies=f, method="modal")
    exact = vibss.frequency_response(model, ["b3.fz"], ["b3.z", "b20.x"], frequencies=f, method="direct")
    assert seen and all(seen)
    assert np.abs(got.response - exact.response).max() <= 1e-10 * np.abs(exact.response).max()
