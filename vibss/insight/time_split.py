"""Which modes make a time response's peak: :func:`time_contributions` (issue 31).

The time response :func:`vibss.simulate` gives (its exact ``"modal"`` method: each mode's own exact
first-order-hold recursion, :mod:`vibss.time.kernels.modal`) split into the response of each
mode and a residual:

- classical damping: one term per undamped mode, ``y_r(t) = O phi_r eta_r(t)`` with ``eta_r`` the
  mode's exact response to ``phi_r^T f(t)``;
- non-proportional damping: the complex modes of the coupled modes, each pole (with its conjugate)
  given to the undamped mode that dominates its shape, as :func:`vibss.modal_contributions` does;
- the residual: the direct terms (the outputs' feedthrough: prescribed motions seen by absolute
  outputs, forces seen by accelerations) and the modes left out by ``n_modes``.

The terms come from the same recursion as the total: each mode is given output rows of its own
(:func:`vibss.time.kernels.modal.modal_outputs`), so the split costs ``(n_modes + 1)`` times the
outputs' part of one run. The check: the terms plus the residual summed against simulate's own modal
response of the same job, relative to each output's peak (:data:`TIME_MODAL`).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from .._validate import integer
from ..errors import AnalysisError, ArgumentError
from ..linear.eigen.basis import modal_basis
from ..linear.plant.plant import Plant
from ..methods import Check, Claim
from ..model.model import Model
from ..nonlinear.kernels import nonlinear_mounts
from ..time.api import simulate
from ..time.inputs import SignalInput
from ..time.kernels import direct_terms, make_grid, prepare
from ..time.kernels.modal import _ModalSet, _remembered_modal_sets, modal_outputs, run_modal
from ..time.methods import METHODS, SimulationJob, TimeMethod
from .time_result import TimeContributions

__all__ = ["time_contributions", "TIME_MODAL", "MAX_VALUES"]

TIME_MODAL = Claim(1e-9, exact=True, conditions="the terms and the residual summed against simulate's exact modal "
                   "response of the same job, relative to each output's peak (inputs piecewise linear, or sine "
                   "and cosine pieces, between their breakpoints)")
"""What :func:`time_contributions` claims, and how it checks it."""

MAX_VALUES = 50_000_000
"""Most values (terms x outputs x samples) :func:`time_contributions` holds (400 MB): more is refused,
naming ``n_modes``."""


def _per_mode(ms: _ModalSet, slot: np.ndarray, slots: int) -> np.ndarray:
    """(slots p, nb, b) ``Y`` with the rows of each block moved to its mode's slot (``slot[mode]``)."""
    if ms.mode is None:
        raise AnalysisError("time_contributions: a modal set has blocks that belong to no mode (Maxwell branch "
                            "states)")
    p, nb, b = ms.Y.shape
    y = np.zeros((slots, p, nb, b), ms.Y.dtype)
    y[slot[ms.mode], :, np.arange(nb), :] = np.moveaxis(ms.Y, 1, 0)
    return y.reshape(slots * p, nb, b)


def _split_kernel(n_modes: int | None, store: dict[str, Any]) -> TimeMethod:
    """A simulate method that returns the modal response of the job (as ``"modal"``) and keeps, in
    ``store``, its split into the lowest ``keep`` modes' terms, the other modes' and the direct terms."""

    def kernel(job: SimulationJob) -> tuple[np.ndarray, str]:
        dt = job.time[1] - job.time[0]
        grid = make_grid(len(job.time), dt, job.breakpoints)
        kin = job.sampled(grid)
        prep = prepare(job.plant)
        sets, how = _remembered_modal_sets(prep, job.q0, job.v0, float(grid.t[-1]))
        basis = modal_basis(job.plant)
        k = basis.phi.shape[1]
        keep = k if n_modes is None else min(n_modes, k)
        slot = np.minimum(np.arange(k), keep)               # mode r >= keep: the "left out" slot
        split = [dataclasses.replace(ms, Y=_per_mode(ms, slot, keep + 1)) for ms in sets]
        p = len(job.plant.outputs)
        parts = modal_outputs(prep, grid, kin, grid.samples, split, (keep + 1) * p)
        store["terms"] = parts.reshape(-1, keep + 1, p).transpose(1, 2, 0)     # (keep + 1, p, ns)
        store["direct"] = direct_terms(prep, kin, grid.samples).T                # (p, ns)
        y, _ = run_modal(prep, grid, kin, grid.samples, job.q0, job.v0, (sets, how))
        store.update(how=how, modes=k, omega=np.asarray(basis.omega), coupled="non-proportional" in how)
        return y, f"exact modal FOH ({how}), each mode's outputs apart"

    def check(job: SimulationJob, y: np.ndarray) -> Check:
        total = store["terms"].sum(axis=0) + store["direct"]
        peak = np.abs(y).max(axis=0)
        scale = np.where(peak > 0, peak, 1.0)
        err = float((np.abs(total.T - y) / scale).max(initial=0.0))
        return Check(err, TIME_MODAL.tolerance, "terms + residual against simulate's modal response, per output peak")

    modal = METHODS["modal"]
    return TimeMethod("modal contributions", kernel, exact=True, hits_edges=True, internal_states=True,
                      claim=TIME_MODAL, checker=check, coster=modal.coster,
                      summary="exact modal superposition, each mode's outputs kept apart")


def time_contributions(model: Model | Plant, excitations: Sequence[Any] | None = None, *,
                       inputs: Mapping[str, SignalInput] | None = None, outputs: Sequence[str] | None = None,
                       t_end: float, dt: float, record_from: float = 0.0, initial: Any = None,
                       n_modes: int | None = None, hysteresis: str = "drop") -> TimeContributions:
    """A time response split into the responses of its modes and a residual: which modes make its peaks.

    Takes :func:`vibss.simulate`'s arguments and gives its response (``.response``, by the exact
    ``"modal"`` method) with each mode's part: classical damping, one term per undamped mode (its
    exact response to ``phi_r^T f(t)``); otherwise each complex mode pair given to the undamped mode
    that dominates its shape. The residual holds the direct terms (outputs that see an input
    directly: absolute motion under a prescribed ground motion, acceleration under a force) and the
    modes left out by ``n_modes``. Terms and residual sum to the response (checked to 1e-9 of each
    output's peak).

    Parameters
    ----------
    model : Model or Plant
        A linear system (no stops or curves, no frequency-dependent mounts).
    excitations : sequence of Excitation or None
        As :func:`vibss.simulate` (default: the model's time-domain excitations).
    inputs : mapping of str to callable or (ns,) array_like, or None
        More input signals by name, as :func:`vibss.simulate`.
    outputs : sequence of str or None
        Output signal names (default: every body DOF's displacement).
    t_end : float
        End time [s].
    dt : float
        Sample interval [s].
    record_from : float
        First recorded time [s].
    initial : mapping or None
        Initial conditions, as :func:`vibss.simulate`.
    n_modes : int or None
        Keep the terms of the lowest ``n_modes`` modes apart (default all); the others go into the
        residual.
    hysteresis : {"drop", "causal"}
        Loss factors, as :func:`vibss.simulate` (``"causal"``: the Maxwell ladder's branch states
        belong to no mode, refused).

    Returns
    -------
    TimeContributions
        ``terms`` (modes, outputs, samples), ``residual``, ``response``; ``dominant()`` at each
        output's peak, ``plot()``.

    Raises
    ------
    AnalysisError
        A model with nonlinear or frequency-dependent mounts.
    ArgumentError
        A bad ``n_modes``, or more than :data:`MAX_VALUES` values to hold.

    Examples
    --------
    >>> from vibss import Body, Model, Mount, MountType
    >>> from vibss.model.excitation import Excitation, Step
    >>> t = MountType("t", [800.0] * 3, damping=[4.0] * 3)
    >>> m = Model([Body("b", 2.0, [1, 1, 1])], [Mount("m", t, "b")])
    >>> c = time_contributions(m, [Excitation("s", "force", "b", Step(10.0), dof="z")], outputs=["b.z"],
    ...                        t_end=0.5, dt=1e-3)
    >>> k = int(abs(c.terms[:, 0, c.peak_index(0)]).argmax())       # the z mode makes the z peak
    >>> float(c.mode_frequency_hz[k].round(3))
    3.183
    """
    _refuse(model, hysteresis)
    keep = None if n_modes is None else integer(n_modes, "n_modes", who="time_contributions", minimum=0)
    n = 6 * len(model.bodies) if isinstance(model, Model) else int(np.shape(model.M)[0])
    p = len(outputs) if outputs is not None else (n if isinstance(model, Model) else len(model.outputs))
    size = (min(n, n if keep is None else keep) + 1) * p * (int(round(float(t_end) / float(dt))) + 1)
    if size > MAX_VALUES:
        raise ArgumentError(f"time_contributions: n_modes: {size:.3g} values (terms x outputs x samples) to hold, "
                            f"more than {MAX_VALUES:.3g}: keep fewer modes apart (n_modes), outputs or samples",
                            argument="n_modes", received=n_modes, expected=f"at most {MAX_VALUES} values")
    store: dict[str, Any] = {}
    resp = simulate(model, excitations, inputs=inputs, outputs=outputs, t_end=t_end, dt=dt,
                    record_from=record_from, initial=initial, method=_split_kernel(keep, store),
                    hysteresis=hysteresis)
    ns = resp.time.size
    terms, direct = store["terms"][:, :, -ns:], store["direct"][:, -ns:]
    k = terms.shape[0] - 1
    notes = []
    if k < store["modes"]:
        notes.append(f"the {store['modes'] - k} modes above the lowest {k} in the residual")
    notes.append(resp.note)
    return TimeContributions(time=resp.time, terms=terms[:k], residual=terms[k] + direct,
                             mode_frequency_hz=store["omega"][:k] / (2 * np.pi), output_names=resp.output_names,
                             output_units=resp.units, response=resp,
                             method="complex" if store["coupled"] else "modal", note="; ".join(n for n in notes if n))


def _refuse(model: Model | Plant, hysteresis: str) -> None:
    """Refuse what has no modal split: nonlinear mounts and Maxwell branch states."""
    if isinstance(model, Model) and nonlinear_mounts(model):
        raise AnalysisError("time_contributions: the model has nonlinear mounts (stops or curves): a nonlinear "
                            "response has no modal split (simulate it, or split the tangent model's response)")
    branched = (model.branches is not None) if isinstance(model, Plant) else (
        hysteresis == "causal" or any(t.has_branches for t in model.mount_types.values()))
    if branched:
        raise AnalysisError("time_contributions: the model has frequency-dependent mounts (or hysteresis='causal'): "
                            "their Maxwell branch states belong to no mode (use simulate)")
