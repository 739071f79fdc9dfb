"""Frequency-dependent mounts: one ladder, one answer in the FRF, the time response, the damped modes
and the python-control system -- each checked against an independent closed form or solver."""

from __future__ import annotations

import warnings

import control
import numpy as np
import pytest
from scipy.integrate import solve_ivp

import vibss
from vibss import Body, Model, Mount, MountType
from vibss.errors import AnalysisError, ModelError, VibssWarning
from vibss.linear.plant.build import build_plant
from vibss.linear.solve.exact import response
from vibss.model.rheology import FractionalZener, fit_ladder

M, K0, KINF, TAU, C = 2.0, 1e4, 3e4, 2e-3, 8.0
K1 = KINF - K0


def _zener_type(name: str = "rubber", damping: float = C) -> MountType:
    return MountType(name, damping=[damping] * 3,
                     rheology={"type": "zener", "k_0": K0, "k_inf": KINF, "tau": TAU})


def _sdof(damping: float = C) -> Model:
    """A body on one mount at its COG: x, y, z are the same single-DOF isolator; rotations free."""
    return Model([Body("b", M, [1.0, 1.0, 1.0])], [Mount("m", _zener_type(damping=damping), "b")])


def _kstar(s: np.ndarray, damping: float = C) -> np.ndarray:
    """Zener k*(s) = k_0 + (k_inf - k_0) s tau / (1 + s tau), plus the parallel dashpot."""
    return K0 + K1 * s * TAU / (1 + s * TAU) + damping * s


# ------------------------------------------------------------------------------------- FRF

def test_zener_isolator_frf_is_the_closed_form():
    w = np.array([1.0, 30.0, 70.7, 120.0, 400.0, 3000.0])
    s = 1j * w
    k = _kstar(s)
    plant = build_plant(_sdof(), ["b.fz", "ground.z.disp"], ["b.z", "mount.m.fz", "ground.fz", "b.z.acc"])
    y = response(plant, s)
    np.testing.assert_allclose(y[0, 0], 1 / (k - M * w**2), rtol=1e-12)          # receptance
    np.testing.assert_allclose(y[0, 1], k / (k - M * w**2), rtol=1e-12)          # transmissibility
    np.testing.assert_allclose(y[1, 0], k / (k - M * w**2), rtol=1e-12)          # force into ground
    np.testing.assert_allclose(y[2, 1], M * w**2 * k / (k - M * w**2), rtol=1e-10)    # ground.fz = k (x - z)
    np.testing.assert_allclose(y[3, 1], -(w**2) * k / (k - M * w**2), rtol=1e-12)
    # the 0 Hz limit is the static stiffness k_0
    np.testing.assert_allclose(response(plant, [0j])[0, 0, 0].real, 1 / K0, rtol=1e-12)


def test_frequency_response_auto_uses_the_ladder_and_says_so():
    f = np.array([2.0, 11.0, 40.0])
    r = vibss.frequency_response(_sdof(), ["b.fz"], ["b.z"], frequencies=f)
    s = 2j * np.pi * f
    np.testing.assert_allclose(r.response[0, 0], 1 / (_kstar(s) - M * (2 * np.pi * f) ** 2), rtol=1e-12)
    assert "['m']" in r.reason and "internal Maxwell states" in r.reason
    with pytest.raises(AnalysisError, match=r"\['m'\]"):
        vibss.frequency_response(_sdof(), ["b.fz"], ["b.z"], frequencies=f, method="modal")


def test_statespace_has_the_branch_states_and_the_same_frf():
    plant = build_plant(_sdof(), ["ground.z.acc", "b.fz"], ["b.z", "mount.m.fz", "b.z.acc"])
    w = np.array([5.0, 70.0, 250.0])
    exact = response(plant, 1j * w)
    for realization in ("modal", "physical"):
        sys = vibss.statespace(plant, realization=realization)
        assert sys.nstates == 12 + 2 + 3 and sys.state_labels[-1] == "mount:m:3:b1"
        got = np.asarray(control.frequency_response(sys, w).complex).reshape(exact.shape)
        assert np.abs(got - exact).max() <= 1e-12 * np.abs(exact).max()


# ------------------------------------------------------------------------------- time domain

def _augmented_rhs(force):
    """m z'' + c z' + k_0 z + k_1 (z - u) = F(t),  tau u' = z - u   (written out by hand)."""
    def rhs(t, x):
        z, v, u = x
        return [v, (force(t) - C * v - K0 * z - K1 * (z - u)) / M, (z - u) / TAU]
    return rhs


def test_time_response_matches_solve_ivp_of_the_augmented_system():
    ramp = 0.01                                         # a ramp then a hold: exact for the FOH
    force = lambda t: np.minimum(np.asarray(t) / ramp, 1.0) * 100.0  # noqa: E731
    dt, t_end = 1e-4, 4.0
    r = vibss.simulate(_sdof(), inputs={"b.fz": force}, outputs=["b.z", "mount.m.fz"], t_end=t_end, dt=dt)
    assert r.method == "forced_response" and "['m']" in r.note
    rhs = _augmented_rhs(lambda t: force(t))
    first = solve_ivp(rhs, (0, ramp), [0, 0, 0], rtol=1e-12, atol=1e-15, method="DOP853", dense_output=True)
    second = solve_ivp(rhs, (ramp, t_end), first.y[:, -1], rtol=1e-12, atol=1e-15, method="DOP853",
                       dense_output=True)
    x = np.where(r.time <= ramp, first.sol(np.minimum(r.time, ramp)), second.sol(np.maximum(r.time, ramp)))
    z, v, u = x
    f = K0 * z + C * v + K1 * (z - u)
    assert np.abs(r.outputs[0] - z).max() <= 1e-8 * np.abs(z).max()
    assert np.abs(r.outputs[1] - f).max() <= 1e-8 * np.abs(f).max()
    np.testing.assert_allclose(r.outputs[0, -1], 100.0 / K0, rtol=1e-6)   # settles on the static stiffness


def test_long_sine_steady_state_equals_the_frf():
    w = 100.0
    poles = np.roots(np.polymul([M, C, K0], [TAU, 1.0]) + np.array([0, 0, K1 * TAU, 0]))
    decay = float(np.min(-poles.real))
    dt = 1e-5                                           # the FOH of the samples: (w dt)^2 / 12 < 1e-7
    periods = 2 * np.pi / w
    t_end = np.ceil(22.0 / decay / periods) * periods
    r = vibss.simulate(_sdof(), inputs={"b.fz": lambda t: np.sin(w * t)}, outputs=["b.z", "mount.m.fz"],
                       t_end=t_end, dt=dt, record_from=t_end - 2 * periods)
    basis = np.column_stack([np.sin(w * r.time), np.cos(w * r.time)])
    coef = np.linalg.lstsq(basis, r.outputs.T, rcond=None)[0]           # y = a sin + b cos
    amplitude = coef[0] + 1j * coef[1]                                  # Im(Y e^{iwt}) = a sin + b cos
    frf = response(build_plant(_sdof(), ["b.fz"], ["b.z", "mount.m.fz"]), [1j * w])[:, 0, 0]
    assert np.all(np.abs(amplitude - frf) <= 1e-6 * np.abs(frf))


def test_only_methods_with_internal_states_take_the_branches():
    with pytest.raises(AnalysisError, match=r"simulate: method 'newmark'.*\['m'\]"):
        vibss.simulate(_sdof(), inputs={"b.fz": lambda t: np.ones_like(t)}, t_end=0.01, dt=1e-3, method="newmark")
    # modal takes them (modes plus branch states) but not beside the free body's rigid rotations
    with pytest.raises(AnalysisError, match=r"simulate: method 'modal' refused: .*\['m'\].*rigid-body.*"
                                            r"\['forced_response'\]"):
        vibss.simulate(_sdof(), inputs={"b.fz": lambda t: np.ones_like(t)}, t_end=0.01, dt=1e-3, method="modal")


# ------------------------------------------------------------------------------- damped modes

def test_damped_modes_of_the_isolator_are_the_roots_of_its_characteristic_cubic():
    d = vibss.damped_modes(_sdof())
    cubic = np.polymul([M, C, K0], [TAU, 1.0]) + np.array([0, 0, K1 * TAU, 0])
    roots = np.roots(cubic)
    roots = roots[roots.imag >= 0]
    for lam in roots:                                   # x, y, z: each root three times
        hits = np.sum(np.abs(d.poles - lam) <= 1e-9 * abs(lam))
        assert hits == 3, (lam, d.poles)
    assert "['m']" in d.note and d.method.startswith("frequency-dependent")


def _skew(r):
    return np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]])


def test_damped_modes_are_roots_of_det_of_the_dynamic_stiffness():
    """Two mounts off the COG couple the DOFs: each pole zeroes det(K(s) + s^2 M), with K(s)
    assembled here by hand from the rheology's k*(s)."""
    zener = MountType("z", rheology={"type": "zener", "k_0": [1e4, 2e4, 3e4], "k_inf": [3e4, 3e4, 9e4],
                                     "tau": [1e-3, 2e-3, 5e-3]})
    prony = MountType("p", damping=[3.0, 3.0, 3.0],
                      rheology={"type": "prony", "k_0": 2e4, "k": [1e4, 5e3], "tau": [1e-2, 1e-3]})
    at = {"a": np.array([0.2, 0.1, 0.0]), "b": np.array([-0.2, 0.0, 0.1]), "c": np.array([0.0, -0.15, -0.1])}
    mounts = [Mount("a", zener, "b", at=at["a"]), Mount("b", prony, "b", at=at["b"]),
              Mount("c", zener, "b", at=at["c"])]
    body = Body("b", 3.0, [0.1, 0.2, 0.15])
    model = Model([body], mounts)
    d = vibss.damped_modes(model)
    mass = np.diag([3.0, 3.0, 3.0, 0.1, 0.2, 0.15])

    def kstar(t, s):
        lad = t.rheology
        if lad.kind == "zener":
            return lad.k_0 + (lad.k_inf - lad.k_0) * s * lad.tau / (1 + s * lad.tau)
        return lad.k_0 + (lad.k * s * lad.tau / (1 + s * lad.tau)).sum(axis=1) + 3.0 * s

    def dyn(s):
        k = np.zeros((6, 6), complex)
        for mt in mounts:
            lmat = np.hstack([np.eye(3), -_skew(at[mt.name])])      # deflection = u + theta x r
            k += lmat.T @ np.diag(kstar(mt.type, s)) @ lmat
        return k + s**2 * mass

    # the FRF of every back-end is the inverse of the hand-assembled dynamic stiffness
    plant = build_plant(model, ["b.fx", "b.fz", "b.my"])               # every DOF's displacement out
    s = 1j * np.array([20.0, 150.0, 700.0])
    want = np.stack([np.linalg.inv(dyn(x))[:, [0, 2, 4]] for x in s], axis=-1)
    for backend in ("dense", "banded", "superlu"):
        got = response(plant, s, backend=backend)
        assert np.abs(got - want).max() <= 1e-12 * np.abs(want).max(), backend

    osc = d.poles[d.poles.imag > 0]
    assert len(osc) == 6
    for lam in d.poles:
        sv = np.linalg.svd(dyn(lam), compute_uv=False)
        assert sv[-1] <= 1e-11 * sv[0], (lam, sv[-1] / sv[0])
    for lam in osc:                                      # Newton on det from a nearby start
        x = lam * (1 + 1e-3)
        for _ in range(30):
            h = 1e-6 * abs(x)
            det = np.linalg.det(dyn(x))
            x = x - det / ((np.linalg.det(dyn(x + h)) - np.linalg.det(dyn(x - h))) / (2 * h))
        assert abs(x - lam) <= 1e-8 * abs(lam)


# ------------------------------------------------------------------------------- fitted ladders

def test_a_tabulated_rubber_is_fitted_within_its_stated_error():
    truth = FractionalZener(1e4, 4e4, 1e-3, 0.6)       # a causal rubber, sampled into a table
    f = np.logspace(0, 3, 13)
    kst = truth.dynamic_stiffness(2 * np.pi * f)
    t = MountType("rub", rheology={"type": "table", "frequency": f, "stiffness": kst.real.T,
                                   "loss_factor": (kst.imag / kst.real).T})
    assert 0 < t.fit_error < 0.02
    check = np.logspace(0, 3, 501)
    exact = t.dynamic_stiffness(check)                  # PCHIP of the table
    fitted = t.ladder.stiffness(2 * np.pi * check)
    assert np.max(np.abs(fitted - exact) / np.abs(exact)) <= t.fit_error * (1 + 1e-9)
    # the interpolated table is the rubber to PCHIP accuracy
    ref = truth.dynamic_stiffness(2 * np.pi * check)
    assert np.max(np.abs(exact - ref) / np.abs(ref)) < 5e-3
    # every analysis uses the ladder: the FRF is the closed form with the ladder's k*
    model = Model([Body("b", 1.0, [1, 1, 1])], [Mount("m", t, "b")])
    w = 2 * np.pi * np.array([3.0, 30.0, 300.0])
    r = response(build_plant(model, ["b.fz"], ["b.z"]), 1j * w)[0, 0]
    np.testing.assert_allclose(r, 1 / (t.ladder.stiffness(w)[:, 2] - w**2), rtol=1e-11)


def test_fractional_zener_ladder_is_accurate_over_its_band():
    fz = MountType("fz", rheology={"type": "fractional_zener", "k_0": 1e4, "k_inf": 5e4, "tau": 1e-3,
                                   "alpha": 0.7})
    lad = fz.ladder
    w = 2 * np.pi * np.logspace(np.log10(lad.band[0]), np.log10(lad.band[1]), 300)
    ref = fz.rheology.dynamic_stiffness(w)
    err = np.max(np.abs(lad.stiffness(w) - ref) / np.abs(ref))
    assert err <= fz.fit_error * (1 + 1e-9) and fz.fit_error < 1e-3
    np.testing.assert_array_equal(lad.static, [1e4] * 3)           # the static stiffness is kept


def test_a_constant_loss_factor_table_is_the_causal_approximation_with_its_error():
    eta = 0.1
    lad = fit_ladder(lambda w: np.full((np.size(w), 3), 1e4 * (1 + 1j * eta)), [10.0, 100.0])
    w = 2 * np.pi * np.logspace(1, 2, 200)
    got = lad.stiffness(w)
    err = np.abs(got - 1e4 * (1 + 1j * eta)) / abs(1e4 * (1 + 1j * eta))
    assert err.max() <= lad.fit_error * (1 + 1e-9) and lad.fit_error < eta
    assert np.all(lad.k >= 0) and np.all(lad.static > 0)           # passive


# ------------------------------------------------------------------------------- bad data

@pytest.mark.parametrize("rheology, message", [
    ({"type": "table", "frequency": [1, 10, 100, 1000], "stiffness": [1e4, 1e4, -5.0, 1e4]},
     r"'bad'.*stiffness on axis 1 at 100 Hz is -5; it must be positive"),
    ({"type": "table", "frequency": [1, 10, 100, 1000], "stiffness": 1e4, "loss_factor": [0.1, -0.2, 0.1, 0.1]},
     r"'bad'.*loss_factor on axis 1 at 10 Hz is -0.2.*negative loss angle"),
    ({"type": "table", "frequency": [1, 10, 100, 1000], "stiffness": [[1e4] * 4, [1e4] * 4, [1e4, 1e4, 1e4, np.nan]]},
     r"'bad'.*stiffness on axis 3 at 1000 Hz is nan"),
    ({"type": "table", "frequency": [1, 10, 10, 1000], "stiffness": 1e4},
     r"'bad'.*frequency: expected increasing frequencies > 0"),
    ({"type": "table", "frequency": [0, 10, 100, 1000], "stiffness": 1e4},
     r"'bad'.*frequency: expected increasing frequencies > 0"),
    ({"type": "table", "frequency": [10], "stiffness": [1e4]}, r"'bad'.*at least 2 points"),
    ({"type": "table", "frequency": [1, 10, 100], "stiffness": [1e4, 2e4]}, r"'bad'.*stiffness: expected 3 values"),
    ({"type": "table", "frequency": [1, 10, 100, 1000], "stiffness": 1e4, "loss_factor": [2.0, 0.0, 0.0, 0.0]},
     r"'bad'.*fitted static stiffness is 0 N/m; a passive mount needs a positive static stiffness.* 1 Hz"),
    ({"type": "zener", "k_0": 2e4, "k_inf": 1e4, "tau": 1e-3}, r"'bad'.*k_inf = 10000 N/m is below k_0"),
    ({"type": "zener", "k_0": 1e4, "k_inf": 2e4, "tau": 0.0}, r"'bad'.*tau: axis 1 is 0.0; expected a finite number > 0"),
    ({"type": "prony", "k_0": 1e4, "k": [1e4, -1.0], "tau": [1e-3, 1e-2]}, r"'bad'.*k: axis 1, term 2"),
    ({"type": "fractional_zener", "k_0": 1e4, "k_inf": 2e4, "tau": 1e-3, "alpha": 1.5}, r"'bad'.*alpha"),
    ({"type": "zenr", "k_0": 1.0}, r"'bad'.*unknown 'zenr' \(did you mean 'zener'\?\)"),
    ({"type": "zener", "k0": 1.0}, r"'bad'.*unknown key\(s\) \['k0'\]"),
    ("zener", r"'bad': rheology: expected a table"),
])
def test_each_bad_rheology_gets_its_message(rheology, message):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", VibssWarning)
        with pytest.raises(ModelError, match=message):
            MountType("bad", rheology=rheology)


def test_inconsistent_mount_type_keys_are_refused():
    z = {"type": "zener", "k_0": 1e4, "k_inf": 2e4, "tau": 1e-3}
    with pytest.raises(ModelError, match="differs from the static stiffness"):
        MountType("t", stiffness=[2e4] * 3, rheology=z)
    with pytest.raises(ModelError, match="give the loss in the rheology"):
        MountType("t", loss_factor=0.1, rheology=z)
    with pytest.raises(ModelError, match="stiffness: give the 3 principal stiffnesses"):
        MountType("t")
    assert MountType("t", stiffness=[1e4] * 3, rheology=z).stiffness.tolist() == [1e4] * 3


def test_tables_warn_on_few_points_and_on_extrapolation():
    with pytest.warns(VibssWarning, match="'few'.*only 3 points"):
        t = MountType("few", rheology={"type": "table", "frequency": [1, 10, 100], "stiffness": [1e4, 1.1e4, 1.2e4],
                                       "loss_factor": 0.05})
    with pytest.warns(VibssWarning, match=r"'few'.*outside the table \(1 to 100 Hz, e.g. 500 Hz\)"):
        t.dynamic_stiffness([50.0, 500.0])
    with pytest.warns(VibssWarning, match=r"'flat'.*ladder.*is up to 1\d(\.\d+)? % off the table over 1 to 100 Hz"):
        MountType("flat", rheology={"type": "table", "frequency": [1, 10, 30, 100], "stiffness": 1e4,
                                    "loss_factor": 0.2})


# ------------------------------------------------------------------------------- files

def test_model_file_rheology_in_file_units_round_trips():
    text = """
[model]
name = "r"
units = {length = "mm", time = "ms"}
[[body]]
name = "b"
mass = 2.0
inertia = [1, 1, 1]
[[mount_type]]
name = "rubber"
damping = [8.0, 8.0, 8.0]
rheology = {type = "zener", k_0 = 10.0, k_inf = 30.0, tau = 2.0}
[[mount]]
name = "m"
type = "rubber"
body = "b"
"""
    model = vibss.loads_model(text)
    t = model.mount_types["rubber"]
    f = np.array([1.0, 20.0, 300.0])
    np.testing.assert_allclose(t.dynamic_stiffness(f), _zener_type().dynamic_stiffness(f), rtol=1e-12)
    again = vibss.loads_model(vibss.dumps_model(model)).mount_types["rubber"]
    np.testing.assert_array_equal(again.dynamic_stiffness(f), t.dynamic_stiffness(f))
    assert again.rheology.to_dict() == t.rheology.to_dict()
    with pytest.raises(ModelError, match=r"mount_type\[1\] \('rubber'\).*k_inf = 3000 N/m is below k_0"):
        vibss.loads_model(text.replace("k_inf = 30.0", "k_inf = 3.0"))


def test_plant_operations_keep_the_branches_consistent():
    plant = build_plant(_sdof(), ["b.fz", "ground.z.disp"], ["b.z", "mount.m.fz", "ground.fz"])
    s = 1j * np.array([40.0, 90.0])
    full = response(plant, s)
    sub = response(plant.select(["ground.z.disp"], ["ground.fz", "b.z"]), s)
    np.testing.assert_allclose(sub, full[[2, 0]][:, [1]], rtol=1e-13)
    kept = plant.restrict(["b.z"])                      # z is decoupled from the rest here
    np.testing.assert_allclose(response(kept, s), full, rtol=1e-12)


def test_mounts_guide_runs_and_its_numbers_hold(capsys):
    import re
    from pathlib import Path

    text = (Path(__file__).parents[1] / "docs" / "analyses" / "mounts.md").read_text()
    scope: dict = {}
    with warnings.catch_warnings():
        warnings.simplefilter("error", VibssWarning)
        for block in re.findall(r"```python\n(.*?)```", text, re.S):
            exec(compile(block, "mounts.md", "exec"), scope)
    out = capsys.readouterr().out
    assert "over 1 to 100 Hz: storage stiffness within 15 %, loss factor within 17 %" in out
    assert "over 5 to 20 Hz: storage stiffness within 5 %, loss factor within 4 %" in out
    np.testing.assert_allclose(vibss.modes(scope["m6"]).frequency_hz[:3],
                               np.sqrt(np.array([200.0, 300.0, 500.0]) / [0.2, 0.3, 0.4]) / (2 * np.pi), rtol=1e-12)
    # the supports' example: the lever rule at 0 Hz (bar on springs at x = -0.7 and 0.5)
    np.testing.assert_allclose(scope["tr"].response[0, :, 0].real, [0.5 / 1.2, 0.7 / 1.2], rtol=1e-12)
    assert "[0.4167 0.5833]" in out
    # the coupled 6x6 example: x and ry from det([[kx - w^2 m, kc], [kc, kry - w^2 Iy]]) = 0
    roots = np.sqrt(np.sort(np.roots([4.0 * 0.3, -(2e4 * 0.3 + 600.0 * 4.0), 2e4 * 600.0 - 1500.0**2]).real))
    f = vibss.modes(scope["mc"]).frequency_hz
    for r in roots / (2 * np.pi):
        assert np.min(np.abs(f - r)) <= 1e-12 * f.max()
    assert "6.1    7.609  8.422 11.836" in out
    assert "[5.0329 5.0329 5.627 ]" in out
    assert scope["sim"].method == "forced_response" and scope["r"].method == "direct"
    k80 = _kstar(2j * np.pi * 80.0, damping=0.0)             # the rheology alone (no dashpot) ...
    np.testing.assert_allclose(scope["rubber"].dynamic_stiffness([80.0])[0, 2], k80 + 8.0 * 2j * np.pi * 80.0,
                               rtol=1e-12)                 # ... plus the parallel dashpot


def test_report_lists_and_plots_the_rheologies():
    from vibss.plotting import plot_dynamic_stiffness
    from vibss.report import study

    table = MountType("tab", rheology={"type": "table", "frequency": [1, 10, 100, 1000],
                                       "stiffness": [1e4, 1.2e4, 1.5e4, 2e4], "loss_factor": [0.05, 0.1, 0.15, 0.2]})
    model = Model([Body("b", 2.0, [1, 1, 1])], [Mount("m", _zener_type(), "b"), Mount("n", table, "b", at=[0.1, 0, 0])])
    fig = plot_dynamic_stiffness(list(model.mount_types.values()))
    top, bottom = fig.axes
    line = top.get_lines()[0]                               # the Zener's |k*| on axis 1, solid
    f, mag = line.get_data()
    np.testing.assert_allclose(mag, np.abs(_kstar(2j * np.pi * f)), rtol=1e-12)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", VibssWarning)
        section = study(model, figures=True).sections[0]
    assert "zener" in section.text and f"table (fit {table.fit_error:.2g})" in section.text
    assert "mount_stiffness.png" in [name for name, _ in section.figures]
