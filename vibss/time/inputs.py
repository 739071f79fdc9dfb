"""What drives a simulation: the excitations and input signals as functions of time with their
breakpoints, the per-body initial conditions, and which inputs the exact modal path integrates
exactly (used by :func:`vibss.time.api.simulate` and the large-model path)."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any, cast

import numpy as np
import numpy.typing as npt

from .._validate import vector
from ..errors import ModelError
from ..linear.plant.plant import Plant
from ..model.model import DOF_NAMES, Model
from ..model.timefunctions import TimeFunction

SignalInput = Callable[[np.ndarray], np.ndarray] | npt.ArrayLike

__all__ = ["SignalInput", "initial_state", "exact_terms", "as_function", "summed"]


def _six(body: str, what: str, vec: Any) -> np.ndarray:
    """6 finite numbers (x y z rx ry rz) of one body's initial displacement or velocity."""
    return vector(vec, 6, what, who=f"simulate: initial[{body!r}]", strict=False,
                  what="6 finite numbers (x y z rx ry rz)")


def initial_state(plant: Plant, initial: Any, model: Model | None) -> tuple[np.ndarray, np.ndarray]:
    """Initial free-DOF displacement and velocity from per-body data.

    ``initial`` maps a body name to ``{"displacement": [6], "velocity": [6]}`` (either key may be
    left out: zero); anything else (a bare list, a number, an unknown body or key) is refused.
    """
    q0, v0 = np.zeros(plant.n), np.zeros(plant.n)
    if initial is None and model is not None:
        initial = (model.settings or {}).get("initial")
    if initial is None or (isinstance(initial, Mapping) and not initial):
        return q0, v0
    if not isinstance(initial, Mapping):
        raise ModelError(f"simulate: initial: expected {{body: {{'displacement': [6], 'velocity': "
                         f"[6]}}}}, got {initial!r}")
    index = {d: i for i, d in enumerate(plant.dofs)}
    bodies = set(model.body_names) if model is not None else {d.rsplit(".", 1)[0] for d in plant.dofs}
    for body, data in initial.items():
        if body not in bodies:
            raise ModelError(f"simulate: initial: unknown body {body!r}; bodies are {sorted(bodies)}")
        if not isinstance(data, Mapping):
            raise ModelError(f"simulate: initial[{body!r}]: expected {{'displacement': [6 numbers], "
                             f"'velocity': [6 numbers]}} (either key optional), got {data!r}")
        unknown = set(data) - {"displacement", "velocity"}
        if unknown:
            raise ModelError(f"simulate: initial[{body!r}]: unknown key(s) {sorted(map(str, unknown))}; "
                             "expected 'displacement' and/or 'velocity'")
        for target, what in ((q0, "displacement"), (v0, "velocity")):
            if data.get(what) is None:
                continue
            a = _six(body, what, data[what])
            for d, val in zip(DOF_NAMES, a):
                label = f"{body}.{d}"
                if label in index:
                    target[index[label]] = val
                elif val != 0.0:
                    raise ModelError(f"simulate: initial[{body!r}]: {what}: {label!r} is not a free "
                                     f"DOF (it is prescribed by an input)")
    return q0, v0


def exact_terms(fn: TimeFunction) -> bool:
    """Whether the exact modal path integrates ``fn`` exactly: piecewise linear, or linear once its
    sine/cosine pieces are removed (every term of a sum)."""
    from ..model.timefunctions import Sum, _linear

    if isinstance(fn, Sum):
        return all(exact_terms(f) for f in fn.terms)
    return _linear(fn) or bool(fn.sinusoids)


def as_function(value: Any, ts: np.ndarray, name: str) -> tuple[Callable[[np.ndarray], np.ndarray], tuple[float, ...]]:
    """An input given to :func:`~vibss.time.api.simulate` by name as ``(u(t), breakpoints)``: a time
    function, a callable, or samples at ``ts`` (interpolated linearly)."""
    if hasattr(value, "value") and hasattr(value, "breakpoints"):
        return value.value, tuple(value.breakpoints)
    if callable(value):
        return value, ()
    a = np.asarray(value, float)
    if a.shape != ts.shape or not np.all(np.isfinite(a)):
        raise ModelError(f"simulate: inputs[{name!r}]: expected a callable u(t) or {ts.size} finite "
                         f"samples (one per dt from 0 to t_end), got shape {a.shape}")
    return cast("Callable[[np.ndarray], np.ndarray]", lambda t, a=a: np.interp(t, ts, a)), ()


def summed(terms: list[tuple[Callable[[np.ndarray], np.ndarray], tuple[float, ...]]]) -> Callable[[np.ndarray], np.ndarray]:
    """One signal from its terms ``(u(t), breakpoints)``: their sum (zero for none)."""
    if not terms:
        return lambda t: np.zeros(np.shape(t))
    if len(terms) == 1:
        return terms[0][0]
    fns = [f for f, _ in terms]
    return cast("Callable[[np.ndarray], np.ndarray]", lambda t: sum(np.asarray(f(t), float) for f in fns))
