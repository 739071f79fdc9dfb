"""Modal contributions to a time response: each term against the closed-form modal step response of a
proportionally damped 2-DOF chain, the total against an independent solve_ivp written here, and the
terms plus the residual against vibss.simulate (classical and complex modes; ground motion seen by
absolute and relative outputs)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import cases.models as cases
import vibss
from vibss import Body, Model, Mount, MountType
from vibss.errors import AnalysisError, ArgumentError
from vibss.model.excitation import Excitation, HalfSine, Haversine, Step

BETA, K1, K2, M1, M2, F0 = 2e-3, 3e4, 4e4, 10.0, 4.0, 50.0


def _chain() -> Model:
    t1 = MountType("t1", [K1] * 3, [BETA * K1] * 3)
    t2 = MountType("t2", [K2] * 3, [BETA * K2] * 3)
    return Model([Body("a", M1, [1, 1, 1]), Body("b", M2, [1, 1, 1])], [Mount("g", t1, "a"), Mount("u", t2, "b", to="a")])


def test_chain_terms_are_the_closed_form_modal_step_responses():
    """C = beta K: term r of b.z under a step F0 on a.fz is x_b x_a F0 / (m_r w_r^2) (1 - e^(-zeta w t)
    (cos w_d t + zeta w / w_d sin w_d t)), zeta = beta w_r / 2."""
    c = vibss.time_contributions(_chain(), [Excitation("s", "force", "a", Step(F0), dof="z")], outputs=["b.z", "a.z"],
                                 t_end=0.4, dt=1e-3)
    t = c.time
    tr, det = (K1 + K2) / M1 + K2 / M2, K1 * K2 / (M1 * M2)
    assert c.method == "modal"
    for w2 in (tr / 2 - np.sqrt(tr**2 / 4 - det), tr / 2 + np.sqrt(tr**2 / 4 - det)):
        x = np.array([1.0, (K1 + K2 - w2 * M1) / K2])
        mr = M1 * x[0] ** 2 + M2 * x[1] ** 2
        w, zeta = np.sqrt(w2), BETA * np.sqrt(w2) / 2
        wd = w * np.sqrt(1 - zeta**2)
        eta = F0 / (mr * w2) * (1 - np.exp(-zeta * w * t) * (np.cos(wd * t) + zeta * w / wd * np.sin(wd * t)))
        same = np.abs(c.mode_frequency_hz - w / (2 * np.pi)) < 1e-8 * w        # x, y and z modes alike
        assert same.sum() == 3
        for out, xo in ((0, x[1]), (1, x[0])):
            exact = xo * x[0] * eta
            assert np.abs(c.terms[same, out].sum(axis=0) - exact).max() < 1e-9 * np.abs(exact).max()
    assert np.abs(c.residual).max() < 1e-15 * np.abs(c.total).max()          # displacements: no direct term
    # the total against solve_ivp of the z chain, written here
    M = np.diag([M1, M2])
    K = np.array([[K1 + K2, -K2], [-K2, K2]])
    A = np.block([[np.zeros((2, 2)), np.eye(2)], [-np.linalg.solve(M, K), -BETA * np.linalg.solve(M, K)]])
    f = np.r_[0.0, 0.0, F0 / M1, 0.0]
    sol = solve_ivp(lambda _, s: A @ s + f, (0, 0.4), np.zeros(4), t_eval=t, rtol=1e-11, atol=1e-14, method="DOP853")
    ref = sol.y[[1, 0]]
    assert np.abs(c.total - ref).max() < 1e-7 * np.abs(ref).max()


@pytest.mark.parametrize("excitation,outputs", [
    (Excitation("pothole", "acceleration", "ground", HalfSine(9.81, start=0.01, duration=0.02), dof="z"),
     ["motor.z", "motor.z.rel", "frame.x.rel", "mount.fl.fz", "motor.z.acc"]),
    (Excitation("bump", "displacement", "ground", Haversine(0.01, duration=0.05), dof="z"),
     ["motor.z", "motor.z.rel", "frame.rx"]),
    (Excitation("hit", "force", "motor", HalfSine(500.0, start=0.0, duration=0.01), dof="x"),
     ["motor.x", "frame.z.vel", "motor.x.acc"]),
])
def test_terms_and_residual_sum_to_simulate(excitation, outputs):
    m = cases.asymmetric_model()                       # non-proportional damping: complex modes
    kw = dict(outputs=outputs, t_end=0.3, dt=5e-4)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        c = vibss.time_contributions(m, [excitation], **kw)
        ref = vibss.simulate(m, [excitation], **kw)
    assert c.method == "complex"
    assert c.output_names == ref.output_names and np.array_equal(c.time, ref.time)
    scale = np.abs(ref.outputs).max(axis=1, keepdims=True)
    assert (np.abs(c.total - ref.outputs) / scale).max() < 1e-9
    assert (np.abs(c.response.outputs - ref.outputs) / scale).max() < 1e-12
    assert "checked" in c.note


def test_relative_and_absolute_differ_by_the_ground_motion_in_the_residual():
    """Under a ground displacement z_g, the absolute output minus the relative one is z_g: the modes'
    terms are the same for both, the difference sits in the residual (the direct term)."""
    bump = Excitation("bump", "displacement", "ground", Haversine(0.01, duration=0.05), dof="z")
    c = vibss.time_contributions(_chain(), [bump], outputs=["b.z", "b.z.rel"], t_end=0.2, dt=1e-3)
    assert np.abs(c.terms[:, 0] - c.terms[:, 1]).max() < 1e-12 * np.abs(c.total).max()
    zg = c.response.inputs[0]
    assert np.abs(c.residual[0] - c.residual[1] - zg).max() < 1e-12 * 0.01


def test_n_modes_puts_the_rest_into_the_residual_and_dominant_names_the_peak_mode():
    m = cases.sdof(10.0, 1e4, 20.0)
    ex = [Excitation("s", "force", "b", HalfSine(100.0, start=0.0, duration=0.02), dof="z")]
    full = vibss.time_contributions(m, ex, outputs=["b.z"], t_end=0.5, dt=1e-3, record_from=0.05)
    few = vibss.time_contributions(m, ex, outputs=["b.z"], t_end=0.5, dt=1e-3, record_from=0.05, n_modes=2)
    assert len(few) == 2 and few.time[0] == pytest.approx(0.05)
    assert np.abs(few.total - full.total).max() < 1e-12 * np.abs(full.total).max()
    j = full.peak_index(0)
    z = int(np.argmax(np.abs(full.terms[:, 0, j])))
    assert full.mode_frequency_hz[z] == pytest.approx(np.sqrt(1e4 / 10.0) / (2 * np.pi), rel=1e-12)
    assert full.share_at(0, j)[z] == pytest.approx(1.0, abs=1e-12)
    assert full.share_in(0, full.window_of(0)).sum() == pytest.approx(1.0, abs=1e-12)
    table = full.dominant(top=2)
    assert table.rows[0][4] == str(z + 1) and table.rows[0][7] == "100.0"
    assert "residual" in [r[4] for r in table.rows]
    assert few.to_pandas().shape[0] == 3 * few.time.size


def test_refuses_what_has_no_modal_split():
    with pytest.raises(ArgumentError):
        vibss.time_contributions(_chain(), [Excitation("s", "force", "a", Step(1.0), dof="z")], t_end=0.1, dt=1e-3,
                                 n_modes=-1)
    zener = MountType("z", rheology={"type": "zener", "k_0": [1e4] * 3, "k_inf": [3e4] * 3, "tau": 1e-3})
    with pytest.raises(AnalysisError, match="frequency-dependent"):
        vibss.time_contributions(cases.sdof(10.0, mount_type=zener), [Excitation("s", "force", "b", Step(1.0), dof="z")],
                                 t_end=0.1, dt=1e-3)


def test_plot(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    m = cases.asymmetric_model()
    ex = [Excitation("hit", "force", "motor", HalfSine(500.0, start=0.0, duration=0.01), dof="z")]
    c = vibss.time_contributions(m, ex, outputs=["motor.z", "frame.z"], t_end=0.3, dt=1e-3)
    fig = c.plot(output="motor.z", top=3)
    assert fig.axes[0].get_xlabel() == "time [s]" and "[m]" in fig.axes[0].get_ylabel()
    fig.savefig(tmp_path / "t.png")


def test_the_check_catches_a_lost_mode(monkeypatch):
    """The self-check is not decoration: a mode's rows dropped from the split is a warning that states it."""
    import vibss.insight.time_split as tc

    real = tc._per_mode

    def lossy(ms, slot, slots):
        y = real(ms, slot, slots)
        p = ms.Y.shape[0]
        top = int(np.abs(y.reshape(slots, p, -1)).sum(axis=(1, 2)).argmax())
        y[top * p:(top + 1) * p] = 0.0
        return y

    monkeypatch.setattr(tc, "_per_mode", lossy)
    with pytest.warns(vibss.VibssWarning, match="missed its claim"):
        tc.time_contributions(cases.sdof(10.0, 1e4, 20.0), [Excitation("s", "force", "b", Step(1.0), dof="z")],
                              outputs=["b.z"], t_end=0.2, dt=1e-3)
