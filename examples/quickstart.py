"""Quick start: a machine on four rubber mounts, built in Python.

Run it with ``python examples/quickstart.py`` (add a folder name to also write the HTML report,
e.g. ``python examples/quickstart.py quickstart-report``). The numbers it prints are pinned by
``tests/project/test_examples.py`` against their closed forms:

- the mounts lie in the plane of the centre of gravity and along the principal axes, so the six
  modes uncouple: f = sqrt(k_total / m) / 2 pi for translations, sqrt(sum k r^2 / I) / 2 pi for
  rotations;
- under its own weight the machine sags m g / (4 k_z).
"""

from __future__ import annotations

import sys

import vibss

MASS = 500.0                       # kg
INERTIA = (40.0, 60.0, 80.0)       # kg m^2, principal moments about the COG (axes = global axes)
STIFFNESS = (2.0e5, 3.0e5, 5.0e5)  # N/m along the mount's local axes 1, 2, 3 (= x, y, z here)
DAMPING = (400.0, 400.0, 1000.0)   # N s/m
CORNER = (0.6, 0.4, 0.0)           # m, one mount relative to the COG; symmetry gives the others


def build_model() -> vibss.Model:
    """The machine: one body, four mounts (one given, three mirrored), gravity along -z."""
    machine = vibss.Body("machine", mass=MASS, inertia=INERTIA, cog=(0.0, 0.0, 0.5))
    rubber = vibss.MountType("rubber", stiffness=STIFFNESS, damping=DAMPING)
    corner = vibss.Mount("corner", rubber, body="machine", at=CORNER)
    sensor = vibss.ControlPoint("sensor", body="machine", at=(0.6, 0.0, 0.3))
    return vibss.Model([machine], vibss.symmetric(corner, "double"), control_points=[sensor],
                       gravity=(0.0, 0.0, -9.81), name="machine on four mounts")


def main(out: str | None = None) -> tuple[vibss.Modes, vibss.StaticResult]:
    """Print the modes and the static sag; write the HTML report into ``out`` if given."""
    model = build_model()
    modes = vibss.modes(model)
    print(modes.report())
    sag = vibss.static(model)
    print(sag.report())
    if out:
        from vibss.report import study, write_report

        print("report:", write_report(study(model), out))
    return modes, sag


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else None)
