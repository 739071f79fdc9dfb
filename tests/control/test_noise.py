"""Noise budgets: a 1-DOF velocity-feedback loop against its closed form, the sum of the independent
contributions against the total PSD of the loop built with the plant's own noise inputs, PSD specs."""

from __future__ import annotations

import numpy as np
import pytest

import cases.models as cases
import vibss.control as vc
from vibss.errors import ArgumentError, ModelError
from vibss.frequency.statespace_response import evaluate
from vibss.io.modelfile import dumps_model
from vibss.model.actuation import Actuator, Sensor

M_, K_, C_, G_ = 10.0, 1e4, 20.0, 300.0
SN = 1e-12                                          # (m/s)^2/Hz


def loop(noise=SN):
    m = cases.sdof(M_, K_, C_, type_name="iso", actuators=[Actuator("a", mount="m", axis=3)],
                   sensors=[Sensor("v", "velocity", body="b", direction=[0, 0, 1], noise=noise)])
    P = vc.plant(m, ["ground.z.disp"], performance=["b.z"], dofs=["b.z"])
    return m, vc.close(P, vc.skyhook(P, G_))


def test_sensor_noise_against_the_closed_form() -> None:
    # m x'' + c x' + k x = u, u = -g (x' + n): X / N = -g / (m s^2 + (c + g) s + k), and the ground's
    # X / Y = (c s + k) / (m s^2 + (c + g) s + k)
    _, cl = loop()
    f = np.geomspace(0.5, 200.0, 800)
    s = 2j * np.pi * f
    sg = 1e-10 / (1 + (f / 2) ** 4)
    b = cl.noise_budget(["b.z"], f, ground=lambda x: 1e-10 / (1 + (x / 2) ** 4))
    den = M_ * s ** 2 + (C_ + G_) * s + K_
    np.testing.assert_allclose(b.psd[0, 0], np.abs(G_ / den) ** 2 * SN, rtol=1e-10)
    np.testing.assert_allclose(b.psd[0, 1], np.abs((C_ * s + K_) / den) ** 2 * sg, rtol=1e-10)
    assert b.sources == ("sensor.v.noise", "ground.z.disp") and b.units == ("m",)
    # RMS: trapezoids of the PSD, cumulative from the top
    assert b.rms[0, 0] == pytest.approx(np.sqrt(np.trapezoid(b.psd[0, 0], f)), rel=1e-12)
    assert b.cumulative_rms[0, 0] == pytest.approx(b.rms_total[0], rel=1e-12) and b.cumulative_rms[0, -1] == 0.0


def test_contributions_sum_to_the_total_of_the_loop_with_the_plants_noise_inputs() -> None:
    # an independent construction: plant(noise=...) gives the measurement a noise input of its own
    m, cl = loop()
    P2 = vc.plant(m, ["ground.z.disp"], performance=["b.z"], dofs=["b.z"], noise={"sensor.v": 1.0})
    cl2 = vc.close(P2, vc.skyhook(P2, G_))
    f = np.geomspace(1.0, 100.0, 50)
    sg = 3e-11
    b = cl.noise_budget(["b.z"], f, ground=sg)
    o = cl2.system.output_labels.index("b:z")
    h = evaluate(cl2.system, 2 * np.pi * f, outputs=[o])[0]          # (inputs, nf)
    i_g = cl2.system.input_labels.index("ground:z:disp")
    i_n = cl2.system.input_labels.index("sensor:v:noise")
    total = np.abs(h[i_g]) ** 2 * sg + np.abs(h[i_n]) ** 2 * SN
    np.testing.assert_allclose(b.total[0], total, rtol=1e-10)


def test_psd_specs_and_refusals() -> None:
    s = Sensor("v", "velocity", body="b", direction=[0, 0, 1], noise=([1.0, 100.0], [1e-10, 1e-12]))
    np.testing.assert_allclose(s.noise_psd([1.0, 10.0, 100.0, 1000.0]), [1e-10, 1e-11, 1e-12, 1e-12], rtol=1e-12)
    assert Sensor("w", "velocity", body="b", direction=[0, 0, 1]).noise_psd([1.0]).tolist() == [0.0]
    with pytest.raises(ModelError, match="noise"):
        Sensor("v", "velocity", body="b", direction=[0, 0, 1], noise=-1.0)
    with pytest.raises(ModelError, match="noise"):
        Sensor("v", "velocity", body="b", direction=[0, 0, 1], noise=([10.0, 1.0], [1.0, 1.0]))
    m, cl = loop(noise=None)
    with pytest.raises(ArgumentError, match="no source"):
        cl.noise_budget(["b.z"], [1.0, 2.0])
    with pytest.raises(ArgumentError, match="not measurements"):
        cl.noise_budget(["b.z"], [1.0, 2.0], noise={"sensor.x": 1.0})
    b = cl.noise_budget(["b.z", "actuator.a.u"], [1.0, 2.0, 4.0], noise={"sensor.v": SN})
    assert b.psd.shape == (2, 1, 3) and b.units == ("m", "N")
    with pytest.raises(ModelError, match="noise PSD is not written"):
        dumps_model(loop()[0])


def test_figure() -> None:
    _, cl = loop()
    b = cl.noise_budget(["b.z"], np.geomspace(0.5, 200.0, 200), ground=1e-10)
    fig = b.plot()
    ax = fig.axes[0]
    assert "Hz" in ax.get_xlabel() and "sqrt(Hz)" in ax.get_ylabel()
    assert len(ax.get_lines()) == 4 and "RMS" in b.report()
