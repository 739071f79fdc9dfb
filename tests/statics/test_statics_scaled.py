"""Statics on the badly scaled family: the sag under gravity against a 60-digit reference.

K formed in floats loses the 1e4 N/m isolators beside 1e16 N/m links (1e16 eps ~ 1 N/m); the solve
from the stiffness factor keeps them, and never refuses a load K carries.
"""

from __future__ import annotations

import numpy as np
import pytest

from cases import mp_reference as mr
from cases import scaled as sc
from vibss import assemble, static
from vibss.model.model import Model

G = np.array([0.0, 0.0, -9.81])


def _weighted(m: Model) -> Model:
    return m.replace(gravity=G)


@pytest.mark.parametrize("k_link", [1e10, 1e12, 1e14, 1e16])
def test_stiff_link_sag_to_1e6_for_links_up_to_1e16(k_link):
    m = _weighted(sc.stiff_links(k_link))
    f = assemble(m).load_vector()
    ref = mr.static(m, f)
    r = static(m)
    assert r.free_motions == ()
    # every DOF relative to the largest, and the vertical sag of each body on its own
    assert np.abs(r.q - ref).max() <= 1e-6 * np.abs(ref).max()
    np.testing.assert_allclose(r.q[2::6], ref[2::6], rtol=1e-9, atol=0)


@pytest.mark.parametrize("name", ["graded_chain", "instrument"])
def test_family_sag_against_the_reference(name):
    m = _weighted(sc.FAMILY[name]())
    f = assemble(m).load_vector()
    ref = mr.static(m, f)
    q = static(m).q
    assert np.abs(q - ref).max() <= 1e-9 * np.abs(ref).max()
    np.testing.assert_allclose(q[2::6], ref[2::6], rtol=1e-8, atol=0)


def test_hanging_chain_carries_its_weight_on_the_soft_mount():
    """Closed form: the 10 N/m mount carries the whole weight; each link stretches by the weight below
    it over 1e6 N/m. Free rotations (mounts at the COGs) are not loaded and are listed, not refused."""
    m = _weighted(sc.hanging_chain())
    r = static(m)
    masses = np.array([b.total_mass for b in m.bodies])
    total = 9.81 * masses.sum()
    z1 = -total / 10.0
    assert r.body("b1")[2] == pytest.approx(z1, rel=1e-12)
    assert r.body("b0")[2] == pytest.approx(z1 - 9.81 * masses[0] / 1e6, rel=1e-12)
    assert r.body("b4")[2] == pytest.approx(
        z1 - 9.81 * (masses[2] + masses[3] + masses[4]) / 1e6 - 9.81 * (masses[3] + masses[4]) / 1e6
        - 9.81 * masses[4] / 1e6, rel=1e-12)
    assert len(r.free_motions) > 0


def test_static_equals_the_zero_frequency_modal_sum():
    """An invariant: K^-1 f = sum_r phi_r phi_r^T f / w_r^2 with the exact modes (stiff links 1e14)."""
    from vibss import modes

    m = _weighted(sc.stiff_links(1e14))
    f = assemble(m).load_vector()
    md = modes(m)
    x = md.shapes @ ((md.shapes.T @ f) / md.omega ** 2)
    q = static(m).q
    assert np.abs(q - x).max() <= 1e-8 * np.abs(q).max()
