"""Study-driven model reduction with measured error: model no more than a scene needs.

:func:`reduce` takes a model (or a :class:`~vibss.linear.plant.plant.Plant`) and a :class:`~vibss.reduction.scope.Scope`
(inputs, outputs, band, tolerance) and returns a :class:`Reduction`. Methods (by name):

``"prune"`` (exact)
    Removes the DOFs (bodies, decoupled directions of symmetric layouts) that no input excites or
    no output sees, from the coupling graph of M, C, K, H; then the modes whose input or output
    participation is zero to round-off. No error at all (zero initial conditions assumed for what
    is removed). :attr:`Reduction.plant` is a Plant in DOF coordinates (modal coordinates
    ``mode<k>`` when a mode was removed).
``"modal"``
    Pruning, then modal truncation with static (residual-flexibility) correction: every mode up to
    the band's top is kept, plus as many above as the tolerance needs; the rest enters
    quasi-statically as a direct feedthrough (``Pf`` for force inputs, ``Pz`` for motion inputs) on
    the **displacement-type outputs** (displacements, deflections and the spring part of mount and
    ground forces). Velocity and acceleration outputs are not corrected (their truncation error is
    in the estimate). :attr:`Reduction.plant` is a Plant in modal coordinates.
``"krylov"``
    Exact pruning of decoupled parts (sparse graph), then a second-order Galerkin projection on a
    rational block Krylov basis built from the inputs (and the outputs, when few) with sparse
    factorisations at real shifts spread over the band, grown greedily where exact sparse solves at
    check frequencies show an error above half the tolerance
    (:mod:`vibss.reduction.krylov`). Never forms a dense n x n matrix when given a Model.
    :attr:`Reduction.plant` is a Plant in Ritz coordinates ``krylov<k>`` (``M = I``, ``K`` diagonal);
    :attr:`Reduction.details` gives the shifts, moments, basis size, checks and timings.
``"auto"`` (default)
    ``"krylov"`` for models of more than :data:`KRYLOV_MIN_DOF` DOFs, else ``"modal"`` (see below).
``"balanced"``
    Pruning, then minimal realisation (``control.minreal``) and balanced truncation
    (``control.balred``) of the well-scaled modal state space (:func:`vibss.linear.statespace.statespace`),
    with the Hankel-singular-value bound ``||G - G_r||_inf <= 2 sum(discarded sigma)``. Needs
    slycot. Returns a **StateSpace** (:attr:`Reduction.system`), not a Plant
    (:attr:`Reduction.plant` is None): use it with python-control. For large models reduce with
    ``"modal"`` first and balance the result: ``reduce(r.plant, scope, "balanced")``.

Every reduced Plant runs unchanged through the analyses that take a Plant
(:func:`vibss.time.simulate`, frequency responses). Initial conditions given per body do not map
to modal coordinates. Accuracy is relative per output: ``max_w |H_red,ij - H_full,ij|`` divided by
the output's largest response ``max_j max_w |H_full,ij|`` to the scope's inputs over the band;
``verify=True`` measures it against the full model.

Examples
--------
>>> from vibss.reduction.scope import Scope
>>> r = reduce(prism_model(), Scope(["prism.fz"], ["prism.z"], 0.0, 10.0))   # doctest: +SKIP
>>> print(r.report())                                                     # doctest: +SKIP
"""

from __future__ import annotations

import dataclasses
import time
from typing import Any, cast

import numpy as np
import scipy.sparse as sp

from .._validate import choice
from ..errors import AnalysisError, ModelError
from ..methods import Check, decide
from ..model.model import Model
from ..linear.plant.plant import Plant
from .krylov import sparse_plant
from .prune import Removal
from .methods import (BALANCED_MAX_STATES, KRYLOV_MIN_DOF, METHODS, MODE_PRUNE_MAX, Reduced, ReduceOptions,
                      ReductionMethod, _states, choose, reduction_cost, resolve_method)
from .result import Reduction
from .scope import Scope
from ..linear.plant.build import build_plant

__all__ = ["reduce", "Reduction", "Removal", "Reduced", "ReduceOptions", "ReductionMethod", "METHODS",
           "BALANCED_MAX_STATES", "KRYLOV_MIN_DOF", "MODE_PRUNE_MAX", "select"]

def select(plant: Plant, scope: Scope) -> Plant:
    """The plant cut to the scope's inputs and outputs (names must be among the plant's)."""
    for what, names, have in (("inputs", scope.inputs, plant.inputs), ("outputs", scope.outputs, plant.outputs)):
        missing = [x for x in names if x not in have]
        if missing:
            raise ModelError(f"scope: {what}: {missing} not among the plant's {what} {list(have)}")
    return plant.select(list(scope.inputs), list(scope.outputs))


def reduce(model_or_plant: Model | Plant, scope: Scope, method: Any = "auto", *, verify: bool = False,
           max_modes: int | None = None, order: int | None = None, residual: str = "vectors",
           n_check: int = 400) -> Reduction:
    """Reduce a model to what ``scope`` needs, with the error estimated (and measured on request).

    Parameters
    ----------
    model_or_plant : Model or Plant
        The full system; a Model is turned into the scope's Plant by
        :func:`vibss.linear.plant.build.build_plant`; a Plant is cut to the scope's inputs and outputs.
    scope : Scope
        Inputs, outputs, band [Hz] and relative tolerance.
    method : {"auto", "prune", "modal", "balanced", "krylov"}, ReductionMethod or callable
        See the module docstring; a callable ``f(plant, scope, options) -> Reduced`` gets what the
        built-ins get (:mod:`vibss.reduction.methods`).
    verify : bool
        Measure the error against the full model over the band (an exact FRF of the full model).
    max_modes : int or None
        Upper limit on kept modes (``"modal"``), even if the tolerance is not met.
    order : int or None
        Number of states to keep (``"balanced"``); default: the smallest meeting the tolerance.
    residual : {"vectors", "static"}
        How ``"modal"`` accounts for the truncated modes: ``"vectors"`` (default) appends their
        static response shapes as extra DOFs; ``"static"`` adds their residual flexibility as a
        direct feedthrough (``Pf``, ``Pz``) on displacement-type outputs only (see the module
        docstring).
    n_check : int
        Verification frequencies over the band.

    Returns
    -------
    Reduction

    Raises
    ------
    ModelError
        Bad scope, model or method (the message names it).
    AnalysisError
        A method cannot apply (e.g. ``"balanced"`` without slycot, or on an unstable system).

    Examples
    --------
    >>> r = reduce(model, Scope(["b.fz"], ["b.z"], 0, 50, 1e-4), verify=True)   # doctest: +SKIP
    >>> r.plant.n, r.measured <= 1e-4                                            # doctest: +SKIP
    """
    if not isinstance(scope, Scope):
        raise ModelError(f"reduce: scope: expected a vibss.reduction.scope.Scope, got {scope!r}")
    chosen = resolve_method(method)
    if isinstance(model_or_plant, Plant):
        n = model_or_plant.n
    elif isinstance(model_or_plant, Model):
        n = 6 * len(model_or_plant.bodies)
    else:
        raise ModelError(f"reduce: model_or_plant: expected a Model or a Plant, got {model_or_plant!r}")
    sparse_input = isinstance(model_or_plant, Plant) and sp.issparse(model_or_plant.K)
    note = ""
    auto = chosen is None
    if chosen is None:                 # auto never keeps an answer past the scope: the exact pruning next
        name, note = choose(n, sparse_input)
        candidates = [METHODS[name]] + ([METHODS["prune"]] if name != "prune" and not sparse_input else [])
    else:
        candidates = [chosen]
    if sparse_input and not candidates[0].sparse:
        raise AnalysisError(f"reduce: method {candidates[0].name!r} needs a dense plant; a sparse plant "
                            "(build_plant(..., sparse=True)) takes method="
                            + " or ".join(repr(k) for k, v in METHODS.items() if v.sparse) + " or 'auto'")
    choice(residual, "residual", ("vectors", "static"), who="reduce")
    opts = ReduceOptions(max_modes=max_modes, order=order, residual=residual)
    scope_n = len(scope.sources) + len(scope.outputs)
    decision = decide(candidates, lambda m: _run(model_or_plant, scope, cast(ReductionMethod, m), opts, note),
                      where="reduce", auto=auto, check=lambda m, r: _check(cast(ReductionMethod, m), r, scope),
                      cost=lambda m: reduction_cost(cast(ReductionMethod, m), n, scope_n),
                      others=[m for m in METHODS.values() if m.sparse or not sparse_input])
    r = decision.answer
    said = "; ".join(x for x in (r.note, decision.note()) if x)
    if decision.check is not None and not decision.check.ok:
        said = f"{said}; missed the scope: estimated error {r.estimate:.3g} > {scope.tolerance:g}"
    r = dataclasses.replace(r, note=said)
    return r.verify(n_check) if verify else r


def _check(method: ReductionMethod, r: Reduction, scope: Scope) -> Check | None:
    """The reduction's own error estimate against the scope's tolerance (None for an exact method,
    whose claim is the exact solve's rounding, or a user's method without a claim)."""
    if method.claim is None or method.claim.exact:
        return None
    kind = r.estimate_kind.split(":")[0]
    return Check(float(r.estimate), scope.tolerance, f"the method's own estimate over the band ({kind})")


def _run(model_or_plant: Model | Plant, scope: Scope, chosen: ReductionMethod, opts: ReduceOptions,
         note: str) -> Reduction:
    """One method's reduction of the scope's plant, timed, as a :class:`Reduction`."""
    t0 = time.perf_counter()          # a sparse method counts its sparse assembly; the others start from the plant
    if isinstance(model_or_plant, Plant):
        full = select(model_or_plant, scope)
    elif chosen.sparse:
        full = sparse_plant(model_or_plant, list(scope.sources), list(scope.outputs))
    else:
        full = build_plant(model_or_plant, list(scope.sources), list(scope.outputs))
    if not chosen.sparse:
        t0 = time.perf_counter()
    out = chosen.kernel(full, scope, opts)
    if not isinstance(out, Reduced):
        raise AnalysisError(f"reduce: method {chosen.name!r} returned {type(out).__name__}, expected a "
                            "vibss.reduction.methods.Reduced")
    took = time.perf_counter() - t0
    plant, system = out.plant, out.system
    if plant is None and system is None:
        raise AnalysisError(f"reduce: method {chosen.name!r} returned neither a plant nor a system")
    return Reduction(method=chosen.name, scope=scope, plant=plant, system=system, full=full,
                  dofs_before=full.n, dofs_after=0 if plant is None else plant.n,
                  states_before=_states(full),
                  states_after=cast(Any, system).nstates if plant is None else _states(plant),
                  removed=tuple(out.removed), estimate=float(out.estimate),
                  estimate_kind=out.estimate_kind, correction=out.correction,
                  kept_hz=np.asarray(out.kept_hz, float), hsv=out.hsv, hsv_bound=out.hsv_bound,
                  io_scale=out.io_scale, reduce_s=took, notes=tuple(out.notes), details=dict(out.details),
                  note=note)
