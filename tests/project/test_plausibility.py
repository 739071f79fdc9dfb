"""Issue 33 item 8: plausibility warnings in the Python API, each naming what looks wrong.

The three cases of the issue: mount points given in mm (modes at tens of kHz), a 30 g pulse 11 s
long, an FRF asked at 1e5-1e7 Hz of a 10 Hz model. The same models in plausible units stay quiet.
Independent numbers: a body on four mounts at the corners of a square of half-side ``a`` rocks at
``sqrt(8 k a^2 / J_z) / 2 pi`` in torsion (the highest mode); a half-sine acceleration of amplitude A and duration T reaches
``2 A T / pi``.
"""

from __future__ import annotations

import re

import warnings

import numpy as np
import pytest

import vibss
from vibss import Body, Model, Mount, MountType
from vibss.model.excitation import Excitation
from vibss.model.timefunctions import HalfSine

G = 9.80665


def table(scale: float) -> Model:
    """A 50 kg table top on four 20 kN/m mounts 0.4 m from its centre; ``scale`` multiplies the
    mount positions (1000: the positions given in mm)."""
    t = MountType("pad", [2e4, 2e4, 2e4], damping=[40.0, 40.0, 40.0])
    corners = [(0.4, 0.4, 0.0), (-0.4, 0.4, 0.0), (0.4, -0.4, 0.0), (-0.4, -0.4, 0.0)]
    return Model([Body("top", 50.0, [2.0, 2.0, 3.0])],
                 [Mount(f"m{i}", t, "top", at=tuple(scale * c for c in p)) for i, p in enumerate(corners)])


def quiet(fn):
    with warnings.catch_warnings():
        warnings.simplefilter("error", vibss.VibssWarning)
        return fn()


def test_mount_positions_in_mm_are_named_when_the_modes_reach_khz():
    with pytest.warns(vibss.VibssWarning, match=r"mount 'm0' 566 m from body 'top'.*positions in mm"):
        m = vibss.modes(table(1000.0))
    def twist(a: float) -> float:       # torsion about z: 4 mounts x (k_x y^2 + k_y x^2), J_z = 3 kg m^2
        return float(np.sqrt(4 * 2 * 2e4 * a**2 / 3.0) / (2 * np.pi))
    assert m.frequency_hz.max() == pytest.approx(twist(400.0), rel=1e-9)        # a = 400 m read from "400 mm"
    plain = quiet(lambda: vibss.modes(table(1.0)))
    assert plain.frequency_hz.max() == pytest.approx(twist(0.4), rel=1e-9)


def test_a_30_g_pulse_11_s_long_is_called_implausible():
    model = table(1.0)
    long = Excitation("shock", "acceleration", "ground", HalfSine(30 * G, duration=11.0), dof="z")
    with pytest.warns(vibss.VibssWarning, match=r"excitation 'shock'.*duration in s where ms") as rec:
        vibss.simulate(model, [long], outputs=["top.z.rel"], t_end=12.0, dt=0.01)
    said = next(str(w.message) for w in rec if "excitation 'shock'" in str(w.message))
    reached = float(re.search(r"reaches ([0-9.e+]+) m/s", said).group(1))
    assert reached == pytest.approx(2 * 30 * G * 11.0 / np.pi, rel=1e-2)   # the half-sine's velocity change
    short = Excitation("shock", "acceleration", "ground", HalfSine(30 * G, duration=0.011), dof="z")
    quiet(lambda: vibss.simulate(model, [short], outputs=["top.z.rel"], t_end=0.2, dt=1e-4))


def test_an_frf_far_above_every_mode_asks_about_units():
    model = table(1.0)
    with pytest.warns(vibss.VibssWarning, match=r"band starts at 1e\+05 Hz.*another unit"):
        vibss.frequency_response(model, inputs=["top.fz"], outputs=["top.z"], frequencies=np.logspace(5, 7, 5))
    quiet(lambda: vibss.frequency_response(model, inputs=["top.fz"], outputs=["top.z"],
                                           frequencies=np.logspace(-1, 2, 5)))
