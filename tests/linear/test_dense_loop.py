"""The dense exact solve frequency by frequency (:func:`vibss.linear.solve.backends._dense_each`, plants
of ``LOOP_DOFS`` and more): backward stable against matrices written out here, the same bits
as numpy's batched LU it replaced, off the frequency axis too, and exactly singular frequencies flagged."""

from __future__ import annotations

import numpy as np
from threadpoolctl import threadpool_limits

import vibss.linear.solve.backends as backends
from vibss import Body, Model, Mount, MountType
from vibss.linear.plant.build import build_plant
from vibss.linear.solve.exact import response, states


def _chain(n: int) -> Model:
    """``n`` 2-6 kg bodies in a line, each on a damped, lossy mount to ground and one to the previous
    body, at offset points (every DOF coupled, non-proportional damping)."""
    rng = np.random.default_rng(11)
    bodies = [Body(f"b{i}", float(rng.uniform(2, 6)), rng.uniform(0.03, 0.05, 3), cog=[0.3 * i, 0, 0])
              for i in range(n)]
    mounts = []
    for i in range(n):
        t = MountType(f"t{i}", rng.uniform(1e4, 1e5, 3), rng.uniform(5, 50, 3), loss_factor=0.03)
        mounts.append(Mount(f"g{i}", t, f"b{i}", at=[0.3 * i + 0.05, 0.04, -0.06]))
        if i:
            mounts.append(Mount(f"l{i}", t, f"b{i}", to=f"b{i - 1}", at=[0.3 * i - 0.15, -0.03, 0.05]))
    return Model(bodies, mounts)


def test_the_loop_is_backward_stable_and_numpys_batched_lu_bit_for_bit() -> None:
    """Each solution's normwise backward error ``||b - A x|| / (||A|| ||x|| + ||b||)``, with ``A(s) =
    K + iH + sC + s^2 M`` written out here from the plant's matrices, is at most ``n eps`` (LU's
    level) at every frequency, on and off the frequency axis; and the answer is the batched LU's."""
    p = build_plant(_chain(20), ["b0.fz", "b7.fx"], ["b3.z", "b19.y"])
    assert p.n >= backends.LOOP_DOFS
    s = np.r_[2j * np.pi * np.linspace(1.0, 80.0, 40), -3.0 + 200j, 5.0 - 40j]
    x, bad = states(p, s, backend="dense")
    assert not bad.any()
    k, c, m, h = (np.asarray(getattr(p, a)) for a in ("K", "C", "M", "H"))
    b = np.asarray(p.F, dtype=complex)
    for i, sk in enumerate(s):
        a = k + 1j * h + sk * c + sk * sk * m
        eta = (np.linalg.norm(b - a @ x[i], axis=0)
               / (np.linalg.norm(a, 2) * np.linalg.norm(x[i], axis=0) + np.linalg.norm(b, axis=0)))
        assert eta.max() <= p.n * np.finfo(float).eps, (i, eta)
    # the same bits at the same BLAS threading: with two threads OpenBLAS splits its products
    # differently between the loop's calls and numpy's batched ones (last-bit differences)
    with threadpool_limits(1):
        y = response(p, s, backend="dense")
        limit = backends.LOOP_DOFS
        try:
            backends.LOOP_DOFS = 10**9                      # numpy's batched LU of the stacked matrices
            stock = response(p, s, backend="dense")
        finally:
            backends.LOOP_DOFS = limit
    np.testing.assert_array_equal(y, stock)


def test_an_exactly_singular_frequency_is_flagged_and_the_others_solved() -> None:
    """18 unconnected 1 kg bodies on 1e4 N/m mounts at their centres: ``K - w^2 M`` has exact zeros on
    its diagonal at 100 rad/s (a zero pivot), and is regular beside it."""
    t = MountType("t", [1e4, 1e4, 1e4])
    model = Model([Body(f"b{i}", 1.0, [1, 1, 1], cog=[i, 0, 0]) for i in range(18)],
                  [Mount(f"m{i}", t, f"b{i}", at=[i, 0, 0]) for i in range(18)])
    p = build_plant(model, ["b0.fz"], ["b0.z"])
    assert p.n >= backends.LOOP_DOFS
    x, bad = states(p, np.array([50j, 100j, 200j]), backend="dense")
    assert bad.tolist() == [False, True, False]
    z = p.dofs.index(next(d for d in p.dofs if d.startswith("b0") and d.endswith("z")))
    np.testing.assert_allclose(x[[0, 2], z, 0].real, [1 / (1e4 - 50.0**2), 1 / (1e4 - 200.0**2)], rtol=1e-14)
    assert not np.any(x[1])
