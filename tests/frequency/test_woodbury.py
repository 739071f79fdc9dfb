"""The ``woodbury`` FRF kernel (undamped modes + the dampers as a low-rank update) against the
60-digit receptance on the badly scaled family, the dense exact solve on general damping (viscous
and hysteretic, rigid modes, a few damped mounts), and ``auto``'s cost model choosing it."""

from __future__ import annotations

from functools import lru_cache

import numpy as np
import pytest

from cases import mp_reference as mpr
from cases import scaled as sc
from cases import ROOT
from vibss import Body, Model, Mount, MountType
from vibss.frequency.api import frequency_response
from vibss.frequency.kernels import METHODS
from vibss.frequency.lowrank import woodbury
from vibss.linear.eigen.basis import modal_basis, damping_factors, projected_damping
from vibss.linear.plant.build import build_plant

TOL = 1e-8          # as the other modal superpositions on the scaled family (test_modal_superposition)


def _dofs(model: Model) -> list[str]:
    return [f"{b.name}.{d}" for b in model.bodies for d in ("x", "y", "z", "rx", "ry", "rz")]


def _forces(model: Model) -> list[str]:
    return [f"{b.name}.{d}" for b in model.bodies for d in ("fx", "fy", "fz", "mx", "my", "mz")]


@lru_cache(maxsize=None)
def _scaled(name: str) -> tuple:
    model = {"graded_chain": lambda: sc.graded_chain(damped=True),
             "stiff_links": lambda: sc.stiff_links(1e10, damped=True),
             "instrument": lambda: sc.instrument(damped=True)}[name]()
    wn = mpr.natural_frequencies(model)
    return model, build_plant(model, _forces(model), _dofs(model)), wn[wn > 0]


@pytest.mark.parametrize("name", [pytest.param("graded_chain", marks=pytest.mark.slow), "stiff_links", "instrument"])
def test_matches_the_60_digit_receptance_on_the_scaled_family(name: str) -> None:
    """Below the modes (the static part in the mounts' forces), beside the slowest and the fastest
    resonance, between two and above all: every column of the receptance to 1e-8 (normwise)."""
    model, plant, el = _scaled(name)
    w = np.concatenate([np.array([0.05, 0.3, 1.003]) * el.min(), [np.sqrt(el[0] * el[-1])],
                        np.array([0.997, 1.01, 3.0]) * el.max()])
    h = woodbury(plant, 1j * w)
    ref = np.stack([mpr.receptance(model, complex(0.0, x)) for x in w], axis=-1)
    err = (np.linalg.norm(h - ref, axis=0) / np.linalg.norm(ref, axis=0)).max(axis=0)
    assert err.max() <= TOL, err


def _few_dampers(hysteretic: bool = False, free: bool = False) -> Model:
    """Four bodies in a chain on undamped mounts; two mounts carry dampers (c not proportional to
    k) and, with ``hysteretic``, a third a loss factor; ``free``: body d has no ground mount and a
    single damped link, so rigid modes stay."""
    rng = np.random.default_rng(3)
    bodies = [Body(n, m, m * np.array([0.02, 0.03, 0.04]), cog=[0.5 * i, 0.1 * i, 0.0])
              for i, (n, m) in enumerate((("a", 40.0), ("b", 5.0), ("c", 12.0), ("d", 2.0)))]
    mounts = []
    for i, b in enumerate(bodies):
        k = rng.uniform(1e4, 1e5, 3)
        if not (free and b.name == "d"):
            for j in range(2):
                mounts.append(Mount(f"g{i}{j}", MountType(f"g{i}{j}", k), b.name, at=rng.uniform(-0.2, 0.2, 3)))
        if i:
            c = [30.0, 5.0, 80.0] if i in (1, 3) else [0.0, 0.0, 0.0]
            eta = 0.1 if (hysteretic and i == 2) else 0.0
            mounts.append(Mount(f"l{i}", MountType(f"l{i}", k, c, eta), b.name, to=bodies[i - 1].name,
                                at=rng.uniform(-0.2, 0.2, 3)))
    return Model(bodies, mounts, name="few dampers")


@pytest.mark.parametrize("hysteretic,free", [(False, False), (True, False), (False, True)])
def test_few_dampers_match_the_dense_solve(hysteretic: bool, free: bool) -> None:
    model = _few_dampers(hysteretic, free)
    ins = ["a.fz", "d.fx", "ground.z.acc", "c.my"]
    outs = ["a.z", "d.x.acc", "mount.l1.f1", "b.rz.vel", "ground.fz"]
    plant = build_plant(model, ins, outs)
    basis = modal_basis(plant)
    assert basis.rigid.any() == free
    el = basis.omega[~basis.rigid]
    f = np.unique(np.concatenate([np.geomspace(0.2 * el.min(), 3 * el.max(), 300), el * (1 + 1e-9)])) / (2 * np.pi)
    ref = frequency_response(plant, frequencies=f, method="direct").response
    got = frequency_response(plant, frequencies=f, method="woodbury")
    assert got.method == "woodbury"
    err = np.linalg.norm(got.response - ref, axis=(0, 1)) / np.linalg.norm(ref, axis=(0, 1))
    assert err.max() <= 1e-10
    # the factor is exact: U Zc U^T and U Zh U^T are the projected damping (an invariant)
    u, zc, zh = damping_factors(plant, basis)
    gamma, eta = projected_damping(plant, basis)
    assert u.shape[1] == 6 + 3 * hysteretic                       # three axes per damped mount
    np.testing.assert_allclose(u @ zc @ u.T, gamma, atol=1e-12 * np.abs(gamma).max())
    np.testing.assert_allclose(u @ zh @ u.T, eta, atol=1e-12 * max(np.abs(eta).max(), 1.0))


def test_an_undamped_mode_beside_a_damped_one() -> None:
    """A body no damper reaches, a hair (1e-7) off its undamped resonance, beside a damped one: the
    undamped mode is an exact 1 / (omega^2 - w^2) term (no damper couples it), and the damped body's
    response is untouched by it."""
    t = MountType("t", [1e4, 2e4, 3e4])
    damped = MountType("d", [1e4, 2e4, 3e4], [5.0, 50.0, 9.0])
    link = MountType("l", [3e3, 3e3, 3e3], [1.0, 2.0, 3.0])
    model = Model([Body("a", 10.0, [1, 2, 3]), Body("b", 4.0, [1, 1, 1], cog=[2, 0, 0])],
                  [Mount("a1", t, "a", at=[0.3, 0.2, 0.1]), Mount("a2", t, "a", at=[-0.3, -0.1, 0.0]),
                   Mount("b1", damped, "b", at=[0.1, 0.2, 0.0]), Mount("b2", t, "b", at=[-0.2, 0.0, 0.1]),
                   Mount("ab", link, "b", to="a", at=[-1.0, 0.0, 0.0])])
    plant = build_plant(model, ["a.fz", "b.fz"], ["a.z", "b.z"])
    basis = modal_basis(plant)
    s = 1j * np.concatenate([basis.omega * (1 + 1e-7), basis.omega * 0.9])
    got, ref = woodbury(plant, s, basis), METHODS["direct"](plant, s)
    err = np.linalg.norm(got - ref, axis=(0, 1)) / np.linalg.norm(ref, axis=(0, 1))
    assert err.max() <= 1e-7                      # the resonance's conditioning, 1e-7 off it


def _chain(n_bodies: int, damped: set[int] | None) -> Model:
    """A chain of bodies on ground mounts and links; links in ``damped`` (all when None) carry dampers."""
    rng = np.random.default_rng(5)
    bodies = [Body(f"b{i}", m, m * np.array([0.02, 0.03, 0.04]), cog=[0.6 * i, 0.0, 0.0])
              for i, m in enumerate(rng.uniform(2.0, 50.0, n_bodies))]
    mounts = []
    for i in range(n_bodies):
        k = rng.uniform(1e4, 1e5, 3)
        c = rng.uniform(1.0, 20.0, 3)
        mounts.append(Mount(f"g{i}", MountType(f"g{i}", k, c if damped is None else np.zeros(3)), f"b{i}",
                            at=rng.uniform(-0.2, 0.2, 3)))
        if i:
            on = damped is None or i in damped
            mounts.append(Mount(f"l{i}", MountType(f"l{i}", k, c if on else np.zeros(3)), f"b{i}", to=f"b{i - 1}",
                                at=rng.uniform(-0.2, 0.2, 3)))
    return Model(bodies, mounts, name="chain")


def test_auto_costs_the_damper_rank() -> None:
    """Two damped links in a 30-body chain (rank 6, 180 DOF): the low-rank update wins and the
    reason says why; every mount damped (rank 3 x 59 > 180): another method, and the reason names
    woodbury's larger estimate. Both agree with the dense solve: to 1e-9 when every mount is damped;
    with two dampers some modes keep damping ratios of 4e-7, where a frequency's relative error
    of 3e-13 in the undamped basis (eigh + refinement) makes up to 3e-7 at their peaks (7.6e-9
    measured): the bound of every modal superposition, 'modal' included."""
    f = np.geomspace(1, 100, 400)
    for model, expect in ((_chain(30, {4, 17}), True), (_chain(30, None), False)):
        r = frequency_response(model, ["b0.fz"], ["b29.z", "b3.x"], f)
        assert (r.method == "woodbury") == expect, r.note
        assert "woodbury" in r.note and "complex" in r.note
        if expect:
            assert "damper rank 6" in r.note
        else:   # the banded solve is estimated cheaper than complex modes (whose sum cancels by 1e8 in
            assert r.method == "sparse"     # b3.x at 100 Hz, 5.7e-7: auto's check would refuse them)
        ref = frequency_response(model, ["b0.fz"], ["b29.z", "b3.x"], f, method="direct").response
        err = np.linalg.norm(r.response - ref, axis=(0, 1)) / np.linalg.norm(ref, axis=(0, 1))
        assert err.max() <= (1e-7 if expect else 1e-9)


@pytest.mark.parametrize("damping", ["general", "classical"])
def test_damping_rank_counts_the_factor_columns_without_forming_them(damping: str) -> None:
    """``auto`` costs woodbury by :func:`damping_rank`: three columns per damped mount, counted from
    the model itself, and the column count of the formed factor ``U`` (an invariant)."""
    import sys
    from pathlib import Path

    from vibss.linear.eigen.basis import damping_rank

    sys.path.insert(0, str(ROOT / "benchmarks"))
    from models import tree_model

    model = tree_model(12, damping=damping)
    plant = build_plant(model, ["b0.fx"], ["b3.z"])
    damped = sum(1 for m in model.mounts if np.any(np.asarray(m.type.damping)))
    assert damped > 0
    assert damping_rank(plant) == 3 * damped == damping_factors(plant, modal_basis(plant))[0].shape[1]
