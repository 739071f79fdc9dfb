"""vibss.update: synthetic measurements from known rates give them back, within the stated standard
deviations when noisy. The "measured" FRFs are computed here by an independent rigid-body model
written in numpy (B = [I, -[r]x] per mount, K = sum B^T k B), not by vibss; the measured modes by
scipy's eigh on those matrices."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import scipy.linalg as sl

import vibss
from vibss import Body, ControlPoint, Model, Mount, MountType, symmetric
from vibss.errors import ArgumentError, VibssError, VibssWarning

MASS, INERTIA, COG = 50.0, np.array([3.0, 4.0, 5.0]), np.array([0.02, -0.01, 0.05])
POINTS = np.array([(0.5, 0.4, -0.2), (-0.45, 0.35, -0.25), (-0.5, -0.42, -0.2), (0.4, -0.38, -0.22)])
DAMPING = np.array([30.0, 30.0, 50.0])
CP = np.array([0.3, 0.2, 0.1])
K3 = np.array([2e4, 3e4, 2.5e4, 3.5e4])
K1 = np.array([1.2e4, 1.0e4, 1.4e4, 0.9e4])
K2 = 1.5e4


def layout(k3=K3, k1=K1, loss=0.0) -> Model:
    """One body on four mounts (global axes) with rates k1, K2, k3 [N/m]; a control point ``c``."""
    mounts = [Mount(f"m{i}", MountType(f"t{i}", [k1[i], K2, k3[i]], DAMPING, loss_factor=loss), "b", at=p)
              for i, p in enumerate(POINTS)]
    return Model([Body("b", MASS, INERTIA, cog=COG)], mounts, [ControlPoint("c", "b", CP)], name="box")


def _skew(r):
    return np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]])


def _b(point):
    """Translation of ``point`` (relative to the COG, vibss's default frame) per (u, theta) of the
    body at its COG."""
    return np.hstack([np.eye(3), -_skew(point)])


def matrices(k3=K3, k1=K1):
    """M, C, K of the layout at the COG, by hand."""
    K = sum(_b(p).T @ np.diag([k1[i], K2, k3[i]]) @ _b(p) for i, p in enumerate(POINTS))
    C = sum(_b(p).T @ np.diag(DAMPING) @ _b(p) for p in POINTS)
    return np.diag([MASS] * 3 + list(INERTIA)), C, K


INPUTS = ["b.fz", "b.fx"]
OUTPUTS = ["b.z", "c.z", "c.x", "c.y"]


def measured_frf(f, noise=0.0, seed=0, k3=K3):
    """Receptances OUTPUTS x INPUTS [m/N] by hand, times (1 + noise * complex normal)."""
    M, C, K = matrices(k3)
    rows = np.vstack([np.eye(6)[2], _b(CP)[2], _b(CP)[0], _b(CP)[1]])
    force = np.eye(6)[:, [2, 0]]
    h = np.stack([rows @ np.linalg.solve(K + 2j * np.pi * x * C - (2 * np.pi * x) ** 2 * M, force) for x in f], -1)
    rng = np.random.default_rng(seed)
    h = h * (1 + noise * (rng.standard_normal(h.shape) + 1j * rng.standard_normal(h.shape)) / np.sqrt(2))
    return vibss.FrequencyResponse.from_measurement(f, h, INPUTS, OUTPUTS, "m/N")


F = np.geomspace(2.0, 40.0, 60)
RATES = [f"m{i}.k3" for i in range(4)]


def test_noise_free_frf_gives_the_rates_back_to_1e8_and_matches_the_hand_model():
    data = measured_frf(F)
    computed = vibss.frequency_response(layout(), INPUTS, OUTPUTS, frequencies=F)
    np.testing.assert_allclose(computed.response, data.response, rtol=1e-10)    # the two models agree
    r = vibss.update(layout(1.4 * K3), data, RATES)
    np.testing.assert_allclose(r.estimate, K3, rtol=1e-8)
    assert r.check.ok and min(r.correlation_after) > 1 - 1e-12 and max(r.correlation_before) < 0.99
    assert r.values["m2.k3"] == pytest.approx(K3[2], rel=1e-8)


def test_one_percent_noise_lands_within_the_stated_std_and_the_std_matches_monte_carlo():
    runs = [vibss.update(layout(1.1 * K3), measured_frf(F, 0.01, seed), RATES) for seed in range(8)]
    est = np.array([r.estimate for r in runs])
    std = np.array([r.standard_deviation for r in runs])
    assert np.all(np.abs(est - K3) < 3.5 * std)
    spread = est.std(axis=0, ddof=1) / std.mean(axis=0)      # 8 seeds: a sample std within ~ +-50 %
    assert np.all((spread > 0.4) & (spread < 1.8)), spread
    assert np.all(std.mean(axis=0) / K3 < 5e-3)              # 1 % noise over 480 channel-frequencies


def test_single_rate_std_is_the_closed_form_of_a_one_dof_fit():
    """One mass on one spring and dashpot: the residual H / H_m - 1 has d/dk = -H^2 / H_m, so
    std(k) = s / sqrt(sum |H|^4 / |H_m|^2)."""
    m, k, c = 10.0, 2e4, 40.0
    model = Model([Body("b", m, [1, 1, 1])], [Mount("m", MountType("t", [k, k, k], [c, c, c]), "b")])
    f = np.linspace(3.0, 15.0, 40)
    w = 2 * np.pi * f
    h = 1 / (k - m * w**2 + 1j * c * w)
    rng = np.random.default_rng(3)
    data = h * (1 + 0.02 * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)))
    start = Model([Body("b", m, [1, 1, 1])], [Mount("m", MountType("t", [k, k, 1.2 * k], [c, c, c]), "b")])
    r = vibss.update(start, vibss.FrequencyResponse.from_measurement(f, data, ["b.fz"], ["b.z"]), "m.k3")
    kk = r.estimate[0]
    hk = 1 / (kk - m * w**2 + 1j * c * w)
    n = 2 * f.size
    s = r.residual_rms[1] * np.sqrt(n / (n - 1))
    assert r.standard_deviation[0] == pytest.approx(s / np.sqrt(np.sum(np.abs(hk) ** 4 / np.abs(data) ** 2)), rel=1e-6)
    assert abs(kk - k) < 3 * r.standard_deviation[0]
    assert model.mounts[0].type.stiffness[2] == k             # the input model is untouched


def _measured_modes(noise=0.0, seed=0, outputs=("b.x", "b.y", "b.z", "c.x", "c.y", "c.z")):
    """Frequencies [Hz] and shapes by scipy's eigh of the hand matrices, with relative noise sized as
    the residuals are (sigma on each frequency, sigma |m| on each shape component)."""
    M, _, K = matrices()
    lam, phi = sl.eigh(K, M)
    rows = {"b.x": np.eye(6)[0], "b.y": np.eye(6)[1], "b.z": np.eye(6)[2],
            "c.x": _b(CP)[0], "c.y": _b(CP)[1], "c.z": _b(CP)[2]}
    shapes = np.array([rows[o] for o in outputs]) @ phi
    rng = np.random.default_rng(seed)
    f = np.sqrt(lam) / (2 * np.pi) * (1 + noise * rng.standard_normal(6))
    shapes = shapes + noise * np.linalg.norm(shapes, axis=0) * rng.standard_normal(shapes.shape)
    return vibss.MeasuredModes(f, -3.0 * shapes, list(outputs))        # any scale and sign


EIGHT = RATES + [f"m{i}.k1" for i in range(4)]


def test_modes_give_eight_rates_back_noise_free_and_within_std_with_noise():
    r = vibss.update(layout(1.2 * K3, 1.2 * K1), _measured_modes(), EIGHT)
    np.testing.assert_allclose(r.estimate, np.concatenate([K3, K1]), rtol=1e-8)
    assert np.all(r.correlation_after > 1 - 1e-12) and r.kind == "modes"
    r = vibss.update(layout(1.2 * K3, 1.2 * K1), _measured_modes(0.01, 5), EIGHT)
    assert np.all(np.abs(r.estimate - np.concatenate([K3, K1])) < 3.5 * r.standard_deviation)
    np.testing.assert_allclose(r.frequency_after, _measured_modes(0.01, 5).frequency_hz, rtol=0.03)


def test_eight_rates_from_a_noisy_frf_land_within_the_stated_std():
    truth = np.concatenate([K3, K1])
    data = measured_frf(F, 0.01, 11)
    r = vibss.update(layout(1.15 * K3, 0.85 * K1), data, EIGHT)
    assert np.all(np.abs(r.estimate - truth) < 3.5 * r.standard_deviation)
    assert np.all(r.standard_deviation / truth < 0.05)


def test_a_mount_position_comes_back_from_modes():
    """The measured modes: scipy's eigh of the hand matrices with mount m0 2 cm higher."""
    POINTS[0, 2] += 0.02
    try:
        tested = _measured_modes()
    finally:
        POINTS[0, 2] -= 0.02
    r = vibss.update(layout(), tested, ["m0.z", "m0.k3"])
    assert r.values["m0.z"] == pytest.approx(0.02, rel=1e-7) and r.values["m0.k3"] == pytest.approx(K3[0], rel=1e-8)


def _central(problem, x, h):
    return np.column_stack([(problem.residual(x + hi * e, False)[0] - problem.residual(x - hi * e, False)[0])
                            / (2 * hi) for hi, e in zip(h, np.eye(x.size))])


def test_frf_jacobian_is_the_central_difference_for_rates_ratios_ties_ground_inputs_and_mount_forces():
    from vibss.design.parameters import Parameter, current_values, parameters_of
    from vibss.measured.update import _frf_problem

    model = layout(loss=0.1)
    params = parameters_of(model, ["m0.k3", "m1.k1/k3", "m1.k3",
                                   Parameter("pair", [("m2", "k2", 1.0), ("m3", "k2", 2.0)])])
    f = np.array([4.0, 7.5, 11.0])
    ins, outs = ["ground.z.acc", "b.fy"], ["c.z", "mount.m0.fz", "b.ry"]
    h = vibss.frequency_response(model, ins, outs, frequencies=f)
    fake = vibss.FrequencyResponse.from_measurement(f, h.response * 1.1, ins, outs)
    problem = _frf_problem(model, fake, params, None)
    x = current_values(model, params) * np.array([1.1, 0.9, 1.2, 1.05])
    problem.residual(0.8 * x, True)          # derivative plants built elsewhere: kept where constant
    assert set(problem._constant) == {0, 3}
    _, jac = problem.residual(x, True)
    fd = _central(problem, x, 1e-5 * np.abs(x))
    assert np.abs(fd - jac).max() < 1e-6 * np.abs(jac).max()


def test_modes_jacobian_is_the_central_difference_for_rates_positions_and_angles():
    from vibss.design.parameters import parameters_of
    from vibss.measured.update import _modes_problem

    model = layout()
    params = parameters_of(model, ["m0.k3", "m1.z", "m2.rx", "m3.k1"])
    problem = _modes_problem(model, _measured_modes(0.02, 1), params, {"shape": 0.5})
    x = np.array([2.2e4, 0.01, 0.05, 1.0e4])
    _, jac = problem.residual(x, True)
    fd = _central(problem, x, np.array([1e-1, 1e-6, 1e-6, 1e-1]))
    assert np.abs(fd - jac).max() < 1e-6 * np.abs(jac).max()


def test_mirror_mounts_seen_only_in_bounce_warn_and_are_named():
    t = MountType("t", [1e4, 1.2e4, 3e4], [20.0, 20.0, 40.0])
    model = Model([Body("b", 40.0, [2.0, 3.0, 4.0])], symmetric(Mount("m", t, "b", at=[0.4, 0.3, 0.0])))
    f = np.linspace(2.0, 12.0, 30)
    h = vibss.frequency_response(model, ["b.fz"], ["b.z"], frequencies=f)
    data = vibss.FrequencyResponse.from_measurement(f, h.response, ["b.fz"], ["b.z"], "m/N")
    with pytest.warns(VibssWarning, match=r"cannot tell apart .*'m.k3' and 'm.xz.k3'"):
        r = vibss.update(model, data, ["m.k3", "m.xz.k3", "m.yz.k1"])
    assert r.unidentifiable == ("m.yz.k1", "m.k3 and m.xz.k3")
    assert np.all(np.isinf(r.standard_deviation))


def test_bad_names_and_arguments_raise_naming_them():
    data = measured_frf(F[:10])
    with pytest.raises(ArgumentError, match="m9"):
        vibss.update(layout(), data, ["m9.k3"])
    renamed = vibss.FrequencyResponse.from_measurement(F[:10], data.response, INPUTS, ["b.zz", *OUTPUTS[1:]])
    with pytest.raises(VibssError, match="b.zz"):
        vibss.update(layout(), renamed, RATES)
    with pytest.raises(ArgumentError, match="m0.z"):
        vibss.update(layout(), data, ["m0.z"])
    with pytest.raises(ArgumentError, match="c.q/b.fz"):
        vibss.update(layout(), data, RATES, weights={"c.q/b.fz": 2.0})
    with pytest.raises(ArgumentError, match="m7.k3"):
        vibss.update(layout(), data, RATES, bounds={"m7.k3": (1.0, 2.0)})
    with pytest.raises(ArgumentError, match="c.w"):
        vibss.update(layout(), vibss.MeasuredModes([5.0], [1.0, 0.5], ["b.z", "c.w"]), ["m0.k3"])
    with pytest.raises(ArgumentError, match="mount.m0.fz"):
        vibss.update(layout(), vibss.MeasuredModes([5.0], [1.0], ["mount.m0.fz"]), ["m0.k3"])
    with pytest.raises(ArgumentError, match="shapes"):
        vibss.MeasuredModes([5.0, 6.0], [[1.0, 0.0]], ["b.z"])


def test_a_model_far_too_stiff_is_brought_back_by_the_scan():
    """From 2.6 times the true rate the relative residual sits on its plateau (the model's response
    far below the data at 3 frequencies); the scan of a common factor starts the fit near it."""
    m, c = 10.0, 20.0
    f = np.array([3.0, 5.0, 8.0])
    w = 2 * np.pi * f
    data = vibss.FrequencyResponse.from_measurement(f, 1 / (2e4 - m * w**2 + 1j * c * w), ["b.fz"], ["b.z"])
    start = Model([Body("b", m, [1, 1, 1])], [Mount("m", MountType("t", [1e4, 1e4, 5.2e4], [c] * 3), "b")])
    r = vibss.update(start, data, ["m.k3"])
    assert r.values["m.k3"] == pytest.approx(2e4, rel=1e-8) and "rates times 0.397" in r.note


def test_bounds_hold_and_a_bad_pair_is_refused():
    data = measured_frf(F[::3])
    r = vibss.update(layout(0.9 * K3), data, RATES, bounds=[[1e4] * 4, [2.8e4] * 4])
    assert np.all(r.estimate <= 2.8e4) and r.estimate[1] == pytest.approx(2.8e4, rel=1e-6)
    with pytest.raises(ArgumentError, match="m2.k3"):
        vibss.update(layout(), data, RATES, bounds={"m2.k3": (3e4, 1e4)})


def test_the_result_follows_the_protocol_and_plots(tmp_path):
    r = vibss.update(layout(1.1 * K3), measured_frf(F[::3], 0.01), RATES, bounds={"m0.k3": (1e4, 4e4)})
    assert r["m1.k3"] == r.values["m1.k3"] and set(r.std) == set(RATES)
    assert "FRAC" in r.report() and r.to_json() and list(r.to_pandas().index) == RATES
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        fig = r.plot()
    assert len(fig.axes) == 6 and all(a.get_ylabel().endswith("[m/N]") for a in fig.axes)
    fig = vibss.update(layout(1.1 * K3), _measured_modes(), RATES).plot()
    assert fig.axes[1].get_ylabel() == "MAC [-]"
