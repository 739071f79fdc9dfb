"""Modal contributions against closed forms (single-DOF and a proportionally damped 2-DOF chain) and,
summed with the residual, against the exact frequency response (another code path: the direct solve)."""

from __future__ import annotations

import numpy as np
import pytest

import cases.models as cases
import vibss
from vibss import Body, Model, Mount, MountType
from vibss.errors import AnalysisError, ArgumentError
from vibss.insight.kernels import classical_terms, complex_terms
from vibss.linear.eigen.basis import modal_basis, projected_damping

F = np.geomspace(0.5, 80.0, 60)


def test_single_dof_term_is_the_closed_form():
    m = cases.sdof(10.0, 1e4, 20.0)
    c = vibss.modal_contributions(m, ["b.fz"], ["b.z", "b.x"], F)
    w = 2 * np.pi * F
    exact = 1.0 / (1e4 - 10.0 * w**2 + 1j * 20.0 * w)
    k = int(np.argmax(np.abs(c.terms[:, 0, 0, 0])))
    assert np.abs(c.terms[k, 0, 0] - exact).max() < 1e-12 * np.abs(exact).max()
    others = np.delete(c.terms[:, 0, 0], k, axis=0)
    assert np.abs(others).max() < 1e-15 * np.abs(exact).max()
    assert np.abs(c.terms[:, 1, 0]).max() < 1e-15 * np.abs(exact).max()    # no x response to a z force
    assert c.method == "modal"


def test_proportionally_damped_chain_terms_are_the_closed_form():
    """C = beta K (classical): term r = x_r x_r^T / (m_r (w_r^2 - w^2 + i w beta w_r^2))."""
    beta, k1, k2, m1, m2 = 2e-3, 3e4, 4e4, 10.0, 4.0
    t1 = MountType("t1", [k1] * 3, [beta * k1] * 3)
    t2 = MountType("t2", [k2] * 3, [beta * k2] * 3)
    m = Model([Body("a", m1, [1, 1, 1]), Body("b", m2, [1, 1, 1])], [Mount("g", t1, "a"), Mount("u", t2, "b", to="a")])
    c = vibss.modal_contributions(m, ["a.fz"], ["b.z"], F)
    tr, det = (k1 + k2) / m1 + k2 / m2, k1 * k2 / (m1 * m2)
    w = 2 * np.pi * F
    for w2 in (tr / 2 - np.sqrt(tr**2 / 4 - det), tr / 2 + np.sqrt(tr**2 / 4 - det)):
        x = np.array([1.0, (k1 + k2 - w2 * m1) / k2])
        mr = m1 * x[0] ** 2 + m2 * x[1] ** 2
        exact = x[1] * x[0] / (mr * (w2 - w**2 + 1j * w * beta * w2))
        same = np.abs(c.mode_frequency_hz - np.sqrt(w2) / (2 * np.pi)) < 1e-8 * np.sqrt(w2)   # x, y, z alike
        assert same.sum() == 3
        assert np.abs(c.terms[same, 0, 0].sum(axis=0) - exact).max() < 1e-12 * np.abs(exact).max()


@pytest.mark.parametrize("inputs,outputs", [
    (["frame.fz", "motor.fx"], ["motor.z", "frame.rx.acc"]),
    (["ground.z.acc", "ground.x.disp"], ["motor.z", "mount.m1.fz", "ground.fz"]),
])
def test_terms_and_residual_sum_to_the_exact_response(inputs, outputs):
    m = cases.asymmetric_model()                       # non-proportional damping: complex modes
    c = vibss.modal_contributions(m, inputs, outputs, F)
    ref = vibss.frequency_response(m, inputs, outputs, F, method="direct").response
    scale = np.abs(ref).max(axis=2, keepdims=True)
    assert c.method == "complex"
    assert (np.abs(c.total - ref) / scale).max() < 1e-9
    assert "checked" in c.note


def test_hysteretic_and_classical_models_sum_to_the_exact_response():
    m = cases.box(10.0, [1.0, 1.2, 1.5], 1e4, 20.0, at=[0.3, 0.2, 0.0], loss_factor=0.05)
    c = vibss.modal_contributions(m, ["b.fz", "ground.y.acc"], ["b.z", "mount.m.fz", "b.ry"], F)
    ref = vibss.frequency_response(m, ["b.fz", "ground.y.acc"], ["b.z", "mount.m.fz", "b.ry"], F, method="direct").response
    scale = np.abs(ref).max(axis=2, keepdims=True)
    assert (np.abs(c.total - ref) / np.where(scale > 0, scale, 1.0)).max() < 1e-9


def test_truncation_moves_the_higher_modes_into_the_residual():
    m = cases.asymmetric_model()
    full = vibss.modal_contributions(m, ["frame.fz"], ["motor.z"], F)
    low = vibss.modal_contributions(m, ["frame.fz"], ["motor.z"], F, n_modes=4)
    assert low.terms.shape[0] == 4 and np.array_equal(low.terms, full.terms[:4])
    assert np.abs(low.residual - full.terms[4:].sum(axis=0) - full.residual).max() < 1e-12 * np.abs(full.total).max()
    assert "8 higher modes in the residual" in low.note


def test_complex_route_agrees_with_the_modal_route_on_classical_damping():
    """Two methods on one problem: the complex modes of a classically damped plant give the same terms."""
    m = cases.box(10.0, [1.0, 1.2, 1.5], 1e4, 20.0, at=[0.3, 0.2, 0.0])
    plant = vibss.build_plant(m, ["b.fz", "b.mx"], ["b.z", "b.rx", "b.x"])
    basis = modal_basis(plant)
    chat, hhat = projected_damping(plant, basis)
    s = 2j * np.pi * F
    a = classical_terms(plant, s, basis, chat, hhat).terms
    b = complex_terms(plant, s, basis, chat, hhat).terms
    elastic = ~basis.rigid
    assert np.abs(a[elastic] - b[elastic]).max() < 1e-10 * np.abs(a).max()


def test_dominant_table_names_the_resonant_mode_at_each_peak():
    m = cases.asymmetric_model()
    c = vibss.modal_contributions(m, ["frame.fz"], ["frame.z"], {"f1": 1.0, "f2": 40.0, "points": 300})
    table = c.dominant(top=1)
    peaks = c.peaks()
    assert len(table.rows) == peaks.size
    for row, f in zip(table.rows, peaks):
        k = int(row[4]) - 1
        assert k == int(np.nanargmax(c.share[:, 0, 0, f]))
    shares = np.concatenate([c.share[:, 0, 0], [np.real(c.residual[0, 0] * np.conj(c.total[0, 0])) / np.abs(c.total[0, 0]) ** 2]])
    assert np.allclose(shares.sum(axis=0), 1.0, atol=1e-9)
    fig = c.plot(output="frame.z")
    assert fig.axes[1].get_xlabel() == "frequency [Hz]"
    assert c.to_pandas().shape[0] == (len(c) + 1) * c.frequency.size


def test_refusals():
    m = cases.sdof(10.0, 1e4, 20.0)
    with pytest.raises(ArgumentError, match="frequencies"):
        vibss.modal_contributions(m, ["b.fz"], ["b.z"], [0.0, 1.0])
    zener = MountType("z", rheology={"type": "zener", "k_0": [1e4] * 3, "k_inf": [3e4] * 3, "tau": 1e-3})
    with pytest.raises(AnalysisError, match="frequency-dependent"):
        vibss.modal_contributions(cases.sdof(10.0, mount_type=zener), ["b.fz"], ["b.z"], [1.0])


def test_the_check_catches_a_lost_mode(monkeypatch):
    """The kernel's self-check is not decoration: a term dropped is a warning that states the error."""
    import dataclasses

    import vibss.insight.api as api

    real = api.classical_terms

    def lossy(*args):
        mt = real(*args)
        terms = mt.terms.copy()
        terms[int(np.abs(terms).sum(axis=(1, 2, 3)).argmax())] = 0.0
        return dataclasses.replace(mt, terms=terms)

    monkeypatch.setattr(api, "classical_terms", lossy)
    with pytest.warns(vibss.VibssWarning, match="missed its claim"):
        api.modal_contributions(cases.sdof(10.0, 1e4, 20.0), ["b.fz"], ["b.z"], F)
