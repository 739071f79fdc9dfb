"""Orders on a model with nonlinear mounts: harmonic balance continued in the speed, the unbalance
force growing with rpm^2 along it (issue 30: "orders and run-ups take it for unbalance forcing").

Independent numbers: at small unbalance (never reaching the stop) the closed form of a one-DOF
oscillator ``m e W^2 / |k - M W^2 + i c W|`` and vibss's linear order response of the same model
without its stop; at an unbalance that drives the body into its stop, the end of a long ``solve_ivp``
integration written here (the bilinear stop force by hand, from rest until the transient has died
away), whose last period's first harmonic is taken by FFT.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from vibss import Body, Model, Mount, MountType
from vibss.errors import ArgumentError
from vibss.orders import OrderForce, Unbalance, order_response

M, K, C, GAP, KS, E = 10.0, 4e4, 40.0, 1e-3, 4e4, 0.01      # kg, N/m, N s/m, m, N/m, m (unbalance radius)


def _model(stops: bool = True) -> Model:
    t = MountType("snub", [K, K, K], damping=[C] * 3, stops={"z": (GAP, KS)} if stops else None)
    return Model([Body("b", M, [1.0, 1.0, 1.0])], [Mount("m", t, "b")])


def test_small_unbalance_is_the_linear_order_response() -> None:
    me = 1e-5                                                          # kg m: 0.02 mm at most, far from the stop
    r = order_response(_model(), Unbalance("u", "b", me / E, E, axis="x"), np.linspace(300.0, 1200.0, 60),
                       ["b.z", "b.y"])
    assert r.method == "harmonic_balance" and r.turning_rpm.size == 0 and r.stable is not None and r.stable.all()
    assert np.all(np.diff(r.rpm) > 0) and r.rpm[0] == pytest.approx(300.0) and r.rpm[-1] == pytest.approx(1200.0)
    W = 2 * np.pi * r.rpm / 60.0
    closed = me * W**2 / np.abs(K - M * W**2 + 1j * C * W)
    np.testing.assert_allclose(np.abs(r.response[0, 0]), closed, rtol=1e-6)
    np.testing.assert_allclose(np.abs(r.response[0, 1]), closed, rtol=1e-6)
    lin = order_response(_model(stops=False), Unbalance("u", "b", me / E, E, axis="x"), r.rpm, ["b.z", "b.y"])
    assert lin.method != "harmonic_balance"
    np.testing.assert_allclose(r.response, lin.response, rtol=1e-6, atol=1e-6 * np.abs(lin.response).max())


def _time_integration(me: float, rpm: float) -> float:
    """First-harmonic amplitude of z at the end of a long integration from rest [m]."""
    W = 2 * np.pi * rpm / 60.0
    F = me * W**2

    def rhs(t: float, s: np.ndarray) -> list[float]:
        z, v = s
        stop = KS * (z - GAP) if z > GAP else (KS * (z + GAP) if z < -GAP else 0.0)
        return [v, (F * np.sin(W * t) - K * z - C * v - stop) / M]

    T = 2 * np.pi / W
    n = int(np.ceil(14.0 / T))                        # 14 s: the transient decays as exp(-2 t)
    sol = solve_ivp(rhs, (0.0, n * T), [0.0, 0.0], method="DOP853", rtol=1e-11, atol=1e-15, dense_output=True,
                    max_step=T / 50)
    t = (n - 1) * T + T * np.arange(256) / 256        # the last period
    return float(2 * np.abs(np.fft.rfft(sol.sol(t)[0])[1]) / 256)


def test_into_the_stop_matches_a_long_time_integration() -> None:
    me, rpm = 8e-4, 600.0                             # 600 rpm: one solution, the body 8 % past its stop
    r = order_response(_model(), Unbalance("u", "b", me / E, E, axis="x"), np.linspace(300.0, rpm, 30),
                       ["b.z"], harmonics=15)
    assert r.rpm[-1] == pytest.approx(rpm, rel=1e-12)
    hb = abs(r.response[0, 0, -1])
    assert hb > 1.05 * GAP
    assert hb == pytest.approx(_time_integration(me, rpm), rel=1e-4)


def test_turning_points_and_refusals() -> None:
    r = order_response(_model(), Unbalance("u", "b", 8e-4 / E, E, axis="x"), np.linspace(300.0, 1200.0, 80),
                       ["b.z"], quantity="accelerance")
    assert r.turning_rpm.size == 2 and r.turning_rpm[0] > r.turning_rpm[1]       # a hardening fold
    assert r.stable is not None and not r.stable.all()
    assert r.units == ("m/s^2",)
    rec = order_response(_model(), Unbalance("u", "b", 8e-4 / E, E, axis="x"), np.linspace(300.0, 1200.0, 80),
                         ["b.z"])                                   # the same branch, as a receptance
    np.testing.assert_allclose(rec.rpm, r.rpm, rtol=1e-12)
    W = 2 * np.pi * rec.rpm / 60.0
    np.testing.assert_allclose(r.response[0, 0], -W**2 * rec.response[0, 0], rtol=1e-12)
    assert rec.units == ("m",)
    two = [Unbalance("u", "b", 0.1, E, axis="x"), OrderForce("o2", "b", 2.0, [300.0], force=[[0.0, 0.0, 1.0]])]
    with pytest.raises(ArgumentError, match="sources of one order"):
        order_response(_model(), two, np.linspace(300.0, 1200.0, 10))
