"""Issue 18: a refusal suggests only what the refusing function accepts.

``simulate(method='modal')`` on a model whose complex modes are defective said "use method='sparse'
or 'direct'" — frequency-response methods that ``simulate`` does not take. Each suggestion is now
taken from the refusing function's own registry, and this test runs every suggestion.
"""

from __future__ import annotations

import numpy as np
import pytest

import vibss

from test_signals import two_body
from vibss import (Body, DefectiveModesError, Excitation, Model, Mount, MountType, Step, frequency_response,
                   simulate, symmetric)
from vibss.frequency.kernels import METHODS as FREQUENCY_METHODS
from vibss.time.methods import METHODS as TIME_METHODS


def critical() -> Model:
    """two_body (non-proportional damping) plus a body whose z mode is critically damped: its
    complex modes are a Jordan block (nearly dependent eigenvectors)."""
    k, c = 1e4, 2 * np.sqrt(1e4)
    base = two_body()
    iso = MountType("tiso", [3 * k / 4, k / 2, k / 4], [0.01 * c, 0.01 * c, c / 4])
    return Model(list(base.bodies) + [Body("iso", 1.0, [0.1, 0.12, 0.14], cog=[3, 0, 0])],
                 list(base.mounts) + list(symmetric(Mount("iso", iso, "iso", at=[0.3, 0.2, 0.0]))))


def test_simulate_suggests_only_its_own_methods(monkeypatch: pytest.MonkeyPatch) -> None:
    import vibss.time.kernels as tk
    from vibss.linear.eigen import complex_modes as cm

    def refuse(*args: object, **kwargs: object) -> object:   # the core's own refusal, as on a Jordan block
        raise DefectiveModesError("complex modes: the eigenvectors are nearly dependent (cond(V) ~ 1e16: "
                                  "critically damped or defective modes), so a modal sum would lose accuracy")

    kick = [Excitation("kick", "force", "engine", Step(1.0), dof="z")]
    kw = dict(outputs=["engine.z"], t_end=0.05, dt=1e-3)
    monkeypatch.setattr(tk, "complex_modes", refuse)          # two_body: non-proportional damping
    with pytest.raises(DefectiveModesError, match=r"simulate: method 'modal' refused: .*nearly dependent") as err:
        simulate(two_body(), kick, method="modal", **kw)
    monkeypatch.setattr(tk, "complex_modes", cm.complex_modes)
    text = str(err.value)
    assert "'sparse'" not in text and "'direct'" not in text
    suggested = err.value.expected
    assert suggested and set(suggested) <= set(TIME_METHODS) and "modal" not in suggested
    ref = simulate(two_body(), kick, method="forced_response", **kw).outputs
    for method in suggested:                        # every suggestion is accepted and agrees
        got = simulate(two_body(), kick, method=method, **kw).outputs
        assert np.abs(got - ref).max() <= 0.05 * np.abs(ref).max(), method


def test_frequency_response_suggests_exact_methods() -> None:
    args = (critical(), ["iso.fz"], ["iso.z"], [1.0, 5.0])
    with pytest.raises(DefectiveModesError, match="method 'complex_modal' refused") as err:
        frequency_response(*args, method="complex_modal")
    assert set(err.value.expected) == {n for n, m in FREQUENCY_METHODS.items() if m.exact}
    ref = frequency_response(*args, method="direct").response
    for method in err.value.expected:
        np.testing.assert_allclose(frequency_response(*args, method=method).response, ref, rtol=1e-9)


def _row(n: int, free_z: int | None, gravity: bool) -> Model:
    """n boxes in a row, each on four mounts, linked to the next (links without z stiffness);
    box ``free_z`` has mounts without z stiffness: free to move in z."""
    t = MountType("t", [1e4, 1.2e4, 2e4])
    free = MountType("f", [1e4, 1.2e4, 0.0])
    link = MountType("l", [1e3, 1e3, 0.0])
    bodies, mounts = [], []
    for i in range(n):
        bodies.append(Body(f"b{i}", 10.0 + i % 7, [1.0, 1.1, 1.2], cog=[2.0 * i, 0, 0]))
        mounts += list(symmetric(Mount(f"m{i}", free if i == free_z else t, f"b{i}", at=[0.3, 0.2, 0.0])))
        if i:
            mounts.append(Mount(f"l{i}", link, f"b{i}", to=f"b{i - 1}", at=[-1.0, 0.0, 0.5]))
    return Model(bodies, mounts, gravity=[0.0, 0.0, -9.81] if gravity else None)


def test_free_motions_of_a_large_model_are_found_without_dense_work(monkeypatch: pytest.MonkeyPatch) -> None:
    """Issue 18: `static` on a 1,000-body model with a free motion took 76 s and 1.6 GB (a dense
    eigendecomposition and a dense M) before naming it. Above NULL_DENSE_MAX free DOFs the free
    motions are found per connected component and by sparse shift-invert; the answer is the dense
    path's."""
    import vibss.linear.solve.static as st
    from vibss import AnalysisError, static

    n = 130                                              # 780 DOFs > NULL_DENSE_MAX
    assert 6 * n > st.NULL_DENSE_MAX
    dense_eigen = st.symmetric_eigen

    def small_only(a: np.ndarray) -> object:
        assert a.shape[0] <= st.NULL_DENSE_MAX, f"dense eigen of {a.shape[0]} DOFs"
        return dense_eigen(a)

    loaded = _row(n, 60, gravity=True)
    with monkeypatch.context() as mp:
        mp.setattr(st, "symmetric_eigen", small_only)
        with pytest.raises(AnalysisError, match=r"do not restrain the load: body 'b60' is free to move in z"):
            static(loaded)
    unloaded = _row(n, 60, gravity=False)
    load = np.zeros(6 * n)
    load[0::6] = 1.0                                     # x forces: along no free motion
    with monkeypatch.context() as mp:
        mp.setattr(st, "symmetric_eigen", small_only)
        sparse = static(unloaded, load)
    monkeypatch.setattr(st, "NULL_DENSE_MAX", 10**6)     # the dense path on the same model
    dense = static(unloaded, load)
    assert sparse.free_motions == dense.free_motions == ("body 'b60' is free to move in z",)
    np.testing.assert_allclose(sparse.q, dense.q, rtol=1e-9, atol=1e-12 * np.abs(dense.q).max())


@pytest.mark.parametrize("make, message", [
    (lambda: vibss.Body("b", 1e-300, [1, 1, 1]), r"body 'b': mass: 1e-300 kg is outside .*1e-09 \.\. 1e\+10 kg"),
    (lambda: vibss.Body("b", 1.0, [1e-20] * 3), r"body 'b': inertia \(principal moments\): 1e-20"),
    (lambda: vibss.Body("b", 1.0, [1, 1, 1], cog=[0, 0, 1e9]), r"body 'b': cog: 1e\+09 m"),
    (lambda: vibss.MountType("t", [1e25, 1.0, 1.0]), r"mount type 't': stiffness: 1e\+25 N/m"),
    (lambda: vibss.MountType("t", [1e3, 1.0, 1.0], [1e20, 0, 0]), r"mount type 't': damping: 1e\+20 N s/m"),
    (lambda: vibss.MountType("t", [1e-9, 1.0, 1.0]), r"stiffness: 1e-09 N/m"),
    (lambda: vibss.Orientation.from_euler([-1e20, 0, 0], degrees=True), r"within \+-360 degrees"),
])
def test_the_python_api_refuses_what_files_refuse(make, message):
    """Issue 18: the ranges of vibss.model.limits.PLAUSIBLE hold for the Python API as for files."""
    with pytest.raises(vibss.ModelError, match=message):
        make()
    # and the limits themselves are accepted: a zero stiffness axis means "none"
    vibss.MountType("t", [0.0, 1e-6, 1e20], [0.0, 0.0, 1e16])
    vibss.Body("b", 1e-9, [1e-15, 1e-15, 1e-15], cog=[1e5, -1e5, 0.0])
