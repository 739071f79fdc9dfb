"""Transmissibility and swept-sine steady states, built on :func:`~vibss.frequency.api.frequency_response`."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from ..errors import AnalysisError, ModelError, SignalError, did_you_mean
from ..linear.plant.assemble import Assembly
from ..linear.plant.build import build_plant
from ..model.model import Model
from .api import frequency_response
from .grid import FrequencyGrid
from .result import FrequencyResponse

__all__ = ["transmissibility", "sweep_response"]


def transmissibility(system: Any, inputs: Sequence[str], outputs: Sequence[str] | None = None,
                     frequencies: Any = None, method: str | Callable[..., np.ndarray] = "auto", *,
                     foundation: Any = None) -> FrequencyResponse:
    """Motion or force transmissibility (dimensionless), safe at 0 Hz; of a model or of any named
    python-control system (a closed loop).

    Motion: prescribed motion inputs (``'ground.z'`` or ``'ground.z.disp'``, or a support's,
    ``'<support>.z'``: the transmissibility from that support alone; velocity and
    acceleration inputs are read as the same motion) to motion outputs of the same kind
    (default: every body DOF): ``|T| = |y| / |z|``. Force: force inputs (``'<body>.fz'``) to force
    outputs (default: the total force and moment into ground and into each support, and each ground
    mount's force).

    A python-control ``StateSpace`` (e.g. a closed loop from :func:`vibss.control.close`, or its
    :class:`~vibss.control.ClosedLoop`) is evaluated directly (balanced realization, one solve per
    frequency; :func:`vibss.frequency.statespace_response.evaluate`); its signal names, in either
    spelling, say what each signal is: an input ``<...>.disp|vel|acc`` is a motion of that order, any
    other input a force; an output's order comes from the system's ``vibss_units`` (set by vibss) or
    its suffix (``.vel``, ``.acc``). The ratio of motions is taken between equal orders
    (``|T| = |y| / |z|``).

    Parameters
    ----------
    system : Model, Assembly, python-control StateSpace or ClosedLoop
    inputs : sequence of str
        All motion inputs or all force inputs.
    outputs : sequence of str or None
        Outputs (see above for the defaults).
    frequencies : array_like [Hz], grid spec or None
    method : str or callable
        As :func:`frequency_response`.
    foundation : Foundation or None
        A flexible foundation under some of the mounts to ground (:class:`vibss.Foundation`),
        coupled exactly at its own frequencies (``frequencies`` None or those). Force inputs add
        the forces into it, ``foundation.<mount>.fx|fy|fz``, to the outputs (the force
        transmissibility into the foundation); motion inputs add its motions
        ``foundation.<mount>.x|y|z``. The foundation is known by its receptance alone: a ground or
        support motion moves only the mounts not standing on it.

    Returns
    -------
    FrequencyResponse
        ``quantity = "transmissibility"``.

    Examples
    --------
    >>> from vibss import Body, Model, Mount, MountType
    >>> m = Model([Body("b", 1.0, [1, 1, 1])], [Mount("m", MountType("t", [1.0] * 3, [0.2] * 3), "b")])
    >>> t = transmissibility(m, ["ground.z"], ["b.z"], frequencies=[0.0])
    >>> print(f"{abs(t.response[0, 0, 0]):.12f}")
    1.000000000000
    """
    if not isinstance(system, (Model, Assembly)):
        return _system_transmissibility(getattr(system, "system", system), inputs, outputs, frequencies)
    model = system.model if isinstance(system, Assembly) else system
    names = [u if isinstance(u, str) else u.signal for u in inputs]
    grounds = {"ground", *model.support_names}
    motion = [u.rsplit(".", 1)[-1] in ("disp", "vel", "acc") or u.split(".", 1)[0] in grounds for u in names]
    if any(motion) and not all(motion):
        raise ModelError(f"inputs: mix of motion and force inputs {names}; transmissibility takes one kind")
    if all(motion):
        ins = [u if u.rsplit(".", 1)[-1] in ("disp", "vel", "acc") else f"{u}.disp" for u in names]
        ins = [u.rsplit(".", 1)[0] + ".disp" for u in ins]
        # a ratio of motions of equal order: velocity and acceleration outputs give the same ratio as
        # their displacements (they were taken over a displacement input: the ratio was s^2 off)
        outs = None if outputs is None else [o[:-4] if isinstance(o, str) and o.endswith((".vel", ".acc"))
                                             else o for o in outputs]
        plant = build_plant(system, ins, outs)
        if any(u not in ("m", "rad") for u in plant.units):
            bad = [y for y, u in zip(plant.outputs, plant.units) if u not in ("m", "rad")]
            raise ModelError(f"outputs: motion transmissibility needs motion outputs; {bad} are not "
                             f"(units {[u for u in plant.units if u not in ('m', 'rad')]})")
    else:
        if outputs is None:
            outputs = [f"{g}.{c}" for g in ("ground", *model.support_names) for c in ("fx", "fy", "fz", "mx", "my", "mz")]
            outputs += [f"mount.{m.name}.{c}" for m in model.mounts if m.to == "ground" for c in ("fx", "fy", "fz")]
        plant = build_plant(system, names, outputs)
        if any(u not in ("N", "N m") for u in plant.units):
            raise ModelError(f"outputs: force transmissibility needs force outputs, got units {list(plant.units)}")
    if foundation is None:
        r = frequency_response(plant, frequencies=frequencies, method=method)
        extra: tuple[str, ...] = ()
    else:
        r = _on_foundation(model, plant, frequencies, method, foundation, all(motion))
        extra = r.outputs[len(plant.outputs):]
    # the names as the user wrote them (a ratio of accelerations is the ratio of their displacements)
    outs_named = ((*outputs, *extra) if outputs is not None and all(isinstance(o, str) for o in outputs)
                  else r.outputs)
    ins_named = tuple(names) if all(motion) else r.inputs
    return FrequencyResponse(r.frequency_hz, r.response, outs_named, ins_named,
                             tuple(_of_order(u, y) for u, y in zip(r.units, outs_named)), "transmissibility",
                             r.method, r.reason, r.natural_hz, r.name,
                             tuple(_of_order(u, x) for u, x in zip(r.input_units, ins_named)),
                             r.mode_numbers, r.mode_labels)


def _on_foundation(model: Model, plant: Any, frequencies: Any, method: Any, foundation: Any,
                   motion: bool) -> FrequencyResponse:
    """The plant's signals on ``foundation`` (exact coupling), with the foundation's motions (motion
    inputs) or the forces into it (force inputs) after the plant's outputs."""
    r = frequency_response(model, list(plant.inputs), list(plant.outputs), frequencies, method=method,
                           foundation=foundation)
    p, n = len(plant.outputs), len(foundation.outputs)
    keep = [*range(p), *(range(p, p + n) if motion else range(p + n, p + 2 * n))]
    return FrequencyResponse(r.frequency_hz, r.response[keep], tuple(r.outputs[i] for i in keep), r.inputs,
                             tuple(r.units[i] for i in keep), r.quantity, r.method, r.reason, r.natural_hz, r.name,
                             r.input_units)


def _of_order(unit: str, name: str) -> str:
    """The unit of a motion signal named with a ``.vel`` or ``.acc`` suffix, from its displacement's."""
    last = name.rsplit(".", 1)[-1]
    if unit in ("m", "rad") and last in ("vel", "acc"):
        return f"{unit}/s" if last == "vel" else f"{unit}/s^2"
    return unit


def _order(name: str, unit: str | None) -> int | None:
    """Time-derivative order of a motion signal (None for a force)."""
    if unit is not None:
        if unit.startswith("N"):
            return None
        return 2 if unit.endswith("/s^2") else 1 if unit.endswith("/s") else 0
    last = name.rsplit(".", 1)[-1]
    if last in ("disp", "vel", "acc"):
        return {"disp": 0, "vel": 1, "acc": 2}[last]
    if last.startswith(("f", "m")) and len(last) == 2:
        return None
    return 0


def _system_transmissibility(system: Any, inputs: Sequence[str], outputs: Sequence[str] | None,
                             frequencies: Any) -> FrequencyResponse:
    """Transmissibility of a named python-control state space (see :func:`transmissibility`)."""
    import control

    from ..frequency.statespace_response import evaluate
    from ..linear.plant.labels import control_name

    if not isinstance(system, control.StateSpace):
        raise ModelError(f"system: expected a Model, an Assembly or a python-control StateSpace, got "
                         f"{type(system).__name__}")
    if system.dt not in (0, None):
        raise ModelError("system: continuous-time systems only (dt = 0)")
    ins = [inputs] if isinstance(inputs, str) else list(inputs)
    outs = list(outputs) if outputs is not None else [s.replace(":", ".") for s in system.output_labels]
    units = getattr(system, "vibss_units", {}) or {}

    def index(labels: Sequence[str], name: str, what: str) -> int:
        c = control_name(name)
        if c not in labels:
            vib = [x.replace(":", ".") for x in labels]
            raise SignalError(f"{what}: no {what[:-1]} named {name!r} in the system; they are {vib}"
                              + did_you_mean(name.replace(":", "."), vib), argument=what, received=name)
        return list(labels).index(c)

    ii = [index(system.input_labels, u, "inputs") for u in ins]
    io = [index(system.output_labels, y, "outputs") for y in outs]
    oi = [_order(u.replace(":", "."), units.get(u.replace(":", "."))) for u in ins]
    oo = [_order(y.replace(":", "."), units.get(y.replace(":", "."))) for y in outs]
    if any(o is None for o in oi) != all(o is None for o in oi):
        raise ModelError(f"inputs: mix of motion and force inputs {ins}; transmissibility takes one kind")
    force = all(o is None for o in oi)
    if force and any(o is not None for o in oo):
        raise ModelError(f"outputs: force transmissibility needs force outputs, got {outs}")
    if not force and any(o is None for o in oo):
        raise ModelError(f"outputs: motion transmissibility needs motion outputs, got {outs}")
    if frequencies is None:
        poles = np.abs(np.linalg.eigvals(np.asarray(system.A, dtype=float))) if system.nstates else np.ones(1)
        poles = poles[poles > 0] if np.any(poles > 0) else np.ones(1)
        f = np.geomspace(poles.min() / (2 * np.pi) / 10, poles.max() / (2 * np.pi) * 10, 1000)
    else:
        f = np.atleast_1d(np.asarray(frequencies, dtype=float))
        if f.ndim != 1 or f.size == 0 or not np.all(np.isfinite(f)) or np.any(f <= 0):
            raise ModelError(f"frequencies: expected frequencies > 0 [Hz], got {frequencies!r}")
    h = evaluate(system, 2 * np.pi * f, outputs=io, inputs=ii)
    if not force:
        s = 2j * np.pi * f
        for a, yo in enumerate(oo):
            for b, ui in enumerate(oi):
                h[a, b] = h[a, b] * s ** (int(ui or 0) - int(yo or 0))
    from ..model.units import input_unit, times_s

    base_in = tuple(input_unit(u.replace(":", "."), "force" if o is None else "displacement") for u, o in zip(ins, oi))
    base_out = tuple(("N" if not units.get(y.replace(":", "."), "N").startswith("N m") else "N m") if o is None
                     else times_s(units.get(y.replace(":", "."), "m"), -o) for y, o in zip(outs, oo))
    return FrequencyResponse(f, h, tuple(y.replace(":", ".") for y in outs), tuple(u.replace(":", ".") for u in ins),
                             base_out, "transmissibility",
                             "statespace (balanced, direct solve)", "", np.zeros(0),
                             str(getattr(system, "name", "system")).replace(":", "."), base_in)


def sweep_response(system: Model | Assembly, excitations: Sequence[Any] | None = None,
                   f1: float | None = None, f2: float | None = None, points: int = 1000,
                   spacing: str = "log", outputs: Sequence[str] | None = None,
                   quantity: str = "receptance", refine: bool = True,
                   method: str | Callable[..., np.ndarray] = "auto") -> FrequencyResponse:
    """Steady state of swept-sine excitations (infinitely slow sweep, ``sweep_time = 0``).

    Each excitation's amplitude varies linearly from ``a1`` at its ``f1`` to ``a2`` at its ``f2``
    (zero outside); all act in phase. The response is ``sum_j H_j(f) a_j(f)``.

    Parameters
    ----------
    system : Model or Assembly
    excitations : sequence or None
        Excitation objects with a ``sine_sweep`` function (``.signal`` and
        ``.function.amplitude_at(f_hz)``), or ``(signal, (a1, a2))`` pairs (amplitudes at ``f1``
        and ``f2`` of this call); default: the model's steady (``sweep_time = 0``) sine-sweep
        excitations (time-domain ones are for the time response and are skipped).
    f1, f2 : float or None
        Band [Hz]; default: the excitations' own band (their sweep limits).
    points, spacing, refine :
        Grid (see :class:`FrequencyGrid`).
    outputs : sequence of str or None
        Outputs; default every body DOF's displacement.
    quantity : str
        As :func:`frequency_response`.
    method : str or callable
        As :func:`frequency_response`.

    Returns
    -------
    FrequencyResponse
        One input, ``"sweep"``; ``quantity = "sweep"``-style amplitudes in output units.

    Raises
    ------
    AnalysisError
        An excitation has a finite ``sweep_time`` (a transient: simulate it in time) or no
        frequency-domain amplitude.
    """
    model = system.model if isinstance(system, Assembly) else system
    if excitations is None:      # the model's frequency-domain (steady sine sweep) excitations only
        excitations = [e for e in model.excitations
                       if hasattr(getattr(e, "function", None), "amplitude_at")
                       and not getattr(e.function, "sweep_time", 0.0)]
        if not excitations:
            raise ModelError("excitations: the model has no sine_sweep excitation with sweep_time = 0 "
                             f"(it has {[getattr(e, 'name', e) for e in model.excitations]}); "
                             "name inputs instead")
    excitations = list(excitations)
    if not excitations:
        raise ModelError("excitations: none given")
    signals: list[Any] = []
    amps: list[tuple[Any, ...]] = []
    bands = []
    for e in excitations:
        if isinstance(e, tuple) and len(e) == 2 and not hasattr(e, "signal"):
            sig, (a1, a2) = e
            signals.append(sig)
            amps.append(("pair", float(a1), float(a2)))
            continue
        fn = getattr(e, "function", None)
        if fn is None or not hasattr(fn, "amplitude_at"):
            raise AnalysisError(f"excitation {getattr(e, 'name', e)!r}: has no frequency-domain amplitude "
                                "(a sine_sweep function with sweep_time = 0 is needed)")
        if getattr(fn, "sweep_time", 0.0):
            raise AnalysisError(f"excitation {getattr(e, 'name', e)!r}: sweep_time = {fn.sweep_time} s is a "
                                "transient sweep; simulate it with the time response (sweep_time 0 = "
                                "steady state)")
        signals.append(e)
        amps.append(("fn", fn))
        bands.append((min(fn.f1, fn.f2), max(fn.f1, fn.f2)))
    lo = f1 if f1 is not None else (min(b[0] for b in bands) if bands else None)
    hi = f2 if f2 is not None else (max(b[1] for b in bands) if bands else None)
    grid = FrequencyGrid(lo, hi, points, spacing, refine)
    r = frequency_response(system, signals, outputs, grid, quantity, method)
    f = r.frequency_hz
    a = np.empty((len(signals), f.size))
    for j, spec in enumerate(amps):
        if spec[0] == "fn":
            a[j] = spec[1].amplitude_at(f)
        else:
            _, a1, a2 = spec
            flo, fhi = f.min(), f.max()
            a[j] = a1 + (a2 - a1) * (f - flo) / (fhi - flo) if fhi > flo else a1
    with np.errstate(invalid="ignore"):
        terms = r.response * a[None, :, :]
    terms = np.where(a[None, :, :] == 0, 0.0, terms)       # inf * 0 outside a sweep band -> 0
    y = terms.sum(axis=1, keepdims=True)
    return FrequencyResponse(f, y, r.outputs, ("sweep",), r.units, quantity, r.method, r.reason,
                             r.natural_hz, r.name, mode_numbers=r.mode_numbers, mode_labels=r.mode_labels)
