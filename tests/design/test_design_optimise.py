"""vibss.design.optimize: a layout built to have a known optimum (mounts symmetric about the TRA
decouple roll completely), constraints honoured, the optimum written as a model file."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import vibss
from vibss.design import Parameter, certificate, optimize, torque_roll_axis
from vibss.errors import ArgumentError

Q = Rotation.from_euler("ZYX", [0.5, -0.3, 0.2]).as_matrix()
Z0 = 0.12


def tilted_layout():
    """Body with a full inertia tensor; crank axis Q ex (the TRA: Q diag Q^T maps it onto itself);
    four mounts at Q (+-a, +-b, Z0) with local axes Q: symmetric about the TRA when Z0 -> 0."""
    body = vibss.Body("b", 150.0, Q @ np.diag([5.0, 12.0, 14.0]) @ Q.T, cog=[0.1, 0.2, 0.5])
    t = vibss.MountType("t", [1.2e5, 2.5e5, 3.0e5])
    mounts = [vibss.Mount(f"m{i}", t, "b", at=Q @ [sx * 0.35, sy * 0.25, Z0], orientation=Q)
              for i, (sx, sy) in enumerate([(1, 1), (1, -1), (-1, 1), (-1, -1)])]
    height = Parameter("height", [(m.name, kind, Q[j, 2]) for m in mounts
                                  for j, kind in enumerate("xyz")])
    return vibss.Model([body], mounts), height


def test_symmetric_about_the_tra_gives_full_roll_decoupling():
    model, height = tilted_layout()
    np.testing.assert_allclose(torque_roll_axis(model, "b", Q[:, 0]), Q[:, 0], atol=1e-12)
    before = certificate(model, frame="tra", axis=Q[:, 0])
    roll = before.dominant.index("b.rx'")
    assert before.purity[roll] < 0.95
    opt = optimize(model, {height: (-0.2, 0.2)}, modes=["rx"], frame="tra", axis=Q[:, 0])
    assert opt.success
    assert opt.x[0] == pytest.approx(-Z0, abs=1e-5)
    assert opt.after.purity[opt.after.dominant.index("b.rx'")] == pytest.approx(1.0, abs=1e-8)


@pytest.mark.parametrize("method", ["SLSQP", "trust-constr"])
def test_exact_and_finite_difference_gradients_reach_the_same_optimum(method):
    model, height = tilted_layout()
    kw = dict(modes=["rx"], frame="tra", axis=Q[:, 0], method=method)
    exact = optimize(model, {height: (-0.2, 0.2)}, gradient="exact", **kw)
    fd = optimize(model, {height: (-0.2, 0.2)}, gradient="finite-difference", **kw)
    assert exact.x[0] == pytest.approx(-Z0, abs=1e-4)
    assert fd.x[0] == pytest.approx(exact.x[0], abs=1e-4)


def test_windows_and_purity_constraints_hold_and_the_model_file_round_trips(tmp_path):
    pt = vibss.load_example("powertrain")
    win = (5.5, 18.0)
    opt = optimize(pt, {"torque-strut.k1": (5e4, 2e5), "gearbox.k3": (7.5e4, 3e5), "engine.xz.k3": (1.2e5, 4e5),
                        "engine.k3": (1.2e5, 4e5), "gearbox.z": (-0.03, 0.03)},
                   windows=win, frame="tra", starts=3)
    f = opt.after.frequency_hz
    assert np.all(f >= win[0] * (1 - 1e-6)) and np.all(f <= win[1] * (1 + 1e-6))
    assert opt.after.purity.mean() > opt.before.purity.mean()
    assert opt.starts == 3 and "Before and after" in opt.report()
    path = tmp_path / "optimised.toml"
    opt.write(path)
    np.testing.assert_allclose(vibss.modes(vibss.load_model(path)).frequency_hz, f, rtol=1e-12)
    assert list(opt.to_pandas().index) == list(opt.variables)
    assert opt["gearbox.z"] == opt.x[-1] and opt.to_json()
    assert "purity" in opt.plot().axes[0].get_ylabel()


def test_bad_bounds_are_refused():
    pt = vibss.load_example("powertrain")
    with pytest.raises(ArgumentError, match="bounds"):
        optimize(pt, {"engine.k3": (0.0, 1e5)})
    with pytest.raises(ArgumentError, match="method"):
        optimize(pt, {"engine.k3": (1e5, 2e5)}, method="nelder")


def test_global_option_finds_the_known_optimum_from_the_far_corner():
    model, height = tilted_layout()
    opt = optimize(model, {height: (-0.2, 0.2)}, modes=["rx"], frame="tra", axis=Q[:, 0], method="global",
                   maxiter=20)
    assert opt.method.startswith("differential evolution")
    assert opt.x[0] == pytest.approx(-Z0, abs=1e-5)


def test_catalogue_rates_are_catalogue_values_and_the_rest_is_reoptimised():
    from vibss.design.parameters import apply, parameters_of

    pt = vibss.load_example("powertrain")
    var = {"torque-strut.k1": (5e4, 2e5), "gearbox.k3": (7.5e4, 3e5), "gearbox.z": (-0.03, 0.03)}
    cat = {"torque-strut.k1": [6e4, 8e4, 1e5, 1.25e5, 1.5e5], "gearbox.k3": [1e5, 1.5e5, 2e5, 2.5e5, 3e5]}
    free = optimize(pt, var, frame="tra", windows=(5.5, 18.0))
    opt = optimize(pt, var, frame="tra", windows=(5.5, 18.0), catalogue=cat)
    assert opt.x[0] in cat["torque-strut.k1"] and opt.x[1] in cat["gearbox.k3"]
    assert opt.objective <= free.objective + 1e-9 and opt.success
    # the same as fixing those rates by hand and optimising the free variable alone
    fixed = apply(pt, parameters_of(pt, ["torque-strut.k1", "gearbox.k3"]), opt.x[:2])
    alone = optimize(fixed, {"gearbox.z": (-0.03, 0.03)}, frame="tra", windows=(5.5, 18.0))
    assert alone.objective == pytest.approx(opt.objective, abs=1e-6)
    with pytest.raises(ArgumentError, match="not a design variable"):
        optimize(pt, var, catalogue={"engine.k3": [1e5]})
