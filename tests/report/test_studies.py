"""One set of study defaults (vibss.studies): the command line, the report and the Python API agree,
and the defaults follow from the model (closed-form frequencies and decay rates)."""

from __future__ import annotations

import dataclasses
import io
import json
import math
from contextlib import redirect_stdout
from pathlib import Path

import numpy as np
import pytest

import cases.models as cases
import vibss
from vibss import Body, Excitation, Model
from vibss.cli import main
from vibss.model.timefunctions import HalfSine, Sine, SineSweep
from vibss.report import study
from vibss.studies import (DECAY_PERIODS, frequency_band, steady_sweeps, study_defaults,
                           time_window, transient_excitations)

# one body on four isotropic mounts in the plane of its COG: six uncoupled modes in closed form
MASS, INERTIA, K, C, A, B = 50.0, (4.0, 6.0, 8.0), 2e4, 100.0, 0.4, 0.3


def box(excitations=(), c: float = C, settings=None) -> Model:
    return cases.box(MASS, list(INERTIA), K, c, at=[A, B, 0.0], type_name="iso", name="box",
                     excitations=list(excitations), settings=settings)


def closed_form(c: float = C) -> tuple[np.ndarray, np.ndarray]:
    """Natural frequencies [Hz] and decay rates zeta*omega [1/s] of the six modes of ``box``."""
    stiff = np.array([4 * K, 4 * K, 4 * K, 4 * K * B**2, 4 * K * A**2, 4 * K * (A**2 + B**2)])
    inert = np.array([MASS, MASS, MASS, *INERTIA])
    f = np.sqrt(stiff / inert) / (2 * np.pi)
    rate = (c / K) * stiff / (2 * inert)            # damping proportional to stiffness: c/k each
    return f, rate


def cli_json(argv: list[str]) -> dict:
    buf = io.StringIO()
    with redirect_stdout(buf):
        assert main([*argv, "--format", "json"]) == 0
    return json.loads(buf.getvalue())


# -- the defaults follow from the model -------------------------------------------------------------

def test_window_covers_the_excitation_and_the_slowest_decay() -> None:
    pulse = Excitation("hit", "force", "b", HalfSine(amplitude=100.0, start=0.02, duration=0.01), dof="z")
    f, rate = closed_form()
    decay = math.log(100.0) / rate.min()            # slowest mode to 1 %
    assert DECAY_PERIODS[0] / f.min() < decay < DECAY_PERIODS[1] / f.min()   # the rule's own regime
    w = time_window(box([pulse]))
    need = 0.03 + decay
    assert need <= w.end <= 1.1 * need              # rounded up to two digits
    # a twentieth of the highest natural period and of the pulse, rounded down to 1-2-5
    limit = min(1 / (20 * f.max()), 0.01 / 20, w.end / 200)
    assert 0.4 * limit <= w.step <= limit
    assert w.end / w.step <= 1e5
    assert w.record_from == 0.0 and w.tolerance == 1e-6


def test_undamped_window_is_twenty_periods_of_the_lowest_mode() -> None:
    f, _ = closed_form(0.0)
    sine = Excitation("hum", "force", "b", Sine(amplitude=1.0, frequency=3.0 * f.max(), start=0.5), dof="x")
    w = time_window(box([sine], c=0.0))
    need = 0.5 + DECAY_PERIODS[1] / f.min()         # a persistent sine: its start + the longest free decay
    assert need <= w.end <= 1.1 * need
    assert 0.4 / (20 * 3.0 * f.max()) <= w.step <= 1 / (20 * 3.0 * f.max())   # the sine's period rules


def test_band_covers_the_modes_or_the_sweeps() -> None:
    f, _ = closed_form()
    b = frequency_band(box())
    np.testing.assert_allclose([b.f1, b.f2], [0.1 * f.min(), 2 * f.max()], rtol=1e-9)
    assert (b.points, b.spacing) == (1000, "log")
    sweep = Excitation("sw", "force", "b", SineSweep(f1=40.0, f2=3.0, a1=1.0, a2=2.0), dof="z")
    steady_sweep = box([sweep])
    b = frequency_band(steady_sweep)
    assert (b.f1, b.f2) == (3.0, 40.0)
    assert steady_sweeps(steady_sweep) == (sweep,) and transient_excitations(steady_sweep) == ()


def test_file_settings_win_key_by_key() -> None:
    f, _ = closed_form()
    m = box(settings={"time": {"end": 2.0}, "frequency": {"f2": 80.0, "points": 50}})
    d = study_defaults(m)
    assert d.time.end == 2.0 and d.time.step <= 1 / (20 * f.max())
    assert (d.band.f2, d.band.points) == (80.0, 50)
    np.testing.assert_allclose(d.band.f1, 0.1 * f.min(), rtol=1e-9)
    m = box(settings={"time": {"end": 0.5, "step": 0.01}, "frequency": {"f1": 1.0, "f2": 9.0}})
    d = study_defaults(m)
    assert (d.time.end, d.time.step, d.band.f1, d.band.f2) == (0.5, 0.01, 1.0, 9.0)


def test_no_mounts_gives_a_plain_window() -> None:
    m = Model([Body("b", 1.0, [1, 1, 1])], [],
              excitations=[Excitation("p", "force", "b", HalfSine(amplitude=1.0, duration=0.2), dof="z")])
    w = time_window(m)
    assert w.end == pytest.approx(1.2) and w.step == pytest.approx(0.005)   # 1 s after; end / 200 -> 5e-3


# -- one model file, one answer -----------------------------------------------------------------------

def _without_analysis(name: str) -> Model:
    model = vibss.load_example(name)
    keep = {k: v for k, v in model.settings.items() if k not in ("time", "frequency")}
    return dataclasses.replace(model, settings=keep)


@pytest.mark.parametrize("name", [pytest.param(n, marks=pytest.mark.slow) if n == "snubbed_cabinet" else n
                                  for n in vibss.example_names()])          # its nonlinear time response: 8-19 s
@pytest.mark.parametrize("settings", ["file", "rule"])
def test_cli_and_report_give_one_window_and_band(name: str, settings: str, tmp_path: Path) -> None:
    model = vibss.load_example(name) if settings == "file" else _without_analysis(name)
    path = tmp_path / f"{name}.toml"
    vibss.dump_model(model, path)
    model = vibss.load_model(path)
    d = study_defaults(model)
    if settings == "file" and "time" in model.settings:     # the file's values, untouched
        assert (d.time.end, d.time.step) == (model.settings["time"]["end"], model.settings["time"]["step"])
        assert (d.band.f1, d.band.f2) == (model.settings["frequency"]["f1"], model.settings["frequency"]["f2"])
    rep = study(model, figures=False, sections=["modes", "frequency", "time"])  # those two read the window and band from the modes
    if d.transient:
        t_cli = np.array(cli_json(["time", str(path), "--output", f"{model.body_names[0]}.z"])["time"])
        t_rep = rep.results["time"].time
        np.testing.assert_allclose(t_cli, t_rep, rtol=0, atol=1e-12)
        assert t_cli[-1] == pytest.approx(d.time.end) and t_cli[1] - t_cli[0] == pytest.approx(d.time.step)
    else:
        assert rep.section("time").skipped
    if d.sweeps:
        f_cli = np.array(cli_json(["frf", str(path)])["frequency_hz"])
        np.testing.assert_array_equal(f_cli, rep.results["frequency"].frequency_hz)
        tr = next(v for k, v in rep.results.items() if k.startswith("transmissibility:"))
        assert (tr.frequency_hz.min(), tr.frequency_hz.max()) == (d.band.f1, d.band.f2)
    else:
        sig = f"{model.body_names[0]}.fz"
        f_cli = np.array(cli_json(["frf", str(path), "--input", sig, "--output", sig[:-2] + "z"])["frequency_hz"])
    assert (f_cli.min(), f_cli.max()) == pytest.approx((d.band.f1, d.band.f2), rel=1e-12)


def test_python_api_skips_steady_sweeps_like_the_cli() -> None:
    model = vibss.load_example("powertrain")
    d = study_defaults(model)
    r = vibss.simulate(model, outputs=["powertrain.z"], t_end=d.time.end, dt=d.time.step)
    assert "skipped steady sweep(s) ['firing-torque']" in r.note
    ref = vibss.simulate(model, list(d.transient), outputs=["powertrain.z"], t_end=d.time.end, dt=d.time.step)
    np.testing.assert_array_equal(r.outputs, ref.outputs)
    t_cli = cli_json(["time", "--example", "powertrain", "--output", "powertrain.z"])
    np.testing.assert_allclose(t_cli["outputs"]["powertrain.z"], r.output("powertrain.z"), rtol=1e-12, atol=0)


@pytest.mark.slow
def test_report_without_a_time_setting_writes_every_section(tmp_path: Path) -> None:
    """The reported bug: packaged_item without ``time =`` made ``vibss report`` crash, writing nothing."""
    path = tmp_path / "x.toml"
    assert main(["example", "write", "packaged_item", str(path)]) == 0
    path.write_text("\n".join(line for line in path.read_text().splitlines()
                              if not line.startswith("time =")))
    out = tmp_path / "out"
    assert main(["report", str(path), "--out", str(out), "--quiet"]) == 0
    assert (out / "index.html").is_file() and (out / "time.png").is_file()
    text = (out / "report.txt").read_text()
    assert "== Time response (transient excitations) ==\nnote: 0 to " in text
    # 8 blocks of 45 N s/m on 12 kg: the translations decay at 8 c / (2 m) = 15 1/s, the slowest
    decay = math.log(100.0) / (8 * 45.0 / (2 * 12.0))
    w = time_window(vibss.load_model(path))
    assert 0.011 + decay <= w.end <= 1.1 * (0.011 + max(decay, 5 / 15.9))
    assert w.step <= 0.011 / 20


def test_a_given_end_sets_the_step_rule() -> None:
    f, _ = closed_form()
    w = time_window(box(), end=100.0)               # long: end / 200 = 0.5 s would miss every mode
    assert w.end == 100.0 and w.note.startswith("end: given")
    assert 0.4 / (20 * f.max()) <= w.step <= 1 / (20 * f.max())
    w = time_window(box(), end=1000.0)              # at most MAX_DEFAULT_SAMPLES samples
    assert 0.4e5 <= w.end / w.step <= 1e5
    with pytest.raises(vibss.ModelError, match="end: expected a positive time"):
        time_window(box(), end=-1.0)
    out = cli_json(["time", "--example", "packaged_item", "--end", "0.05", "--output", "item.z"])
    assert out["time"][-1] == pytest.approx(0.05) and out["time"][1] == pytest.approx(1e-4)  # the file's step


def test_time_studies_lead_with_what_matters(capsys):
    """Issue 16 item 4: under a base pulse `vibss time` led with absolute displacements drifting to
    0.67 m and listed 23 channels the symmetry leaves at zero. Now the mount strokes and the
    item's acceleration lead (as in the report) and the zero channels are counted, not listed."""
    import vibss
    from vibss.cli import main
    from vibss.studies import time_outputs

    item = vibss.load_example("packaged_item")              # 50 g half-sine of the ground, vertical
    chosen = time_outputs(item)
    assert chosen.base and chosen.outputs[0].startswith("mount.") and chosen.outputs[-1] == "item.rz.rel"
    powertrain = vibss.load_example("powertrain")
    forced = time_outputs(powertrain, [e for e in powertrain.excitations if e.kind == "force"])
    assert not forced.base and forced.outputs[0] == "powertrain.x"
    assert main(["time", "--example", "packaged_item"]) == 0
    captured = capsys.readouterr()
    table = captured.out.split("unit\n", 1)[1].splitlines()
    assert table[0].split()[0].startswith("mount.") and "dz" in table[0].split()[0]
    listed = [row.split()[0] for row in table if not row.startswith("(")]
    # the doubly symmetric item under a vertical input: lateral and rotational channels are zero
    # by symmetry (an invariant, not a number from vibss), vertical ones are not
    assert not {"item.x.rel", "item.y.rel", "item.rx.rel", "item.ry.rel", "item.rz.rel", "item.x.acc"} & set(listed)
    assert {"item.z.rel", "item.z.acc"} <= set(listed)
    pulse = item.excitations[0].function                 # the ground keeps 2 A T / pi of velocity
    assert f"drift: drop-shock leaves the ground moving at {2 * pulse.amplitude * pulse.duration / np.pi:.3g} m/s" \
        in captured.err
    assert table[-1].startswith("(23 outputs below 1e-9")


def test_accelerations_in_g_on_request(capsys):
    """Issue 16 item 4: absolute acceleration in g on request (--g, or a file in g)."""
    import vibss
    from vibss.cli import main
    from vibss.plotting import plot_time_groups

    model = vibss.load_example("packaged_item")
    r = vibss.simulate(model, outputs=["item.z.acc", "mount.lower.dz"], t_end=0.05, dt=1e-4)
    g = r.in_g()
    assert g.units == ("g", "m")
    np.testing.assert_array_equal(g.outputs[0], r.outputs[0] / 9.80665)    # standard gravity
    np.testing.assert_array_equal(g.outputs[1], r.outputs[1])
    fig = plot_time_groups(r, show_inputs=True, acceleration="g")
    labels = [ax.get_ylabel() for ax in fig.axes]
    assert "input\n[g]" in labels and "acceleration\n[g]" in labels
    ins = next(ax for ax in fig.axes if ax.get_ylabel() == "input\n[g]")
    assert max(ins.lines[0].get_ydata()) == pytest.approx(50.0, rel=1e-3)   # the file's 50 g pulse
    assert main(["time", "--example", "packaged_item", "--g"]) == 0
    row = next(x for x in capsys.readouterr().out.splitlines() if x.startswith("item.z.acc"))
    assert row.split()[-1] == "g"
    assert float(row.split()[1]) == pytest.approx(np.max(np.abs(r.outputs[0])) / 9.80665, rel=1e-5)
