"""Benchmark models: random rigid bodies on rotated mounts in three topologies, as a user's model.

- ``chain_model(n_bodies, damping=...)`` joins every body to ground by two mounts and to its
  neighbour(s) by one or two mounts, all at random points with random orientations;
- ``grid_model(n_bodies, width=10, ...)``: a ``width``-wide grid (issue 17's independent benchmark):
  5-50 kg bodies with full inertia tensors, two ground mounts each, one mount to each +x and +y
  neighbour; no narrow band under any ordering;
- ``tree_model(n_bodies, ...)``: a random tree like a vehicle's subframes (each body hangs off a
  random earlier one by three mounts, a third of the bodies also on ground), plus a few cross links.
- ``lattice_model(n_bodies, ...)``: a 3-D lattice, each body linked to its +-x, +-y, +-z neighbours
  (one mount per pair), one ground mount per body: the widest band of the suite per DOF;
- ``random_graph_model(n_bodies, ...)``: a sparse random graph, each body linked to 3 random other
  bodies (seeded), one ground mount per body: no ordering bands it, SuperLU fills in;
- ``mechanism_model(n_bodies, ...)``: a chain with mechanism modes: body 0 on ground by three mounts,
  each body on the previous one by three; every fifth link a slide (its three mounts share one
  orientation and have no stiffness along their local x): one free relative motion (a zero
  frequency) per slide;
- ``tower_model(n_bodies, ...)``: a soft tower, a 3 x 3-footprint lattice (three mounts on the
  body below) standing on very soft
  ground mounts under its bottom layer: its lowest mode is below 1 mHz at every size (0.77 mHz at
  150 DOF, 0.16 mHz at 6,000, 0.03 mHz at 60,000; the 60,000-DOF build takes about 50 s); damping scaled at 1 Hz (not at that mode).
- ``topology_model(kind, n_bodies, ...)`` picks one by name (``TOPOLOGIES``, ``NEW_TOPOLOGIES``);
  ``SUITE_DOFS`` are the sizes the suite measures them at, ``LARGE_DOF`` the large path's.

damping:
- ``"none"``: no viscous damping;
- ``"classical"``: every mount c = beta k with one beta (C = beta K, classically damped); beta is
  chosen so the lowest elastic mode has damping ratio ``zeta``;
- ``"general"``: a random beta per mount (non-proportional, complex modes).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from scipy.spatial.transform import Rotation

from vibss import Body, Model, Mount, MountType


TOPOLOGIES = ("chain", "grid", "tree")
NEW_TOPOLOGIES = ("lattice", "random", "mechanism", "tower")
"""The topologies issue 34 added (3-D lattice, random graph, mechanism chain, soft tower)."""
SUITE_DOFS = (150, 600, 2400, 6000)
"""The sizes of the suite [DOF] (6 per body)."""
LARGE_DOF = 60000
"""The large path's size [DOF]."""


def topology_model(kind: str, n_bodies: int = 100, damping: str = "classical", zeta: float = 1e-3,
                   seed: int = 0) -> Model:
    """A builder of this module by name (``kind`` in ``TOPOLOGIES + NEW_TOPOLOGIES``)."""
    builders = {"chain": lambda: chain_model(n_bodies, damping, zeta, seed),
                "grid": lambda: grid_model(n_bodies, damping=damping, zeta=zeta, seed=seed),
                "tree": lambda: tree_model(n_bodies, damping=damping, zeta=zeta, seed=seed),
                "lattice": lambda: lattice_model(n_bodies, damping=damping, zeta=zeta, seed=seed),
                "random": lambda: random_graph_model(n_bodies, damping=damping, zeta=zeta, seed=seed),
                "mechanism": lambda: mechanism_model(n_bodies, damping=damping, zeta=zeta, seed=seed),
                "tower": lambda: tower_model(n_bodies, damping=damping, zeta=zeta, seed=seed)}
    if kind not in builders:
        raise ValueError(f"kind: {kind!r} is not one of {TOPOLOGIES + NEW_TOPOLOGIES}")
    return builders[kind]()


def _box(n_bodies: int, nx: int, ny: int) -> tuple[Any, Any]:
    """Position of body i in an ``nx`` x ``ny`` x ... lattice, and its -x, -y, -z neighbours."""
    def at(i: int) -> list[float]:
        return [float(i % nx), float((i // nx) % ny), float(i // (nx * ny))]

    def below(i: int) -> list[int]:
        x, y = i % nx, (i // nx) % ny
        return ([i - 1] if x else []) + ([i - nx] if y else []) + ([i - nx * ny] if i >= nx * ny else [])

    return at, below


def lattice_model(n_bodies: int = 100, damping: str = "classical", zeta: float = 1e-3, seed: int = 0) -> Model:
    """A 3-D lattice of ``n_bodies`` bodies (5-50 kg, 1e4-1e6 N/m), about a cube, 6 n DOF.

    One mount to each -x, -y and -z neighbour (so each body links to its +-x, +-y, +-z ones) and
    one ground mount per body, at random points and orientations.
    """
    side = max(1, round(n_bodies ** (1 / 3)))
    at, below = _box(n_bodies, side, side)
    return _random_model(n_bodies, damping, zeta, seed, "nice", 1, below, position=at, masses=(5.0, 50.0),
                         name=f"3-D lattice of {n_bodies} bodies ({damping} damping)")


def random_graph_model(n_bodies: int = 100, damping: str = "classical", zeta: float = 1e-3,
                       seed: int = 0) -> Model:
    """A sparse random graph of ``n_bodies`` bodies (5-50 kg, 1e4-1e6 N/m), 6 n DOF: each body
    linked by one mount to each of 3 random other bodies (earlier ones, seeded; so about 6 links a
    body), one ground mount per body."""
    rng = np.random.default_rng(seed + 104729)
    picks = [rng.choice(i, size=min(3, i), replace=False).tolist() if i else [] for i in range(n_bodies)]
    return _random_model(n_bodies, damping, zeta, seed, "nice", 1, lambda i: picks[i],
                         position=lambda i: [float(i % 10), float(i // 10 % 10), float(i // 100)],
                         masses=(5.0, 50.0), name=f"random graph of {n_bodies} bodies ({damping} damping)")


SLIDE_EVERY = 5
"""A mechanism chain's every fifth link is a slide (one free relative motion)."""


def mechanism_model(n_bodies: int = 100, damping: str = "classical", zeta: float = 1e-3, seed: int = 0) -> Model:
    """A chain with mechanism modes (1-100 kg, 1e4-1e6 N/m), 6 n DOF, ``(n_bodies - 1) // 5`` of
    them at zero frequency: body 0 on ground by three mounts, body i on body i - 1 by three; the
    links of the bodies i = 5, 10, ... are slides (the three mounts oriented alike with no stiffness
    along their local x: a free relative translation)."""
    def slide(body: int, to: str, k: np.ndarray, orient: np.ndarray, first: np.ndarray) -> tuple:
        if to != "ground" and body % SLIDE_EVERY == 0:
            return k * np.array([0.0, 1.0, 1.0]), first
        return k, orient

    return _random_model(n_bodies, damping, zeta, seed, "nice", 3, lambda i: [i - 1] * 3 if i else [],
                         position=lambda i: [1.0 * i, 0.0, 0.0], masses=None,
                         grounded=[i == 0 for i in range(n_bodies)], edit=slide,
                         name=f"mechanism chain of {n_bodies} bodies ({damping} damping)")


TOWER_BASE = 2e-8
"""The soft tower's ground mounts are this times the usual 1e4-1e6 N/m (at 25 bodies; times the
square of its height above)."""


def tower_model(n_bodies: int = 100, damping: str = "classical", zeta: float = 1e-3, seed: int = 0) -> Model:
    """A soft tower of ``n_bodies`` bodies (5-50 kg), 6 n DOF: a 3 x 3-footprint lattice (links
    1e4-1e6 N/m to each -x and -y neighbour, three to the -z one) whose bottom layer stands on two ground mounts a body
    of :data:`TOWER_BASE` times that stiffness (times ``(n_bodies / 25)^2``): lowest mode below 1 mHz (0.77 mHz at 150 DOF, 0.03 mHz at 60,000). Damping
    is scaled to ``zeta`` at 1 Hz (the lowest mode's would overdamp the links)."""
    at, below = _box(n_bodies, 3, 3)
    base = TOWER_BASE * max(1.0, n_bodies / 25) ** 2      # a taller tower rocks lower: 0.1-0.8 mHz

    def links(i: int) -> list[int]:     # three mounts on the body below: no free rotation of a lone top body
        down = below(i)
        return down + ([i - 9] * 2 if i >= 9 else [])

    def soft(body: int, to: str, k: np.ndarray, orient: np.ndarray, first: np.ndarray) -> tuple:
        return (k * base if to == "ground" else k), orient

    return _random_model(n_bodies, damping, zeta, seed, "nice", 2, links, position=at, masses=(5.0, 50.0),
                         grounded=[i < 9 for i in range(n_bodies)], edit=soft, w_ref=2 * np.pi,
                         name=f"soft tower of {n_bodies} bodies ({damping} damping)")


def chain_model(n_bodies: int = 100, damping: str = "classical", zeta: float = 1e-3,
                seed: int = 0, scale: str = "nice", ground_mounts: int = 2) -> Model:
    """Random chain of ``n_bodies`` rigid bodies (6 n DOF) on mounts to ground and neighbours.

    ``scale="nice"``: 1-100 kg, 1e4-1e6 N/m; ``"bad"``: 1e-3-1e4 kg, 1e2-1e8 N/m.
    """
    def links(i: int) -> list[int]:
        return ([i - 1] if i > 0 else []) + ([i - 2] if i > 1 and i % 3 == 0 else [])

    return _random_model(n_bodies, damping, zeta, seed, scale, ground_mounts, links,
                         position=lambda i: [1.0 * i, 0.0, 0.0], masses=None,
                         name=f"chain of {n_bodies} bodies ({damping} damping)")


def grid_model(n_bodies: int = 100, width: int = 10, damping: str = "classical", zeta: float = 1e-3,
               seed: int = 0) -> Model:
    """A ``width``-wide grid of ``n_bodies`` bodies (5-50 kg, 1e4-1e6 N/m), 6 n DOF.

    Two ground mounts per body, one mount to the -x neighbour and one to the -y neighbour (so each
    body links to its +x/+y neighbours once), all at random points and orientations.
    """
    def links(i: int) -> list[int]:
        return ([i - 1] if i % width else []) + ([i - width] if i >= width else [])

    return _random_model(n_bodies, damping, zeta, seed, "nice", 2, links,
                         position=lambda i: [1.0 * (i % width), 1.0 * (i // width), 0.0],
                         masses=(5.0, 50.0), name=f"{width}-wide grid of {n_bodies} bodies ({damping} damping)")


def tree_model(n_bodies: int = 100, damping: str = "classical", zeta: float = 1e-3, seed: int = 0) -> Model:
    """A random tree of ``n_bodies`` bodies, like a vehicle's subframes, 6 n DOF.

    Body i > 0 hangs off a random earlier body by three mounts (fewer leave it free to rotate);
    body 0 and every third body also sit on ground (two mounts), and one body in ten has a cross
    link to another random earlier body. Its modes spread over five decades (0.1 Hz .. 10 kHz at
    100 bodies): light bodies hang stiffly off heavy ones.
    """
    rng = np.random.default_rng(seed + 7919)
    parent = [int(rng.integers(0, i)) if i else -1 for i in range(n_bodies)]
    cross = [int(rng.integers(0, i)) if i > 1 and rng.random() < 0.1 else -1 for i in range(n_bodies)]

    def links(i: int) -> list[int]:
        return ([parent[i]] * 3 if parent[i] >= 0 else []) + ([cross[i]] if cross[i] >= 0 else [])

    grounded = [i == 0 or i % 3 == 0 for i in range(n_bodies)]
    return _random_model(n_bodies, damping, zeta, seed, "nice", 2, links,
                         position=lambda i: [float(i % 17), float(i // 17), float(i % 5)],
                         masses=(1.0, 100.0), grounded=grounded,
                         name=f"random tree of {n_bodies} bodies ({damping} damping)")


def _random_model(n_bodies: int, damping: str, zeta: float, seed: int, scale: str, ground_mounts: int,
                  links: Any, position: Any, masses: tuple[float, float] | None, name: str,
                  grounded: list[bool] | None = None, edit: Any = None, w_ref: float | None = None) -> Model:
    rng = np.random.default_rng(seed)
    lo_m, hi_m, lo_k, hi_k = (1.0, 100.0, 1e4, 1e6) if scale == "nice" else (1e-3, 1e4, 1e2, 1e8)
    if masses is not None:
        lo_m, hi_m = masses
    bodies = []
    for i in range(n_bodies):
        m = float(np.exp(rng.uniform(np.log(lo_m), np.log(hi_m))))
        size = rng.uniform(0.2, 0.6, 3)
        moments = m / 12 * np.array([size[1]**2 + size[2]**2, size[0]**2 + size[2]**2,
                                     size[0]**2 + size[1]**2])
        axes = Rotation.random(random_state=rng.integers(1 << 31)).as_matrix()
        bodies.append(Body(f"b{i}", m, moments, cog=position(i), principal_axes=axes))
    mounts = []
    first: dict[int, np.ndarray] = {}

    def mount(name: str, body: int, to: str) -> Mount:
        k = np.exp(rng.uniform(np.log(lo_k), np.log(hi_k), 3))
        beta = 0.0 if damping == "none" else 1.0 if damping == "classical" else float(np.exp(rng.uniform(-1.5, 1.5)))
        at = rng.uniform(-0.4, 0.4, 3)            # the draws in this order: the older models unchanged
        orient = Rotation.random(random_state=rng.integers(1 << 31)).as_matrix()
        if edit is not None:
            k, orient = edit(body, to, k, orient, first.setdefault(body, orient))
        c = beta * k  # scaled below to the requested zeta
        return Mount(name, MountType(f"t_{name}", k, c), f"b{body}", at=at, to=to, orientation=orient)

    for i in range(n_bodies):
        if grounded is None or grounded[i]:
            for j in range(ground_mounts):
                mounts.append(mount(f"g{i}_{j}", i, "ground"))
        for k, j in enumerate(links(i)):
            mounts.append(mount("nstuvw"[k] + str(i), i, f"b{j}"))
    model = Model(bodies, mounts, name=name)
    if damping == "none":
        return model
    # scale all dampings so that the lowest elastic mode (or w_ref) gets roughly `zeta` (beta = 2 zeta / w1)
    w1 = lowest_elastic(model) if w_ref is None else w_ref
    beta_ref = 2 * zeta / w1
    scaled = [Mount(m.name, MountType(m.type.name, m.type.stiffness, m.type.damping * beta_ref),
                    m.body, at=m.at, to=m.to, orientation=m.orientation) for m in model.mounts]
    return model.replace(mounts=scaled)


def lowest_elastic(model: Model, count: int = 1) -> float:
    """The lowest nonzero undamped natural frequency of ``model`` [rad/s] (a mechanism's zero modes,
    one per slide, skipped): dense ``eigh`` up to 1,200 DOF, shift-invert ``eigsh`` above."""
    import scipy.linalg as sl
    import scipy.sparse.linalg as spl

    from vibss import assemble

    n = 6 * len(model.bodies)
    zeros = sum(1 for m in model.mounts if m.to != "ground" and not np.all(m.type.stiffness)) // 3
    k = min(n, zeros + count + (2 if zeros else 0))
    if n <= 1200:
        a = assemble(model, sparse=False)
        lam = sl.eigh(a.K, a.M, eigvals_only=True, subset_by_index=[0, k - 1])
    else:
        a = assemble(model, sparse=True)
        shift = -1e-8                      # [rad^2/s^2]: just below every eigenvalue (mechanisms: K singular)
        lam = np.sort(spl.eigsh(a.K.tocsc(), k=k, M=a.M.tocsc(), sigma=shift, which="LM", ncv=max(2 * k + 1, 20),
                                return_eigenvectors=False))
    return float(np.sqrt(np.sort(lam)[zeros]))
