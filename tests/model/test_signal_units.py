"""The unit algebra of signals: output per input units in text, JSON, pandas and figures; the ``g``
acceleration unit and ``gravity = "standard"`` in model files."""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest

import vibss
from vibss.errors import ModelError, VibssWarning
from vibss.io.modelfile import loads_model
from vibss.model.units import STANDARD_GRAVITY

BOX = """
[model]
units = {{ length = "mm"{extra} }}
{gravity}
[[body]]
name = "box"
mass = 20.0
inertia = [0.1, 0.1, 0.1]
[[mount_type]]
name = "iso"
stiffness = [50.0, 50.0, 80.0]          # N/mm
damping = [0.2, 0.2, 0.2]
[[mount]]
type = "iso"
body = "box"
at = [100.0, 100.0, -50.0]
symmetry = "double"
"""


def box(gravity: str = "", extra: str = "") -> vibss.Model:
    return loads_model(BOX.format(gravity=gravity, extra=extra))


def test_frf_units_are_output_per_input() -> None:
    r = vibss.frequency_response(box(), ["box.fz", "box.my", "ground.z.acc"], ["box.z", "ground.fz", "box.ry"],
                                 [2.0, 20.0])
    assert r.channel_unit("box.z", "box.fz") == "m/N"
    assert r.channel_unit("ground.fz", "box.my") == "N/(N m)"
    assert r.channel_unit("box.ry", "ground.z.acc") == "rad/(m/s^2)"
    data = json.loads(r.to_json())
    assert data["inputs"]["box.my"]["outputs"]["box.ry"]["unit"] == "rad/(N m)"
    assert "N/(N m)" in r.report() and "m/N" in str(r.summary())
    acc = vibss.frequency_response(box(), ["ground.z.acc"], ["box.z"], [5.0], quantity="accelerance")
    assert acc.channel_unit("box.z") == "(m/s^2)/(m/s^2)"
    pytest.importorskip("pandas")
    assert r.to_pandas().attrs["units"]["ground.fz/box.fz"] == "N/N"


def test_transmissibility_is_dimensionless_only_between_equal_units() -> None:
    t = vibss.transmissibility(box(), ["ground.z"], ["box.z", "box.ry"], [5.0])
    assert t.channel_unit("box.z") == "-"
    assert t.channel_unit("box.ry") == "rad/m"
    f = vibss.transmissibility(box(), ["box.fz", "box.my"], ["ground.fz"], [5.0])
    assert f.channel_unit("ground.fz", "box.fz") == "-" and f.channel_unit("ground.fz", "box.my") == "N/(N m)"


def test_bode_axis_carries_the_unit() -> None:
    r = vibss.frequency_response(box(), ["box.fz"], ["box.z", "box.x"], [1.0, 5.0, 20.0])
    fig = r.plot()
    assert "[m/N]" in fig.axes[0].get_ylabel()


def test_g_unit_and_standard_gravity() -> None:
    standard = box(gravity='gravity = "standard"')
    np.testing.assert_array_equal(standard.gravity, [0.0, 0.0, -STANDARD_GRAVITY])
    in_g = box(gravity="gravity = [0.0, 0.0, -1.0]", extra=', acceleration = "g"')
    np.testing.assert_array_equal(in_g.gravity, standard.gravity)
    # the static sag is the same physics: m g / k_total
    sag = vibss.static(standard).q[2]
    assert sag == pytest.approx(-20.0 * STANDARD_GRAVITY / (4 * 80e3), rel=1e-9)
    with pytest.warns(VibssWarning, match=r"gravity 9\.81 is read in mm/s\^2.*\"standard\""):
        looks_si = box(gravity="gravity = [0.0, 0.0, -9.81]")
    assert looks_si.gravity[2] == pytest.approx(-9.81e-3)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        box(gravity="gravity = [0.0, 0.0, -9810.0]")          # mm/s^2, as the file says: no warning
    with pytest.raises(ModelError, match="gravity.*\"standard\""):
        box(gravity='gravity = "earth"')
    with pytest.raises(ModelError, match="acceleration.*\"g\""):
        box(extra=', acceleration = "gee"')


def test_acceleration_excitations_in_g() -> None:
    """A 30 g, 11 ms half-sine written in g and ms: its peak is 30 x 9.80665 m/s^2 at 5.5 ms."""
    text = BOX.format(gravity="", extra=', time = "ms", acceleration = "g"') + """
[[excitation]]
name = "shock"
kind = "acceleration"
target = "ground"
dof = "z"
function = { type = "half_sine", amplitude = 30.0, start = 0.0, duration = 11.0 }
"""
    f = loads_model(text).excitations[0].function
    assert f.value(np.array([5.5e-3]))[0] == pytest.approx(30 * STANDARD_GRAVITY, rel=1e-12)
    assert f.value(np.array([11.5e-3]))[0] == 0.0


def test_isolator_without_a_sweep_gets_transmissibility_in_the_report() -> None:
    """Reciprocity: the motion transmissibility ground.d -> body.d equals the force transmissibility
    body.fd -> ground.fd (Maxwell-Betti at the COG); and the report shows both."""
    from vibss.report import study

    m = vibss.load_example("inertia_block")
    r = study(m, figures=False)
    sec = r.section("frequency")
    assert not sec.skipped and "no sine sweep" in sec.note
    motion, force = r.results["transmissibility:motion"], r.results["transmissibility:force"]
    for d in "xyz":
        np.testing.assert_allclose(motion[d].response[0, 0], force[d].response[0, 0], rtol=1e-9)
        np.testing.assert_allclose(motion[d].response[1, 0], force[d].response[0, 1], rtol=1e-9)
    assert all(row[3] != "nan" for row in sec.tables[0].rows)


def test_shock_study_leads_with_stroke_and_acceleration_and_names_the_pulse() -> None:
    from vibss.report import study

    r = study(vibss.load_example("packaged_item"), figures=False)
    rows = r.section("time").tables[0].rows
    assert rows[0][0].startswith("mount.") and rows[0][4] == "m"         # stroke first
    units = [row[4] for row in rows]
    assert units.index("m/s^2") < max(i for i, row in enumerate(rows) if not row[0].startswith("mount."))
    peaks = np.array([abs(float(row[1])) for row in rows if row[4] == "m"])
    assert peaks.min() > 1e-9 * peaks.max()                              # zero channels dropped
    excitations = r.section("model").tables[-1]
    params = excitations.rows[0][5]
    assert "duration 0.011 s" in params and "(50.02 g)" in params        # 490.5 m/s^2 / 9.80665


def test_static_section_draws_body_and_mount_deflections() -> None:
    from vibss.report import study

    m = vibss.load_example("inertia_block")
    r = study(m, figures=True)
    names = [n for n, _ in r.section("static").figures]
    assert names == ["static.png", "static_mounts.png"]
    fig = dict(r.section("static").figures)["static_mounts.png"]
    bars = [p.get_height() for p in fig.axes[0].patches]
    local = r.results["static"].mount_deflection_local.reshape(-1, 3) * 1e3
    np.testing.assert_allclose(sorted(bars), sorted(local.ravel()), rtol=1e-12, atol=1e-12)


def test_motion_transmissibility_of_accelerations_is_the_ratio_of_equal_orders() -> None:
    """ground.z.acc -> b.z.acc is the same dimensionless ratio as displacement over displacement
    (it was silently taken over the ground displacement: s^2 times too large, in (m/s^2)/m)."""
    import numpy as np
    import vibss

    t = vibss.MountType("t", [1e4] * 3, [20.0] * 3)
    m = vibss.Model([vibss.Body("b", 10.0, [1, 1, 1])], [vibss.Mount("m", t, "b")])
    f = np.array([1.0, 5.0, 30.0])
    acc = vibss.transmissibility(m, ["ground.z.acc"], ["b.z.acc"], frequencies=f)
    s = 2j * np.pi * f
    np.testing.assert_allclose(acc.response[0, 0], (1e4 + 20 * s) / (10 * s ** 2 + 20 * s + 1e4), rtol=1e-12)
    assert acc.channel_unit(0, 0) == "-"
    with pytest.raises(vibss.ModelError, match=r"needs motion outputs; \['mount.m.fz'\]"):
        vibss.transmissibility(m, ["ground.z"], ["mount.m.fz"], frequencies=f)
