"""Issue 33 item 9: a notebook shows the full tables: a static result its mounts' deflections and
forces (it showed the bodies only), modes their kinetic-energy distribution beside the frequencies.

Independent numbers: a body of mass m on four equal mounts of vertical rate k placed symmetrically
sags ``m g / 4k`` on each, each mount carrying ``m g / 4``; its vertical mode is all z energy.
"""

from __future__ import annotations

import re

import pytest

import cases.models as cases
import vibss

M, K, G = 12.0, 3e4, 9.81


def model() -> vibss.Model:
    return cases.box(M, [1.0, 1.2, 1.5], [K, K, K], 30.0, at=[0.3, 0.2, 0.0], gravity=[0.0, 0.0, -G])


def test_the_static_result_shows_its_mounts_in_a_notebook():
    html = vibss.static(model())._repr_html_()
    assert html.count("<table") == 2 and "Mounts" in html
    sag = f"{-1e3 * M * G / (4 * K):.4f}"                      # mm, every mount alike
    force = f"{-M * G / 4:.2f}"                               # N into ground, z
    rows = re.findall(r"<tr>(.*?)</tr>", html, flags=re.S)
    mounts = [r for r in rows if "-&gt;ground" in r or "->ground" in r]
    assert len(mounts) == 4
    assert all(sag in r and force in r for r in mounts), mounts[0]


def test_modes_show_their_energy_distribution_in_a_notebook():
    m = vibss.modes(model())
    html = m._repr_html_()
    assert html.count("<table") == 2 and "kinetic-energy" in html
    z = list(m.labels).index("z")
    row = re.findall(r"<tr>(.*?)</tr>", html.split("kinetic-energy", 1)[1], flags=re.S)[z + 1]
    cells = re.findall(r"<td[^>]*>(.*?)</td>", row)
    assert cells[3 + 2] == "100.0" and cells[3 + 0] == "0.0"      # b.z carries it all, b.x nothing
    assert float(cells[1]) == pytest.approx((4 * K / M) ** 0.5 / (2 * 3.141592653589793), rel=1e-3)
