"""Issue 17 item 5: small models without overhead, and without a changed answer.

Two things are tested. The dense small-model path (the assembly, the stiffness factor G and the
Jacobi eigen path's products done in NumPy) gives *bit for bit* the digits of the scipy.sparse path
it replaces -- the reference is scipy.sparse itself, on the badly scaled family where the order of
summation is part of the answer. And the memo (:mod:`vibss.linear.plant.memo`) that hands a model's
assembly, plants and spectra out again is keyed right: the same model gives what a fresh solve
gives, another model (even an equal one) is solved anew, a large one is not kept, and what is kept
stays read-only.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
import cases.models as cases
from cases.models import asymmetric_model, prism_model, two_mass_model
from cases.scaled import graded_chain, hanging_chain, instrument, stiff_links

import vibss
from vibss import Body, Model, Mount, MountType
from vibss.linear.plant import memo
from vibss.linear.plant.assemble import _assemble, assemble
from vibss.linear.eigen.jacobi import _sparse_order_product
from vibss.linear.eigen.checks import _inverse_cholesky
from vibss.linear.plant.build import build_plant

MODELS = {
    "prism": prism_model, "two_mass": two_mass_model, "asymmetric": asymmetric_model,
    "graded_chain": lambda: graded_chain(True), "hanging_chain": hanging_chain,
    "instrument": instrument, "stiff_links": lambda: stiff_links(1e14, True),
    "powertrain": lambda: vibss.load_example("powertrain"),
}


def bits(a: np.ndarray) -> bytes:
    return np.ascontiguousarray(a).tobytes()


@pytest.fixture(autouse=True)
def empty_memo():
    memo.forget()
    yield
    memo.forget()


@pytest.mark.parametrize("name", sorted(MODELS))
def test_dense_assembly_and_factor_are_the_sparse_path_bit_for_bit(name: str) -> None:
    """K, C, H, their ground couplings, M and the stiffness factor G of the dense path against the
    scipy.sparse assembly of the same model (COO sums, sparse slicing and adding, ``st @ B``)."""
    model = MODELS[name]()
    dense, sparse = _assemble(model, False), _assemble(model, True)
    assert not sp.issparse(dense.K) and sp.issparse(sparse.K)
    for key in ("M", "K", "C", "H"):
        assert bits(dense.dense(key)) == bits(sparse.dense(key)), key
    for key in ("Kg", "Cg", "Hg"):
        assert bits(getattr(dense, key)) == bits(getattr(sparse, key)), key
    gd, gs = dense.stiffness_factor(), sparse.stiffness_factor()
    assert gd.shape == gs.shape
    for part in ("data", "indices", "indptr"):
        assert bits(getattr(gd, part)) == bits(getattr(gs, part)), part


@pytest.mark.parametrize("name", sorted(MODELS))
def test_jacobi_products_are_scipys_bit_for_bit(name: str) -> None:
    """The two products of the Jacobi path, ``G L^-T`` and ``L^-T V``, against scipy.sparse's."""
    a = _assemble(model := MODELS[name](), True)
    g, li = a.stiffness_factor(), _inverse_cholesky(a.M)
    assert li is not None
    ref = (sp.csr_matrix(g) @ sp.csr_matrix(li).T).toarray()
    assert bits(_sparse_order_product(g.toarray(), li.toarray())) == bits(ref)
    v = np.random.default_rng(len(model.bodies)).standard_normal((a.n, a.n))
    assert bits(_sparse_order_product(li.toarray().T, v.T)) == bits(np.asarray(li.T @ v))
    # the dense mass matrix gives the same blocks of L^-1 as the sparse one
    ld = _inverse_cholesky(_assemble(model, False).M)
    for part in ("data", "indices", "indptr"):
        assert bits(getattr(ld, part)) == bits(getattr(li, part)), part


@pytest.mark.parametrize("name", ["graded_chain", "hanging_chain", "stiff_links"])
def test_modes_of_the_dense_path_are_the_sparse_paths(name: str) -> None:
    """The whole eigen path on the badly scaled family: frequencies and shapes bit for bit (the error
    bound multiplies by M in its own form, 6x6 blocks or sparse, as it did before: close, not equal)."""
    model = MODELS[name]()
    d, s = vibss.modes(_assemble(model, False)), vibss.modes(_assemble(model, True))
    for key in ("omega", "shapes"):
        assert bits(getattr(d, key)) == bits(getattr(s, key)), key
    np.testing.assert_allclose(d.error_estimate, s.error_estimate, rtol=1e-6)


def box() -> Model:
    return cases.box(10.0, [1.0, 1.2, 1.5], [1e4, 1.2e4, 2e4], [20.0, 30.0, 15.0], cog=[0.0, 0.0, 0.1],
                     at=[(0.3, 0.2, 0.0), (-0.3, 0.2, 0.0), (0.3, -0.2, 0.0), (-0.25, -0.2, 0.0)], name="box")


def test_the_same_model_is_remembered_and_another_is_not() -> None:
    m = box()
    assert assemble(m) is assemble(m)
    assert assemble(m, sparse=True) is not assemble(m)
    assert assemble(box()) is not assemble(m)            # equal, but another model
    p = build_plant(m, ["b.fz"], ["b.z"])
    assert build_plant(m, ["b.fz"], ["b.z"]) is p
    assert build_plant(m, ["b.fx"], ["b.z"]) is not p
    assert build_plant(m, ["b.fz"], ["b.z"], modal_damping=0.02) is not build_plant(m, ["b.fz"], ["b.z"],
                                                                                     modal_damping=0.02)
    # what is kept is read-only
    with pytest.raises(ValueError, match="read-only"):
        assemble(m).K[0, 0] = 1.0
    with pytest.raises(ValueError, match="read-only"):
        p.K[0, 0] = 1.0


def test_the_memo_is_bounded_and_holds_no_large_model() -> None:
    models = [box() for _ in range(memo.MODELS + 3)]
    first = assemble(models[0])
    for m in models[1:]:
        assemble(m)
    assert len(memo._MEMO) == memo.MODELS
    assert assemble(models[0]) is not first                 # dropped, least recently used
    t = MountType("t", [1e4] * 3)
    n = memo.SMALL_DOFS // 6 + 1
    big = Model([Body(f"b{i}", 1.0, [1, 1, 1], cog=[i, 0, 0]) for i in range(n)],
                [Mount(f"m{i}", t, f"b{i}") for i in range(n)])
    memo.forget()
    assert assemble(big) is not assemble(big)
    assert len(memo._MEMO) == 0


def requests(m: Model) -> list[np.ndarray]:
    f = np.linspace(1.0, 60.0, 40)
    u = {"b.fz": lambda t: np.sin(30 * t)}
    return [vibss.modes(m).omega, vibss.modes(m, n_modes=3).omega,
            vibss.frequency_response(m, ["b.fz"], ["b.z"], frequencies=f).response,
            vibss.simulate(m, inputs=u, outputs=["b.z"], t_end=0.3, dt=1e-3)["b.z"],
            vibss.simulate(m, inputs=u, outputs=["b.z"], t_end=0.3, dt=1e-3,
                           initial={"b": {"displacement": [0, 0, 1e-3, 0, 0, 0]}})["b.z"],
            vibss.simulate(m, inputs=u, outputs=["b.z"], t_end=0.2, dt=1e-3)["b.z"]]


def test_answers_asked_again_are_the_fresh_answers() -> None:
    """modes, frequency_response and simulate on a remembered model against a fresh solve of a new,
    equal model (nothing remembered): identical numbers, and no answer of one request (other
    n_modes, initial state or horizon) handed to another."""
    m = box()
    first, again = requests(m), requests(m)
    memo.forget()
    fresh = requests(box())
    assert first[1].shape == (3,) and first[4][0] == pytest.approx(1e-3) and first[5].shape == (201,)
    for a, b, c in zip(first, again, fresh):
        np.testing.assert_array_equal(a, b)
        np.testing.assert_array_equal(a, c)
    assert not np.array_equal(first[3], first[4])    # the initial displacement is not forgotten
    # a shorter run is the start of the longer (its own horizon: to round-off, the scan's blocks differ)
    np.testing.assert_allclose(first[5], first[3][:201], rtol=0, atol=1e-12 * np.abs(first[3]).max())


def test_components_of_a_dense_pattern_are_csgraphs() -> None:
    """The mass blocks of a small dense M are found without scipy.sparse: the same labels as
    ``scipy.sparse.csgraph.connected_components`` on random symmetric patterns."""
    from scipy.sparse.csgraph import connected_components

    from vibss.linear.eigen.checks import _components

    rng = np.random.default_rng(1)
    for _ in range(200):
        n = int(rng.integers(1, 30))
        p = rng.random((n, n)) < 0.08
        p = p | p.T | np.eye(n, dtype=bool)
        np.testing.assert_array_equal(_components(p), connected_components(sp.csr_matrix(p), directed=False)[1])


def test_dynamic_stiffness_on_the_imaginary_axis_is_the_complex_expression_bit_for_bit() -> None:
    """The real-arithmetic build of ``K + iH + sC + s^2 M`` at ``s = i w`` against the complex
    expression it replaces (``k0 + s C + s^2 M`` in complex arithmetic), bit for bit, on random
    matrices spanning twelve decades (with and without ``H``, negative and huge ``w``), and off the
    axis the complex expression itself."""
    from vibss.linear.solve.backends import dynamic_stiffness

    rng = np.random.default_rng(3)
    for trial in range(60):
        n = int(rng.integers(1, 14))
        k, c, m, h = (np.exp(rng.uniform(-14, 14, (n, n))) * rng.choice([-1.0, 1.0], (n, n)) for _ in range(4))
        k0 = k + 1j * h if trial % 2 else k
        w = np.exp(rng.uniform(-3, 9, 50)) * rng.choice([-1.0, 1.0], 50)
        s = 1j * w
        sc = s[:, None, None]
        ref = k0[None] + sc * c[None] + sc**2 * m[None]
        assert bits(dynamic_stiffness(k0, c, m, s)) == bits(ref)
        s2 = s + rng.uniform(-1, 1, 50)
        sc2 = s2[:, None, None]
        assert bits(dynamic_stiffness(k0, c, m, s2)) == bits(k0[None] + sc2 * c[None] + sc2**2 * m[None])


def test_resonance_marks_of_a_remembered_plant_follow_the_band_and_stay_read_only() -> None:
    """The marks kept for the last band (issue 17 item 5) against the modes themselves
    (:func:`vibss.modes`, a second path): every elastic natural frequency inside each band asked in
    turn, and the kept array cannot be made writeable through a result (issue 18)."""
    m = box()
    fn = vibss.modes(m).frequency_hz
    for lo, hi in ((1.0, 60.0), (0.5, 8.0), (1.0, 60.0), (20.0, 400.0)):
        f = np.linspace(lo, hi, 30)
        r = vibss.frequency_response(m, ["b.fz"], ["b.z"], frequencies=f)
        want = fn[(fn >= lo) & (fn <= hi) & (fn > 0)]
        np.testing.assert_allclose(r.natural_hz, want, rtol=1e-12)
        assert len(r.mode_labels) == want.size
        assert not r.response.flags.writeable
        with pytest.raises(ValueError):      # shared with the next call: not even by its flag
            r.natural_hz.flags.writeable = True


def test_a_grid_without_breakpoints_is_the_samples_themselves() -> None:
    """``make_grid`` without breakpoints inside the run (no ``union1d``) against the samples
    ``k dt`` and ``searchsorted`` written out here, and one step length of exactly ``dt``."""
    from vibss.time.kernels import make_grid

    for n, dt in ((1001, 1e-3), (7, 0.25), (50_000, 3.3e-5)):
        ts = dt * np.arange(n)
        for bps in (np.zeros(0), np.array([0.0, ts[-1], 2 * ts[-1]]), np.array([5 * dt])):
            g = make_grid(n, dt, bps)
            assert bits(g.t) == bits(ts) and bits(g.h) == bits(np.diff(ts))
            np.testing.assert_array_equal(g.samples, np.searchsorted(ts, ts))
            assert g.steps.tolist() == [dt] and not g.hkey.any()


def test_one_blas_thread_sets_every_pool_to_one_and_puts_it_back() -> None:
    """The time runs' own limiter (threadpoolctl's pools set directly) against threadpoolctl's
    report of them: one thread inside, nested too, and what was there before afterwards."""
    from threadpoolctl import threadpool_info

    from vibss.time.kernels import one_blas_thread

    before = [i["num_threads"] for i in threadpool_info()]
    with one_blas_thread():
        assert all(i["num_threads"] == 1 for i in threadpool_info())
        with one_blas_thread():
            assert all(i["num_threads"] == 1 for i in threadpool_info())
        assert all(i["num_threads"] == 1 for i in threadpool_info())
    assert [i["num_threads"] for i in threadpool_info()] == before


def test_small_lapack_calls_are_numpys_bit_for_bit_and_fail_as_numpy_does() -> None:
    """``inverse_cholesky`` and ``eigh_small`` (numpy.linalg's gufuncs without their wrappers) give
    ``np.linalg.inv(np.linalg.cholesky(m))`` and ``np.linalg.eigh(a)`` bit for bit, one matrix or a
    stack; a mass block that is not positive definite, or a NaN, raises numpy's LinAlgError (no
    FloatingPointError, no RuntimeWarning)."""
    import warnings

    from vibss.linear.eigen.small import eigh_small, inverse_cholesky

    rng = np.random.default_rng(34)
    a = rng.standard_normal((5, 6, 6))
    spd = a @ a.transpose(0, 2, 1) + 1e-3 * np.eye(6)
    assert bits(inverse_cholesky(spd)) == bits(np.linalg.inv(np.linalg.cholesky(spd)))
    assert bits(inverse_cholesky(spd[0])) == bits(np.linalg.inv(np.linalg.cholesky(spd[0])))
    w, v = eigh_small(spd[1])
    ref = np.linalg.eigh(spd[1])
    assert bits(w) == bits(ref[0]) and bits(v) == bits(ref[1])
    bad = spd.copy()
    bad[2] = -bad[2]                                   # one block of the stack not positive definite
    nan = spd[0].copy()
    nan[0, 0] = np.nan
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(np.linalg.LinAlgError):
            inverse_cholesky(bad)
        with pytest.raises(np.linalg.LinAlgError):
            eigh_small(nan)
