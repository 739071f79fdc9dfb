"""`vibss report` on the examples: the text, the figures and one self-contained HTML page."""

from __future__ import annotations

import argparse
import dataclasses
import re

import matplotlib

matplotlib.use("Agg")

import numpy as np
import pytest

import vibss
from vibss.commands import example as example_command
from vibss.commands import report as report_command
from vibss.io import example_names, load_example
from vibss.report import html_table, study
from vibss.results import TextTable as Table


def run(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(prog="vibss")
    sub = parser.add_subparsers()
    report_command.register(sub)
    example_command.register(sub)
    args = parser.parse_args(argv)
    return args.func(args)


@pytest.fixture(scope="module", params=["prism", "two_mass"])
def written(request, tmp_path_factory):
    out = tmp_path_factory.mktemp(request.param)
    assert run(["report", "--example", request.param, "--out", str(out)]) == 0
    return request.param, out


@pytest.mark.slow
def test_report_writes_html_and_figures(written, capfd):
    name, out = written
    html = (out / "index.html").read_text(encoding="utf-8")
    for png in ("model.png", "modes.png", "modes_views.png", "energy.png"):
        assert (out / png).stat().st_size > 1000
    # self-contained: every figure written is embedded
    assert html.count("data:image/png;base64,") == len(list(out.glob("*.png"))) >= 5
    assert 'src="' not in html.replace('src="data:', "")      # ... and nothing referenced outside
    # the HTML shows the frequencies that vibss.modes computes, as the tables print them
    freqs = vibss.modes(load_example(name)).frequency_hz
    cells = re.findall(r'<td class="n">([0-9.]+)</td>', html)
    for f in freqs:
        assert f"{f:.4f}" in cells
    assert "<table>" in html and "Modal kinetic-energy distribution" in html


def test_report_text_and_progress(capsys, tmp_path):
    assert run(["report", "--example", "prism", "--no-figures"]) == 0
    out, err = capsys.readouterr()
    assert "[1/10] model ..." in err and "[4/10] damped modes ..." in err
    assert "1.0066" in out and "34.8" in out                  # x and rx modes of reference case 1
    assert "skipped: the model has no loads and no gravity" in out
    assert not list(tmp_path.iterdir())


def test_sections_that_apply_run():
    r = study(load_example("powertrain"), figures=False)
    assert [s.key for s in r.sections if s.skipped] == ["control", "harmonic"]   # no actuators; a linear file asks for no harmonic balance
    assert "no actuators" in r.section("control").note
    assert r.section("frequency").tables[0].rows                 # the firing-torque sweep
    assert r.section("time").note.startswith("0 to 1 s")          # the pothole, [analysis] time
    assert "static" in r.results and "damped" in r.results


def test_sections_asked_for_run_alone_in_the_report_order(capsys):
    full = study(load_example("prism"), figures=False)
    some = study(load_example("prism"), figures=False, sections=["frequency", "modes"])
    assert [s.key for s in some.sections] == [s.key for s in full.sections]       # the report's order kept
    for s in some.sections:
        if s.key in ("modes", "frequency"):
            assert s.text == full.section(s.key).text and not s.skipped
        else:
            assert s.skipped and not s.failed and s.note == "not asked for (sections)"
    assert set(some.results) < set(full.results) and "damped" not in some.results
    with pytest.raises(vibss.SignalError, match=r"no section 'frequncy' \(did you mean 'frequency'\?\)"):
        study(load_example("prism"), sections=["frequncy"])
    with pytest.raises(vibss.ArgumentError, match="no section asked for"):
        study(load_example("prism"), sections=[])
    gen = study(load_example("prism"), figures=False, sections=(k for k in ["modes"]))     # read once
    assert [s.key for s in gen.sections if not s.skipped] == ["modes"]
    assert [s.key for s in study(load_example("prism"), figures=False, sections="modes, frequency").sections
            if not s.skipped] == ["modes", "frequency"]
    assert run(["report", "--example", "prism", "--no-figures", "--sections", "modes"]) == 0
    out, err = capsys.readouterr()
    assert "[1/1] undamped modes ..." in err and "1.0066" in out and "skipped: not asked for" in out


def test_html_table_escapes_and_aligns():
    t = Table(["name", "value"], [["<a>", "1.5"], ["b", "-2e-3"]], title="T & U")
    h = html_table(t)
    assert "&lt;a&gt;" in h and "T &amp; U" in h
    assert h.count('class="n"') == 2 and h.count('class="t"') == 2


def test_example_list_and_write(capsys, tmp_path):
    assert run(["example", "list"]) == 0
    out = capsys.readouterr().out
    for name in example_names():
        assert re.search(rf"^{name}\s", out, re.M)
    assert run(["example", "write", "prism", str(tmp_path)]) == 0
    written = tmp_path / "prism.toml"
    assert written.read_text() == (vibss.io.example_path("prism")).read_text()
    assert run(["example", "write", "prism", str(written)]) == 1      # refuses to overwrite
    assert "--force" in capsys.readouterr().err
    assert run(["example", "write", "prism", str(written), "--force"]) == 0


# == moved from the file of review-round fixes: report band and per-section failures =====

# 9, 10 -- report ---------------------------------------------------------------------------------

def test_report_sweep_uses_the_file_band() -> None:
    from vibss.frequency.sweep import sweep_response
    from vibss.report import study

    model = load_example("powertrain")
    spec = model.settings["frequency"]
    rep = study(model, figures=False)
    r = rep.results["frequency"]
    assert r.frequency_hz.min() == spec["f1"] and r.frequency_hz.max() == spec["f2"]
    cli = sweep_response(model, None, spec.get("f1"), spec.get("f2"), int(spec.get("points", 1000)),
                         spec.get("spacing", "log"))       # what ``vibss frf`` computes
    np.testing.assert_array_equal(r.frequency_hz, cli.frequency_hz)
    for y in r.outputs:
        assert r.peaks(y, "sweep") == cli.peaks(y, "sweep")


def test_report_survives_a_numerical_failure_in_one_section(monkeypatch: pytest.MonkeyPatch) -> None:
    from vibss import report

    def broken(*args: object) -> object:
        raise np.linalg.LinAlgError("Singular matrix")

    monkeypatch.setitem(report._RUNNERS, "damped", broken)
    rep = report.study(load_example("two_mass"), figures=False)
    sec = rep.section("damped")
    assert sec.skipped and sec.note == "failed: LinAlgError: Singular matrix"
    assert not rep.section("modes").skipped and "modes" in rep.results

    def typo(*args: object) -> object:
        raise TypeError("a programming error")

    monkeypatch.setitem(report._RUNNERS, "damped", typo)
    rep = report.study(load_example("two_mass"), figures=False)     # a bug fails its section only
    sec = rep.section("damped")
    assert sec.failed and sec.note == "failed: internal error, please report: TypeError: a programming error"
    assert rep.failed == ("damped",) and not rep.section("modes").skipped
    assert "FAILED: internal error, please report: TypeError: a programming error" in rep.text()


@pytest.mark.slow
def test_command_writes_every_good_section_and_exits_3(monkeypatch: pytest.MonkeyPatch, tmp_path, capsys) -> None:
    """The issue's case: a section that raises anything still leaves the others written, in the text,
    the HTML and on disk; the exit status is 3 and stderr names the failed sections."""
    from vibss import report

    def broken(*args: object) -> object:
        raise KeyError("lost")

    monkeypatch.setitem(report._RUNNERS, "time", broken)
    out = tmp_path / "r"
    assert run(["report", "--example", "powertrain", "--out", str(out), "--quiet"]) == 3
    err = capsys.readouterr().err
    assert "1 section(s) failed: time" in err
    html = (out / "index.html").read_text(encoding="utf-8")
    assert 'class="failed">Failed: internal error, please report: KeyError' in html
    for png in ("modes.png", "sweep.png", "design_certificate.png", "orders.png"):
        assert (out / png).stat().st_size > 1000


@pytest.mark.slow
def test_a_figure_that_fails_to_save_is_noted(monkeypatch: pytest.MonkeyPatch, tmp_path) -> None:
    from vibss import report

    full = report.study(load_example("prism"), figures=True)
    rep = dataclasses.replace(full, sections=tuple(s for s in full.sections if s.key in ("model", "modes")))
    fig = rep.section("modes").figures[0][1]
    monkeypatch.setattr(fig, "savefig", lambda *a, **k: (_ for _ in ()).throw(OSError("disk full")))
    index, written = report.render_report(rep, tmp_path)      # two sections: the other figures' drawing is not the point
    sec = written.section("modes")
    assert sec.failed and "figure modes.png failed: OSError: disk full" in sec.note
    assert not written.section("model").failed and (tmp_path / "model.png").exists()
    assert index.exists() and (tmp_path / "energy.png").exists() and not (tmp_path / "modes.png").exists()


def test_no_negative_zeros_in_tables():
    """Issue 16: '-0.0' and 'zeta -0.00000' in tables. Cells that round to zero lose the sign;
    genuine small negatives keep it."""
    from vibss.results import TextTable as Table

    t = Table(["a", "b"], [["-0.0", "-0.00000 mm"], ["-0.01", "-0e+00"], ["-1e-06", "x-0.0"]])
    assert t.rows == [["0.0", "0.00000 mm"], ["-0.01", "0e+00"], ["-1e-06", "x-0.0"]]
    # the powertrain's energy table printed "-0.0" for a tiny negative share before
    m = vibss.modes(vibss.load_example("powertrain"))
    assert np.any((m.energy < 0) & (m.energy > -5e-4)) and " -0.0" not in m.energy_table().render()


def test_no_negative_zeros_outside_tables():
    """The static reaction line and the certificate's sag printed '-0.00' (an exactly balanced
    moment comes out of the solve as -1e-13): the powertrain's reaction about z is zero by its
    symmetry, and its sign must not show."""
    import re

    r = vibss.static(vibss.load_example("powertrain"))
    assert abs(r.reaction[5]) < 1e-6 and r.reaction[5] != 0.0
    line = next(x for x in r.report().splitlines() if x.startswith("Total reaction"))
    assert not re.search(r"(^|[ (,])-0\.0+([^0-9]|$)", line), line
    assert not re.search(r"(^|[ (,])-0\.0+([^0-9]|$)", vibss.design.certificate(
        vibss.load_example("powertrain")).report())


def test_figures_saved_once_have_the_pixels_of_savefig(tmp_path) -> None:
    """render_report lays a figure out alone and renders it once (issue 33): the PNG has exactly the
    pixels matplotlib's own two-draw ``savefig`` gives, labels placed on the model's three views
    included, and the figure keeps its layout engine."""
    from PIL import Image

    from vibss.plotting import plot_model
    from vibss.report.html import _save_png

    model = load_example("two_mass")
    stock, once = plot_model(model, view="three"), plot_model(model, view="three")
    stock.savefig(tmp_path / "stock.png", dpi=110)
    engine = once.get_layout_engine()
    _save_png(once, tmp_path / "once.png", 110)
    assert once.get_layout_engine() is engine
    a, b = (np.asarray(Image.open(tmp_path / f)) for f in ("stock.png", "once.png"))
    assert a.shape == b.shape and np.array_equal(a, b)
