"""vibss.design.sensitivity: every exact derivative against central differences of vibss.modes /
vibss.static on rebuilt models (1e-6 relative), tied parameters, angles at non-zero values,
refusal of repeated frequencies."""

from __future__ import annotations

import numpy as np
import pytest

import vibss
from vibss.design import Parameter, sensitivity
from vibss.design.parameters import apply, current_values, parameters_of
from vibss.design.sensitivity import evaluate
from vibss.errors import AnalysisError, ArgumentError

PARAMS = ["engine.k1", "engine.k3", "gearbox.k2", "torque-strut.k1", "engine.x", "engine.xz.z",
          "gearbox.y", "engine.rx", "gearbox.ry", "torque-strut.rz",
          Parameter("engine pair height", [("engine", "z", 1.0), ("engine.xz", "z", 1.0)]),
          Parameter("engine pair spread", [("engine", "y", 1.0), ("engine.xz", "y", -1.0)])]


def _quantities(model, frame):
    md = vibss.modes(model)
    a = vibss.assemble(model)
    M = np.asarray(a.M)
    R = np.kron(np.eye(2), frame)
    pr, mp = R.T @ md.shapes, R.T @ M @ md.shapes
    ke = (pr * mp).T / np.sum(pr * mp, axis=0)[:, None]
    weight = np.zeros(6)
    weight[:3] = model.bodies[0].masses * model.gravity
    sag = vibss.static(a, loads=weight).q
    return md.frequency_hz, md.shapes, ke, sag


def _check(an, fd, what):
    scale = np.abs(an).max()
    err = np.abs(an - fd).max()
    assert err <= 1e-6 * scale, f"{what}: max error {err:.3g} vs scale {scale:.3g}"


@pytest.mark.parametrize("frame", ["global", "tra"])
def test_all_derivatives_match_central_differences(powertrain, frame):
    params = parameters_of(powertrain, PARAMS)
    v0 = current_values(powertrain, params)
    sens = evaluate(powertrain, params, v0, frame=frame)
    for j, p in enumerate(params):
        h = 1e-5 * v0[j] if p.is_rate else 1e-6
        up, down = (_quantities(apply(powertrain, params, v0 + s * h * np.eye(len(v0))[j]), sens.frame)
                    for s in (1, -1))
        fd = [(u - d) / (2 * h) for u, d in zip(up, down)]
        _check(sens.d_frequency[:, j], fd[0], f"{p.name}: frequency")
        _check(sens.d_shapes[:, :, j], fd[1], f"{p.name}: shapes")
        _check(sens.d_ke[:, :, j], fd[2], f"{p.name}: KE fractions")
        _check(sens.d_sag[:, j], fd[3], f"{p.name}: sag")
        dom = np.argmax(sens.ke_matrix, axis=1)
        _check(sens.d_purity[:, j], fd[2][np.arange(6), dom], f"{p.name}: purity")


def test_angles_composed_at_non_zero_values(powertrain):
    params = parameters_of(powertrain, ["engine.rx", "engine.ry", "engine.rz", "gearbox.k3"])
    v = np.array([0.2, -0.3, 0.25, current_values(powertrain, parameters_of(powertrain, ["gearbox.k3"]))[0] * 1.3])
    sens = evaluate(powertrain, params, v, shapes=False)
    for j in range(3):
        h = 1e-6
        fu = vibss.modes(apply(powertrain, params, v + h * np.eye(4)[j])).frequency_hz
        fl = vibss.modes(apply(powertrain, params, v - h * np.eye(4)[j])).frequency_hz
        _check(sens.d_frequency[:, j], (fu - fl) / (2 * h), f"angle {j}")


def test_apply_gives_shared_types_their_own_name_only_when_needed(powertrain):
    both = Parameter("engine rate", [("engine", "k3", 1.0), ("engine.xz", "k3", 1.0)])
    m = apply(powertrain, [both], [3e5])
    assert {x.type.name for x in m.mounts[:2]} == {"engine-mount"}
    one = apply(powertrain, parameters_of(powertrain, ["engine.k3"]), [3e5])
    assert [x.type.name for x in one.mounts[:2]] == ["engine-mount.engine", "engine-mount"]
    assert one.mounts[0].type.stiffness[2] == 3e5


def test_protocol_and_lookups(powertrain):
    s = sensitivity(powertrain, ["engine.k3", "engine.z"])
    assert s["f2", "engine.z"] == s.d_frequency[1, 1]
    assert list(s.to_pandas().index) == ["engine.k3", "engine.z"]
    assert "Exact sensitivities" in s.report()
    assert s.plot().axes[0].get_xlabel().startswith("change of frequency")
    assert s.to_json()


def test_repeated_frequencies_are_refused():
    t = vibss.MountType("t", [1e5, 1e5, 1e5])
    m = vibss.Model([vibss.Body("b", 10.0, [1.0, 1.0, 1.0])],
                    vibss.symmetric(vibss.Mount("m", t, "b", at=[0.2, 0.2, 0.0])))
    with pytest.raises(AnalysisError, match="repeated"):
        sensitivity(m, ["m.k3"])


def test_bad_parameters(powertrain):
    with pytest.raises(ArgumentError, match="did you mean"):
        sensitivity(powertrain, ["engin.k3"])
    with pytest.raises(ArgumentError, match="kind"):
        sensitivity(powertrain, ["engine.k4"])
    with pytest.raises(ArgumentError, match="mix units"):
        Parameter("p", [("engine", "k3", 1.0), ("engine", "z", 1.0)])


def test_body_to_body_mounts_against_central_differences():
    """two_mass: the upper mounts join two bodies (lever arms on both ends); symmetry broken first."""
    m = vibss.load_example("two_mass")
    m = apply(m, parameters_of(m, ["upper.z", "lower.x", "upper.x", "lower.k1"]), [0.013, 0.02, -0.017, 18000.0])
    params = parameters_of(m, ["upper.k1", "upper.yz.k3", "upper.z", "lower.x", "upper.x"])
    v0 = current_values(m, params)
    sens = evaluate(m, params, v0)
    for j, p in enumerate(params):
        h = 1e-5 * v0[j] if p.is_rate else 1e-5
        up, down = (vibss.modes(apply(m, params, v0 + s * h * np.eye(len(v0))[j])) for s in (1, -1))
        _check(sens.d_frequency[:, j], (up.frequency_hz - down.frequency_hz) / (2 * h), f"{p.name}: frequency")
        _check(sens.d_shapes[:, :, j], (up.shapes - down.shapes) / (2 * h), f"{p.name}: shapes")
        _check(sens.d_ke[:, :, j], (up.energy - down.energy) / (2 * h), f"{p.name}: KE")
