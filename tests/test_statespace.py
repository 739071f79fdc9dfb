"""State-space realizations: python-control's frequency response equals the second-order solve."""

from __future__ import annotations

import sys
from pathlib import Path

import control
import numpy as np
import pytest

from vibss import AnalysisError, Body, Model
from vibss.frequency.kernels import direct
from vibss.linear.plant.build import build_plant
from vibss.linear.statespace import statespace

sys.path.insert(0, str(Path(__file__).resolve().parent))
from test_signals import two_body  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from benchmarks.models import chain_model  # noqa: E402


def _rel(h, ref):
    return float(np.max(np.linalg.norm(h - ref, axis=(0, 1)) / np.linalg.norm(ref, axis=(0, 1))))


@pytest.mark.parametrize("realization", ["modal", "physical"])
@pytest.mark.parametrize("inputs, outputs", [
    (["engine.fz", "frame.my", "sensor.fx"], ["engine.z", "sensor.x.acc", "mount.e1.f1", "ground.fz", "frame.rx.vel"]),
    (["ground.z.acc", "frame.x.vel", "engine.rz.acc"], ["engine.z.acc", "mount.g2.f3", "ground.mx", "sensor.y.vel"]),
    (["ground.y.disp", "frame.rx.disp", "engine.fz"], ["engine.z", "sensor.y", "mount.g1.d1"]),
])
def test_frequency_response_matches_second_order(realization, inputs, outputs):
    p = build_plant(two_body(), inputs, outputs)
    sys_ = statespace(p, realization=realization)
    w = np.geomspace(0.5, 500, 200)
    h = control.frequency_response(sys_, w).complex
    assert _rel(h, direct(p, 1j * w)) < 1e-10
    assert sys_.input_labels == [u.replace(".", ":") for u in inputs]


def test_100_dof_lightly_damped():
    model = chain_model(17, damping="general", zeta=1e-3)     # 102 DOF
    p = build_plant(model, ["b0.fz", "b8.mx", "ground.x.acc"], ["b0.z", "b8.rx", "b16.y", "b4.x.acc"])
    sys_ = statespace(p)
    w2 = np.linalg.eigvals(np.linalg.solve(p.M, p.K)).real
    w = np.union1d(np.geomspace(0.5, 2, 300) * np.sqrt(w2.min()), np.sqrt(np.sort(w2)))   # on resonances too
    h = control.frequency_response(sys_, w).complex
    assert _rel(h, direct(p, 1j * w)) < 1e-8


def test_free_body_rigid_modes():
    p = build_plant(Model([Body("f", 2.0, [[1, 0.1, 0], [0.1, 2, 0], [0, 0, 3]])]), ["f.fz", "f.mx"],
                    ["f.z", "f.rx", "f.z.acc"])
    sys_ = statespace(p)
    assert np.all(np.isfinite(sys_.A)) and np.allclose(sys_.poles(), 0)
    w = np.geomspace(0.1, 10, 20)
    assert _rel(control.frequency_response(sys_, w).complex, direct(p, 1j * w)) < 1e-12


def test_displacement_input_is_the_only_input_and_improper_outputs_raise():
    p = build_plant(two_body(), ["ground.z.disp"], ["engine.z"])
    sys_ = statespace(p)
    assert sys_.ninputs == 1 and sys_.nstates == 24
    with pytest.raises(AnalysisError, match="velocity or acceleration"):
        statespace(build_plant(two_body(), ["ground.z.disp"], ["frame.z.acc"]))
    statespace(build_plant(two_body(), ["ground.z.disp"], ["engine.z.acc"]))   # no damper between: proper
    with pytest.raises(ValueError, match="realization"):
        statespace(p, realization="balanced")


def test_state_names():
    p = build_plant(two_body(), ["ground.z.acc"], ["engine.z"])
    modal = statespace(p)
    assert modal.state_labels[0] == "mode1:pos" and modal.state_labels[-2:] == ["ground:z:acc:z", "ground:z:acc:zdot"]
    phys = statespace(p, realization="physical")
    assert phys.state_labels[:2] == ["frame:x", "frame:y"] and phys.state_labels[12] == "frame:x:vel"


def test_vibss_names_index_the_system():
    """sys['engine.z', 'ground.z.acc'] (the issue's spelling) picks the same channel as the stored
    'engine:z', 'ground:z:acc', and that channel's response is the second-order one."""
    inputs, outputs = ["engine.fz", "ground.z.acc"], ["engine.z", "sensor.x.acc", "ground.fz"]
    p = build_plant(two_body(), inputs, outputs)
    sys_ = statespace(p)
    sub = sys_["engine.z", "ground.z.acc"]
    same = sys_["engine:z", "ground:z:acc"]
    assert type(sub).__name__ == "NamedStateSpace"
    assert sub.input_labels == ["ground:z:acc"] and sub.output_labels == ["engine:z"]
    assert np.array_equal(sub.B, same.B) and np.array_equal(sub.C, same.C)
    w = np.geomspace(0.5, 500, 50)
    ref = direct(p, 1j * w)[0:1, 1:2]
    assert _rel(control.frequency_response(sub, w).complex.reshape(1, 1, -1), ref) < 1e-10
    both = sys_[["engine.z", "ground.fz"], ["engine.fz"]]
    assert both.output_labels == ["engine:z", "ground:fz"]
    assert sub["engine.z", "ground.z.acc"].nstates == sys_.nstates        # sub-systems index too
    assert sys_.find_input("ground.z.acc") == 1 and sys_.find_output("ground.fz") == 2
    assert sys_.find_outputs(["sensor.x.acc", "engine.z"]) == [1, 0]
    assert sys_.find_input("nope.z") is None
    # python-control's own operations still work on it (and name signals with ':')
    loop = control.feedback(sys_, control.ss([], [], [], np.zeros((2, 3))), sign=-1)
    assert np.allclose(np.sort_complex(loop.poles()), np.sort_complex(sys_.poles()))


def test_named_statespace_keys_errors_sample_pickle():
    """Found in review: mixed keys, 2-lists, bad names and indices, sub-system states, sample, pickle."""
    import copy
    import pickle

    p = build_plant(two_body(), ["engine.fz", "ground.z.acc"], ["engine.z", "ground.into.fz", "frame.x"])
    sys_ = statespace(p, realization="physical")
    both = sys_[["engine.z", 2], "engine.fz"]                      # a name and an index
    assert both.output_labels == ["engine:z", "frame:x"]
    assert sys_[["engine.z", "engine.fz"]].input_labels == ["engine:fz"]   # a 2-list is (outputs, inputs)
    assert sys_[-1, -1].output_labels == ["frame:x"] and sys_[-1, -1].input_labels == ["ground:z:acc"]
    with pytest.raises(IndexError, match="index 3 out of range for 3 outputs"):
        sys_[3, 0]
    with pytest.raises(ValueError, match=r"no output named 'engine.zz' \(did you mean 'engine.z'\?\)"):
        sys_["engine.zz", "engine.fz"]
    with pytest.raises(ValueError, match=r"'engine.fz' is an input, not an output"):
        sys_["engine.fz", "engine.fz"]
    with pytest.raises(ValueError, match="names a signal twice"):
        sys_[["engine.z", "engine:z"], 0]
    sub = sys_["frame.x", "engine.fz"]
    assert sub.state_labels == sys_.state_labels and np.array_equal(sub.vibss_state_scale, sys_.vibss_state_scale)
    assert sys_.find_state("frame.z") == sys_.find_state("frame:z") is not None
    assert sys_.find_input(3) is None
    d = sys_.sample(1e-3)
    assert type(d).__name__ == "NamedStateSpace" and d.dt == 1e-3
    assert d["engine.z", "engine.fz"].noutputs == 1
    for clone in (pickle.loads(pickle.dumps(sys_)), copy.deepcopy(sys_)):
        assert type(clone).__name__ == "NamedStateSpace" and clone.output_labels == sys_.output_labels
        assert np.array_equal(clone.A, sys_.A) and np.array_equal(clone.vibss_state_scale, sys_.vibss_state_scale)
