"""The standing adversarial suite of issue 18: random models against an independent reference,
invariants, a loader fuzzer, threads and pickling.

Short, seeded and deterministic in every test run (``derandomize=True``: the same examples each
time); ``make fuzz`` runs the same tests longer (``VIBSS_FUZZ=1``: 1,000 models per property,
10,000 mutated files; figures in docs/robustness.md), and ``VIBSS_FUZZ_SEED=<int>`` draws other
models (deterministic per seed). Random models come from
:func:`fuzzing.model_specs` (1-6 bodies, masses over seven decades, full inertia tensors, inclined
mounts, zero-stiffness axes, links from soft to 1e16 N/m, non-proportional viscous and hysteretic
damping, rigid modes); the reference is ``tests/cases/mp_reference.py`` (60 digits) and
``tests/cases/reference_impl.py`` (loops per mount), which share no code with vibss.

Stated tolerances (the figures the long run is held to):

- assembly: every entry of M, K, C, H within 1e-13 of the largest entry of the reference;
- modes: elastic w^2 within 1e-8 (relative) of the 60-digit values; every reference rigid mode
  (|w^2| < 1e-30 of the largest) flagged rigid (w^2 exactly 0), nothing flagged rigid whose
  reference w^2 exceeds 1e-24 of the largest;
- frame invariance (the model rotated and moved as a whole): the same within 1e-7 (relative);
- time: ``simulate`` by modal superposition and by ``forced_response`` within 1e-8 of the largest output;
- statics and FRF: within 1e-8 of the largest reference value (60 digits); reciprocity within 1e-8 (the
  accuracy promised; 2.7e-9 measured with 1e12 N/m links beside 1e4 N/m mounts);
  the FRF at 0 Hz applied to the load is the static deflection (without hysteretic damping: with it,
  ``(K + iH)^-1`` is complex and is checked against 60 digits instead).
"""

from __future__ import annotations

import contextlib
import io
import pickle
import signal
import threading
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import HealthCheck, Phase, event, given, seed, settings  # noqa: E402
from hypothesis.control import currently_in_test_context  # noqa: E402

from cases import fuzzing  # noqa: E402
from cases import mp_reference  # noqa: E402
import vibss  # noqa: E402
from vibss.linear.eigen import complex_modes  # noqa: E402
from vibss.cli import main  # noqa: E402
from vibss.errors import AnalysisError, DefectiveModesError  # noqa: E402
from vibss.io.modelfile import example_path  # noqa: E402

SETTINGS = settings(max_examples=fuzzing.MODELS, derandomize=True, deadline=None, database=None,
                    suppress_health_check=list(HealthCheck), print_blob=True,
                    phases=[Phase.explicit, Phase.generate])      # no shrinking: the example is printed


def DRAW(test: Callable[..., None]) -> Callable[..., None]:   # noqa: N802  (used as a decorator)
    """``VIBSS_FUZZ_SEED`` set: every property draws its models from that seed (another draw)."""
    return test if fuzzing.SEED is None else seed(fuzzing.SEED)(test)


RIGID = 1e-30
"""A reference eigenvalue below this fraction of the largest is a rigid-body mode."""

RIGID_FLAGGED = 1e-24
"""vibss may call a mode rigid when its 60-digit w^2 is below this fraction of the largest (a
frequency 1e-12 of the top: the round-off of lever arms computed from positions,
``vibss.linear.eigen.checks.ROUNDOFF_LEVERS``); between this and :data:`RIGID` either answer is
right."""


def _split(w2: np.ndarray) -> tuple[np.ndarray, float]:
    top = max(float(np.abs(w2).max()), 1e-300)
    return np.abs(w2) <= RIGID * top, top


def _forces(model: vibss.Model) -> tuple[list[str], list[str]]:
    inputs = [f"{b.name}.f{d}" if not d.startswith("r") else f"{b.name}.m{d[1]}"
              for b in model.bodies for d in vibss.DOF_NAMES]
    return inputs, [f"{b.name}.{d}" for b in model.bodies for d in vibss.DOF_NAMES]


# -- random models against the independent reference ----------------------------------------------
@DRAW
@SETTINGS
@given(fuzzing.model_specs())
def test_assembly_matches_the_loop_reference(spec: fuzzing.Spec) -> None:
    model = fuzzing.build(spec)
    asm = vibss.assemble(model)
    for name, ref in zip("MKCH", fuzzing.reference_matrices(model)):
        scale = max(float(np.abs(ref).max()), 1e-300)
        assert np.abs(asm.dense(name) - ref).max() <= 1e-13 * scale, name
    sparse = vibss.assemble(model, sparse=True)
    np.testing.assert_array_equal(sparse.dense("K"), asm.dense("K"))


@DRAW
@SETTINGS
@given(fuzzing.model_specs())
def test_modes_match_60_digits(spec: fuzzing.Spec) -> None:
    model = fuzzing.build(spec)
    md = vibss.modes(model)
    ref = mp_reference.omega2(model)
    rigid, top = _split(ref)
    mine = md.omega ** 2
    assert np.all(md.rigid[rigid])                        # every rigid mode is flagged rigid ...
    assert np.all(np.abs(ref[md.rigid]) <= RIGID_FLAGGED * top)    # ... and nothing elastic is
    assert np.all(mine[md.rigid] == 0)
    assert np.all(np.abs(mine[~md.rigid] - ref[~md.rigid]) <= 1e-8 * ref[~md.rigid])
    phi = md.shapes                                       # and its shapes are M-orthonormal
    M = fuzzing.reference_matrices(model)[0]
    np.testing.assert_allclose(phi.T @ M @ phi, np.eye(len(mine)), atol=1e-9)


@DRAW
@SETTINGS
@given(fuzzing.model_specs(), hypothesis.strategies.integers(0, 2**32 - 1))
def test_frame_invariance(spec: fuzzing.Spec, seed: int) -> None:
    """Rotating and moving the whole model (gravity too) changes no frequency."""
    base = vibss.modes(fuzzing.build(spec)).omega
    rng = np.random.default_rng(seed)
    moved = vibss.modes(fuzzing.build(spec, fuzzing.rotation(seed), rng.uniform(-2, 2, 3))).omega
    top = max(float(base.max()), 1e-300)
    elastic = base > 1e-5 * top
    assert np.all(np.abs(moved[elastic] - base[elastic]) <= 1e-7 * base[elastic])
    assert np.all(moved[~elastic] <= 1e-4 * top)


@DRAW
@SETTINGS
@given(fuzzing.model_specs())
def test_statics_match_60_digits_and_the_frf_at_0_hz(spec: fuzzing.Spec) -> None:
    model = fuzzing.build(spec)
    load = vibss.assemble(model).load_vector(include_gravity=True)
    rigid, _ = _split(mp_reference.omega2(model))
    if rigid.any():                                      # free motions: refused when loaded, else solved
        try:
            r = vibss.static(model)
        except AnalysisError as exc:
            assert "do not restrain" in str(exc)
        else:
            assert r.free_motions
        return
    q = vibss.static(model).q
    ref = fuzzing.mp_static(model, load)
    scale = float(np.abs(ref).max())
    assert np.abs(q - ref).max() <= 1e-8 * scale
    inputs, outputs = _forces(model)
    h0 = vibss.frequency_response(model, inputs, outputs, frequencies=[0.0], method="direct").response[:, :, 0]
    if any(np.any(m.type.loss_factor) for m in model.mounts):   # hysteresis: (K + iH)^-1 at 0 Hz
        ref0 = fuzzing.mp_solve(model, 0.0, load)[:, 0]
        assert np.abs(h0 @ load - ref0).max() <= 1e-8 * float(np.abs(ref0).max())
    else:
        assert np.abs(h0 @ load - q).max() <= 1e-8 * scale


@DRAW
@SETTINGS
@given(fuzzing.model_specs(), hypothesis.strategies.floats(0.1, 200.0))
def test_frf_matches_60_digits_and_is_reciprocal(spec: fuzzing.Spec, f_hz: float) -> None:
    model = fuzzing.build(spec)
    inputs, outputs = _forces(model)
    cols = [0, len(inputs) - 1]
    r = vibss.frequency_response(model, [inputs[j] for j in cols], outputs, frequencies=[f_hz])
    ref = fuzzing.mp_frf(model, f_hz, cols)
    h = r.response[:, :, 0]
    scale = float(np.abs(ref).max())
    assert np.abs(h - ref).max() <= 1e-8 * scale, r.method
    full = vibss.frequency_response(model, inputs, outputs, frequencies=[f_hz]).response[:, :, 0]
    big = float(np.abs(full).max())
    assert np.abs(full - full.T).max() <= 1e-8 * big


@DRAW
@SETTINGS
@given(fuzzing.model_specs())
def test_time_methods_agree(spec: fuzzing.Spec) -> None:
    """A step force: exact modal superposition and python-control's exact discretisation agree
    (rigid modes, stiff links and non-proportional damping included), or the modal form refuses
    nearly dependent complex modes in one line and ``auto`` gives python-control's answer."""
    model = fuzzing.build(spec)
    kick = [vibss.Excitation("kick", "force", "b0", vibss.Step(1.0), dof="z")]
    kw = dict(outputs=[f"b0.{d}" for d in vibss.DOF_NAMES], t_end=0.05, dt=1e-3)
    ref = vibss.simulate(model, kick, method="forced_response", **kw).outputs
    try:
        modal = vibss.simulate(model, kick, method="modal", **kw).outputs
    except DefectiveModesError as exc:
        # the modal form's own refusal (nearly dependent complex modes, e.g. a rigid mode that
        # the damping couples): it must say so, and `auto` must then give forced_response's answer
        assert "nearly dependent" in str(exc)
        if currently_in_test_context():           # not when a pinned model calls the inner test
            event("modal refused: nearly dependent complex modes; auto took forced_response")
        auto = vibss.simulate(model, kick, **kw)
        assert "auto -> forced_response: modal refused" in auto.note
        np.testing.assert_array_equal(auto.outputs, ref)
        return
    tol = 1e-8 * max(float(np.abs(ref).max()), 1e-300)
    if np.abs(modal - ref).max() > tol:
        # they disagree: a certified expm (ball arithmetic, its own error bound) says which is off, and
        # vibss's own method must be right
        exact, radius = mp_reference.step_response_certified(model, np.eye(6 * len(model.bodies))[2], 1e-3, 50)
        assert radius < 1e-12
        if currently_in_test_context():
            event("modal and forced_response disagree; modal checked against a certified expm")
        assert np.abs(modal - exact).max() <= tol


# -- the loader fuzzer ---------------------------------------------------------------------------------
COMMANDS = (["modes"], ["static"], ["frf"])


class _Hang(Exception):
    pass


def _alarm(signum: int, frame: Any) -> None:
    raise _Hang


def run_cli(argv: list[str], seconds: int = 30) -> tuple[int, str]:
    """``vibss ARGV`` in process: (exit status, stderr); a run over ``seconds`` is a failure."""
    out, err = io.StringIO(), io.StringIO()
    old = signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(seconds)
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            status = main(argv)
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)
    return status, err.getvalue()


@pytest.mark.filterwarnings("error::RuntimeWarning")     # an overflow warning is a second line: a bug
def test_mutated_model_files_exit_0_2_or_3_in_one_line(tmp_path: Path) -> None:
    texts = {name: example_path(name).read_text() for name in vibss.example_names()}
    counts = {0: 0, 2: 0, 3: 0}
    for i, (name, text) in enumerate(fuzzing.mutated_files(texts, fuzzing.FILES)):
        path = tmp_path / f"{i % 50}.toml"
        path.write_bytes(text.encode("utf-8", "surrogatepass"))
        before = path.read_bytes()
        argv = COMMANDS[i % len(COMMANDS)] + [str(path)]
        status, err = run_cli(argv)
        assert status in counts, f"{name}: vibss {' '.join(argv)} exited {status}: {err}"
        assert status == 0 or err.count("\n") == 1, f"{name}: {err}"
        assert "Traceback" not in err
        assert path.read_bytes() == before
        counts[status] += 1
    print(f"\nfuzzed {sum(counts.values())} mutated files: exit 0: {counts[0]}, exit 2: {counts[2]}, "
          f"exit 3: {counts[3]}; no traceback, no hang, no other status, no input changed")
    assert counts[2] > 0 and counts[0] > 0                 # the mutations reach both outcomes


@pytest.mark.filterwarnings("error::RuntimeWarning")
def test_a_huge_direction_is_normalised_not_overflowed() -> None:
    """Found by the long run (platform example, sensor ``direction = [1e308, 1, 0]``): the norm
    overflowed to inf with a RuntimeWarning and the direction became ``[0, 0, 0]``."""
    from vibss.model.actuation import Sensor

    s = Sensor("v", "velocity", body="b", direction=[1e308, 1.0, 0.0])
    assert s.direction.tolist() == [1.0, 1e-308, 0.0]
    e = vibss.Excitation("e", "force", "b", vibss.Step(1.0), direction=[3e-300, 0.0, -4e-300])
    np.testing.assert_allclose(e.direction, [0.6, 0.0, -0.8], rtol=1e-15)


# -- threads and pickling ------------------------------------------------------------------------------
ANALYSES: dict[str, Callable[[vibss.Model], np.ndarray]] = {
    "modes": lambda m: vibss.modes(m).omega,
    "static": lambda m: vibss.static(m).q,
    "frf": lambda m: vibss.frequency_response(m, ["powertrain.fz"], ["powertrain.z", "powertrain.rx"], frequencies=[2.0, 9.0, 30.0]).response,
    "damped": lambda m: vibss.damped_modes(m).poles,
    "modal": lambda m: vibss.simulate(m, t_end=0.3, dt=1e-3, method="modal").outputs,
    "forced_response": lambda m: vibss.simulate(m, t_end=0.3, dt=1e-3, method="forced_response").outputs,
    "ivp": lambda m: vibss.simulate(m, t_end=0.3, dt=1e-3, method="ivp").outputs,
}
IVP_RTOL = 1e-12
"""simulate(method='ivp') from several threads agrees to this (relative to the largest output): its
adaptive steps follow floating-point details that BLAS may order differently per thread; every
other analysis is bit-identical."""


@pytest.mark.parametrize("name", list(ANALYSES))
def test_eight_threads_give_the_main_threads_answers(name: str) -> None:
    model = vibss.load_example("powertrain")
    ref = ANALYSES[name](model)
    got: list[Any] = [None] * 8

    def work(i: int) -> None:
        got[i] = ANALYSES[name](model)

    threads = [threading.Thread(target=work, args=(i,)) for i in range(8)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(120)
    for g in got:
        assert g is not None
        if name == "ivp":
            assert np.abs(g - ref).max() <= IVP_RTOL * np.abs(ref).max()
        else:
            np.testing.assert_array_equal(g, ref)


def test_time_runs_from_several_threads_leave_the_blas_threads_as_they_were() -> None:
    """Found checking issue 18's ivp remark: the modal recursion and ``forced_response`` each
    limited BLAS to one thread with ``threadpool_limits``, a process-wide setting restored to what
    each call saw on entry. Two runs overlapping as A enters, B enters, A leaves, B leaves left the
    process on one BLAS thread for good (seen after 8 threads of ``simulate``). That order, forced."""
    from threadpoolctl import threadpool_info

    from vibss.time.kernels import one_blas_thread

    step = [threading.Event() for _ in range(3)]

    def a() -> None:
        with one_blas_thread():
            step[0].set()
            step[1].wait(10)
        step[2].set()

    def b() -> None:
        step[0].wait(10)
        with one_blas_thread():
            step[1].set()
            step[2].wait(10)

    before = [i["num_threads"] for i in threadpool_info()]    # the environment's (2 cores: 2)
    threads = [threading.Thread(target=a), threading.Thread(target=b)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(30)
    assert [i["num_threads"] for i in threadpool_info()] == before


@DRAW
@SETTINGS
@given(fuzzing.model_specs())
def test_pickled_models_give_the_same_answers(spec: fuzzing.Spec) -> None:
    model = fuzzing.build(spec)
    back = pickle.loads(pickle.dumps(model))
    np.testing.assert_array_equal(vibss.modes(back).omega, vibss.modes(model).omega)
    md = vibss.modes(model)
    again = pickle.loads(pickle.dumps(md))
    np.testing.assert_array_equal(again.frequency_hz, md.frequency_hz)
    assert not again.omega.flags.writeable


def test_an_inclined_zero_stiffness_axis_is_not_a_singular_block() -> None:
    """Found by this suite: a mount with one zero principal stiffness, inclined, has a rounded
    global ``kp`` whose smallest eigenvalue is +2e-12 instead of 0; the mounts' exact form took it
    as positive definite and its singular ``Z(s)`` ended in ``LinAlgError: Singular matrix``. (Such
    a mount is now kept apart per stiff local axis, a scalar ``Z`` each, never as a 3 x 3 block.)"""
    from scipy.spatial.transform import Rotation

    t = vibss.MountType("t", [430163.3193050424, 0.0, 1661723.4748265292], [4301.6, 0.0, 16617.2], 0.05)
    soft = vibss.MountType("s", [1e4, 2e4, 3e4], [10.0, 30.0, 20.0])
    R = Rotation.from_quat([0.5420314059089282, -0.08863364395539232, -0.15013221758244688,
                            -0.8220744184143892]).as_matrix()
    model = vibss.Model([vibss.Body("b", 2.0, [0.1, 0.2, 0.25])],
                        [vibss.Mount("a", t, "b", at=[0.1, 0.2, 0.0], orientation=R)]
                        + list(vibss.symmetric(vibss.Mount("m", soft, "b", at=[0.3, 0.2, -0.1]))))
    inputs, outputs = _forces(model)
    for f_hz in (1.0, 40.0):
        got = vibss.frequency_response(model, inputs, outputs, frequencies=[f_hz], method="sparse").response[:, :, 0]
        ref = fuzzing.mp_frf(model, f_hz, list(range(6)))
        assert np.abs(got - ref).max() <= 1e-10 * np.abs(ref).max()


def test_an_unflagged_zero_frequency_does_not_divide_by_zero() -> None:
    """Found by the long run: a free motion that touches the mounts only at round-off level (both
    norms of the rigid test ~1e-13) came out of the Jacobi solver with w^2 = 0 but not flagged
    rigid, and the modal realization divided by its zero scale (forced_response: RuntimeWarning,
    inf). Mount 0's damping of 2.4e-302 N s/m is as hypothesis drew it."""
    test_time_methods_agree.hypothesis.inner_test(_ROUND_OFF_ROTATION)      # type: ignore[attr-defined]


_ROUND_OFF_ROTATION = fuzzing.Spec(
    masses=(0.3241830965265331,), spreads=((0.9998594712341624, 0.01, 0.002560790487202888),),
    axes=((-1.0742533474085465, -1.9451184006994062, 0.6180339887498949),),
    cogs=((0.4122731339886847, 0.10337233851257799, -0.4039931497140613),),
    mounts=((0, -1, (0.4122731339886857, 0.10337233851257799, -0.530919300878596), (0.5, -0.5, -0.28318975039989297),
             (2152760.727902773, 2152760.727902773, 0.0), (2.395025809638697e-302, 3782.730464452283, 0.0), 0.0),
            (0, -1, (0.4122731339886847, 0.10337233851257799, -0.4039931497140613), (1.0, 1.73, -5.07660693271757e-45),
             (359.03901107354903, 2152760.727902773, 51912.202541547296),
             (3.5903901107354904e-06, 2.7973662269365573e-224, 5.19122025415473e-11), 0.0)))


@pytest.mark.parametrize("ground", [
    (457652.3420089377, 0.0, 0.0),
    (0.0, 0.0, 0.0)])
def test_a_stiff_link_beside_a_single_axis_mount_is_solved_in_the_mounts_form(ground: tuple) -> None:
    """Found by the long run: a 13 g body held by one single-axis 4.6e5 N/m mount, linked by
    2e13 ... 8e13 N/m to a free 4.6 t body. The mount with zero axes is assembled with the rest, so the
    stiffness ratio that chooses the mounts' form saw the link alone (3.7) and the assembled form
    lost 4.7e-3 of the FRF (``direct``; 4.1e-3 ``sparse``) against 60 digits. With no stiffness to
    ground at all (only inertia holds the 13 g body) the stiffness ratio is 3.7 and the assembled form
    lost 1.6e-3: the mounts' form is now chosen below the frequency where the link's round-off would
    swamp the inertia holding the free motions (``MountForm.inertia_w2``)."""
    spec = fuzzing.Spec(
        masses=(0.01326724803150852, 4576.753184177788),
        spreads=((0.9999999999999994, 0.005246995596342535, 0.03311344134944793), (0.02293242204900574, 0.2107556164974517, 0.1)),
        axes=((-2.568673140654491, 0.8952350919654499, -1.1125369292536007e-308),
              (-8.09449804378436e-211, -0.021832797059942344, -2.2250738585e-313)),
        cogs=((0.42994173513624356, 0.3533068768252312, -0.9094202388947035),
              (-7.435378542279869e-184, -2.152828192866674e-57, 0.17391179141299706)),
        mounts=((0, -1, (0.43012427486401206, 0.6363400278296703, -0.9094202388947035),
                 (-1.692192518845633, -1.8734109338444936e-76, -2.9246569313511417),
                 ground, (0.0, 0.0, 0.0), 0.0),
                (1, 0, (-1.9256192622707014e-75, 5.960464477539063e-08, 0.17391179141299706),
                 (-0.3244883538096053, -1.8635406444868896, -2.731229785180112),
                 (22548026857379.746, 63602496805000.164, 84137367843376.64), (0.0, 0.0, 0.0), 0.0)))
    model = fuzzing.build(spec)
    inputs, outputs = _forces(model)
    ref = fuzzing.mp_frf(model, 1.9, [0])
    for method in ("direct", "sparse"):
        h = vibss.frequency_response(model, inputs[:1], outputs, frequencies=[1.9], method=method).response[:, :, 0]
        assert np.abs(h - ref).max() <= 1e-8 * np.abs(ref).max(), method


def test_one_sweep_mixes_the_forms_by_frequency_and_keeps_the_exact_resonance() -> None:
    """A 1 kg body on one 3-axis mount at its COG (f_n = 1 Hz) rotates freely, so below
    ``sqrt(inertia_w2 / MOUNTS_RATIO)`` (``inertia_w2 = k / m``: 0.032 Hz) its sweep is solved in the
    mounts' form, above it in the assembled form, whose exact zero pivot at 1 Hz is an unbounded
    response. Both parts against the closed form ``1 / (k - m w^2)``."""
    from vibss.linear.plant.build import build_plant
    from vibss.linear.solve.exact import _mounts_at

    k = (2 * np.pi) ** 2
    model = vibss.Model([vibss.Body("b", 1.0, [1, 1, 1])], [vibss.Mount("m", vibss.MountType("t", [k] * 3), "b")])
    f = np.array([0.001, 0.01, 1.0, 2.0])
    plant = build_plant(model, ["b.fz"], ["b.z"])
    assert plant.mounts is not None and plant.mounts.inertia_w2 == pytest.approx(k, rel=1e-12)
    assert _mounts_at(plant, "auto", 2j * np.pi * f).tolist() == [True, True, False, False]
    h = vibss.frequency_response(model, ["b.fz"], ["b.z"], frequencies=f, method="direct").response[0, 0]
    assert np.isinf(h[2].real)
    w = 2 * np.pi * f[[0, 1, 3]]
    np.testing.assert_allclose(h[[0, 1, 3]], 1 / (k - w**2), rtol=1e-12)


def test_a_nearly_free_rotation_at_0_hz_keeps_the_statics_digits() -> None:
    """The mechanism of the long run's "static = FRF at 0 Hz" failure (3.8e-8 of a 1.45e6 m
    deflection): three mounts nearly in line (lever arms of 1e-5 m beside 0.5 m), the model turned
    so that the weak rotation is no coordinate axis. Its stiffness cancels in the assembled K's entries
    (FRF at 0 Hz 1e-7 off 60 digits); statics, from the stiffness factor, keeps 1e-11."""
    d = 1e-5
    mounts = tuple((0, -1, at, (0.0, 0.0, 0.0), (1e5, 2e5, 3e5), (0.0, 0.0, 0.0), 0.0)
                   for at in ((-0.5, 0.0, 0.0), (0.5, d, 0.0), (0.1, 0.0, d)))
    spec = fuzzing.Spec(masses=(2.0,), spreads=((0.05, 0.1, 0.15),), axes=((0.3, 0.2, 0.1),), cogs=((0.0, 0.0, 0.0),),
                        mounts=mounts)
    model = fuzzing.build(spec, fuzzing.rotation(3), np.array([0.3, -0.7, 1.1]))
    load = vibss.assemble(model).load_vector(include_gravity=True)
    ref = fuzzing.mp_static(model, load)
    scale = float(np.abs(ref).max())
    assert np.abs(vibss.static(model).q - ref).max() <= 1e-8 * scale
    inputs, outputs = _forces(model)
    for method in ("direct", "sparse"):
        h0 = vibss.frequency_response(model, inputs, outputs, frequencies=[0.0], method=method).response[:, :, 0]
        assert np.abs(h0 @ load - ref).max() <= 1e-10 * scale, method


def test_a_rotation_touching_the_mounts_at_round_off_is_flagged_rigid() -> None:
    """Found by the long run: the model of the test above has a rotation about an axis through both
    mounts up to 1e-15 m (the 60-digit w^2 is 1.5e-54 of 1.5e7); both norms of the per-mode rigid test
    were round-off (1.3e-13 / 5.4e-12), so ``modes`` printed it as a 0 Hz elastic mode."""
    model = fuzzing.build(_ROUND_OFF_ROTATION)
    rigid, _ = _split(mp_reference.omega2(model))
    assert rigid.tolist() == [True] + [False] * 5
    md = vibss.modes(model)
    assert md.rigid.tolist() == rigid.tolist()
    assert "(rigid)" in str(md)                      # what `vibss modes` prints
    test_modes_match_60_digits.hypothesis.inner_test(_ROUND_OFF_ROTATION)   # type: ignore[attr-defined]


def test_every_rigid_mode_of_a_six_body_model_is_flagged() -> None:
    """Found by the fourth long run: ten rigid modes in 60 digits (w^2 <= 8e-63 of the top); vibss
    flagged nine. The tenth touches the mounts only through the Jacobi SVD's leakage
    (``||G phi|| = 9.9e-14`` rad/s beside ``omega_max = 4.1e7``), now under its backward-error floor
    ``n eps omega_max``; the eleventh (0.098 rad/s in 60 digits) stays elastic. The whole property
    (both directions of the rigid test, every elastic w^2 to 1e-8) against 60 digits (~5 s)."""
    model = fuzzing.build(_LEAKY_RIGID)
    rigid, _ = _split(mp_reference.omega2(model))
    assert rigid.tolist() == [True] * 10 + [False] * 26
    assert vibss.modes(model).rigid.tolist() == rigid.tolist()
    test_modes_match_60_digits.hypothesis.inner_test(_LEAKY_RIGID)   # type: ignore[attr-defined]


_LEAKY_RIGID = fuzzing.Spec(masses=(1052.3841987328603,
      1.0,
      0.0025825456638842166,
      1.0,
      10000.0,
      8.607543149099852),
     spreads=((0.0012566852412061625,
       0.10710676363028833,
       0.009999769744141627),
      (0.999997697417558, 0.1, 0.31622776601683794),
      (0.0026933133913627115, 0.136466006032681, 0.0019404816858245059),
      (0.11414950755026625, 0.03162277660168379, 0.7447145782842644),
      (0.009699398579104719, 0.999997697417558, 1.0),
      (0.0011404221202631411, 0.0019350488502505785, 0.0011207369369343875)),
     axes=((-1.7213462273695335, 2.698910393349415, -5.960464477539063e-08),
      (-1.1271622002034345, -1.9115648283953843, 1.332568730475625),
      (-5.815859415049078e-149, -2.7958732597555804, -2.00001),
      (1.8495005532014392, 1.6705640808809514, 0.0021084020653754365),
      (3.0231541631102193e-259, 2.3960818440767824, -0.99999),
      (-2.198944866028942, -1.426727235182307, -2.872686395495781)),
     cogs=((0.99125865965599, -0.7046494126455252, -0.6477800135718694),
      (2.5e-09, -0.30917962965246903, 1.1754943508222875e-38),
      (5.8639411406472266e-74, -0.3006316890374253, -0.15022801521332263),
      (-0.99999, 0.04167007060402228, 4.803643756496837e-265),
      (0.024631229221059092, 1.0, -3.6225531982739525e-79),
      (0.8068334087224058, 3.3725169011788884e-135, -0.6496081542925642)),
     mounts=((0,
       -1,
       (float(0.99125865965599),
        float(-0.7908504299636848),
        float(-0.4110509180977898)),
       (-2.3736741972259203, 0.7877585532407787, -0.8751074113038184),
       (28068.65582379462, 137011.58865188077, 3930474.277104989),
       (183.88670581359068, 1.9199412877258405e-40, 389.6678135316769),
       0.05),
      (0,
       -1,
       (float(0.99125865965599),
        float(-1.0166051398407474),
        float(-0.14778001357186943)),
       (-0.9301072452586787, 3.7232142583389084e-73, 4.3677596820332945e-94),
       (1284167.396108047, 26440.25633204104, 8958.865662106276),
       (1.506973442932459e-290, 98.87238138651195, 15.293455328689586),
       0.0),
      (0,
       -1,
       (float(0.7641240673385066),
        float(-0.942135082079439),
        float(-0.4726003059364686)),
       (2.4207446240971233, 1.3375996640490886, 2.546804096917585),
       (313434.02658324095, 100.0, 407.5275299380837),
       (1346.0955564345143, 0.5703898665472885, 3.249106448502269),
       0.0),
      (0,
       -1,
       (float(0.99125865965599),
        float(-0.7046494126455252),
        float(-0.17342025750857748)),
       (-2.0, -1.638748137143467, -1.2079739404041153e-302),
       (507105.13315669075, 0.0, 5350.157654427723),
       (4789.388956081352, 0.0, 30.664461124787202),
       0.0),
      (1,
       -1,
       (float(0.34311423619997417),
        float(-0.5463374227444866),
        float(1.1754943508222875e-38)),
       (2.297437904112, 1.1095970674638815, 2.5959722069454525),
       (28068.65582379462, 993406.5616843296, 13590.090186223137),
       (1.3868e-319, 0.11842329050236752, 52.76143739455885),
       0.05),
      (1,
       -1,
       (float(0.07715508871669176),
        float(-0.03750363674144419),
        float(0.5)),
       (2.5e-09, 2.082052231972856, -2.2506758448651656),
       (2548473.361139328, 1023278.9928157487, 2420.65983624291),
       (5.67054145501025e-307, 9804.886304590183, 16.106148658145568),
       0.05),
      (1,
       -1,
       (float(0.5000000025),
        float(-0.30917962965246903),
        float(0.4464772568205615)),
       (-1.401298464324817e-45, -1e-06, -0.3902360363623769),
       (0.0, 100.0, 10.0 ** 2.00001),
       (0.0, 1.192092896e-05, 0.7696569222808258),
       0.0),
      (1,
       0,
       (float(-0.2931202849937084),
        float(-0.41900252446583175),
        float(1.1754943508222875e-38)),
       (1e-12, -1.8377511515170744, 2e-09),
       (35426684200872.39, 1518152791304978.8, 28439657122719.58),
       (0.0, 0.0, 0.0),
       0.0),
      (2,
       -1,
       (float(5.8639411406472266e-74),
        float(-0.15694052701221617),
        float(-0.15022801521332263)),
       (0.545179800497106, -2.8994049213889834, 1.0),
       (768.9582779248358, 3077614.1979879723, 1024.5488041237977),
       (1.9223956948120893e-06, 12372.162499877302, 5.064e-321),
       0.05),
      (2,
       0,
       (float(5.8639411406472266e-74),
        float(-0.3006316890374253),
        float(-0.15022801521332263)),
       (-0.17480562641481406, 0.4117660198344695, -0.19398713362886005),
       (755888.7316845161, 755888.7316845161, 755888.7316845161),
       (0.0, 0.0, 0.0),
       0.0),
      (3,
       0,
       (float(-0.99999),
        float(0.04167007060402228),
        float(4.803643756496837e-265)),
       (0.009117579544226387, 6.103515625e-05, -0.2867610923317469),
       (100.0, 0.552164209762593, 100.0),
       (0.0, 0.0, 0.0),
       0.0),
      (4,
       0,
       (float(0.024631229221059092),
        float(1.0),
        float(-3.6225531982739525e-79)),
       (2.0918851941080425, 0.001667101647519709, 1.6968993663939536e-104),
       (100.0, 100.0, 100.0),
       (0.0, 0.0, 0.0),
       0.0),
      (5,
       0,
       (float(0.8068334087224058),
        float(3.3725169011788884e-135),
        float(-0.6496081542925642)),
       (0.0728270961941451, 2.9999999999999996, 5e-324),
       (99.9650012683731, 100.0, 100.0),
       (0.0, 0.0, 0.0),
       0.0)))


def test_a_denormal_stiffness_is_a_free_motion_not_a_1e164_m_answer():
    """Found by the suite when another test ran first in the same worker: a body held by one mount
    with a zero axis and one point link has a rotation no mount resists; round-off left its stiffness
    at 1.5e-323 N m/rad, which the equilibration scaled by 1e161 (1e164 m, no free motion named).
    The 60-digit reference has a zero eigenvalue there; vibss now names the motion."""
    spec = fuzzing.Spec(masses=(0.013082104112138171, 79.9273194693494),
    spreads=((0.0015956277405827536,
    0.18452842258132177,
    0.026498811372458804),
    (0.12202792538706478, 0.043605599101467954, 0.31622776601683794)),
    axes=((1.8373286986349973, 2.6539978375030193, -0.5964772477377611),
    (-1.7078237972444716, 2.6264093426052666, 0.45359237)),
    cogs=((-9.724907648824234e-60,
    0.28440251515660475,
    -1.7653451402547723e-258),
    (-4.1697030611993627e-241, -6.178060771626514e-10, -0.5)),
    mounts=((0,
    -1,
    (float(0.34570996274777044),
    float(0.2741790219415826),
    float(0.11358448341425331)),
    (-2.729964339288314e-95, 1.8496257160338798, -7.496775674958775e-298),
    (1000.0, 2894.1002421939797, 10.0 ** 3.3),
    (5.012417046828009, 0.2733428835605011, 14.438982924813477),
    0.0),
    (0,
    -1,
    (float(-0.3077522561650618),
    float(0.015457077167767175),
    float(-0.4823177970571608)),
    (-0.27779367267608013, -0.5838398912982408, 1.6501808651827599),
    (469619.32726717286, 135038.4811443669, 4720706.231236422),
    (6.186900566558526e-15, 221.28247088160853, 0.47207062312364223),
    0.0),
    (0,
    -1,
    (float(0.1974868306497456),
    float(0.11981834278456188),
    float(-0.3770250744797723)),
    (-0.6348031862712125, 1.0864474951846503, 2.0627330334632976),
    (10.0 ** 2.00001, 487377.77439214237, 124609.73397527936),
    (0.2946442070058633, 569.0313387502273, 1127.4805948518522),
    0.05),
    (1,
    -1,
    (float(-3.436157503996374e-231),
    float(0.05864440560149726),
    float(-0.5)),
    (-1.9046248214320782, -2.6563476552343066, 2.5e-09),
    (352.9380861863868, 113613.36939930294, 0.0),
    (7.85313309244804e-309, 161.86823448287083, 0.0),
    0.0),
    (1,
    0,
    (float(-7.449685503596712e-163),
    float(-6.178060771626514e-10),
    float(-0.5)),
    (-2.4112665387007075, -2.5987820154454027, -0.22097228517654255),
    (406.7709118656453, 0.40677091186564573, 5.037090294428186),
    (0.0, 0.0, 0.0),
    0.0)))
    model = fuzzing.build(spec)
    rigid, _ = _split(mp_reference.omega2(model))
    assert rigid.sum() == 1
    r = vibss.static(model)
    assert r.free_motions == ("body 'b1' is free to rotate about y",)
    assert np.abs(r.q).max() < 1e5                 # the restrained part: soft, but not 1e164 m


def test_time_methods_agree_on_a_four_body_model_whose_poles_are_all_accurate() -> None:
    """Found by the sixth long run (the 38th model of "time methods agree"): no pole at risk (the
    largest eps max|lam| / decay is 7e-12), yet ``modal`` was 1.13e-8 of the largest output (b0.rz)
    off a 40-digit ``expm`` of the first-order system, ``forced_response`` 1.3e-12: ``eig``'s
    vectors, unrefined, carried an inconsistency between their halves that the structured left
    vectors magnify by ``omega / |lam|`` (6.1e5 / 0.14). Every vector refined: 2.7e-14. The model as
    hypothesis drew it."""
    test_time_methods_agree.hypothesis.inner_test(_FOUR_BODY_TIME)     # type: ignore[attr-defined]


_FOUR_BODY_TIME = fuzzing.Spec(masses=(561.0563778826496,
0.2621568819272609,
0.9766490650261562,
0.28430112108826805),
spreads=((0.0015468237961136996, 0.001000000000000001, 0.1),
(0.28245252913284047, 0.1, 0.001000000000000001),
(0.016559184332004262, 0.9999997255105045, 0.13057526088914703),
(0.7586476866992615, 0.0226975581039136, 0.01)),
axes=((-1.360459249932398, -0.12305388746119927, -1.9561975576991e-171),
(-2.695489848969719, -1.0060327978491426, -0.23373732702190075),
(-0.3163300243846061, -1.105727762240682, 2.448830105911728e-308),
(0.6132702924092186, 5.230024774530638e-285, -0.17732389855460884)),
cogs=((-0.9943932471492625, 5.325102258991674e-197, -0.17364056627936342),
(-0.7158280748165704, 0.9, -0.8372525311333501),
(-0.979089255964098, -0.11332627786413219, 0.6447044891464331),
(-2.0950672443880146e-191, -0.13518794736333484, 0.8759676720309368)),
mounts=((0,
-1,
(np.float64(-0.9943932471482625),
np.float64(0.42642319046478927),
np.float64(0.07635943372063658)),
(2.2283582161363515, 0.7844257948853208, 2.6225516641886166),
(1000.0, 974597.3571654843, 1140.035529616631),
(2.291310591461531, 9251.789844982495, 10.799282005743603),
0.0),
(1,
-1,
(np.float64(-0.7801640175519674),
np.float64(0.9),
np.float64(-0.8372525311333501)),
(2.1287848206906794, 2.9999999999999996, 1.0518229137933623),
(5725.827160454753, 32894.45346406375, 2676066.627578719),
(5.7258271604547524e-11, 194.2826548415022, 2585.857521480989),
0.05),
(1,
-1,
(np.float64(-1.0491614081499037),
np.float64(1.1031875981245696),
np.float64(-0.6913329825340998)),
(-1.7028549733185642e-60, 4.6e-10, -1.785216617499065),
(100.0, 6697020.544398821, 108015.59190224938),
(0.3162274651547315, 65911.65414711878, 7.09342376938579e-43),
0.0),
(1,
0,
(np.float64(-0.6904280748165704),
np.float64(1.016524084017136),
np.float64(-1.1177974199279357)),
(1.192092896e-07, -2.593030024294129, -2.225073858507e-311),
(74.6396677626746, 22.094468880029247, 1366.8541265579756),
(0.0, 0.0, 0.0),
0.0),
(2,
-1,
(np.float64(-0.9038241804906039),
np.float64(-0.10741710587186526),
np.float64(1.116154769146907)),
(-0.2505947610259929, 0.5323439394860578, -1.7053005941370625),
(2478628.275474674, 2478628.275474674, 63149.21507158579),
(18822.97618749794, 13909.694496245034, 42.271672890492056),
0.0),
(2,
1,
(np.float64(-1.479089255964098),
np.float64(-0.4213654710938252),
np.float64(0.959881153935745)),
(-1.1, 3.0, -2.047605145233187),
(7194747.628053922, 9808347.949536966, 3417083623.0878577),
(0.0, 0.0, 0.0),
0.0),
(3,
-1,
(np.float64(-0.3280632114779176),
np.float64(-0.4375209084227602),
np.float64(1.0028559143258384)),
(1.6543032512914498e-171, 1.2850058454149833, -2.4920660455671433),
(625.9263311205219, 4062432.4467764627, 10.0 ** 2.00001),
(2.0120195267673464e-282, 36815.93338329568, 0.5760337525953582),
0.0),
(3,
-1,
(np.float64(0.48429213344017397),
np.float64(0.36481205263666516),
np.float64(1.1729345936634512)),
(1.8506561466308735, 4.0402590069598835e-185, 2.680893251328386e-260),
(974597.3571654843, 23517.782098441694, 1255.3100754147245),
(4971.339048318514, 8.003336629517842e-118, 9.19457122944542),
0.0),
(3,
-1,
(np.float64(0.34881509831946267),
np.float64(-0.13518794736333484),
np.float64(1.2648320062343485)),
(1.566142745239402, -7.902567024207943e-167, 4.476097732049895e-35),
(735.7697233876663, 368184.71706691716, 705.7952036442576),
(1.2581066672790884, 3419.3200099045284, 1.541333031738558),
0.0),
(3,
0,
(np.float64(0.18639824220679746),
np.float64(-0.4603640673497935),
np.float64(0.8759676720309368)),
(-2.003385832766498, 2.3120060373180413, 2.3709017909009233),
(1.5245036041880768, 0.11358395974925135, 100.00228888681097),
(0.0, 0.0, 0.0),
0.0)))


def test_a_rigid_mode_the_damping_couples_is_refused_by_modal_and_auto_takes_forced_response() -> None:
    """Found by the time property after the sixth long run: four rigid modes, the fourth coupled
    to the elastic modes by 5e-8 1/s through ``Phi^T C Phi`` (its own damping -2.7e-15: zero within
    its shape's error) sits among the complex modes with an exact zero eigenvalue beside a nearly
    zero one, cond(V) 1.6e15. ``modal`` refuses in one line (as at f80277b); ``auto`` names the
    refusal and takes ``forced_response``. Not solved: a modal form for a rigid mode coupled only
    by damping (its displacement the integral of a coupled velocity). The model as hypothesis drew it."""
    test_time_methods_agree.hypothesis.inner_test(_RIGID_COUPLED_TIME)     # type: ignore[attr-defined]
    model = fuzzing.build(_RIGID_COUPLED_TIME)
    kick = [vibss.Excitation("kick", "force", "b0", vibss.Step(1.0), dof="z")]
    with pytest.raises(DefectiveModesError, match="nearly dependent"):
        vibss.simulate(model, kick, method="modal", outputs=["b0.z"], t_end=0.05, dt=1e-3)


_RIGID_COUPLED_TIME = fuzzing.Spec(masses=(0.002895362892020492, 1000.0, 1.0, 2.0174370856119244),
spreads=((0.29407619363947096, 0.329397967514023, 0.0027455039120287614),
(0.001984594631103667, 0.844069299777635, 0.009177967288330266),
(0.001, 0.006665394417911391, 0.002288241280342034),
(0.46654464312841926, 0.0018755435611611238, 0.31622776601683794)),
axes=((-0.5626089083344104,
-0.017262334493424625,
-4.220820945525689e-202),
(1.9471049310285142, -1.5632690520538675, -2.3549498525765395),
(-1.7285594102627784e-276, -1.0075275804040311, 1.046910910464149),
(-1e-10, -1.5846516874708922, -0.3552317991586369)),
cogs=((0.45359237, -4.438894210827963e-107, 0.5522161742501632),
(-0.47386997097237404, -0.12685325020095184, -0.4581713315690762),
(1.0, 8.886523917225265e-52, 1.4243244279237272e-276),
(0.16867564248988676, -2.2546102284524386e-111, -0.99999)),
mounts=((0,
-1,
(np.float64(0.618189061000989),
np.float64(-0.14074157987357377),
np.float64(0.8585763991406299)),
(-2.633947601066263, 0.4624972768438802, 1.7468221377142115),
(3104.3237816106825, 2483.4654979196375, 10.0 ** 4.6),
(3.2729366270869e-77, 15.953391875277948, 388.158889992539),
0.0),
(1,
-1,
(np.float64(-0.07394012000741068),
np.float64(0.13615230513513654),
np.float64(-0.3832432520299991)),
(3.0, 1.5320981034657896e-154, 1.8723727543739717),
(0.0, 307754.9321627571, 589.1333953995552),
(0.0, 247.36667872739997, 0.017674001861986657),
0.05),
(1,
-1,
(np.float64(-0.43295814381312936),
np.float64(0.0073117107727452835),
np.float64(-0.6947770020409665)),
(2e-09, 1.2419735411948025, -2.105576558163656),
(210782.67835915432, 10.0 ** 2.00001, 1179.0250006367137),
(1552.897340450942, 2.000298669068881e-280, 6.576603891064497),
0.0),
(1,
0,
(np.float64(-0.5365164704282341),
np.float64(-0.12685325020095184),
np.float64(-0.595238105038949)),
(-0.8416127429330875, 0.5238970745891676, 2.4515276786111305e-287),
(1100292332791.5593, 1278043513841.8477, 146051096450.1101),
(0.0, 0.0, 0.0),
0.0),
(2,
-1,
(np.float64(1.0), np.float64(-0.5), np.float64(0.2722397538815988)),
(-2.6694018003551814, 3.298888388984491e-231, 5.960464477539063e-08),
(4009477.8468728936, 35646.93488886381, 372.2565678024539),
(244.71910686480064, 168.60902355715237, 1.3347245845056612e-229),
0.0),
(2,
-1,
(np.float64(0.5), np.float64(8.886523917225265e-52), np.float64(2e-09)),
(1.0986613324485743, -1.815256371827925, 2.194708558270925),
(327.35494893410754, 10.0 ** 2.00001, 37365.39513012179),
(2.907582910803177e-07, 0.1794544436745484, 93.65973108792252),
0.0),
(2,
0,
(np.float64(0.5),
np.float64(3.8346189084955976e-25),
np.float64(-7.1117166879310745e-102)),
(0.0, 0.0, 0.0),
(476.17758630008, 476.17758630008, 202.72770394221808),
(0.0, 0.0, 0.0),
0.0),
(3,
0,
(np.float64(0.1633444672786334),
np.float64(9.27683910134517e-27),
np.float64(-0.99999)),
(2.827396461468936, 0.0, 0.0),
(2026479.311847839, 2021497.9732862588, 864365.5083960749),
(0.0, 0.0, 0.0),
0.0)))


@pytest.mark.slow
def test_time_methods_agree_where_python_control_is_the_one_off() -> None:
    """Found after the sixth long run by the same property under another draw: a one-rigid-mode
    model (36 DOF, modes 1.7 rad/s up), ``modal`` and ``forced_response`` differ by 1.77e-8 of the
    largest output; against a 40-digit ``expm`` of the first-order system ``modal`` is 8.8e-13 off
    and ``forced_response`` (python-control's discretisation) 1.77e-8 (the reference is now the same
    ``expm`` in 800-bit ball arithmetic, radius 7e-68: 3 s where mpmath took 24 s). Where the two disagree the
    property now asks the 40-digit reference, and vibss's method must meet it. The model as
    hypothesis drew it."""
    test_time_methods_agree.hypothesis.inner_test(_PC_OFF_TIME)     # type: ignore[attr-defined]


_PC_OFF_TIME = fuzzing.Spec(masses=(0.001, 1.0, 12.190653122815988, 1.0, 1.0, 1.0),
spreads=((0.001590174824826058,
0.1718985138573278,
0.0010908994107691897),
(0.028321128253050713, 1.0, 0.10000230261160267),
(0.00649503575862369, 0.010256305613923477, 0.04512141631495995),
(0.0027892135700573854, 0.005343913873701842, 0.26064242958005446),
(0.8731600335248292, 0.42743283189421594, 1.0),
(0.006317806921893766, 0.6121961985937978, 0.03475889084919719)),
axes=((2.397590986059914, -9.00013548986534e-72, 2.373781840143627),
(0.2, 0.1378594868739107, 1.3958000082288802),
(1.2312488231409207, -1.2554417882253383e-26, 1.2764302039412296),
(0.9462966015387062, -2.8799238195192816, 0.5656567618159007),
(-1.804856153847823, -8.145315083648734e-09, 2.74383516505873),
(-2.920979861038501, -2.7817243889431857, -2.603023827472845)),
cogs=((-0.47635383693176425, -0.45318809818111905, 0.40774825554615934),
(8.185299951053801e-74, -0.6054316854783058, -0.6938524699278643),
(1e-05, 1.0, -0.8612814501797699),
(-0.4677529417577889, -0.15057880912462518, 1e-15),
(-0.5939666219061447, -0.35324852127228323, 0.6866080419607545),
(0.9357612620895868, -0.31220863407235233, -0.7391809190565257)),
mounts=((0,
-1,
(np.float64(-0.47635383692176425),
np.float64(-0.45318809818111905),
np.float64(0.8923256471907957)),
(-0.2187605026128674, 2.12689608204424, 0.11841876360425374),
(8966370.153669931, 818.8926338995853, 4591096.6271668635),
(38051.55827209295, 0.6730245983060628, 26651.377240026708),
0.05),
(0,
-1,
(np.float64(-0.4507063970878915),
np.float64(-0.31958194160948783),
np.float64(0.40768722038990934)),
(2.614275229751092, 2.9999999999999996, 2.7596486791703665),
(823229.9510046165, 6282.039873861494, 18524.174564674297),
(4639.637570314704, 59.932023381030525, 75.52518776824213),
0.05),
(1,
-1,
(np.float64(0.2439078598297454),
np.float64(-0.6054316854783058),
np.float64(-0.46378056134850587)),
(-2.962223817715267, -1.9, -0.7937313333526546),
(144847.4785252327, 2638489.0229603513, 10.0 ** 2.00001),
(1253.448119793582, 5.943184545080366e-76, 0.0030000690783480812),
0.0),
(1,
0,
(np.float64(0.04632989440027224),
np.float64(-0.6054316853070125),
np.float64(-1.1699597863456943)),
(1e-09, -1.228468120748229, -6.5696359330885086e-52),
(6186846902563495.0, 6186846902563495.0, 6186846902563495.0),
(0.0, 0.0, 0.0),
0.0),
(2,
-1,
(np.float64(-0.2766885700942052),
np.float64(1.0),
np.float64(-0.8612814501797699)),
(0.6964378845380388, -0.5, 2.3209369695943813),
(11768.700628180963, 34131.325573458744, 43461.258882367125),
(37.00322788200566, 247.29174941857363, 7.026330147677782e-27),
0.05),
(2,
1,
(np.float64(1e-05),
np.float64(1.00003),
np.float64(-0.5685397710326396)),
(2.631759091207905e-174, -3.556835111499887e-91, 2.0366501159452346),
(3658.052493654996, 389.8922193114611, 777.9666078144274),
(0.0, 0.0, 0.0),
0.0),
(3,
-1,
(np.float64(-0.023690179361924302),
np.float64(0.21334181782119765),
np.float64(-0.2226696737633223)),
(-2.9999999999999996, -2.8967172450241954, 1.1811784794827194),
(9999999.99999998, 98328.45391913666, 1754825.259998557),
(47089.82764116725, 942.1277206232763, 1.901523166305356e-256),
0.05),
(3,
-1,
(np.float64(-0.4677529417577889),
np.float64(0.142922420835905),
np.float64(6.1035156251e-05)),
(-1.116002039701908e-284, 2.773125751483672, -0.1552061752635039),
(342518.68124126235, 57878.16660854147, 248436.32646502115),
(322.5210679357827, 447.6025673437715, 0.0006210908161625529),
0.0),
(3,
-1,
(np.float64(-0.4151964744363419),
np.float64(-0.1504788091246252),
np.float64(1e-15)),
(-2.904132538911569e-69, 2.4325440651779602e-282, 2.838672926077315),
(1950729.663290844, 5364.050813399358, 10000000.0),
(14669.280602960325, 16.324657696649577, 1.674249039088896e-293),
0.0),
(3,
2,
(np.float64(-0.4676919066015389),
np.float64(-0.15057880912462518),
np.float64(-0.4698492639731807)),
(-4.968650451315058e-120, -2.037554567735694, -1.1931661780032347e-241),
(7931628250308.265, 6951040992901.61, 21136804678337.605),
(0.0, 0.0, 0.0),
0.0),
(4,
-1,
(np.float64(-0.5939666219061447),
np.float64(-0.5521120728292481),
np.float64(0.5027595557875055)),
(-0.4849958140980597, -6.643364832314915e-282, -1.2751767210694065),
(10.0 ** 2.00001, 10.0 ** 2.00001, 193605.09057335946),
(0.5672811294433937, 0.5788221047283814, 211.95491911121192),
0.0),
(4,
2,
(np.float64(-0.5939666219061447),
np.float64(-0.10324852127228323),
np.float64(0.6866080419607545)),
(1.0495273137860197, -1.3644434705722297, -2.1240567581459144),
(9999999999999960.0, 9999999999999960.0, 9999999999999960.0),
(0.0, 0.0, 0.0),
0.0),
(5,
-1,
(np.float64(1.026472742601467),
np.float64(-0.3122086340731867),
np.float64(-0.9501883233554034)),
(0.9771295530225652, -1.0004483084664064e-49, -1.5593591806311013),
(611.5859675372668, 100000.0, 17095.084993574033),
(5.267655472524625, 653.9067660676507, 63.810623289955025),
0.05),
(5,
-1,
(np.float64(0.9827740908897115),
np.float64(-0.6716737415814992),
np.float64(-0.7391809190565257)),
(-0.5, 2.063195239356636, 2.5973347438626444),
(100.0, 689851.0822368248, 27247.624086368727),
(9.999999999999999e-10, 4061.11847682818, 92.87771452586408),
0.05),
(5,
-1,
(np.float64(0.5919130510000512),
np.float64(-0.5608749092133167),
np.float64(-0.70773266866432)),
(2.762085656104512, -1.748145574231026, 1.9968223615987313),
(1211.9149596886316, 3594.3939738075287, 10.0 ** 2.00001),
(7.02554014327766, 5.278610450714754, 0.4278317899546351),
0.05),
(5,
-1,
(np.float64(0.9357612620895868),
np.float64(-0.34237844924577066),
np.float64(-0.43243715163971785)),
(-1.5892472000735967, -0.3172982053717375, -0.3947418006594958),
(10.0 ** 2.00001, 596283.1677747505, 343.6411428207505),
(0.44237126004601285, 3417.735206636971, 2.4776551720867395),
0.05),
(5,
3,
(np.float64(0.9357912620895867),
np.float64(-0.31220863407235233),
np.float64(-0.3516310173854873)),
(-1.0910053251047245, -2.192689862081914, 2.421153517557257),
(3255504123580.512, 3255504123580.512, 3255504123580.512),
(0.0, 0.0, 0.0),
0.0)))


def test_frf_of_a_two_gram_model_at_0_1_hz_matches_60_digits() -> None:
    """Found after the sixth long run by the same property under another draw: ``direct`` and
    ``sparse`` alike 1.49e-8 off 60 digits (tolerance 1e-8) at 0.1 Hz on a two-body model of 1.9 g
    and 9.2 g. Its ground mount has a zero principal stiffness beside a 6e5 N/m axis, so it was
    assembled with the rest, rounding the free axis at 6e5 N/m's level against an inertia of
    ~7e-4 N/m. Mounts with diagonal local matrices are now kept apart per stiff local axis: 4e-16.
    The model as hypothesis drew it."""
    test_frf_matches_60_digits_and_is_reciprocal.hypothesis.inner_test(_LIGHT_FRF, 0.1)     # type: ignore[attr-defined]


_LIGHT_FRF = fuzzing.Spec(masses=(0.001852307602602872, 0.009158964752016155),
spreads=((0.01677619168306678, 0.0725489837633772, 0.11277033703197269),
(0.10594157489008986, 0.003130122641676893, 1.0)),
axes=((0.7248417045333104, 0.9053488881803498, -1.1514589695271606),
(-6.389236201516376e-84, 1.1455345939103898, -3.949689047933959e-264)),
cogs=((-0.7355688704566035, 1.192092896e-07, -0.8217630625100698),
(-9.770312026686836e-228, 0.01, -2.9000511932652077e-244)),
mounts=((0,
-1,
(np.float64(-0.6850699184595722),
np.float64(0.01977633063920508),
np.float64(-0.9392908018865621)),
(-1.1432131038609739, -2.6432913807781797e-300, -2.00001),
(597396.317515135, 0.0, 877.2504106692594),
(1146.07610224352, 0.0, 1.8465871851594095e-50),
0.0),
(1,
0,
(np.float64(0.005032558803377806),
np.float64(0.013840757228614968),
np.float64(0.42489019843580755)),
(-8.274431526030995e-304, 1.0751093601546948e-135, 2.5025633813298676),
(1.0, 100.0023026116027, 100.0023026116027),
(0.0, 0.0, 0.0),
0.0)))


@pytest.mark.filterwarnings("error::RuntimeWarning")
def test_a_refined_complex_mode_that_degenerates_keeps_eigs_pair() -> None:
    """Found by the time property the same day, after every mode's vector was refined over a finite
    horizon: an inverse-iteration step on an all-but-exact pole gave a vector of ~1e308 whose norm
    overflowed (RuntimeWarning, NaN modes). The step is now scaled before it is normalised, and a
    mode whose refinement is not finite keeps ``eig``'s pair. The model as hypothesis drew it."""
    test_time_methods_agree.hypothesis.inner_test(_DEGENERATE_REFINE_TIME)     # type: ignore[attr-defined]


_DEGENERATE_REFINE_TIME = fuzzing.Spec(masses=(0.001000000000000001,
1.0,
3.1610898568990478,
0.022514596393344757,
312.01335482885054),
spreads=((0.04676897624481237, 0.8857255693572148, 0.002191063658588918),
(0.24056336369380812, 1.0, 0.0028636117011902546),
(0.46776899304680825, 0.002778551403182345, 0.01),
(0.038592333220347434, 0.0017565316101403692, 0.9724467924516041),
(0.023367627826476778, 0.056704361967797205, 0.1241054520099234)),
axes=((0.01, -1.3019257534310977, 6.103515625e-05),
(-1.7451487129102268, 2.220446049250313e-16, 5.2192105083258045e-71),
(2.694589738827773, -2.6039584213136144e-127, 0.9364300542565527),
(1.8633211965391716, 0.5240690963560919, -2.0),
(-0.4448125808309795, 0.9035896146571716, -2.575050950330391)),
cogs=((0.8910042347022737, 0.509745578124349, 0.7053095235083275),
(-0.7613175112088082, -1.2649110211797295e-78, 1.401298464324817e-45),
(0.0, 5e-324, 0.0001),
(-1.0, -5.90534610123904e-278, -0.6089211381541019),
(0.6230260896000606, 0.891040570112688, -0.9209863119903696)),
mounts=((0,
-1,
(np.float64(0.8968831997728246),
np.float64(0.509745578134349),
np.float64(0.5121150618719523)),
(0.19170351846696077, 2.220446049250313e-16, -2.9628773857856983),
(0.0, 0.0, 156.8572012314556),
(0.0, 0.0, 1.632367146188459e-148),
0.0),
(1,
0,
(np.float64(-0.7549175146166457),
np.float64(-1.2649110211797295e-78),
np.float64(0.006511256012496233)),
(0.327565687658927, 0.3357659077646531, 0.35749161076366875),
(1.0, 100.0, 100.0),
(0.0, 0.0, 0.0),
0.0),
(2,
0,
(np.float64(0.0), np.float64(5e-324), np.float64(0.003660634085116426)),
(1e-11, -0.2935333854534376, -0.20623816653431198),
(100.0, 100.0, 100.0),
(0.0, 0.0, 0.0),
0.0),
(3,
0,
(np.float64(-1.0),
np.float64(-5.90534610123904e-278),
np.float64(-0.6089211381541019)),
(6.955147017807571e-202, 0.0039515922108060335, 1.175494351e-38),
(1.0, 100.0, 0.9999769744141628),
(0.0, 0.0, 0.0),
0.0),
(4,
0,
(np.float64(0.6230260896000606),
np.float64(0.891040570112688),
np.float64(-0.9209863119903696)),
(0.0, 0.0, 2.00001),
(1.0, 100.0, 100.0),
(0.0, 0.0, 0.0),
0.0)))


def test_time_methods_agree_on_a_six_body_model_with_1e16_links() -> None:
    """Found by the fifth long run (the 152nd model of "time methods agree"): a step force on b0,
    the two exact-on-the-grid methods differed by 1.24e-13 rad in b0.rz (its largest 3.57e-6 rad),
    growing steadily over the 50 steps. Against the exact step response (``expm`` of the first-order
    matrix built from ``mp_reference``'s 60-digit M, K, C, in 50 digits; 70 s, so not run here)
    ``modal`` was 3.5e-8 off and ``forced_response`` 4.8e-10: the complex modes' slow vectors
    (0.09 to 1.9 rad/s, rigid-like over the 0.05 s) kept ``eig``'s mixing ``eps max|lam| / gap``
    (``max|lam|`` 3.2e9 rad/s) where only their poles were refined. The model as hypothesis drew it."""
    test_time_methods_agree.hypothesis.inner_test(_STIFF_SIX_BODY_TIME)     # type: ignore[attr-defined]


def test_time_methods_agree_there_with_only_the_slow_vectors_refined(monkeypatch: pytest.MonkeyPatch) -> None:
    """The large-model branch of the refinement (inverse iteration only for the modes slower than
    the horizon, the pole alone for the others) on the same model: still within the tolerance."""
    monkeypatch.setattr(complex_modes, "REFINE_FLOPS", 0.0)
    test_time_methods_agree.hypothesis.inner_test(_STIFF_SIX_BODY_TIME)     # type: ignore[attr-defined]


_STIFF_SIX_BODY_TIME = fuzzing.Spec(masses=(1.0000002744895709,
9424.194824127839,
1.0,
1.000000002302585,
0.079557054209273,
0.001000000000000001),
spreads=((0.629007205774805, 0.021829847740125106, 0.016119229117121707),
(0.9999999997697415, 0.003726455040023109, 1.0),
(0.009597049028175384, 0.9824229587771371, 1.0),
(0.21309123280564982, 0.005584661271465268, 1.0),
(0.7941787506530135, 0.6337337462177053, 1.0),
(0.002538341129193361, 0.3299404151713259, 1.0)),
axes=((-1.9, 1.592541942840434, 1e-07),
(-6.820363986790245e-38, 1e-10, 0.4625295012489996),
(0.7930524048844241, 3.2102627595794945e-08, -1.2791184534598234),
(-1.7770442831778843, 2.5e-09, -2.225073858507203e-309),
(-2.8601937448249916e-07, 1.8309382620309087, -1.7842713004689599),
(-2.0786022163468285, -7.668448416834048e-46, -0.414783635565505)),
cogs=((1.1595402456805221e-71, -0.7531819138651255, 0.7705812601594411),
(5e-324, -0.5378515192291479, -0.5157235881036563),
(-0.3333333333333333, 0.2850130141801748, -0.5),
(-0.8878502772257684, -0.07545813491951914, -0.22216344897181917),
(-0.3975433787075392, -0.8090384803691739, 0.3555388975357887),
(-0.0, 0.5061321649133212, 0.16187539704804643)),
mounts=((0,
-1,
(np.float64(0.16602861773935917),
np.float64(-0.7018513020497771),
np.float64(0.7805812601594411)),
(-2.1012329590620453, -1e-05, 2.9646687235444364),
(0.0, 6245305.727765969, 126332.35330705882),
(0.0, 36684.86011798587, 961.6243767826894),
0.0),
(0,
-1,
(np.float64(-0.4273574505143789),
np.float64(-0.8221501332331943),
np.float64(1.0176428528834305)),
(1e-07, 4.392453943698112e-76, -0.28784563206278513),
(629415.5872609816, 10.0 ** 2.00001, 28068.65582379462),
(5015.688490368408, 0.01731525674010564, 2.9221865497382553),
0.05),
(1,
0,
(np.float64(-0.22165549815599855),
np.float64(-0.7904997374677496),
np.float64(-0.9742958501729052)),
(1.3700094776739314e-275, 2.052233185544477, -1.0),
(15505627002616.041, 294790226611726.44, 287672040187602.7),
(0.0, 0.0, 0.0),
0.0),
(2,
0,
(np.float64(-0.5700211561509165),
np.float64(0.332769274906913),
np.float64(-0.5)),
(0.49931932496393294, 0.08058816780472, 2.3453567755461586),
(13601191303138.32, 13601191303138.32, 13601191303138.32),
(0.0, 0.0, 0.0),
0.0),
(3,
-1,
(np.float64(-1.202345328690619),
np.float64(0.42454186508048086),
np.float64(0.21750601141993875)),
(-4.5098367367594857e-250,
-7.2393077871809125e-112,
2.1921896193116304),
(0.0, 5530763.88888288, 100.0000000000001),
(0.0, 8542.78642011378, 0.9446163576982279),
0.0),
(3,
-1,
(np.float64(-0.6246323958396356),
np.float64(-0.3457897261022426),
np.float64(-0.1502449824139328)),
(-1.3409120119011089, 0.5, -2.037627021754081e-95),
(100000.0, 391270.75942950527, 1274.9621701419694),
(324.4608283262139, 3801.188428059828, 11.109983221396247),
0.05),
(3,
-1,
(np.float64(-0.8878502772257684),
np.float64(0.27501148651093277),
np.float64(0.15514567764723353)),
(-8.259100022544123e-200, 1.6774576227439905e-95, 5e-324),
(468.20203985248673, 10.0 ** 2.00001, 428198.7789099174),
(1.2972297265718138, 3.140037711403329e-07, 4.950555278466053e-39),
0.0),
(3,
-1,
(np.float64(-0.9218852771692062),
np.float64(-0.07545813491951914),
np.float64(0.2778365510281808)),
(-1.6443689813711062e-137, -1.3470726770641699, -2.220446049250313e-16),
(0.0, 8397.578350869922, 860614.367497624),
(0.0, 9.325371070821151e-231, 6971.310254808544),
0.0),
(3,
0,
(np.float64(-0.8878502773257684),
np.float64(0.3375164704800413),
np.float64(-0.6391971744785347)),
(1.6008715224309817, -1.4327792338273495, 1.0826601876540476),
(440.25779469182913, 189.9291881304199, 440.25779469182913),
(0.0, 0.0, 0.0),
0.0),
(4,
-1,
(np.float64(0.05660868379609296),
np.float64(-0.8090384803691739),
np.float64(0.31986117168827366)),
(1.7764456770430295, 1.1, -5.351888876447203e-106),
(100.0, 10.0 ** 2.00001, 425.94958511898636),
(2.2733247049666827e-48, 0.5848499119220603, 0.35312358118431963),
0.0),
(4,
3,
(np.float64(-0.7878642713885405),
np.float64(-0.8090384803691739),
np.float64(0.8555388975357887)),
(1.1754943508222875e-38, -2.708503370595545, -0.5592883360897218),
(8370459472.374692, 1846636933.7058682, 256520536097.95578),
(0.0, 0.0, 0.0),
0.0),
(5,
-1,
(np.float64(4.5449294292859936e-178),
np.float64(0.03894110843465581),
np.float64(0.6534522048880678)),
(-0.8475107410505505, -2.671325841180739, -0.0),
(969.7869472922276, 26059.461559103005, 1998453.5025251482),
(0.08544832429247734, 118.34539049808669, 3.871164370335387e-07),
0.05),
(5,
-1,
(np.float64(-0.36598527023681493),
np.float64(0.6497685247317201),
np.float64(-0.12586372220564995)),
(-2.0459206800709024, 3.9899566055680683e-87, 2.2362846309588527),
(8720784.515888887, 28479.562914642007, 12695.617781834439),
(56071.580927717776, 251.35834001268037, 33.533648826766026),
0.0),
(5,
4,
(np.float64(0.0796048305129392),
np.float64(0.7734687054024851),
np.float64(0.16187533744340166)),
(-2.3469177999192885, -0.04253491169718426, 4.730974495228369e-25),
(5989970313626673.0, 16463179294887.225, 9854435193235402.0),
(0.0, 0.0, 0.0),
0.0)))
