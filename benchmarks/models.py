"""Benchmark models: random rigid bodies on rotated mounts in three topologies, as a user's model.

- ``chain_model(n_bodies, damping=...)`` joins every body to ground by two mounts and to its
  neighbour(s) by one or two mounts, all at random points with random orientations;
- ``grid_model(n_bodies, width=10, ...)``: a ``width``-wide grid (issue 17's independent benchmark):
  5-50 kg bodies with full inertia tensors, two ground mounts each, one mount to each +x and +y
  neighbour; no narrow band under any ordering;
- ``tree_model(n_bodies, ...)``: a random tree like a vehicle's subframes (each body hangs off a
  random earlier one by three mounts, a third of the bodies also on ground), plus a few cross links.
- ``topology_model(kind, n_bodies, ...)`` picks one by name (``TOPOLOGIES``).

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


def topology_model(kind: str, n_bodies: int = 100, damping: str = "classical", zeta: float = 1e-3,
                   seed: int = 0) -> Model:
    """``chain_model``, ``grid_model`` or ``tree_model`` by name (``kind`` in ``TOPOLOGIES``)."""
    if kind == "chain":
        return chain_model(n_bodies, damping, zeta, seed)
    if kind == "grid":
        return grid_model(n_bodies, damping=damping, zeta=zeta, seed=seed)
    if kind == "tree":
        return tree_model(n_bodies, damping=damping, zeta=zeta, seed=seed)
    raise ValueError(f"kind: {kind!r} is not one of {TOPOLOGIES}")


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
                  grounded: list[bool] | None = None) -> Model:
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
    beta_ref = None

    def mount(name: str, body: str, to: str) -> Mount:
        k = np.exp(rng.uniform(np.log(lo_k), np.log(hi_k), 3))
        if damping == "none":
            c = np.zeros(3)
        else:
            beta = 1.0 if damping == "classical" else float(np.exp(rng.uniform(-1.5, 1.5)))
            c = beta * k  # scaled below to the requested zeta
        at = rng.uniform(-0.4, 0.4, 3)
        orient = Rotation.random(random_state=rng.integers(1 << 31)).as_matrix()
        return Mount(name, MountType(f"t_{name}", k, c), body, at=at, to=to, orientation=orient)

    for i in range(n_bodies):
        if grounded is None or grounded[i]:
            for j in range(ground_mounts):
                mounts.append(mount(f"g{i}_{j}", f"b{i}", "ground"))
        for k, j in enumerate(links(i)):
            mounts.append(mount("nstu"[k] + str(i), f"b{i}", f"b{j}"))
    model = Model(bodies, mounts, name=name)
    if damping == "none":
        return model
    # scale all dampings so that the lowest elastic mode gets roughly `zeta` (beta = 2 zeta / w1)
    import scipy.linalg as sl

    from vibss import assemble

    a = assemble(model, sparse=False)
    w1 = float(np.sqrt(sl.eigh(a.K, a.M, eigvals_only=True, subset_by_index=[0, 0])[0]))
    beta_ref = 2 * zeta / w1
    scaled = [Mount(m.name, MountType(m.type.name, m.type.stiffness, m.type.damping * beta_ref),
                    m.body, at=m.at, to=m.to, orientation=m.orientation) for m in model.mounts]
    return model.replace(mounts=scaled)
