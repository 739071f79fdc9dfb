"""Issue 34's shortcuts for a model never seen before, each held to the work it skips.

- the free-motion test of the mounts' form skips its SVD only where the Cholesky of ``K`` proves that
  no motion is free: on random models, free and held, the shortcut never says "held" where the SVD
  of the stiffness factor finds a free motion;
- a dense plant's band structure, found by NumPy, is the sparse route's (ordering, band, storage);
- the exact solve's ``auto`` takes the band a cost model already found, and gives the dense LU's
  answer;
- mode labels from energy fractions, against the definition written out here.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from cases.models import asymmetric_model, powertrain, prism_model, two_body
from cases.scaled import graded_chain, hanging_chain, stiff_links
from vibss import Body, Model, Mount, MountType, Orientation
from vibss.linear.eigen.directions import dof_labels
from vibss.linear.plant import mountform
from vibss.linear.plant.assemble import assemble
from vibss.linear.plant.build import build_plant
from vibss.linear.solve import banded, exact
from vibss.model.model import DOF_NAMES


def chain(n: int, seed: int, free_end: bool = False) -> Model:
    """``n`` bodies in a row, each on two inclined mounts to ground and one to its neighbour; with
    ``free_end`` the last body hangs on a single mount at its centre of gravity (its rotations free)."""
    rng = np.random.default_rng(seed)
    t = MountType("t", [2e4, 3e4, 5e4], [10.0, 10.0, 20.0])
    bodies = [Body(f"b{i}", float(rng.uniform(1, 50)), rng.uniform(1.0, 1.8, 3), cog=[float(i), 0.0, 0.0])
              for i in range(n)]
    mounts = []
    for i in range(n - 1 if free_end else n):
        for j in range(2):
            mounts.append(Mount(f"g{i}_{j}", t, f"b{i}", at=rng.uniform(-0.4, 0.4, 3),
                                orientation=Orientation.from_euler(rng.uniform(0, 90, 3), degrees=True)))
        if i:
            mounts.append(Mount(f"l{i}", t, f"b{i}", to=f"b{i - 1}", at=[-0.5, 0.1, 0.0]))
    if free_end:
        mounts.append(Mount("end", t, f"b{n - 1}", to=f"b{n - 2}", at=[0.0, 0.0, 0.0]))
    return Model(bodies, mounts)


MODELS = {"prism": prism_model, "asymmetric": asymmetric_model, "two_body": two_body, "powertrain": powertrain,
          "graded": lambda: graded_chain(True), "hanging": hanging_chain, "stiff_links": lambda: stiff_links(1e14, True),
          **{f"chain{s}": (lambda s=s: chain(6, s)) for s in range(4)},
          **{f"free_end{s}": (lambda s=s: chain(5, s, free_end=True)) for s in range(4)}}


@pytest.mark.parametrize("name", sorted(MODELS))
def test_the_cholesky_shortcut_never_hides_a_free_motion(name: str) -> None:
    a = assemble(MODELS[name]())
    free = np.arange(a.n)
    g = a.stiffness_factor().toarray()
    if g.shape[0] < g.shape[1]:
        return                                    # fewer rows than DOFs: free without either test
    sv = np.linalg.svd(g, compute_uv=False)       # the test the shortcut stands in for
    svd_free = sv[-1] <= g.shape[0] * np.finfo(float).eps * sv[0]
    held = mountform._held(a, free, g)
    assert not (held and svd_free)
    if name.startswith("free_end"):
        assert svd_free and not held and mountform._free_motion(a, free)
    if name.startswith("chain"):
        assert held                               # an ordinary model: the SVD is not needed


@pytest.mark.parametrize("name", ["chain0", "chain1", "free_end2", "graded", "asymmetric", "powertrain"])
def test_a_dense_plants_band_structure_is_the_sparse_routes(name: str) -> None:
    model = MODELS[name]()
    first = model.bodies[0].name
    dense = build_plant(model, [f"{first}.fz"], [f"{first}.x"])
    sparse = build_plant(model, [f"{first}.fz"], [f"{first}.x"], sparse=True)
    assert not sp.issparse(dense.K) and sp.issparse(sparse.K)
    a, b = banded.structure(dense), banded.structure(sparse)
    assert (a.band, a.banded) == (b.band, b.banded)
    np.testing.assert_array_equal(a.perm, b.perm)
    assert a.seconds_per_frequency == b.seconds_per_frequency and set(a.parts) == set(b.parts)
    for key in a.parts:
        np.testing.assert_array_equal(a.parts[key], b.parts[key])


def test_auto_takes_a_known_band_and_gives_the_dense_answer() -> None:
    plant = build_plant(chain(12, 5), ["b0.fz", "b11.fx"], ["b3.z", "b11.rx"])
    s = 2j * np.pi * np.array([0.5, 3.0, 7.0, 20.0, 80.0])
    assert exact._pick(plant, "auto") == "dense"          # no band known: the dense LU, as before
    plant.cached("band structure", lambda: banded.structure(plant))
    assert exact._pick(plant, "auto") == "banded"         # 72 DOF, band 17: cheaper
    ref = exact.response(plant, s, backend="dense")
    got = exact.response(plant, s)
    err = np.linalg.norm(got - ref, axis=(0, 1)) / np.linalg.norm(ref, axis=(0, 1))
    assert err.max() < 1e-12


def test_mode_labels_are_the_definition() -> None:
    rng = np.random.default_rng(11)
    for trial in range(40):
        nb = int(rng.integers(1, 4))
        dofs = [f"b{i // 6}.{DOF_NAMES[i % 6]}" for i in range(6 * nb) if rng.random() < 0.85] + ["motor.torque"]
        e = rng.random((5, len(dofs))) * (rng.random((5, len(dofs))) < 0.6)
        bodies = list(dict.fromkeys(d.split(".")[0] for d in dofs if d.split(".")[1] in DOF_NAMES))
        want = []
        for row in e:          # per direction the summed share; then the body holding most of it
            share = {d: sum(row[j] for j, x in enumerate(dofs) if x.endswith("." + d)) for d in DOF_NAMES}
            if not any(row[j] for j, x in enumerate(dofs) if x.split(".")[1] in DOF_NAMES):
                want.append("")
                continue
            d = max(DOF_NAMES, key=lambda k: (share[k], -DOF_NAMES.index(k)))
            by = {b: sum(row[j] for j, x in enumerate(dofs) if x == f"{b}.{d}") for b in bodies}
            b = max(bodies, key=lambda k: (by[k], -bodies.index(k)))
            want.append(d if len(bodies) == 1 else f"{b}.{d}")
        assert dof_labels(e, dofs) == want, trial
