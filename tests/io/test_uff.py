"""UFF dataset 58 out and in (pyuff, the optional extra that the test set-up installs)."""

from __future__ import annotations

import numpy as np
import pytest

pyuff = pytest.importorskip("pyuff")

import cases.models as cases  # noqa: E402
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


def two_bodies() -> vibss.Model:
    t = vibss.MountType("t", [1e4, 2e4, 3e4], [10.0, 20.0, 30.0])
    a = vibss.Body("engine", 50.0, [2.0, 3.0, 4.0], cog=[0.1, -0.2, 0.5])
    b = vibss.Body("frame", 20.0, [1.0, 1.5, 2.0], cog=[0.0, 0.3, 0.1])
    return vibss.Model([a, b], [vibss.Mount("m1", t, "engine", at=[0.3, 0.2, 0.3]),
                                vibss.Mount("m2", t, "engine", at=[-0.2, 0.1, 0.3], to="frame"),
                                vibss.Mount("m3", t, "frame", at=[0.2, -0.3, 0.0]),
                                vibss.Mount("m4", t, "frame", at=[-0.2, 0.3, 0.0])])


def test_mode_shapes_out_as_datasets_55_and_2411(tmp_path) -> None:
    """Six significant digits is the format (E13.5); what comes back is checked against the
    invariants of mass-normalised modes (Phi' M Phi = I, Phi' K Phi = diag w^2) on vibss's own
    matrices, the nodes against the bodies' centres of gravity, and pyuff reading the records."""
    from vibss.io import read_uff_modes

    m = two_bodies()
    md = vibss.modes(m)
    path = write_uff(md, tmp_path / "modes.uff")
    back = read_uff_modes(path)
    np.testing.assert_allclose(back.frequency_hz, md.frequency_hz, rtol=1e-5)
    np.testing.assert_allclose(back.coordinates, [[0.1, -0.2, 0.5], [0.0, 0.3, 0.1]], rtol=1e-15)
    asm = vibss.assemble(m)
    M, K = asm.dense("M"), asm.dense("K")
    phi = back.shapes                                            # rows engine x..rz, frame x..rz
    assert md.dofs == tuple(f"{b}.{d}" for b in ("engine", "frame") for d in ("x", "y", "z", "rx", "ry", "rz"))
    np.testing.assert_allclose(phi.T @ M @ phi, np.eye(12), atol=3e-5)
    np.testing.assert_allclose(np.diag(phi.T @ K @ phi), md.omega ** 2, rtol=3e-5, atol=3e-5 * md.omega.max() ** 2)
    recs = pyuff.UFF(str(path)).read_sets()
    assert [r["type"] for r in recs] == [2411] + [55] * 12
    assert recs[1]["analysis_type"] == 2 and recs[1]["n_data_per_node"] == 6 and recs[1]["id2"].startswith("nodes: engine,frame")


def test_some_mode_shapes_and_errors(tmp_path) -> None:
    from vibss.io import read_uff_modes

    md = vibss.modes(two_bodies(), n_modes=3)
    back = read_uff_modes(write_uff(md, tmp_path / "z.uff"))
    assert back.shapes.shape == (12, 3) and back.ids == ("vibss mode 1", "vibss mode 2", "vibss mode 3")
    np.testing.assert_allclose(back.shapes, md.shapes, rtol=0, atol=1e-5 * np.abs(md.shapes).max())
    with pytest.raises(vibss.ModelError, match="no dataset 55"):
        read_uff_modes(write_uff(vibss.frequency_response(model(), ["b.fz"], ["b.z"], [1.0, 2.0]),
                                 tmp_path / "f.uff"))
    with pytest.raises(vibss.ModelError, match="no such file"):
        read_uff_modes(tmp_path / "none.uff")


def test_control_points_are_nodes_that_move_with_their_body(tmp_path) -> None:
    """A point's mode shape is the body's rigid motion there: u = u_cog + theta x r (independent
    cross product here), rotations equal to the body's."""
    from vibss.io import read_uff_modes

    base = two_bodies()
    m = vibss.Model(base.bodies, base.mounts, control_points=[vibss.ControlPoint("top", "engine", [0.2, -0.1, 0.4])])
    md = vibss.modes(m)
    back = read_uff_modes(write_uff(md, tmp_path / "p.uff"))
    assert back.nodes.tolist() == [1, 2, 3]
    np.testing.assert_allclose(back.coordinates[2], [0.3, -0.3, 0.9], rtol=1e-15)
    q = md.shapes[:6]                                                     # engine's six rows
    u = q[:3] + np.cross(q[3:].T, [0.2, -0.1, 0.4]).T
    scale = np.abs(md.shapes).max()
    np.testing.assert_allclose(back.shapes[12:15], u, atol=2e-5 * scale)
    np.testing.assert_allclose(back.shapes[15:18], q[3:], atol=2e-5 * scale)


def test_frequency_shift_finds_a_stiffness_error() -> None:
    """'Measured' = the model with every stiffness 4 % low: its frequencies are sqrt(0.96) of the
    model's, so the computed response matches at alpha = 1 / sqrt(0.96) = 1.0206 (light damping:
    the FRAC there is 1 to the damping's first order)."""
    from vibss.io import frequency_shift

    def sdof(k: float) -> vibss.Model:
        return cases.sdof(5.0, k, 0.5, inertia=[0.1, 0.1, 0.1])

    f_meas = np.linspace(5.0, 20.0, 301)
    measured = vibss.frequency_response(sdof(0.96 * 2e4), ["b.fz"], ["b.z"], f_meas)
    computed = vibss.frequency_response(sdof(2e4), ["b.fz"], ["b.z"], np.linspace(3.0, 26.0, 20001))
    alpha, score = frequency_shift(measured, computed)["b.z/b.fz"]
    assert alpha == pytest.approx(1 / np.sqrt(0.96), rel=1e-5)
    assert score > 0.99 > frac(measured, computed)["b.z/b.fz"]
    with pytest.raises(vibss.ModelError, match="covers"):
        frequency_shift(measured, vibss.frequency_response(sdof(2e4), ["b.fz"], ["b.z"], f_meas))


def test_overlay_of_a_measured_frf(tmp_path) -> None:
    """The test-against-model figure: one magnitude and one phase axes, lines and markers per
    channel, the FRAC in the measured channel's legend entry (equal to vibss.io.frac)."""
    from vibss.plotting import plot_test_overlay

    m = model()
    computed = vibss.frequency_response(m, ["b.fz"], ["b.z", "b.x"], np.geomspace(1.0, 100.0, 400))
    path = write_uff(vibss.frequency_response(m, ["b.fz"], ["b.z"], np.geomspace(2.0, 80.0, 60)), tmp_path / "t.uff")
    measured = read_uff(path)
    fig = plot_test_overlay(measured, computed)
    top = fig.axes[0]
    labels = [t.get_text() for t in top.get_legend().get_texts()]
    assert labels == ["b.z/b.fz computed", f"b.z/b.fz measured (FRAC {frac(measured, computed)['b.z/b.fz']:.3f})"]
    assert top.get_ylabel() == "|H| [m/N]" and fig.axes[1].get_xlabel() == "frequency [Hz]"
    with pytest.raises(vibss.ModelError, match="not in both"):
        plot_test_overlay(measured, computed, ["b.x/b.fz"])
