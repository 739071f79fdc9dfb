"""Energy distributions against closed forms (2-DOF chains, a symmetric body) and against an
independent per-mount loop written here (point motions, the mounts' own axes)."""

from __future__ import annotations

import numpy as np
import pytest

import cases.models as cases
import vibss
from vibss import Body, Model, Mount, MountType, Orientation
from vibss.errors import AnalysisError, ArgumentError


def chain(c1=None, c2=None, eta1=0.0, eta2=0.0) -> Model:
    """ground -k1- body a -k2- body b, mounts at the COGs: per direction a 2-DOF chain (rotations free)."""
    k1, k2 = np.array([1e4, 2e4, 3e4]), np.array([2e4, 3.5e4, 4e4])
    t1 = MountType("t1", k1, c1 if c1 is not None else [0.0] * 3, loss_factor=eta1)
    t2 = MountType("t2", k2, c2 if c2 is not None else [0.0] * 3, loss_factor=eta2)
    return Model([Body("a", 10.0, [1, 1, 1]), Body("b", 4.0, [1, 1, 1])],
                 [Mount("g", t1, "a"), Mount("u", t2, "b", to="a")], name="chain")


def chain_modes(k1: float, k2: float, m1: float = 10.0, m2: float = 4.0) -> tuple[np.ndarray, np.ndarray]:
    """Closed-form 2x2: squared frequencies and shapes (columns [x_a, x_b]) of the chain."""
    tr, det = (k1 + k2) / m1 + k2 / m2, k1 * k2 / (m1 * m2)
    w2 = np.array([tr / 2 - np.sqrt(tr**2 / 4 - det), tr / 2 + np.sqrt(tr**2 / 4 - det)])
    shapes = np.array([[1.0, 1.0], [(k1 + k2 - w * m1) / k2 for w in w2]])     # row 1 of (K - w2 M) x = 0
    return w2, shapes


def elastic_rows(e):
    return np.flatnonzero(~e.rigid)


def test_strain_shares_of_a_chain_are_the_closed_form():
    e = vibss.energy_distribution(chain(), "strain")
    k1, k2 = [1e4, 2e4, 3e4], [2e4, 3.5e4, 4e4]
    checked = 0
    for d in range(3):
        w2, x = chain_modes(k1[d], k2[d])
        for r in range(2):
            share = k1[d] * x[0, r] ** 2 / (k1[d] * x[0, r] ** 2 + k2[d] * (x[1, r] - x[0, r]) ** 2)
            k = int(np.argmin(np.abs(e.frequency_hz - np.sqrt(w2[r]) / (2 * np.pi))))
            assert e.fractions[k].tolist() == pytest.approx([share, 1 - share], abs=1e-12)
            axis = np.zeros(6)
            axis[d] = 1.0
            assert e.by_axis[k, 0] == pytest.approx(share * axis, abs=1e-12)     # all on the mount's axis d
            checked += 1
    assert checked == 6 and np.isnan(e.fractions[e.rigid]).all() and e.rigid.sum() == 6


def test_kinetic_shares_per_body_are_the_closed_form():
    e = vibss.energy_distribution(chain(), "kinetic")
    w2, x = chain_modes(3e4, 4e4)                  # z
    for r in range(2):
        k = int(np.argmin(np.abs(e.frequency_hz - np.sqrt(w2[r]) / (2 * np.pi))))
        share = 10.0 * x[0, r] ** 2 / (10.0 * x[0, r] ** 2 + 4.0 * x[1, r] ** 2)
        assert e.fractions[k].tolist() == pytest.approx([share, 1 - share], abs=1e-12)
        assert e.by_axis[k, :, 2].tolist() == pytest.approx([share, 1 - share], abs=1e-12)


def test_dissipated_shares_of_a_chain_are_the_closed_form():
    c1, c2, eta1, eta2 = [10.0, 20.0, 30.0], [5.0, 8.0, 2.0], 0.05, 0.2
    e = vibss.energy_distribution(chain(c1, c2, eta1, eta2), "dissipative")
    w2, x = chain_modes(3e4, 4e4)                  # z
    for r in range(2):
        w = np.sqrt(w2[r])
        k = int(np.argmin(np.abs(e.frequency_hz - w / (2 * np.pi))))
        d1, d2 = (w * 30.0 + eta1 * 3e4) * x[0, r] ** 2, (w * 2.0 + eta2 * 4e4) * (x[1, r] - x[0, r]) ** 2
        assert e.fractions[k].tolist() == pytest.approx([d1 / (d1 + d2), d2 / (d1 + d2)], abs=1e-12)


def test_a_symmetric_body_shares_alike_and_by_stiffness():
    """Mounts at (+-0.5, 0, 0): the x mode deflects both alike, so the shares are k1 : k2."""
    m = Model([Body("b", 10.0, [1, 1, 1])], [Mount("m1", MountType("t", [1e4] * 3), "b", at=[-0.5, 0, 0]),
                                              Mount("m2", MountType("u", [3e4] * 3), "b", at=[0.5, 0, 0])])
    e = vibss.energy_distribution(m, "strain")
    x_mode = int(np.argmin(np.abs(e.frequency_hz - np.sqrt(4e4 / 10.0) / (2 * np.pi))))
    assert e.fractions[x_mode].tolist() == pytest.approx([0.25, 0.75], abs=1e-12)


def per_mount_loop(model: Model, shapes: np.ndarray, omega: np.ndarray, kind: str) -> np.ndarray:
    """(k, mounts, 6) energies by a loop over modes and mounts: point motions u = x + theta x r of both
    sides, the deflection in the mount's axes, k_j d_j^2 (or (w c_j + eta_j k_j) d_j^2)."""
    names = model.body_names
    out = np.zeros((shapes.shape[1], len(model.mounts), 6))
    for r in range(shapes.shape[1]):
        for p, mt in enumerate(model.mounts):
            point = np.asarray(mt.at, float) + (np.asarray(model.body(mt.body).cog) if mt.frame == "body" else 0.0)

            def motion(body: str) -> np.ndarray:
                if body not in names:
                    return np.zeros(3)
                q = shapes[6 * names.index(body):6 * names.index(body) + 6, r]
                return q[:3] + np.cross(q[3:], point - np.asarray(model.body(body).cog))
            local = mt.orientation.matrix.T @ (motion(mt.body) - motion(mt.to))
            k = np.asarray(mt.type.stiffness, float)
            if kind == "strain":
                out[r, p, :3] = 0.5 * k * local**2
            else:
                coef = omega[r] * np.asarray(mt.type.damping, float) + np.asarray(mt.type.loss_factor) * k
                out[r, p, :3] = np.pi * coef * local**2
    return out


@pytest.mark.parametrize("kind", ["strain", "dissipative"])
def test_inclined_two_body_model_matches_a_per_mount_loop(kind):
    m = cases.asymmetric_model()
    und = vibss.modes(m)
    e = vibss.energy_distribution(und, kind)
    ref = per_mount_loop(m, und.shapes, und.omega, kind)
    tot = ref.sum(axis=(1, 2))
    assert np.abs(e.by_axis - ref / tot[:, None, None]).max() < 1e-10
    assert np.abs(e.energy - tot).max() < 1e-10 * tot.max()
    assert np.allclose(e.fractions.sum(axis=1), 1.0, atol=1e-13)
    assert "checked" in e.note


def test_hysteretic_mounts_share_the_dissipation_by_their_loss_factor():
    """No dashpots, one loss factor: each mount dissipates pi eta k d^2, so its share is its strain
    energy share weighted by eta (here only m2 is lossy: 100 %)."""
    m = Model([Body("b", 10.0, [1, 1, 1])], [Mount("m1", MountType("t", [1e4] * 3), "b", at=[-0.5, 0, 0]),
                                              Mount("m2", MountType("u", [3e4] * 3, loss_factor=0.1), "b", at=[0.5, 0, 0])])
    e = vibss.energy_distribution(m, "dissipative")
    ok = ~e.rigid
    assert np.allclose(e.fractions[ok], [0.0, 1.0], atol=1e-12)


def test_refusals_name_the_argument():
    with pytest.raises(ArgumentError, match="kind"):
        vibss.energy_distribution(chain(), "potential")
    with pytest.raises(AnalysisError, match="dissipative"):
        vibss.energy_distribution(chain(), "dissipative")


def test_table_pandas_and_heat_map():
    e = vibss.energy_distribution(cases.asymmetric_model(), "strain")
    text = e.report()
    assert "Modal strain energy per mount [%]" in text and "fl.3" in text and "fl.r1" not in text
    df = e.to_pandas()
    assert list(df.columns[:2]) == ["frequency_hz", "fl"] and df.index[0] == 1
    assert e.to_pandas(by_axis=True).shape == (12, 1 + 6 * 7)
    assert np.array_equal(e["m1"], e.fractions[:, 4], equal_nan=True)
    fig = e.plot()
    assert fig.axes[0].get_xlabel() == "mount" and e.plot(by_axis=True).axes[0].get_xlabel() == "mount (local axis)"
    assert e.to_json()


def test_rotational_stiffness_is_shared_to_the_rotation_axes():
    """A 6x6 mount at the COG with rotational rates kr: the rx mode loads only its r1 axis (closed
    form: all of that mode's strain energy), a translation mode only its 1, 2, 3 axes."""
    t = MountType("r", [1e4, 2e4, 3e4], rotational_stiffness=[100.0, 200.0, 300.0])
    m = Model([Body("b", 10.0, [1.0, 1.5, 2.0])], [Mount("m", t, "b")])
    e = vibss.energy_distribution(m, "strain")
    und = vibss.modes(m)
    for k, d in enumerate(und.directions):
        want = np.zeros(6)
        want[["x", "y", "z", "rx", "ry", "rz"].index(d)] = 1.0
        assert e.by_axis[k, 0] == pytest.approx(want, abs=1e-12)
    rx = und.directions.index("rx")
    assert e.energy[rx] == pytest.approx(0.5 * 100.0 / 1.0, rel=1e-12)     # w^2 / 2 = kr / (2 J)
