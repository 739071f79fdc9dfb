"""Issue 33 item 5: under ground motion the body motions are relative to the ground, absolute on
request, and a ground input that leaves the ground moving is flagged as a drift, never a headline.

Independent numbers: ``<body>.<dof>.rel`` against the absolute output minus the ground motion the
test computes from the input's closed form; the drift of a half-sine acceleration pulse
``A sin(pi t / T)``: ``v = 2 A T / pi`` after it and ``d(t) = A T^2 / pi + v (t - T)``.
"""

from __future__ import annotations

import numpy as np
import pytest

import vibss
from vibss.model.excitation import Excitation
from vibss.model.timefunctions import HalfSine, Haversine
from vibss.studies import time_outputs
from vibss.time.drift import ground_drifts


def test_relative_motion_is_the_absolute_minus_the_ground_in_time_and_frequency():
    model = vibss.load_example("powertrain")
    bump = Haversine(-0.01, start=0.05, duration=0.1)
    r = vibss.simulate(model, [Excitation("bump", "displacement", "ground", bump, dof="z")],
                       outputs=["powertrain.z", "powertrain.z.rel", "powertrain.x", "powertrain.x.rel",
                                "powertrain.ry.rel", "powertrain.ry"], t_end=0.4, dt=1e-3)
    ground = bump.value(r.time)
    assert np.abs(r["powertrain.z.rel"] - (r["powertrain.z"] - ground)).max() <= 1e-12 * 0.01
    assert np.abs(r["powertrain.x.rel"] - r["powertrain.x"]).max() <= 1e-15      # no x motion of the ground
    assert np.abs(r["powertrain.ry.rel"] - r["powertrain.ry"]).max() <= 1e-15
    f = vibss.frequency_response(model, inputs=["ground.z.disp"], outputs=["powertrain.z", "powertrain.z.rel"],
                                 frequencies=[1.0, 8.0, 30.0])
    assert np.allclose(f.response[1, 0], f.response[0, 0] - 1.0, rtol=0, atol=1e-12)
    assert f.units == ("m", "m")


def test_a_ground_rotation_moves_the_cog_by_its_lever_arm():
    """``ground.rx.disp`` turns ground about the global origin: a COG at height h and lateral y moves
    ``-h rx`` in y and ``y rx`` in z; the relative motion removes exactly that."""
    model = vibss.load_example("powertrain")
    cog = np.asarray(model.bodies[0].cog, float)
    f = vibss.frequency_response(model, inputs=["ground.rx.disp"],
                                 outputs=["powertrain.y", "powertrain.y.rel", "powertrain.z", "powertrain.z.rel"],
                                 frequencies=[5.0])
    h = f.response[:, 0, 0]
    assert h[1] == pytest.approx(h[0] + cog[2], abs=1e-12)
    assert h[3] == pytest.approx(h[2] - cog[1], abs=1e-12)


def test_time_outputs_lead_with_relative_motion_under_ground_motion_and_absolute_on_request():
    model = vibss.load_example("ground_shake")
    rel = time_outputs(model)
    assert rel.relative and "cabinet.x.rel" in rel.outputs and "cabinet.x" not in rel.outputs
    ab = time_outputs(model, absolute=True)
    assert not ab.relative and "cabinet.x" in ab.outputs
    forced = time_outputs(model, [Excitation("push", "force", "cabinet", HalfSine(10.0, duration=0.01), dof="x")])
    assert not forced.relative and not forced.base


def test_a_half_sine_acceleration_is_flagged_as_a_drift_and_a_bump_is_not():
    a, dur, t_end = 29.43, 0.015, 1.0
    pulse = Excitation("pothole", "acceleration", "ground", HalfSine(a, start=0.0, duration=dur), dof="z")
    (d,) = ground_drifts([pulse], t_end)
    v = 2 * a * dur / np.pi
    assert d.velocity == pytest.approx(v, rel=1e-4)                 # the trapezoidal rule on 20,001 points
    assert d.displacement == pytest.approx(a * dur**2 / np.pi + v * (t_end - dur), rel=1e-4)
    assert "0.281 m/s" in d.text()
    bump = Excitation("bump", "displacement", "ground", Haversine(-0.01, duration=0.1), dof="z")
    assert ground_drifts([bump], t_end) == []
    zero_net = Excitation("pair", "acceleration", "ground",
                          HalfSine(a, duration=dur) + HalfSine(-a, start=dur, duration=dur), dof="z")
    assert ground_drifts([zero_net], t_end) == []
