"""vibss.control.tune: closed-form minimal gains of a 1-DOF skyhook isolator, over a tolerance set
too, goals it cannot meet, and a dynamic structure checked by close()."""

from __future__ import annotations

import numpy as np
import pytest

import cases.models as cases
import vibss.control as vc
from vibss.control.tune import tune
from vibss.errors import ArgumentError
from vibss.model.actuation import Actuator, Sensor

M_, K_ = 10.0, 1e4
CH = ("ground.z.vel", "b.z.vel")


def plant(c0: float = 0.0, measurements: tuple[str, ...] = ("sensor.v",)) -> vc.GeneralizedPlant:
    m = cases.sdof(M_, K_, c0, type_name="iso", actuators=[Actuator("a", mount="m", axis=3)],
                   sensors=[Sensor("v", "velocity", body="b", direction=[0, 0, 1]),
                            Sensor("s", "relative_displacement", mount="m", axis=3)])
    return vc.plant(m, ["ground.z.vel"], performance=["b.z.vel"], measurements=list(measurements), dofs=["b.z"])


def test_skyhook_reaches_the_closed_form_minimal_gain_for_a_peak_goal() -> None:
    # m x'' + c x' + k (x - y) = 0: |T|^2 = k^2 / ((k - m u)^2 + c^2 u), u = w^2. Its minimum over u is
    # at u* = (2 m k - c^2) / (2 m^2), where the denominator is (4 m k c^2 - c^4) / (4 m^2): with
    # zeta = c / (2 sqrt(m k)), |T|_peak = 1 / (2 zeta sqrt(1 - zeta^2)). |T|_peak <= T gives
    # zeta^2 >= (1 - sqrt(1 - 1 / T^2)) / 2, and effort (c |T|) grows with c: the least c meets it exactly.
    T = 2.0
    zeta = np.sqrt((1 - np.sqrt(1 - 1 / T ** 2)) / 2)
    c_min = 2 * np.sqrt(M_ * K_) * zeta
    r = tune(plant(), "skyhook", [("peak_transmissibility", "<=", T, CH)])
    assert r.all_met
    assert r.parameters["a.gain"] == pytest.approx(c_min, rel=1e-2)
    assert r.achieved[0] == pytest.approx(T, rel=1e-3)
    assert r.check.ok and "every goal met" in r.report()


def test_damping_goal_over_the_tolerance_set() -> None:
    # zeta = c / (2 sqrt(m k_v)) falls as k_v grows: the worst corner is k (1 + 0.2), so the least c is
    # 2 * 0.3 * sqrt(m * 1.2 k)
    r = tune(plant(), "skyhook", [("damping", ">=", 0.3)], tolerances={"m.k3": 0.2})
    assert r.variants == 3 and r.all_met
    assert r.parameters["a.gain"] == pytest.approx(0.6 * np.sqrt(M_ * 1.2 * K_), rel=1e-2)
    # close() on the nominal plant agrees: zeta = c / (2 sqrt(m k))
    assert r.closed.damping.min() == pytest.approx(r.parameters["a.gain"] / (2 * np.sqrt(M_ * K_)), rel=1e-9)


def test_a_goal_that_cannot_be_met_is_reported() -> None:
    # |T(0)| = 1 for any skyhook gain: a peak below 1 is out of reach
    r = tune(plant(), "skyhook", [("peak_transmissibility", "<=", 0.5, CH), ("damping", ">=", 0.1)], maxiter=60)
    assert not r.all_met and not r.met[0]
    assert "NO" in r.table.render()


def test_lead_lag_on_a_stroke_sensor_is_verified_by_close() -> None:
    r = tune(plant(c0=5.0, measurements=("sensor.s",)), "lead_lag", [("damping", ">=", 0.2), ("disk_margin", ">=", 0.5)])
    assert r.all_met and r.controller.nstates == 1
    assert r.closed.damping.min() >= 0.2 * (1 - 1e-6)
    assert min(m.disk_margin for m in r.closed.margins) >= 0.5 * (1 - 1e-2)
    with pytest.raises(ArgumentError, match="structure"):
        tune(plant(), "pidd", [("damping", ">=", 0.2)])
    with pytest.raises(ArgumentError, match="goals"):
        tune(plant(), "skyhook", [("damping", "=", 0.2)])
