"""fit_rheology: data from a known law give its parameters back; data from another law give an
honest error and a warning. The reference stiffnesses are written out here in closed form."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from matplotlib.figure import Figure

import vibss
from vibss import fit_rheology
from vibss.errors import ArgumentError, VibssWarning

F = np.geomspace(1.0, 1e4, 40)
W = 2 * np.pi * F


def zener(k0: float, kinf: float, tau: float) -> np.ndarray:
    s = 1j * W * tau
    return k0 + (kinf - k0) * s / (1 + s)


def fractional(k0: float, kinf: float, tau: float, alpha: float) -> np.ndarray:
    p = (1j * W * tau) ** alpha
    return (k0 + kinf * p) / (1 + p)


def prony(k0: float, k: list[float], tau: list[float]) -> np.ndarray:
    return k0 + sum(ki * 1j * W * ti / (1 + 1j * W * ti) for ki, ti in zip(k, tau))


def test_zener_data_give_the_zener_back_on_each_axis():
    truth = np.array([[1e5, 3e5, 1e-3], [2e4, 2.5e4, 2e-2], [5e6, 1.5e7, 3e-4]])
    data = np.array([zener(*p) for p in truth])
    fit = fit_rheology(F, data, "zener")
    got = np.column_stack([fit.rheology.k_0, fit.rheology.k_inf, fit.rheology.tau])
    np.testing.assert_allclose(got, truth, rtol=1e-6)
    assert fit.rms_error.max() < 1e-9 and fit.ok and fit.method == "least_squares"
    assert isinstance(fit.rheology, vibss.model.rheology.Zener)


def test_fractional_data_give_the_fractional_law_back():
    k0, kinf, tau, alpha = 1e5, 5e5, 2e-3, 0.4
    fit = fit_rheology(F, fractional(k0, kinf, tau, alpha), "fractional")
    r = fit.rheology
    for got, want in ((r.k_0, k0), (r.k_inf, kinf), (r.tau, tau), (r.alpha, alpha)):
        np.testing.assert_allclose(got, want, rtol=1e-6)
    assert "ladder" in fit.note


def test_storage_and_loss_factor_are_the_same_data_as_the_complex_stiffness():
    k = zener(1e5, 3e5, 1e-3)
    a = fit_rheology(F, k, "zener")
    b = fit_rheology(F, k.real, "zener", loss_factor=k.imag / k.real)
    np.testing.assert_allclose(b.rheology.tau, a.rheology.tau, rtol=1e-9)


def test_a_zener_fitted_to_a_three_term_prony_law_states_its_error_and_warns():
    data = prony(1e5, [5e4, 1e5, 2e5], [1e-1, 3e-3, 1e-4])
    with pytest.warns(VibssWarning, match="zener law misses the data"):
        fit = fit_rheology(F, data, "zener")
    # the error the fit reports is that of its own parameters, recomputed here in closed form
    own = zener(fit.rheology.k_0[0], fit.rheology.k_inf[0], fit.rheology.tau[0])
    rms = np.sqrt(np.mean(np.abs(np.log(own / data)) ** 2))
    np.testing.assert_allclose(fit.rms_error, rms, rtol=1e-9)
    assert rms > 0.05 and not fit.ok
    # the same data are a Prony law of order 3: fitted to rounding, silently
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        exact = fit_rheology(F, data, "prony", order=3)
    assert exact.rms_error.max() < 1e-9
    np.testing.assert_allclose(exact.rheology.tau[0], [1e-4, 3e-3, 1e-1], rtol=1e-6)


def test_a_fitted_rheology_goes_into_a_mount_type_and_a_model():
    fit = fit_rheology(F, zener(1e4, 3e4, 1e-2), "zener")
    t = vibss.MountType("fitted", rheology=fit.rheology)
    np.testing.assert_allclose(t.dynamic_stiffness(F)[:, 2], zener(1e4, 3e4, 1e-2), rtol=1e-6)


def test_the_result_protocol_and_the_figure(tmp_path):
    fit = fit_rheology(F, zener(1e5, 3e5, 1e-3), "zener")
    assert fit["axis 3"].shape == F.shape and "RMS log error" in fit.report()
    assert fit.to_json() and fit.to_dict()["rheology"]["type"] == "zener"
    fig = fit.plot()
    assert isinstance(fig, Figure)
    fig.savefig(tmp_path / "fit.png")


@pytest.mark.parametrize("kwargs,field", [
    (dict(frequencies=[2.0, 1.0], dynamic_stiffness=[1, 2]), "frequencies"),
    (dict(frequencies=[1.0, 2.0], dynamic_stiffness=[1, 2, 3]), "dynamic_stiffness"),
    (dict(frequencies=[1.0, 2.0], dynamic_stiffness=[-1, 2]), "dynamic_stiffness"),
    (dict(frequencies=[1.0, 2.0], dynamic_stiffness=[1, 2], type="zenr"), "type"),
    (dict(frequencies=[1.0, 2.0], dynamic_stiffness=[1, 2], order=2), "order"),
    (dict(frequencies=[1.0, 2.0], dynamic_stiffness=[1, 2], type="prony", order=4), "frequencies"),
    (dict(frequencies=[1.0, 2.0], dynamic_stiffness=[1, 2], loss_factor=[0.1, 0.1, 0.1]), "loss_factor"),
])
def test_bad_data_are_refused_by_name(kwargs, field):
    with pytest.raises(ArgumentError, match=f"fit_rheology: {field}") as err:
        fit_rheology(**kwargs)
    assert err.value.argument == field
