"""The adversarial suite's machinery: random models, an independent reference, mutated files.

Used by ``tests/robustness/test_random_models.py`` (a short, seeded run in every test run) and by ``make fuzz``
(the same tests, longer: ``VIBSS_FUZZ=1``; see docs/robustness.md for the figures of the last run).

- :func:`model_spec` / :func:`build` — a random model from plain numbers: 1–6 bodies, masses over
  seven decades, full inertia tensors (principal moments from a random mass distribution, random
  principal axes), inclined mounts at random points, zero-stiffness axes, body–body links from soft
  to 1e16 N/m, non-proportional viscous and hysteretic damping; some models have rigid modes.
- :func:`reference_eigen`, :func:`reference_frf`, :func:`reference_static` — the answers from the
  loop-per-mount matrices of ``reference_impl`` (no vibss code beyond reading the model's fields)
  with plain NumPy/SciPy solves.
- :func:`mutations` — seeded mutations of a model file's text (numbers made extreme, lines dropped or
  doubled, keys renamed, nesting deepened, bytes flipped, a byte-order mark, truncation ...).
"""

from __future__ import annotations

import os
import random
import re
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.linalg as sl
from scipy.spatial.transform import Rotation

from cases.reference_impl import loop_assemble, loop_mass
from vibss import GROUND, Body, Model, Mount, MountType

LONG = bool(os.environ.get("VIBSS_FUZZ"))
"""``make fuzz``: the long run (1,000 models per property, 10,000 mutated files)."""

MODELS = int(os.environ.get("VIBSS_FUZZ_MODELS", 1000 if LONG else 12))
"""Random models per property (``VIBSS_FUZZ_MODELS`` overrides)."""

FILES = int(os.environ.get("VIBSS_FUZZ_FILES", 10_000 if LONG else 60))
"""Mutated model files, spread over the examples (``VIBSS_FUZZ_FILES`` overrides)."""

SEED = int(os.environ["VIBSS_FUZZ_SEED"]) if os.environ.get("VIBSS_FUZZ_SEED") else None
"""Another draw of random models (``VIBSS_FUZZ_SEED``: an integer; the draws stay deterministic per
seed). Unset, hypothesis derives the draw from each test's own code, so the same tests give the same
models run to run; but a change to a test, or selecting other tests, may move it."""

EPS = np.finfo(float).eps


@dataclass(frozen=True)
class Spec:
    """A random model as plain numbers (what hypothesis draws and shrinks)."""

    masses: tuple[float, ...]
    spreads: tuple[tuple[float, float, float], ...]      # second moments of the mass [m^2]
    axes: tuple[tuple[float, float, float], ...]         # rotation vectors of the principal axes
    cogs: tuple[tuple[float, float, float], ...]
    mounts: tuple[tuple[int, int, tuple[float, float, float], tuple[float, float, float],
                        tuple[float, float, float], tuple[float, float, float], float], ...]
    """(body, to (-1: ground), at, rotation vector, stiffness, damping, loss factor)."""


def build(spec: Spec, rotation: np.ndarray | None = None, shift: np.ndarray | None = None) -> Model:
    """The model of ``spec``, optionally rigidly moved (``x -> R x + shift``) as a whole."""
    R = np.eye(3) if rotation is None else rotation
    t = np.zeros(3) if shift is None else shift
    bodies = []
    for i, (m, s, a, c) in enumerate(zip(spec.masses, spec.spreads, spec.axes, spec.cogs)):
        moments = m * np.array([s[1] + s[2], s[0] + s[2], s[0] + s[1]])
        axes = R @ Rotation.from_rotvec(a).as_matrix()
        tensor = axes @ np.diag(moments) @ axes.T                  # a full tensor in global axes
        bodies.append(Body(f"b{i}", m, (tensor + tensor.T) / 2, cog=R @ np.array(c) + t))
    mounts = []
    for j, (b, to, at, rv, k, c, eta) in enumerate(spec.mounts):
        mt = MountType(f"t{j}", k, c, eta)
        orient = R @ Rotation.from_rotvec(rv).as_matrix()
        mounts.append(Mount(f"m{j}", mt, f"b{b}", at=R @ np.array(at) + t, frame="global",
                            to=GROUND if to < 0 else f"b{to}", orientation=orient))
    return Model(bodies, mounts, gravity=R @ np.array([0.0, 0.0, -9.81]), name="fuzz")


MAX_BODIES = 6 if LONG else 4
"""Largest random model (the 60-digit reference costs ~0.5 s at 6 bodies, 0.1 s at 4)."""


def model_specs(max_bodies: int = MAX_BODIES) -> Any:
    """The hypothesis strategy of :class:`Spec`."""
    from hypothesis import strategies as st

    def vec(lo: float, hi: float) -> Any:
        return st.tuples(*[st.floats(lo, hi, allow_nan=False, allow_infinity=False)] * 3)

    decade = st.floats(-3.0, 4.0)                                  # masses 1 g .. 10 t
    positive = st.floats(2.0, 7.0).map(lambda e: 10.0 ** e)
    stiff = st.integers(0, 9).flatmap(lambda i: st.just(0.0) if i == 0 else positive)   # 1 axis in 10 free
    link = st.one_of(st.floats(2.0, 7.0), st.floats(9.0, 16.0))     # log10 of a link's stiffness

    @st.composite
    def spec(draw: Any) -> Spec:
        nb = draw(st.integers(1, max_bodies))
        masses = tuple(10.0 ** draw(decade) for _ in range(nb))
        spreads = tuple(tuple(10.0 ** x for x in draw(vec(-3.0, 0.0))) for _ in range(nb))
        axes = tuple(draw(vec(-3.0, 3.0)) for _ in range(nb))
        cogs = tuple(draw(vec(-1.0, 1.0)) for _ in range(nb))
        mounts = []
        for b in range(nb):                                        # 1-4 ground mounts a body ...
            for _ in range(draw(st.integers(0 if b else 1, 4))):
                k = tuple(draw(stiff) for _ in range(3))
                c = tuple(draw(st.floats(0.0, 1e-2)) * x for x in k)   # non-proportional
                mounts.append((b, -1, tuple(np.add(cogs[b], draw(vec(-0.5, 0.5)))), draw(vec(-3.0, 3.0)),
                               k, c, draw(st.sampled_from([0.0, 0.0, 0.05]))))
            if b:                                                  # ... and a link to an earlier body
                # one mount's own axes within 3 decades: the mounts' exact form keeps each mount's
                # 3x3 stiffness in global axes, which holds a 1e2 axis beside a 1e15 one only to
                # 1e15 eps / 1e2 (docs/robustness.md)
                e = draw(link)
                k = (10.0 ** e,) * 3 if draw(st.booleans()) else tuple(10.0 ** (e - draw(st.floats(0.0, 3.0)))
                                                                     for _ in range(3))
                mounts.append((b, draw(st.integers(0, b - 1)), tuple(np.add(cogs[b], draw(vec(-0.5, 0.5)))),
                               draw(vec(-3.0, 3.0)), k, (0.0, 0.0, 0.0), 0.0))
        return Spec(masses, spreads, axes, cogs, tuple(mounts))

    return spec()


# -- the independent reference -----------------------------------------------------------------------
def reference_matrices(model: Model) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(M, K, C, H) from the loop-per-mount assembly of ``reference_impl``."""
    K = loop_assemble(model)
    C = loop_assemble(model, "damping")
    H = loop_assemble(_lossy(model))            # hysteretic: eta k per principal axis, the same loop
    return loop_mass(model), K, C, H


def reference_eigen(model: Model) -> tuple[np.ndarray, float]:
    """Squared natural frequencies [rad^2/s^2] by ``scipy.linalg.eigh(K, M)`` and their absolute
    error bound (backward-stable eigh: a few hundred eps times the largest)."""
    M, K, _, _ = reference_matrices(model)
    w2 = sl.eigh(K, M, eigvals_only=True)
    return w2, 500 * EPS * max(float(np.abs(w2).max()), 1e-300) * K.shape[0]


def reference_frf(model: Model, f_hz: float, inputs: list[int], outputs: list[int]) -> np.ndarray:
    """Receptance of body DOFs to body forces at ``f_hz`` by one dense complex solve."""
    M, K, C, H = reference_matrices(model)
    s = 2j * np.pi * f_hz
    Z = K + 1j * H + s * C + s * s * M
    F = np.zeros((K.shape[0], len(inputs)))
    F[inputs, range(len(inputs))] = 1.0
    return np.linalg.solve(Z, F)[outputs]


def mp_frf(model: Model, f_hz: float, columns: list[int]) -> np.ndarray:
    """Columns of the receptance ``(K + iH + sC + s^2 M)^-1`` in 60-digit arithmetic."""
    n = 6 * len(model.bodies)
    return mp_solve(model, f_hz, np.eye(n)[:, columns])


def mp_solve(model: Model, f_hz: float, rhs: np.ndarray) -> np.ndarray:
    """``(K + iH + sC + s^2 M)^-1 rhs`` at ``s = 2 pi i f_hz`` in 60-digit arithmetic."""
    import mpmath as mp

    from cases.mp_reference import DPS, mass, matrices

    lossy = _lossy(model)
    rhs = np.asarray(rhs, float).reshape(6 * len(model.bodies), -1)
    with mp.workdps(DPS):
        s = mp.mpc(0, 2 * mp.pi * mp.mpf(f_hz))
        D = matrices(model) + mp.mpc(0, 1) * matrices(lossy) + s * matrices(model, "damping") + s * s * mass(model)
        out = []
        for j in range(rhs.shape[1]):
            x = mp.lu_solve(D, mp.matrix([mp.mpf(float(v)) for v in rhs[:, j]]))
            out.append([complex(x[i]) for i in range(D.rows)])
    return np.array(out).T


def mp_static(model: Model, load: np.ndarray) -> np.ndarray:
    """``K^-1 f`` in 60-digit arithmetic (K nonsingular)."""
    from cases.mp_reference import static

    return static(model, load)


def _lossy(model: Model) -> Model:
    """The model with each mount's stiffness replaced by ``eta k`` (its hysteretic stiffness)."""
    return Model(model.bodies, [Mount(m.name, MountType(f"h.{m.name}", np.asarray(m.type.stiffness)
                                                        * np.broadcast_to(np.asarray(m.type.loss_factor, float), (3,))),
                                      m.body, at=m.at, to=m.to, orientation=m.orientation, frame=m.frame)
                                for m in model.mounts])


def rotation(seed: int) -> np.ndarray:
    """A seeded random rotation matrix."""
    return Rotation.random(random_state=seed).as_matrix()


# -- mutated files -----------------------------------------------------------------------------------
EXTREMES = ["0", "-0.0", "1e-300", "-1e-300", "1e308", "-1e308", "1e400", "nan", "inf", "-inf", "1" + "0" * 400,
            "1" + "0" * 5000, "9" * 31, "3.0e-7", "-1.0", "1e20", "1e16", "2", "true", '"x"', "[]", "{}",
            "[" * 40 + "1" + "]" * 40, "{ a = " * 30 + "1" + " }" * 30]


def mutations(text: str, rng: random.Random) -> str:
    """One to three seeded mutations of a TOML model file's text."""
    for _ in range(rng.randint(1, 3)):
        kind = rng.randrange(10)
        lines = text.split("\n")
        numbers = list(re.finditer(r"(?<![\w.])-?\d+(\.\d+)?([eE][-+]?\d+)?", text))
        if kind <= 2 and numbers:                            # a number made extreme
            m = rng.choice(numbers)
            text = text[:m.start()] + rng.choice(EXTREMES) + text[m.end():]
        elif kind == 3 and len(lines) > 1:                   # a line dropped
            del lines[rng.randrange(len(lines))]
            text = "\n".join(lines)
        elif kind == 4:                                      # a line doubled
            i = rng.randrange(len(lines))
            lines.insert(i, lines[i])
            text = "\n".join(lines)
        elif kind == 5:                                      # a key renamed
            keys = list(re.finditer(r"^(\w+)\s*=", text, re.M))
            if keys:
                m = rng.choice(keys)
                text = text[:m.start(1)] + rng.choice(["mass", "name", "x", "stiffness", "type", "body", "euler",
                                                       "file", m.group(1) + "s"]) + text[m.end(1):]
        elif kind == 6:                                      # bytes flipped
            b = bytearray(text.encode())
            for _ in range(rng.randint(1, 4)):
                if b:
                    b[rng.randrange(len(b))] = rng.randrange(256)
            text = b.decode("utf-8", "replace")
        elif kind == 7:                                      # truncated
            text = text[:rng.randrange(len(text) + 1)]
        elif kind == 8:                                      # a byte-order mark, or a table file
            text = ("\ufeff" + text) if rng.random() < 0.5 else text + (
                '\n[[excitation]]\nkind = "force"\ntarget = "%s"\ndof = "z"\nfunction = { type = "table", file = "%s" }\n'
                % (rng.choice(["engine", "ground", "b"]), rng.choice(["/dev/zero", ".", "/dev/null", "missing.csv"])))
        else:                                                # a string value changed
            strings = list(re.finditer(r'"[^"\n]*"', text))
            if strings:
                m = rng.choice(strings)
                text = text[:m.start()] + rng.choice(['""', '"ground"', '"%s"' % ("x" * 300), '"a.b"', "1"]) + text[m.end():]
    return text


def mutated_files(texts: dict[str, str], count: int, seed: int = 18) -> Iterator[tuple[str, str]]:
    """``count`` (name, mutated text) pairs, spread over ``texts`` (seeded, deterministic)."""
    rng = random.Random(seed)
    names = sorted(texts)
    for i in range(count):
        name = names[i % len(names)]
        yield f"{name}-{i}", mutations(texts[name], rng)
