"""Start-up: ``import vibss`` and the command line load python-control, matplotlib, pandas and the
heavy SciPy submodules only when an analysis needs them; every public name still resolves; the
command line's written-out choices match the library's registries."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

HEAVY = ("control", "matplotlib", "scipy.signal", "pandas", "scipy.stats", "scipy.optimize", "slycot")


def _loaded(code: str) -> list[str]:
    """Heavy modules in sys.modules after running ``code`` in a fresh interpreter."""
    probe = code + f"\nimport sys, json\nprint(json.dumps([m for m in {HEAVY!r} if m in sys.modules]))"
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def test_import_vibss_is_light():
    assert _loaded("import vibss") == []


def test_help_does_not_even_load_numpy():
    code = ("import sys\nfrom vibss.cli import main\ntry:\n    main(['--help'])\nexcept SystemExit:\n    pass\n"
            "assert 'numpy' not in sys.modules, 'numpy loaded by --help'")
    assert _loaded(code) == []


def test_modes_command_loads_no_control_or_plotting():
    code = "from vibss.cli import main\nassert main(['modes', '--example', 'prism']) == 0"
    assert _loaded(code) == []


def test_every_public_name_resolves():
    import vibss

    for name in vibss.__all__:
        assert getattr(vibss, name) is not None, name
    assert set(vibss.__all__) <= set(dir(vibss))
    with pytest.raises(AttributeError, match="no attribute 'nope'"):
        vibss.nope  # noqa: B018


def test_command_line_choices_match_the_library():
    from vibss.commands import study, time
    from vibss.design.grid import ANALYSES
    from vibss.time.api import METHODS

    assert sorted(study.ANALYSES) == sorted(ANALYSES)
    assert sorted(time.METHODS) == sorted(METHODS)


def test_frf_and_time_commands_load_no_control_or_plotting():
    code = ("from vibss.cli import main\n"
            "assert main(['frf', '--example', 'prism', '--input', 'prism.fz', '--output', 'prism.z']) == 0\n"
            "assert main(['time', '--example', 'powertrain']) == 0")
    assert _loaded(code) == []


def test_subpackages_resolve_as_attributes():
    """``vibss.io.x``, ``vibss.linear.x`` ... work without importing the subpackage first (notebooks
    and scripts written before the imports went lazy rely on it)."""
    code = ("import vibss\nassert vibss.io.modelfile.example_names()\nassert vibss.linear.plant.plant.Plant\n"
            "assert vibss.plotting.plot_modes")
    assert "matplotlib" in _loaded(code)


def test_time_functions_are_public():
    import vibss
    from vibss.model import timefunctions

    for name in ("HalfSine", "Haversine", "SineSweep", "Table", "Step", "Sine", "TimeFunction"):
        assert getattr(vibss, name) is getattr(timefunctions, name) and name in vibss.__all__


def test_frf_no_refine_keeps_exactly_the_base_points(capsys):
    from vibss.cli import main

    args = ["frf", "--example", "prism", "--input", "prism.fz", "--output", "prism.z", "--points", "5",
            "--format", "json"]
    assert main(args + ["--no-refine"]) == 0
    assert len(json.loads(capsys.readouterr().out)["frequency_hz"]) == 5
    assert main(args) == 0
    assert len(json.loads(capsys.readouterr().out)["frequency_hz"]) > 5      # refined at the resonances
