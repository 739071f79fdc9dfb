"""Issue 33 item 9: modes followed across a sweep by their shapes, with a legend, so colours do not
swap where frequencies cross or veer.

Independent numbers: a body on one mount at its centre of gravity has ``f_x = sqrt(k_x / m) / 2 pi``
whatever the other rates, so as ``k_x`` sweeps past ``k_y`` and ``k_z`` the x mode's track must follow
that closed form while the frequency-sorted order changes; the MAC of a mode with itself is 1.
"""

from __future__ import annotations

import matplotlib
import numpy as np
import pytest

import vibss
from vibss import Body, Model, Mount, MountType
from vibss.errors import ModelError
from vibss.modal.tracking import mac

matplotlib.use("Agg")
M = 10.0


def model(kx: float) -> Model:
    return Model([Body("b", M, [1.0, 1.0, 1.0])], [Mount("m", MountType("t", [kx, 2e4, 3e4]), "b")])


def test_a_crossing_mode_keeps_its_track_and_its_closed_form():
    kx = np.linspace(1e4, 5e4, 9)
    steps = [vibss.modes(model(k)) for k in kx]
    sorted_x = [list(s.labels).index("x") for s in steps]
    assert len(set(sorted_x)) > 1                                   # the sorted order does change
    tr = vibss.track_modes(steps)
    j = tr.labels.index("x")
    assert np.allclose(tr.frequency_hz[:, j], np.sqrt(kx / M) / (2 * np.pi), rtol=1e-9)
    for lab, f in (("y", np.sqrt(2e4 / M)), ("z", np.sqrt(3e4 / M))):
        assert np.allclose(tr.frequency_hz[:, tr.labels.index(lab)], f / (2 * np.pi), rtol=1e-9)
    assert tr.mac[:, 3:].min() > 1 - 1e-9 and tr.weak == []
    fig = tr.plot(kx / 1e3, "k_x [kN/m]")
    legend = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert any(t.startswith("4: x (") for t in legend) and fig.axes[0].get_xlabel() == "k_x [kN/m]"


def test_mac_is_one_for_a_shape_and_zero_for_an_m_orthogonal_one():
    phi = np.eye(3)
    m = np.diag([1.0, 2.0, 3.0])
    assert np.allclose(mac(phi, 2.0 * phi, m), np.eye(3))


def test_steps_that_do_not_match_are_refused():
    two = Model([Body("a", 1.0, [1, 1, 1]), Body("c", 1.0, [1, 1, 1])],
                [Mount("m", MountType("t", [1e4] * 3), "a"), Mount("n", MountType("t", [1e4] * 3), "c")])
    with pytest.raises(ModelError, match="step 1: 12 modes"):
        vibss.track_modes([vibss.modes(model(1e4)), vibss.modes(two)])
