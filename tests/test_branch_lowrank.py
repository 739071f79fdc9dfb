"""Frequency-dependent mounts in the fast FRF paths: the ``woodbury`` kernel with Maxwell (and
fluid-track) branches as a low-rank update of the undamped modes, the banded back-end with the
branches in its band, and ``auto``'s choice between them -- each against the dense exact solve
(``direct``, one LU per frequency of the assembled matrix with the branches eliminated) or a closed form."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import vibss
from vibss import Body, Model, Mount, MountType
from vibss.frequency.kernels import METHODS
from vibss.frequency.lowrank import woodbury
from vibss.frequency.methods import choose_without_modes
from vibss.linear.plant.build import build_plant
from vibss.linear.solve.exact import states

ZENER = {"type": "zener", "k_0": [2e4, 3e4, 5e4], "k_inf": [4e4, 5e4, 1.2e5], "tau": 2e-3}
PRONY = {"type": "prony", "k_0": 3e4, "k": [2e4, 8e3], "tau": [1e-2, 1e-3]}
HYDRO = {"type": "hydraulic", "k_r": 2e5, "c_r": 50.0, "k_b": [0.0, 0.0, 1e5], "m_f": [0.0, 0.0, 20.0],
         "c_f": [0.0, 0.0, 200.0]}


def _chain(n: int, special: dict[str, dict], damping: str = "classical", eta: float = 0.0, seed: int = 4) -> Model:
    """``n`` bodies in a chain, two ground mounts each and one link to the previous body, at random
    points and orientations; ``special`` maps ground mounts ``g<i>_<j>`` to a rheology.
    ``damping``: ``"classical"`` (c = 2e-3 k on every plain mount), ``"general"`` (a few random
    dashpots), ``"none"``; ``eta`` a loss factor on the links."""
    rng = np.random.default_rng(seed)
    bodies = [Body(f"b{i}", m, m * rng.uniform(0.02, 0.05, 3), cog=[0.8 * i, 0.0, 0.0],
                   principal_axes=Rotation.random(random_state=int(rng.integers(1 << 30))).as_matrix())
              for i, m in enumerate(rng.uniform(5.0, 50.0, n))]
    mounts = []

    def plain(name: str, k: np.ndarray, loss: float = 0.0) -> MountType:
        c = 2e-3 * k if damping == "classical" else (rng.uniform(0, 60, 3) * (rng.random() < 0.3)
                                                     if damping == "general" else np.zeros(3))
        return MountType(name, k, c, loss)

    for i in range(n):
        for j in range(2):
            name = f"g{i}_{j}"
            k = rng.uniform(2e4, 2e5, 3)
            spec = special.get(name)
            dash = None
            if spec is not None and spec["type"] != "hydraulic" and damping != "none":
                # classical: the same c = 2e-3 k on its static stiffness, so C stays proportional to K
                dash = 2e-3 * np.broadcast_to(spec["k_0"], 3) if damping == "classical" else [30.0] * 3
            t = (plain(name, k) if spec is None else MountType(name, damping=dash, rheology=spec) if dash is not None
                 else MountType(name, rheology=spec))
            mounts.append(Mount(name, t, f"b{i}", at=rng.uniform(-0.3, 0.3, 3),
                                orientation=Rotation.random(random_state=int(rng.integers(1 << 30))).as_matrix()))
        if i:
            mounts.append(Mount(f"l{i}", plain(f"l{i}", rng.uniform(1e4, 1e5, 3), eta), f"b{i}", to=f"b{i - 1}",
                                at=rng.uniform(-0.3, 0.3, 3)))
    return Model(bodies, mounts, name="chain with frequency-dependent mounts")


def _err(h: np.ndarray, ref: np.ndarray) -> float:
    return float(np.max(np.linalg.norm(h - ref, axis=(0, 1)) / np.linalg.norm(ref, axis=(0, 1))))


CASES = {
    "zener, classical": ({"g2_0": ZENER, "g2_1": ZENER, "g3_0": ZENER, "g3_1": ZENER}, "classical", 0.0),
    "prony + fluid track, general damping": ({"g1_0": PRONY, "g4_1": HYDRO}, "general", 0.0),
    "zener, loss factor, no dashpots": ({"g0_0": ZENER, "g5_1": ZENER}, "none", 0.05),
}


@pytest.mark.parametrize("case", list(CASES))
def test_woodbury_with_branches_matches_the_dense_solve(case: str) -> None:
    """Force and base-motion inputs, displacement, acceleration, mount-force and ground-force
    outputs (the branch forces enter the last two), over a band across every mode."""
    special, damping, eta = CASES[case]
    model = _chain(6, special, damping, eta)
    first = sorted(special)[0]
    plant = build_plant(model, ["b0.fz", "b3.mx", "ground.z.acc", "ground.x.disp"],
                        ["b1.z", "b5.x.acc", f"mount.{first}.f1", "ground.fz", "b2.rx.vel"])
    w = np.geomspace(0.5, 3e3, 300)
    h = woodbury(plant, 1j * w)
    ref = METHODS["direct"].kernel(plant, 1j * w, None)
    assert _err(h, ref) <= 1e-9


def test_woodbury_single_dof_zener_is_the_closed_form() -> None:
    """A body on one Zener mount at its COG: ``1 / (k*(s) - m w^2)`` with
    ``k*(s) = k_0 + (k_inf - k_0) s tau / (1 + s tau) + c s``."""
    m, k0, kinf, tau, c = 2.0, 1e4, 3e4, 2e-3, 8.0
    t = MountType("z", damping=[c] * 3, rheology={"type": "zener", "k_0": k0, "k_inf": kinf, "tau": tau})
    plant = build_plant(Model([Body("b", m, [1.0, 1.0, 1.0])], [Mount("m", t, "b")]), ["b.fz"], ["b.z"])
    w = np.array([1.0, 30.0, 70.7, 120.0, 400.0, 3000.0])
    s = 1j * w
    kstar = k0 + (kinf - k0) * s * tau / (1 + s * tau) + c * s
    np.testing.assert_allclose(woodbury(plant, s)[0, 0], 1 / (kstar - m * w**2), rtol=1e-12)


def test_auto_takes_the_low_rank_update_for_few_branches_and_the_band_for_many() -> None:
    """Four Zener mounts on a 40-body chain with classical damping: the rank-12 update; every ground
    mount Zener (rank 240 = n): the banded exact solve. Both equal the dense solve."""
    few = _chain(40, {f"g{i}_{j}": ZENER for i in (19, 20) for j in (0, 1)})
    many = _chain(40, {f"g{i}_{j}": ZENER for i in range(40) for j in (0, 1)})
    f = np.geomspace(0.5, 100.0, 200)
    ins, outs = ["b19.fz", "b20.fx"], ["b19.z", "b21.y", "b20.rx"]     # near the Zener mounts
    for model, expect in ((few, "woodbury"), (many, "sparse")):
        r = vibss.frequency_response(model, ins, outs, frequencies=f)
        assert r.method == expect, r.note
        plant = build_plant(model, ins, outs)
        assert _err(r.response, METHODS["direct"].kernel(plant, 2j * np.pi * f, None)) <= 1e-9


def test_auto_chooses_the_band_for_full_rank_branches_without_the_modes() -> None:
    """Every ground mount Zener (r = n): ``auto`` takes the banded exact solve from sizes and
    structure alone -- no undamped modes computed (none cached on the plant), no resonance marks,
    the note says why -- and it equals the dense solve; with a grid spec (built around the modes)
    the modes are computed and marked as before; a few branches still go to the cost model on the
    modes (``woodbury``)."""
    many = _chain(30, {f"g{i}_{j}": ZENER for i in range(30) for j in (0, 1)})
    ins, outs = ["b3.fz", "b17.mx"], ["b3.z", "b20.ry", "mount.g4_1.f2"]     # a branch force output too
    plant = build_plant(many, ins, outs)
    f = np.geomspace(0.5, 100.0, 150)
    assert choose_without_modes(plant, f.size)[0] == "sparse"
    r = vibss.frequency_response(plant, frequencies=f)
    assert r.method == "sparse" and "no modes computed" in r.note and "resonances not marked" in r.note
    assert r.natural_hz.size == 0 and "modal basis" not in plant._cache
    assert _err(r.response, METHODS["direct"].kernel(plant, 2j * np.pi * f, None)) <= 1e-9
    grid = vibss.frequency_response(many, ins, outs, frequencies={"f1": 0.5, "f2": 100.0, "points": 50})
    assert grid.method == "sparse" and grid.natural_hz.size > 0
    few = build_plant(_chain(30, {f"g{i}_{j}": ZENER for i in (14, 15) for j in (0, 1)}), ins, outs)
    assert choose_without_modes(few, f.size) is None
    assert vibss.frequency_response(few, frequencies=f).method == "woodbury"


def test_banded_backend_with_branches_off_the_axis_matches_the_dense_solve() -> None:
    """The banded LU's one-GEMM assembly of ``K + iH + sC + s^2 M + sum g(s) K_tau`` at Laplace
    points off the imaginary axis (real parts), with two relaxation times and a loss factor."""
    model = _chain(8, {"g1_0": ZENER, "g6_1": PRONY}, "general", 0.05)
    plant = build_plant(model, ["b0.fz", "ground.y.vel"], ["b7.z", "b3.ry"])
    s = np.array([-3.0 + 40j, 5.0 + 400j, -0.5 + 2e3j, 1j])
    xb, bad_b = states(plant, s, backend="banded")
    xd, bad_d = states(plant, s, backend="dense")
    assert not bad_b.any() and not bad_d.any()
    np.testing.assert_allclose(xb, xd, rtol=1e-10, atol=1e-12 * np.abs(xd).max())


def test_woodbury_with_branches_and_rigid_modes_matches_the_dense_solve() -> None:
    """Two bodies floating free (six rigid modes), joined by two Zener links and a plain mount
    with general damping: the rigid modes' 1 / s^2 and the branches together."""
    z = MountType("z", damping=[5.0] * 3, rheology=ZENER)
    plain = MountType("p", [1e5, 2e5, 3e5], [20.0, 30.0, 40.0])
    bodies = [Body("a", 10.0, [0.3, 0.4, 0.5]), Body("b", 3.0, [0.05, 0.06, 0.07], cog=[0.5, 0.1, 0.0])]
    mounts = [Mount("l1", z, "b", to="a", at=[0.3, 0.1, -0.1]), Mount("l2", plain, "b", to="a", at=[0.1, -0.2, 0.2]),
              Mount("l3", z, "b", to="a", at=[0.2, 0.2, 0.1])]
    plant = build_plant(Model(bodies, mounts), ["a.fz", "b.mx"], ["b.z", "a.rx", "mount.l1.f2", "b.x.acc"])
    w = np.geomspace(0.3, 5e3, 300)
    assert _err(woodbury(plant, 1j * w), METHODS["direct"].kernel(plant, 1j * w, None)) <= 1e-9
