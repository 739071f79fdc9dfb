"""Plant.select / restrict / project against the original plant's response.

Every check compares with an independent computation: the full plant's exact FRF (a direct
complex solve written here, sharing no code with the kernels), sliced or unchanged, and the
invariants of a Galerkin projection (a full basis loses nothing; K = Kf^T Kf survives).
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from typing import Any

import numpy as np
import pytest
import scipy.linalg as sl
import scipy.sparse as sp

from vibss import Body, Model, Mount, MountType, VibssError
from vibss.errors import AnalysisError, ModelError
from vibss.linear.plant.plant import FIELD_ROLES, Plant
from vibss.linear.plant.build import build_plant


def _frf(p: Plant, w: np.ndarray) -> np.ndarray:
    """(p, m, nf) exact response at s = i w by one dense complex solve per frequency."""
    out = np.empty((len(p.outputs), len(p.inputs), w.size), complex)
    M, C, K, H = (np.asarray(a.toarray() if sp.issparse(a) else a) for a in (p.M, p.C, p.K, p.H))
    oh = 0.0 if p.Oh is None else p.Oh
    ph = 0.0 if p.Ph is None else p.Ph
    for k, wk in enumerate(w):
        s = 1j * wk
        zf = np.array([s ** -max(o, 0) if o > 0 else 1.0 for o in p.order])
        rhs = p.F - (p.Kz + 1j * p.Hz + s * p.Cz + s * s * p.Mz) * zf
        x = np.linalg.solve(K + 1j * H + s * C + s * s * M, rhs)
        y = (p.Oq + 1j * oh + s * p.Ov + s * s * p.Oa) @ x
        out[:, :, k] = y + (p.Pz + 1j * ph + s * p.Pv + s * s * p.Pa) * zf + p.Pf
    return out


def _model() -> Model:
    """Two bodies, viscous and hysteretic mounts, an offset sensor point: every map is populated."""
    t1 = MountType("t1", [2e4, 3e4, 5e4], [30.0, 20.0, 40.0], loss_factor=0.05)
    t2 = MountType("t2", [8e3, 6e3, 9e3], [5.0, 9.0, 4.0], loss_factor=[0.02, 0.1, 0.03])
    return Model([Body("a", 12.0, [0.3, 0.4, 0.5], cog=[0.0, 0.1, 0.2]),
                  Body("b", 3.0, [0.05, 0.06, 0.04], cog=[0.3, 0.0, 0.4])],
                 [Mount("m1", t1, "a", at=[0.1, 0.2, -0.1]), Mount("m2", t1, "a", at=[-0.2, 0.1, -0.1]),
                  Mount("m3", t2, "b", at=[0.05, 0.0, -0.05], to="a")])


INPUTS = ["a.fz", "ground.z.acc", "b.mx", "ground.x.disp"]
OUTPUTS = ["b.z", "a.rx", "mount.m1.fz", "mount.m3.fx", "ground.fz", "b.z.acc"]
W = 2 * np.pi * np.array([0.7, 3.0, 11.0, 29.0, 85.0])


@pytest.fixture(scope="module")
def plant() -> Plant:
    p = build_plant(_model(), INPUTS, OUTPUTS)
    assert p.Oh is not None and np.any(p.Oh) and p.Ph is not None and np.any(p.H)  # the test needs them
    return p


def test_every_field_has_a_role() -> None:
    missing = [f.name for f in fields(Plant) if f.name not in FIELD_ROLES]
    assert missing == []


def test_select_is_slicing_the_response(plant: Plant) -> None:
    full = _frf(plant, W)
    sel = plant.select(["ground.x.disp", "a.fz"], ["mount.m3.fx", "b.z", "mount.m1.fz"])
    assert sel.inputs == ("ground.x.disp", "a.fz") and sel.kinds == ("displacement", "force")
    assert sel.outputs == ("mount.m3.fx", "b.z", "mount.m1.fz") and sel.units == ("N", "m", "N")
    ref = full[np.ix_([3, 0, 2], [3, 0], range(W.size))]
    np.testing.assert_allclose(_frf(sel, W), ref, rtol=1e-12, atol=1e-14 * np.abs(ref).max())


def test_select_by_index_and_one_side_only(plant: Plant) -> None:
    full = _frf(plant, W)
    by_index = plant.select(inputs=[1], outputs=[-1, 2])
    assert by_index.inputs == ("ground.z.acc",) and by_index.outputs == ("b.z.acc", "mount.m1.fz")
    np.testing.assert_allclose(_frf(by_index, W), full[np.ix_([5, 2], [1], range(W.size))], rtol=1e-12)
    only_out = plant.select(outputs=["ground.fz"])
    assert only_out.inputs == plant.inputs and only_out.F is plant.F
    np.testing.assert_allclose(_frf(only_out, W), full[[4]], rtol=1e-12)


def test_select_refuses_unknown_names(plant: Plant) -> None:
    with pytest.raises(ModelError, match=r"no output named 'b.zz' \(did you mean 'b.z'\?\)"):
        plant.select(outputs=["b.zz"])
    with pytest.raises(ModelError, match="index 9 is out of range"):
        plant.select(inputs=[9])
    with pytest.raises(VibssError):
        plant.restrict(["a.q"])


def test_restrict_to_a_decoupled_part_is_exact() -> None:
    """Body c shares no mount with a and b: dropping its DOFs leaves a/b's response unchanged."""
    m = _model()
    iso = Model(list(m.bodies) + [Body("c", 5.0, [1, 1, 1])],
                list(m.mounts) + [Mount("mc", MountType("tc", [1e3] * 3, [1.0] * 3), "c")])
    p = build_plant(iso, ["a.fz", "ground.z.acc"], ["b.z", "mount.m1.fz"])
    keep = [d for d in p.dofs if not d.startswith("c.")]
    r = p.restrict(keep)
    assert r.dofs == tuple(keep) and r.M.shape == (12, 12) and r.Oq.shape == (2, 12)
    np.testing.assert_allclose(_frf(r, W), _frf(p, W), rtol=1e-12)
    mask = np.array([not d.startswith("c.") for d in p.dofs])
    np.testing.assert_array_equal(p.restrict(mask).K, r.K)


def test_restrict_permuted_keeps_the_response_and_clamps_dropped_dofs(plant: Plant) -> None:
    order = np.random.default_rng(1).permutation(plant.n)
    np.testing.assert_allclose(_frf(plant.restrict(order), W), _frf(plant, W), rtol=1e-11)
    # one DOF kept: a single-DOF system with the diagonal entries (closed form)
    one = plant.restrict(["b.z"])
    i = plant.dofs.index("b.z")
    w = W[2]
    dyn = plant.K[i, i] + 1j * plant.H[i, i] + 1j * w * plant.C[i, i] - w * w * plant.M[i, i]
    y = plant.Oq[0, i] * plant.F[i, 0] / dyn
    assert _frf(one, W[2:3])[0, 0, 0] == pytest.approx(y, rel=1e-12)


def test_restrict_keeps_sparse_matrices_sparse(plant: Plant) -> None:
    sparse = build_plant(_model(), INPUTS, OUTPUTS, sparse=True)
    r = sparse.restrict(list(range(6)))
    assert sp.issparse(r.K) and sp.issparse(r.F) is False
    np.testing.assert_allclose(r.K.toarray(), plant.K[:6, :6])


def test_project_on_the_full_modal_basis_reproduces_the_frf(plant: Plant) -> None:
    w2, phi = sl.eigh(plant.K, plant.M)
    modal = plant.project(phi, [f"m{i}" for i in range(plant.n)])
    assert modal.dofs[0] == "m0"
    np.testing.assert_allclose(modal.M, np.eye(plant.n), atol=1e-12)
    np.testing.assert_allclose(np.diag(modal.K), w2, rtol=1e-9, atol=1e-9 * w2.max())
    ref = _frf(plant, W)
    np.testing.assert_allclose(_frf(modal, W), ref, rtol=1e-9, atol=1e-12 * np.abs(ref).max())


def test_project_on_any_full_basis_and_known_fields(plant: Plant) -> None:
    v = np.random.default_rng(3).normal(size=(plant.n, plant.n))
    proj = plant.project(v)
    assert proj.dofs == tuple(f"v{i + 1}" for i in range(plant.n))
    ref = _frf(plant, W)
    np.testing.assert_allclose(_frf(proj, W), ref, rtol=1e-7, atol=1e-10 * np.abs(ref).max())
    known = plant.project(v, M=np.zeros((plant.n, plant.n)))
    assert not np.any(known.M)       # a known field is taken as given, not computed
    with pytest.raises(ModelError, match="not projected fields"):
        plant.project(v, F=np.zeros(1), units=())
    with pytest.raises(ModelError, match="one row per free DOF"):
        plant.project(v[:3])


def test_project_on_a_subspace_is_the_galerkin_reduction(plant: Plant) -> None:
    v = np.random.default_rng(4).normal(size=(plant.n, 5))
    p = plant.project(v)
    np.testing.assert_allclose(p.K, v.T @ plant.K @ v, rtol=1e-12)
    np.testing.assert_allclose(p.F, v.T @ plant.F, rtol=1e-12)
    np.testing.assert_allclose(p.Oh, plant.Oh @ v, rtol=1e-12)
    np.testing.assert_array_equal(p.Pf, plant.Pf)


def _dense(a):
    return a.toarray() if sp.issparse(a) else np.asarray(a)


def test_stiffness_factor_follows_restrict_and_project(plant: Plant) -> None:
    assert plant.Kf is not None                              # build_plant gives K = Kf^T Kf
    kf = _dense(plant.Kf)
    np.testing.assert_allclose(kf.T @ kf, plant.K, rtol=1e-12, atol=1e-9 * np.abs(plant.K).max())
    r = plant.restrict([0, 3, 7, 8])
    rk = _dense(r.Kf)
    np.testing.assert_allclose(rk.T @ rk, r.K, rtol=1e-12, atol=1e-9 * np.abs(plant.K).max())
    v = np.random.default_rng(5).normal(size=(plant.n, 4))
    p = plant.project(v)
    np.testing.assert_allclose(p.Kf.T @ p.Kf, p.K, rtol=1e-9, atol=1e-9 * np.abs(p.K).max())
    assert plant.project(v, K=np.eye(4)).Kf is None          # a given K: its factor is not known


def test_mount_form_kept_by_select_dropped_by_restrict_and_project(plant: Plant) -> None:
    assert plant.select(outputs=["b.z"]).mounts is plant.mounts
    assert plant.restrict([0, 1]).mounts is None and plant.project(np.eye(plant.n)[:, :2]).mounts is None


@dataclass(frozen=True, eq=False)
class _Extra(Plant):
    extra: Any = None


def test_unclassified_fields_ignored_when_none_refused_otherwise(plant: Plant) -> None:
    kw = {f.name: getattr(plant, f.name) for f in fields(Plant) if f.init}
    quiet = _Extra(**kw)
    assert quiet.select(outputs=["b.z"]).outputs == ("b.z",)
    assert quiet.restrict([0, 1]).n == 2
    loud = _Extra(**kw, extra=np.ones(3))
    with pytest.raises(AnalysisError, match="'extra' has no role"):
        loud.restrict([0, 1])
