"""Small closed-form systems shared by the subject test files: a 10 kg single DOF on a 1e4 N/m,
20 N s/m mount (the same stiffness and damping in x, y and z) and an undamped-below, damped-above
two-body chain."""

from __future__ import annotations

import numpy as np

from cases.models import sdof as _sdof
from vibss import Body, Model, Mount, MountType

K, M, C = 1e4, 10.0, 20.0
WN = np.sqrt(K / M)


def sdof(c: float = C) -> Model:
    """One 10 kg body on one mount at its COG: w_n = sqrt(K / M) in x, y and z; rotations free."""
    return _sdof(M, K, c)


def chain() -> Model:
    """Body ``a`` (10 kg) on 1e4 N/m to ground, body ``b`` (2 kg) on 2e3 N/m, 3 N s/m to ``a``."""
    k1, k2 = 1e4, 2e3
    return Model([Body("a", 10.0, [1, 1, 1]), Body("b", 2.0, [1, 1, 1])],
                 [Mount("m1", MountType("t", [k1] * 3), "a"),
                  Mount("m2", MountType("t2", [k2] * 3, [3.0] * 3), "b", to="a")])
