"""The exact modal time response of modes plus a few Maxwell branch states (vibss.linear.eigen.branch_modes,
vibss.time.branched): the structured eigen-solve against LAPACK on the dense augmented matrix, the
time response against solve_ivp of the physical augmented system, against forced_response, and the
steady state of a long sine against the exact frequency response; the refusals fall back and say so."""

from __future__ import annotations

import warnings
from dataclasses import replace

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import vibss
from benchmarks.models import chain_model
from vibss import Body, Model, Mount, MountType
from vibss.errors import DefectiveModesError
from vibss.linear.eigen.branch_modes import branch_modes
from vibss.linear.plant.build import build_plant
from vibss.linear.solve.exact import response
from vibss.model.timefunctions import Sine


def _dense(omega, c, bphi, k, tau):
    """The augmented modal state matrix on [eta; eta'; f], written out."""
    n, r = omega.size, k.size
    A = np.zeros((2 * n + r, 2 * n + r))
    A[:n, n:2 * n] = np.eye(n)
    A[n:2 * n, :n] = -np.diag(omega ** 2)
    A[n:2 * n, n:2 * n] = -np.diag(c)
    A[n:2 * n, 2 * n:] = -bphi.T
    A[2 * n:, n:2 * n] = k[:, None] * bphi
    A[2 * n:, 2 * n:] = -np.diag(1.0 / tau)
    return A


def _spectrum(bm):
    return np.concatenate([bm.lam, bm.lam[bm.weight == 2].conj()])


@pytest.mark.parametrize("seed,strength,same_tau", [(0, 0.03, False), (1, 0.1, True), (2, 0.1, False),
                                                    (3, 0.3, True)])
def test_roots_vectors_and_dual_against_the_dense_matrix(seed, strength, same_tau):
    rng = np.random.default_rng(seed)
    n, r = 25, 4
    omega = np.sort(rng.uniform(1.0, 100.0, n))
    c = 2 * 0.02 * omega
    c[-1] = 2.5 * omega[-1]                                  # one overdamped mode: two real roots
    bphi = rng.normal(size=(r, n)) * strength
    k = rng.uniform(50.0, 500.0, r)
    tau = np.full(r, 0.05) if same_tau else rng.uniform(0.01, 0.1, r)
    bm = branch_modes(omega, c, bphi, k, tau)
    A = _dense(omega, c, bphi, k, tau)
    ev = np.linalg.eigvals(A)
    lam = _spectrum(bm)
    assert lam.size == A.shape[0]
    for a, b in ((lam, ev), (ev, lam)):                      # the same multiset, both ways
        assert max(np.min(np.abs(b - x)) / abs(x) for x in a) <= 1e-10
    # right eigenvectors satisfy A v = lam v; the dual rows are V^-1 on the kept roots
    V = np.vstack([bm.eta, bm.eta * bm.lam[None], bm.force])
    res = np.abs(A @ V - V * bm.lam[None]).max(axis=0) / (np.abs(A).max() * np.abs(V).max(axis=0))
    assert res.max() <= 1e-12
    de, dd, df = bm.dual()
    W = np.vstack([de, dd, df])
    np.testing.assert_allclose(W.T @ V, np.eye(V.shape[1]), atol=1e-9)
    np.testing.assert_allclose(W.T @ A, bm.lam[:, None] * W.T, atol=1e-9 * np.abs(A).max() * np.abs(W).max())


def test_trace_invariants_used_by_the_certificate_are_the_dense_traces():
    rng = np.random.default_rng(5)
    omega, c = np.array([3.0, 7.0, 11.0]), np.array([0.1, 0.2, 0.3])
    bphi, k, tau = rng.normal(size=(2, 3)), np.array([40.0, 90.0]), np.array([0.1, 0.3])
    A = _dense(omega, c, bphi, k, tau)
    lam = _spectrum(branch_modes(omega, c, bphi, k, tau))
    np.testing.assert_allclose(np.sum(lam).real, np.trace(A), rtol=1e-12)
    np.testing.assert_allclose(np.sum(lam * lam).real, np.trace(A @ A), rtol=1e-12)
    assert np.trace(A @ A) == pytest.approx(-2 * np.sum(omega ** 2) + np.sum(c ** 2) + np.sum(1 / tau ** 2)
                                            - 2 * np.sum(k[:, None] * bphi ** 2), rel=1e-14)


def test_a_rigid_mode_or_a_critically_damped_one_is_refused():
    one = (np.array([[1.0]]), np.array([10.0]), np.array([0.1]))
    with pytest.raises(DefectiveModesError, match="rigid-body"):
        branch_modes(np.array([0.0]), np.array([0.0]), *one)
    with pytest.raises(DefectiveModesError, match="critically damped"):
        branch_modes(np.array([2.0]), np.array([4.0]), *one)


# ------------------------------------------------------------------------------ time response

def _zener(name, k0, kinf, tau, damping):
    return MountType(name, damping=list(damping), rheology={"type": "zener", "k_0": list(k0), "k_inf": list(kinf),
                                                          "tau": tau})


def _model(n_bodies: int, zener: tuple[str, ...], ratio: float = 2.0, tau: float = 5e-3,
           damping: float = 0.002) -> Model:
    """A chain of bodies, each on four ground mounts, linked by one mount to the next; the ground
    mounts named in ``zener`` are Zener (k_inf = ratio k_0) with the same static stiffness.
    ``damping``: dashpots c = damping k on every mount (stiffness-proportional: classical)."""
    rng = np.random.default_rng(7)
    bodies, mounts = [], []
    for i in range(n_bodies):
        bodies.append(Body(f"b{i}", float(rng.uniform(5, 20)), list(rng.uniform(1.0, 1.6, 3)),
                           cog=[1.5 * i, 0.0, 0.0]))
        for j, (y, z) in enumerate(((-0.4, -0.3), (0.4, -0.3), (-0.3, 0.3), (0.3, 0.3))):
            k = rng.uniform(1e4, 5e4, 3)
            name = f"g{i}_{j}"
            if name in zener:
                t = _zener(name, k, ratio * k, tau, damping * k)
            else:
                t = MountType(name, stiffness=list(k), damping=list(damping * k))
            mounts.append(Mount(name, t, f"b{i}", at=[1.5 * i + (0.3 if j % 2 else -0.3), y, z]))
        if i:
            k = rng.uniform(1e4, 5e4, 3)
            mounts.append(Mount(f"l{i}", MountType(f"l{i}", stiffness=list(k), damping=list(damping * k)),
                                f"b{i}", to=f"b{i - 1}", at=[1.5 * i - 0.75, 0.0, 0.0]))
    return Model(bodies, mounts)


def _ivp(model: Model, inp: str, outs: list[str], u, knots: np.ndarray, times: np.ndarray) -> np.ndarray:
    """solve_ivp (Radau, rtol 1e-11) of the physical augmented system
    ``M q'' + C q' + K q + B^T k (B q - u_b) = F u``, ``tau u_b' = B q - u_b``, restarted at the
    input's knots; the outputs are DOF displacements."""
    p = build_plant(model, [inp], outs)
    M, C, K, F = (np.asarray(a, float) for a in (p.M, p.C, p.K, p.F[:, 0]))
    br = p.branches
    B, k, tau = br.B, br.k, br.tau
    n, r = p.n, br.r
    Mi = np.linalg.inv(M)
    A = np.zeros((2 * n + r, 2 * n + r))
    A[:n, n:2 * n] = np.eye(n)
    A[n:2 * n, :n] = -Mi @ (K + B.T @ (k[:, None] * B))
    A[n:2 * n, n:2 * n] = -Mi @ C
    A[n:2 * n, 2 * n:] = Mi @ (B.T * k[None])
    A[2 * n:, :n] = B / tau[:, None]
    A[2 * n:, 2 * n:] = -np.diag(1 / tau)
    b = np.concatenate([np.zeros(n), Mi @ F, np.zeros(r)])
    rows = [p.dofs.index(o) for o in outs]
    y = np.zeros((len(outs), times.size))
    x = np.zeros(2 * n + r)
    for lo, hi in zip(knots[:-1], knots[1:]):
        sel = (times >= lo - 1e-12) & (times <= hi + 1e-12)
        sol = solve_ivp(lambda t, z: A @ z + b * u(t), (lo, hi), x, method="Radau", rtol=1e-11, atol=1e-18,
                        jac=A, dense_output=True)
        y[:, sel] = sol.sol(np.clip(times[sel], lo, hi))[rows]
        x = sol.sol(hi)
    return y


@pytest.mark.parametrize("n_bodies,zener,ratio,damping", [
    (1, ("g0_0", "g0_3"), 2.0, 0.002),          # one body, two Zener mounts
    (3, ("g1_0", "g1_1", "g1_2", "g1_3"), 2.0, 0.0),   # no dashpots at all (undamped modes)
    (3, ("g1_0", "g1_1", "g1_2", "g1_3"), 2.0, 0.002),
    (5, ("g2_0", "g2_2"), 12.0, 0.002),         # strongly coupled: k_inf = 12 k_0, roots move far
])
def test_time_response_matches_solve_ivp_of_the_augmented_system(n_bodies, zener, ratio, damping):
    model = _model(n_bodies, zener, ratio=ratio, damping=damping)
    mid = f"b{n_bodies // 2}"
    dt, steps = 2e-4, 600
    knots = np.arange(0, steps * dt + 1e-12, 40 * dt)
    vals = np.random.default_rng(3).standard_normal(knots.size) * 100.0
    u = lambda t: np.interp(t, knots, vals)  # noqa: E731
    outs = [f"{mid}.z", f"{mid}.rx", "b0.y"]
    r = vibss.simulate(model, inputs={f"{mid}.fz": u}, outputs=outs, t_end=steps * dt, dt=dt, method="modal")
    assert r.method == "modal" and "secular equation" in r.note
    ref = _ivp(model, f"{mid}.fz", outs, u, knots, r.time)
    for got, want in zip(r.outputs, ref):
        assert np.abs(got - want).max() <= 1e-8 * np.abs(want).max()


def test_strong_coupling_moves_the_roots_far_and_is_still_certified():
    """k_inf = 12 k_0 at tau near the modes' periods: some roots move by much more than the modes'
    spacing, and the structured solve finds them all (checked against LAPACK on the dense matrix)."""
    p = build_plant(_model(5, ("g2_0", "g2_2"), ratio=12.0), ["b2.fz"], ["b2.z"])
    from vibss.linear.eigen.basis import modal_basis, projected_damping

    mb = modal_basis(p)
    c = np.diag(projected_damping(p, mb)[0])
    w = np.sqrt(mb.omega2)
    args = (w, c, p.branches.B @ mb.phi, p.branches.k, p.branches.tau)
    bm = branch_modes(*args)
    ev = np.linalg.eigvals(_dense(*args))
    lam = _spectrum(bm)
    assert max(np.min(np.abs(ev - x)) / abs(x) for x in lam) <= 1e-10
    assert max(np.min(np.abs(lam - x)) / abs(x) for x in ev) <= 1e-10
    disc = (c / 2) ** 2 - w ** 2 + 0j
    uncoupled = np.concatenate([-c / 2 + np.sqrt(disc), -c / 2 - np.sqrt(disc), -1 / p.branches.tau])
    moved = np.array([np.min(np.abs(uncoupled - x)) for x in lam])
    assert moved.max() > 10 * np.min(np.diff(np.sort(w)))    # far, on the modes' own scale
    assert np.sum(moved > 0.1 * np.abs(lam)) >= 3             # several roots moved by a tenth of themselves


def test_engine_like_chain_agrees_with_forced_response():
    base = chain_model(20, damping="classical", zeta=1e-3)
    zener = {"g10_0", "g10_1", "g11_0", "g11_1"}
    assert zener <= {m.name for m in base.mounts}
    mounts = [replace(m, type=MountType(m.type.name + "_z", damping=m.type.damping,
                                        rheology={"type": "zener", "k_0": m.type.stiffness,
                                                  "k_inf": 2 * m.type.stiffness, "tau": 5e-3}))
              if m.name in zener else m for m in base.mounts]
    model = replace(base, mounts=tuple(mounts))
    dt, steps = 2e-4, 1000
    knots = np.arange(0, steps * dt + 50 * dt, 50 * dt)
    vals = np.random.default_rng(1).standard_normal((2, knots.size)) * 100.0
    inputs = {"b6.fz": lambda t: np.interp(t, knots, vals[0]), "b13.fx": lambda t: np.interp(t, knots, vals[1])}
    outs = ["b6.x", "b6.z", "b6.ry", "mount.g10_0.fz", "b6.z.acc"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        auto = vibss.simulate(model, inputs=inputs, outputs=outs, t_end=steps * dt, dt=dt)
        ref = vibss.simulate(model, inputs=inputs, outputs=outs, t_end=steps * dt, dt=dt, method="forced_response")
    assert auto.method == "modal" and "12 branch states on 120 DOFs" in auto.note
    for got, want in zip(auto.outputs, ref.outputs):
        assert np.abs(got - want).max() <= 1e-9 * np.abs(want).max()


@pytest.mark.parametrize("zener,method", [(("g1_0", "g1_3"), "auto"),
                                          (("g1_0", "g1_1", "g1_2", "g1_3"), "modal")])
def test_long_sine_steady_state_equals_the_frf(zener, method):
    model = _model(3, zener, damping=0.004)
    w = 2 * np.pi * 12.0
    outs = ["b1.z", "mount.g1_0.fz", "b2.rx"]
    p = build_plant(model, ["b1.fz"], outs)
    from vibss.linear.eigen.basis import modal_basis, projected_damping

    mb = modal_basis(p)
    bm = branch_modes(np.sqrt(mb.omega2), np.diag(projected_damping(p, mb)[0]), p.branches.B @ mb.phi,
                      p.branches.k, p.branches.tau)
    decay = float(np.min(-bm.lam.real))
    period = 2 * np.pi / w
    dt = period / 400                                  # the FOH of the samples: (w dt)^2 / 12 < 2e-5 ...
    t_end = np.ceil(25.0 / decay / period) * period    # ... but a sine piece is exact (not sampled)
    sine = Sine(1.0, 12.0)
    r = vibss.simulate(model, inputs={"b1.fz": sine}, outputs=outs, t_end=t_end, dt=dt,
                       record_from=t_end - 2 * period, method=method)
    assert r.method == "modal" and "secular equation" in r.note and "every input exact" in r.note
    basis = np.column_stack([np.sin(w * r.time), np.cos(w * r.time)])
    coef = np.linalg.lstsq(basis, r.outputs.T, rcond=None)[0]
    amplitude = coef[0] + 1j * coef[1]
    frf = response(p, [1j * w])[:, 0, 0]
    assert np.all(np.abs(amplitude - frf) <= 1e-6 * np.abs(frf))


def test_a_free_floating_body_falls_back_and_the_note_says_why():
    t = _zener("z", [1e4] * 3, [3e4] * 3, 2e-3, [8.0] * 3)
    model = Model([Body("b", 2.0, [1.0, 1.0, 1.0])], [Mount("m", t, "b")])    # rotations free: rigid modes
    force = lambda t: np.minimum(np.asarray(t) / 0.01, 1.0) * 100.0  # noqa: E731
    r = vibss.simulate(model, inputs={"b.fz": force}, outputs=["b.z"], t_end=0.2, dt=1e-3)
    assert r.method == "forced_response"
    assert "modal refused" in r.note and "rigid-body mode" in r.note
    with pytest.raises(DefectiveModesError, match="rigid-body mode"):
        vibss.simulate(model, inputs={"b.fz": force}, outputs=["b.z"], t_end=0.2, dt=1e-3, method="modal")


def test_many_branches_keep_the_dense_path_and_say_so():
    zener = tuple(f"g{i}_{j}" for i in range(2) for j in range(4))            # 24 branches on 12 DOFs
    r = vibss.simulate(_model(2, zener), inputs={"b0.fz": lambda t: np.ones_like(t)}, outputs=["b0.z"],
                       t_end=0.05, dt=1e-3)
    assert r.method == "forced_response" and "the dense augmented matrix is cheaper" in r.note
