"""Harmonic balance against independent answers: the exact FRF of a linear model, the closed-form
backbone of the symmetric bilinear stop oscillator, the end of a long solve_ivp integration (a
preloaded one-sided stop, whose mean shifts), Hill's stability against integrations started on
the branch, and the refusals. The slow sweeps' jump frequencies are in test_harmonic_sweep.py."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.interpolate import PchipInterpolator

import vibss
from vibss import Body, Model, Mount, MountType
from vibss.errors import ArgumentError, SignalError, VibssWarning
from vibss.nonlinear.harmonic import harmonic_balance

from tests.cases.models import two_body

G = 9.81


def _sdof(k: float, c: float, mass: float, stops: dict, gravity: bool = False) -> Model:
    t = MountType("snub", [k, k, k], damping=[c, c, c], stops=stops)
    return Model([Body("b", mass, [1.0, 1.0, 1.0])], [Mount("m", t, "b")],
                 gravity=[0.0, 0.0, -G] if gravity else None)


def test_a_linear_model_gives_its_frequency_response() -> None:
    model = two_body()
    names = {"engine.fz": 120.0, "ground.z.acc": 2.5 - 1.0j}
    outs = ["engine.z", "engine.rx", "mount.e1.fz", "ground.fz"]
    f = np.array([3.0, 7.5, 11.0, 40.0])
    r = harmonic_balance(model, names, outs, frequencies=f, harmonics=3)
    frf = vibss.frequency_response(model, list(names), outs, frequencies=f)
    expected = np.einsum("pmf,m->pf", frf.response, np.array(list(names.values())))
    assert np.allclose(r.frequencies, f, rtol=1e-15)
    assert np.abs(r.harmonics[:, 1, :] - expected).max() <= 1e-10 * np.abs(expected).max()
    assert not np.any(r.harmonics[:, [0, 2, 3], :])
    assert r.stable is not None and r.stable.all()                          # a damped linear model


def test_stops_out_of_reach_give_the_tangent_frequency_response() -> None:
    model = _sdof(4e4, 40.0, 10.0, {"z": (0.5, 4e5)})
    f = np.linspace(4.0, 16.0, 7)
    r = harmonic_balance(model, {"ground.z.acc": 3.0}, ["b.z", "mount.m.f3"], frequencies=f, harmonics=4)
    frf = vibss.frequency_response(vibss.operating_point(model).tangent, ["ground.z.acc"], ["b.z", "mount.m.f3"],
                                   frequencies=f)
    assert np.abs(r.harmonics[:, 1, :] - 3.0 * frf.response[:, 0, :]).max() <= 1e-10 * 3.0 * np.abs(frf.response).max()


def _bilinear_backbone(k: float, ks: float, c: float, mass: float, A: float) -> float:
    """Free-vibration frequency [rad/s] of m x'' + k x + ks (|x| - c)+ sign x = 0 at amplitude A > c.

    Outside the clearance the motion is harmonic at w2 = sqrt((k + ks)/m) about x_e = ks c/(k + ks),
    inside at w1 = sqrt(k/m); a quarter period is the time from 0 to c plus from c to A.
    """
    w1, w2 = np.sqrt(k / mass), np.sqrt((k + ks) / mass)
    xe = ks * c / (k + ks)
    t2 = np.arccos((c - xe) / (A - xe)) / w2
    vc = w2 * np.sqrt((A - xe) ** 2 - (c - xe) ** 2)
    t1 = np.arctan2(c * w1, vc) / w1                 # x = B sin(w1 t) reaches c with speed vc
    return 2 * np.pi / (4 * (t1 + t2))


def test_the_resonance_peak_follows_the_bilinear_backbone() -> None:
    k, ks, c, mass, zeta = 4e4, 4e4, 1e-3, 10.0, 2e-3     # light damping: the peak lies on the backbone
    w1 = np.sqrt(k / mass)
    model = _sdof(k, 2 * zeta * np.sqrt(k * mass), mass, {"z": (c, ks)})
    f1 = w1 / (2 * np.pi)
    r = harmonic_balance(model, {"b.fz": 2 * zeta * k * 1.6e-3}, ["b.z"], frequencies=(f1, 1.2 * f1),
                         harmonics=7, points=100, stability=False)
    b = int(np.argmax(r.peak[0]))
    A = float(r.peak[0, b])
    assert 1.3 * c < A < 2.5 * c                      # a small amplitude past the clearance
    expected = _bilinear_backbone(k, ks, c, mass, A)
    assert r.omega[b] == pytest.approx(expected, rel=5e-5)
    assert r.turning_points.size == 2 and r.turning_points.max() == pytest.approx(r.frequencies[b], rel=1e-3)


def _integrate(model_k: float, c: float, mass: float, cm: float, cp: float, ks: float, force: float, f: float,
               periods: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The last period of m x'' + c x' + k x + stop(x) = -m g + F cos(w t) from rest: times, x, force."""
    w = 2 * np.pi * f

    def stop(x: np.ndarray) -> np.ndarray:
        return ks * (np.maximum(x - cp, 0.0) + np.minimum(x + cm, 0.0))

    def rhs(t: float, y: np.ndarray) -> list[float]:
        x, v = y
        return [v, (-mass * G + force * np.cos(w * t) - c * v - model_k * x - float(stop(np.array(x)))) / mass]

    T = 2 * np.pi / w
    sol = solve_ivp(rhs, [0.0, periods * T], [0.0, 0.0], method="DOP853", rtol=1e-12, atol=1e-16, dense_output=True)
    t = (periods - 1) * T + np.linspace(0.0, T, 2048, endpoint=False)
    x, v = sol.sol(t)
    return t - (periods - 1) * T, x, model_k * x + c * v + stop(x)


def test_a_preloaded_one_sided_stop_agrees_with_a_long_integration() -> None:
    k, c, mass, ks, cm, cp = 4e4, 126.0, 10.0, 4e4, 2e-3, 1.0      # sits on the lower stop under its weight
    model = _sdof(k, c, mass, {"z": ((cm, cp), ks)}, gravity=True)
    force, f = 40.0, 10.0
    r = harmonic_balance(model, {"b.fz": force}, ["b.z", "mount.m.fz"], frequencies=[f], harmonics=25,
                         samples=4096, stability=False)
    t, x, fm = _integrate(k, c, mass, cm, cp, ks, force, f, 60)
    w = 2 * np.pi * f
    ref = 2 * np.mean(x * np.exp(-1j * w * t))
    q0 = vibss.operating_point(model).q[2]
    assert x.min() < -cm < x.max() and q0 < -cm                      # on the stop and off it: nonlinear
    assert r.harmonics[0, 1, 0] == pytest.approx(ref, rel=1e-6)
    assert q0 + r.harmonics[0, 0, 0].real == pytest.approx(np.mean(x), rel=1e-6)   # the mean shifts
    ref_f = 2 * np.mean(fm * np.exp(-1j * w * t))
    assert r.harmonics[1, 1, 0] == pytest.approx(ref_f, rel=1e-6)    # the mount force carries the stop's
    assert r.residual.max() < 1e-10 and r.truncation[0] < 1e-5


def _state(r: vibss.nonlinear.result.HarmonicBalanceResult, b: int) -> list[float]:
    Y = r.harmonics[0, :, b]
    k = np.arange(Y.size)
    return [float(np.sum(Y).real), float(np.sum(1j * k * r.omega[b] * Y).real)]


def test_the_middle_branch_is_unstable_by_both_methods_as_integrations_show() -> None:
    k, c, mass, ks, cl = 4e4, 40.0, 10.0, 4e4, 1e-3
    model = _sdof(k, c, mass, {"z": (cl, ks)})
    for method in ("floquet", "hill"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", VibssWarning)
            r = harmonic_balance(model, {"b.fz": 10.0}, ["b.z"], frequencies=(8.0, 16.0), harmonics=7, points=100,
                                 stability=method)
        assert r.stable is not None and r.turning_points.size == 2 and method in r.note.lower()
        i, j = sorted(r.turning_index)
        assert r.stable[:i - 1].all() and r.stable[j + 2:].all()
        assert not r.stable[i + 2:j - 1].any()
    # integrations from a middle-branch point and from the upper-branch point at the same frequency
    mid = (i + j) // 2
    f = r.frequencies[mid]
    upper = int(np.argmin(np.where(np.arange(r.frequencies.size) < i, np.abs(r.frequencies - f), np.inf)))
    w = r.omega[mid]

    def rhs(t: float, y: np.ndarray) -> list[float]:
        x, v = y
        s = ks * (max(x - cl, 0.0) + min(x + cl, 0.0))
        return [v, (10.0 * np.cos(w * t) - c * v - k * x - s) / mass]

    def amplitude_after(y0: list[float]) -> float:
        T = 2 * np.pi / w
        sol = solve_ivp(rhs, [0.0, 40 * T], y0, rtol=1e-9, atol=1e-13, dense_output=True)
        return float(np.abs(sol.sol(39 * T + np.linspace(0, T, 200))[0]).max())

    assert amplitude_after(_state(r, upper)) == pytest.approx(r.peak[0, upper], rel=2e-2)     # stays: stable
    away = amplitude_after(_state(r, mid))
    assert abs(away - r.peak[0, mid]) > 0.1 * r.peak[0, mid]                                   # leaves: unstable


@pytest.mark.parametrize("kwargs, error, words", [
    ({"inputs": {"b.fq": 1.0}}, SignalError, "b.fq"),
    ({"inputs": {}}, ArgumentError, "inputs"),
    ({"inputs": {"b.fz": float("nan")}}, ArgumentError, "b.fz"),
    ({"harmonics": 0}, ArgumentError, "harmonics"),
    ({"harmonics": 2.5}, ArgumentError, "harmonics"),
    ({"frequencies": (0.0, 10.0)}, ArgumentError, "frequencies"),
    ({"frequencies": [-1.0, 5.0]}, ArgumentError, "frequencies"),
    ({"frequencies": (10.0, 5.0)}, ArgumentError, "f_end > f_start"),
    ({"outputs": ["b.zz"]}, SignalError, "b.zz"),
    ({"stability": "flocket"}, ArgumentError, "floquet"),
    ({"tolerance": 0.0}, ArgumentError, "tolerance"),
])
def test_bad_input_is_refused_by_name(kwargs: dict, error: type, words: str) -> None:
    model = _sdof(4e4, 40.0, 10.0, {"z": (1e-3, 4e4)})
    args = {"inputs": {"b.fz": 10.0}, "outputs": ["b.z"], "frequencies": (5.0, 6.0), "harmonics": 3} | kwargs
    with pytest.raises(error, match=words.replace(".", r"\.")):
        harmonic_balance(model, **args)


def test_too_few_harmonics_warn_with_the_truncation_estimate() -> None:
    model = _sdof(4e4, 126.0, 10.0, {"z": (1e-3, 4e5)})
    with pytest.warns(VibssWarning, match="raise harmonics"):
        r = harmonic_balance(model, {"b.fz": 40.0}, ["b.z"], frequencies=[10.0], harmonics=3, stability=False)
    assert not r.check.ok and r.check.error > r.claim.tolerance


def test_a_hardening_curve_agrees_with_a_long_integration() -> None:
    """A Duffing-like PCHIP curve (k d + k3 d^3 through 11 points), one solution at 10 Hz; stable by
    Floquet's multipliers (the default) and Hill's method."""
    k, k3, c, mass, force, f = 4e4, 1e10, 126.0, 10.0, 20.0, 10.0
    d = np.linspace(-5e-3, 5e-3, 11)
    points = np.column_stack([d, k * d + k3 * d**3])
    t = MountType("duff", [k, k, 0.0], damping=[c] * 3, curve={"z": points.tolist()})   # z: the curve's slope
    model = Model([Body("b", mass, [1.0, 1.0, 1.0])], [Mount("m", t, "b")])
    r = harmonic_balance(model, {"b.fz": force}, ["b.z"], frequencies=[f], harmonics=15)
    law = PchipInterpolator(points[:, 0], points[:, 1])          # |x| stays inside the points
    w = 2 * np.pi * f

    def rhs(t_: float, y: np.ndarray) -> list[float]:
        return [y[1], (force * np.cos(w * t_) - c * y[1] - float(law(y[0]))) / mass]

    T = 2 * np.pi / w
    sol = solve_ivp(rhs, [0.0, 60 * T], [0.0, 0.0], method="DOP853", rtol=1e-12, atol=1e-16, dense_output=True)
    tt = 59 * T + np.linspace(0.0, T, 2048, endpoint=False)
    x = sol.sol(tt)[0]
    assert np.abs(x).max() > 1.2e-3                                 # the cubic adds over 40 % to the rate there
    assert r.harmonics[0, 1, 0] == pytest.approx(2 * np.mean(x * np.exp(-1j * w * tt)), rel=1e-6)
    assert r.stable is not None and r.stable[0] and "magnus" in r.note.lower()
    h = harmonic_balance(model, {"b.fz": force}, ["b.z"], frequencies=[f], harmonics=15, stability="hill")
    assert h.stable is not None and h.stable[0] and "hill" in h.note.lower()


def test_floquet_on_a_curve_matches_the_integrated_variational_equation() -> None:
    """The Magnus monodromy of a hardening PCHIP curve (fold, unstable middle branch) against DOP853
    (rtol 1e-13) of the variational equation ``z'' = -(c z' + f'(x(t)) z) / m`` along the same
    harmonic-balance orbit; on the stable branches the closed form: a 1-DOF oscillator's two
    multipliers of equal modulus have growth ``-c / 2m`` whatever ``f'(x(t))`` (their product is
    ``exp(-c T / m)``). The other five DOFs are damped harder, so z's exponent is the largest. Hill's
    method agrees on every flag."""
    k, k3, c, mass, force = 4e4, 1e10, 40.0, 10.0, 8.0
    d = np.linspace(-5e-3, 5e-3, 11)
    points = np.column_stack([d, k * d + k3 * d**3])
    t = MountType("duff", [k, k, 0.0], damping=[400.0, 400.0, c], curve={"z": points.tolist()},
                  rotational_stiffness=[4e4] * 3, rotational_damping=[400.0] * 3)
    model = Model([Body("b", mass, [1.0, 1.0, 1.0])], [Mount("m", t, "b")])
    r = {}
    for how in ("auto", "hill"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", VibssWarning)
            r[how] = harmonic_balance(model, {"b.fz": force}, ["b.z"], frequencies=(8.0, 16.0), harmonics=9,
                                      points=60, stability=how)
    fl = r["auto"]
    assert fl.stable is not None and "magnus" in fl.note.lower() and "hill's method at" not in fl.note.lower()
    np.testing.assert_array_equal(fl.stable, r["hill"].stable)
    i, j = sorted(fl.turning_index)
    assert fl.stable[:i].all() and fl.stable[j + 1:].all() and not fl.stable[i + 1:j].any()
    law = PchipInterpolator(points[:, 0], points[:, 1])          # |x| stays inside the points
    for b in (i - 3, i + 2, (i + j) // 2, j + 3):
        Y, w = fl.harmonics[0, :, b], fl.omega[b]
        k_ = np.arange(Y.size)

        def rhs(t_: float, z: np.ndarray) -> list[float]:
            kt = float(law(float(np.real(np.exp(1j * k_ * w * t_) @ Y)), 1))
            return [z[1], -(c * z[1] + kt * z[0]) / mass, z[3], -(c * z[3] + kt * z[2]) / mass]

        T = 2 * np.pi / w
        sol = solve_ivp(rhs, [0, T], [1.0, 0.0, 0.0, 1.0], method="DOP853", rtol=1e-13, atol=1e-15)
        mu = np.linalg.eigvals(sol.y[:, -1].reshape(2, 2).T)
        g = float(np.log(np.abs(mu).max()) / T)
        assert fl.growth[b] == pytest.approx(g, rel=1e-5, abs=1e-9)
        if fl.stable[b]:
            assert g == pytest.approx(-c / (2 * mass), rel=1e-9)


def test_where_the_magnus_steps_do_not_settle_hill_answers_and_the_note_says_so(monkeypatch) -> None:
    """Floquet's monodromy on a curve refused its own convergence (a tolerance no doubling meets): each
    such point takes Hill's method, with Hill's flags and growth rates, and the note counts them."""
    import vibss.nonlinear.hb.floquet as fq

    k, k3, c, mass = 4e4, 1e10, 126.0, 10.0
    d = np.linspace(-5e-3, 5e-3, 11)
    t = MountType("duff", [k, k, 0.0], damping=[c] * 3, curve={"z": np.column_stack([d, k * d + k3 * d**3]).tolist()})
    model = Model([Body("b", mass, [1.0, 1.0, 1.0])], [Mount("m", t, "b")])
    args = dict(inputs={"b.fz": 20.0}, outputs=["b.z"], frequencies=[8.0, 10.0, 12.0], harmonics=9)
    hill = harmonic_balance(model, **args, stability="hill")
    growth, runs = fq._growth, []

    def unsettled(phi: np.ndarray, omega: float) -> float:       # each doubling moves it by 1 1/s
        runs.append(1)
        return growth(phi, omega) + (-1.0) ** len(runs)

    monkeypatch.setattr(fq, "_growth", unsettled)
    r = harmonic_balance(model, **args)
    assert "Hill's method at 3 points" in r.note
    np.testing.assert_array_equal(r.stable, hill.stable)
    np.testing.assert_allclose(r.growth, hill.growth, rtol=1e-12)
    import vibss.nonlinear.harmonic as hb                                  # where Hill's matrix would not fit:
    monkeypatch.setattr(hb, "HILL_MAX", 100)                               # Floquet's finest answer, said so
    with pytest.warns(VibssWarning, match="did not converge"):
        r = harmonic_balance(model, **args)
    assert "unconverged at 3 points" in r.note and "limit 100" in r.note and np.all(np.isfinite(r.growth))


@pytest.mark.slow
def test_a_box_on_four_snubbers_agrees_with_its_rigid_body_equations() -> None:
    """Six DOF, stops on two local axes of four mounts, bounce, surge and pitch at once: the first
    harmonics of the motions, the ground forces (which carry the stops' forces) and the mean shift
    against the rigid body's equations of motion written here (small rotations, mounts at corners)."""
    k, c, mass, inertia = np.array([2e4, 2e4, 5e4]), np.array([60.0, 60.0, 150.0]), 20.0, np.array([0.4, 0.5, 0.6])
    ks, gap, kx, gx = 5e5, (2e-3, 1e-3), 2e5, 0.5e-3
    t = MountType("snub", k, c, stops={"z": (gap, ks), "x": (gx, kx)})
    model = Model([Body("b", mass, inertia)], vibss.symmetric(Mount("m", t, "b", at=[0.15, 0.1, 0.0])),
                  gravity=[0.0, 0.0, -G])
    f, fz, fx, my = 9.0, 150.0, 40.0, 10.0
    outs = ["b.x", "b.z", "b.ry", "ground.fz", "ground.fx"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", VibssWarning)
        r = harmonic_balance(model, {"b.fz": fz, "b.fx": fx, "b.my": my}, outs, frequencies=[f], harmonics=13)
    corners = np.array([[sx * 0.15, sy * 0.1, 0.0] for sx in (1, -1) for sy in (1, -1)])     # (4, 3)
    w = 2 * np.pi * f

    def mount_forces(q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """(4, 3) force of each mount into ground: k d + c d' + the stops beyond their gaps."""
        d = q[:3] + np.cross(q[3:], corners)
        out = k * d + c * (v[:3] + np.cross(v[3:], corners))
        out[:, 2] += ks * (np.maximum(d[:, 2] - gap[1], 0.0) + np.minimum(d[:, 2] + gap[0], 0.0))
        out[:, 0] += kx * (np.maximum(d[:, 0] - gx, 0.0) + np.minimum(d[:, 0] + gx, 0.0))
        return out

    def rhs(t_: float, y: np.ndarray) -> np.ndarray:
        fm = mount_forces(y[:6], y[6:])
        cos = np.cos(w * t_)
        force = np.array([fx * cos, 0.0, fz * cos - mass * G]) - fm.sum(axis=0)
        moment = np.array([0.0, my * cos, 0.0]) - np.cross(corners, fm).sum(axis=0)
        return np.concatenate([y[6:], force / mass, moment / inertia])

    q0 = vibss.operating_point(model).q
    T = 2 * np.pi / w
    sol = solve_ivp(rhs, [0.0, 16 * T], np.concatenate([q0, np.zeros(6)]), rtol=1e-8, atol=1e-12, dense_output=True)
    tt = 15 * T + np.linspace(0.0, T, 512, endpoint=False)              # decay times under 0.2 s: 1.8 s is steady
    y = sol.sol(tt)
    ground = np.array([mount_forces(y[:6, i], y[6:, i]).sum(axis=0) for i in range(tt.size)])
    signals = np.array([y[0], y[2], y[4], ground[:, 2], ground[:, 0]])
    ref = 2 * np.mean(signals * np.exp(-1j * w * tt), axis=1)
    error = np.abs(r.harmonics[:, 1, 0] - ref) / np.abs(ref)
    assert np.all(error[:3] < 1e-3) and np.all(error[3:] < 1e-2)          # motions; forces through stiff stops
    shift = np.mean(signals[:3], axis=1) - q0[[0, 2, 4]]
    assert r.harmonics[1:3, 0, 0].real == pytest.approx(shift[1:], rel=1e-3)  # z and ry leave their static place


def test_ground_acceleration_into_a_stop_agrees_with_a_long_integration() -> None:
    """Prescribed ground motion: the stop sees the relative deflection x - z_g, z_g = -A cos(w t) / w^2.

    At 14 Hz the hardening branch is stable but a small solution may coexist, so the integration
    starts on the harmonic-balance state: were it not a periodic orbit, 40 periods would leave it.
    """
    k, c, mass, ks, gap, acc, f = 4e4, 126.0, 10.0, 4e5, 1e-3, 15.0, 14.0
    model = _sdof(k, c, mass, {"z": (gap, ks)})
    r = harmonic_balance(model, {"ground.z.acc": acc}, ["b.z", "mount.m.d3"], frequencies=[f], harmonics=21,
                         samples=4096)
    assert r.stable is not None and r.stable[0]
    w = 2 * np.pi * f

    def rhs(t: float, y: np.ndarray) -> list[float]:
        zg, vg = -acc * np.cos(w * t) / w**2, acc * np.sin(w * t) / w
        d, v = y[0] - zg, y[1] - vg
        stop = ks * (max(d - gap, 0.0) + min(d + gap, 0.0))
        return [y[1], -(c * v + k * d + stop) / mass]

    T = 2 * np.pi / w
    sol = solve_ivp(rhs, [0.0, 40 * T], _state(r, 0), method="DOP853", rtol=1e-12, atol=1e-16, dense_output=True)
    tt = 39 * T + np.linspace(0.0, T, 2048, endpoint=False)
    x = sol.sol(tt)[0]
    d = x + acc * np.cos(w * tt) / w**2
    assert np.abs(d).max() > 1.5 * gap                              # well into the stop
    for i, signal in enumerate((x, d)):
        assert r.harmonics[i, 1, 0] == pytest.approx(2 * np.mean(signal * np.exp(-1j * w * tt)), rel=1e-6)
