"""Shared helpers of :mod:`vibss.design`: the 6x6 matrices of one body on its mounts, axis names."""

from __future__ import annotations

from typing import Any

import numpy as np

from ..linear.eigen.small import symmetric_eigen
from .._validate import vector
from ..errors import AnalysisError, ArgumentError, VibssError, did_you_mean
from ..linear.plant.assemble import Assembly, assemble
from ..linear.eigen.directions import energy_fractions
from ..model.model import Model

__all__ = ["body_blocks", "unit_axis", "body_name", "AXES", "FRAMES", "frame_axes", "frame_rotation",
           "ke_fractions"]

AXES: dict[str, np.ndarray] = {"x": np.eye(3)[0], "y": np.eye(3)[1], "z": np.eye(3)[2]}
"""Global axes by name."""


def body_name(model: Model, body: str | None, who: str) -> str:
    """The body's name; ``None`` is the only body of a single-body model."""
    if body is None:
        if len(model.bodies) != 1:
            raise ArgumentError(f"{who}: body: the model has {len(model.bodies)} bodies "
                                f"{model.body_names}; name one", argument="body", received=None,
                                expected=model.body_names)
        return model.bodies[0].name
    if body not in model.body_names:
        raise ArgumentError(f"{who}: body: unknown body {body!r}; bodies are {model.body_names}"
                            + did_you_mean(body, model.body_names), argument="body", received=body,
                            expected=model.body_names)
    return body


def unit_axis(axis: Any, argument: str, who: str) -> np.ndarray:
    """``axis`` ("x", "y", "z" or 3 numbers, any length) as a unit vector in global axes [-]."""
    if isinstance(axis, str):
        if axis not in AXES:
            raise ArgumentError(f"{who}: {argument}: unknown axis {axis!r}; expected 'x', 'y', 'z' "
                                "or 3 numbers", argument=argument, received=axis, expected=list(AXES))
        return AXES[axis].copy()
    v = vector(axis, 3, argument, who=who)
    norm = float(np.linalg.norm(v))
    if norm == 0.0:
        raise ArgumentError(f"{who}: {argument}: the axis must not be zero, got {v.tolist()}",
                            argument=argument, received=axis, expected="a non-zero vector")
    return v / norm


def body_blocks(model: Model | Assembly, body: str | None, who: str) -> tuple[Assembly, int, np.ndarray, np.ndarray]:
    """Assembly, body index and the body's 6x6 mass and stiffness about its COG (others held fixed)."""
    a = model if isinstance(model, Assembly) else assemble(model)
    name = body_name(a.model, body, who)
    i = a.model.body_index(name)
    sl = slice(6 * i, 6 * i + 6)
    M = np.asarray(a.dense("M")[sl, sl])
    K = np.asarray(a.dense("K")[sl, sl])
    if np.linalg.matrix_rank(K, tol=1e-12 * max(np.abs(K).max(), 1e-300)) < 6:
        raise AnalysisError(f"{who}: the mounts of body {name!r} do not restrain all six rigid-body "
                            "motions (its 6x6 stiffness about the COG is singular); add mounts or "
                            "rates", argument="body", received=name)
    return a, i, M, K


FRAMES = ("global", "tra", "principal")
"""Named coordinate frames of the decoupling measures (or a 3x3 matrix of axes as columns)."""


def frame_axes(model: Model, body: str, frame: Any, axis: Any, who: str) -> np.ndarray:
    """(3, 3) axes (columns, global) of the frame in which the kinetic energy is split.

    ``"global"``: the global axes; ``"tra"``: axis 1 along the torque-roll axis of ``axis``, axis 2
    horizontal-ish (``z x tra``), axis 3 completing; ``"principal"``: principal axes of inertia;
    a (3, 3) rotation matrix: its columns.
    """
    if isinstance(frame, str):
        if frame not in FRAMES:
            raise ArgumentError(f"{who}: frame: unknown frame {frame!r}; expected one of {list(FRAMES)} "
                                "or a 3x3 rotation matrix" + did_you_mean(frame, FRAMES),
                                argument="frame", received=frame, expected=list(FRAMES))
        J = model.body(body).tensor
        if frame == "global":
            return np.eye(3)
        if frame == "principal":
            w, v = symmetric_eigen(J)
            v = v * np.sign(v[np.argmax(np.abs(v), axis=0), np.arange(3)])
            return v if np.linalg.det(v) > 0 else v * np.array([1.0, 1.0, -1.0])
        t = np.linalg.solve(J, unit_axis(axis, "axis", who))
        t /= np.linalg.norm(t)
        ref = np.eye(3)[2] if abs(t[2]) < 0.9 else np.eye(3)[0]
        y = np.cross(ref, t)
        y /= np.linalg.norm(y)
        return np.column_stack([t, y, np.cross(t, y)])
    from ..model.geometry import Orientation
    try:
        return Orientation.coerce(frame).matrix
    except VibssError as exc:            # a bad matrix: say which argument
        raise ArgumentError(f"{who}: frame: expected one of {list(FRAMES)} or a 3x3 rotation matrix, "
                            f"got {frame!r} ({exc})", argument="frame", received=frame) from None


def frame_rotation(n_dof: int, axes: np.ndarray) -> np.ndarray:
    """(n, n) block-diagonal ``R`` with ``q = R q'``: every body's translations and rotations in ``axes``."""
    return np.kron(np.eye(n_dof // 3), axes)


def ke_fractions(phi: np.ndarray, M: np.ndarray, R: np.ndarray | None = None) -> np.ndarray:
    """(..., k, n) kinetic-energy fractions of shapes ``phi`` (..., n, k) with the FULL mass matrix.

    ``E[i, j] = phi'_j (M' phi')_j / phi^T M phi`` in the frame coordinates ``q' = R^T q``
    (``M' = R^T M R``), rows summing to 1; products of inertia included.
    """
    if R is not None:
        phi = np.swapaxes(R, -1, -2) @ phi
        M = np.swapaxes(R, -1, -2) @ M @ R
    if phi.ndim == 2:
        return energy_fractions(phi, M)             # the one definition (vibss.linear.eigen.directions)
    mp = M @ phi                                      # a stack of variants: the same, batched
    num = np.swapaxes((phi.conj() * mp).real, -1, -2)
    return num / num.sum(axis=-1, keepdims=True)
