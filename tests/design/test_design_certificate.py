"""vibss.design.certificate: KE matrix from the full M against an independent eigen-solve, sums,
sag against vibss.static, windows and the protocol."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest
import scipy.linalg as sl

import vibss
from vibss.design import certificate
from vibss.errors import ArgumentError


def _independent_ke(model):
    a = vibss.assemble(model)
    M, K = np.asarray(a.M), np.asarray(a.K)
    w2, phi = sl.eigh(K, M, driver="gv")            # a second solver (LAPACK sygv)
    num = (phi * (M @ phi)).T
    return np.sqrt(w2) / 2 / np.pi, num / np.einsum("ik,ij,jk->k", phi, M, phi)[:, None], M, phi


def test_ke_matrix_is_phi_times_M_phi_with_the_full_mass_matrix(powertrain):
    cert = certificate(powertrain)
    f, ke, M, phi = _independent_ke(powertrain)
    np.testing.assert_allclose(cert.frequency_hz, f, rtol=1e-10)
    np.testing.assert_allclose(cert.ke_matrix, ke, atol=1e-10)
    np.testing.assert_allclose(cert.ke_matrix.sum(axis=1), 1.0, atol=1e-12)
    np.testing.assert_allclose(cert.ke_matrix.sum(axis=0), 1.0, atol=1e-10)
    np.testing.assert_allclose(cert.purity, ke.max(axis=1), atol=1e-10)
    # products of inertia matter: diag(M) gives a visibly different table on this powertrain
    d = np.diag(M)
    ke_diag = (phi**2 * d[:, None]).T / (phi**2 * d[:, None]).sum(axis=0)[:, None]
    assert np.abs(ke_diag - ke).max() > 0.02        # two points on one entry


def test_to_dict_holds_ke_matrix_and_purity(powertrain):
    cert = certificate(powertrain, purity=0.8, windows=(5.0, 26.7 / np.sqrt(2)))
    d = json.loads(cert.to_json())
    assert np.shape(d["ke_matrix"]) == (6, 6) and len(d["purity"]) == 6
    assert d["passed"] is False and d["pure"].count(True) == int(np.sum(cert.purity >= 0.8))
    assert cert["powertrain.z"].shape == (6,)
    assert "FAILED" in cert.report() and "purity" in cert.summary().render()
    assert list(cert.to_pandas()["purity"]) == pytest.approx(list(cert.purity))


def test_tra_frame_rows_sum_to_one_and_rotate_the_energy(powertrain):
    cert = certificate(powertrain, frame="tra")
    np.testing.assert_allclose(cert.ke_matrix.sum(axis=1), 1.0, atol=1e-12)
    tra = vibss.design.torque_roll_axis(powertrain, "powertrain", "x")
    np.testing.assert_allclose(cert.frame[:, 0], tra, atol=1e-14)
    np.testing.assert_allclose(cert.frame.T @ cert.frame, np.eye(3), atol=1e-14)


def test_sag_under_weight_and_torque_agree_with_static(powertrain):
    cert = certificate(powertrain, torque=120.0)
    a = vibss.assemble(powertrain)
    weight = a.load_vector(include_gravity=True, case="__none__") - a.load_vector(include_gravity=False, case="__none__")
    np.testing.assert_allclose(cert.sag_weight, vibss.static(a, loads=weight).q, rtol=1e-9, atol=1e-15)
    drive = np.zeros(6)
    drive[3] = 120.0
    np.testing.assert_allclose(cert.sag_torque, vibss.static(a, loads=drive).q, rtol=1e-9, atol=1e-15)


def test_windows_by_direction_and_by_mode(powertrain):
    cert = certificate(powertrain, windows={"z": (8.0, 9.0), 1: (6.0, 7.0)})
    assert cert.in_window.tolist() == [False, True, True, True, True, True]
    with pytest.raises(ArgumentError, match="unknown direction"):
        certificate(powertrain, windows={"zz": (1, 2)})
    with pytest.raises(ArgumentError, match="purity"):
        certificate(powertrain, purity=90)
    with pytest.raises(ArgumentError, match="frame"):
        certificate(powertrain, frame="tr")


def test_plot(powertrain):
    fig = certificate(powertrain, frame="tra").plot()
    assert "kinetic energy" in fig.axes[-1].get_ylabel()


def _state_space_fractions(model):
    """KE fractions of the complex modes from scipy's eig of the first-order system (independent)."""
    a = vibss.assemble(model)
    M, K, C = (np.asarray(x) for x in (a.M, a.K, a.C))
    n = len(M)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(M, K), -np.linalg.solve(M, C)]])
    lam, V = np.linalg.eig(A)
    keep = lam.imag > 0
    lam, psi = lam[keep], V[:n, keep]
    order = np.argsort(np.abs(lam))
    lam, psi = lam[order], psi[:, order]
    num = (psi.conj() * (M @ psi)).real.T
    return np.abs(lam) / 2 / np.pi, num / num.sum(axis=1, keepdims=True)


def test_damped_fractions_against_the_state_space_eigenvectors():
    pt = vibss.load_example("powertrain")
    strut = pt.mounts[-1]
    heavy = vibss.MountType("heavy-strut", strut.type.stiffness, damping=[2000.0, 50.0, 50.0])
    model = pt.replace(mounts=list(pt.mounts[:-1]) + [dataclasses.replace(strut, type=heavy)])
    cert = certificate(model, damped=True)
    f, fr = _state_space_fractions(model)
    # damped modes sorted by |pole| pair with the undamped modes in order here
    np.testing.assert_allclose(cert.ke_matrix_damped, fr, atol=1e-9)
    assert np.abs(cert.ke_matrix_damped - cert.ke_matrix).max() > 0.01      # non-proportional: differs
    assert "damped purity" in cert.summary().render()


def test_classical_damping_leaves_the_fractions_unchanged():
    t = vibss.MountType("t", [1e5, 2e5, 3e5], damping=[1e2, 2e2, 3e2])       # C = 1e-3 K
    body = vibss.Body("b", 50.0, [[2.0, 0.2, 0.1], [0.2, 3.0, -0.3], [0.1, -0.3, 4.0]])
    model = vibss.Model([body], vibss.symmetric(vibss.Mount("m", t, "b", at=[0.3, 0.2, -0.1])))
    cert = certificate(model, damped=True)
    np.testing.assert_allclose(cert.ke_matrix_damped, cert.ke_matrix, atol=1e-10)
