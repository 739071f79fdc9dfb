"""The solve in the mounts' forces by refinement (vibss/linear/solve/refine.py): the assembled LU
refined with the residual in the mounts' form meets a 240-bit ball-arithmetic reference on a soft
tower and a hanging chain where the assembled LU alone does not; the iteration's own rules."""

from __future__ import annotations

import dataclasses
import sys
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spl

from cases import mp_reference as mpr
from cases import scaled as sc
from vibss.linear.plant.build import build_plant
from vibss.linear.solve import backends
from vibss.linear.solve.exact import forcing, response, zfactor
from vibss.linear.solve.refine import TARGET, Contraction, mounts_product, refine

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
from models import tower_model  # noqa: E402

TOL = 1e-10


def _towers():
    model = tower_model(11, damping="classical", seed=2)
    return model, ["b10.fx", "b4.fz"]


def _chain():
    model = sc.hanging_chain()
    return model, [f"{model.bodies[-1].name}.fz", f"{model.bodies[0].name}.fx"]


@pytest.mark.parametrize("case", [_towers, _chain])
def test_refined_assembled_lu_meets_the_240_bit_reference(case, monkeypatch):
    model, ins = case()
    dofs = [f"{b.name}.{d}" for b in model.bodies for d in ("x", "y", "z", "rx", "ry", "rz")]
    plant = build_plant(model, ins, dofs, sparse=True)
    form = plant.mounts
    assert form is not None and form.stiffness_ratio > 1e3
    wn = mpr.natural_frequencies(model)
    el = wn[wn > 0]
    w = np.array([0.3 * el.min(), 1.001 * el.min(), 0.999 * el[el.size // 2], 1.01 * el.max()])
    s = 1j * w
    cols = [dofs.index(i.replace(".f", ".")) for i in ins]
    refs = np.stack([mpr.receptance(model, complex(sk))[:, cols] for sk in s])      # (nf, n, m)
    scale = np.abs(refs).max(axis=1)                                                # per column
    k, m, c = (sp.csc_matrix(getattr(plant, a)) for a in ("K", "M", "C"))
    rhs = forcing(plant, s, zfactor(s, plant.order))
    plain, refined = [], []
    for i, sk in enumerate(s):
        lu = spl.splu(sp.csc_matrix(k + sk * c + sk * sk * m, dtype=complex))
        apply = mounts_product(form, sp.csr_matrix(plant.M), form.B.T.tocsr(), None, sk)
        x, corr, ok = refine(lu.solve, apply, rhs[i])
        assert ok and corr <= TARGET
        plain.append(np.abs(lu.solve(rhs[i]) - refs[i]).max(axis=0) / scale[i])
        refined.append(np.abs(x - refs[i]).max(axis=0) / scale[i])
    assert max(np.max(e) for e in refined) <= TOL
    assert max(np.max(e) for e in plain) > 1e3 * max(np.max(e) for e in refined)   # the LU alone does not
    monkeypatch.setattr(backends, "MOUNTS_DENSE_MAX", 0)                            # the back-end's own path
    accepted = []

    def spy(*args):                     # the assembled LU (ordered once, reused) refined: no saddle fallback
        x, corr, ok = refine(*args)
        accepted.append(ok)
        return x, corr, ok

    monkeypatch.setattr(backends, "refine", spy)
    y = response(plant, s, form="mounts")                                           # (p, m, nf)
    assert accepted == [True] * s.size and plant.known("assembled pattern, ordered") is not None
    ref_y = np.moveaxis(refs, 0, -1)
    assert np.max(np.abs(y - ref_y) / scale.T[None]) <= TOL


def test_refinement_contracts_to_the_solution_and_says_when_it_cannot():
    rng = np.random.default_rng(5)
    a = rng.standard_normal((40, 40)) + 40 * np.eye(40)
    r = rng.standard_normal((40, 2)) + 0j
    exact = np.linalg.solve(a, r)
    near = np.linalg.inv(a + 1e-3 * rng.standard_normal((40, 40)))     # contracts by ~1e-4 a step
    x, corr, ok = refine(lambda b: near @ b, lambda v: a @ v, r)
    assert ok and corr <= TARGET and np.abs(x - exact).max() <= 1e-13 * np.abs(exact).max()
    # a sweep's contraction measured at one frequency lets a closer LU at the next stop after one step,
    # still within TARGET of the solution; a contraction too weak to bound anything is not used
    hint, calls = Contraction(), []
    refine(lambda b: near @ b, lambda v: a @ v, r, hint)
    assert 1e-6 < hint.rho < 1e-2
    closer = np.linalg.inv(a + 1e-10 * rng.standard_normal((40, 40)))
    x, corr, ok = refine(lambda b: calls.append(1) or closer @ b, lambda v: a @ v, r, hint)
    assert ok and len(calls) == 2 and np.abs(x - exact).max() <= 1e-13 * np.abs(exact).max()
    calls.clear()
    x, corr, ok = refine(lambda b: calls.append(1) or closer @ b, lambda v: a @ v, r, Contraction(0.2))
    assert ok and len(calls) >= 3
    far = np.linalg.inv(a + 60 * np.eye(40))                           # ||I - far a|| > 1: diverges
    x, corr, ok = refine(lambda b: -far @ b, lambda v: a @ v, r)
    assert not ok


def test_where_the_refinement_misses_the_saddle_system_answers(monkeypatch):
    """A frequency whose refinement of the assembled LU reports no convergence is solved by SuperLU of
    the saddle system in the mounts' forces, refined the same way: still the 240-bit answer."""
    model, ins = _towers()
    dofs = [f"{b.name}.{d}" for b in model.bodies for d in ("x", "y", "z", "rx", "ry", "rz")]
    plant = build_plant(model, ins, dofs, sparse=True)
    el = mpr.natural_frequencies(model)
    s = 1j * np.array([1.001 * el[el > 0].min(), 0.999 * el[el.size // 2]])
    cols = [dofs.index(i.replace(".f", ".")) for i in ins]
    refs = np.stack([mpr.receptance(model, complex(sk))[:, cols] for sk in s], axis=-1)    # (n, m, nf)
    calls = []

    def first_misses(solve, apply, r, *hint):
        calls.append(solve)
        x, corr, ok = refine(solve, apply, r, *hint)
        return x, corr, ok and len(calls) % 2 == 0          # every frequency's first attempt "misses"

    monkeypatch.setattr(backends, "refine", first_misses)
    monkeypatch.setattr(backends, "MOUNTS_DENSE_MAX", 0)
    y = response(plant, s, form="mounts")
    assert len(calls) == 2 * s.size
    assert np.max(np.abs(y - refs) / np.abs(refs).max(axis=0, keepdims=True)) <= TOL


def test_a_saddle_solve_that_cannot_converge_marks_its_frequency_singular():
    """0 Hz on a mechanism chain (slides: free motions) above the dense size: both the assembled LU's
    and the saddle system's refinements miss. The frequency must be marked singular so that the limit
    path answers (infinite receptance along the free motion, as the dense saddle path gives), not
    return the diverged iterate (a review found -1.4e34 m/N here)."""
    from models import mechanism_model

    model = mechanism_model(26, seed=1)
    plant = build_plant(model, ["b25.fx"], ["b25.x", "b3.z"], sparse=True)
    assert plant.n + 3 * len(model.mounts) > backends.MOUNTS_DENSE_MAX
    import vibss

    r = vibss.frequency_response(model, ["b25.fx"], ["b25.x", "b3.z"], [0.0, 1.0], method="sparse")
    h = np.stack([r.channel("b25.x"), r.channel("b3.z")])               # (outputs, frequencies)
    assert np.isinf(np.abs(h[:, 0])).all() and np.isfinite(h[:, 1]).all()


def test_the_check_reads_the_backward_errors_the_refined_solve_recorded(monkeypatch):
    """The refined solve records the normwise backward error of each answer it returns (residual in the
    mounts' form); the exact methods' check reads those at its points instead of solving them again,
    and they agree with the check's own computation (the assembled products) to round-off's level:
    both far below the 1e-10 claim, the recorded one (no assembled round-off) no larger."""
    from vibss.frequency import contracts
    from vibss.linear.solve import exact
    from vibss.linear.solve.refine import recorded_backward_errors

    monkeypatch.setattr(backends, "MOUNTS_DENSE_MAX", 0)
    model, ins = _towers()
    plant = build_plant(model, ins, ["b10.x", "b0.z"], sparse=True)
    s = 2j * np.pi * np.geomspace(1e-3, 10.0, 12)
    response(plant, s, form="mounts")
    f = forcing(plant, s, zfactor(s, plant.order))
    record = recorded_backward_errors(plant, s, f)
    assert record is not None
    kept, stall = record
    assert kept.shape == (s.size,) and np.all(kept < 1e-14) and stall == 0.0     # every point converged
    assert recorded_backward_errors(plant, s, 2.0 * f) is None          # other right-hand sides: not recorded
    fresh = dataclasses.replace(plant)                  # the same plant, nothing recorded: solved again
    again = contracts.backward_error(fresh, s[[0, 5, 11]], 1e-10, "sparse")
    assert "as it solved" not in again.where
    calls = []
    real = exact.states
    monkeypatch.setattr(contracts, "states", lambda *a, **k: calls.append(1) or real(*a, **k))
    read = contracts.backward_error(plant, s[[0, 5, 11]], 1e-10, "sparse")
    assert not calls and "as it solved" in read.where
    assert read.error == pytest.approx(kept[[0, 5, 11]].max(), rel=0, abs=0)
    assert read.error <= max(again.error, 1e-16) * 10 and again.error < 1e-12
