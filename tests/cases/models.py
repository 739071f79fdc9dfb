"""Model builders of the reference and test cases (inputs written out here), and the parametrised
builders the subject test files share (``sdof``, ``box``, ``two_body``, ``powertrain``): each test
file calls them with its own numbers."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

import vibss
from vibss import Body, ControlPoint, Model, Mount, MountType, Orientation, symmetric


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


def sdof(mass: float, stiffness: Any = None, damping: Any = None, *, mount_type: MountType | None = None,
         inertia: Any = (1.0, 1.0, 1.0), body: str = "b", mount: str = "m", type_name: str = "t",
         **model: Any) -> Model:
    """One body on one mount at its COG: x, y and z are single-DOF isolators, the rotations are free.

    Parameters
    ----------
    mass : float
        The body's mass [kg].
    stiffness, damping : float or (3,) array_like
        The mount's stiffness [N/m] and damping [N s/m]; a scalar is the same in x, y and z
        (``damping=None`` leaves it to ``MountType``'s default). Ignored when ``mount_type`` is given.
    mount_type : MountType, optional
        The mount's type, when it is more than a spring and a dashpot (a rheology, a loss factor).
    inertia : (3,) array_like
        Principal moments of inertia [kg m^2].
    body, mount, type_name : str
        The names of the body, the mount and its type.
    **model
        Passed to ``Model`` (``name``, ``gravity``, ``actuators``, ``sensors``, ...).
    """
    if mount_type is None:
        k = [stiffness] * 3 if np.ndim(stiffness) == 0 else stiffness
        c = [damping] * 3 if damping is not None and np.ndim(damping) == 0 else damping
        mount_type = MountType(type_name, k) if c is None else MountType(type_name, k, c)
    return Model([Body(body, mass, inertia)], [Mount(mount, mount_type, body)], **model)


def box(mass: float, inertia: Any, stiffness: Any, damping: Any = None, *, at: Any,
        cog: Any = None, loss_factor: float | None = None, body: str = "b", mount: str = "m",
        type_name: str = "t", **model: Any) -> Model:
    """One body on four mounts of one type.

    Parameters
    ----------
    mass : float
        The body's mass [kg].
    inertia : (3,) array_like
        Principal moments of inertia [kg m^2].
    stiffness, damping : float or (3,) array_like
        The mounts' stiffness [N/m] and damping [N s/m]; a scalar is the same in x, y and z
        (``damping=None`` leaves it to ``MountType``'s default).
    at : (3,) array_like or sequence of (3,) array_like
        One point [m]: the mount there and its mirror images (``symmetric``, double symmetry,
        names ``m``, ``m.xz``, ...). A list of points: one mount at each, named ``m0``, ``m1``, ...
    cog : (3,) array_like, optional
        The body's centre of gravity [m] (``Body``'s default when None).
    loss_factor : float, optional
        The mounts' loss factor [-] (``MountType``'s default when None).
    body, mount, type_name : str
        The names of the body, the mounts and their type.
    **model
        Passed to ``Model`` (``name``, ``gravity``, ``excitations``, ``settings``, ...).
    """
    k = [stiffness] * 3 if np.ndim(stiffness) == 0 else stiffness
    c = [damping] * 3 if damping is not None and np.ndim(damping) == 0 else damping
    extra: dict[str, Any] = {} if loss_factor is None else {"loss_factor": loss_factor}
    t = MountType(type_name, k, **extra) if c is None else MountType(type_name, k, c, **extra)
    b = Body(body, mass, inertia) if cog is None else Body(body, mass, inertia, cog=cog)
    if np.ndim(at) == 1:
        mounts: Sequence[Mount] = symmetric(Mount(mount, t, body, at=at))
    else:
        mounts = [Mount(f"{mount}{i}", t, body, at=p) for i, p in enumerate(at)]
    return Model([b], mounts, **model)


def two_body() -> Model:
    """A frame (300 kg, products of inertia) on four ground mounts, two of them tilted, and an
    engine (120 kg, rotated principal axes) on three mounts to the frame; a control point on the
    engine. Stiffness and damping differ per direction (non-proportional damping)."""
    t1 = MountType("soft", [2e4, 3e4, 5e4], [40.0, 10.0, 80.0])
    t2 = MountType("stiff", [8e4, 6e4, 9e4], [5.0, 60.0, 20.0])
    inertia = [[12.0, -1.5, 0.8], [-1.5, 20.0, 0.6], [0.8, 0.6, 25.0]]
    b1 = Body("frame", 300.0, inertia, cog=[0.1, -0.05, 0.3])
    b2 = Body("engine", 120.0, [3.0, 5.0, 6.0], cog=[0.4, 0.2, 0.9],
              principal_axes=Orientation.from_euler([20, 10, -5], degrees=True))
    tilt = Orientation.from_euler([30, 15, 0], degrees=True)
    mounts = [Mount("g1", t1, "frame", at=[0.8, 0.6, -0.3], orientation=tilt),
              Mount("g2", t1, "frame", at=[-0.7, 0.5, -0.2]),
              Mount("g3", t1, "frame", at=[0.6, -0.6, -0.35], orientation=Orientation.from_euler([-40, 0, 20], degrees=True)),
              Mount("g4", t1, "frame", at=[-0.5, -0.7, -0.3]),
              Mount("e1", t2, "engine", at=[0.3, 0.3, -0.2], to="frame", orientation=tilt),
              Mount("e2", t2, "engine", at=[-0.3, 0.25, -0.25], to="frame"),
              Mount("e3", t2, "engine", at=[0.0, -0.3, -0.2], to="frame",
                    orientation=Orientation.from_euler([0, 45, 0], degrees=True))]
    cps = [ControlPoint("sensor", "engine", [0.2, 0.1, 0.3])]
    return Model([b1, b2], mounts, cps, name="two body")


def powertrain() -> Model:
    """The bundled powertrain example (``vibss.load_example("powertrain")``)."""
    return vibss.load_example("powertrain")
