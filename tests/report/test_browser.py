"""The HTML report in a real browser: headless Chromium (the one Debian packages) opens ``index.html``
of a two-body report and the test reads back the DOM after the page's scripts ran and a screenshot.

Checked: every section renders, the 3-D mode viewer lists every mode at the frequency vibss.modes
computes and draws non-blank pixels (its own count, and the screenshot's), and the console shows no
error (the page records ``window.onerror`` and ``console.error`` into ``<html data-errors>``;
Chromium's log on stderr must hold no "Uncaught"). A deliberately broken copy of the page shows the
error checks can fail. ``VIBSS_KEEP_SCREENSHOT=1`` copies the screenshot to
``docs/figures/report_viewer.png``.
"""

from __future__ import annotations

import html as html_lib
import os
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

import vibss
from cases.models import two_body
from vibss.report import study, write_report

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
pytestmark = pytest.mark.skipif(
    CHROMIUM is None, reason="no Chromium binary ('chromium' or 'chromium-browser') on PATH; "
                             "`make venv` installs it where apt-get and root are available")

WIDTH = 1000            # browser window width [CSS px]; the page's layout does not depend on the height
DOCS_FIGURE = Path(__file__).resolve().parents[2] / "docs" / "figures" / "report_viewer.png"


def chromium(page: Path, profile: Path, *args: str) -> subprocess.CompletedProcess:
    """Run headless Chromium on ``page`` (1.5 s of virtual time for the scripts and a few frames)."""
    cmd = [CHROMIUM, "--headless=new", "--disable-gpu", "--no-sandbox", "--hide-scrollbars",
           "--enable-logging=stderr", "--v=0", "--virtual-time-budget=1500", f"--user-data-dir={profile}",
           *args, page.as_uri()]
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, f"chromium failed ({done.returncode}): {done.stderr[-2000:]}"
    return done


def attribute(dom: str, tag_id: str, name: str) -> str | None:
    tag = re.search(rf'<[a-z]+ [^>]*id="{tag_id}"[^>]*>', dom)
    assert tag, f"no element #{tag_id} in the DOM"
    value = re.search(rf'\b{name}="([^"]*)"', tag.group(0))
    return None if value is None else html_lib.unescape(value.group(1))


def errors_of(dom: str, stderr: str) -> list[str]:
    """Errors the page recorded into <html data-errors> and uncaught ones in Chromium's log."""
    head = re.search(r"<html[^>]*>", dom)
    found = re.findall(r'data-errors="([^"]*)"', head.group(0) if head else "")
    return found + [line for line in stderr.splitlines() if "Uncaught" in line]


@pytest.fixture(scope="module")
def page(tmp_path_factory):
    """The report written, its DOM after the scripts ran and Chromium's log."""
    out = tmp_path_factory.mktemp("browser")
    report = study(two_body(), figures=False)
    index = write_report(report, out / "report")
    done = chromium(index, out / "profile", f"--window-size={WIDTH},800", "--dump-dom")
    return report, index, done.stdout, done.stderr, out


def test_every_section_renders(page):
    report, _, dom, _, _ = page
    for s in report.sections:
        assert f'<h2 id="{s.key}">{html_lib.escape(s.title)}</h2>' in dom
    shown = [s for s in report.sections if not s.skipped]
    assert dom.count("<table>") == sum(len(s.tables) for s in shown)
    # the mode list is built by the page's script from its JSON: one entry per mode, at the frequency
    # of vibss.modes (which the Python side computed; the page only formats it)
    freqs = vibss.modes(two_body()).frequency_hz
    options = re.findall(r'<option value="(\d+)">(\d+): ([0-9.]+) Hz, ([^<]+)</option>', dom)
    assert len(options) == len(freqs)
    for k, (value, number, hz, _) in enumerate(options):
        assert (int(value), int(number)) == (k, k + 1)
        assert float(hz) == pytest.approx(freqs[k], abs=0.0051 * max(1.0, freqs[k] / 10))


def test_no_console_errors(page):
    _, _, dom, stderr, _ = page
    assert errors_of(dom, stderr) == []


def test_error_checks_can_fail(page):
    """A copy of the page with a script error and a console.error call: both checks see them."""
    _, index, _, _, out = page
    broken = index.with_name("broken.html")
    text = index.read_text(encoding="utf-8")
    broken.write_text(text.replace("</body>", '<script>console.error("vibss-test");\nnoSuchFunction();</script></body>'),
                      encoding="utf-8")
    done = chromium(broken, out / "profile-broken", f"--window-size={WIDTH},800", "--dump-dom")
    found = errors_of(done.stdout, done.stderr)
    assert any("vibss-test" in e for e in found) and any("noSuchFunction" in e for e in found)
    assert any("Uncaught" in e for e in found)          # Chromium's own log sees it too


def test_viewer_draws_and_keeps_a_screenshot(page):
    _, index, dom, _, out = page
    painted, pixels = (int(attribute(dom, "viewer-canvas", k)) for k in ("data-painted", "data-pixels"))
    assert 0.02 < painted / pixels < 0.8                  # the model itself, before the legend and triad
    assert int(attribute(dom, "viewer-canvas", "data-frames")) >= 1
    x, y, w, h = (int(v) for v in attribute(dom, "viewer-canvas", "data-rect").split(","))
    shot = out / "report_viewer.png"
    chromium(index, out / "profile-shot", f"--window-size={WIDTH},{y + h + 40}", f"--screenshot={shot}")
    from PIL import Image

    image = Image.open(shot).convert("RGB")
    crop = image.crop((x - 2, y - 40, x + w + 2, y + h + 2))    # the canvas and the mode bar above it
    crop.save(shot)
    rgb = np.asarray(crop, float)[42:-4, 4:-4]                 # the canvas only
    ink = np.any(rgb < 235, axis=2).mean()
    bluish = ((rgb[..., 2] - rgb[..., 0]) > 25).mean()        # the first body's translucent blue faces
    orange = ((rgb[..., 0] - rgb[..., 2]) > 40).mean()        # ... and the second's orange ones
    assert ink > 0.02 and bluish > 0.01 and orange > 0.005, (ink, bluish, orange)
    if os.environ.get("VIBSS_KEEP_SCREENSHOT") == "1":
        DOCS_FIGURE.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(shot, DOCS_FIGURE)
