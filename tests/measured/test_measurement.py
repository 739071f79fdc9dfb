"""Measured responses: FrequencyResponse.from_measurement, and the readers that return one."""

from __future__ import annotations

import numpy as np
import pytest

import vibss
from vibss import FrequencyResponse
from vibss.errors import ArgumentError
from vibss.frequency.result import MEASURED_NOTE
from vibss.io import read_csv, write_csv


def _sdof(f: np.ndarray) -> np.ndarray:
    """Receptance of 2 kg on 1e4 N/m with 20 N s/m, in closed form [m/N]."""
    w = 2 * np.pi * f
    return 1.0 / (1e4 - 2.0 * w**2 + 20j * w)


def test_from_measurement_keeps_the_data_and_says_it_is_measured():
    f = np.geomspace(1.0, 100.0, 7)
    h = _sdof(f)
    mine = h.copy()
    r = FrequencyResponse.from_measurement(f, h, inputs=["hammer.fz"], outputs=["table.z"], units="m/N")
    assert r.method == "measured" and r.note.startswith(MEASURED_NOTE)
    assert r.response.shape == (1, 1, 7) and np.array_equal(r.response[0, 0], h)
    assert np.array_equal(h, mine) and r.natural_hz.size == 0
    assert np.array_equal(r["table.z", "hammer.fz"], h)
    assert r.channel_unit("table.z") == "m/N"


def test_from_measurement_with_input_units_names_the_channel_unit():
    f = np.array([1.0, 2.0, 3.0])
    h = np.ones((2, 1, 3), dtype=complex)
    r = FrequencyResponse.from_measurement(f, h, ["f"], ["a", "b"], ["m", "m/s^2"], input_units=["N"])
    assert r.channel_units == (("m/N",), ("(m/s^2)/N",))


@pytest.mark.parametrize("kwargs,field", [
    (dict(frequencies=[2.0, 1.0], response=[1, 2]), "frequencies"),
    (dict(frequencies=[-1.0, 1.0], response=[1, 2]), "frequencies"),
    (dict(frequencies=[1.0, 2.0], response=[1, 2, 3]), "response"),
    (dict(frequencies=[1.0, 2.0], response=[1, np.nan]), "response"),
    (dict(frequencies=[1.0, 2.0], response=[1, 2], outputs=["a", "b"]), "outputs"),
    (dict(frequencies=[1.0, 2.0], response=[[1, 2], [3, 4]], outputs=["a", "a"]), "outputs"),
    (dict(frequencies=[1.0, 2.0], response=[1, 2], inputs="f"), "inputs"),
    (dict(frequencies=[1.0, 2.0], response=[1, 2], units=["m", "m"]), "units"),
    (dict(frequencies=[1.0, 2.0], response=[1, 2], input_units=["N", "N"]), "input_units"),
])
def test_from_measurement_refuses_bad_fields_by_name(kwargs, field):
    with pytest.raises(ArgumentError, match=f"from_measurement: {field}") as err:
        FrequencyResponse.from_measurement(**kwargs)
    assert err.value.argument == field


def test_the_csv_reader_returns_a_measured_response(tmp_path):
    f = np.geomspace(1.0, 100.0, 9)
    m = vibss.Model([vibss.Body("b", 2.0, [1, 1, 1])],
                    [vibss.Mount("m", vibss.MountType("t", [1e4] * 3, [20.0] * 3), "b")])
    computed = vibss.frequency_response(m, ["b.fz"], ["b.z"], frequencies=f)
    back = read_csv(write_csv(computed, tmp_path / "frf.csv"))
    assert back.method == "measured" and back.note == f"{MEASURED_NOTE}; read from frf.csv"
    assert np.array_equal(back.response, computed.response)
    np.testing.assert_allclose(back.response[0, 0], _sdof(f), rtol=1e-12)


def test_the_uff_reader_returns_a_measured_response(tmp_path):
    pytest.importorskip("pyuff")
    from vibss.io import read_uff, write_uff

    f = np.geomspace(1.0, 100.0, 9)
    r = FrequencyResponse.from_measurement(f, _sdof(f), ["hammer.fz"], ["table.z"], "m/N")
    back = read_uff(write_uff(r, tmp_path / "m.uff"))
    assert back.method == "measured" and back.note.startswith(MEASURED_NOTE)
    assert back.outputs == ("table.z",) and back.inputs == ("hammer.fz",)
    assert np.array_equal(back.response, r.response)
