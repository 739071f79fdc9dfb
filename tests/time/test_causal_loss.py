"""A constant loss factor in the time domain (issue 14 item 2): its causal approximation.

References, none computed by the code under test: the hysteretic closed form k (1 + i eta); the
equivalent damping of a hysteretic single-DOF oscillator at resonance (zeta = eta / 2, the
logarithmic decrement of its free decay pi eta); passivity and causality of a Maxwell ladder (every
branch stiffness and relaxation time non-negative, loss angle >= 0); and the converted model's own
FRF against the steady state of a long sine run in the time domain (<= 1e-6, one mount one answer).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import vibss
from cases.models import box
from vibss.errors import ArgumentError, ModelError, VibssWarning
from vibss.studies import causal_loss, causal_loss_fit

ETA, K, MASS = 0.1, 4e4, 10.0          # f_n = sqrt(K / MASS) / 2 pi = 10.07 Hz


def _sdof(eta: float = ETA) -> vibss.Model:
    return box(MASS, [1.0, 1.0, 1.0], K, at=[0.1, 0.1, 0.0], loss_factor=eta, type_name="rubber")


def test_the_ladder_is_passive_causal_and_as_near_as_kramers_kronig_allows():
    band = (1.0, 100.0)
    fit = causal_loss_fit(_sdof(), band)
    t = fit.model.mounts[0].type
    lad = t.ladder
    assert np.all(lad.k >= 0) and np.all(lad.tau > 0) and np.all(lad.static > 0)   # passive, causal
    w = 2 * np.pi * np.geomspace(*band, 1000)
    kstar = lad.stiffness(w)
    assert np.all(kstar.imag >= 0)
    storage = np.abs(kstar.real / K - 1).max()
    loss = np.abs(kstar.imag / kstar.real / ETA - 1).max()
    # the stated errors bound the measured ones (on a finer grid: within a per mille of them)
    assert storage <= fit.storage_error * 1.001 and loss <= fit.loss_error * 1.001
    # Kramers-Kronig: the exact causal constant loss (k* ~ (i w)^(2 atan(eta) / pi)) has a storage
    # stiffness rising by (f2 / f1)^(2 atan(eta) / pi) over the band, +-15.8 % about its centre here;
    # the ladder keeps within that and the loss factor within a fifth
    kk = (band[1] / band[0]) ** (np.arctan(ETA) / np.pi) - 1
    assert 0.5 * kk < fit.storage_error <= kk and fit.loss_error < 0.2
    centre = lad.stiffness(np.array([2 * np.pi * 10.0]))[0, 2]
    assert centre.imag / centre.real == pytest.approx(ETA, rel=0.05)
    assert fit.mounts == ("m", "m.xz", "m.yz", "m.xz.yz")
    assert f"storage stiffness within {100 * fit.storage_error:.2g} %" in fit.note
    narrow = causal_loss_fit(_sdof(), (5.0, 20.0))       # a narrower band: closer
    assert narrow.storage_error < fit.storage_error / 2 and narrow.loss_error < fit.loss_error


def test_free_decay_has_the_damping_of_the_loss_factor():
    """Logarithmic decrement of the vertical free decay: pi eta (zeta = eta / 2) at resonance."""
    model = _sdof()
    kick = vibss.Excitation("kick", "force", "b", vibss.HalfSine(50.0, duration=0.002), dof="z")
    with warnings.catch_warnings():
        warnings.simplefilter("error", VibssWarning)       # nothing left out, so no warning
        r = vibss.simulate(model, [kick], outputs=["b.z"], t_end=1.0, dt=1e-4, hysteresis="causal")
    def decrement(z: np.ndarray) -> float:
        peaks = [i for i in range(1, z.size - 1) if z[i - 1] < z[i] > z[i + 1] and r.time[i] > 0.01]
        return float(np.log(z[peaks[0]] / z[peaks[4]]) / 4)

    assert decrement(r.outputs[0]) == pytest.approx(np.pi * ETA, rel=0.1)
    assert "causal Maxwell ladder" in r.note
    with pytest.warns(VibssWarning, match=r"vibss.causal_loss\(model\)"):
        dropped = vibss.simulate(model, [kick], outputs=["b.z"], t_end=1.0, dt=1e-4)
    assert abs(decrement(dropped.outputs[0])) < 1e-3          # rings undamped without it


def test_long_sine_in_time_equals_the_frf_of_the_same_model():
    f = 9.0
    model = causal_loss(_sdof())
    sine = vibss.Excitation("shake", "force", "b", vibss.Sine(100.0, f), dof="z")
    r = vibss.simulate(model, [sine], outputs=["b.z"], t_end=12.0, dt=1e-3, record_from=11.0)
    t, z = r.time, r.outputs[0]
    basis = np.column_stack([np.sin(2 * np.pi * f * t), np.cos(2 * np.pi * f * t)])
    (a, b), *_ = np.linalg.lstsq(basis, z, rcond=None)
    h = vibss.frequency_response(model, ["b.fz"], ["b.z"], frequencies=[f]).response[0, 0, 0]
    # 100 N sin(w t) -> 100 (Re H sin + Im H cos); the samples are joined linearly (first-order
    # hold), which scales a sine's fundamental by sinc^2(w dt / 2) exactly (the triangle kernel)
    hold = np.sinc(f * 1e-3) ** 2                       # numpy's sinc(x) = sin(pi x) / (pi x)
    assert complex(a, b) == pytest.approx(100.0 * hold * h, rel=1e-6)
    # and within the stated fit error of the hysteretic FRF it stands for
    h0 = vibss.frequency_response(_sdof(), ["b.fz"], ["b.z"], frequencies=[f]).response[0, 0, 0]
    fit = causal_loss_fit(_sdof())
    assert abs(h - h0) / abs(h0) < 2 * max(fit.storage_error, ETA * fit.loss_error)


def test_refusals():
    with pytest.raises(ArgumentError, match="hysteresis"):
        vibss.simulate(_sdof(), [], t_end=1.0, dt=0.1, hysteresis="casual")
    with pytest.raises(ModelError, match="band"):
        causal_loss(_sdof(), band=[10.0, 1.0])
    flat = vibss.MountType("flat", [K, K, 0.0], loss_factor=ETA)
    bad = vibss.Model([vibss.Body("b", MASS, [1.0, 1.0, 1.0])],
                      vibss.symmetric(vibss.Mount("m", flat, "b", at=[0.1, 0.1, 0.0])))
    with pytest.raises(ModelError, match="mount type 'flat'.*zero axis"):
        causal_loss(bad, band=[1.0, 10.0])
    plain = vibss.load_example("prism")
    assert causal_loss(plain) is plain
