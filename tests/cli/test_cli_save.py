"""``--save FILE``: the CLI's results as test data (CSV or UFF by the suffix), equal to the API's."""

from __future__ import annotations

import numpy as np
import pytest

import vibss
from vibss.cli import main
from vibss.io import read_csv


def test_frf_saved_as_csv_equals_the_api(tmp_path, capsys) -> None:
    path = tmp_path / "frf.csv"
    assert main(["frf", "--example", "prism", "--input", "prism.fz", "--output", "prism.z", "--f1", "1",
                 "--f2", "50", "--points", "7", "--spacing", "linear", "--no-refine", "--save", str(path)]) == 0
    back = read_csv(path)
    api = vibss.frequency_response(vibss.load_example("prism"), ["prism.fz"], ["prism.z"],
                                   np.linspace(1.0, 50.0, 7))
    np.testing.assert_array_equal(back.frequency_hz, api.frequency_hz)
    np.testing.assert_allclose(back.response, api.response, rtol=1e-13)
    assert "CSV written to" in capsys.readouterr().err


def test_modes_saved_as_uff_and_bad_suffix_refused_before_work(tmp_path, capsys) -> None:
    pytest.importorskip("pyuff")
    from vibss.io import read_uff_modes

    path = tmp_path / "m.uff"
    assert main(["modes", "--example", "two_mass", "--save", str(path)]) == 0
    back = read_uff_modes(path)
    np.testing.assert_allclose(back.frequency_hz, vibss.modes(vibss.load_example("two_mass")).frequency_hz, rtol=1e-5)
    capsys.readouterr()
    assert main(["modes", "--example", "two_mass", "--save", str(tmp_path / "m.csv")]) == 2
    out = capsys.readouterr()
    assert out.out == "" and "vibss: error: --save" in out.err and ".uff, .unv" in out.err
