"""Methods as objects: every registry looped against its exact reference, the facts the drivers
act on, and a user callable through each resolver.

References: frequency methods against ``direct`` (itself checked against a dense solve written
here); time methods against ``forced_response`` on inputs that are exactly piecewise linear with
kinks on samples (where it is exact); reduction methods against the exact FRF of the full plant.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from vibss import Body, Model, Mount, MountType, VibssError
from vibss.errors import AnalysisError, ModelError, VibssWarning
from vibss.frequency import METHODS as FREQ, FrequencyMethod, frequency_response
from vibss.linear.eigen.basis import ModalBasis
from vibss.linear.plant.build import build_plant
from vibss.methods import Method
from vibss.model.excitation import Excitation
from vibss.model.timefunctions import Ramp, Rectangular
from vibss.reduction import METHODS as RED, Reduced, ReductionMethod, reduce
from vibss.reduction.kernels import frf
from vibss.reduction.scope import Scope
from vibss.time import METHODS as TIME, SimulationJob, TimeMethod, simulate


def _model(beta: float = 2e-3) -> Model:
    """Three grounded bodies in a chain, damping proportional to stiffness (C = beta K: classical)."""
    def t(name: str, k: list[float]) -> MountType:
        return MountType(name, k, [beta * x for x in k])
    bodies = [Body(f"b{i}", m, [0.2 * m, 0.3 * m, 0.25 * m], cog=[0.1 * i, 0.0, 0.05 * i])
              for i, m in enumerate((20.0, 5.0, 2.0))]
    mounts = [Mount(f"g{j}", t("tg", [4e4, 5e4, 8e4]), "b0", at=at)
              for j, at in enumerate(([0.3, 0.2, -0.1], [-0.3, 0.2, -0.1], [0.0, -0.3, -0.1]))]
    mounts += [Mount(f"l{i}{j}", t(f"tl{i}", [1e4 / (i + 1), 2e4, 1.5e4]), f"b{i + 1}", at=at, to=f"b{i}")
               for i in range(2) for j, at in enumerate(([0.05, 0.05, -0.05], [-0.05, 0.0, -0.05],
                                                         [0.0, -0.05, -0.05]))]
    return Model(bodies, mounts, name="chain3")


INPUTS, OUTPUTS = ["b0.fz", "b2.fx"], ["b2.z", "b1.rx", "mount.l10.fz"]
F_HZ = np.array([0.5, 2.0, 5.0, 9.0, 14.0, 30.0, 60.0])


def _dense_solve(p, w):
    out = np.empty((len(p.outputs), len(p.inputs), w.size), complex)
    for k, wk in enumerate(w):
        s = 1j * wk
        x = np.linalg.solve(p.K + s * p.C + s * s * p.M, p.F)
        out[:, :, k] = (p.Oq + s * p.Ov + s * s * p.Oa) @ x + p.Pf
    return out


@pytest.fixture(scope="module")
def plant():
    return build_plant(_model(), INPUTS, OUTPUTS)


@pytest.fixture(scope="module")
def reference(plant):
    ref = frequency_response(plant, frequencies=F_HZ, method="direct").response
    np.testing.assert_allclose(ref, _dense_solve(plant, 2 * np.pi * F_HZ), rtol=1e-11)
    return ref


# -------------------------------------------------------------------------------- frequency

@pytest.mark.parametrize("name", list(FREQ))
def test_every_frequency_method_matches_direct(plant, reference, name) -> None:
    r = frequency_response(plant, frequencies=F_HZ, method=name)
    assert r.method == name and isinstance(FREQ[name], FrequencyMethod) and FREQ[name].name == name
    np.testing.assert_allclose(r.response, reference, rtol=1e-8, atol=1e-10 * np.abs(reference).max())


def test_frequency_registry_facts_are_consistent() -> None:
    assert {n for n, m in FREQ.items() if m.exact} == {"direct", "sparse"}
    assert {n for n, m in FREQ.items() if m.needs_basis} == {"modal", "complex_modal", "woodbury"}
    for m in FREQ.values():
        assert m.fallback is None or FREQ[m.fallback].exact


def test_a_user_kernel_receives_what_the_builtins_receive(plant, reference) -> None:
    seen = []

    def mine(p, s, basis):
        seen.append(basis)
        return FREQ["modal"].kernel(p, s, basis)

    r = frequency_response(plant, frequencies=F_HZ, method=mine)
    assert r.method == "mine" and isinstance(seen[0], ModalBasis) and seen[0].phi.shape == (plant.n, plant.n)
    np.testing.assert_allclose(r.response, reference, rtol=1e-8, atol=1e-10 * np.abs(reference).max())
    two = frequency_response(plant, frequencies=F_HZ, method=lambda p, s: FREQ["direct"](p, s))
    np.testing.assert_allclose(two.response, reference, rtol=1e-12)
    obj = FrequencyMethod("twice", lambda p, s, basis=None: 2 * FREQ["direct"](p, s))
    np.testing.assert_allclose(frequency_response(plant, frequencies=F_HZ, method=obj).response,
                               2 * reference, rtol=1e-12)


def test_unknown_frequency_method_is_a_vibss_error_with_a_suggestion(plant) -> None:
    with pytest.raises(VibssError, match=r"unknown 'modall'.*did you mean 'modal'"):
        frequency_response(plant, frequencies=F_HZ, method="modall")
    with pytest.raises(ValueError):     # ModelError stays a ValueError
        frequency_response(plant, frequencies=F_HZ, method=3)


def test_sparse_plants_take_only_sparse_capable_methods(reference) -> None:
    ps = build_plant(_model(), INPUTS, OUTPUTS, sparse=True)
    r = frequency_response(ps, frequencies=F_HZ)
    assert r.method == "sparse"
    np.testing.assert_allclose(r.response, reference, rtol=1e-10)
    with pytest.raises(AnalysisError, match="'complex_modal' needs the dense plant"):
        frequency_response(ps, frequencies=F_HZ, method="complex_modal")


def test_damping_projection_is_computed_once_per_plant(plant) -> None:
    from vibss.linear.eigen.basis import modal_basis, projected_damping

    fresh = build_plant(_model(), INPUTS, OUTPUTS)
    basis = modal_basis(fresh)
    g, h = projected_damping(fresh, basis)
    np.testing.assert_allclose(g, basis.phi.T @ fresh.C @ basis.phi, atol=1e-12 * np.abs(g).max())
    np.testing.assert_allclose(g, 2e-3 * np.diag(basis.omega2), atol=1e-9 * np.abs(g).max())  # C = beta K
    assert not np.any(h) and projected_damping(fresh, basis)[0] is g
    keys = [k for k in fresh._cache if k.startswith("projected damping")]
    FREQ["modal"](fresh, 2j * np.pi * F_HZ, basis)
    FREQ["complex_modal"](fresh, 2j * np.pi * F_HZ, basis)
    assert [k for k in fresh._cache if k.startswith("projected damping")] == keys


# ------------------------------------------------------------------------------------- time

DT, T_END = 2e-4, 0.4


def _ramp() -> Excitation:
    return Excitation("push", "force", "b0", Ramp(2e3, start=0.01, end=0.03), dof="z")


@pytest.fixture(scope="module")
def time_reference():
    return simulate(_model(), [_ramp()], outputs=OUTPUTS, t_end=T_END, dt=DT, method="forced_response")


@pytest.mark.parametrize("name", list(TIME))
def test_every_time_method_matches_the_reference(time_reference, name) -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", VibssWarning)
        r = simulate(_model(), [_ramp()], outputs=OUTPUTS, t_end=T_END, dt=DT, method=name, rtol=1e-10)
    assert r.method == name and isinstance(TIME[name], TimeMethod)
    ref = time_reference.outputs
    scale = np.abs(ref).max(axis=1, keepdims=True)
    err = float((np.abs(r.outputs - ref) / scale).max())
    # exact methods to round-off; ivp to its tolerance; the fixed-step integrators to O((w dt)^2)
    tol = 1e-8 if TIME[name].exact else (1e-6 if TIME[name].uses_solver else 2e-2)
    assert err <= tol, (name, err)


def test_time_facts_drive_the_driver() -> None:
    motion = build_plant(_model(), ["ground.z.acc"], ["b2.z"])
    refuse = TimeMethod("forces", TIME["forced_response"].kernel, forces_only=True)
    with pytest.raises(ModelError, match="'forces' takes only force inputs"):
        simulate(motion, inputs={"ground.z.acc": lambda t: np.zeros_like(t)}, t_end=0.01, dt=1e-3,
                 method=refuse)
    for name in ("newmark", "central_difference"):
        assert TIME[name].forces_only
    # a pulse edge between samples: warned about unless the method hits the edges
    pulse = Excitation("kick", "force", "b0", Rectangular(10.0, start=0.01005, duration=0.0101), dof="z")
    for hits, warned in ((False, True), (True, False)):
        m = TimeMethod("m", TIME["forced_response"].kernel, hits_edges=hits)
        with warnings.catch_warnings(record=True) as got:
            warnings.simplefilter("always")
            simulate(_model(), [pulse], outputs=["b2.z"], t_end=0.05, dt=1e-3, method=m)
        assert any("sampling_edges" in str(w.message) for w in got) is warned


def test_a_user_time_method_receives_the_job(time_reference) -> None:
    jobs = []

    def mine(job):
        jobs.append(job)
        return TIME["modal"](job)

    r = simulate(_model(), [_ramp()], outputs=OUTPUTS, t_end=T_END, dt=DT, method=mine)
    assert r.method == "mine" and isinstance(jobs[0], SimulationJob)
    assert jobs[0].breakpoints.tolist() == [0.01, 0.03]
    np.testing.assert_allclose(r.outputs, time_reference.outputs, rtol=0,
                               atol=1e-8 * np.abs(time_reference.outputs).max())
    with pytest.raises(ModelError, match=r"unknown 'modl'.*did you mean 'modal'"):
        simulate(_model(), [_ramp()], t_end=0.01, dt=1e-3, method="modl")


# -------------------------------------------------------------------------------- reduction

SCOPE = Scope(["b0.fz"], ["b2.z", "b1.rx"], 0.0, 40.0, 1e-4)


@pytest.mark.parametrize("name", list(RED))
def test_every_reduction_method_meets_its_tolerance_against_the_exact_frf(name) -> None:
    r = reduce(_model(), SCOPE, method=name, verify=True)
    assert r.method == name and isinstance(RED[name], ReductionMethod)
    assert (r.plant is not None) is RED[name].gives_plant
    w = 2 * np.pi * np.linspace(0.1, 40.0, 157)
    full = frf(r.full, 1j * w)
    err = np.abs(r.response(1j * w) - full).max() / np.abs(full).max()
    # an independent grid: a sampled estimate may be passed between its own check points, so the
    # inexact methods get a factor 2 (balanced: 1.07e-4 here against its "bound" 8.3e-5)
    assert err <= (1e-10 if RED[name].exact else 2 * SCOPE.tolerance), (name, err)
    assert r.measured is not None and r.measured <= SCOPE.tolerance


def test_a_user_reduction_method_gets_plant_scope_options_and_returns_reduced() -> None:
    got = {}

    def identity(plant, scope, options):
        got.update(plant=plant, scope=scope, options=options)
        return Reduced(plant=plant, estimate_kind="exact")

    r = reduce(_model(), SCOPE, method=identity, max_modes=7, verify=True)
    assert r.method == "identity" and got["scope"] is SCOPE and got["options"].max_modes == 7
    assert got["plant"].inputs == ("b0.fz",) and r.measured == 0.0
    with pytest.raises(AnalysisError, match="expected a vibss.reduction.methods.Reduced"):
        reduce(_model(), SCOPE, method=lambda p, s, o: {"plant": p})
    with pytest.raises(ModelError, match=r"unknown 'krilov'.*did you mean 'krylov'"):
        reduce(_model(), SCOPE, method="krilov")


def test_resolver_passes_method_objects_through_and_refuses_junk() -> None:
    from vibss.methods import resolve

    m = Method("x", abs)
    assert resolve(m, {}, where="t") is m and m(-2) == 2
    with pytest.raises(ModelError, match=r"t: method: unknown 42; expected one of \['x'\]"):
        resolve(42, {"x": m}, where="t")
    with pytest.raises(ModelError, match="handled by t itself"):
        resolve("auto", {"x": m}, where="t", extra=["auto"])
