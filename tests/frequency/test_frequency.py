"""Frequency response against closed forms, statics, reciprocity and between methods."""

from __future__ import annotations

import json
import sys

import numpy as np
import pytest

from cases import small as sc
from cases import ROOT
from vibss import AnalysisError, Body, Model, ModelError, Mount, MountType, assemble, symmetric
from vibss.frequency.api import frequency_response
from vibss.frequency.grid import FrequencyGrid, frequency_grid
from vibss.frequency.sweep import sweep_response, transmissibility
from vibss.frequency.kernels import METHODS
from vibss.linear.plant.build import build_plant

import cases.models as cases  # noqa: E402
from cases.models import two_body  # noqa: E402


def sdof(zeta: float = 0.05, fn: float = 1.0, mass: float = 1.0) -> Model:
    """A point mass on one mount at its COG: z is a single DOF (rotations decouple)."""
    k = mass * (2 * np.pi * fn) ** 2
    return cases.sdof(mass, k, 2 * zeta * np.sqrt(k * mass), body="m", mount="s")


def closed_form_t(r, zeta):
    return np.sqrt(1 + (2 * zeta * r) ** 2) / np.sqrt((1 - r**2) ** 2 + (2 * zeta * r) ** 2)


@pytest.mark.parametrize("zeta", [0.01, 0.1, 0.5])
def test_sdof_transmissibility_closed_form(zeta):
    f = np.concatenate([[0.0], np.geomspace(0.05, 20, 200), [1.0]])
    t = closed_form_t(f / 1.0, zeta)
    base = transmissibility(sdof(zeta), ["ground.z"], ["m.z"], frequencies=f)
    force = transmissibility(sdof(zeta), ["m.fz"], ["ground.fz", "mount.s.fz"], frequencies=f)
    np.testing.assert_allclose(np.abs(base.response[0, 0]), t, rtol=1e-10)
    np.testing.assert_allclose(np.abs(force.response[0, 0]), t, rtol=1e-10)
    np.testing.assert_allclose(force.response[1, 0], force.response[0, 0], rtol=1e-12)
    assert base.quantity == "transmissibility" and np.all(np.isfinite(base.response))


def test_zero_hz_is_static_deflection():
    m = two_body()
    a = assemble(m)
    f = np.zeros(12)
    f[8] = 1.0                               # engine.fz
    q = np.linalg.solve(a.K, f)              # independent static solve
    for method in ("auto", "direct", "modal", "complex_modal", "sparse"):
        if method == "modal":
            continue                         # general damping: not eligible
        r = frequency_response(m, ["engine.fz"], frequencies=[0.0, 0.3], method=method)
        np.testing.assert_allclose(r.response[:, 0, 0].real, q, rtol=1e-9, atol=1e-12 * np.abs(q).max())
        assert np.all(r.response[:, 0, 0].imag == pytest.approx(0.0, abs=1e-12 * np.abs(q).max()))


def test_reciprocity_collocated():
    m = two_body()
    pairs = ["engine.fz", "frame.fx", "sensor.fy", "engine.mx"]
    outs = ["engine.z", "frame.x", "sensor.y", "engine.rx"]
    r = frequency_response(m, pairs, outs, frequencies=np.geomspace(0.5, 50, 60), method="direct")
    h = r.response
    np.testing.assert_allclose(h, np.swapaxes(h, 0, 1), rtol=1e-9, atol=1e-12 * np.abs(h).max())


@pytest.mark.parametrize("hysteretic", [False, True])
def test_all_methods_agree_on_asymmetric_nonproportional_case(hysteretic):
    m = two_body()
    if hysteretic:
        m = m.replace(mounts=[Mount(x.name, MountType(x.type.name + "h", x.type.stiffness, x.type.damping, 0.08),
                                    x.body, x.at, x.to, x.orientation) for x in m.mounts])
    ins = ["engine.fz", "sensor.fx", "ground.y.acc", "frame.rz.vel"]
    outs = ["engine.z", "sensor.x.acc", "mount.e2.f1", "ground.fz", "frame.x.vel", "mount.g1.d3"]
    p = build_plant(m, ins, outs)
    f = frequency_grid(p, FrequencyGrid(0.2, 60.0, 300))
    ref = frequency_response(p, frequencies=f, method="direct").response
    methods = ["complex_modal", "woodbury", "sparse", "auto"] + ([] if hysteretic else ["statespace"])
    for method in methods:
        h = frequency_response(p, frequencies=f, method=method).response
        err = np.max(np.linalg.norm(h - ref, axis=(0, 1)) / np.linalg.norm(ref, axis=(0, 1)))
        assert err < 1e-9, (method, err)
    with pytest.raises(AnalysisError, match="classical"):
        frequency_response(p, frequencies=f, method="modal")


def test_modal_on_classical_damping_and_rigid_modes():
    t = MountType("t", [1e4, 2e4, 3e4], [10.0, 20.0, 30.0])           # C = 1e-3 K: classical
    m = Model([Body("b", 50.0, [[2, 0.3, 0], [0.3, 3, 0.1], [0, 0.1, 4]], cog=[0.1, 0, 0.2])],
              list(symmetric(Mount("m", t, "b", at=[0.4, 0.3, -0.2]), "double")))
    free = Model([Body("f", 2.0, [1.0, 2.0, 3.0])])                      # six rigid-body modes
    for model, ins in ((m, ["b.fz", "b.mx", "ground.x.acc"]), (free, ["f.fz", "f.my"])):
        p = build_plant(model, ins)
        f = np.geomspace(0.1, 30, 150)
        ref = frequency_response(p, frequencies=f, method="direct").response
        h = frequency_response(p, frequencies=f, method="modal").response
        assert np.max(np.abs(h - ref)) < 1e-10 * np.abs(ref).max()
    r = frequency_response(free, ["f.fz"], ["f.z", "f.x"], frequencies=[0.0, 1.0], quantity="accelerance")
    assert r.response[0, 0, 0] == pytest.approx(-0.5) or r.response[0, 0, 0] == pytest.approx(0.5)
    assert r.response[1, 0, 0] == 0
    assert np.isinf(frequency_response(free, ["f.fz"], ["f.z"], frequencies=[0.0]).response[0, 0, 0])


def test_displacement_velocity_acceleration_inputs_agree():
    m = two_body()
    f = np.concatenate([[0.0], np.geomspace(0.3, 40, 80)])
    outs = ["engine.z", "mount.g2.d3", "ground.fz", "sensor.x.vel"]
    res = {k: frequency_response(m, [f"frame.ry.{k}", f"ground.z.{k}"], outs, frequencies=f).response
           for k in ("disp", "vel", "acc")}
    s = 2j * np.pi * f[1:]
    np.testing.assert_allclose(res["vel"][..., 1:] * s, res["disp"][..., 1:], rtol=1e-9)
    np.testing.assert_allclose(res["acc"][..., 1:] * s**2, res["disp"][..., 1:], rtol=1e-9)
    # 0 Hz: the displacement of a constant-velocity/acceleration input is unbounded; relative quantities are not
    assert np.isinf(res["vel"][0, 1, 0]) and np.isinf(res["acc"][0, 1, 0])
    assert np.isfinite(res["acc"][1, 1, 0])        # mount deflection under constant ground acceleration
    assert not np.any(np.isnan(res["vel"])) and not np.any(np.isnan(res["acc"]))


def test_reference_case_2_resonances():
    t = MountType("k", [12000.0] * 3)
    b1 = Body("b1", 1000.0, [10.0, 20.0, 30.0])
    b2 = Body("b2", 1000.0, [10.0, 20.0, 30.0])
    pts = [(1, 1, -1), (-1, 1, -1), (-1, -1, -1), (1, -1, -1)]
    mounts = [Mount(f"g{i}", t, "b1", at=p) for i, p in enumerate(pts)]
    mounts += [Mount(f"c{i}", t, "b2", at=p, to="b1") for i, p in enumerate(pts)]
    m = Model([b1, b2], mounts).replace(mounts=[Mount(x.name, MountType("kd", [12000.0] * 3, [12.0] * 3), x.body,
                                                      x.at, x.to) for x in mounts])
    r = frequency_response(m, ["b2.fx", "b2.fz"], ["b1.x", "b2.x", "b1.z", "b2.z"],
                           frequencies={"f1": 0.2, "f2": 3.0, "points": 300})
    peaks_x = sorted(f for f, _ in r.peaks("b2.x", "b2.fx", 2))
    peaks_z = sorted(f for f, _ in r.peaks("b2.z", "b2.fz", 2))
    np.testing.assert_allclose(peaks_x, [0.48, 1.26], atol=0.005)
    np.testing.assert_allclose(peaks_z, [0.68, 1.78], atol=0.005)
    for f in (0.48, 0.68, 1.26, 1.78):
        assert np.min(np.abs(r.natural_hz - f)) < 0.005


def test_grid_refinement_resolves_light_damping():
    m = sdof(zeta=0.001)
    coarse = frequency_response(m, ["m.fz"], ["m.z"], frequencies={"f1": 0.1, "f2": 10, "points": 50, "refine": False})
    fine = frequency_response(m, ["m.fz"], ["m.z"], frequencies={"f1": 0.1, "f2": 10, "points": 50})
    k = (2 * np.pi) ** 2
    exact_peak = 1 / (k * 2 * 0.001 * np.sqrt(1 - 0.001**2))
    assert np.abs(fine.response).max() == pytest.approx(exact_peak, rel=1e-5)
    assert np.abs(coarse.response).max() < 0.5 * exact_peak


def test_sweep_response_and_dict():
    m = sdof(zeta=0.05)
    sw = sweep_response(m, [("m.fz", (10.0, 30.0))], f1=0.5, f2=2.0, points=40, outputs=["m.z"])
    single = frequency_response(m, ["m.fz"], ["m.z"], frequencies=sw.frequency_hz)
    a = 10.0 + 20.0 * (sw.frequency_hz - 0.5) / 1.5
    np.testing.assert_allclose(sw.response[0, 0], single.response[0, 0] * a, rtol=1e-12)
    d = json.loads(json.dumps(sw.to_dict()))
    assert set(d) >= {"frequency_hz", "outputs"} and set(d["outputs"]["m.z"]) >= {"amplitude", "phase_deg"}
    assert len(d["outputs"]["m.z"]["amplitude"]) == sw.frequency_hz.size
    assert "m.z" in sw.report()
    from vibss.model.excitation import Excitation, SineSweep
    e = Excitation("sw", "force", "m", SineSweep(f1=0.5, f2=2.0, a1=10.0, a2=30.0), dof="z")
    sw2 = sweep_response(m.replace(excitations=[e]), points=40, outputs=["m.z"])
    np.testing.assert_allclose(sw2.response, sw.response, rtol=1e-12)
    with pytest.raises(AnalysisError, match="transient"):
        sweep_response(m, [Excitation("t", "force", "m", SineSweep(0.5, 2.0, 1.0, 1.0, sweep_time=5.0), dof="z")])


def test_errors_and_result_api():
    m = sdof()
    with pytest.raises(ValueError, match="direct"):
        frequency_response(m, ["m.fz"], method="fast")
    with pytest.raises(ValueError, match="quantity"):
        frequency_response(m, ["m.fz"], quantity="compliance")
    with pytest.raises(ModelError, match="did you mean"):
        frequency_response(m, ["m.fzz"])
    r = frequency_response(m, ["m.fz", "m.fx"], ["m.z", "m.x"], frequencies=[0.5, 1.0, 2.0],
                           method=lambda p, s: METHODS["direct"](p, s))
    assert r.method == "<lambda>" and r.frd.noutputs == 2
    assert r.to_pandas().shape == (3, 4)
    assert set(r.to_dict()["inputs"]) == {"m.fz", "m.fx"}
    mob = frequency_response(m, ["m.fz"], ["m.z"], frequencies=[0.0, 1.5], quantity="mobility")
    assert abs(mob.response[0, 0, 0]) < 1e-15 and np.isfinite(mob.response).all()


def test_plot_all_and_by_body() -> None:
    import matplotlib

    matplotlib.use("Agg")
    from cases.models import two_mass_model

    r = frequency_response(two_mass_model(), ["body1.fx"], ["body1.x", "body2.x", "body2.z"],
                           frequencies=np.linspace(0.1, 3.0, 50))
    assert len(r.plot().axes) == 2
    fig = r.plot(by="body")
    assert len(fig.axes) == 4 and [a.get_title() for a in fig.axes[:2]] == ["body1", "body2"]
    with pytest.raises(ValueError, match="by must be"):
        r.plot(by="mount")


@pytest.mark.parametrize("case", ["free body", "bodies joined only to each other", "damper-only mounts"])
def test_complex_modal_with_rigid_modes_matches_direct(case: str) -> None:
    """Rigid modes untouched by dampers are exact 1/s^2 terms; damped ones repeat eigenvalue 0."""
    t1 = MountType("t1", [1e4, 2e4, 3e4], [20.0, 5.0, 1.0])
    t2 = MountType("t2", [5e3] * 3, [50.0] * 3)
    a, b = Body("a", 10.0, [1, 2, 3]), Body("b", 5.0, [1, 1, 1])
    if case == "free body":
        model = Model([a, b, Body("free", 2.0, [1, 1, 1])],
                      [Mount("m1", t1, "a", at=[0.3, 0.2, -0.1]), Mount("m2", t1, "a", at=[-0.3, 0.1, -0.1]),
                       Mount("m3", t1, "a", at=[0, -0.2, -0.1]), Mount("m4", t2, "b", to="a", at=[0.1, 0, 0.2])])
        inputs, outputs = ["free.fz", "a.fz"], ["free.z", "b.x", "a.z"]
    elif case == "bodies joined only to each other":
        model = Model([a, b], [Mount("m4", t2, "b", to="a", at=[0.1, 0, 0.2]),
                               Mount("m5", t1, "b", to="a", at=[-0.1, 0.1, -0.2])])
        inputs, outputs = ["a.fz", "b.fx"], ["b.z", "a.x"]
    else:
        dashpot = MountType("dashpot", [0.0, 0.0, 0.0], [30.0, 40.0, 50.0])
        model = Model([a, b], [Mount("d1", dashpot, "a", at=[0.2, 0, 0]), Mount("d2", dashpot, "a", at=[-0.2, 0.1, 0]),
                               Mount("d3", dashpot, "a", at=[0, -0.2, 0.1]), Mount("m4", t2, "b", to="a", at=[0.1, 0, 0.2])])
        inputs, outputs = ["a.fz", "b.fx"], ["b.z", "a.x"]
    f = np.linspace(0.5, 40.0, 40)
    ref = frequency_response(model, inputs, outputs, frequencies=f, method="direct").response
    for method in ("complex_modal", "sparse"):
        got = frequency_response(model, inputs, outputs, frequencies=f, method=method).response
        err = max(np.linalg.norm(got[..., k] - ref[..., k]) / np.linalg.norm(ref[..., k]) for k in range(f.size))
        assert err < 1e-9, method


@pytest.mark.parametrize("method", ["direct", "sparse"])
@pytest.mark.parametrize("quantity,power", [("receptance", 0), ("mobility", 1), ("accelerance", 2)])
def test_undamped_exactly_at_resonance_is_infinite_not_an_error(quantity: str, power: int, method: str) -> None:
    """Found in review: the direct solve raised LinAlgError; k - m w^2 = 0 there, so |H| = inf."""
    k = (2 * np.pi) ** 2                                     # 1 kg on k: f_n = 1 Hz
    m = Model([Body("b", 1.0, [1, 1, 1])], [Mount("m", MountType("t", [k] * 3), "b")])
    r = frequency_response(m, ["b.fz"], ["b.z"], frequencies=[0.5, 1.0, 2.0], method=method, quantity=quantity)
    h = r.response[0, 0]
    assert np.isinf(h[1].real) and np.all(np.isfinite(h[[0, 2]]))
    for i, f in ((0, 0.5), (2, 2.0)):
        w = 2 * np.pi * f
        assert h[i] == pytest.approx((1j * w) ** power / (k - w**2), rel=1e-12)
    assert r.to_dict()["outputs"]["b.z"]["amplitude"][1] is None      # JSON: null, not Infinity


def test_json_with_several_inputs_keeps_the_spec_outputs_key() -> None:
    """Found in review: several inputs dropped the spec's top-level "outputs"."""
    from cases.models import two_mass_model

    r = frequency_response(two_mass_model(), ["body1.fx", "body2.fx"], ["body2.x"], frequencies=[0.3, 1.0])
    d = json.loads(json.dumps(r.to_dict()))
    assert set(d["outputs"]) == {"body2.x/body1.fx", "body2.x/body2.fx"}
    assert d["outputs"]["body2.x/body2.fx"] == d["inputs"]["body2.fx"]["outputs"]["body2.x"]
    # reciprocity of the chain: x of body 2 per force on body 1 equals x of body 1 per force on body 2
    r2 = frequency_response(two_mass_model(), ["body2.fx"], ["body1.x"], frequencies=[0.3, 1.0])
    np.testing.assert_allclose(d["outputs"]["body2.x/body1.fx"]["amplitude"], r2.to_dict()["outputs"]["body1.x"]["amplitude"],
                               rtol=1e-10)


def test_report_gives_the_band_edge_maximum_when_no_peak_is_inside() -> None:
    """Found in review: the text said amplitude 0 when the largest response sat at a band edge."""
    from cases.models import two_mass_model

    r = frequency_response(two_mass_model(), ["body1.fx"], ["body2.x"], frequencies=np.linspace(0.1, 0.3, 21),
                           method="direct")
    line = r.report().splitlines()[-1]
    assert "no peak inside" in line and "0.3000" in line
    assert f"{abs(r.response[0, 0, -1]):.4e}" in line        # the value at 0.3 Hz, below the first mode


def _chain(n_bodies: int, shuffle: bool, extra: int = 0, seed: int = 3) -> Model:
    """Bodies in a chain (each joined to ground and to the next), listed in shuffled order, and
    ``extra`` random long-range mounts (which widen the band)."""
    rng = np.random.default_rng(seed)
    order = rng.permutation(n_bodies) if shuffle else np.arange(n_bodies)
    bodies = [Body(f"b{i}", float(rng.uniform(5, 50)), rng.uniform(1.0, 1.5, 3).tolist(), cog=[float(i), 0, 0])
              for i in order]

    def mt(name):
        k = rng.uniform(1e4, 1e5, 3)
        return MountType(name, k.tolist(), (k * rng.uniform(1e-4, 1e-3, 3)).tolist())   # non-proportional

    mounts = [Mount(f"g{i}", mt(f"g{i}"), f"b{i}", at=rng.uniform(-0.3, 0.3, 3).tolist()) for i in range(n_bodies)]
    mounts += [Mount(f"n{i}", mt(f"n{i}"), f"b{i}", to=f"b{i - 1}", at=rng.uniform(-0.3, 0.3, 3).tolist())
               for i in range(1, n_bodies)]
    for j in range(extra):
        a, b = rng.choice(n_bodies, 2, replace=False)
        mounts.append(Mount(f"x{j}", mt(f"x{j}"), f"b{a}", to=f"b{b}", at=rng.uniform(-0.3, 0.3, 3).tolist()))
    return Model(bodies, mounts)


@pytest.mark.parametrize("shuffle, extra, banded", [(False, 0, True), (True, 0, True), (True, 12, False)])
def test_sparse_method_matches_direct_banded_and_superlu(shuffle: bool, extra: int, banded: bool) -> None:
    """The reverse Cuthill-McKee ordering finds the chain's narrow band whatever the body order
    (each body couples to its neighbours: half-bandwidth under 3 bodies, 18 DOFs); long-range mounts
    widen it past BAND_MAX and SuperLU takes over. Both equal the dense direct solve."""
    from vibss.linear.solve.banded import BAND_MAX, structure

    model = _chain(16, shuffle, extra)
    ins = ["b3.fz", "b11.mx", "ground.y.acc"]
    outs = ["b0.z", "b15.rx", "mount.n7.f2", "ground.fz", "b8.y.vel"]
    p = build_plant(model, ins, outs)
    st = structure(p)
    assert st.banded is banded and (st.band < 18 if banded else st.band > BAND_MAX)
    f = np.geomspace(0.5, 80.0, 120)
    ref = frequency_response(p, frequencies=f, method="direct").response
    got = frequency_response(p, frequencies=f, method="sparse").response
    err = np.max(np.linalg.norm(got - ref, axis=(0, 1)) / np.linalg.norm(ref, axis=(0, 1)))
    assert err < 1e-10


def _rel_max(h: np.ndarray, ref: np.ndarray) -> float:
    return float(np.max(np.linalg.norm(h - ref, axis=(0, 1)) / np.linalg.norm(ref, axis=(0, 1))))


@pytest.mark.parametrize("c", [1e-1, 1e-3, 1e-7])
def test_complex_modal_lightly_damped_rigid_mode(c: float) -> None:
    """Found in review: a body hanging on a damper of c N s/m has a rigid mode decaying at c/m;
    partial fractions in 1/lam lost eps |s|/|lam| and raised at c = 1e-7. Now 1/(s (s - lam))."""
    m = Model([Body("b", 1000.0, [100, 120, 140]), Body("e", 100.0, [10, 12, 14], cog=[0, 0, 1]),
               Body("c", 10.0, [1, 1, 1], cog=[1, 0, 0])],
              list(symmetric(Mount("g", MountType("g", [1e7] * 3, [1e4] * 3), "b", at=[1, 1, 0])))
              + list(symmetric(Mount("ge", MountType("ge", [1e6] * 3, [1e2, 1e3, 1e2]), "e", to="b",
                                     at=[0.5, 0.5, -0.5])))
              + [Mount("d", MountType("d", [0, 0, 0], [c] * 3), "c", to="b", at=[0.1, 0.1, 0.1])])
    f = np.geomspace(0.1, 1000, 120)
    args = (m, ["b.fz", "c.fx"], ["b.z", "c.x"], f)
    ref = frequency_response(*args, method="direct").response
    assert _rel_max(frequency_response(*args, method="complex_modal").response, ref) < 1e-10


def test_critically_damped_mode_refused_by_complex_modes_and_auto_goes_sparse() -> None:
    """Found in review: a critically damped mode is a Jordan block; V is singular and the modal
    sum was wrong by 2x. complex_modal now refuses (cond(V)), and auto falls back to sparse."""
    k, c = 1e4, 2 * np.sqrt(1e4)
    base = two_body()
    m = Model(list(base.bodies) + [Body("iso", 1.0, [0.1, 0.12, 0.14], cog=[3, 0, 0])],
              list(base.mounts) + list(symmetric(Mount("iso", MountType("tiso", [3 * k / 4, k / 2, k / 4],
                                                                      [0.01 * c, 0.01 * c, c / 4]),
                                                       "iso", at=[0.3, 0.2, 0.0]))))   # z: critical
    args = (m, ["iso.fz", "engine.fz"], ["iso.z", "engine.x"], {"f1": 0.0, "f2": 100, "points": 200})
    with pytest.raises(AnalysisError, match="nearly dependent"):
        frequency_response(*args, method="complex_modal")
    ref = frequency_response(*args, method="direct").response
    r = frequency_response(*args)
    assert r.method == "sparse" and "complex_modal refused" in r.reason
    assert _rel_max(r.response[..., 1:], ref[..., 1:]) < 1e-10


def test_auto_is_exact_on_badly_scaled_models_and_avoids_complex_modes_on_undamped_ones() -> None:
    """Found in review: eig's pole error eps max|lam| (overdamped modes) swamps slowly decaying
    modes of a badly scaled model (1e-6 error, or a false 'zero eigenvalue' raise). Complex modes now
    screen and refine those poles, so ``auto`` may take them there, costed with the refinement;
    whichever it takes must meet the dense solve."""
    sys.path.insert(0, str(ROOT / "benchmarks"))
    from models import chain_model

    m = chain_model(10, "general", scale="bad")
    f = np.geomspace(0.05, 1000, 150)
    r = frequency_response(m, ["b0.fz"], ["b1.x", "b4.z"], f)
    assert r.method in ("sparse", "complex_modal") and "slow poles refined" in r.reason
    ref = frequency_response(m, ["b0.fz"], ["b1.x", "b4.z"], f, method="direct").response
    assert _rel_max(r.response, ref) < 1e-8
    frequency_response(m, ["b0.fz"], ["b1.x"], f, method="complex_modal")   # no false raise
    und = frequency_response(chain_model(3, "none"), ["b0.fz"], ["b2.x"], f)
    assert und.method == "sparse" and und.reason.startswith("undamped")


def test_modal_exactly_at_undamped_resonance_is_inf_only_where_the_mode_shows() -> None:
    """Found in review: 1/0 in the modal sum spread NaN to every channel."""
    m = Model([Body("b", 1.0, [1, 1, 1])], [Mount("m", MountType("u", [4.0, 16.0, 9.0]), "b")])
    h = frequency_response(m, ["b.fz", "b.fx"], ["b.z", "b.x"], [1 / np.pi], method="modal").response[..., 0]
    assert h[0, 0] == pytest.approx(1 / (9.0 - 4.0)) and h[0, 1] == 0 and h[1, 0] == 0
    assert np.isinf(h[1, 1]) and not np.any(np.isnan(h))


def test_sparse_plant_frequency_response_needs_no_dense_matrix() -> None:
    """Found in review: a sparse plant could not go through frequency_response (dense modes first).
    build_plant(sparse=True) keeps M, C, K, H sparse; the result equals the dense plant's."""
    import scipy.sparse as sp

    model = _chain(12, shuffle=True)
    ins, outs = ["b3.fz", "ground.y.acc"], ["b0.z", "mount.n7.f2", "b8.into.fz", "b8.y.vel"]
    ps = build_plant(model, ins, outs, sparse=True)
    pd = build_plant(model, ins, outs)
    assert sp.issparse(ps.K) and sp.issparse(ps.M)
    np.testing.assert_array_equal(ps.K.toarray(), pd.K)
    f = np.geomspace(0.5, 80.0, 60)
    for quantity in ("receptance", "accelerance"):
        r = frequency_response(ps, frequencies=f, quantity=quantity)
        ref = frequency_response(pd, frequencies=f, method="direct", quantity=quantity)
        assert r.method == "sparse" and r.reason.startswith("sparse plant") and r.natural_hz.size == 0
        assert r.units == ref.units
        assert _rel_max(r.response, ref.response) < 1e-10
    with pytest.raises(ModelError, match="needs explicit"):
        frequency_response(ps)
    with pytest.raises(ModelError, match="frequencies > 0"):
        frequency_response(ps, frequencies=[0.0, 1.0])
    with pytest.raises(AnalysisError, match="needs the dense plant"):
        frequency_response(ps, frequencies=f, method="modal")
    with pytest.raises(ModelError, match="modal_damping"):
        build_plant(model, ins, outs, modal_damping=0.01, sparse=True)


def test_sparse_plant_refused_clearly_where_dense_matrices_are_needed() -> None:
    from vibss.linear.statespace import statespace
    from vibss.time.api import simulate

    ps = build_plant(_chain(4, shuffle=False), ["b0.fz"], ["b1.z"], sparse=True)
    with pytest.raises(AnalysisError, match="sparse matrices"):
        statespace(ps)
    with pytest.raises(AnalysisError, match="sparse matrices"):
        simulate(ps, inputs={"b0.fz": lambda t: np.ones_like(t)}, t_end=0.01, dt=1e-3)


# == moved from the file of review-round fixes: frequency grid and peaks ===================

# 6 -- frequencies argument ------------------------------------------------------------------------

@pytest.mark.parametrize("frequencies, message", [
    ([], r"frequencies: got an empty list"),
    ({"f1": 1, "f2": 5, "points": "x"}, r"frequencies: points: expected an integer >= 2, got 'x'"),
    ({"f1": "a", "f2": 5}, r"frequencies: f1: expected a frequency >= 0 \[Hz\] or None, got 'a'"),
    ({"f1": 1, "f2": 5, "points": 2.5}, r"frequencies: points: expected an integer >= 2, got 2.5"),
    ({"f1": 1, "f2": 5, "points": 1}, r"frequencies: points: expected an integer >= 2, got 1"),
    ({"f1": 1, "f2": 5, "spacing": "lin"}, r"frequencies: spacing: expected 'log' or 'linear'"),
    ("abc", r"frequencies: expected finite frequencies >= 0"),
])
def test_bad_frequencies_are_model_errors(frequencies: object, message: str) -> None:
    with pytest.raises(ModelError, match=message):
        frequency_response(sc.sdof(), ["b.fz"], ["b.z"], frequencies=frequencies)


def test_integral_float_points_are_accepted() -> None:
    r = frequency_response(sc.sdof(), ["b.fz"], ["b.z"],
                           frequencies={"f1": 1, "f2": 5, "points": 10.0, "spacing": "linear", "refine": False})
    np.testing.assert_allclose(r.frequency_hz, np.linspace(1, 5, 10))


# 7 -- peaks beside an infinite 0 Hz value ----------------------------------------------------------

def test_no_peak_beside_an_infinite_zero_hz_value() -> None:
    f = np.concatenate([[0.0, 0.005, 0.01], np.linspace(1, 10, 901)])
    r = frequency_response(sc.sdof(), ["ground.z.acc"], ["b.z"], frequencies=f)
    assert np.isinf(r.channel("b.z")[0])
    peaks = r.peaks("b.z")
    assert len(peaks) == 1
    fp, a = peaks[0]
    w = 2 * np.pi * fp
    np.testing.assert_allclose(a, abs((sc.K + 1j * w * sc.C) / (sc.K - sc.M * w**2 + 1j * w * sc.C)) / w**2, rtol=1e-10)
    assert abs(fp - sc.WN / (2 * np.pi)) < 0.02
    assert "infinite" in r.report()


def test_grid_without_refinement_keeps_exactly_the_base_points():
    """Issue 16: refine=False (CLI --no-refine) gives exactly `points` frequencies, the geometric
    series from f1 to f2; refine=True adds points at the resonances inside the band."""
    import vibss
    from vibss.frequency.grid import FrequencyGrid
    from vibss.frequency.sweep import sweep_response

    model = vibss.load_example("prism")
    r = vibss.frequency_response(model, ["prism.fz"], ["prism.z"],
                                 frequencies=FrequencyGrid(1.0, 100.0, 5, refine=False))
    assert np.allclose(r.frequency_hz, [1.0, 10**0.5, 10.0, 10**1.5, 100.0])
    r = vibss.frequency_response(model, ["prism.fz"], ["prism.z"], frequencies={"points": 7, "refine": False})
    assert r.frequency_hz.size == 7
    refined = vibss.frequency_response(model, ["prism.fz"], ["prism.z"], frequencies={"points": 7})
    assert refined.frequency_hz.size > 7
    sw = sweep_response(vibss.load_example("powertrain"), points=5, refine=False)
    assert sw.frequency_hz.size == 5


def test_large_models_with_explicit_frequencies_stay_sparse(monkeypatch) -> None:
    """Above LARGE_DOFS a Model asked for explicit frequencies is solved sparse, with no dense
    eigen-analysis (it took 200 s at 6,000 DOF); the answer equals the dense path's."""
    import vibss
    import vibss.frequency.methods as fa
    from vibss import Body, Model, Mount, MountType

    t = MountType("t", [1e4, 2e4, 3e4], [10.0, 20.0, 30.0])
    bodies = [Body(f"b{i}", 2.0 + i, [0.1, 0.2, 0.3], cog=[i, 0.0, 0.0]) for i in range(3)]
    mounts = [Mount(f"g{i}", t, f"b{i}", at=[0.1, 0.2, -0.1]) for i in range(3)]
    mounts += [Mount(f"n{i}", t, f"b{i}", at=[-0.5, 0.0, 0.0], to=f"b{i - 1}") for i in (1, 2)]
    m = Model(bodies, mounts)
    f = np.array([2.0, 7.0, 19.0])
    dense = vibss.frequency_response(m, ["b0.fz"], ["b0.z", "b2.x"], frequencies=f)
    monkeypatch.setattr(fa, "LARGE_DOFS", 12)
    sparse = vibss.frequency_response(m, ["b0.fz"], ["b0.z", "b2.x"], frequencies=f)
    assert sparse.method == "sparse" and "kept sparse" in sparse.note and sparse.natural_hz.size == 0
    np.testing.assert_allclose(sparse.response, dense.response, rtol=1e-12)
    # a grid spec needs the modes: the dense path stays
    assert "kept sparse" not in vibss.frequency_response(m, ["b0.fz"], ["b0.z"], frequencies={"f1": 1, "f2": 30, "points": 5}).note
