"""Validation of the Python API: every bad input is a ModelError naming entity and field."""

from __future__ import annotations

import numpy as np
import pytest

from vibss import Body, ControlPoint, Load, Model, ModelError, Mount, MountType, Orientation, symmetric

T = MountType("t", [1.0, 1.0, 1.0])


@pytest.mark.parametrize("kwargs,pattern", [
    (dict(mass=-1.0), r"body 'b': mass must be positive"),
    (dict(mass=0.0), r"body 'b': mass must be positive"),
    (dict(mass=float("nan")), r"body 'b': mass must be finite"),
    (dict(mass=[1.0, 2.0]), r"body 'b': mass: expected a number or 3 numbers"),
    (dict(inertia=[1.0, -2.0, 3.0]), r"body 'b': inertia is not positive definite"),
    (dict(inertia=[1.0, 1.0, 5.0]), r"body 'b': .*triangle inequality"),
    (dict(inertia=[[1, 0.5, 0], [0, 1, 0], [0, 0, 1]]), r"body 'b': inertia tensor must be symmetric"),
    (dict(inertia=[[1, 2, 0], [2, 1, 0], [0, 0, 1]]), r"body 'b': inertia is not positive definite"),
    (dict(inertia=[1.0, 1.0]), r"body 'b': inertia: expected 3 principal moments or a 3x3"),
    (dict(cog=[0.0, 1.0]), r"body 'b': cog: expected 3 numbers"),
    (dict(cog=[0.0, np.inf, 0.0]), r"body 'b': cog: values must be finite"),
])
def test_bad_body(kwargs, pattern):
    args = dict(name="b", mass=1.0, inertia=[1.0, 1.0, 1.0]) | kwargs
    with pytest.raises(ModelError, match=pattern):
        Body(**args)


@pytest.mark.parametrize("kwargs,pattern", [
    (dict(stiffness=[1.0, -1.0, 1.0]), r"mount type 'rubber': stiffness must not be negative"),
    (dict(stiffness=[1.0, 1.0]), r"mount type 'rubber': stiffness: expected 3 numbers"),
    (dict(stiffness=[1.0, 1.0, 1.0], damping=[0.0, -2.0, 0.0]), r"damping must not be negative"),
    (dict(stiffness=[1.0, np.nan, 1.0]), r"stiffness: values must be finite"),
    (dict(stiffness=[1.0, 1.0, 1.0], loss_factor=-0.1), r"loss_factor must be finite and not negative"),
])
def test_bad_mount_type(kwargs, pattern):
    with pytest.raises(ModelError, match=pattern):
        MountType("rubber", **kwargs)


def test_bad_mounts():
    with pytest.raises(ModelError, match=r"mount 'm': joins body 'b' to itself"):
        Mount("m", T, "b", to="b")
    with pytest.raises(ModelError, match=r"mount 'm': .*not orthogonal"):
        Mount("m", T, "b", orientation=[[1, 0.1, 0], [0, 1, 0], [0, 0, 1]])
    with pytest.raises(ModelError, match=r"mount 'm': .*left-handed"):
        Mount("m", T, "b", orientation=np.diag([1.0, 1.0, -1.0]))
    with pytest.raises(ModelError, match=r"mount 'm': at: expected 3 numbers"):
        Mount("m", T, "b", at=[1, 2])
    with pytest.raises(ModelError, match=r"unknown symmetry 'diagonal'"):
        symmetric(Mount("m", T, "b"), "diagonal")
    with pytest.raises(ModelError, match=r"frame must be 'body' or 'global'"):
        Mount("m", T, "b", frame="local")


def test_model_cross_references():
    b = Body("engine", 1.0, [1, 1, 1])
    with pytest.raises(ModelError, match=r"mount 'm': to: unknown body 'engin'.*did you mean 'engine'"):
        Model([b, Body("x", 1.0, [1, 1, 1])], [Mount("m", T, "x", to="engin")])
    with pytest.raises(ModelError, match=r"mount 'm': body: unknown body 'motor'"):
        Model([b], [Mount("m", T, "motor")])
    with pytest.raises(ModelError, match=r"body name 'engine' is used twice"):
        Model([b, b])
    with pytest.raises(ModelError, match=r"control point 'cp': unknown body"):
        Model([b], control_points=[ControlPoint("cp", "engin", [0, 0, 0])])
    with pytest.raises(ModelError, match=r"load .*unknown body"):
        Model([b], loads=[Load("l", "nobody", force=[1, 0, 0])])
    with pytest.raises(ModelError, match=r"needs at least one body"):
        Model([])


def test_euler_sequence_errors():
    with pytest.raises(ModelError, match="sequence"):
        Orientation.from_euler([0, 0, 0], sequence="ZYx")


def test_inputs_not_mutated():
    inertia = [[2.0, 0.1, 0.0], [0.1, 3.0, 0.0], [0.0, 0.0, 4.0]]
    at = [0.1, 0.2, 0.3]
    b = Body("b", 1.0, inertia)
    m = Mount("m", T, "b", at=at)
    assert inertia == [[2.0, 0.1, 0.0], [0.1, 3.0, 0.0], [0.0, 0.0, 4.0]] and at == [0.1, 0.2, 0.3]
    with pytest.raises(ValueError):
        m.at[0] = 5.0          # frozen arrays
    with pytest.raises(AttributeError):
        b.mass = 3.0           # frozen dataclass


def test_symmetric_names_and_points():
    ms = symmetric(Mount("front", T, "b", at=[1.0, 2.0, 3.0]), "double")
    assert [m.name for m in ms] == ["front", "front.xz", "front.yz", "front.xz.yz"]
    np.testing.assert_array_equal([m.at for m in ms], [[1, 2, 3], [1, -2, 3], [-1, 2, 3], [-1, -2, 3]])


def test_mirrored_orientation_mirrors_stiffness():
    t = MountType("t", [1.0, 2.0, 5.0])
    o = Orientation.from_euler([30, 20, 10], degrees=True)
    m = Mount("m", t, "b", orientation=o).mirrored(["xz"])
    s = np.diag([1.0, -1.0, 1.0])
    k = o.matrix @ np.diag(t.stiffness) @ o.matrix.T
    km = m.orientation.matrix @ np.diag(t.stiffness) @ m.orientation.matrix.T
    np.testing.assert_allclose(km, s @ k @ s, atol=1e-14)
    assert np.linalg.det(m.orientation.matrix) == pytest.approx(1.0)


# --- defects found in review: each reproduced first, then fixed -----------------------------------

@pytest.mark.parametrize("bad", ["5", True, None, [True, False, True]])
def test_strings_and_bools_are_not_numbers(bad):
    with pytest.raises(ModelError, match=r"body 'b': mass: expected a number"):
        Body("b", bad, [1.0, 1.0, 1.0])
    with pytest.raises(ModelError, match=r"mount type 't': stiffness: expected 3 numbers"):
        MountType("t", [bad, 1.0, 1.0] if not isinstance(bad, list) else bad)


def test_control_point_named_like_a_body_is_refused():
    b = Body("b", 100.0, [10, 20, 25])
    with pytest.raises(ModelError, match=r"control point 'b': the name is taken"):
        Model([b], control_points=[ControlPoint("b", "b", [1.0, 0, 0])])


@pytest.mark.parametrize("call,pattern", [
    (lambda b: Model(None), r"bodies: expected a sequence of Body"),
    (lambda b: Model(b), r"bodies: expected a sequence of Body"),
    (lambda b: Model([b], settings=[1]), r"settings: expected a mapping"),
    (lambda b: Model([b], excitations=5), r"excitations: expected a sequence"),
    (lambda b: Model([b], control_points=[ControlPoint("p", ["b"], [0, 0, 0])]), r"body must be a body name"),
    (lambda b: Model([b], loads=[Load("l", body=["b"])]), r"body must be a body name"),
    (lambda b: symmetric(Mount("m", T, "b"), ["xz"]), r"unknown symmetry"),
])
def test_malformed_arguments_are_model_errors(call, pattern):
    with pytest.raises(ModelError, match=pattern):
        call(Body("b", 1.0, [1, 1, 1]))


def test_settings_are_not_shared_with_the_caller():
    given = {"frequency": {"f1": 1.0}}
    m = Model([Body("b", 1.0, [1, 1, 1])], settings=given)
    m.settings["frequency"]["f1"] = 99.0
    assert given == {"frequency": {"f1": 1.0}}


def test_transformed_refuses_to_leave_excitations_unrotated():
    from vibss.model.excitation import Excitation, Step

    e = Excitation("e", "force", "b", Step(1.0), direction=[1, 0, 0])
    m = Model([Body("b", 1.0, [1, 1, 1])], excitations=[e])
    with pytest.raises(ModelError, match="not rotated"):
        m.transformed(Orientation.from_euler([90, 0, 0], degrees=True).matrix)
    assert m.transformed(offset=[1.0, 0, 0]).excitations == (e,)      # a pure shift is fine


def test_overflowing_mount_is_named():
    """A point 1e200 m away is refused where it is given (the range files and API share); the
    assembly's own overflow check, behind it, still names a mount whose products overflow."""
    from vibss import assemble

    with pytest.raises(ModelError, match=r"mount 'far': at: 1e\+200 m is outside .* \(0 \.\. 100000 m\)"):
        Mount("far", MountType("t", [1e4] * 3), "b", at=[1e200, 1e200, 0])
    m = Model([Body("b", 1.0, [1, 1, 1])], [Mount("hard", MountType("t", [1e20] * 3, [1e16] * 3), "b", at=[1e5, 1e5, 0])])
    a = assemble(m)                                   # the largest plausible values stay finite
    assert np.all(np.isfinite(a.dense("K"))) and np.all(np.isfinite(a.dense("C")))


@pytest.mark.parametrize("make, match", [
    (lambda t: Model([Body("e:1", 1.0, [1, 1, 1])], [Mount("g", t, "e:1")]), "contains ':'"),
    (lambda t: Model([Body("mount", 1.0, [1, 1, 1])], [Mount("g", t, "mount")]), "'mount' is reserved"),
    (lambda t: Model([Body("a.into", 1.0, [1, 1, 1])], [Mount("g", t, "a.into")]), "both a force input"),
    (lambda t: Model([Body("a", 1.0, [1, 1, 1])], [Mount("g", t, "a")], [ControlPoint("a.into", "a", [0, 0, 1])]),
     "both a force input"),
    (lambda t: Model([Body("a", 1.0, [1, 1, 1])], [Mount("g:1", t, "a")]), "contains ':'"),
])
def test_names_that_would_make_signals_ambiguous_are_refused(make, match):
    """Found in review: ':' collides with python-control's spelling, 'mount' bodies and '<x>.into'
    points made signals unreachable or gave an input and an output the same name."""
    with pytest.raises(ModelError, match=match):
        make(MountType("t", [1e4, 1e4, 1e4]))


def _load_fields(load):
    return (load.name, load.body, load.force.tolist(), load.moment.tolist(),
            None if load.at is None else load.at.tolist(), load.frame, load.case)


def test_load_takes_its_name_first_and_the_old_order_warns():
    """Issue 16: Load(name, body, ...) as Body and Mount; the old Load(body, force, ..., name=...) gives
    the same load with a DeprecationWarning that spells the new call."""
    import warnings

    new = Load("pump", "frame", [0.0, 0.0, -120.0], [1.0, 0.0, 0.0], [0.1, 0.0, 0.0], "global", "run")
    assert _load_fields(new) == ("pump", "frame", [0.0, 0.0, -120.0], [1.0, 0.0, 0.0], [0.1, 0.0, 0.0], "global", "run")
    with warnings.catch_warnings():
        warnings.simplefilter("error")                                   # the new spellings never warn
        assert _load_fields(Load("pump", body="frame", force=[0, 0, -120.0], moment=[1, 0, 0], at=[0.1, 0, 0],
                                 frame="global", case="run")) == _load_fields(new)
        assert _load_fields(Load(body="frame", name="pump", force=[0, 0, -120.0], moment=[1, 0, 0],
                                 at=[0.1, 0, 0], frame="global", case="run")) == _load_fields(new)
    olds = [lambda: Load("frame", [0, 0, -120.0], [1, 0, 0], [0.1, 0, 0], "global", "pump", "run"),
            lambda: Load("frame", force=[0, 0, -120.0], moment=[1, 0, 0], at=[0.1, 0, 0], frame="global",
                         name="pump", case="run")]
    for make in olds:
        with pytest.warns(DeprecationWarning, match=r"name comes first.*Load\('pump', 'frame', force=\.\.\.\)"):
            assert _load_fields(make()) == _load_fields(new)
    with pytest.warns(DeprecationWarning):
        assert Load("frame").body == "frame" and Load("frame").name == ""  # one positional: the body
    with pytest.raises(ModelError, match="body: missing"):
        Load(name="pump")
    with pytest.raises(ModelError, match="name given twice"):
        Load("pump", "frame", name="other")
    with pytest.raises(ModelError, match="unknown argument"):
        Load("pump", "frame", forces=[0, 0, 1])


def test_files_read_loads_without_a_warning():
    """The file reader builds loads itself: a model file with [[load]] never shows the deprecation."""
    import warnings

    import vibss

    text = ('[[body]]\nname = "b"\nmass = 1.0\ninertia = [1, 1, 1]\n[[mount_type]]\nname = "t"\n'
            'stiffness = [1e4, 1e4, 1e4]\n[[mount]]\nname = "m"\ntype = "t"\nbody = "b"\n'
            '[[load]]\nname = "w"\nbody = "b"\nforce = [0, 0, -10]\n')
    with warnings.catch_warnings():
        warnings.simplefilter("error", DeprecationWarning)
        (load,) = vibss.loads_model(text).loads
    assert _load_fields(load)[:3] == ("w", "b", [0.0, 0.0, -10.0])


def test_table_takes_the_file_spelling_and_the_old_one():
    """Table(time=, value=) as in files; times=/values= (and positions) give the same table; the file
    reader gives it too."""
    from vibss import Table

    t, v = [0.0, 0.5, 2.0], [0.0, 4.0, 1.0]
    tables = [Table(time=t, value=v), Table(times=t, values=v), Table(t, v), Table(t, values=v)]
    probe = np.linspace(-1.0, 3.0, 17)
    expected = np.interp(probe, t, v, left=0.0, right=0.0)              # linear interpolation, zero outside
    for tab in tables:
        assert tab.times.tolist() == t and tab.values.tolist() == v
        assert np.allclose(tab.value(probe), expected)
    from vibss.model.excitation import function_from_dict

    assert function_from_dict({"type": "table", "time": t, "value": v}).values.tolist() == v
    with pytest.raises(ModelError, match="time: given twice"):
        Table(time=t, times=t, value=v)
    with pytest.raises(ModelError, match="value: missing"):
        Table(time=t)


def test_model_shows_its_bodies_and_mounts_in_a_notebook() -> None:
    """Issue 33 item 9: Model had no _repr_html_."""
    import re

    import vibss

    m = vibss.load_example("powertrain")
    page = m._repr_html_()
    assert page.count("<table>") == 2
    rows = re.findall(r"<tr><td>([^<]*)</td>", page)
    assert rows == [b.name for b in m.bodies] + [mt.name for mt in m.mounts]
    assert f"total mass {m.total_mass:.6g} kg" in page and "&#x27;" in page     # the name's quotes escaped
