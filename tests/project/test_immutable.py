"""Issue 18: what a result, an assembly or a plant hands out cannot be changed from outside.

Before, ``md.omega[:] = 0`` went through and the cached ``md.frequency_hz`` kept the old values
(two answers from one result); ``K = asm.dense('K'); K *= 4`` doubled every later frequency. The
walk below visits every public result type (and the plain-data results of the design, orders,
random and shock packages), reads every public attribute, and for every array it finds (nested in
tuples, lists and dicts too) requires either that writing to it fails, or that it is a fresh copy
made on each access (so that writing to it changes nothing the object holds).
"""

from __future__ import annotations

import dataclasses
import pickle
from collections.abc import Iterator
from typing import Any

import numpy as np
import pytest
import scipy.sparse as sp

import cases.models as cases
import vibss
from vibss import (Body, Excitation, Model, Mount, MountType, Scope, damped_modes, frequency_response,
                   modes, reduce, simulate, static, sweep_envelope, symmetric)
from vibss.design import (certificate, design_axes, elastic_axes, monte_carlo, optimize, sensitivity,
                          torque_response)
from vibss.linear.plant.build import build_plant
from vibss.model.excitation import SineSweep, Step
from vibss.orders import Unbalance, order_response
from vibss.results import Result, read_only
from vibss.control.filespec import run_control
from vibss.shock.filespec import run_shock

SKIP = {"control", "frd", "data", "model", "plot", "deterministic", "reliable"}
"""Attributes not walked: python-control twins (their own objects), the model (frozen data with
its own tests), methods; nested results are walked as results of their own."""


def box() -> Model:
    return cases.box(10.0, [1.0, 1.2, 1.5], [1e4, 1.2e4, 2e4], 20.0, at=[0.3, 0.2, 0.1],
                     gravity=[0.0, 0.0, -9.81], name="box")


@pytest.fixture(scope="module")
def objects() -> dict[str, Any]:
    m = box()
    und = modes(m)
    pt = vibss.load_example("powertrain")
    sweep = Excitation("sw", "force", "b", SineSweep(f1=2.0, f2=6.0, a1=1.0, a2=1.0, sweep_time=2.0), dof="z")
    t = np.linspace(0.0, 0.02, 201)
    tr = simulate(m, [Excitation("s", "force", "b", Step(5.0), dof="z")], outputs=["b.z"], t_end=0.2, dt=1e-3)
    return {
        "static": static(m),
        "modes": und,
        "damped": damped_modes(m, und),
        "frequency": frequency_response(m, ["b.fz"], ["b.z"], frequencies=[0.0, 1.0, 3.0]),
        "update": vibss.update(m, frequency_response(m, ["b.fz"], ["b.z"], frequencies=[1.0, 3.0, 9.0]), ["m.k3"]),
        "time": tr,
        "peaks": tr.peaks() if hasattr(tr, "peaks") else None,
        "sweep": sweep_envelope(m, sweep, outputs=["b.z"], points=20),
        "reduction": reduce(m, Scope(["b.fz"], ["b.z"], 0.0, 20.0, 1e-6), method="modal"),
        "assembly": vibss.assemble(m),
        "sparse assembly": vibss.assemble(m, sparse=True),
        "plant": build_plant(m, ["b.fz"], ["b.z"]),
        "certificate": certificate(pt),
        "sensitivity": sensitivity(pt, ["engine.k3"]),
        "monte carlo": monte_carlo(pt, {"engine.k3": 0.1}, n=8, sampling="random", seed=1),
        "optimisation": optimize(m, {"m.k3": (1e4, 3e4)}, modes=["z"], purity=0.5, maxiter=2),
        "elastic axes": elastic_axes(m),
        "torque response": torque_response(m, "b", "x"),
        "design axes": design_axes(m),
        "orders": order_response(m, Unbalance("u", "b", 0.01, 0.05, axis="x"), [600.0, 1200.0], ["b.z"]),
        "random": vibss.random_response(m, {"b.fz": ([1.0, 100.0], [1.0, 1.0])}, ["b.z"]),
        "srs": vibss.srs(t, np.sin(2 * np.pi * 50 * t), [20.0, 50.0]),
        "envelope": vibss.srs(t, np.sin(2 * np.pi * 50 * t), [20.0, 50.0]).check([20.0, 50.0], [1.0, 1.0]),
        "shock study": run_shock(vibss.load_example("packaged_item")),
        "operating point": vibss.operating_point(Model([Body("b", 10.0, [1.0, 1.2, 1.5])], vibss.symmetric(Mount(
            "m", MountType("snub", [1e4, 1.2e4, 2e4], stops={"z": (1e-3, 1e6)}), "b", at=[0.3, 0.2, 0.1])),
            gravity=[0.0, 0.0, -9.81])),
        "harmonic balance": vibss.harmonic_balance(Model([Body("b", 10.0, [1.0, 1.2, 1.5])], [Mount(
            "m", MountType("snub", [1e4, 1.2e4, 2e4], [20.0] * 3, stops={"z": (1e-3, 1e6)}), "b")]),
            {"b.fz": 5.0}, ["b.z"], frequencies=[2.0, 4.0], harmonics=3),
        **control_objects(),
        **insight_objects(m),
    }


def insight_objects(m: Model) -> dict[str, Any]:
    """The energy distribution, modal and path contributions of the box."""
    return {
        "energy": vibss.energy_distribution(m, "strain"),
        "modal contributions": vibss.modal_contributions(m, ["b.fz"], ["b.z"], [1.0, 3.0, 9.0]),
        "paths": vibss.path_contributions(m, ["b.fz"], [1.0, 3.0]),
        "time contributions": vibss.time_contributions(m, inputs={"b.fz": np.ones(11)}, outputs=["b.z"], t_end=0.1,
                                                       dt=0.01),
    }


def control_objects() -> dict[str, Any]:
    """The closed loop, its demand, a semi-active run and a file's control study of small models."""
    import vibss.control as vc
    from vibss.model.actuation import Actuator, Sensor
    from vibss.random import PSD

    t = MountType("iso", [1e4] * 3, [20.0] * 3)
    m = Model([Body("b", 10.0, [1, 1, 1])], [Mount("m", t, "b")], actuators=[Actuator("a", mount="m", axis=3)],
              sensors=[Sensor("v", "velocity", body="b", direction=[0, 0, 1]),
                       Sensor("rv", "relative_velocity", mount="m", axis=3),
                       Sensor("s", "relative_displacement", mount="m", axis=3)])
    P = vc.plant(m, ["ground.z.acc"], performance=["b.z.acc"], measurements=["sensor.rv", "sensor.s"], dofs=["b.z"])
    cl = vc.close(P, vc.velocity_feedback(P, 100.0, pairs={"a": "sensor.rv"}))
    Pv = vc.plant(m, ["ground.z.vel"], performance=["b.z.vel"], measurements=["sensor.v", "sensor.rv"], dofs=["b.z"])
    return {
        "closed loop": cl,
        "demand": cl.demand({"ground.z.acc": PSD([1.0, 100.0], [0.01, 0.01])}, ["sensor.s"]),
        "semi-active": vc.clipped_skyhook(Pv, {"ground.z.vel": vibss.HalfSine(0.2, start=0.0, duration=0.02)},
                                          end=0.1, step=1e-3, c_sky=400.0, c_min=5.0, c_max=300.0),
        "control study": run_control(vibss.load_example("platform")),
        "robustness": vc.robustness(Pv, vc.skyhook(Pv, 150.0), {"m.k3": 0.2}, n=5),
        "tuning": vc.tune(Pv, "skyhook", [("damping", ">=", 0.2)], maxiter=20),
        "noise budget": cl.noise_budget(["b.z.acc"], [1.0, 2.0], noise={"sensor.rv": 1e-10}),
    }


def arrays(value: Any, path: str, depth: int = 0) -> Iterator[tuple[str, np.ndarray]]:
    """Every ndarray in ``value`` (and the arrays of a sparse matrix), with where it was found."""
    if depth > 4:
        return
    if isinstance(value, np.ndarray) and value.dtype != object:
        yield path, value
    elif sp.issparse(value):
        for k in ("data", "indices", "indptr"):
            if hasattr(value, k):
                yield f"{path}.{k}", getattr(value, k)
    elif isinstance(value, (tuple, list)):
        for i, v in enumerate(value):
            yield from arrays(v, f"{path}[{i}]", depth + 1)
    elif isinstance(value, dict):
        for k, v in value.items():
            yield from arrays(v, f"{path}[{k!r}]", depth + 1)


def public_values(obj: Any) -> Iterator[tuple[str, Any]]:
    """Every public data attribute of ``obj`` (fields, properties, cached properties)."""
    for name in dir(obj):
        if name.startswith("_") or name in SKIP:
            continue
        try:
            value = getattr(obj, name)
        except Exception:                       # a property that needs more (e.g. a missing option)
            continue
        if callable(value) and not isinstance(value, np.ndarray):
            continue
        yield name, value


def writable_handles(obj: Any) -> list[str]:
    """Paths of arrays reachable from ``obj`` that can be changed in place and are not fresh copies."""
    bad = []
    for name, value in public_values(obj):
        again = dict(public_values(obj)).get(name)
        for path, a in arrays(value, name):
            if not a.flags.writeable:
                with pytest.raises(ValueError, match="read-only"):
                    a[...] = a
                continue
            # writeable is allowed only for a copy made on each access (changing it changes nothing)
            if any(np.shares_memory(a, b) for _, b in arrays(again, name)):
                bad.append(path)
    return bad


KINDS = ["static", "modes", "damped", "frequency", "time", "peaks", "sweep", "reduction", "assembly",
         "sparse assembly", "plant", "certificate", "sensitivity", "monte carlo", "optimisation",
         "elastic axes", "torque response", "design axes", "orders", "random", "srs", "envelope", "shock study", "closed loop",
         "demand", "semi-active", "control study", "operating point", "energy", "modal contributions", "paths"]


def test_every_public_result_type_is_in_the_walk(objects: dict[str, Any]) -> None:
    public = set()
    import vibss.control
    import vibss.insight

    for module in (vibss, vibss.design, vibss.orders, vibss.random, vibss.shock, vibss.control, vibss.insight):
        public |= {getattr(module, n) for n in module.__all__
                   if isinstance(getattr(module, n), type) and issubclass(getattr(module, n), Result)}
    walked = {type(o) for o in objects.values()}
    assert public <= walked, sorted(c.__name__ for c in public - walked)


@pytest.mark.parametrize("kind", KINDS)
def test_no_array_handed_out_can_be_changed(objects: dict[str, Any], kind: str) -> None:
    obj = objects[kind]
    if obj is None:
        pytest.skip("no peak table")
    assert writable_handles(obj) == []


@pytest.mark.parametrize("kind", KINDS)
def test_pickled_results_stay_read_only(objects: dict[str, Any], kind: str) -> None:
    obj = objects[kind]
    if obj is None or kind in ("optimisation",):
        pytest.skip("not pickled here")
    back = pickle.loads(pickle.dumps(obj))
    assert writable_handles(back) == []
    for name, value in public_values(obj):
        for (path, a), (_, b) in zip(arrays(value, name), arrays(getattr(back, name), name)):
            np.testing.assert_array_equal(a, b, err_msg=path)


def test_cached_frequencies_cannot_go_stale() -> None:
    """The campaign's case: ``md.omega[:] = 0`` passed and ``md.frequency_hz`` kept the old values."""
    md = modes(box())
    hz = md.frequency_hz.copy()
    with pytest.raises(ValueError, match="read-only"):
        md.omega[:] = 0
    with pytest.raises(ValueError, match="read-only"):
        md.shapes *= 2
    np.testing.assert_array_equal(md.frequency_hz, hz)
    np.testing.assert_allclose(2 * np.pi * md.frequency_hz, md.omega, rtol=1e-15)


def test_assembly_and_plant_changes_cannot_reach_later_analyses() -> None:
    m = box()
    for asm in (vibss.assemble(m), vibss.assemble(m, sparse=True)):
        before = modes(asm).frequency_hz
        with pytest.raises(ValueError, match="read-only"):
            asm.kp[0] *= 4
        if sp.issparse(asm.K):
            with pytest.raises(ValueError, match="read-only"):
                asm.K.data[:] *= 4
        np.testing.assert_array_equal(modes(asm).frequency_hz, before)
    plant = build_plant(m, ["b.fz"], ["b.z"])
    with pytest.raises(ValueError, match="read-only"):
        plant.K[2, 2] = 0.0


def test_the_callers_arrays_stay_theirs() -> None:
    """Freezing a result never freezes the array the caller passed in (a read-only view is kept)."""
    t = np.linspace(0.0, 0.02, 201)
    x = np.sin(2 * np.pi * 50 * t)
    f = np.array([20.0, 50.0])
    r = vibss.srs(t, x, f)
    assert t.flags.writeable and x.flags.writeable and f.flags.writeable
    assert not r.frequency_hz.flags.writeable
    mine = np.zeros(3)
    assert not read_only(mine).flags.writeable and mine.flags.writeable


def test_results_are_still_frozen_dataclasses(objects: dict[str, Any]) -> None:
    for kind in KINDS:
        obj = objects[kind]
        if obj is None or not dataclasses.is_dataclass(obj):
            continue
        name = dataclasses.fields(obj)[0].name
        with pytest.raises(dataclasses.FrozenInstanceError):
            setattr(obj, name, None)


def test_assembly_matrices_cannot_be_changed_from_outside():
    """Issue 18: `K = asm.dense('K'); K *= 4` doubled every later frequency of modes(asm)."""
    import pytest

    asm = vibss.assemble(vibss.load_example("two_mass"), sparse=True)
    before = vibss.modes(asm).frequency_hz
    K = asm.dense("K")
    with pytest.raises(ValueError, match="read-only"):
        K *= 4
    np.testing.assert_array_equal(vibss.modes(asm).frequency_hz, before)
    mine = asm.dense("K").copy()
    mine *= 4                                           # a copy is the user's to change
    assert np.allclose(mine, 4 * asm.dense("K"))


@pytest.mark.parametrize("kind", ["static", "modes", "damped", "frequency", "time", "peaks", "sweep", "reduction",
                                  "certificate", "sensitivity", "monte carlo", "optimisation", "design axes",
                                  "orders", "random", "srs", "energy", "modal contributions", "paths",
                                  "harmonic balance"])
def test_every_table_carries_its_units(objects: dict[str, Any], kind: str) -> None:
    """Issue 33: every ``to_pandas()`` says the unit of each column in ``attrs["units"]`` (a column
    whose rows each have their own unit is covered by a ``"by row"`` or ``"by output"`` entry)."""
    pytest.importorskip("pandas")
    df = objects[kind].to_pandas()
    units = df.attrs.get("units")
    assert isinstance(units, dict) and units, kind
    flat = [c if isinstance(c, str) else c[0] for c in df.columns]
    covered = set(units) | {"unit"}
    grouped = {"by row", "by output", "shares", "df", "dpurity"} & set(units)
    missing = [c for c in flat if c not in covered and not grouped]
    assert not missing, (kind, missing)
