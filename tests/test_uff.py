"""UFF dataset 58 out and in (pyuff, the optional extra that the test set-up installs)."""

from __future__ import annotations

import numpy as np
import pytest

pyuff = pytest.importorskip("pyuff")

import vibss  # noqa: E402
from vibss.io import frac, read_uff, write_uff  # noqa: E402


def model() -> vibss.Model:
    t = vibss.MountType("t", [1e4, 2e4, 3e4], [10.0, 20.0, 30.0])
    return vibss.Model([vibss.Body("b", 5.0, [0.1, 0.2, 0.3])], [vibss.Mount("m", t, "b", at=[0.1, 0.0, -0.1])])


def test_frf_round_trip_is_exact(tmp_path) -> None:
    r = vibss.frequency_response(model(), ["b.fz", "b.fx"], ["b.z", "b.x", "mount.m.fz"], np.geomspace(1, 100, 57))
    path = write_uff(r, tmp_path / "frf.uff")
    back = read_uff(path)
    assert back.outputs == r.outputs and back.inputs == r.inputs
    np.testing.assert_allclose(back.response, r.response, rtol=1e-12, atol=0.0)
    np.testing.assert_allclose(back.frequency_hz, r.frequency_hz, rtol=1e-12)
    assert back.units[0] == "m/N"
    # pyuff itself reads what vibss wrote: the complex data of the first channel, and its direction
    first = pyuff.UFF(str(path)).read_sets(0)
    np.testing.assert_allclose(first["data"], r.response[0, 0], rtol=1e-12)
    assert first["rsp_dir"] == 3 and first["ref_dir"] == 3 and first["func_type"] == 4
    assert frac(back, r)["b.z/b.fz"] == pytest.approx(1.0, abs=1e-12)


def test_reads_a_file_written_by_pyuff_and_time_records(tmp_path) -> None:
    f = np.linspace(1.0, 50.0, 50)
    h = 1.0 / (1e4 - (2 * np.pi * f) ** 2 * 5.0 + 2j * np.pi * f * 20.0)
    path = tmp_path / "other.uff"
    pyuff.UFF(str(path)).write_sets(pyuff.prepare_58(func_type=4, rsp_node=7, rsp_dir=3, ref_node=7, ref_dir=3,
                                                     data=h, x=f, id1="", id2="", binary=0,
                                                     orddenom_spec_data_type=13), mode="add")
    r = read_uff(path)
    assert r.outputs == ("node7.3",) and r.inputs == ("node7.3",)
    np.testing.assert_allclose(r.response[0, 0], h, rtol=1e-10)             # ASCII: about 11 digits
    computed = vibss.frequency_response(model(), ["b.fz"], ["b.z"], f)
    assert 0.0 < frac(computed, computed)["b.z/b.fz"] <= 1.0 + 1e-12
    t = vibss.simulate(model(), inputs={"b.fz": lambda x: np.sin(20 * x)}, outputs=["b.z"], t_end=0.1, dt=1e-3)
    tp = write_uff(t, tmp_path / "time.uff")
    rec = pyuff.UFF(str(tp)).read_sets(0)
    np.testing.assert_allclose(rec["data"], t["b.z"], rtol=1e-12)
    with pytest.raises(vibss.ModelError, match="no dataset 58 FRF"):
        read_uff(tp)
