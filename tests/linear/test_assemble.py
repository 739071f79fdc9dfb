"""Assembly: invariants and an independent loop-per-mount computation."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from vibss import Body, Model, Mount, MountType, assemble
from vibss.modal.kernels import rigid_influence

from cases.reference_impl import loop_assemble, loop_mass


def test_matrices_match_independent_loop(asym):
    a = assemble(asym)
    np.testing.assert_allclose(a.K, loop_assemble(asym), rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(a.C, loop_assemble(asym, "damping"), rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(a.M, loop_mass(asym), rtol=1e-14)


@pytest.mark.parametrize("name", ["M", "K", "C"])
def test_symmetric_positive_semidefinite(asym, name):
    mat = getattr(assemble(asym), name)
    np.testing.assert_array_equal(mat, mat.T)
    w = np.linalg.eigvalsh(mat)
    assert w.min() >= -1e-12 * w.max()


def test_released_ground_stiffness_annihilates_rigid_motion(asym):
    """K_full (bodies + ground DOFs) times any rigid motion of everything is zero."""
    a = assemble(asym)
    kfull = np.block([[a.K, a.Kg], [a.Kg.T, np.zeros((6, 6))]])
    # ground's own diagonal block: rebuild it from the coupling-free identity K_full r = 0 on the
    # body rows, and check the ground rows through the deflection matrix instead
    r = np.vstack([rigid_influence(asym, about=np.zeros(3)), np.eye(6)])
    np.testing.assert_allclose(kfull[:a.n] @ r, 0.0, atol=1e-8 * np.abs(a.K).max())
    delta = a.deflection_matrix() @ r
    np.testing.assert_allclose(delta, 0.0, atol=1e-14)


def test_sparse_equals_dense(asym):
    d, s = assemble(asym, sparse=False), assemble(asym, sparse=True)
    assert sp.issparse(s.K) and not sp.issparse(d.K)
    for key in "MKCH":
        np.testing.assert_allclose(getattr(s, key).toarray(), getattr(d, key), rtol=1e-14, atol=1e-9)


def test_deflection_matrix_matches_point_motion(asym):
    a = assemble(asym)
    rng = np.random.default_rng(1)
    q = np.concatenate([rng.normal(size=a.n), np.zeros(6)])
    delta = (a.deflection_matrix() @ q).reshape(-1, 3)
    for p, m in enumerate(asym.mounts):
        point = asym.mount_point(m)
        def motion(body):
            if body == "ground":
                return np.zeros(3)
            i = asym.body_index(body)
            u, th = q[6 * i:6 * i + 3], q[6 * i + 3:6 * i + 6]
            return u + np.cross(th, point - asym.body(body).cog)
        np.testing.assert_allclose(delta[p], motion(m.body) - motion(m.to), atol=1e-13)


def test_zero_stiffness_axis_allowed():
    t = MountType("one-way", [0.0, 0.0, 5e4])
    a = assemble(Model([Body("b", 1.0, [1, 1, 1])], [Mount("m", t, "b")]))
    assert a.K[2, 2] == 5e4 and a.K[0, 0] == 0.0


def test_loads_at_points_give_moments():
    from vibss import Load

    m = Model([Body("b", 1.0, [1, 1, 1], cog=[1, 2, 3])],
              loads=[Load("l", "b", force=[0, 0, -10.0], at=[0.5, 0, 0])])
    f = assemble(m).load_vector()
    np.testing.assert_allclose(f[:3], [0, 0, -10])
    np.testing.assert_allclose(f[3:], np.cross([0.5, 0, 0], [0, 0, -10.0]))
