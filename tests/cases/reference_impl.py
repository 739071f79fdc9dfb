"""Independent (slow, loop-per-mount) implementations used as second computations in tests.

Written from the formulation with cross products and explicit loops, sharing no code with
vibss.assemble beyond reading the model's fields.
"""

from __future__ import annotations

import numpy as np

from vibss import GROUND, Model


def point_motion_matrix(r: np.ndarray) -> np.ndarray:
    """3x6 map from (u, theta) to u + theta x r, built column by column with np.cross."""
    out = np.zeros((3, 6))
    for j in range(3):
        e = np.zeros(3)
        e[j] = 1.0
        out[:, j] = e
        out[:, 3 + j] = np.cross(e, r)
    return out


def loop_assemble(model: Model, key: str = "stiffness") -> np.ndarray:
    """K (or C with key='damping') by summing B^T k B over mounts in a Python loop."""
    names = model.body_names
    n = 6 * len(names)
    out = np.zeros((n, n))
    for m in model.mounts:
        p = m.at + model.body(m.body).cog if m.frame == "body" else m.at
        t = m.orientation.matrix
        kp = t @ np.diag(getattr(m.type, key)) @ t.T
        b = np.zeros((3, n))
        i = names.index(m.body)
        b[:, 6 * i:6 * i + 6] += point_motion_matrix(p - model.body(m.body).cog)
        if m.to != GROUND:
            j = names.index(m.to)
            b[:, 6 * j:6 * j + 6] -= point_motion_matrix(p - model.body(m.to).cog)
        out += b.T @ kp @ b
    return out


def loop_mass(model: Model) -> np.ndarray:
    """Block-diagonal mass matrix, body by body."""
    n = 6 * len(model.bodies)
    out = np.zeros((n, n))
    for i, b in enumerate(model.bodies):
        out[6 * i:6 * i + 3, 6 * i:6 * i + 3] = np.diag(b.masses)
        out[6 * i + 3:6 * i + 6, 6 * i + 3:6 * i + 6] = b.tensor
    return out
