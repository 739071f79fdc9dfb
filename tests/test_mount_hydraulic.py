"""Hydraulic mounts (issue 14): a rubber spring and a fluid column with mass, one answer everywhere.

A body of mass M on one hydraulic mount at its COG: along z the mount is ``k* = k_r + s c_r +
k_b P / (k_b + P)``, ``P = m_f s^2 + c_f s``; along x and y it is rubber only (``k_b = 0``). Every
reference below is written out here from that definition: the closed-form receptance, the quartic
``(M s^2 + c_r s + k_r)(m_f s^2 + c_f s + k_b) + k_b (m_f s^2 + c_f s) = 0`` whose roots are the
z poles, and the four-state ODE ``M z'' = F - c_r z' - k_r z - k_b (z - y)``,
``m_f y'' = k_b (z - y) - c_f y'`` integrated by ``solve_ivp``.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import vibss
from vibss import Body, Model, Mount, MountType
from vibss.errors import ModelError
from vibss.io.modelfile import dumps_model, loads_model
from vibss.linear.plant.build import build_plant
from vibss.linear.solve.exact import response

M, KR, CR, KB, MF, CF = 20.0, 2.0e5, 60.0, 3.0e5, 4.0, 150.0
SPEC = {"type": "hydraulic", "k_r": KR, "c_r": CR, "k_b": [0.0, 0.0, KB], "m_f": [0.0, 0.0, MF],
        "c_f": [0.0, 0.0, CF]}


def model() -> Model:
    return Model([Body("b", M, [1.0, 1.0, 1.0])], [Mount("m", MountType("hydro", rheology=SPEC), "b")])


def kstar(s: np.ndarray) -> np.ndarray:
    p = MF * s ** 2 + CF * s
    return KR + CR * s + KB * p / (KB + p)


def test_frf_is_the_closed_form_and_the_mount_has_its_notch_and_peak() -> None:
    w = np.array([1.0, 60.0, 200.0, 270.0, 300.0, 1000.0, 1e4])
    s = 1j * w
    y = response(build_plant(model(), ["b.fz", "ground.z.disp"], ["b.z", "mount.m.fz"]), s)
    np.testing.assert_allclose(y[0, 0], 1 / (kstar(s) + M * s ** 2), rtol=1e-12)
    np.testing.assert_allclose(y[1, 0], kstar(s) / (kstar(s) + M * s ** 2), rtol=1e-12)   # force into ground
    # the rheology's own formula and the ladder every analysis uses agree; passive at every frequency
    t = MountType("hydro", rheology=SPEC)
    w_fine = np.geomspace(1.0, 1e4, 400)
    exact = t.rheology.dynamic_stiffness(w_fine)[:, 2]
    np.testing.assert_allclose(t.ladder.stiffness(w_fine)[:, 2], exact, rtol=1e-13)
    assert np.all(exact.imag >= 0)
    wn = np.sqrt(KB / MF)                                       # the track's resonance
    assert exact.real[w_fine < 0.8 * wn].min() < KR             # the notch below it
    assert exact.real[-1] == pytest.approx(KR + KB, rel=1e-3)   # the fluid locked above it
    assert abs(w_fine[np.argmax(exact.imag - CR * w_fine)] / wn - 1) < 0.1   # loss peak near it


def test_damped_modes_are_the_roots_of_the_quartic() -> None:
    d = vibss.damped_modes(model())
    quartic = np.polyadd(np.polymul([M, CR, KR], [MF, CF, KB]), KB * np.array([MF, CF, 0.0]))
    roots = np.roots(quartic)
    for lam in roots[roots.imag >= 0]:
        assert np.min(np.abs(d.poles - lam)) <= 1e-9 * abs(lam), (lam, d.poles)
    assert "fluid-track" in d.note


def test_time_response_matches_solve_ivp_of_the_four_state_system() -> None:
    ramp, t_end, dt = 0.005, 0.6, 1e-4
    force = lambda t: np.minimum(np.asarray(t) / ramp, 1.0) * 500.0  # noqa: E731  (exact for the FOH)
    r = vibss.simulate(model(), inputs={"b.fz": force}, outputs=["b.z", "mount.m.fz"], t_end=t_end, dt=dt)

    def rhs(t: float, x: np.ndarray) -> list[float]:
        z, v, y, u = x
        fb = KB * (z - y)
        return [v, (force(t) - CR * v - KR * z - fb) / M, u, (fb - CF * u) / MF]

    first = solve_ivp(rhs, (0, ramp), [0, 0, 0, 0], rtol=1e-12, atol=1e-16, method="DOP853", dense_output=True)
    second = solve_ivp(rhs, (ramp, t_end), first.y[:, -1], rtol=1e-12, atol=1e-16, method="DOP853",
                       dense_output=True)
    x = np.where(r.time <= ramp, first.sol(np.minimum(r.time, ramp)), second.sol(np.maximum(r.time, ramp)))
    z, v, y, _ = x
    f = KR * z + CR * v + KB * (z - y)
    assert np.abs(r["b.z"] - z).max() <= 1e-8 * np.abs(z).max()
    assert np.abs(r["mount.m.fz"] - f).max() <= 1e-8 * np.abs(f).max()


def test_statespace_carries_the_fluid_states_and_the_file_round_trip() -> None:
    sys = vibss.statespace(model(), inputs=["b.fz"], outputs=["b.z"])
    assert [s for s in sys.state_labels if s.startswith("mount:")] == ["mount:m:3:b1", "mount:m:3:b1:v"]
    w = np.array([50.0, 280.0])
    h = np.array([complex(sys(1j * x)[0, 0]) if np.ndim(sys(1j * x)) else complex(sys(1j * x)) for x in w])
    np.testing.assert_allclose(h, 1 / (kstar(1j * w) - M * w ** 2), rtol=1e-9)
    back = loads_model(dumps_model(model()))
    s = 1j * np.array([10.0, 270.0])
    np.testing.assert_allclose(response(build_plant(back, ["b.fz"], ["b.z"]), s),
                               response(build_plant(model(), ["b.fz"], ["b.z"]), s), rtol=1e-14)


@pytest.mark.parametrize("change, message", [
    ({"m_f": [0.0, 0.0, 0.0]}, r"axis 3: m_f must be > 0 where k_b > 0"),
    ({"c_f": -1.0}, r"c_f: axis 1 is -1.0"),
    ({"k_b": 1e5, "m_f": 1.0, "c_f": 1.0, "gain": 2}, r"unknown key\(s\) \['gain'\]"),
])
def test_bad_hydraulic_data_are_named(change: dict, message: str) -> None:
    with pytest.raises(ModelError, match=message):
        MountType("hydro", rheology={**SPEC, **change})


def test_a_hydraulic_mount_in_file_units() -> None:
    """N, mm, g: stiffness in N/mm, damping in N s/mm, the fluid mass in g — the same mount as SI."""
    text = f"""
[model]
name = "h"
units = {{length = "mm", mass = "g"}}
[[body]]
name = "b"
mass = {M * 1e3}
inertia = [1e9, 1e9, 1e9]
[[mount_type]]
name = "hydro"
rheology = {{type = "hydraulic", k_r = {KR / 1e3}, c_r = {CR / 1e3}, k_b = [0, 0, {KB / 1e3}], m_f = [0, 0, {MF * 1e3}], c_f = [0, 0, {CF / 1e3}]}}
[[mount]]
name = "m"
type = "hydro"
body = "b"
"""
    t = vibss.loads_model(text).mount_types["hydro"]
    w = np.array([5.0, 270.0, 2000.0])
    np.testing.assert_allclose(t.dynamic_stiffness(w), MountType("hydro", rheology=SPEC).dynamic_stiffness(w), rtol=1e-12)
