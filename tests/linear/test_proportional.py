"""Damping read off the matrices: ``C = a M + b K`` (and ``H``) gives the projected damping without a
projection. Checked against the projection itself (a second method) and against the values the
model was built with."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
import scipy.sparse as sp

from models import topology_model
from vibss.linear.eigen.basis import classical_damping, modal_basis, projected_damping, proportional
from vibss.linear.plant.build import build_plant


def _plant(kind: str = "random", damping: str = "classical", bodies: int = 20):
    return build_plant(topology_model(kind, bodies, damping=damping), ["b1.fz"], ["b1.z"])


@pytest.mark.parametrize("kind", ["random", "tree", "mechanism"])
def test_stiffness_proportional_damping_is_read_off_and_equals_the_projection(kind):
    plant = _plant(kind)
    ab = proportional(plant)
    assert ab is not None and ab[0] == 0.0
    K, C = np.asarray(plant.K), np.asarray(plant.C)
    ratio = C[K != 0] / K[K != 0]                 # every mount's c / k: the model's beta
    assert ab[1] == pytest.approx(float(np.median(ratio)), rel=1e-13)
    basis = modal_basis(plant)
    g = projected_damping(plant, basis)[0]
    direct = basis.phi.T @ C @ basis.phi        # the projection it replaces
    assert np.count_nonzero(g - np.diag(np.diag(g))) == 0
    scale = np.abs(np.diag(direct)).max()
    assert np.abs(np.diag(g) - np.diag(direct)).max() <= 1e-12 * scale
    assert np.abs(direct - np.diag(np.diag(direct))).max() <= 1e-12 * scale
    assert classical_damping(plant, basis)[0]


def test_rayleigh_damping_and_a_loss_factor_are_recovered():
    plant = _plant("grid", bodies=20)
    M, K = np.asarray(plant.M), np.asarray(plant.K)
    a, b = 0.37, 2.5e-4
    rayleigh = replace(plant, C=a * M + b * K, H=0.02 * K)
    got = proportional(rayleigh, "C")
    assert got is not None and got == pytest.approx((a, b), rel=1e-12)
    assert proportional(rayleigh, "H") == pytest.approx((0.0, 0.02), rel=1e-13)
    basis = modal_basis(rayleigh)
    g, h = projected_damping(rayleigh, basis)
    w2 = basis.omega2
    np.testing.assert_allclose(np.diag(g), a + b * w2, rtol=1e-12)
    np.testing.assert_allclose(np.diag(h), 0.02 * w2, rtol=1e-12)
    for got, mat in ((g, rayleigh.C), (h, rayleigh.H)):          # against the projection it replaces
        direct = basis.phi.T @ mat @ basis.phi
        scale = np.abs(np.diag(direct)).max()
        assert np.abs(got - direct).max() <= 1e-11 * scale
    assert classical_damping(rayleigh, basis)[0]


def test_a_sparse_plant_is_read_the_same_way():
    model = topology_model("grid", 20, damping="classical")
    plant = build_plant(model, ["b1.fz"], ["b1.z"], sparse=True)
    assert sp.issparse(plant.K) and sp.issparse(plant.C)
    dense = proportional(build_plant(model, ["b1.fz"], ["b1.z"]))
    assert dense is not None and proportional(plant) == pytest.approx(dense, rel=1e-13)
    rayleigh = replace(plant, C=sp.csr_matrix(0.37 * plant.M + 2.5e-4 * plant.K))
    assert proportional(rayleigh) == pytest.approx((0.37, 2.5e-4), rel=1e-12)
    assert proportional(build_plant(topology_model("grid", 20, damping="general"), ["b1.fz"], ["b1.z"],
                                    sparse=True)) is None


def test_general_damping_and_a_perturbed_entry_are_not_proportional():
    assert proportional(_plant("random", damping="general")) is None
    plant = _plant("random")
    C = np.array(plant.C)
    i, j = np.argwhere(C != 0)[3]
    C[i, j] *= 1 + 1e-9                            # one entry off by 1e-9: the projection decides
    C[j, i] = C[i, j]
    bent = replace(plant, C=C)
    assert proportional(bent) is None
    basis = modal_basis(bent)
    direct = basis.phi.T @ C @ basis.phi
    np.testing.assert_allclose(projected_damping(bent, basis)[0], 0.5 * (direct + direct.T), rtol=0, atol=1e-13 * np.abs(direct).max())


def test_a_small_damper_on_a_soft_dof_is_not_taken_for_rounding():
    """C = beta K on a chain whose stiffnesses span 1e2-1e8 N/m, plus a damper on its softest DOF that is
    1e-15 of the largest entry of beta K (under the assembly's rounding of that entry, far over the
    soft DOF's own): the bound is per entry, so C is not proportional and the projection keeps it."""
    from models import chain_model

    plant = build_plant(chain_model(10, damping="classical", scale="bad", seed=1), ["b1.fz"], ["b1.z"])
    K = np.asarray(plant.K)
    beta = 1e-4
    i = int(np.argmin(np.where(np.diag(K) > 0, np.diag(K), np.inf)))
    C = beta * K
    C[i, i] += 1e-15 * beta * np.abs(K).max()
    assert proportional(replace(plant, C=beta * K)) == (0.0, pytest.approx(beta, rel=1e-13))
    bent = replace(plant, C=C)
    assert proportional(bent) is None
    basis = modal_basis(bent)
    direct = basis.phi.T @ C @ basis.phi
    np.testing.assert_allclose(projected_damping(bent, basis)[0], 0.5 * (direct + direct.T), rtol=0,
                               atol=1e-13 * np.abs(direct).max())
