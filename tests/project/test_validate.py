"""Shared validators (vibss/_validate.py) and the error contract: every deliberate raise is a
VibssError that names the argument, carries its data and pickles."""

from __future__ import annotations

import ast
import builtins
import inspect
import pickle
from pathlib import Path

import numpy as np
import pytest

import vibss
from vibss import Body, Model, Mount, MountType, Scope, errors
from vibss import _validate as v
from vibss.errors import ArgumentError, SignalError, VibssError

PACKAGE = Path(vibss.__file__).parent


# -- validators ----------------------------------------------------------------------------------

def test_vector_names_the_argument_and_shows_what_came() -> None:
    np.testing.assert_array_equal(v.vector((1, 2, 3), 3, "at"), [1.0, 2.0, 3.0])
    cases = [([1, 2], r"mount 'm': at: expected 3 numbers, got shape \(2,\) \(\[1, 2\]\)"),
             ([1, np.nan, 2], r"mount 'm': at: values must be finite, got \[1.0, nan, 2.0\]"),
             ("abc", r"mount 'm': at: expected 3 numbers, got 'abc'"),
             ([True, 1, 2], r"mount 'm': at: expected 3 numbers, got \[True, 1, 2\]")]
    for value, message in cases:
        with pytest.raises(ArgumentError, match=message) as err:
            v.vector(value, 3, "at", who="mount 'm'")
        assert err.value.argument == "at" and err.value.received is value


def test_array_shapes_with_free_lengths() -> None:
    assert v.array(np.ones((4, 3)), "points", (None, 3)).shape == (4, 3)
    with pytest.raises(ArgumentError, match=r"points: expected an array of numbers of shape \(n, 3\)"):
        v.array(np.ones((4, 2)), "points", (None, 3))
    assert np.isinf(v.array([np.inf], "x", finite=False)[0])


@pytest.mark.parametrize("value, kwargs, message", [
    (0.0, {"minimum": 0.0, "strict": True, "unit": "s"}, r"dt: expected a finite number > 0 \[s\], got 0.0"),
    (-1, {"minimum": 0.0}, r"dt: expected a finite number >= 0, got -1"),
    ("1e-3", {}, r"dt: expected a finite number, got '1e-3'"),
    (True, {}, r"dt: expected a finite number, got True"),
    (float("inf"), {}, r"dt: expected a finite number, got inf"),
    (-2.0, {"minimum": 0.0, "what": "a number of seconds", "must": "a positive time step"},
     r"dt: must be a positive time step, got -2.0"),
])
def test_number(value: object, kwargs: dict, message: str) -> None:
    with pytest.raises(ArgumentError, match=message) as err:
        v.number(value, "dt", **kwargs)
    assert err.value.argument == "dt" and err.value.received is value
    assert v.number(np.float32(0.5), "dt", minimum=0.0) == 0.5


def test_integer() -> None:
    assert v.integer(10.0, "points", minimum=2) == 10
    for bad in (1, 2.5, True, "3", None):
        with pytest.raises(ArgumentError, match=r"points: expected an integer >= 2, got"):
            v.integer(bad, "points", minimum=2)


def test_choice_lists_the_options_and_guesses() -> None:
    assert v.choice("modal", "method", ["auto", "modal"]) == "modal"
    f = lambda plant, s: s  # noqa: E731
    assert v.choice(f, "method", ["auto"], callable_ok=True) is f
    with pytest.raises(ArgumentError, match=r"method: unknown 'modall' \(did you mean 'modal'\?\); "
                                            r"expected one of \['auto', 'modal'\] or a callable") as err:
        v.choice("modall", "method", ["auto", "modal"], callable_ok=True)
    assert err.value.expected == ("auto", "modal")
    with pytest.raises(ArgumentError, match=r"spacing: expected 'log' or 'linear', got 'lin' "
                                            r"\(did you mean 'linear'\?\)"):
        v.choice("lin", "spacing", ("log", "linear"), expected="'log' or 'linear'")
    with pytest.raises(ArgumentError, match=r"method: unknown 3"):
        v.choice(3, "method", ["auto"])


def test_name_index_is_a_key_error_with_did_you_mean() -> None:
    assert v.name_index("b.z", ("b.x", "b.z"), "output") == 1
    with pytest.raises(SignalError, match=r"output: no output named 'b.zz' \(did you mean 'b.z'\?\); "
                                          r"the outputs are \['b.x', 'b.z'\]") as err:
        v.name_index("b.zz", ("b.x", "b.z"), "output")
    assert isinstance(err.value, KeyError) and isinstance(err.value, ValueError)
    assert str(err.value).startswith("output:")          # not KeyError's quoted repr


# -- the error classes -----------------------------------------------------------------------------

ERRORS = [c for _, c in inspect.getmembers(errors, inspect.isclass)
          if issubclass(c, VibssError) and c is not VibssError]


@pytest.mark.parametrize("cls", ERRORS, ids=lambda c: c.__name__)
def test_every_error_has_a_builtin_twin_and_pickles_with_its_data(cls: type) -> None:
    twins = [b for b in inspect.getmro(cls) if b.__module__ == "builtins" and b not in (Exception, BaseException, object)]
    assert twins, f"{cls.__name__} subclasses no built-in exception"
    err = cls(f"{cls.__name__}: x: bad", argument="x", received=np.array([1.0, 2.0]), expected=("a", "b"))
    back = pickle.loads(pickle.dumps(err))
    assert type(back) is cls and str(back) == str(err)
    assert back.argument == "x" and back.expected == ("a", "b")
    np.testing.assert_array_equal(back.received, [1.0, 2.0])


def test_unpicklable_data_is_kept_as_text() -> None:
    err = ArgumentError("inputs: bad", argument="inputs", received=lambda t: t)
    back = pickle.loads(pickle.dumps(err))
    assert "lambda" in back.received and str(back) == "inputs: bad"


def test_model_error_stays_a_value_error() -> None:
    assert issubclass(errors.ModelError, ValueError) and issubclass(errors.ModelFileError, ValueError)
    assert issubclass(errors.AnalysisError, RuntimeError)


# -- no deliberate raise escapes VibssError -------------------------------------------------------------

BUILTIN_ERRORS = {n for n, o in vars(builtins).items() if isinstance(o, type) and issubclass(o, BaseException)}


def _builtin_raises(root: Path = PACKAGE) -> list[str]:
    hits = []
    for path in sorted(root.rglob("*.py")):
        tree = ast.parse(path.read_text())
        # a module's __getattr__ must raise AttributeError: that is Python's attribute protocol
        protocol = {id(n) for f in ast.walk(tree) if isinstance(f, ast.FunctionDef) and f.name == "__getattr__"
                    for n in ast.walk(f) if isinstance(n, ast.Raise)}
        for node in ast.walk(tree):
            if not isinstance(node, ast.Raise) or node.exc is None or id(node) in protocol:
                continue
            exc = node.exc.func if isinstance(node.exc, ast.Call) else node.exc
            name = exc.id if isinstance(exc, ast.Name) else None
            if name in BUILTIN_ERRORS and name not in ("NotImplementedError", "SystemExit"):
                hits.append(f"{path.relative_to(root.parent)}:{node.lineno}: raise {name}")
    return hits


def test_no_deliberate_raise_of_a_builtin_exception() -> None:
    """Every ``raise`` in vibss raises a VibssError subclass (abstract methods and the CLI's
    SystemExit excepted), so ``except vibss.VibssError`` catches every refusal."""
    assert _builtin_raises() == []


def test_the_grep_finds_a_builtin_raise(tmp_path: Path) -> None:
    """The check above can fail: the same walk flags a planted ``raise ValueError(...)``."""
    pkg = tmp_path / "pkg"
    pkg.mkdir()
    (pkg / "m.py").write_text("def f():\n    raise ValueError('x')\n\ndef g():\n    raise KeyError\n\n"
                              "def h():\n    raise NotImplementedError\n\n"
                              "def __getattr__(name):\n    raise AttributeError(name)\n")
    assert _builtin_raises(pkg) == ["pkg/m.py:2: raise ValueError", "pkg/m.py:5: raise KeyError"]


# -- bad inputs at the public boundary ---------------------------------------------------------------

def _model() -> Model:
    t = MountType("t", [1e4, 1e4, 1e4], [10.0, 10.0, 10.0])
    return Model([Body("b", 1.0, [1e-2, 1e-2, 1e-2])], vibss.symmetric(Mount("m", t, "b", at=[0.1, 0.1, 0])))


BAD = [
    ("method", "modal", lambda m: vibss.frequency_response(m, ["b.fz"], ["b.z"], [1.0], method="modall")),
    ("quantity", "accelerance", lambda m: vibss.frequency_response(m, ["b.fz"], ["b.z"], [1.0],
                                                                   quantity="acceleranse")),
    ("method", "dense", lambda m: vibss.modes(m, method="dens")),
    ("n_modes", None, lambda m: vibss.modes(m, n_modes=0)),
    ("method", "prune", lambda m: vibss.reduce(m, Scope(["b.fz"], ["b.z"], 0, 10), method="prun")),
    ("residual", "static", lambda m: vibss.reduce(m, Scope(["b.fz"], ["b.z"], 0, 10), residual="statik")),
    ("dt", None, lambda m: vibss.simulate(m, inputs={"b.fz": np.sin}, t_end=1.0, dt=-1.0)),
    ("solver", "Radau", lambda m: vibss.simulate(m, inputs={"b.fz": np.sin}, t_end=1.0, dt=0.01,
                                                 method="ivp", solver="radau")),
    ("realization", "modal", lambda m: vibss.statespace(m, inputs=["b.fz"], outputs=["b.z"], realization="modl")),
    ("outputs", "b.z", lambda m: vibss.statespace(m, inputs=["b.fz"], outputs=["b.z"])["b.zz", "b.fz"]),
    ("outputs", None, lambda m: vibss.statespace(m, inputs=["b.fz"], outputs=["b.z"])[1.5, 0]),
    ("undamped", None, lambda m: vibss.damped_modes(m, vibss.modes(m, n_modes=2))),
    ("loads", None, lambda m: vibss.static(m, loads=[1.0, 2.0])),
    ("f2", None, lambda m: Scope(["b.fz"], ["b.z"], 10.0, 5.0)),
    ("output", "b.z", lambda m: vibss.frequency_response(m, ["b.fz"], ["b.z"], [1.0]).channel("b.zz")),
    ("inputs", "b.fz", lambda m: vibss.frequency_response(m, ["b.fq"], ["b.z"], [1.0])),
    ("outputs", "b.z", lambda m: vibss.simulate(m, inputs={"b.fz": np.sin}, outputs=["b.zz"], t_end=0.1,
                                                dt=0.01)),
]


@pytest.mark.parametrize("argument, guess, call", BAD, ids=[f"{a}-{i}" for i, (a, _, _) in enumerate(BAD)])
def test_bad_inputs_raise_vibss_errors_naming_the_argument(argument: str, guess: str | None, call) -> None:
    with pytest.raises(VibssError) as err:
        call(_model())
    assert err.value.argument == argument and argument in str(err.value)
    if guess is not None:
        assert f"did you mean {guess!r}" in str(err.value)
    back = pickle.loads(pickle.dumps(err.value))
    assert str(back) == str(err.value) and back.argument == argument


def test_report_section_lookup_guesses() -> None:
    from vibss import report

    rep = report.study(_model(), figures=False)
    with pytest.raises(SignalError, match=r"did you mean 'modes'") as err:
        rep.section("mode")
    assert isinstance(err.value, KeyError)
