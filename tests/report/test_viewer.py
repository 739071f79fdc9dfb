"""The 3-D mode viewer's data and page fragment, without a browser (tests/report/test_browser.py opens it)."""

from __future__ import annotations

import dataclasses
import json
import re

import numpy as np
import pytest

import vibss
from cases.models import two_body
from vibss.report import Section, study, write_report
from vibss.report.viewer import MOTION_FRACTION, viewer_data, viewer_html


@pytest.fixture(scope="module")
def modes():
    return vibss.modes(two_body())


def test_geometry_is_the_model(modes):
    """Cogs and mount points are the model's; each box is the uniform box of its body's inertia."""
    model, data = modes.model, viewer_data(modes)
    for b, d in zip(model.bodies, data["bodies"]):
        assert np.allclose(d["cog"], b.cog, rtol=1e-6, atol=1e-9)
        c = np.array(d["corners"])
        # corners by sign bits (4 x + 2 y + z): the edges from corner 0 are the box's axes
        edges = np.array([c[4] - c[0], c[2] - c[0], c[1] - c[0]])
        sides = np.linalg.norm(edges, axis=1)
        axes = (edges / sides[:, None]).T
        assert np.allclose(axes.T @ axes, np.eye(3), atol=1e-5)
        a2 = sides ** 2
        principal = b.total_mass / 12 * np.array([a2[1] + a2[2], a2[0] + a2[2], a2[0] + a2[1]])
        assert np.allclose(axes @ np.diag(principal) @ axes.T, b.tensor, rtol=1e-4, atol=1e-4 * np.abs(b.tensor).max())
    names = model.body_names
    for m, d in zip(model.mounts, data["mounts"]):
        assert np.allclose(d["point"], model.mount_point(m), rtol=1e-6, atol=1e-9)
        assert names[d["body"]] == m.body and (d["to"] == -1 if m.to == "ground" else names[d["to"]] == m.to)


def test_motion_is_the_mode_scaled_to_a_tenth_of_the_size(modes):
    """Each mode's body motion is the mass-normalised shape times one positive factor, and the largest
    small-motion displacement u + theta x r of any drawn point (box corners, mount and control points)
    is 10 % of the model's size."""
    model, data = modes.model, viewer_data(modes)
    size = data["size"]
    for k, mode in enumerate(data["modes"]):
        q = np.array(mode["q"])
        assert mode["hz"] == pytest.approx(modes.omega[k] / (2 * np.pi), rel=1e-12)
        shape = modes.shapes[:, k].reshape(-1, 6)
        factor = np.sum(q * shape) / np.sum(shape * shape)
        assert factor > 0 and np.allclose(q, factor * shape, rtol=1e-5, atol=1e-6 * np.abs(q).max())
        worst = 0.0
        for i, b in enumerate(model.bodies):
            pts = [np.array(data["bodies"][i]["corners"])]
            pts += [model.mount_point(m)[None] for m in model.mounts if b.name in (m.body, m.to)]
            pts += [(b.cog + model.point(c.body, c.at, c.frame))[None] for c in model.control_points if c.body == b.name]
            r = np.vstack(pts) - b.cog
            d = q[i, :3] + np.cross(q[i, 3:], r)
            worst = max(worst, np.linalg.norm(d, axis=1).max())
        assert worst == pytest.approx(MOTION_FRACTION * size, rel=1e-4)


def test_fragment_is_self_contained(modes):
    page = viewer_html(modes)
    assert "<canvas" in page and 'id="viewer-data"' in page
    assert not re.search(r"https?://|\bsrc=|import\s*\(|fetch\(|XMLHttpRequest", page)   # no network
    payload = re.search(r'<script type="application/json" id="viewer-data">(.*?)</script>', page, re.S)
    assert json.loads(payload.group(1))["name"] == "two body"
    script = page[page.index("<script>\n"):]
    assert len(script.splitlines()) < 300


def test_viewer_only_with_a_modes_section(tmp_path):
    report = study(two_body(), figures=False)
    html = write_report(report, tmp_path / "with").read_text(encoding="utf-8")
    assert html.count("<canvas") == 1 and html.index('id="modes-viewer"') > html.index('id="modes"')
    skipped = Section("modes", "Undamped modes", skipped=True, note="not run")
    sections = tuple(skipped if s.key == "modes" else s for s in report.sections)
    results = {k: v for k, v in report.results.items() if k != "modes"}
    bare = dataclasses.replace(report, sections=sections, results=results)
    html = write_report(bare, tmp_path / "without").read_text(encoding="utf-8")
    assert "<canvas" not in html and "<script" not in html and "Skipped: not run" in html


def test_a_large_model_carries_its_lowest_modes(modes):
    data = viewer_data(modes, max_modes=3)
    assert [m["n"] for m in data["modes"]] == [1, 2, 3] and data["total"] == len(modes) == 12
