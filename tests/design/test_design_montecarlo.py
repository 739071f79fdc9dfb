"""vibss.design.monte_carlo: the batched eigen-solve equals a loop of vibss.modes on rebuilt models
(1e-10), sampling and probabilities."""

from __future__ import annotations

import numpy as np
import pytest

import vibss
from vibss.design import Parameter, monte_carlo
from vibss.design.montecarlo import batch_modes
from vibss.design.parameters import apply, current_values, parameters_of
from vibss.errors import ArgumentError


TOL = {"engine.k1": 0.2, "engine.k3": 0.15, "engine.xz.k2": 0.15, "gearbox.k3": 0.2,
       "torque-strut.k1": 0.15, "engine.x": 0.01, "gearbox.z": 0.02, "engine.rx": 0.1,
       "engine.ry": 0.05, "torque-strut.rz": 0.1,
       Parameter("pair height", [("engine", "z", 1.0), ("engine.xz", "z", 1.0)]): 0.01}


def test_batched_equals_a_loop_of_vibss_modes_on_100_variants(powertrain):
    mc = monte_carlo(powertrain, TOL, n=100, sampling="random", seed=3)
    params = parameters_of(powertrain, list(TOL))
    f, phi, ke = batch_modes(powertrain, params, mc.samples)
    for v in range(100):
        md = vibss.modes(apply(powertrain, params, mc.samples[v]))
        np.testing.assert_allclose(mc.frequency_hz[v], md.frequency_hz, rtol=1e-10)
        np.testing.assert_allclose(ke[v], md.energy, atol=1e-10)
        np.testing.assert_allclose(phi[v], md.shapes, atol=1e-10 * np.abs(md.shapes).max())
        np.testing.assert_allclose(mc.purity[v], md.energy.max(axis=1), atol=1e-10)


def test_multi_body_batch_matches_modes():
    model = vibss.load_example("two_mass")
    params = parameters_of(model, [f"{m.name}.k3" for m in model.mounts] + [f"{model.mounts[0].name}.x"])
    v0 = current_values(model, params)
    rng = np.random.default_rng(1)
    vals = v0 * (1 + 0.2 * rng.uniform(-1, 1, (20, len(v0))))
    vals[:, -1] = rng.uniform(-0.05, 0.05, 20)
    f, _, ke = batch_modes(model, params, vals)
    for v in range(20):
        md = vibss.modes(apply(model, params, vals[v]))
        np.testing.assert_allclose(f[v], md.frequency_hz, rtol=1e-10)


@pytest.mark.parametrize("sampling", ["random", "lhs", "sobol"])
def test_samples_stay_within_tolerance_and_probabilities_count(powertrain, sampling):
    mc = monte_carlo(powertrain, {"engine.k3": 0.15, "engine.z": 0.01}, n=256, sampling=sampling,
                     purity=0.5, windows=(5.0, 13.0))
    k0 = powertrain.mounts[0].type.stiffness[2]
    assert np.all(np.abs(mc.samples[:, 0] / k0 - 1) <= 0.15) and np.all(np.abs(mc.samples[:, 1]) <= 0.01)
    ok = (mc.purity >= 0.5).all(axis=1) & ((mc.frequency_hz >= 5) & (mc.frequency_hz <= 13)).all(axis=1)
    assert mc.probability["all"] == pytest.approx(ok.mean())
    if sampling == "lhs":           # one sample in each of the n strata of every parameter
        strata = np.floor((mc.samples[:, 1] / 0.01 + 1) / 2 * 256).astype(int)
        assert sorted(strata) == list(range(256))


def test_protocol_and_ranking(powertrain):
    mc = monte_carlo(powertrain, {"engine.k3": 0.15, "gearbox.k3": 0.15, "torque-strut.k2": 0.15},
                     n=2000, distribution="normal", purity=0.5)
    r = mc.ranking("frequency")
    assert r.shape == (3, 6) and np.all(np.abs(r) <= 1 + 1e-12)
    assert np.abs(r[2]).max() < np.abs(r[:2]).max()         # the strut's soft side rate barely matters
    assert mc["f1"].shape == (2000,)
    assert len(mc.to_pandas()) == 2000 and mc.to_json()
    assert "Tolerance study" in mc.report()
    assert len(mc.plot().axes) == 2
    fig = mc.plot(kind="tornado", mode=3)
    assert fig.axes[0].get_xlabel() == "correlation with the purity of mode 3 [-]"
    with pytest.raises(ArgumentError, match="sampling"):
        monte_carlo(powertrain, {"engine.k3": 0.1}, n=10, sampling="halton")
