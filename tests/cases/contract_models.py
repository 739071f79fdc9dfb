"""The contract campaign's random models (issue 29 item 6): five families where methods lose digits.

Each family is a seeded, deterministic generator of small models (1-4 bodies, so that the 60-digit
references of :mod:`cases.mp_reference` stay cheap) built from a :class:`cases.fuzzing.Spec` by
:func:`cases.fuzzing.build`:

- ``penalty``: a chain on soft ground mounts (1e3-1e5 N/m) joined by penalty links (1e10-1e14 N/m);
- ``mass_ratio``: masses over six decades (1e-2 ... 1e4 kg) on mounts and links of 1e3-1e6 N/m;
- ``mechanism``: a chain whose links hold some directions only (zero-stiffness axes): rigid modes
  inside the chain while the first body is grounded;
- ``near_repeated``: a symmetric layout (identical bodies on identical mounts at mirrored points),
  perturbed by about 1e-8 (relative): frequencies within 1e-8 of each other;
- ``general_damping``: strongly non-proportional viscous damping (damping ratios up to ~0.3, a
  different ratio per mount and axis).

Ground mounts are damped on every stiff axis (no undamped resonance, so the response at an exact
natural frequency is finite); there is no hysteretic damping (the time domain would drop it, with
a warning that is not about accuracy).

Examples
--------
>>> [c.family for c in cases(1)]
['penalty', 'mass_ratio', 'mechanism', 'near_repeated', 'general_damping']
>>> cases(1)[0].model.name
'penalty-0'
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from cases.fuzzing import Spec, build
from vibss import Model

__all__ = ["Case", "FAMILIES", "cases", "family"]

Vec = tuple[float, float, float]


@dataclass(frozen=True)
class Case:
    """One campaign model: its family, its index in the family and the model."""

    family: str
    index: int
    model: Model

    @property
    def name(self) -> str:
        return f"{self.family}-{self.index}"

    @property
    def bodies(self) -> int:
        return len(self.model.bodies)


def _v(x: np.ndarray) -> Vec:
    return (float(x[0]), float(x[1]), float(x[2]))


def _body(rng: np.random.Generator, mass: float, cog: np.ndarray) -> tuple[float, Vec, Vec, Vec]:
    """(mass, second moments [m^2], rotation vector of the principal axes, cog)."""
    spread = 10.0 ** rng.uniform(-2.0, -0.5, 3)
    return mass, _v(spread), _v(rng.uniform(-3, 3, 3)), _v(cog)


def _ground(rng: np.random.Generator, b: int, cog: Vec, k_lo: float, k_hi: float, zeta: float = 0.02,
            free_axis: bool = False) -> tuple:
    """A damped ground mount near body ``b``: stiffness per axis 10**U(lo, hi), ``c = 2 zeta k / w``
    with ``w`` about 30 rad/s (non-proportional: each axis its own ratio)."""
    k = 10.0 ** rng.uniform(np.log10(k_lo), np.log10(k_hi), 3)
    if free_axis:
        k[rng.integers(3)] = 0.0
    c = 2 * zeta * rng.uniform(0.2, 1.0, 3) * k / 30.0
    at = np.add(cog, rng.uniform(-0.4, 0.4, 3))
    return (b, -1, _v(at), _v(rng.uniform(-3, 3, 3)), _v(k), _v(c), 0.0)


def _link(rng: np.random.Generator, b: int, to: int, cog: Vec, k: np.ndarray,
          c: np.ndarray | None = None) -> tuple:
    at = np.add(cog, rng.uniform(-0.3, 0.3, 3))
    return (b, to, _v(at), _v(rng.uniform(-3, 3, 3)), _v(k), _v(np.zeros(3) if c is None else c), 0.0)


def _chain(rng: np.random.Generator, nb: int, masses: np.ndarray, ground: Callable[[int, Vec], list],
           link: Callable[[int, int, Vec], tuple], links: int = 1) -> Spec:
    """Bodies 0.8 m apart along x, each with its ground mounts and ``links`` links to the previous one."""
    bodies = [_body(rng, float(masses[i]), np.array([0.8 * i, 0.0, 0.0]) + rng.uniform(-0.1, 0.1, 3))
              for i in range(nb)]
    mounts: list[tuple] = []
    for i, b in enumerate(bodies):
        mounts += ground(i, b[3])
        if i:
            mounts += [link(i, i - 1, b[3]) for _ in range(links)]
    return Spec(tuple(b[0] for b in bodies), tuple(b[1] for b in bodies), tuple(b[2] for b in bodies),
                tuple(b[3] for b in bodies), tuple(mounts))


def penalty(rng: np.random.Generator, nb: int) -> Spec:
    """Soft ground mounts (1e3-1e5 N/m) on the first body (and some others), one or two penalty
    links 1e10-1e14 N/m between neighbours (one link's axes within 3 decades of each other)."""
    masses = 10.0 ** rng.uniform(0.0, 2.0, nb)

    def ground(i: int, cog: Vec) -> list:
        n = 3 if i == 0 else int(rng.integers(0, 2))
        return [_ground(rng, i, cog, 1e3, 1e5) for _ in range(n)]

    def link(i: int, j: int, cog: Vec) -> tuple:
        e = rng.uniform(10.0, 14.0)
        return _link(rng, i, j, cog, 10.0 ** (e - rng.uniform(0.0, 3.0, 3)))

    return _chain(rng, nb, masses, ground, link, links=int(rng.integers(1, 3)))


def mass_ratio(rng: np.random.Generator, nb: int) -> Spec:
    """Masses over six decades (the first and last 1e-2 and 1e4 kg, the others between), mounts
    and links 1e3-1e6 N/m."""
    ends = np.array([1e-2, 1e4]) if rng.random() < 0.5 else np.array([1e4, 1e-2])
    masses = np.concatenate([ends[:1], 10.0 ** rng.uniform(-2.0, 4.0, max(nb - 2, 0)), ends[1:]])[:nb] \
        if nb > 1 else ends[:1]

    def ground(i: int, cog: Vec) -> list:
        n = 3 if i == 0 else int(rng.integers(0, 3))
        return [_ground(rng, i, cog, 1e3, 1e6) for _ in range(n)]

    def link(i: int, j: int, cog: Vec) -> tuple:
        return _link(rng, i, j, cog, 10.0 ** rng.uniform(3.0, 6.0, 3))

    return _chain(rng, nb, masses, ground, link)


def mechanism(rng: np.random.Generator, nb: int) -> Spec:
    """A grounded first body; each further body hangs on one or two links that hold only some
    directions (one or two zero-stiffness axes): mechanism (rigid) modes inside the chain. A
    one-body model has a ground mount with a free axis and a second one parallel to it."""
    masses = 10.0 ** rng.uniform(0.0, 2.0, nb)

    def ground(i: int, cog: Vec) -> list:
        if i:
            return []
        if nb == 1:      # two mounts sharing one free axis (same orientation): a free translation
            g = _ground(rng, 0, cog, 1e3, 1e5)
            k = np.array(g[4])
            k[0] = 0.0
            c = np.where(k > 0, np.array(g[5]), 0.0)
            g = (*g[:4], _v(k), _v(c), 0.0)
            g2 = (0, -1, _v(np.add(cog, rng.uniform(-0.4, 0.4, 3))), g[3], g[4], g[5], 0.0)
            return [g, g2]
        return [_ground(rng, 0, cog, 1e3, 1e5) for _ in range(3)]

    def link(i: int, j: int, cog: Vec) -> tuple:
        k = 10.0 ** rng.uniform(3.0, 6.0, 3)
        k[rng.choice(3, size=int(rng.integers(1, 3)), replace=False)] = 0.0
        return _link(rng, i, j, cog, k, 0.01 * k * rng.uniform(0.1, 1.0, 3))

    return _chain(rng, nb, masses, ground, link)


def near_repeated(rng: np.random.Generator, nb: int) -> Spec:
    """Identical bodies (principal axes along x, y, z, equal x and y moments) on four identical
    mounts at (+-a, +-a, -h) each, the bodies joined by a soft link at their centres; every
    position, stiffness and mass then perturbed by about 1e-8 (relative)."""
    m = 10.0 ** rng.uniform(0.0, 2.0)
    r2 = 10.0 ** rng.uniform(-2.0, -1.0)
    a, h = rng.uniform(0.2, 0.5), rng.uniform(0.05, 0.2)
    kz, kxy = 10.0 ** rng.uniform(4.0, 5.0), 10.0 ** rng.uniform(3.0, 4.0)
    k = np.array([kxy, kxy, kz])
    c = 0.002 * k
    tiny = lambda: 1.0 + 1e-8 * rng.standard_normal()   # noqa: E731
    masses, spreads, axes, cogs, mounts = [], [], [], [], []
    for i in range(nb):
        cog = np.array([1.5 * i, 0.0, 0.0])
        masses.append(m * tiny())
        spreads.append((r2 * tiny(), r2 * tiny(), 2 * r2 * tiny()))
        axes.append((0.0, 0.0, 0.0))
        cogs.append(_v(cog))
        for sx in (-1, 1):
            for sy in (-1, 1):
                at = cog + np.array([sx * a * tiny(), sy * a * tiny(), -h * tiny()])
                mounts.append((i, -1, _v(at), (0.0, 0.0, 0.0), _v(k * [tiny(), tiny(), tiny()]), _v(c), 0.0))
        if i:
            mounts.append((i, i - 1, _v(cog - [0.75, 0.0, 0.0]), (0.0, 0.0, 0.0), _v(0.01 * k * tiny()),
                           (0.0, 0.0, 0.0), 0.0))
    return Spec(tuple(masses), tuple(spreads), tuple(axes), tuple(cogs), tuple(mounts))


def general_damping(rng: np.random.Generator, nb: int) -> Spec:
    """Mounts of 1e3-1e6 N/m whose damping ratio differs per mount and axis (0.001 ... 0.3):
    strongly non-proportional; the links damped too."""
    masses = 10.0 ** rng.uniform(0.0, 2.5, nb)

    def ground(i: int, cog: Vec) -> list:
        n = 3 if i == 0 else int(rng.integers(0, 3))
        return [_ground(rng, i, cog, 1e3, 1e6, zeta=10.0 ** rng.uniform(-3.0, -0.5)) for _ in range(n)]

    def link(i: int, j: int, cog: Vec) -> tuple:
        k = 10.0 ** rng.uniform(3.0, 6.0, 3)
        return _link(rng, i, j, cog, k, 2 * 10.0 ** rng.uniform(-3.0, -0.5, 3) * k / 30.0)

    return _chain(rng, nb, masses, ground, link)


FAMILIES: dict[str, Callable[[np.random.Generator, int], Spec]] = {
    "penalty": penalty, "mass_ratio": mass_ratio, "mechanism": mechanism,
    "near_repeated": near_repeated, "general_damping": general_damping}
"""The families by name, each ``f(rng, bodies) -> Spec``."""


def family(name: str, index: int, max_bodies: int = 4, seed: int = 29) -> Case:
    """Model ``index`` of family ``name``: seeded by (seed, family, index), deterministic.

    Parameters
    ----------
    name : str
        One of :data:`FAMILIES`.
    index : int
        Position in the family (the body count cycles 1 ... ``max_bodies``, starting at 2).
    max_bodies : int
        Largest model [bodies].
    seed : int
        The draw.

    Returns
    -------
    Case
    """
    rng = np.random.default_rng([seed, list(FAMILIES).index(name), index])
    nb = 1 + (index + 1) % max_bodies
    model = build(FAMILIES[name](rng, nb))
    return Case(name, index, Model(model.bodies, model.mounts, gravity=model.gravity, name=f"{name}-{index}"))


def cases(per_family: int, max_bodies: int = 4, seed: int = 29) -> list[Case]:
    """``per_family`` models of every family, interleaved (family by family for each index)."""
    return [family(name, i, max_bodies, seed) for i in range(per_family) for name in FAMILIES]
