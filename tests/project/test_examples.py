"""The documented examples, with their numbers pinned against closed forms.

Every number the docs quote from a computation is checked here: the quick start
(docs/getting-started.md, examples/quickstart.py) and reference case 1, the prism
(docs/analyses/modes.md, docs/index.md).
"""

from __future__ import annotations

import importlib.util

import numpy as np
import pytest

from cases import ROOT
import vibss
from vibss.io import load_example



def _quickstart():
    spec = importlib.util.spec_from_file_location("quickstart", ROOT / "examples" / "quickstart.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_quickstart_against_closed_forms(capsys):
    qs = _quickstart()
    modes, sag = qs.main()
    out = capsys.readouterr().out
    m, (ixx, iyy, izz) = qs.MASS, qs.INERTIA
    kx, ky, kz = qs.STIFFNESS
    x, y, _ = qs.CORNER
    w = {"x": np.sqrt(4 * kx / m), "y": np.sqrt(4 * ky / m), "z": np.sqrt(4 * kz / m),
         "rx": np.sqrt(4 * kz * y**2 / ixx), "ry": np.sqrt(4 * kz * x**2 / iyy),
         "rz": np.sqrt(4 * (kx * y**2 + ky * x**2) / izz)}
    expected = sorted((v / (2 * np.pi), d) for d, v in w.items())
    assert modes.directions == [d for _, d in expected]
    assert np.allclose(modes.frequency_hz, [f for f, _ in expected], rtol=1e-12)
    # the values quoted in docs/getting-started.md
    assert np.round(modes.frequency_hz, 3).tolist() == [6.366, 7.797, 10.066, 13.316, 14.235, 17.435]
    sag_z = sag.body("machine")[2]
    assert sag_z == pytest.approx(-m * 9.81 / (4 * kz), rel=1e-12)
    assert f"{1e3 * sag_z:.4f}" == "-2.4525"
    assert "-2.4525" in out and "10.0658" in out
    assert np.allclose(sag.mount_force[:, 2], -m * 9.81 / 4)   # each mount carries a quarter, into ground


def test_prism_example_is_reference_case_1():
    modes = vibss.modes(load_example("prism"))
    m, i = 1000.0, {"rx": 10.0, "ry": 20.0, "rz": 30.0}
    k = np.array([10e3, 20e3, 30e3])
    w = {"x": np.sqrt(4 * k[0] / m), "y": np.sqrt(4 * k[1] / m), "z": np.sqrt(4 * k[2] / m),
         "rx": np.sqrt(4 * k[2] * 2**2 / i["rx"]), "ry": np.sqrt(4 * k[2] * 1**2 / i["ry"]),
         "rz": np.sqrt(4 * (k[0] * 2**2 + k[1] * 1**2) / i["rz"])}
    for f, d in zip(modes.frequency_hz, modes.directions):
        assert f == pytest.approx(w[d] / (2 * np.pi), rel=1e-12)
    # as docs/index.md and docs/analyses/modes.md print them
    assert [f"{f:.2f}" for f in modes.frequency_hz] == ["1.01", "1.42", "1.74", "12.33", "14.24", "34.87"]
    assert [f"{c:.0f}" for c in modes.cpm] == ["60", "85", "105", "740", "854", "2092"]
    assert np.allclose(np.abs(modes.relative_shapes), np.eye(6)[:, [0, 1, 2, 4, 5, 3]], atol=1e-12)


def test_two_mass_example_is_reference_case_2():
    modes = vibss.modes(load_example("two_mass"))
    got = sorted(zip(np.round(modes.frequency_hz, 2), modes.directions))
    assert got == sorted([(0.48, "x"), (0.48, "y"), (0.68, "z"), (1.26, "x"), (1.26, "y"), (1.78, "z"),
                          (5.56, "rz"), (6.83, "ry"), (9.65, "rx"), (14.57, "rz"), (17.89, "ry"),
                          (25.26, "rx")])


def test_every_example_loads_and_has_modes():
    for name in vibss.io.example_names():
        modes = vibss.modes(load_example(name))
        assert np.all(np.isfinite(modes.frequency_hz))


def _blocks(doc: str, lang: str) -> list[str]:
    text = (ROOT / "docs" / doc).read_text(encoding="utf-8")
    return [b.split("```", 1)[0] for b in text.split(f"```{lang}\n")[1:]]


@pytest.mark.slow
def test_getting_started_code_runs_and_matches_quickstart(tmp_path, monkeypatch, capsys):
    import matplotlib

    matplotlib.use("Agg")
    monkeypatch.chdir(tmp_path)
    scope: dict = {}
    for block in _blocks("getting-started.md", "python"):
        exec(compile(block, "getting-started.md", "exec"), scope)
    assert (tmp_path / "mode5.gif").exists() and (tmp_path / "modes.png").exists()
    (toml,) = _blocks("getting-started.md", "toml")
    from_file = vibss.io.loads_model(toml)
    qs = _quickstart().build_model()
    for model in (scope["model"], from_file):
        assert np.allclose(vibss.modes(model).frequency_hz, vibss.modes(qs).frequency_hz, rtol=1e-12)
        assert np.allclose(vibss.static(model).q, vibss.static(qs).q, rtol=1e-12, atol=1e-15)
