"""One spelling per public name, American as SciPy and python-control spell them (issue 28 item 8):
every old (British, or colliding) name still works for one release, warns with a
DeprecationWarning naming its replacement, and is the new object."""

from __future__ import annotations

import importlib

import numpy as np
import pytest

import vibss

ALIASES = [  # (module, old name, new name)
    ("vibss", "study", "grid_study"),
    ("vibss.design", "optimise", "optimize"),
    ("vibss.design", "Optimisation", "Optimization"),
    ("vibss.design", "study", "grid_study"),
    ("vibss.design.optimize", "optimise", "optimize"),
    ("vibss.design.optimize", "Optimisation", "Optimization"),
    ("vibss.design.reliability", "reliable_optimise", "reliable_optimize"),
    ("vibss.plotting.design", "plot_optimisation", "plot_optimization"),
    ("vibss.plotting.layout", "AXIS_COLOURS", "AXIS_COLORS"),
    ("vibss.results", "Table", "TextTable"),
]


@pytest.mark.parametrize("module,old,new", ALIASES, ids=[f"{m}.{o}" for m, o, _ in ALIASES])
def test_old_module_names_warn_and_are_the_new_objects(module: str, old: str, new: str) -> None:
    mod = importlib.import_module(module)
    with pytest.warns(DeprecationWarning, match=new):
        value = getattr(mod, old)
    assert value is getattr(mod, new)


def test_plot_design_axes_moved_to_the_analysis() -> None:
    """The figure no longer computes: the old plotting name forwards to vibss.design's."""
    import vibss.plotting.design as figures

    with pytest.warns(DeprecationWarning, match="vibss.design.plot_design_axes"):
        old = figures.plot_design_axes
    assert old is vibss.design.plot_design_axes


def test_old_attributes_warn() -> None:
    m = vibss.load_example("powertrain")
    ea = vibss.design.elastic_axes(m)
    with pytest.warns(DeprecationWarning, match="center_global"):
        np.testing.assert_array_equal(ea.centre_global, ea.center_global)
    with pytest.warns(DeprecationWarning, match="ElasticAxes.center"):
        np.testing.assert_array_equal(ea.centre, ea.center)
    s = vibss.design.sensitivity(m, ["engine.k3"])
    with pytest.warns(DeprecationWarning, match="normalized"):
        np.testing.assert_array_equal(s.normalised("purity"), s.normalized("purity"))


def test_old_keyword_and_option_warn() -> None:
    from vibss.cli import main
    from vibss.design.filespec import run_design

    m = vibss.load_example("powertrain")
    with pytest.warns(DeprecationWarning, match="optimize_layout"):
        run = run_design(m, optimise_layout=False)
    with pytest.warns(DeprecationWarning, match="optimization"):
        assert run.optimisation is run.optimization is None
    with pytest.raises(TypeError, match="not both"), pytest.warns(DeprecationWarning):
        run_design(m, optimise_layout=False, optimize_layout=False)
    with pytest.warns(DeprecationWarning, match="--optimize"):
        assert main(["design", "--example", "powertrain", "--optimise", "--format", "json"]) == 0


def test_center_spellings_and_their_old_names() -> None:
    model = vibss.load_example("powertrain")
    with pytest.warns(DeprecationWarning, match="Model.centre_of_gravity is deprecated"):
        old = model.centre_of_gravity
    np.testing.assert_array_equal(old, model.center_of_gravity)
    r = vibss.static(model)
    name = model.bodies[0].name
    with pytest.warns(DeprecationWarning, match="StaticResult.centre_of_rotation is deprecated"):
        got = r.centre_of_rotation(name)
    want = r.center_of_rotation(name)
    assert (got is None and want is None) or np.array_equal(got, want)
    import vibss.statics as st
    with pytest.warns(DeprecationWarning, match="vibss.statics.centre_of_rotation"):
        assert st.centre_of_rotation is st.center_of_rotation
