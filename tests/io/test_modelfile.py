"""Model files: reference cases through files equal the Python API, exact round trips, located errors."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import scipy.linalg as sl

from vibss import Body, Model, ModelError, ModelFileError, Mount, MountType, assemble, symmetric
from vibss.io import (dump_model, dumps_model, example_names, example_path, load_example,
                      load_model, loads_model, model_to_dict)


def _hz(model):
    a = assemble(model)
    return np.sqrt(np.abs(sl.eigh(a.K, a.M, eigvals_only=True))) / (2 * np.pi)


def _case1_api():
    spring = MountType("spring", [1e4, 2e4, 3e4])
    body = Body("prism", 1000.0, [10.0, 20.0, 30.0])
    return Model([body], symmetric(Mount("corner", spring, "prism", at=[1.0, 2.0, 0.0]), "double"))


def _case2_api():
    spring = MountType("spring", [12000.0] * 3)
    bodies = [Body(n, 1000.0, [10.0, 20.0, 30.0]) for n in ("body1", "body2")]
    mounts = symmetric(Mount("lower", spring, "body1", at=[1, 1, -1]), "double") + \
        symmetric(Mount("upper", spring, "body2", at=[1, 1, -1], to="body1"), "double")
    return Model(bodies, mounts)


def test_case1_file_equals_api_and_reference_frequencies():
    a, b = assemble(load_example("prism")), assemble(_case1_api())
    np.testing.assert_array_equal(a.M, b.M)
    np.testing.assert_array_equal(a.K, b.K)
    f = _hz(load_example("prism"))
    closed = np.sqrt([40e3 / 1000, 80e3 / 1000, 120e3 / 1000, 4 * 30e3 * 1 / 20,
                      4 * (10e3 * 4 + 20e3 * 1) / 30, 4 * 30e3 * 4 / 10]) / (2 * np.pi)
    np.testing.assert_allclose(f, closed, rtol=1e-10)
    # the handbook's table (1.0065 and 1.7434 are truncated there, hence 1e-4 Hz)
    np.testing.assert_allclose(f, [1.0065, 1.4235, 1.7434, 12.33, 14.24, 34.87], atol=6e-3)
    np.testing.assert_allclose(f[:3], [1.0065, 1.4235, 1.7434], atol=1e-4)


def test_case2_in_mm_equals_si_and_reference_frequencies():
    a, b = assemble(load_example("two_mass")), assemble(_case2_api())
    np.testing.assert_allclose(a.M, b.M, rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(a.K, b.K, rtol=1e-12, atol=1e-7)
    f = np.round(_hz(load_example("two_mass")), 2)
    assert f.tolist() == [0.48, 0.48, 0.68, 1.26, 1.26, 1.78, 5.56, 6.83, 9.65, 14.57, 17.89, 25.26]


def test_all_examples_load_and_are_stable():
    assert {"prism", "two_mass", "powertrain", "inertia_block", "ground_shake",
            "packaged_item"} <= set(example_names())
    for name in example_names():
        model = load_example(name)
        a = assemble(model)
        assert np.all(sl.eigh(a.K, a.M, eigvals_only=True) > 0), name   # fully restrained
        for x in model.excitations:
            assert x.target in model.body_names + ["ground"]


def test_powertrain_is_realistic():
    model = load_example("powertrain")
    body = model.bodies[0]
    assert 150 <= body.mass <= 200
    assert np.count_nonzero(body.tensor - np.diag(np.diag(body.tensor))) == 6   # products of inertia
    f = _hz(model)
    assert 5.0 <= f.min() and f.max() <= 20.0
    assert assemble(model).has_damping and model.gravity is not None
    assert {x.signal for x in model.excitations} == {"powertrain.mx", "ground.z.disp"}   # the pothole: a dip that ends where it began
    assert model.settings["load_cases"] == {"full-load": ["drive-torque"]}
    assert model.loads[0].moment.tolist() == pytest.approx([420.0, 0.0, 0.0])   # 4.2e5 N mm -> N m


def test_units_are_converted_once(tmp_path):
    text = """
[model]
units = { length = "mm", mass = "t", force = "kN", time = "ms" }
gravity = [0, 0, -0.00981]
[[body]]
name = "b"
mass = 0.5
inertia = [1e6, 1e6, 1e6]
cog = [0, 0, 100]
initial = { displacement = [1, 0, 0, 90, 0, 0], velocity = [2, 0, 0, 0, 0, 0] }
[[mount_type]]
name = "t"
stiffness = [1, 2, 3]
damping = [0.001, 0, 0]
[[mount]]
type = "t"
body = "b"
orientation = { euler = [90, 0, 0] }
[[excitation]]
kind = "acceleration"
target = "ground"
dof = "z"
function = { type = "half_sine", amplitude = 0.00981, start = 1, duration = 11 }
[analysis]
time = { end = 500, step = 0.5 }
"""
    m = loads_model(text)
    b = m.bodies[0]
    assert b.mass == pytest.approx(500.0)
    assert b.inertia.tolist() == pytest.approx([1000.0] * 3)         # 1e6 t mm^2 = 1000 kg m^2
    assert b.cog.tolist() == pytest.approx([0, 0, 0.1])
    assert m.gravity.tolist() == pytest.approx([0, 0, -9.81])         # mm/ms^2 -> m/s^2
    t = m.mounts[0].type
    assert t.stiffness.tolist() == pytest.approx([1e6, 2e6, 3e6])     # kN/mm
    assert t.damping[0] == pytest.approx(1.0)                          # kN ms/mm = N s/m
    np.testing.assert_allclose(m.mounts[0].orientation.matrix[:, 0], [0, 1, 0], atol=1e-15)
    assert m.mounts[0].name == "mount1"
    init = m.settings["initial"]["b"]
    assert init["displacement"] == pytest.approx([1e-3, 0, 0, math.pi / 2, 0, 0])
    assert init["velocity"][0] == pytest.approx(2.0)                   # mm/ms
    f = m.excitations[0].function
    assert (f.amplitude, f.start, f.duration) == pytest.approx((9.81, 1e-3, 0.011))
    assert m.excitations[0].name == "excitation1"
    assert m.settings["time"] == pytest.approx({"end": 0.5, "step": 5e-4})


@pytest.mark.parametrize("name", ["prism", "two_mass", "powertrain", "inertia_block",
                                  "ground_shake", "packaged_item"])
@pytest.mark.parametrize("fmt", ["toml", "json"])
def test_dump_load_round_trip_is_exact(name, fmt):
    model = load_example(name)
    again = loads_model(dumps_model(model, fmt), fmt)
    a, b = assemble(model), assemble(again)
    for key in ("M", "K", "C", "H"):
        np.testing.assert_array_equal(getattr(a, key), getattr(b, key))
    assert [m.name for m in again.mounts] == [m.name for m in model.mounts]
    assert again.settings == model.settings
    assert (again.gravity is None) == (model.gravity is None)
    assert model.gravity is None or np.array_equal(again.gravity, model.gravity)
    t = np.linspace(0.0, 2.0, 1001)
    for x, y in zip(model.excitations, again.excitations, strict=True):
        assert (x.name, x.signal) == (y.name, y.signal)
        if not getattr(x.function, "steady_state", False):
            np.testing.assert_array_equal(x.value(t), y.value(t))
    assert dumps_model(again, fmt) == dumps_model(model, fmt)


def test_dump_model_to_file_and_load(tmp_path):
    model = load_example("powertrain")
    dump_model(model, tmp_path / "p.toml")
    dump_model(model, tmp_path / "p.json")
    json.loads((tmp_path / "p.json").read_text())
    for p in ("p.toml", "p.json"):
        np.testing.assert_array_equal(assemble(load_model(tmp_path / p)).K, assemble(model).K)


def test_dump_does_not_touch_the_model():
    model = load_example("inertia_block")
    before = model_to_dict(model)
    dumps_model(model)
    assert model_to_dict(model) == before


def test_table_file_relative_to_the_model(tmp_path):
    (tmp_path / "rec.csv").write_text("t_ms,a_mm_ms2\n0,0\n10,1000\n20,0\n")
    (tmp_path / "m.toml").write_text("""
[model]
units = { length = "mm", time = "ms" }
[[body]]
name = "b"
mass = 1.0
inertia = [1, 1, 1]
[[mount_type]]
name = "t"
stiffness = [1, 1, 1]
[[mount]]
type = "t"
body = "b"
[[excitation]]
kind = "acceleration"
target = "ground"
dof = "x"
function = { type = "table", file = "rec.csv" }
""")
    f = load_model(tmp_path / "m.toml").excitations[0].function
    assert f.times.tolist() == pytest.approx([0.0, 0.01, 0.02])
    assert f.value(0.005) == pytest.approx(5e5)      # 1000 mm/ms^2 = 1e6 m/s^2, halfway: 5e5


BASE = """\
[model]
name = "m"

[[body]]
name = "prism"
mass = 1000.0
inertia = [10.0, 20.0, 30.0]

[[mount_type]]
name = "spring"
stiffness = [1e4, 2e4, 3e4]

[[mount]]
name = "corner"
type = "spring"
body = "prism"
at = [1.0, 2.0, 0.0]
symmetry = "double"

[[excitation]]
name = "shock"
kind = "force"
target = "prism"
dof = "z"
function = { type = "half_sine", amplitude = 1.0, start = 0.0, duration = 0.01 }
"""


def test_base_is_valid():
    assert len(loads_model(BASE).mounts) == 4


@pytest.mark.parametrize("old, new, words", [
    ("mass = 1000.0", "mass = -1.0", ["body[1] ('prism')", "mass", "positive"]),
    ("mass = 1000.0", "mass = 0.0", ["body[1] ('prism')", "mass", "positive"]),
    ("mass = 1000.0", "mass = nan", ["body[1] ('prism')", "mass", "finite"]),
    ("mass = 1000.0", "mass = [1.0, 2.0]", ["body[1] ('prism')", "mass", "3 numbers"]),
    ("mass = 1000.0", "mass = \"heavy\"", ["body[1] ('prism')", "mass", "a number"]),
    ("inertia = [10.0, 20.0, 30.0]", "inertia = [10.0, 10.0, 30.0]", ["body[1] ('prism')", "triangle"]),
    ("inertia = [10.0, 20.0, 30.0]", "inertia_tensor = [[1, 2, 0], [2, 1, 0], [0, 0, 1]]",
     ["body[1] ('prism')", "positive definite"]),
    ("inertia = [10.0, 20.0, 30.0]", "inertia = [10.0, 20.0]", ["body[1] ('prism')", "inertia", "3 numbers"]),
    ("inertia = [10.0, 20.0, 30.0]", "", ["body[1] ('prism')", "inertia"]),
    ("stiffness = [1e4, 2e4, 3e4]", "stiffness = [-1e4, 2e4, 3e4]",
     ["mount_type[1] ('spring')", "stiffness", "negative"]),
    ("stiffness = [1e4, 2e4, 3e4]", "stifness = [1e4, 2e4, 3e4]",
     ["mount_type[1] ('spring')", "stifness", "did you mean 'stiffness'"]),
    ("at = [1.0, 2.0, 0.0]", "at = [1.0, 2.0]", ["mount[1] ('corner')", "at", "3 numbers"]),
    ("body = \"prism\"\nat", "body = \"prsm\"\nat", ["mount[1] ('corner')", "body", "did you mean 'prism'"]),
    ("type = \"spring\"", "type = \"sprung\"", ["mount[1] ('corner')", "type", "did you mean 'spring'"]),
    ("symmetry = \"double\"", "symmetry = \"quad\"", ["mount[1] ('corner')", "symmetry", "'double'"]),
    ("symmetry = \"double\"", "to = \"prism\"", ["mount[1] ('corner')", "itself"]),
    ("symmetry = \"double\"", "orientation = { matrix = [[1, 0, 0], [0, 1, 0.1], [0, 0, 1]] }",
     ["mount[1] ('corner')", "orientation", "orthogonal"]),
    ("symmetry = \"double\"", "orientation = { euler = [0, 0, 0], sequence = \"ZZY\" }",
     ["mount[1] ('corner')", "orientation", "sequence"]),
    ("symmetry = \"double\"", "orientation = { eulre = [0, 0, 0] }",
     ["mount[1] ('corner')", "orientation", "eulre", "did you mean 'euler'"]),
    ("symmetry = \"double\"", "frame = \"local\"", ["mount[1] ('corner')", "frame"]),
    ("name = \"m\"", "name = \"m\"\nunits = { length = \"furlong\" }", ["[model]", "length", "furlong"]),
    ("name = \"m\"", "name = \"m\"\nunits = { lenght = \"mm\" }", ["[model]", "did you mean 'length'"]),
    ("name = \"m\"", "name = \"m\"\ngravity = [0, -9.81]", ["[model]", "gravity", "3 numbers"]),
    ("[[mount_type]]", "[[mount_typ]]", ["mount_typ", "did you mean 'mount_type'"]),
    ("[[body]]", "[body]", ["body", "[[body]]"]),
    ("target = \"prism\"", "target = \"ground\"", ["excitation[1] ('shock')", "force", "ground"]),
    ("target = \"prism\"", "target = \"prisma\"",
     ["excitation[1] ('shock')", "target", "did you mean 'prism'"]),
    ("dof = \"z\"", "dof = \"up\"", ["excitation[1] ('shock')", "dof"]),
    ("dof = \"z\"", "dof = \"rz\"\nat = [1, 0, 0]", ["excitation[1] ('shock')", "at", "moment"]),
    ("duration = 0.01", "duration = -0.01", ["excitation[1] ('shock')", "half_sine", "duration"]),
    ("type = \"half_sine\"", "type = \"half-sine\"", ["excitation[1] ('shock')", "did you mean 'half_sine'"]),
    ("kind = \"force\"", "kind = \"forse\"", ["excitation[1] ('shock')", "kind", "'force'"]),
    ("name = \"m\"", "name = \"m\"\n[analysis]\nfrequency = { f1 = 1, f2 = 10, points = 1 }",
     ["[analysis]", "frequency", "points"]),
    ("name = \"m\"", "name = \"m\"\n[analysis]\ntime = { end = 1, step = 2 }",
     ["[analysis]", "time", "step"]),
    ("name = \"m\"", "name = \"m\"\n[analysis]\nfrequency = { f1 = 0, f2 = 10, spacing = \"log\" }",
     ["[analysis]", "frequency", "f1"]),
])
def test_bad_input_is_located(old, new, words):
    assert old in BASE
    with pytest.raises(ModelFileError) as info:
        loads_model(BASE.replace(old, new, 1), source="bad.toml")
    msg = str(info.value)
    assert msg.startswith("bad.toml") and msg.count("bad.toml") == 1, msg
    for w in words:
        assert w in msg, msg


def test_second_entry_is_counted_from_one():
    text = BASE + '\n[[mount]]\ntype = "spring"\nbody = "prism"\nto = "ghost"\n'
    with pytest.raises(ModelFileError, match=r"mount\[2\]: to: unknown body 'ghost'"):
        loads_model(text)


def test_duplicate_names_are_errors():
    with pytest.raises(ModelFileError, match="'corner' is used twice"):
        loads_model(BASE + '\n[[mount]]\nname = "corner"\ntype = "spring"\nbody = "prism"\n')
    with pytest.raises(ModelFileError, match=r"mount_type\[2\].*defined twice"):
        loads_model(BASE + '\n[[mount_type]]\nname = "spring"\nstiffness = [1, 1, 1]\n')


def test_toml_syntax_error_gives_the_line():
    with pytest.raises(ModelFileError, match=r"x\.toml: TOML syntax error.*line 3"):
        loads_model("[model]\nname = 'a'\nmass == 2\n", source="x.toml")


def test_json_is_accepted_and_its_syntax_errors_located():
    model = loads_model(json.dumps(model_to_dict(load_example("prism"))), "json")
    np.testing.assert_array_equal(assemble(model).K, assemble(load_example("prism")).K)
    with pytest.raises(ModelFileError, match="line 2"):
        loads_model('{"model":\n {,}}', "json")


def test_file_errors(tmp_path):
    with pytest.raises(ModelFileError, match="cannot read"):
        load_model(tmp_path / "none.toml")
    with pytest.raises(ModelFileError, match=r"\.yaml"):
        load_model(tmp_path / "m.yaml")
    bad = tmp_path / "m.toml"
    bad.write_text(BASE.replace("mass = 1000.0", "mass = -5.0"))
    with pytest.raises(ModelFileError, match=r"m\.toml: body\[1\] \('prism'\): mass"):
        load_model(bad)


def test_unknown_example_lists_the_names():
    with pytest.raises(ModelError, match="did you mean 'prism'"):
        example_path("prisma")
    assert example_path("prism.toml").name == "prism.toml"


def test_non_string_function_type_and_unit_are_located_errors(tmp_path):
    """Found in review: these crashed the loader with 'unhashable type: list'."""
    body = '[[body]]\nname = "b"\nmass = 1.0\ninertia = [1.0, 1.0, 1.0]\n'
    for extra, pattern in (('[model]\nunits = { length = ["mm"] }\n', r"units: length: unknown unit \['mm'\]"),
                           ('[[excitation]]\nkind = "force"\ntarget = "b"\ndof = "z"\nfunction = { type = [1] }\n',
                            r"excitation\[1\].*type: expected one of")):
        f = tmp_path / "m.toml"
        f.write_text(extra + body if extra.startswith("[model]") else body + extra)
        with pytest.raises(ModelFileError, match=pattern):
            load_model(f)
