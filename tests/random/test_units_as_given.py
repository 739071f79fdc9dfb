"""Issue 33 item 2 for random vibration: a spec given in g^2/Hz is shown in g^2/Hz (figures said
"SI unit^2/Hz"), accelerations in g on request, zeros outside the band not drawn as 1e-300.

Independent numbers: the spec's own breakpoints (the PSD is log-log linear between them, so at a
breakpoint the level is the number given), and 1 g = 9.80665 m/s^2.
"""

from __future__ import annotations

import matplotlib
import numpy as np
import pytest

import vibss

matplotlib.use("Agg")
G = 9.80665
F = np.array([20.0, 80.0, 350.0, 2000.0])
LEVEL = np.array([0.01, 0.04, 0.04, 0.007])


def result() -> vibss.RandomResponse:
    t = vibss.MountType("iso", [1e5, 1e5, 1e5], damping=[40.0] * 3)
    m = vibss.Model([vibss.Body("box", 20.0, [1, 1, 1])], [vibss.Mount("m", t, "box")])
    return vibss.random_response(m, {"ground.z.acc": (F, LEVEL)}, ["box.z.acc", "mount.m.dz"])


def test_the_input_spec_keeps_its_unit_in_the_result_and_the_figure():
    r = result()
    levels, units = r.input_levels()
    assert units == ("g^2/Hz",)
    at = [int(np.argmin(np.abs(r.frequency_hz - f))) for f in F]
    assert np.allclose(r.frequency_hz[at], F) and np.allclose(levels[0, at], LEVEL, rtol=1e-12)
    assert np.allclose(r.input_psd[0, at], LEVEL * G**2, rtol=1e-12)        # SI underneath
    fig = r.plot()
    labels = [a.get_ylabel() for a in fig.axes]
    assert "input PSD [g^2/Hz]" in labels and not any("SI unit" in x for x in labels)
    lows = [np.nanmin(line.get_ydata()) for a in fig.axes for line in a.get_lines()]
    assert min(lows) > 1e-30                                               # no 1e-300 spike at the band edge


def test_a_flat_spec_is_drawn_flat_over_two_decades():
    """0.04 g^2/Hz flat: its log-log interpolation carries round-off (1e-17 of the level) that the
    autoscale once zoomed onto, drawing spikes under a single tick. The panel spans two decades
    about the level, and so does a flat output."""
    t = vibss.MountType("iso", [1e5, 1e5, 1e5], damping=[40.0] * 3)
    m = vibss.Model([vibss.Body("box", 20.0, [1, 1, 1])], [vibss.Mount("m", t, "box")])
    r = vibss.random_response(m, {"ground.z.acc": ([1e-3, 1e6], [0.04, 0.04])}, ["box.z.acc"])
    panel = r.plot().axes[-1]
    lo, hi = panel.get_ylim()
    assert hi / lo == pytest.approx(100.0, rel=1e-9) and lo < 0.04 < hi
    assert np.ptp(panel.get_lines()[0].get_ydata()) < 1e-12 * 0.04                    # the round-off itself


def test_accelerations_in_g_on_request():
    r = result()
    g = r.in_g()
    assert g.units == ("g", "m") and g.rms[0] == pytest.approx(r.rms[0] / G, rel=1e-14)
    assert np.allclose(g.psd[0], r.psd[0] / G**2, rtol=1e-14) and np.array_equal(g.psd[1], r.psd[1])
    assert g.psd_units()[0] == "g^2/Hz"
