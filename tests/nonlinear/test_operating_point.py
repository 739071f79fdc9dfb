"""The operating point of nonlinear mounts against closed forms: the bilinear stop's static
deflection, a curve's equilibrium on one of its points, tangent modes sqrt(sum k / m) with the
PCHIP slope from the Fritsch-Carlson formula, and the refusals."""

from __future__ import annotations

import numpy as np
import pytest

import vibss
from vibss import Body, Model, Mount, MountType, symmetric
from vibss.errors import ModelError
from vibss.nonlinear import operating_point

G = 9.81
MASS = 120.0


def _box(t: MountType, mass: float = MASS) -> Model:
    return Model([Body("b", mass, [2.0, 2.5, 3.0])], symmetric(Mount("m", t, "b", at=[0.3, 0.2, 0.0])),
                 gravity=[0.0, 0.0, -G], name="box")


@pytest.mark.parametrize("clearance", [0.5e-3, 2e-3, 20e-3])
def test_bilinear_stop_sag_is_the_closed_form(clearance: float) -> None:
    k, ks = 1.5e5, 2e6
    t = MountType("snub", [k, k, k], stops={"z": (clearance, ks)})
    op = operating_point(_box(t))
    w = MASS * G / 4                                  # per mount
    free = k * clearance
    sag = w / k if w <= free else clearance + (w - free) / (k + ks)
    assert op.q[2] == pytest.approx(-sag, rel=1e-12)
    assert op.clearance["m.z"] == pytest.approx(clearance - sag, rel=1e-9, abs=1e-15)
    assert op.stop_force["m.z"] == pytest.approx(max(sag - clearance, 0.0) * ks, rel=1e-9, abs=1e-9)
    assert np.sum(op.static.mount_force[:, 2]) == pytest.approx(-MASS * G, rel=1e-12)   # equilibrium


def _fritsch_carlson(x: np.ndarray, y: np.ndarray, k: int) -> float:
    """PCHIP's slope at interior knot k: the weighted harmonic mean of the two secants."""
    h0, h1 = x[k] - x[k - 1], x[k + 1] - x[k]
    s0, s1 = (y[k] - y[k - 1]) / h0, (y[k + 1] - y[k]) / h1
    w1, w2 = 2 * h1 + h0, h1 + 2 * h0
    return (w1 + w2) / (w1 / s0 + w2 / s1)


def test_equilibrium_on_a_curve_point_and_the_tangent_bounce_mode() -> None:
    x = np.array([-6e-3, -3e-3, 0.0, 2e-3, 4e-3, 6e-3])
    y = np.array([-1500.0, -500.0, 0.0, 300.0, 900.0, 2000.0])
    t = MountType("curved", [2e5, 2e5, 0.0], curve={"z": list(zip(x, y))})
    mass = 4 * 500.0 / G                              # each mount carries 500 N: the point (-3 mm, -500 N)
    op = operating_point(_box(t, mass))
    assert op.q[2] == pytest.approx(-3e-3, rel=1e-10)
    kt = _fritsch_carlson(x, y, 1)
    assert op.tangent.mounts[0].type.stiffness[2] == pytest.approx(kt, rel=1e-9)   # q to ~1e-12, times the curvature
    fz = vibss.modes(op.tangent).frequency_hz
    bounce = np.sqrt(4 * kt / mass) / (2 * np.pi)
    assert np.min(np.abs(fz - bounce)) < 1e-9 * bounce
    k0 = _fritsch_carlson(x, y, 2)
    assert t.stiffness[2] == pytest.approx(k0, rel=1e-12)      # the unloaded rate is the slope at zero


def test_a_linear_model_is_its_static_deflection() -> None:
    t = MountType("lin", [1e5, 1e5, 2e5])
    op = operating_point(_box(t))
    assert op.q[2] == pytest.approx(-MASS * G / (4 * 2e5), rel=1e-12) and op.iterations == 0   # m g / (4 kz)


def test_a_load_beyond_a_flat_curve_end_names_the_mount_and_axis() -> None:
    pts = [(-2e-3, -1001.0), (-1e-3, -1000.0), (0.0, 0.0), (1e-3, 1000.0), (2e-3, 1001.0)]
    t = MountType("flat", [1e5, 1e5, 0.0], curve={"z": pts})
    assert float(t.laws[2].tangent(-3e-3)) == 0.0     # PCHIP's end slope is zero here
    with pytest.raises(ModelError, match="mount 'm' axis 'z': the load needs more than its curve's end force"):
        operating_point(_box(t, mass=4 * 1200.0 / G))


@pytest.mark.parametrize("kwargs, match", [
    ({"stops": {"z": (-1e-3, 1e6)}}, r"stops\['z'\]: clearance must be finite and not negative"),
    ({"stops": {"w": (1e-3, 1e6)}}, "stops: unknown axis 'w'"),
    ({"stops": {"z": (1e-3, 0.0)}}, "stiffness: expected a positive stop rate"),
    ({"curve": {"z": [(-1e-3, -10.0), (1e-3, 5.0), (2e-3, 1.0)]}}, "the curve must pass through"),
    ({"curve": {"z": [(-1e-3, -10.0), (0.0, 0.0), (1e-3, 5.0), (2e-3, 1.0)]}}, "force must increase"),
])
def test_bad_stops_and_curves_name_the_type_and_axis(kwargs: dict, match: str) -> None:
    with pytest.raises(ModelError, match=match) as info:
        MountType("bad", [1e5, 1e5, 1e5], **kwargs)
    assert "mount type 'bad'" in str(info.value)


def test_static_and_modes_of_the_nonlinear_model_are_the_operating_point() -> None:
    k, ks, c = 1.5e5, 2e6, 1e-3        # 294 N per mount, 150 N in the free travel: on the stops
    t = MountType("snub", [k, k, k], stops={"z": (c, ks)})
    model = _box(t)
    op = vibss.operating_point(model)
    st = vibss.static(model)
    w = MASS * G / 4                                              # per mount, past the free travel k c
    assert st.q[2] == pytest.approx(-(c + (w - k * c) / (k + ks)), rel=1e-12) and st.iterations > 1
    md = vibss.modes(model)
    assert "modes of the tangent model at the operating point" in md.note
    bounce = np.sqrt(4 * (k + ks) / MASS) / (2 * np.pi)          # every mount on its stop
    assert np.min(np.abs(md.frequency_hz - bounce)) < 1e-9 * bounce
    np.testing.assert_allclose(md.frequency_hz, vibss.modes(op.tangent).frequency_hz, rtol=1e-12)


def test_linear_analyses_refuse_the_nonlinear_model_and_name_the_tangent() -> None:
    model = _box(MountType("snub", [1.5e5, 1.5e5, 1.5e5], stops={"z": (2e-3, 2e6)}))
    for call in (lambda: vibss.frequency_response(model, ["b.fz"], ["b.z"], [1.0, 10.0]),
                 lambda: vibss.damped_modes(model)):      # simulate takes it (test_time_response.py)
        with pytest.raises(ModelError, match=r"mounts \['m', 'm.xz', 'm.yz', 'm.xz.yz'\] have stops .* "
                                             r"vibss.operating_point\(model\).tangent"):
            call()
