"""The badly scaled family: models on which "exact" must still mean exact.

Masses over 7 decades, stiff links beside soft mounts, mm-scale geometry, rigid modes beside
0.005 Hz suspension modes. Each builder returns a :class:`vibss.Model`; the extended-precision
answers come from :mod:`mp_reference`, which reads only the model's fields.
"""

from __future__ import annotations

import numpy as np

from vibss import Body, Model, Mount, MountType, Orientation


def graded_chain(damped: bool = False) -> Model:
    """Eight bodies of 1 g ... 10 t in a chain with offsets and inclined mounts, one ground mount.

    Stiffnesses range over 1e2 ... 1e9 N/m (ratio 1e7 and more); inertias follow m r^2 with r from
    5 mm to 0.5 m, so the rotational and translational blocks differ by up to 1e11.
    """
    bodies, mounts = [], []
    rng = np.random.default_rng(7)
    for i in range(8):
        m = 10.0 ** (i - 3)
        r = 0.005 * 10 ** (i / 3.5)
        bodies.append(Body(f"b{i}", m, m * r * r * np.array([1.0, 1.3, 1.7]),
                           cog=[0.02 * i, 0.01 * (-1) ** i, 0.03 * i],
                           principal_axes=Orientation.from_euler(rng.uniform(-30, 30, 3), degrees=True)))
    for i in range(8):
        k = 10.0 ** (2 + i) * np.array([1.0, 1.5, 2.5])
        c = 1e-3 * k * np.array([1.0, 3.0, 0.5]) if damped else np.zeros(3)
        t = MountType(f"t{i}", k, c)
        ori = Orientation.from_euler(rng.uniform(-40, 40, 3), degrees=True)
        for j, off in enumerate(([0.6, 0.4, -0.5], [-0.5, 0.3, -0.4], [0.1, -0.7, -0.6])):
            r = 0.005 * 10 ** (i / 3.5)
            at = np.asarray(off) * r
            to = "ground" if i == 0 else f"b{i - 1}"
            mounts.append(Mount(f"m{i}_{j}", t, f"b{i}", at=at, to=to, orientation=ori))
    return Model(bodies, mounts, name="graded_chain")


def hanging_chain() -> Model:
    """Bodies of 1 g, 10 t, 10 g, 1 t, 100 g; the 10 t one on one soft mount (10 N/m), the others
    linked by 1e6 N/m mounts at their COGs (rotations are free: rigid modes beside 0.005 Hz modes)."""
    masses = [1e-3, 1e4, 1e-2, 1e3, 1e-1]
    bodies = [Body(f"b{i}", m, [m * 0.01] * 3, cog=[0.0, 0.0, -float(i)]) for i, m in enumerate(masses)]
    soft = MountType("soft", [10.0, 10.0, 10.0])
    link = MountType("link", [1e6, 1e6, 1e6])
    mounts = [Mount("hang", soft, "b1")]
    for i in (0, 2, 3, 4):
        j = 1 if i == 0 else i - 1
        mounts.append(Mount(f"l{i}", link, f"b{i}", to=f"b{j}"))
    return Model(bodies, mounts, name="hanging_chain")


def stiff_links(k_link: float, damped: bool = False) -> Model:
    """Two 100 kg bodies on 1e4 N/m isolators joined by three link mounts of ``k_link`` [N/m].

    The links make a rigid joint as ``k_link`` grows: the six isolation modes tend to those of one
    200 kg body and barely change from 1e10 N/m on.
    """
    iso = MountType("iso", [1e4, 1e4, 1e4], [20.0, 30.0, 40.0] if damped else [0.0, 0.0, 0.0])
    link = MountType("link", [k_link] * 3)
    a = Body("a", 100.0, [2.0, 3.0, 4.0], cog=[0.0, 0.0, 0.0])
    b = Body("b", 100.0, [2.5, 3.5, 4.5], cog=[0.8, 0.1, 0.05])
    mounts = []
    for name, cog in (("a", a.cog), ("b", b.cog)):
        for j, off in enumerate(([0.3, 0.25, -0.2], [0.3, -0.25, -0.2], [-0.3, 0.25, -0.2], [-0.3, -0.25, -0.2])):
            mounts.append(Mount(f"{name}{j}", iso, name, at=off))
    for j, p in enumerate(([0.4, 0.0, 0.0], [0.4, 0.2, 0.1], [0.4, -0.1, 0.2])):
        mounts.append(Mount(f"link{j}", link, "b", at=p, to="a", frame="global"))
    return Model([a, b], mounts, name=f"stiff_links_{k_link:g}")


def instrument(damped: bool = True) -> Model:
    """A 50 g sensor on a 2 kg bracket on a 300 kg block, mm-scale offsets, non-proportional damping."""
    block = Body("block", 300.0, [12.0, 15.0, 20.0], cog=[0.0, 0.0, 0.25])
    bracket = Body("bracket", 2.0, [2e-3, 3e-3, 2.5e-3], cog=[0.102, 0.031, 0.512])
    sensor = Body("sensor", 0.05, [4e-6, 5e-6, 3e-6], cog=[0.107, 0.034, 0.526])
    f = 1.0 if damped else 0.0
    iso = MountType("iso", [2e5, 2e5, 3e5], f * np.array([300.0, 200.0, 800.0]))
    clamp = MountType("clamp", [5e7, 4e7, 8e7], f * np.array([50.0, 10.0, 20.0]))
    glue = MountType("glue", [2e8, 2e8, 5e8], f * np.array([1.0, 2.0, 0.5]))
    mounts = [Mount(f"iso{j}", iso, "block", at=p) for j, p in
              enumerate(([0.4, 0.3, -0.25], [0.4, -0.3, -0.25], [-0.4, 0.3, -0.25], [-0.4, -0.3, -0.25]))]
    mounts += [Mount(f"clamp{j}", clamp, "bracket", at=p, to="block") for j, p in
               enumerate(([0.012, 0.008, -0.009], [-0.011, 0.009, -0.009], [0.0, -0.010, -0.009]))]
    mounts += [Mount(f"glue{j}", glue, "sensor", at=p, to="bracket",
                     orientation=Orientation.from_euler([10.0 * j, 5.0, 0.0], degrees=True)) for j, p in
               enumerate(([0.004, 0.003, -0.003], [-0.004, 0.003, -0.003], [0.0, -0.004, -0.003]))]
    return Model([block, bracket, sensor], mounts, name="instrument")


FAMILY = {
    "graded_chain": graded_chain,
    "hanging_chain": hanging_chain,
    "stiff_links_1e10": lambda: stiff_links(1e10),
    "instrument": instrument,
}
"""The shared badly scaled cases, by name (each a zero-argument builder)."""
