"""Shared helpers of :mod:`vibss.design`: the 6x6 matrices of one body on its mounts, axis names."""

from __future__ import annotations

from typing import Any

import numpy as np

from .._validate import vector
from ..errors import AnalysisError, ArgumentError, did_you_mean
from ..linear.assemble import Assembly, assemble
from ..model.model import Model

__all__ = ["body_blocks", "unit_axis", "body_name", "AXES"]

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
