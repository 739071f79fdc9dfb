"""Frequency response: FRFs of named outputs to named inputs (transmissibility and swept-sine
steady states build on it in :mod:`vibss.frequency.sweep`).

``frequency_response`` evaluates ``Y(i w) / U`` of a :class:`~vibss.linear.plant.plant.Plant` for named inputs and
outputs with a kernel from :data:`vibss.frequency.kernels.METHODS` (``"auto"`` picks one and records why).
Conventions:

- frequencies are given and reported in Hz (``omega`` in rad/s is kept too);
- ``quantity`` multiplies every output by ``(i w)^k``: receptance (k = 0, the outputs as named),
  mobility (k = 1, their time derivative) or accelerance (k = 2);
- a motion input ``u`` of order 1 or 2 (velocity, acceleration) prescribes ``z = u / (i w)^order``;
- hysteretic damping (mount loss factors, ``K + i H``) acts in the frequency domain only;
- at exactly 0 Hz the response is the limit ``w -> 0+``, computed exactly from the Laurent series
  (:func:`vibss.frequency.kernels.zero_frequency_limit`): finite where the limit exists (e.g. the static
  deflection, a velocity ratio, a mass line), ``inf`` where it diverges (displacement under a
  constant velocity or acceleration, receptance of an unrestrained rigid-body motion). Never NaN.

Examples
--------
>>> from vibss import Body, Model, Mount, MountType
>>> m = Model([Body("b", 10.0, [1, 1, 1])], [Mount("m", MountType("t", [1e4] * 3, [20.0] * 3), "b")])
>>> r = frequency_response(m, ["b.fz"], ["b.z"], frequencies=[0.0, 1.0])
>>> print(f"{abs(r.response[0, 0, 0]):.6g} m/N by {r.method}")   # 1 / k at 0 Hz
0.0001 m/N by direct
"""

from __future__ import annotations

import warnings
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np
import scipy.sparse as sp

from ..linear.plant.assemble import Assembly
from .._validate import choice
from ..errors import AnalysisError, DefectiveModesError, ModelError, VibssWarning
from .contracts import settle
from .kernels import METHODS, zero_frequency_limit
from ..linear.plant.branches import require_none
from .methods import FrequencyMethod, applies, candidates, choose, choose_without_modes, resolve_method, stays_sparse
from ..methods import LARGE_DOFS
from ..model.model import Model
from ..linear.plant.plant import Plant
from ..linear.plant.build import build_plant
from ..linear.eigen.directions import dof_labels, energy_fractions
from ..linear.eigen.basis import ModalBasis, modal_basis
from .grid import FrequencyGrid, frequency_grid
from .result import FrequencyResponse

__all__ = ["frequency_response", "QUANTITIES"]

QUANTITIES = {"receptance": 0, "mobility": 1, "accelerance": 2}
"""Output time-derivative order of each FRF quantity."""


def _as_plant(system: Model | Assembly | Plant, inputs: Any, outputs: Any) -> Plant:
    if isinstance(system, Plant):
        if inputs is not None or outputs is not None:
            raise ModelError("inputs/outputs: a Plant already fixes its signals; pass a Model to choose them")
        return system
    if inputs is None:
        raise ModelError("inputs: name at least one input signal, e.g. 'engine.fz' or 'ground.z.acc'")
    return build_plant(system, inputs, outputs)


def _frequencies(plant: Plant, frequencies: Any, basis: ModalBasis | None) -> np.ndarray:
    if frequencies is None or isinstance(frequencies, (Mapping, FrequencyGrid)):
        return frequency_grid(plant, frequencies, basis)
    try:
        f = np.atleast_1d(np.asarray(frequencies, dtype=float))
    except (TypeError, ValueError):
        f = np.array([np.nan])
    # min and max say it all: NaN or inf anywhere makes one of them non-finite
    lo, hi = (float(f.min()), float(f.max())) if f.ndim == 1 and f.size else (0.0, 0.0)
    if f.ndim != 1 or not (np.isfinite(lo) and np.isfinite(hi) and lo >= 0):
        raise ModelError(f"frequencies: expected finite frequencies >= 0 [Hz], got {frequencies!r}")
    if f.size == 0:
        raise ModelError("frequencies: got an empty list; give at least one frequency [Hz], a grid "
                         "mapping {f1, f2, points} or None")
    return f


_NO_MODES = ("no undamped modes computed (the method needs none, and those of the static stiffness are not a "
             "frequency-dependent model's resonances)")


def _modes_if_needed(plant: Plant, frequencies: Any,
                     chosen: Any) -> tuple[ModalBasis | None, np.ndarray, tuple[str, str] | None]:
    """The undamped modes (or None), the frequencies [Hz] and ``auto``'s choice if it needed no modes.

    A dense plant's modes are computed for the default grid, for the resonance marks and for the
    methods that superpose them. A plant with frequency-dependent mounts asked for explicit
    frequencies skips them when a built-in method needs none (given, or chosen from sizes and
    structure by :func:`vibss.frequency.methods.choose_without_modes`; a user's kernel still gets
    them, and so does 0 Hz): its static-stiffness modes do not mark its resonances, and at 600 DOFs
    they cost a tenth of the banded exact solve.
    """
    if plant.branches is None or frequencies is None or isinstance(frequencies, (Mapping, FrequencyGrid)):
        basis = modal_basis(plant)
        return basis, _frequencies(plant, frequencies, basis), None
    f = _frequencies(plant, frequencies, None)
    pick = choose_without_modes(plant, f.size) if chosen is None else None
    method = chosen if pick is None else METHODS[pick[0]]
    builtin = method is not None and METHODS.get(method.name) is method      # a user's method gets the modes
    if not builtin or getattr(method, "needs_basis", True) or not np.all(f > 0):
        return modal_basis(plant), f, pick
    return None, f, pick


def _fresh(raw: Any, chosen: Any, shape: tuple[int, ...]) -> bool:
    """Whether a kernel's answer can be the result's array itself: a built-in kernel's new, writeable
    complex array of the result's shape (a user's kernel may keep its array, so that is copied)."""
    return (chosen is METHODS.get(chosen.name) and isinstance(raw, np.ndarray) and raw.dtype == complex
            and raw.shape == shape and raw.flags.writeable)


def _times_power(raw: np.ndarray, s: np.ndarray, k: int) -> np.ndarray:
    """Mobility / accelerance: ``raw * s^k``, keeping inf as inf."""
    if not k:
        return raw
    with np.errstate(invalid="ignore"):
        scaled = raw * s**k
    scaled[np.isinf(raw)] = np.inf
    return scaled


def _units(plant: Plant, quantity: str) -> tuple[str, ...]:
    """Units of the outputs' quantity: the output unit times ``s^-k`` (mobility k = 1, accelerance 2)."""
    from ..model.units import times_s

    return plant.cached(f"units of the {quantity}",
                        lambda: tuple(times_s(u, QUANTITIES[quantity]) for u in plant.units))


def _input_units(plant: Plant) -> tuple[str, ...]:
    from ..model.units import input_unit

    return plant.cached("input units", lambda: tuple(input_unit(u, k) for u, k in zip(plant.inputs, plant.kinds)))


def frequency_response(system: Model | Assembly | Plant, inputs: Sequence[Any] | None = None,
                       outputs: Sequence[str] | None = None, frequencies: Any = None,
                       quantity: str = "receptance",
                       method: str | Callable[..., np.ndarray] = "auto", *,
                       foundation: Any = None) -> FrequencyResponse:
    """Frequency response functions of named outputs to named inputs.

    Parameters
    ----------
    system : Model, Assembly or Plant
        The system; a Plant fixes the signals itself.
    inputs : sequence of str or Excitation
        Input signals (see :mod:`vibss.signals`).
    outputs : sequence of str or None
        Output signals; default every body DOF's displacement.
    frequencies : (nf,) array_like [Hz], FrequencyGrid, mapping or None
        Explicit frequencies, or a grid spec (default: refined log grid around the modes).
    quantity : {"receptance", "mobility", "accelerance"}
        Multiply the outputs by ``(i w)^0, ^1, ^2``.
    method : {"auto", "direct", "modal", "complex_modal", "woodbury", "sparse", "subspace", "statespace"}, FrequencyMethod or callable
        Method (:data:`vibss.frequency.kernels.METHODS`), or a kernel ``f(plant, s, basis) -> (p, m, nf)``
        with the built-ins' signature (``s`` Laplace points ``i w``, ``basis`` the undamped
        :class:`~vibss.linear.eigen.basis.ModalBasis`, None for a sparse plant; ``f(plant, s)`` is
        accepted too).
    foundation : Foundation or None
        A flexible foundation under some of the mounts to ground (:class:`vibss.Foundation`), coupled
        exactly by frequency-based substructuring at its own frequencies; its motions
        ``foundation.<mount>.x|y|z`` are added to the outputs.

    Returns
    -------
    FrequencyResponse

    Raises
    ------
    ArgumentError
        Unknown ``method`` or ``quantity`` (a ModelError, so a ValueError, naming the argument).
    ModelError
        Bad signal names or frequencies.
    AnalysisError
        The method cannot answer (e.g. ``modal`` on non-classical damping).
    """
    choice(quantity, "quantity", QUANTITIES)
    if foundation is not None:
        from ..measured.coupling import couple
        return couple(system, foundation, inputs, outputs, frequencies, quantity, method)
    chosen = resolve_method(method)
    plant, basis, f, pick, large = _plant_and_modes(system, inputs, outputs, frequencies, chosen)
    chosen, reason = _settled(plant, chosen, pick, basis, f.size)
    _warn_implausible_band(plant, basis, f)
    if basis is None and not large and not sp.issparse(plant.K):
        reason = f"{reason}; resonances not marked: {_NO_MODES}"
    large_note = (f"{plant.n} DOFs above {LARGE_DOFS} with explicit frequencies: kept sparse, no dense "
                  "eigen-analysis (resonances not marked)") if large else ""
    reason = "; ".join(x for x in (large_note, reason) if x)
    k = QUANTITIES[quantity]
    pos = f > 0
    every = bool(pos.all())             # no 0 Hz: the kernel's array is the response, no masked copy
    h = None if every else np.empty((len(plant.outputs), len(plant.inputs), f.size), dtype=complex)
    if every or np.any(pos):
        s = 2j * np.pi * (f if every else f[pos])
        raw, chosen, reason = _evaluated(plant, s, basis, chosen, method, reason)
        shape = (len(plant.outputs), len(plant.inputs), f.size)
        if h is None and _fresh(raw, chosen, shape):
            h = _times_power(raw, s, k)
        else:                           # 0 Hz among them, or a user's kernel: copied in, as complex
            h = np.empty(shape, dtype=complex) if h is None else h
            h[:, :, pos] = _times_power(raw, s, k)
    if not every:
        assert h is not None
        h[:, :, ~pos] = zero_frequency_limit(plant, power=k)[:, :, None]
    assert h is not None
    units = _units(plant, quantity)
    fr, numbers, labels = _resonances(plant, basis, float(f.min()), float(f.max()))
    return FrequencyResponse(f, h, plant.outputs, plant.inputs, units, quantity, chosen.name, reason,
                             fr, plant.name, _input_units(plant), numbers, labels)


BAND_ABOVE = 100.0
"""A band that starts this many times above every natural frequency is implausible: the response
there is the mass line, and the frequencies were most likely meant in another unit."""


def _warn_implausible_band(plant: Plant, basis: ModalBasis | None, f: np.ndarray) -> None:
    """Warn when every asked frequency lies over :data:`BAND_ABOVE` times the highest natural
    frequency (the modes' when known, else the Gershgorin bound ``max_i sum_j |K_ij| / M_ii``,
    which is above it for a diagonal ``M``: a warning it gives is never a false alarm by much)."""
    if f.size == 0 or float(f.min()) <= 0:
        return
    if basis is not None and basis.omega.size:
        top = float(np.max(basis.omega)) / (2 * np.pi)
    else:
        k = abs(plant.K).sum(axis=1) if sp.issparse(plant.K) else np.abs(plant.K).sum(axis=1)
        m = plant.M.diagonal() if sp.issparse(plant.M) else np.diag(plant.M)
        ratio = np.asarray(k).ravel() / np.where(m > 0, m, np.inf)
        top = float(np.sqrt(ratio.max(initial=0.0))) / (2 * np.pi)
    if top > 0 and float(f.min()) > BAND_ABOVE * top:
        warnings.warn(f"frequency_response: the band starts at {float(f.min()):.4g} Hz, over {BAND_ABOVE:g} "
                      f"times every natural frequency (the highest is about {top:.3g} Hz): only the mass line "
                      "is left there; were the frequencies meant in another unit?", VibssWarning, stacklevel=3)


def _plant_and_modes(system: Model | Assembly | Plant, inputs: Any, outputs: Any, frequencies: Any,
                     chosen: FrequencyMethod | None) -> tuple[Plant, ModalBasis | None, np.ndarray,
                                                             tuple[str, str] | None, bool]:
    """The plant (sparse for a large model, :func:`~vibss.frequency.methods.stays_sparse`), its
    undamped modes or None, the frequencies [Hz], ``auto``'s choice if it needed no modes, and
    whether the model was kept sparse."""
    large = stays_sparse(system, frequencies, chosen)
    if large and inputs is not None and not isinstance(system, Plant):
        plant = build_plant(system, inputs, outputs, sparse=True)
    else:
        large = False
        plant = _as_plant(system, inputs, outputs)
    if not sp.issparse(plant.K):
        basis, f, pick = _modes_if_needed(plant, frequencies, chosen)
        return plant, basis, f, pick, large
    # no dense eigen-analysis: explicit frequencies > 0, no resonance marks
    if frequencies is None or isinstance(frequencies, (Mapping, FrequencyGrid)):
        raise ModelError("frequencies: a sparse plant (build_plant(..., sparse=True)) needs explicit "
                         "frequencies [Hz]: the default grid is built around the modes")
    f = _frequencies(plant, frequencies, None)
    if np.any(f <= 0):
        raise ModelError("frequencies: a sparse plant takes frequencies > 0 (the 0 Hz limit needs the modes)")
    if chosen is not None and not chosen.sparse_ok:
        raise AnalysisError(f"method {chosen.name!r} needs the dense plant; a sparse plant (build_plant("
                            f"..., sparse=True)) takes {[m for m, v in METHODS.items() if v.sparse_ok]} "
                            "or 'auto'")
    return plant, None, f, None, large


def _settled(plant: Plant, chosen: FrequencyMethod | None, pick: tuple[str, str] | None,
             basis: ModalBasis | None, nf: int) -> tuple[FrequencyMethod, str]:
    """The method that runs (``auto`` settled by :func:`~vibss.frequency.methods.choose`) and why."""
    reason = ""
    if pick is not None:                      # auto chose from sizes and structure, without the modes
        name, reason = pick
        chosen = METHODS[name]
    elif chosen is None:
        name, reason = choose(plant, nf, basis)
        chosen = METHODS[name]
    elif plant.branches is not None and not chosen.internal_states:
        require_none(plant, f"frequency_response: method {chosen.name!r}",
                     f"use one of {[k for k, v in METHODS.items() if v.internal_states]} or 'auto'")
    elif plant.branches is not None:
        reason = plant.branches.note()
    return chosen, reason


def _evaluated(plant: Plant, s: np.ndarray, basis: ModalBasis | None, chosen: FrequencyMethod, method: Any,
               reason: str) -> tuple[Any, FrequencyMethod, str]:
    """The kernel's answer at the Laplace points ``s``, the method that gave it and the note with its
    check, settled by the one decider (:func:`vibss.methods.decide`).

    ``auto`` tries its pick, then the exact fallback (:func:`~vibss.frequency.methods.candidates`),
    and keeps only an answer whose check passed (:func:`vibss.frequency.contracts.check`); a named
    method is held to its estimate by the memory guard before it runs, and a miss of its claim is a
    :class:`~vibss.errors.VibssWarning` whose note carries the error measured at every frequency.
    """
    auto = isinstance(method, str) and method == "auto"
    order = candidates(plant, chosen, s.size, basis) if auto else [chosen]
    others = [] if auto else [m for m in METHODS.values() if m is not chosen and m.cost is not None
                              and (basis is not None or m.sparse_ok) and applies(m, plant, basis)]
    try:
        dec, own = settle(plant, s, basis, order, auto, others)
    except DefectiveModesError as exc:
        exact = [n for n, m in METHODS.items() if m.exact]
        raise DefectiveModesError(f"frequency_response: method {chosen.name!r} refused: {exc}; use an "
                                  f"exact method: {exact} (or 'auto')", argument="method",
                                  received=chosen.name, expected=exact) from None
    chosen, raw = next(m for m in order if m is dec.method), dec.answer
    if dec.attempts[:-1]:
        reason = f"{reason}; {dec.method.name}: {chosen.summary}" if reason else chosen.summary
    parts = [reason]
    if chosen.name in own:
        parts.append(own[chosen.name][0])
    if dec.check is not None and (chosen.claim is None or not (chosen.exact or chosen.needs_basis
                                                               or chosen.self_checked)):
        before = "; ".join(a.text() for a in dec.attempts[:-1])
        c = dec.check
        assert c is not None
        parts += [f"tried {before}" if before else "",
                  f"{chosen.name!r} is not an exact method: relative error {c.error:.1e} at {c.where}"
                  + (f" ({c.text()})" if chosen.claim is not None else "")]
    else:
        parts.append(dec.note())
    return raw, chosen, "; ".join(x for x in parts if x)


def _resonances(plant: Plant, basis: ModalBasis | None, lo: float,
                hi: float) -> tuple[np.ndarray, tuple[int, ...], tuple[str, ...]]:
    """Undamped natural frequencies [Hz] in ``[lo, hi]``, their mode numbers (from 1, rigid modes
    counted, as :func:`vibss.modes`) and labels (``"tank.y"``); no numbers when the plant's DOFs are
    not body DOFs (a modal plant)."""
    if basis is None:
        return np.zeros(0), (), ()
    own = plant._cache.get("modal basis") is basis
    if not own:
        return _band_resonances(plant, basis, lo, hi)
    # the plant's own modes: the last band's answer kept (a loop asks the same band again)
    last: dict[tuple[float, float], Any] = plant.cached("resonances of the last band", dict)
    hit = last.get((lo, hi))
    if hit is None:
        hit = _band_resonances(plant, basis, lo, hi)
        hit[0].flags.writeable = False
        last.clear()
        last[(lo, hi)] = hit
    return hit[0].view(), hit[1], hit[2]    # a view of the kept array: it cannot be made writeable


def _band_resonances(plant: Plant, basis: ModalBasis, lo: float,
                     hi: float) -> tuple[np.ndarray, tuple[int, ...], tuple[str, ...]]:
    fr = basis.omega / (2 * np.pi)
    keep = ~basis.rigid & (fr >= lo) & (fr <= hi)
    if not keep.any():
        return np.zeros(0), (), ()
    phi = basis.phi
    own = plant._cache.get("modal basis") is basis
    if own:                                           # the plant's own modes: labelled once per plant
        every = plant.cached("mode labels", lambda: tuple(dof_labels(energy_fractions(phi, plant.M), plant.dofs)))
        labels = [every[k] for k in np.flatnonzero(keep)]
    else:
        labels = dof_labels(energy_fractions(phi[:, keep], plant.M), plant.dofs)
    if not all(labels):
        return fr[keep], (), ()
    return fr[keep], tuple(int(k) + 1 for k in np.flatnonzero(keep)), tuple(labels)
