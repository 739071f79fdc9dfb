"""The exact solution at a check's points from the undamped modes (:mod:`vibss.linear.solve.from_modes`):
the same numbers as the exact solve where it certifies them, and the exact solve where it cannot."""

from __future__ import annotations

import numpy as np

from vibss.linear.eigen.basis import modal_basis, projected_damping
from vibss.linear.plant.build import build_plant
from vibss.linear.solve.exact import response
from vibss.linear.solve.from_modes import ACCEPT, reference, refined_response


def _plant(kind: str = "random", damping: str = "classical"):
    from models import topology_model

    return build_plant(topology_model(kind, 40, damping=damping, zeta=1e-3, seed=3),
                       ["b3.fz", "b20.fx"], ["b3.z", "b20.x", "b33.ry"])


def _diag(plant, basis):
    gam, hys = projected_damping(plant, basis)
    return np.where(basis.rigid, 0.0, basis.omega2), np.diag(gam).copy(), np.diag(hys).copy()


def test_refined_from_the_modes_is_the_exact_solve_at_resonances_and_between():
    """A 240-DOF random graph, damping 1e-3 of critical: at each of its first resonances and between
    them every point is certified (backward error at LU's level) and matches the exact solve (LU
    with partial pivoting, a second method) to 1e-9 of each point's response."""
    p = _plant()
    b = modal_basis(p)
    w = np.sqrt(b.omega2[~b.rigid][:8])
    s = 1j * np.sort(np.concatenate([w, 0.5 * (w[:-1] + w[1:])]))
    y, ok = refined_response(p, s, b.phi, *_diag(p, b))
    assert ok.all()
    exact = np.moveaxis(response(p, s), -1, 0)
    err = np.linalg.norm(y - exact, axis=(1, 2)) / np.linalg.norm(exact, axis=(1, 2))
    assert err.max() < 1e-9


def test_a_wrong_basis_is_not_certified_and_the_exact_solve_answers():
    """Two modes swapped in frequency (their shapes kept): the modal inverse is no longer A(s)^-1,
    the one refinement step leaves a residual far above LU's level at the points near them, and
    :func:`reference` answers there with the exact solve, saying so."""
    p = _plant()
    b = modal_basis(p)
    w2, g, h = _diag(p, b)
    el = np.flatnonzero(~b.rigid)
    bad = w2.copy()
    bad[el[[2, 3]]] = bad[el[[3, 2]]]
    s = 1j * np.sqrt(w2[el[[2, 3, 20]]]) * 1.001
    _, ok = refined_response(p, s, b.phi, bad, g, h)
    assert not ok[:2].any()
    y, how = reference(p, s, b)
    np.testing.assert_allclose(y, response(p, s), rtol=1e-9, atol=0)
    assert "refined once" in how


def test_non_classical_damping_and_undamped_resonances_go_to_the_exact_solve():
    """General damping (Phi^T C Phi not diagonal): no modal inverse, the exact solve; an undamped
    model exactly at a natural frequency: not certified (the modal inverse is infinite there)."""
    p = _plant(damping="general")
    b = modal_basis(p)
    s = 1j * np.sqrt(b.omega2[~b.rigid][[0, 5]])
    y, how = reference(p, s, b)
    assert how == " against the exact solve"
    np.testing.assert_array_equal(y, response(p, s))
    from models import topology_model

    q = build_plant(topology_model("chain", 10, damping="classical", zeta=0.0, seed=1), ["b1.fz"], ["b1.z"])
    bq = modal_basis(q)
    at = 1j * np.sqrt(bq.omega2[~bq.rigid][:1])
    _, ok = refined_response(q, at, bq.phi, *_diag(q, bq))
    assert not ok.any() and ACCEPT > 0
