"""vibss.control.robustness: closed forms of a 1-DOF skyhook isolator whose mount rate is off, a
stability boundary with a known probability, and the platform's variants rebuilt and closed again."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import cases.models as cases
import vibss
import vibss.control as vc
from vibss.control.loop import controller
from vibss.control.variants import HOLD
from vibss.errors import ArgumentError, ControlDesignError
from vibss.frequency.statespace_response import evaluate
from vibss.model.actuation import Actuator, Sensor

M_, K_ = 10.0, 1e4


def isolator(c0: float = 0.0) -> vibss.Model:
    return cases.sdof(M_, K_, c0, type_name="iso", actuators=[Actuator("a", mount="m", axis=3)],
                      sensors=[Sensor("v", "velocity", body="b", direction=[0, 0, 1]),
                               Sensor("s", "relative_displacement", mount="m", axis=3)])


def test_skyhook_variants_match_the_closed_forms() -> None:
    # m x'' + c x' + k_v (x - y) = 0 (c the skyhook damper): zeta = c / (2 sqrt(m k_v)) and, undamped
    # mount, |T|_peak = 1 / (2 zeta sqrt(1 - zeta^2)) for zeta < 1/sqrt(2) (|T|^-2 minimised over w^2)
    P = vc.plant(isolator(), ["ground.z.vel"], performance=["b.z.vel"], measurements=["sensor.v"], dofs=["b.z"])
    c = 150.0
    r = vc.robustness(P, vc.skyhook(P, c), {"m.k3": 0.3}, n=40, channel=("ground.z.vel", "b.z.vel"))
    kv = r.values[:, 0]
    zeta = c / (2 * np.sqrt(M_ * kv))
    np.testing.assert_allclose(r.damping, zeta, rtol=1e-10)
    np.testing.assert_allclose(r.peak, 1 / (2 * zeta * np.sqrt(1 - zeta ** 2)), rtol=1e-6)
    assert r.corner.sum() == 2 and sorted(r.values[r.corner, 0]) == pytest.approx([0.7 * K_, 1.3 * K_])
    assert r.stable.all() and r.p_stable == 1.0
    assert r.worst.mounts[0].type.stiffness[2] == pytest.approx(kv[r.worst_index])
    assert r.check is not None and r.check.ok


def test_probability_of_stability_against_the_exact_boundary() -> None:
    # positive displacement feedback u = +g d (a negative spring g) on a damped isolator: stable iff
    # k_v > g. With k uniform on K (1 +- 0.2) and g = 0.9 K: P(stable) = (1.2 - 0.9) / 0.4 = 0.75
    P = vc.plant(isolator(c0=40.0), ["ground.z.disp"], performance=["b.z"], measurements=["sensor.s"],
                 dofs=["b.z"])
    g = 0.9 * K_
    K = controller(np.zeros((0, 0)), np.zeros((0, 1)), np.zeros((1, 0)), np.array([[g]]), ["sensor.s"],
                   ["actuator.a.u"], {"design": "negative spring"})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")           # a fragile nominal loop: warned by close, on purpose
        r = vc.robustness(P, K, {"m.k3": 0.2}, n=400, seed=1)
    kv = r.values[:, 0]
    np.testing.assert_array_equal(r.stable, kv > g)
    assert abs(r.p_stable - 0.75) < 0.01                       # LHS: one sample per 1/400 stratum
    lo, hi = r.p_stable_interval
    assert lo < 0.75 < hi and hi - lo < 0.1
    assert not r.stable[r.worst_index] and r.worst.mounts[0].type.stiffness[2] < g


def test_variants_agree_with_the_rebuilt_and_closed_platform() -> None:
    m = vibss.load_example("platform")
    cs = m.settings["control"]
    P = vc.plant(m, cs["disturbances"], performance=cs["performance"])
    K = vc.skyhook(P, cs["gain"])
    tol = {"fl.k3": 0.3, "fr.k3": 0.3, "rl.k1": 0.3}
    r = vc.robustness(P, K, tol, n=6, corners=0, channel=("ground.z.vel", "table.z.vel"))
    params = vibss.design.parameters.parameters_of(m, list(tol))
    for i in range(3):
        mv = vibss.design.parameters.apply(m, params, r.values[i])
        cl = vc.close(vc.plant(mv, cs["disturbances"], performance=cs["performance"]), K)
        assert r.damping[i] == pytest.approx(cl.damping.min(), rel=1e-9)
        assert r.disk_margin[i] == pytest.approx(min(x.disk_margin for x in cl.margins), rel=1e-4)
        # the peak on a fine grid of the rebuilt loop's own response
        f = np.geomspace(0.1, 900, 20000)
        j = cl.system.input_labels.index("ground:z:vel")
        o = cl.system.output_labels.index("table:z:vel")
        h = np.abs(evaluate(cl.system, 2 * np.pi * f, outputs=[o], inputs=[j])[0, 0])
        k = int(np.argmax(h))
        f2 = np.linspace(f[k - 1], f[k + 1], 2001)
        peak = np.abs(evaluate(cl.system, 2 * np.pi * f2, outputs=[o], inputs=[j])[0, 0]).max()
        assert r.peak[i] == pytest.approx(peak, rel=1e-6)


def test_rebuild_takes_shifts_and_lft_refuses_them() -> None:
    P = vc.plant(isolator(), ["ground.z.vel"], performance=["b.z.vel"], measurements=["sensor.v"], dofs=["b.z"])
    K = vc.skyhook(P, 150.0)
    with pytest.raises(ControlDesignError, match="rebuild"):
        vc.robustness(P, K, {"m.k3": 0.2, "m.z": 0.01}, method="lft")
    r = vc.robustness(P, K, {"m.k3": 0.2, "m.z": 0.01}, n=4, corners=0)
    assert r.method == "rebuild" and r.check is None
    np.testing.assert_allclose(r.damping, 150.0 / (2 * np.sqrt(M_ * r.values[:, 0])), rtol=1e-10)
    with pytest.raises(ArgumentError, match="tolerances"):
        vc.robustness(P, K, {})


def test_figure_and_table(tmp_path) -> None:
    P = vc.plant(isolator(), ["ground.z.vel"], performance=["b.z.vel"], measurements=["sensor.v"], dofs=["b.z"])
    r = vc.robustness(P, vc.skyhook(P, 150.0), {"m.k3": 0.2}, n=30)
    text = r.report()
    assert "P(stable) = 1.0000" in text and "worst corner" in text
    fig = r.plot()
    assert len(fig.axes) == 3 and all(a.get_xlabel() for a in fig.axes)
    assert r.to_pandas().shape == (32, 7) and r.to_dict()["n"] == 30


@pytest.mark.slow
def test_cli_robust(capsys, tmp_path) -> None:
    from vibss.cli import main

    png = tmp_path / "r.png"
    assert main(["control", "--example", "platform", "--robust", "0.2", "--variants", "20",
                 "--robust-plot", str(png)]) == 0
    out = capsys.readouterr().out
    assert "Robustness over 20 variants + 64 corners" in out and "P(stable) = 1.0000" in out
    assert png.stat().st_size > 0
    assert main(["control", "--example", "platform", "--robust", "1.5"]) == 2
    capsys.readouterr()
    assert main(["control", "--example", "platform", "--robust", "0.1", "--variants", "5", "--format", "json"]) == 0
    import json

    doc = json.loads(capsys.readouterr().out)                 # one document: the loop and its robustness
    assert doc["robustness"]["n"] == 5 and "margins" in doc["control"]


def test_held_poles_are_checked() -> None:
    # the platform's 24 closed-loop poles: 12 solved per variant (the rest held, with their static
    # residual) agree with all 24; 4 do not, and the rebuilt check says so
    m = vibss.load_example("platform")
    cs = m.settings["control"]
    P = vc.plant(m, cs["disturbances"], performance=cs["performance"])
    K = vc.skyhook(P, cs["gain"])
    tol = {"fl.k3": 0.3, "fr.k3": 0.3, "rl.k1": 0.3}
    full = vc.robustness(P, K, tol, n=10, corners=0)
    part = vc.robustness(P, K, tol, n=10, corners=0, states=12)
    # the poles the rate channels barely see are held too (variants.HOLD bounds their relative shift)
    np.testing.assert_allclose(part.damping, full.damping, rtol=HOLD)
    assert "of the lowest 12 the rate channels see" in part.note and part.check.ok
    with pytest.warns(vibss.errors.VibssWarning, match="raise states="):
        few = vc.robustness(P, K, tol, n=10, corners=0, states=4)
    assert not few.check.ok


def test_fast_path_against_every_variant_rebuilt() -> None:
    """lft (the poles the channels see solved, the rest held; responses by the internal feedback)
    against method='rebuild' (every variant's model rebuilt, its loop closed, all poles): the same
    stability per variant, damping within the held poles' bound, margins and peaks on the same grid."""
    m = vibss.load_example("platform")
    cs = m.settings["control"]
    P = vc.plant(m, cs["disturbances"], performance=cs["performance"])
    K = vc.skyhook(P, cs["gain"])
    tol = {"fl.k3": 0.4, "fr.k3": 0.4, "rl.k1": 0.4, "rr.k2": 0.4}
    fast = vc.robustness(P, K, tol, n=12, corners=2, method="lft")
    full = vc.robustness(P, K, tol, n=12, corners=2, method="rebuild")
    assert np.array_equal(fast.stable, full.stable)
    np.testing.assert_allclose(fast.damping, full.damping, rtol=10 * HOLD)
    for key in ("disk_margin", "mimo_disk_margin", "peak"):
        np.testing.assert_allclose(getattr(fast, key), getattr(full, key), rtol=1e-9)
