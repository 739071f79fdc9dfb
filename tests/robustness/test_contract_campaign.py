"""The contract campaign (issue 29 item 6): every method of every analysis on the campaign's random
models, against a 60-digit reference, and no silent miss.

A method's answer is judged against its registry entry's stated :class:`vibss.methods.Claim`:

- *within claim*: the measured error (against :mod:`cases.mp_reference`, 60 digits) is within
  ``claim.tolerance``;
- *warned*: outside it, but a :class:`~vibss.errors.VibssWarning` of that call states an error
  bound (``"error 3.1e-04"``) that covers the measured error;
- *refused*: the call raised a :class:`~vibss.errors.VibssError` (a refusal, not a crash);
- *crashed*: it raised anything else (counted among the silent misses);
- *over time*: stopped after :data:`CALL_SECONDS` (counted, not failed: no method states a time
  estimate yet);
- *no claim*: the method states no claim yet (``claim is None``): counted, never failed;
- *silent miss*: none of the above. The test of each method asserts there are none.

The error measured, per analysis (the same measure the claims are stated in):

- ``modes``: the largest relative error of an elastic natural frequency ``|w - w_ref| / w_ref``; a
  mode flagged rigid whose reference is elastic (or the reverse) is an error of 1. The modes'
  own a-posteriori bound (:attr:`vibss.Modes.error_estimate`, Kato-Temple) must also cover each
  mode's error: a bound that does not is a silent miss too;
- ``frequency_response``: per frequency, the largest entry error over the largest reference entry
  (receptance of every DOF to a force and a moment), the largest over the frequencies (the first
  two natural frequencies, a third below the first, one between the first and the top);
- ``simulate``: the largest error of the first body's six DOFs over the largest reference value,
  a step force from rest (the reference advances the exact state transition in 40 digits);
- ``reduce``: the scope's measure (:func:`vibss.reduction.result.relative_error`) at frequencies
  over the band and beside its resonances; a non-exact method's claim is the scope's tolerance;
- ``static``: the largest deflection error over the largest reference deflection (self-weight);
  a model with free motions has no reference (its refusal is counted).

Size: a few seconds in ``make test`` (one model per family, up to 3 bodies); ``make fuzz``
(``VIBSS_FUZZ=1``) runs :data:`PER_FAMILY` models per family up to 4 bodies
(``VIBSS_CAMPAIGN_MODELS`` overrides). Each method's figures are printed (``-s``) and, with
``VIBSS_CAMPAIGN_OUT=<file>``, appended to that file as JSON lines (docs/robustness.md).
"""

from __future__ import annotations

import json
import math
import os
import re
import signal
import threading
import warnings
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from typing import Any

import mpmath as mp
import numpy as np
import pytest

from cases import contract_models, fuzzing, mp_reference
import vibss
from vibss.errors import VibssError, VibssWarning
from vibss.frequency.methods import METHODS as FREQUENCY
from vibss.methods import Claim
from vibss.modal.methods import METHODS as EIGEN
from vibss.reduction.methods import METHODS as REDUCTION
from vibss.reduction.result import relative_error
from vibss.reduction.scope import Scope
from vibss.time.methods import METHODS as TIME

PER_FAMILY = int(os.environ.get("VIBSS_CAMPAIGN_MODELS", 40 if fuzzing.LONG else 1))
"""Models per family (``make fuzz``: 40, i.e. 200 models; ``make test``: 1)."""

MAX_BODIES = 4 if fuzzing.LONG else 3
"""Largest model [bodies]."""

TIME_BODIES = 3 if fuzzing.LONG else 2
"""Largest model simulated [bodies]: the reference's 40-digit ``expm`` of the (12 b + 1)-square
state matrix grows as b^3 (0.4 s at 2 bodies, 3 s at 4)."""

CASES = contract_models.cases(PER_FAMILY, MAX_BODIES)

RIGID = 1e-30
"""A reference eigenvalue below this fraction of the largest is a rigid-body mode."""

RIGID_EITHER = 1e-24
"""Between :data:`RIGID` and this fraction either answer is right (the round-off of lever arms,
``vibss.linear.eigen.checks.ROUNDOFF_LEVERS``; as in test_random_models.py)."""

PRINTED = 1.05
"""A stated bound printed to two digits covers an error up to this factor above it."""

CALL_SECONDS = 5.0
"""A call still running after this is stopped and counted as *over time* [s] (the methods state no
time estimate yet; ``simulate(method="ivp")`` took 12-54 s through 1e13 N/m links, 0.05 s elsewhere)."""

DT, STEPS = 1e-3, 50
"""The time step [s] and number of steps of the step responses (as test_random_models.py)."""


# -- the outcome of one call ---------------------------------------------------------------------
@dataclass
class Tally:
    """One method's figures over the campaign."""

    analysis: str
    method: str
    answers: int = 0
    within: int = 0
    warned: int = 0            # answers that came with a VibssWarning (any)
    covered: int = 0           # answers outside the claim whose warning's bound covers the error
    refused: int = 0
    crashed: int = 0           # raised something other than a VibssError (also a silent miss)
    over_time: int = 0         # stopped after CALL_SECONDS (a hang: counted, not failed; no time claim yet)
    slow: list[str] = field(default_factory=list)
    no_claim: int = 0
    unchecked: int = 0         # answers without a reference (free motions of a static solve)
    silent: list[str] = field(default_factory=list)
    largest: float = 0.0       # the largest error measured [-]
    by_family: dict[str, float] = field(default_factory=dict)    # the largest per family [-]

    def row(self) -> dict[str, Any]:
        out = asdict(self)
        out["silent"] = len(self.silent)
        out["examples"] = self.silent[:3]
        out["slow"] = self.slow[:5]
        return out


@dataclass(frozen=True)
class Outcome:
    """What a call gave: its answer (None: refused), its refusal, and the bounds its warnings stated."""

    answer: Any
    refusal: str
    warned: bool
    bounds: tuple[float, ...]
    crash: str = ""


_BOUND = re.compile(r"error(?: bound| estimate)?(?: of| about| ~|:)*\s*~?([0-9.]+(?:e[-+]?\d+)?)", re.I)


def stated_bounds(text: str) -> tuple[float, ...]:
    """The error bounds a warning or note states (``"error 3.1e-04"``, ``"error bound 2e-3"``)."""
    out = []
    for m in _BOUND.finditer(text):
        try:
            out.append(float(m.group(1)))
        except ValueError:
            pass
    return tuple(out)


class OverTime(Exception):
    """A call ran past :data:`CALL_SECONDS`."""


def _alarm(signum: int, frame: Any) -> None:
    raise OverTime


def attempt(call: Callable[[], Any]) -> Outcome:
    """Run ``call``: its answer and the bounds of its VibssWarnings, or its refusal (a VibssError),
    or its crash (anything else: ``crash`` set, counted as a silent miss), or ``"over time"``
    (stopped after :data:`CALL_SECONDS`: counted apart, see :class:`Tally`)."""
    timed = hasattr(signal, "SIGALRM") and threading.current_thread() is threading.main_thread()
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always", VibssWarning)
        before = signal.signal(signal.SIGALRM, _alarm) if timed else None
        if timed:
            signal.setitimer(signal.ITIMER_REAL, CALL_SECONDS)
        try:
            answer = call()
        except OverTime:
            return Outcome(None, "", False, (), crash="over time")
        except VibssError as exc:
            return Outcome(None, f"{type(exc).__name__}: {exc}", False, ())
        except Exception as exc:           # noqa: BLE001  (a crash: counted, the campaign goes on)
            return Outcome(None, "", False, (), crash=f"{type(exc).__name__}: {exc}"[:300])
        finally:
            if timed:
                signal.setitimer(signal.ITIMER_REAL, 0)
                signal.signal(signal.SIGALRM, before)
    ours = [str(w.message) for w in seen if issubclass(w.category, VibssWarning)]
    note = str(getattr(answer, "note", "") or "")
    bounds = tuple(b for text in ours for b in stated_bounds(text))
    if ours:                          # the note may carry the measured bound the warning announces
        bounds += stated_bounds(note)
    return Outcome(answer, "", bool(ours), bounds)


def judge(tally: Tally, case: str, out: Outcome, error: float | None, claim: Claim | None,
          limit: float | None = None) -> None:
    """Count one outcome; ``error`` None: no reference; ``limit``: the claim's tolerance if not its own."""
    if out.crash == "over time":
        tally.over_time += 1
        tally.slow.append(case)
        return
    if out.crash:
        tally.crashed += 1
        tally.silent.append(f"{case}: crashed: {out.crash}")
        return
    if out.answer is None:
        tally.refused += 1
        return
    tally.answers += 1
    tally.warned += out.warned
    if error is None:
        tally.unchecked += 1
        return
    tally.largest = max(tally.largest, error) if not math.isnan(error) else math.inf
    fam = case.rsplit("-", 1)[0]
    tally.by_family[fam] = max(tally.by_family.get(fam, 0.0), error) if not math.isnan(error) else math.inf
    if claim is None:
        tally.no_claim += 1
        return
    tol = claim.tolerance if limit is None else limit
    if error <= tol:
        tally.within += 1
    elif any(error <= PRINTED * b for b in out.bounds):
        tally.covered += 1
    else:
        tally.silent.append(f"{case}: error {error:.1e} > {tol:.0e}, "
                            f"{'warned ' + str(out.bounds) if out.warned else 'no warning'}")


def claim_of(registry: dict[str, Any], name: str, answered: str) -> Claim | None:
    """The claim of method ``name`` (for ``"auto"``: of the method that answered, if it says which)."""
    if name != "auto":
        return registry[name].claim
    for key, m in registry.items():
        if answered == key or answered.startswith(key + "+") or answered.startswith(key + " "):
            return m.claim
    return None


# -- references (60 digits), computed once per model ---------------------------------------------
_cache: dict[tuple[str, str], Any] = {}


def cached(case: contract_models.Case, what: str, make: Callable[[], Any]) -> Any:
    key = (case.name, what)
    if key not in _cache:
        _cache[key] = make()
    return _cache[key]


def spectrum(case: contract_models.Case) -> tuple[np.ndarray, np.ndarray]:
    """Reference ``w2`` and its rigid mask."""
    def make() -> tuple[np.ndarray, np.ndarray]:
        w2 = mp_reference.omega2(case.model)
        top = max(float(np.abs(w2).max()), 1e-300)
        return w2, np.abs(w2) <= RIGID * top
    return cached(case, "w2", make)


def elastic_hz(case: contract_models.Case) -> np.ndarray:
    w2, rigid = spectrum(case)
    return np.sqrt(w2[~rigid]) / (2 * np.pi)


def signals(case: contract_models.Case) -> tuple[list[str], list[int], list[str]]:
    """A force on the first body and a moment on the last: names, DOF columns; every DOF as outputs."""
    last = case.model.bodies[-1].name
    first = case.model.bodies[0].name
    outputs = [f"{b.name}.{d}" for b in case.model.bodies for d in vibss.DOF_NAMES]
    return [f"{first}.fz", f"{last}.mx"], [2, 6 * (len(case.model.bodies) - 1) + 3], outputs


def frf_frequencies(case: contract_models.Case) -> np.ndarray:
    f = elastic_hz(case)
    if f.size == 0:
        return np.array([1.0, 10.0])
    picks = [0.3 * f[0], f[0], np.sqrt(f[0] * f[-1])] + ([f[1]] if f.size > 1 else [])
    return np.unique(np.array(picks))


def mp_matrices(case: contract_models.Case) -> tuple[Any, Any, Any]:
    """K, C and M of the model in 60-digit arithmetic (assembled once; the models have no loss factor)."""
    assert not any(np.any(m.type.loss_factor) for m in case.model.mounts)
    with mp.workdps(mp_reference.DPS):
        return cached(case, "KCM", lambda: (mp_reference.matrices(case.model),
                                            mp_reference.matrices(case.model, "damping"),
                                            mp_reference.mass(case.model)))


def reference_frf(case: contract_models.Case, freqs: np.ndarray, columns: list[int]) -> np.ndarray:
    """(n, m, nf) receptance ``(K + sC + s^2 M)^-1`` columns in 60 digits (one LU per frequency)."""
    def make() -> np.ndarray:
        K, C, M = mp_matrices(case)
        out = []
        with mp.workdps(mp_reference.DPS):
            for f in freqs:
                s = mp.mpc(0, 2 * mp.pi * mp.mpf(float(f)))
                a = K + s * C + s * s * M           # one object: mpmath keeps its LU for the next column
                cols = []
                for j in columns:
                    e = mp.zeros(K.rows, 1)
                    e[j] = 1
                    y = mp.lu_solve(a, e)
                    cols.append([complex(y[i]) for i in range(K.rows)])
                out.append(np.array(cols).T)
        return np.stack(out, axis=-1)
    return cached(case, "frf" + ",".join(f"{x:.17g}" for x in freqs) + str(columns), make)


def error_frf(h: np.ndarray, ref: np.ndarray) -> float:
    """Largest over frequencies of (largest entry error) / (largest reference entry)."""
    err = np.abs(h - ref).reshape(-1, ref.shape[-1]).max(axis=0)
    scale = np.abs(ref).reshape(-1, ref.shape[-1]).max(axis=0)
    return float(np.max(err / np.maximum(scale, 1e-300)))


# -- the analyses -----------------------------------------------------------------------------------
def run_modes(name: str, tally: Tally, case: contract_models.Case) -> None:
    w2, rigid = spectrum(case)
    n = w2.size
    n_modes = None if name != "shift-invert" else max(1, min(n - 2, 8))
    out = attempt(lambda: vibss.modes(case.model, n_modes=n_modes, method=name))
    error = None
    if out.answer is not None:
        md = out.answer
        k = len(md)
        ref, ref_rigid = w2[:k], rigid[:k]
        top = max(float(np.abs(w2).max()), 1e-300)
        either = np.abs(ref) <= RIGID_EITHER * top
        mismatch = (md.rigid != ref_rigid) & ~either
        el = ~md.rigid & ~ref_rigid
        wref = np.sqrt(ref[el])
        per = np.abs(md.omega[el] - wref) / wref
        error = 1.0 if np.any(mismatch) else float(per.max(initial=0.0))
        est = np.asarray(md.error_estimate)[el]
        if np.any(~(per <= PRINTED * est)):          # the modes' own bound must cover each mode
            worst = int(np.argmax(per / np.where(est > 0, est, 1e-300)))
            tally.silent.append(f"{case.name}: a frequency error {per[worst]:.1e} above its Kato-Temple "
                                f"bound {est[worst]:.1e}")
    judge(tally, case.name, out, error, claim_of(EIGEN, name, out.answer.method if out.answer else ""))


def run_frf(name: str, tally: Tally, case: contract_models.Case) -> None:
    inputs, cols, outputs = signals(case)
    f = frf_frequencies(case)
    out = attempt(lambda: vibss.frequency_response(case.model, inputs, outputs, frequencies=f, method=name))
    error = None if out.answer is None else error_frf(out.answer.response, reference_frf(case, f, cols))
    judge(tally, case.name, out, error, claim_of(FREQUENCY, name, str(getattr(out.answer, "method", ""))))


def reference_step(case: contract_models.Case) -> np.ndarray:
    load = np.zeros(6 * case.bodies)
    load[2] = 1.0
    return cached(case, "step", lambda: mp_reference.step_response(case.model, load, DT, STEPS, rows=6))


def run_time(name: str, tally: Tally, case: contract_models.Case) -> None:
    first = case.model.bodies[0].name
    kick = [vibss.Excitation("kick", "force", first, vibss.Step(1.0), dof="z")]
    outputs = [f"{first}.{d}" for d in vibss.DOF_NAMES]
    out = attempt(lambda: vibss.simulate(case.model, kick, outputs=outputs, t_end=DT * STEPS, dt=DT,
                                         method=name))
    error = None
    if out.answer is not None:
        ref = reference_step(case)
        y = np.asarray(out.answer.outputs).reshape(len(outputs), -1)
        error = float(np.abs(y - ref).max() / max(float(np.abs(ref).max()), 1e-300))
    judge(tally, case.name, out, error, claim_of(TIME, name, str(getattr(out.answer, "method", ""))))


def scope_of(case: contract_models.Case) -> tuple[Scope, np.ndarray]:
    """A force on the first body to its z and the last body's z (one body: its z and rx), over a
    band holding the first three elastic modes (1.5 times the third); and the check frequencies [Hz]:
    over the band, at its measure's start (:meth:`Scope.low_end`), on each resonance (the peak a
    relative error is measured against: a mode of damping ratio 1e-5 is far narrower than any fixed
    offset) and beside it."""
    f = elastic_hz(case)
    top = 1.5 * float(f[min(2, f.size - 1)]) if f.size else 10.0
    first, last = case.model.bodies[0].name, case.model.bodies[-1].name
    outputs = [f"{first}.z", f"{last}.z"] if last != first else [f"{first}.z", f"{first}.rx"]
    scope = Scope([f"{first}.fz"], outputs, 0.0, top, 1e-3)
    inside = f[f < top]
    _, rigid = spectrum(case)
    start = scope.low_end(np.r_[np.zeros(int(rigid.sum())), 2 * np.pi * f]) / (2 * np.pi)
    check = np.unique(np.concatenate([np.linspace(top / 20, top, 4), [start], inside, inside * (1 + 1e-3)]))
    return scope, check


def run_reduce(name: str, tally: Tally, case: contract_models.Case) -> None:
    scope, check = scope_of(case)
    out = attempt(lambda: vibss.reduce(case.model, scope, method=name))
    error = None
    if out.answer is not None:
        dofs = [2, 6 * (case.bodies - 1) + 2] if case.bodies > 1 else [2, 3]
        full = reference_frf(case, check, [2])[dofs]                    # (2, 1, nf)
        error = relative_error(full, out.answer.response(2j * np.pi * check))
    claim = claim_of(REDUCTION, name, str(getattr(out.answer, "method", "")))
    limit = None if claim is None or claim.exact else scope.tolerance
    judge(tally, case.name, out, error, claim, limit)


def run_static(name: str, tally: Tally, case: contract_models.Case) -> None:
    out = attempt(lambda: vibss.static(case.model))
    error = None
    _, rigid = spectrum(case)
    if out.answer is not None and not rigid.any():
        load = vibss.assemble(case.model).load_vector(include_gravity=True)
        ref = cached(case, "static", lambda: fuzzing.mp_static(case.model, load))
        error = float(np.abs(out.answer.q - ref).max() / max(float(np.abs(ref).max()), 1e-300))
    judge(tally, case.name, out, error, STATIC_CLAIM)


STATIC_CLAIM: Claim | None = None
"""The static solve has no registry entry yet, hence no stated claim (its figures are counted)."""

ANALYSES: dict[str, tuple[Callable[[str, Tally, contract_models.Case], None], list[str], int]] = {
    "modes": (run_modes, [*EIGEN, "auto"], MAX_BODIES),
    "frequency_response": (run_frf, [*FREQUENCY, "auto"], MAX_BODIES),
    "simulate": (run_time, [*TIME, "auto"], TIME_BODIES),
    "reduce": (run_reduce, [*REDUCTION, "auto"], MAX_BODIES),
    "static": (run_static, ["solve"], MAX_BODIES),
}
"""Each analysis: its runner, its methods (every registry entry and ``auto``), its largest model."""

SLOW = {("simulate", "ivp")}
"""Over ~4 s at the small size (Radau through the penalty links' 1e7 rad/s modes)."""

KNOWN: dict[tuple[str, str], tuple[str, tuple[str, ...]]] = {
}
"""Silent misses found today: (analysis, method) -> (why, the models that show it). A strict xfail
where the run holds one of those models (fixing it turns the test red until the entry goes)."""


def _params() -> list[Any]:
    out = []
    names_run = {c.name for c in CASES}
    for analysis, (_, names, _) in ANALYSES.items():
        for name in names:
            why, where = KNOWN.get((analysis, name), ("", ()))
            marks = [pytest.mark.xfail(strict=True, reason=why)] if names_run.intersection(where) else []
            marks += [pytest.mark.slow] if (analysis, name) in SLOW else []
            out.append(pytest.param(analysis, name, marks=marks, id=f"{analysis}-{name}"))
    return out


@pytest.mark.parametrize(("analysis", "method"), _params())
def test_no_silent_miss(analysis: str, method: str) -> None:
    """Every answer of the method is within its claim, or warned with a bound that covers the
    measured error, or a refusal; the figures go to stdout and ``VIBSS_CAMPAIGN_OUT``."""
    runner, _, largest = ANALYSES[analysis]
    tally = Tally(analysis, method)
    for case in CASES:
        if case.bodies <= largest:
            with np.errstate(all="ignore"):
                runner(method, tally, case)
    row = tally.row()
    print(f"\ncampaign {json.dumps(row)}")
    if os.environ.get("VIBSS_CAMPAIGN_OUT"):
        with open(os.environ["VIBSS_CAMPAIGN_OUT"], "a") as fh:
            fh.write(json.dumps(row) + "\n")
    assert not tally.silent, f"{len(tally.silent)} silent misses: {tally.silent[:5]}"


def test_the_generator_is_deterministic_and_covers_its_families() -> None:
    """The same draw twice; every family present; near-repeated frequencies really within 1e-7;
    mechanisms really have rigid modes inside a grounded chain; penalty links really 1e10 and up."""
    a, b = contract_models.cases(1, 3), contract_models.cases(1, 3)
    assert [c.model.name for c in a] == [c.model.name for c in b]
    for x, y in zip(a, b):
        np.testing.assert_array_equal(vibss.assemble(x.model).dense("K"), vibss.assemble(y.model).dense("K"))
    by = {c.family: c for c in a}
    assert set(by) == set(contract_models.FAMILIES)
    f = elastic_hz(by["near_repeated"])
    assert np.min(np.diff(f) / f[1:]) < 1e-7
    assert spectrum(by["mechanism"])[1].any()
    assert max(float(np.max(m.type.stiffness)) for m in by["penalty"].model.mounts) >= 1e10
    masses = [b.mass for b in by["mass_ratio"].model.bodies]
    assert max(masses) / min(masses) >= 1e5


def test_subspace_through_penalty_links_refuses_or_answers() -> None:
    """Found by the campaign (make fuzz): four bodies joined by 1e10-1e14 N/m links, a force and a
    moment in: ``subspace`` crashed with a raw LinAlgError; it must answer within its claim or refuse
    with a VibssError (fixed: a basis that becomes dependent is answered by the exact solve)."""
    case = contract_models.family("penalty", 22)
    inputs, cols, outputs = signals(case)
    f = frf_frequencies(case)
    try:
        r = vibss.frequency_response(case.model, inputs, outputs, frequencies=f, method="subspace")
    except VibssError:
        return
    assert error_frf(r.response, reference_frf(case, f, cols)) <= 1e-8
