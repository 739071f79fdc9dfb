"""CSV out and in: FRFs, time records and PSDs with exact doubles and units in the header."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

import vibss
from vibss.errors import ModelError, ModelFileError
from vibss.io import read_csv, write_csv


def model() -> vibss.Model:
    t = vibss.MountType("t", [1e4, 2e4, 3e4], [10.0, 20.0, 30.0])
    return vibss.Model([vibss.Body("b", 5.0, [0.1, 0.2, 0.3])], [vibss.Mount("m", t, "b", at=[0.1, 0.0, -0.1])])


def test_frf_round_trip_is_exact_and_pandas_reads_it(tmp_path) -> None:
    f = np.geomspace(1.0, 200.0, 41)
    t = vibss.MountType("t", [1e4, 2e4, 3e4], [10.0, 20.0, 30.0])
    sdof = vibss.Model([vibss.Body("b", 5.0, [0.1, 0.2, 0.3])], [vibss.Mount("m", t, "b")])  # z decoupled
    r = vibss.frequency_response(sdof, ["b.fz", "ground.z.acc"], ["b.z", "mount.m.fz"], f)
    path = write_csv(r, tmp_path / "frf.csv")
    back = read_csv(path)
    assert back.outputs == r.outputs and back.inputs == r.inputs
    np.testing.assert_array_equal(back.response, r.response)                  # 17 digits: same doubles
    np.testing.assert_array_equal(back.frequency_hz, f)
    assert back.channel_unit("b.z", "b.fz") == r.channel_unit("b.z", "b.fz") == "m/N"
    assert vibss.io.frac(back, r)["b.z/b.fz"] == pytest.approx(1.0, abs=1e-14)
    df = pd.read_csv(path, comment="#")
    assert df.columns[1] == "b.z/b.fz re [m/N]"
    # the independent check: a single-DOF z receptance 1 / (k - m w^2 + i c w) at the mount's axis
    w = 2 * np.pi * f
    h = df["b.z/b.fz re [m/N]"].to_numpy() + 1j * df["b.z/b.fz im [m/N]"].to_numpy()
    np.testing.assert_allclose(h, 1 / (3e4 - 5.0 * w ** 2 + 30j * w), rtol=1e-10)


def test_time_and_psd_files(tmp_path) -> None:
    t = vibss.simulate(model(), inputs={"b.fz": lambda x: np.sin(20 * x)}, outputs=["b.z", "mount.m.fz"],
                       t_end=0.1, dt=1e-3)
    back = read_csv(write_csv(t, tmp_path / "t.csv"))
    np.testing.assert_array_equal(back.outputs, t.outputs)
    np.testing.assert_array_equal(back.time, t.time)
    assert back.output_names == t.output_names and back.units == t.units
    rr = vibss.random_response(model(), {"b.fz": ([1.0, 100.0], [1.0, 1.0])}, ["b.z"])
    text = write_csv(rr, tmp_path / "psd.csv").read_text()
    assert text.startswith("# vibss psd") and "b.z [m^2/Hz]" in text
    df = pd.read_csv(tmp_path / "psd.csv", comment="#")
    # the RMS is the square root of the PSD's integral (trapezoid on the result's own grid)
    assert np.sqrt(np.trapezoid(df.iloc[:, 1], df.iloc[:, 0])) == pytest.approx(rr.rms[0], rel=1e-3)


def test_bad_files_are_named(tmp_path) -> None:
    p = tmp_path / "x.csv"
    p.write_text("frequency_hz,b.z/b.fz re [m/N]\n1.0,2.0\n")
    with pytest.raises(ModelFileError, match="needs both 're' and 'im'"):
        read_csv(p)
    p.write_text("time_s,b.z [m]\n0.0,1.0\n0.1,abc\n")
    with pytest.raises(ModelFileError, match="line 3: a value is not a number"):
        read_csv(p)
    p.write_text("t,b.z [m]\n0.0,1.0\n")
    with pytest.raises(ModelFileError, match="first column 't'"):
        read_csv(p)
    p.write_text("time_s,b.z\n0.0,1.0\n")
    with pytest.raises(ModelFileError, match=r"expected '<signal> \[unit\]'"):
        read_csv(p)
    with pytest.raises(ModelError, match="expected a FrequencyResponse"):
        write_csv(vibss.modes(model()), p)
