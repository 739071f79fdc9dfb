"""Issue 33 items 3 and 4: names exactly as the user wrote them, and channels that are identically
zero said to be so (no ``nan``, no empty log panel, no library warning).

Independent numbers: a body on four mounts placed symmetrically about its centre of gravity cannot
roll under a vertical force (the mount forces' moments cancel pairwise); the vertical
transmissibility of a 1-DOF isolator is ``|k + i c w| / |k - m w^2 + i c w|``.
"""

from __future__ import annotations

import warnings

import matplotlib
import numpy as np
import pytest

import vibss
from vibss import Body, Model, Mount, MountType

matplotlib.use("Agg")

K, C, MASS = 1e5, 50.0, 10.0


def symmetric() -> Model:
    t = MountType("t", [K, K, 2 * K], damping=[C, C, C])
    corners = [(0.2, 0.2, 0.0), (-0.2, 0.2, 0.0), (0.2, -0.2, 0.0), (-0.2, -0.2, 0.0)]
    return Model([Body("b", MASS, [1.0, 1.0, 1.0])], [Mount(f"m{i}", t, "b", at=p) for i, p in enumerate(corners)])


def test_transmissibility_keeps_the_names_and_units_as_given():
    f = np.array([1.0, 10.0, 30.0])
    t = vibss.transmissibility(symmetric(), ["ground.z.acc"], ["b.z.acc", "b.rx.acc"], frequencies=f)
    assert t.outputs == ("b.z.acc", "b.rx.acc") and t.inputs == ("ground.z.acc",)
    assert t.units == ("m/s^2", "rad/s^2") and t.input_units == ("m/s^2",)
    assert t.channel_unit("b.z.acc") == "-" and t.channel_units == (("-",), ("(rad/s^2)/(m/s^2)",))
    assert list(t.to_pandas().columns) == ["b.z.acc/ground.z.acc", "b.rx.acc/ground.z.acc"]
    w = 2 * np.pi * f
    k, c = 4 * 2 * K, 4 * C
    closed = np.abs(k + 1j * c * w) / np.abs(k - MASS * w**2 + 1j * c * w)
    assert np.allclose(t.magnitude[0, 0], closed, rtol=1e-10)
    plain = vibss.transmissibility(symmetric(), ["ground.z"], ["b.z"], frequencies=f)
    assert plain.outputs == ("b.z",) and plain.inputs == ("ground.z",)
    assert np.allclose(plain.magnitude[0, 0], closed, rtol=1e-10)


def test_a_channel_zero_by_symmetry_says_so_in_tables_and_figures():
    r = vibss.frequency_response(symmetric(), inputs=["b.fz"], outputs=["b.z", "b.rx"],
                                 frequencies=np.linspace(1, 100, 40))
    assert r.zero_channels.tolist() == [[False], [True]]
    text = r.report()
    row = next(line for line in text.splitlines() if line.startswith("b.rx"))
    assert "identically zero" in row and "nan" not in text
    assert any("identically zero" in str(cell) for cell in r.summary().rows[1])
    with warnings.catch_warnings():
        warnings.simplefilter("error")          # no "no positive values" from matplotlib
        fig = r.plot()
        fig.canvas.draw()
    texts = [t.get_text() for ax in fig.axes for t in ax.texts]
    assert any("identically zero" in t for t in texts)
    labels = [t.get_text() for ax in fig.axes if ax.get_legend() for t in ax.get_legend().get_texts()]
    assert "b.rx \u2261 0" in labels and "b.z" in labels


def test_a_small_but_real_channel_is_not_called_zero():
    """An off-centre mount makes the roll small but real: it keeps its peak row."""
    model = symmetric()
    t = model.mounts[0].type
    shifted = [Mount("m0", t, "b", at=(0.2, 0.2001, 0.0)), *model.mounts[1:]]
    r = vibss.frequency_response(Model(model.bodies, shifted), inputs=["b.fz"], outputs=["b.rx"],
                                 frequencies=np.linspace(1, 100, 40))
    assert not r.zero_channels.any()
    assert "identically zero" not in r.report()
