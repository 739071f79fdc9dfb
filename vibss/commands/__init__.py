"""Sub-commands of the ``vibss`` command line, one module each (see :mod:`vibss.cli`).

To add one: write ``vibss/commands/<name>.py`` with ``register(subparsers)`` and list it below.
"""

from __future__ import annotations

from . import control, design, example, frf, modes, orders, random, report, srs, static, study, time

COMMANDS = [modes, static, frf, time, orders, srs, random, design, study, control, report, example]
