"""Model builders of the reference and test cases (inputs written out here)."""

from __future__ import annotations

import numpy as np

from vibss import Body, Model, Mount, MountType, Orientation, symmetric


def prism_model() -> Model:
    """Reference case 1: rectangular prism on four springs."""
    t = MountType("spring", stiffness=[10_000.0, 20_000.0, 30_000.0])
    body = Body("prism", mass=1000.0, inertia=[10.0, 20.0, 30.0])
    return Model([body], symmetric(Mount("m", t, "prism", at=[1.0, 2.0, 0.0]), "double"), name="prism")


def two_mass_model() -> Model:
    """Reference case 2: two identical bodies in a chain."""
    t = MountType("A", stiffness=[12_000.0] * 3)
    bodies = [Body(f"body{i}", 1000.0, [10.0, 20.0, 30.0]) for i in (1, 2)]
    pts = [(1, 1, -1), (-1, 1, -1), (-1, -1, -1), (1, -1, -1)]
    mounts = [Mount(f"g{i}", t, "body1", at=p) for i, p in enumerate(pts)]
    mounts += [Mount(f"u{i}", t, "body2", at=p, to="body1") for i, p in enumerate(pts)]
    return Model(bodies, mounts, name="two mass")


def asymmetric_model(damped: bool = True) -> Model:
    """Two bodies, products of inertia, offset COGs, inclined mounts, non-proportional damping."""
    j2 = np.array([[12.0, -1.0, 0.5], [-1.0, 15.0, 0.2], [0.5, 0.2, 20.0]])
    b1 = Body("frame", 300.0, [20.0, 35.0, 40.0], cog=[0.1, -0.05, 0.4],
              principal_axes=Orientation.from_euler([15, -10, 5], degrees=True))
    b2 = Body("motor", [80.0, 80.0, 80.0], j2, cog=[0.3, 0.2, 0.9])
    c = (lambda k: np.asarray(k) * (2e-3 if damped else 0.0))
    ta = MountType("A", [2e5, 1.5e5, 4e5], c([1.0, 1.0, 1.0]) * 2e5)
    tb = MountType("B", [5e4, 8e4, 1.2e5], c([3.0, 0.5, 1.0]) * 1e5)
    mounts = [
        Mount("fl", ta, "frame", at=[0.6, 0.4, -0.3], orientation=Orientation.from_euler([0, 30, 0], degrees=True)),
        Mount("fr", ta, "frame", at=[0.6, -0.45, -0.3], orientation=Orientation.from_euler([0, -25, 10], degrees=True)),
        Mount("rl", tb, "frame", at=[-0.7, 0.5, -0.35]),
        Mount("rr", tb, "frame", at=[-0.65, -0.5, -0.3], orientation=Orientation.from_euler([45, 0, 0], degrees=True)),
        Mount("m1", tb, "motor", at=[0.2, 0.15, -0.2], to="frame", orientation=Orientation.from_euler([20, 10, 0], degrees=True)),
        Mount("m2", tb, "motor", at=[-0.25, 0.1, -0.2], to="frame"),
        Mount("m3", ta, "motor", at=[0.0, -0.2, -0.25], to="frame", orientation=Orientation.from_euler([0, 0, 35], degrees=True)),
    ]
    return Model([b1, b2], mounts, name="asymmetric")
