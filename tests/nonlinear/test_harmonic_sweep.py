"""The turning points of harmonic balance against the jumps of slow swept-sine integrations
(scipy solve_ivp, written here): an upward sweep falls off the resonance near the upper fold, a
downward sweep jumps onto it near the lower fold."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from vibss import Body, Model, Mount, MountType
from vibss.nonlinear.harmonic import harmonic_balance

K, C, MASS, KS, GAP, FORCE = 4e4, 40.0, 10.0, 4e4, 1e-3, 10.0       # 10 Hz, 3 % damping, a stop at 1 mm


def _sweep(f0: float, f1: float, rate: float, y0: list[float]) -> tuple[np.ndarray, np.ndarray]:
    """Instantaneous frequency [Hz] and amplitude per two cycles [m] of a linear sweep at ``rate``
    [Hz/s] from the state ``y0`` [m, m/s]."""
    duration = abs(f1 - f0) / rate
    slope = np.sign(f1 - f0) * rate

    def rhs(t: float, y: np.ndarray) -> list[float]:
        x, v = y
        stop = KS * (max(x - GAP, 0.0) + min(x + GAP, 0.0))
        phase = 2 * np.pi * (f0 * t + 0.5 * slope * t * t)
        return [v, (FORCE * np.cos(phase) - C * v - K * x - stop) / MASS]

    # LSODA: 1.55 s a sweep against RK45's 2.8 s (125,000 and 224,000 evaluations), the same jump to 1e-12
    sol = solve_ivp(rhs, [0.0, duration], y0, method="LSODA", rtol=1e-7, atol=1e-11, dense_output=True)
    per = 1.0 / max(f0, f1)
    edges = np.arange(0.0, duration - 2 * per, 2 * per)                 # windows of about two cycles
    t = edges[:, None] + np.linspace(0.0, 2 * per, 60)[None, :]
    amp = np.abs(sol.sol(t.ravel())[0].reshape(t.shape)).max(axis=1)
    return f0 + slope * (edges + per), amp


@pytest.mark.slow
def test_the_jumps_of_slow_sweeps_are_the_turning_points() -> None:
    t = MountType("snub", [K, K, K], damping=[C] * 3, stops={"z": (GAP, KS)})
    model = Model([Body("b", MASS, [1.0, 1.0, 1.0])], [Mount("m", t, "b")])
    r = harmonic_balance(model, {"b.fz": FORCE}, ["b.z"], frequencies=(8.0, 16.0), harmonics=7, points=100,
                         stability=False)
    assert r.turning_points.size == 2
    upper, lower = r.turning_points.max(), r.turning_points.min()
    # upwards from the resonant branch at 12.3 Hz (its state from the branch: where the sweep falls
    # off is the integration's own answer), downwards from rest at 11.9 Hz (the small response)
    first = int(r.turning_index.min())
    b = int(np.argmin(np.abs(r.frequencies[:first] - 12.3)))
    Y, k = r.harmonics[0, :, b], np.arange(r.harmonics.shape[1])
    state = [float(np.sum(Y).real), float(np.sum(1j * k * r.omega[b] * Y).real)]
    f, a = _sweep(float(r.frequencies[b]), 13.0, 0.01, state)
    drop = int(np.argmin(np.diff(a)))                      # the largest fall between windows
    assert a[drop - 4] > 2 * a[drop + 4]
    assert f[drop] == pytest.approx(upper, rel=1e-2)
    f, a = _sweep(11.9, 10.8, 0.02, [0.0, 0.0])
    rise = int(np.argmax(np.diff(a)))
    assert a[rise + 2] > 1.5 * a[rise - 2]
    assert f[rise] == pytest.approx(lower, rel=1e-2)
