"""``vibss modes FILE --energy strain`` and the report's modes section with its strain-energy table."""

from __future__ import annotations

import numpy as np

import vibss
from vibss.cli import main
from vibss.report.sections.modes import _modes_section

EXAMPLE = str(vibss.load_example.__globals__["__file__"]).rsplit("/", 2)[0] + "/examples/powertrain.toml"


def test_modes_energy_option_prints_the_mounts_shares(capsys):
    assert main(["modes", EXAMPLE, "--energy", "strain"]) == 0
    out = capsys.readouterr().out
    model = vibss.load_example("powertrain")
    e = vibss.energy_distribution(model, "strain")
    first = out.split("Modal strain energy per mount [%]")[1].splitlines()[3].split()
    assert first[2] == e.dominant[0]
    assert [float(v) for v in first[3:]] == list(np.round(100 * e.fractions[0], 1))
    assert "engine.r1" not in out                # a 3-DOF mount's rotations hold nothing: no column


def test_report_modes_section_shows_strain_beside_kinetic():
    model = vibss.load_example("powertrain")
    results: dict = {}
    sec = _modes_section(model, False, results)
    titles = [t.title for t in sec.tables]
    assert "Modal kinetic-energy distribution [%]" in titles and "Modal strain energy per mount [%]" in titles
    assert np.allclose(results["strain energy"].fractions.sum(axis=1), 1.0)
