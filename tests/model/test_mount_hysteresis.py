"""Mount data that cannot mean anything is refused; a loss factor is never dropped silently."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import vibss
from vibss import Body, Model, Mount, MountType
from vibss.errors import ModelError, VibssWarning


@pytest.mark.parametrize("kwargs", [
    {"stiffness": lambda w: 1e4},                           # was a RecursionError
    {"stiffness": [1e4] * 3, "damping": print},
    {"stiffness": [1e4] * 3, "loss_factor": lambda w: 0.1},
    {"stiffness": {"k": 1e4}},
    {"stiffness": object()},
    {"stiffness": [1e4, "a", 1e4]},
])
def test_nonsense_mount_data_is_a_model_error_naming_the_type(kwargs):
    with pytest.raises(ModelError, match="mount type 'rubber'"):
        MountType("rubber", **kwargs)


def _model(eta: float) -> Model:
    hyst = MountType("hyst", [1e4, 1e4, 2e4], loss_factor=eta)
    plain = MountType("plain", [1e4, 1e4, 1e4], damping=[5.0, 5.0, 5.0])
    return Model([Body("b", 2.0, [0.1, 0.1, 0.1])],
                 [Mount("soft", hyst, "b", at=[0.2, 0, 0]), Mount("other", plain, "b", at=[-0.2, 0, 0])])


def _record(fn):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        out = fn()
    return out, [str(w.message) for w in caught if issubclass(w.category, VibssWarning)]


def _run(model: Model):
    return vibss.simulate(model, inputs={"b.fz": lambda t: np.ones_like(t)}, outputs=["b.z", "b.ry"],
                          t_end=0.2, dt=1e-3)


def test_time_response_names_the_mount_whose_loss_factor_it_leaves_out():
    r, msgs = _record(lambda: _run(_model(0.2)))
    assert len(msgs) == 1 and msgs[0].startswith("simulate:") and "['soft']" in msgs[0]
    assert "['soft']" in r.note and "left out" in r.note
    # what is said is what is done: the response is that of the model without the loss factor
    ref, none = _record(lambda: _run(_model(0.0)))
    assert none == [] and "left out" not in ref.note
    np.testing.assert_array_equal(r.outputs, ref.outputs)


def test_damped_modes_and_statespace_name_the_mount():
    d, msgs = _record(lambda: vibss.damped_modes(_model(0.2)))
    assert len(msgs) == 1 and msgs[0].startswith("damped_modes:") and "['soft']" in msgs[0]
    assert "['soft']" in d.note
    d0, none = _record(lambda: vibss.damped_modes(_model(0.0)))
    assert none == [] and d0.note == ""
    np.testing.assert_allclose(d.poles, d0.poles, rtol=1e-12, atol=1e-9)
    _, msgs = _record(lambda: vibss.statespace(_model(0.2), inputs=["b.fz"], outputs=["b.z"]))
    assert len(msgs) == 1 and msgs[0].startswith("statespace:") and "['soft']" in msgs[0]
    plant = vibss.build_plant(_model(0.2), ["b.fz"], ["b.z"])
    _, msgs = _record(lambda: vibss.statespace(plant))
    assert len(msgs) == 1 and "hysteretic stiffness" in msgs[0]


def test_frequency_response_keeps_the_loss_factor():
    """The FRF uses k (1 + i eta): the single-DOF closed form, and no warning."""
    t = MountType("t", [1e4, 1e4, 1e4], loss_factor=0.1)
    m = Model([Body("b", 1.0, [1, 1, 1])], [Mount("m", t, "b")])
    w = np.array([50.0, 100.0, 150.0])
    r, msgs = _record(lambda: vibss.frequency_response(m, ["b.fz"], ["b.z"], frequencies=w / (2 * np.pi),
                                                       method="direct"))
    assert msgs == []
    np.testing.assert_allclose(r.response[0, 0], 1.0 / (1e4 * (1 + 0.1j) - w**2), rtol=1e-12)
