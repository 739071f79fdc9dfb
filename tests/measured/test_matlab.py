"""MATLAB exchange: write_matlab / read_matlab round trips, and the file's matrices mean what they
say (the frequency response from the file's A, B, C, D and from its M, C, K agrees with vibss's)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.io import loadmat

import vibss
from cases.models import asymmetric_model
from vibss.errors import ArgumentError, ModelFileError
from vibss.io import read_matlab, write_matlab

INPUTS = ["motor.fz", "ground.z.acc"]
OUTPUTS = ["motor.z", "frame.x.acc", "mount.m1.fz"]


@pytest.fixture(scope="module")
def plant():
    m = asymmetric_model()
    return vibss.build_plant(m, INPUTS, [o for o in OUTPUTS])


def test_round_trip_is_bit_exact(plant, tmp_path):
    sys = vibss.statespace(plant)
    back = read_matlab(write_matlab(plant, tmp_path / "plant.mat"))
    for key in ("A", "B", "C", "D"):
        assert np.array_equal(getattr(back, key), np.asarray(getattr(sys, key))), key
    assert back.inputs == tuple(INPUTS) and back.outputs == tuple(OUTPUTS)
    assert back.states == tuple(x.replace(":", ".") for x in sys.state_labels)
    assert back.input_units == ("N", "m/s^2") and back.output_units == plant.units
    for key in ("M", "C", "K", "F", "Kz", "Cz", "Mz", "Oq", "Ov", "Oa", "Pz", "Pv", "Pa", "Pf"):
        assert np.array_equal(back.second_order[key], np.asarray(getattr(plant, key))), key
    assert back.dofs == plant.dofs and back.kinds == plant.kinds
    again = back.statespace
    assert np.array_equal(again.A, sys.A) and again.input_labels == sys.input_labels


def test_the_files_matrices_give_vibss_frequency_response(plant, tmp_path):
    """Read with scipy alone: C (sI - A)^-1 B + D and the second-order solve against vibss."""
    m = asymmetric_model()
    f = np.array([0.7, 3.0, 11.0])
    ref = vibss.frequency_response(m, INPUTS, OUTPUTS, frequencies=f).response
    raw = loadmat(str(write_matlab(m, tmp_path / "model", inputs=INPUTS, outputs=OUTPUTS)))
    a, b, c, d = (raw[k] for k in "ABCD")
    so = raw["second_order"][0, 0]
    for k, fk in enumerate(f):
        s = 2j * np.pi * fk
        h = c @ np.linalg.solve(s * np.eye(a.shape[0]) - a, b) + d
        np.testing.assert_allclose(h, ref[:, :, k], rtol=1e-9, atol=1e-12 * np.abs(ref[:, :, k]).max())
        # second order: a force column moves q; the acceleration input is z'' = u, z = u / s^2
        order = np.array([{"force": 0, "displacement": 0, "velocity": 1, "acceleration": 2}[str(x.item())]
                          for x in so["kinds"].ravel()])
        zu = np.where(order > 0, s ** (-order.astype(float)), 1.0) * (order >= 0)
        force = np.array([str(x.item()) == "force" for x in so["kinds"].ravel()])
        z = np.diag(np.where(force, 0.0, zu))
        rhs = so["F"] * force - (so["Kz"] + s * so["Cz"] + s**2 * so["Mz"]) @ z
        q = np.linalg.solve(so["K"] + s * so["C"] + s**2 * so["M"], rhs)
        y = (so["Oq"] + s * so["Ov"] + s**2 * so["Oa"]) @ q + (so["Pz"] + s * so["Pv"] + s**2 * so["Pa"]) @ z \
            + so["Pf"] * force
        np.testing.assert_allclose(y, ref[:, :, k], rtol=1e-9, atol=1e-12 * np.abs(ref[:, :, k]).max())


def test_a_state_space_goes_out_with_its_names(tmp_path):
    import control

    sys = control.ss([[-1.0, 0.0], [0.0, -2.0]], [[1.0], [1.0]], [[1.0, 1.0]], [[0.0]], inputs=["u"],
                     outputs=["y"], name="toy")
    back = read_matlab(write_matlab(sys, tmp_path / "toy.mat"))
    assert np.array_equal(back.A, sys.A) and back.inputs == ("u",) and back.outputs == ("y",)
    assert back.second_order == {} and back.name == "toy"


def test_bad_arguments_and_files_are_named(plant, tmp_path):
    with pytest.raises(ArgumentError, match="write_matlab: system"):
        write_matlab("plant", tmp_path / "x.mat")
    with pytest.raises(ArgumentError, match="write_matlab: inputs"):
        write_matlab(asymmetric_model(), tmp_path / "x.mat")
    with pytest.raises(ArgumentError, match="write_matlab: inputs, outputs"):
        write_matlab(plant, tmp_path / "x.mat", inputs=["motor.fz"])
    with pytest.raises(ModelFileError, match="no such file"):
        read_matlab(tmp_path / "none.mat")
    bad = tmp_path / "bad.mat"
    bad.write_text("not a mat file")
    with pytest.raises(ModelFileError, match="not a MAT file"):
        read_matlab(bad)


def test_frequency_dependent_mounts_are_in_the_state_space_and_the_file_says_so(tmp_path):
    from vibss.errors import VibssWarning

    t = vibss.MountType("r", rheology={"type": "zener", "k_0": 1e4, "k_inf": 3e4, "tau": 2e-3})
    m = vibss.Model([vibss.Body("b", 2.0, [1, 1, 1])], [vibss.Mount("m", t, "b")])
    with pytest.warns(VibssWarning, match="Maxwell branches"):
        path = write_matlab(m, tmp_path / "r.mat", inputs=["b.fz"], outputs=["b.z"])
    back = read_matlab(path)
    assert "Maxwell branches" in back.note
    f = np.array([5.0, 20.0, 80.0])
    ref = vibss.frequency_response(m, ["b.fz"], ["b.z"], frequencies=f).response[0, 0]
    s = 2j * np.pi * f
    h = [(back.C @ np.linalg.solve(sk * np.eye(back.A.shape[0]) - back.A, back.B) + back.D)[0, 0] for sk in s]
    np.testing.assert_allclose(h, ref, rtol=1e-9)
