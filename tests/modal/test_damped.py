"""Damped modes against python-control's poles, closed forms, free bodies."""

from __future__ import annotations

import control as ct
import numpy as np

from vibss import Body, Model, Mount, MountType, assemble, damped_modes, modes


def physical_poles(model):
    a = assemble(model)
    n = a.n
    mi = np.linalg.inv(a.M)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-mi @ a.K, -mi @ a.C]])
    p = ct.ss(A, np.zeros((2 * n, 1)), np.zeros((1, 2 * n)), 0).poles()
    return p


def test_general_damping_matches_control_poles(asym):
    d = damped_modes(asym)
    assert "general" in d.method
    p = physical_poles(asym)
    p = p[p.imag >= 0]
    p = p[np.lexsort((-p.real, np.abs(p)))]
    np.testing.assert_allclose(d.poles, p, rtol=1e-9)


def test_single_dof_closed_form():
    k, c, m = 4e4, 60.0, 10.0
    t = MountType("t", [k, k, k], [c, c, c])
    # one mount at the COG: translations are single-DOF oscillators, rotations free
    d = damped_modes(Model([Body("b", m, [1, 1, 1])], [Mount("s", t, "b")]))
    wn, zeta = np.sqrt(k / m), c / (2 * np.sqrt(k * m))
    el = d.frequency_hz > 0
    np.testing.assert_allclose(d.natural_frequency[el], wn, rtol=1e-12)
    np.testing.assert_allclose(d.damping_ratio[el], zeta, rtol=1e-12)
    np.testing.assert_allclose(d.poles[el], -zeta * wn + 1j * wn * np.sqrt(1 - zeta**2), rtol=1e-12)


def test_free_body_gives_no_unstable_poles(asym):
    loose = Body("loose", 2.0, [0.1, 0.2, 0.25], cog=[2, 0, 0])
    model = asym.replace(bodies=list(asym.bodies) + [loose])
    d = damped_modes(model)
    assert np.all(d.poles.real <= 0)
    assert np.sum(d.natural_frequency == 0) == 6
    assert np.all(d.damping_ratio >= 0)
    # the elastic poles are those of the model without the loose body
    np.testing.assert_allclose(np.sort_complex(d.poles[d.natural_frequency > 0]),
                               np.sort_complex(damped_modes(asym).poles), rtol=1e-10)


def test_classical_damping_uses_closed_form():
    t = MountType("t", [1e5, 2e5, 3e5], damping=[100.0, 200.0, 300.0])   # c = 1e-3 k: C = 1e-3 K
    b = Body("b", 50.0, [2.0, 3.0, 4.0])
    from vibss import symmetric

    model = Model([b], symmetric(Mount("m", t, "b", at=[0.4, 0.3, -0.1])))
    d = damped_modes(model)
    assert "classical" in d.method
    w = modes(model).omega
    np.testing.assert_allclose(d.damping_ratio, 1e-3 * w / 2, rtol=1e-9)
    p = physical_poles(model)
    np.testing.assert_allclose(np.sort_complex(d.poles), np.sort_complex(p[p.imag >= 0]), rtol=1e-9)


def test_pairing_follows_undamped_modes(asym):
    d = damped_modes(asym)
    np.testing.assert_array_equal(d.paired, np.arange(12))
    assert d.to_dict()["modes"][0]["undamped_mode"] == 1
