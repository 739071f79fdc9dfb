"""Benchmark models: chains/grids of random rigid bodies on rotated mounts, as a user's large model.

``chain_model(n_bodies, damping=...)`` joins every body to ground by two mounts and to its
neighbour(s) by one or two mounts, all at random points with random orientations.

damping:
- ``"none"``: no viscous damping;
- ``"classical"``: every mount c = beta k with one beta (C = beta K, classically damped); beta is
  chosen so the lowest elastic mode has damping ratio ``zeta``;
- ``"general"``: a random beta per mount (non-proportional, complex modes).
"""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

from vibss import Body, Model, Mount, MountType


def chain_model(n_bodies: int = 100, damping: str = "classical", zeta: float = 1e-3,
                seed: int = 0, scale: str = "nice", ground_mounts: int = 2) -> Model:
    """Random chain of ``n_bodies`` rigid bodies (6 n DOF) on mounts to ground and neighbours.

    ``scale="nice"``: 1-100 kg, 1e4-1e6 N/m; ``"bad"``: 1e-3-1e4 kg, 1e2-1e8 N/m.
    """
    rng = np.random.default_rng(seed)
    lo_m, hi_m, lo_k, hi_k = (1.0, 100.0, 1e4, 1e6) if scale == "nice" else (1e-3, 1e4, 1e2, 1e8)
    bodies = []
    for i in range(n_bodies):
        m = float(np.exp(rng.uniform(np.log(lo_m), np.log(hi_m))))
        size = rng.uniform(0.2, 0.6, 3)
        moments = m / 12 * np.array([size[1]**2 + size[2]**2, size[0]**2 + size[2]**2,
                                     size[0]**2 + size[1]**2])
        axes = Rotation.random(random_state=rng.integers(1 << 31)).as_matrix()
        bodies.append(Body(f"b{i}", m, moments, cog=[1.0 * i, 0.0, 0.0], principal_axes=axes))
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
        for j in range(ground_mounts):
            mounts.append(mount(f"g{i}_{j}", f"b{i}", "ground"))
        if i > 0:
            mounts.append(mount(f"n{i}", f"b{i}", f"b{i-1}"))
        if i > 1 and i % 3 == 0:
            mounts.append(mount(f"s{i}", f"b{i}", f"b{i-2}"))
    model = Model(bodies, mounts, name=f"chain of {n_bodies} bodies ({damping} damping)")
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
