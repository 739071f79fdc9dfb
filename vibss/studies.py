"""Study defaults: one answer, from the model, to "which window, which step, which band, which sweeps".

The command line (``vibss time``, ``vibss frf``), the report (:func:`vibss.report.study`) and the
Python API (:func:`vibss.simulate` without ``t_end``/``dt``) all take their defaults from here, so
one model file gives one answer everywhere.

Rules (each value of the file's ``[analysis]`` table wins over its rule):

- **Steady sweeps.** An excitation whose time function is a steady state (a ``sine_sweep`` with
  ``sweep_time = 0``: an infinitely slow sweep, no time history) belongs to the frequency studies;
  every other excitation is transient and belongs to the time studies (:func:`steady_sweeps`,
  :func:`transient_excitations`).
- **Time window** (:func:`time_window`). ``end`` = the time the last transient excitation ends (its
  ``start`` for one that never ends: a sine from ``start`` on) plus the free decay of the slowest
  mode to 1 %, ``ln(100) / (zeta_r omega_r)`` (``zeta_r`` from the modal projection of the viscous
  and hysteretic damping), kept within 5 to 20 periods of the lowest elastic mode; 1 s after the
  excitations when the model has no elastic mode. ``step`` = the smallest of ``end / 200``, a
  twentieth of the highest natural period, a twentieth of the period of the highest excitation
  frequency (sines, sweeps) and a twentieth of the shortest pulse, rounded down to 1, 2 or 5 times a
  power of ten; coarser (rounded up to 1, 2 or 5 times a power of ten) where that would make more
  than :data:`MAX_DEFAULT_SAMPLES` samples. ``end`` is rounded up to two
  significant digits.
- **Time outputs** (:func:`time_outputs`). Under base excitation (every transient excitation a
  prescribed ground motion) the mount deflections (what the isolators stroke) and the bodies'
  absolute accelerations (what the item feels) lead, absolute body motion last (it follows the
  ground); under forces, body motion and mount forces lead.
- **Frequency band** (:func:`frequency_band`). ``f1``, ``f2`` = the steady sweeps' band (lowest
  ``f1`` to highest ``f2``) when the model has steady sweeps, else a tenth of the lowest to twice the
  highest elastic natural frequency (the rule of :class:`vibss.FrequencyGrid`); 0.01 to 100 Hz
  without elastic modes. ``points`` 1000, ``spacing`` ``"log"``.

Examples
--------
>>> from vibss import load_example
>>> d = study_defaults(load_example("powertrain"))
>>> [e.name for e in d.sweeps], d.band.f1, d.band.f2, d.time.end, d.time.step
(['firing-torque'], 2.0, 50.0, 1.0, 0.0005)
>>> w = time_window(load_example("two_mass"))      # undamped, no [analysis]: 20 periods of 0.48 Hz
>>> w.end, w.step
(42.0, 0.001)
>>> w.note.split("; ")[1]
'step: a twentieth of the highest natural period (25.26 Hz)'
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from .errors import ModelError
from .linear.plant.assemble import assemble
from .modal.api import modes as undamped_modes
from .modal.result import Modes
from .model.model import Model

__all__ = ["TimeWindow", "FrequencyBand", "StudyDefaults", "TimeOutputs", "is_steady_sweep", "steady_sweeps",
           "transient_excitations", "time_window", "time_outputs", "frequency_band", "study_defaults",
           "CausalLoss", "causal_loss", "causal_loss_fit", "MAX_DEFAULT_SAMPLES", "DECAY_PERIODS"]

MAX_DEFAULT_SAMPLES = 100_000
"""Most samples ``end / step + 1`` of a default time window (a coarser step beyond)."""

DECAY_PERIODS = (5.0, 20.0)
"""The free decay after the excitations is kept within these many periods of the lowest mode."""

POINTS_PER_PERIOD = 20.0
"""Samples per period of the highest natural or excitation frequency, and per shortest pulse."""


@dataclass(frozen=True)
class TimeWindow:
    """Time window and step of a time study.

    Attributes
    ----------
    end : float
        End time [s] (the simulation starts at 0).
    step : float
        Sample interval [s].
    record_from : float
        First recorded time [s].
    tolerance : float
        Relative tolerance of the ``ivp`` method.
    note : str
        Where ``end`` and ``step`` came from (the file, or the rule that gave them).
    """

    end: float
    step: float
    record_from: float = 0.0
    tolerance: float = 1e-6
    note: str = ""


@dataclass(frozen=True)
class FrequencyBand:
    """Frequency band and base grid of a frequency study.

    Attributes
    ----------
    f1, f2 : float
        Band [Hz].
    points : int
        Number of base points.
    spacing : {"log", "linear"}
        Base spacing.
    note : str
        Where the band came from.
    """

    f1: float
    f2: float
    points: int = 1000
    spacing: str = "log"
    note: str = ""

    def grid(self) -> dict[str, Any]:
        """The band as a grid mapping for ``frequencies=`` (:class:`vibss.FrequencyGrid` keys)."""
        return {"f1": self.f1, "f2": self.f2, "points": self.points, "spacing": self.spacing}


@dataclass(frozen=True)
class StudyDefaults:
    """Everything :func:`study_defaults` decides for one model.

    Attributes
    ----------
    time : TimeWindow
        Window and step of the time studies.
    band : FrequencyBand
        Band of the frequency studies.
    sweeps : tuple of Excitation
        The steady (``sweep_time = 0``) sine sweeps: frequency studies only.
    transient : tuple of Excitation
        The other excitations: time studies.
    """

    time: TimeWindow
    band: FrequencyBand
    sweeps: tuple[Any, ...]
    transient: tuple[Any, ...]


def is_steady_sweep(excitation: Any) -> bool:
    """Whether an excitation is a steady state (``sine_sweep`` with ``sweep_time = 0``).

    Parameters
    ----------
    excitation : Excitation
        An excitation (anything with a ``function``).
    """
    return bool(getattr(getattr(excitation, "function", None), "steady_state", False))


def steady_sweeps(model: Model) -> tuple[Any, ...]:
    """The model's steady-state sine sweeps (frequency studies only), in file order."""
    return tuple(e for e in model.excitations if is_steady_sweep(e))


def transient_excitations(model: Model) -> tuple[Any, ...]:
    """The model's excitations with a time history (everything but steady sweeps), in file order."""
    return tuple(e for e in model.excitations if not is_steady_sweep(e))


@dataclass(frozen=True)
class TimeOutputs:
    """The outputs of a time study, the ones that matter first.

    Attributes
    ----------
    outputs : tuple of str
        Signal names, leading ones first.
    lead : tuple of str
        The plot groups to draw first (``"mount deflection"``, ``"acceleration"`` ...; the groups of
        :func:`vibss.plotting.plot_time_groups`).
    base : bool
        True when every excitation is a prescribed ground motion.
    relative : bool
        The body motions are relative to the rigid ground (``<body>.<dof>.rel``).
    """

    outputs: tuple[str, ...]
    lead: tuple[str, ...]
    base: bool
    relative: bool = False


def time_outputs(model: Model, excitations: Sequence[Any] | None = None, absolute: bool = False) -> TimeOutputs:
    """Default outputs of a time study, leading with what matters (see the module docstring).

    Under prescribed motion of the rigid ground alone, the body motions are relative to the ground
    (``<body>.<dof>.rel``): a ground acceleration that leaves the ground moving makes every absolute
    motion a drift, which would hide the vibration.

    Parameters
    ----------
    model : Model
        The model.
    excitations : sequence of Excitation or None
        The excitations simulated (default: the model's transient ones).
    absolute : bool
        Absolute body motions under ground motion too.

    Examples
    --------
    >>> from vibss import load_example
    >>> t = time_outputs(load_example("packaged_item"))
    >>> t.base, t.outputs[0], t.lead
    (True, 'mount.lower.dx', ('mount deflection', 'acceleration'))
    """
    transient = list(transient_excitations(model) if excitations is None else excitations)
    grounds = ("ground", *model.support_names)     # the rigid ground and every named support
    base = bool(transient) and all(e.target in grounds and e.kind != "force" for e in transient)
    deflections = [f"mount.{m.name}.{d}" for m in model.mounts for d in ("dx", "dy", "dz")]
    accelerations = [f"{b}.{d}.acc" for b in model.body_names for d in "xyz"]
    motions = [f"{b}.{d}" for b in model.body_names for d in ("x", "y", "z", "rx", "ry", "rz")]
    forces = [f"mount.{m.name}.{d}" for m in model.mounts for d in ("fx", "fy", "fz")]
    if base:
        relative = not absolute and all(e.target == "ground" for e in transient)
        moved = [f"{x}.rel" for x in motions] if relative else motions
        return TimeOutputs(tuple(deflections + accelerations + moved), ("mount deflection", "acceleration"), True,
                           relative)
    return TimeOutputs(tuple(motions + forces + accelerations + deflections), ("body translation", "mount force"),
                       False)


def _settings(model: Model, key: str) -> dict[str, Any]:
    spec = (model.settings or {}).get(key) or {}
    if not hasattr(spec, "get"):
        raise ModelError(f"model: settings[{key!r}]: expected a mapping ([analysis] {key} = {{...}}), "
                         f"got {spec!r}")
    return dict(spec)


def _modes(model: Model, modes: Modes | None) -> Modes | None:
    if modes is not None:
        return modes
    return undamped_modes(model) if model.mounts else None


def _elastic_hz(m: Modes | None) -> np.ndarray:
    return np.array([]) if m is None else np.asarray(m.frequency_hz[~m.rigid], float)


def _modal_zeta(model: Model, m: Modes) -> np.ndarray:
    """Damping ratio of each elastic mode from the modal projection of C (viscous) and H (loss factor)."""
    a = assemble(model)
    phi = m.shapes[:, ~m.rigid]
    w = m.omega[~m.rigid]
    c = np.sum(phi * (a.dense("C") @ phi), axis=0)       # diag(phi^T C phi), one BLAS product
    h = np.sum(phi * (a.dense("H") @ phi), axis=0)
    return np.maximum(c / (2.0 * w) + h / (2.0 * w ** 2), 0.0)


def _parts(fn: Any) -> Iterable[Any]:
    return getattr(fn, "terms", None) or [fn]


def _excitation_steps(excitations: Sequence[Any]) -> list[tuple[float, str]]:
    """(step, why) limits from the excitations' frequencies and pulse durations."""
    out = []
    for e in excitations:
        for f in _parts(e.function):
            dur = getattr(f, "duration", None)
            if isinstance(dur, float) and dur > 0:
                out.append((dur / POINTS_PER_PERIOD, f"a twentieth of the {dur:.3g} s pulse of {e.name!r}"))
            for key in ("frequency", "f1", "f2"):
                v = getattr(f, key, None)
                if isinstance(v, float) and v > 0:
                    out.append((1.0 / (POINTS_PER_PERIOD * v),
                                f"a twentieth of the period of {e.name!r} at {v:.4g} Hz"))
    return out


def _round_down_125(x: float) -> float:
    """The largest 1, 2 or 5 times a power of ten not above ``x``."""
    p = 10.0 ** math.floor(math.log10(x))
    for k in (5.0, 2.0, 1.0):
        if k * p <= x * (1 + 1e-12):
            return float(f"{k * p:.1e}")
    return float(f"{p:.1e}")  # pragma: no cover - k = 1 always fits


def _round_up_125(x: float) -> float:
    """The smallest 1, 2 or 5 times a power of ten not below ``x``."""
    p = 10.0 ** math.floor(math.log10(x))
    for k in (1.0, 2.0, 5.0, 10.0):
        if k * p >= x * (1 - 1e-12):
            return float(f"{k * p:.1e}")
    return float(f"{10 * p:.1e}")  # pragma: no cover - k = 10 always fits


def _round_up_2(x: float) -> float:
    """``x`` rounded up to two significant digits."""
    p = 10.0 ** (math.floor(math.log10(x)) - 1)
    return float(f"{math.ceil(x / p * (1 - 1e-12)) * p:.2g}")


def time_window(model: Model, modes: Modes | None = None, *, end: float | None = None) -> TimeWindow:
    """The time window and step of a time study of ``model`` (see the module docstring).

    Parameters
    ----------
    model : Model
        The model (its ``[analysis] time`` settings, excitations and modes decide).
    modes : Modes or None
        The model's undamped modes, if already computed.
    end : float or None
        An end time [s] chosen by the caller (``vibss time --end``): it replaces the file's and the
        rule's, and the step follows from it (unless the file sets the step).

    Returns
    -------
    TimeWindow

    Examples
    --------
    >>> from vibss import load_example
    >>> w = time_window(load_example("packaged_item"))
    >>> w.end, w.step, w.note
    (0.2, 0.0001, 'end: [analysis] time; step: [analysis] time')
    """
    spec = _settings(model, "time")
    transient = transient_excitations(model)
    record_from = float(spec.get("record_from", 0.0))
    notes = []
    m = None
    given = end is not None
    end = end if given else spec.get("end")
    if end is None:
        m = _modes(model, modes)
        # a persistent excitation (a sine from ``start`` on): its start; the decay covers the build-up
        times = [e.function.end_time if math.isfinite(e.function.end_time)
                 else float(getattr(e.function, "start", 0.0)) for e in transient]
        t_exc = max(times, default=0.0)
        f = _elastic_hz(m)
        if f.size and m is not None:
            zeta = _modal_zeta(model, m)
            with np.errstate(divide="ignore"):
                decay = float(np.max(np.log(100.0) / (zeta * 2 * np.pi * f)))
            lo, hi = DECAY_PERIODS[0] / f.min(), DECAY_PERIODS[1] / f.min()
            free = min(max(decay, lo), hi)
            took = f"{decay:.3g} s" if math.isfinite(decay) else "never: an undamped mode"
            notes.append(f"end: excitations end at {t_exc:.4g} s + free decay of the slowest mode to 1 % "
                         f"({took}), limited to {DECAY_PERIODS[0]:g} to {DECAY_PERIODS[1]:g} periods "
                         f"of the lowest mode ({f.min():.4g} Hz)")
        else:
            free = 1.0
            notes.append(f"end: excitations end at {t_exc:.4g} s + 1 s (no elastic mode)")
        end = _round_up_2(max(t_exc + free, record_from + free))
    else:
        notes.append("end: given" if given else "end: [analysis] time")
    end = float(end)
    if not (math.isfinite(end) and end > 0):
        raise ModelError(f"time window: end: expected a positive time [s], got {end!r}")
    step = spec.get("step")
    if step is None:
        m = m if m is not None else _modes(model, modes)
        f = _elastic_hz(m)
        limits = [(end / 200.0, "end / 200")]
        if f.size:
            limits.append((1.0 / (POINTS_PER_PERIOD * f.max()),
                           f"a twentieth of the highest natural period ({f.max():.4g} Hz)"))
        limits += _excitation_steps(transient)
        step, why = min(limits, key=lambda x: x[0])
        floor = end / (MAX_DEFAULT_SAMPLES - 1)
        step = _round_down_125(step)
        if step < floor:
            step, why = _round_up_125(floor), f"{why} would exceed {MAX_DEFAULT_SAMPLES} samples"
        step = min(step, end)
        notes.append(f"step: {why}")
    else:
        notes.append("step: [analysis] time")
    return TimeWindow(end, float(step), record_from, float(spec.get("tolerance", 1e-6)), "; ".join(notes))


def frequency_band(model: Model, modes: Modes | None = None) -> FrequencyBand:
    """The frequency band and base grid of a frequency study of ``model`` (see the module docstring).

    Parameters
    ----------
    model : Model
        The model (its ``[analysis] frequency`` settings, steady sweeps and modes decide).
    modes : Modes or None
        The model's undamped modes, if already computed.

    Returns
    -------
    FrequencyBand

    Examples
    --------
    >>> from vibss import load_example
    >>> b = frequency_band(load_example("two_mass"))
    >>> round(b.f1, 4), round(b.f2, 3), b.points, b.note
    (0.0481, 50.526, 1000, 'a tenth of the lowest to twice the highest natural frequency')
    """
    spec = _settings(model, "frequency")
    unknown = set(spec) - {"f1", "f2", "points", "spacing"}
    if unknown:
        raise ModelError(f"[analysis] frequency: unknown key(s) {sorted(unknown)}; expected f1, f2, "
                         "points, spacing")
    sweeps = steady_sweeps(model)
    f1, f2 = spec.get("f1"), spec.get("f2")
    if f1 is not None and f2 is not None:
        note = "[analysis] frequency"
    elif sweeps:
        lo = min(min(e.function.f1, e.function.f2) for e in sweeps)
        hi = max(max(e.function.f1, e.function.f2) for e in sweeps)
        f1, f2 = (lo if f1 is None else f1), (hi if f2 is None else f2)
        note = "the steady sweeps' band"
    else:
        f = _elastic_hz(_modes(model, modes))
        lo, hi = (0.1 * f.min(), 2.0 * f.max()) if f.size else (0.01, 100.0)
        f1, f2 = (lo if f1 is None else f1), (hi if f2 is None else f2)
        note = ("a tenth of the lowest to twice the highest natural frequency" if f.size
                else "0.01 to 100 Hz (no elastic mode)")
    return FrequencyBand(float(f1), float(f2), int(spec.get("points", 1000)),
                         str(spec.get("spacing", "log")), note)


def study_defaults(model: Model, modes: Modes | None = None) -> StudyDefaults:
    """Window, step, band and the split of the excitations for every study of ``model``.

    Parameters
    ----------
    model : Model
        The model.
    modes : Modes or None
        The model's undamped modes, if already computed (saves an eigen-solve).

    Returns
    -------
    StudyDefaults
    """
    needs = modes is None and (not {"end", "step"} <= set(_settings(model, "time"))
                               or not ({"f1", "f2"} <= set(_settings(model, "frequency"))
                                       or steady_sweeps(model)))
    m = _modes(model, modes) if needs else modes     # one eigen-solve for both
    return StudyDefaults(time_window(model, m), frequency_band(model, m), steady_sweeps(model),
                         transient_excitations(model))


@dataclass(frozen=True)
class CausalLoss:
    """The result of :func:`causal_loss_fit`.

    Attributes
    ----------
    model : Model
        The model with its loss factors as causal ladders (the same object when it has none).
    mounts : tuple of str
        The mounts converted.
    band : (float, float)
        The band the ladders were fitted over [Hz].
    storage_error, loss_error : float
        Largest relative error over the band of the storage stiffness ``k'`` against ``k`` and of
        the loss factor ``k'' / k'`` against ``eta`` (0 when nothing was converted).
    """

    model: Model
    mounts: tuple[str, ...]
    band: tuple[float, float]
    storage_error: float
    loss_error: float

    @property
    def note(self) -> str:
        """The sentence for a result's ``note`` (``""`` when nothing was converted)."""
        if not self.mounts:
            return ""
        return (f"loss factor of mount(s) {list(self.mounts)} as a causal Maxwell ladder fitted over "
                f"{self.band[0]:.4g} to {self.band[1]:.4g} Hz: storage stiffness within "
                f"{100 * self.storage_error:.2g} %, loss factor within {100 * self.loss_error:.2g} % of "
                "k (1 + i eta) there")


def causal_loss(model: Model, band: Sequence[float] | None = None) -> Model:
    """``model`` with every constant loss factor replaced by its causal approximation over a band.

    A constant loss factor ``k (1 + i eta)`` has no causal time-domain form, so the time response,
    the damped modes and the python-control system leave it out (with a warning). This gives those
    mounts a ``prony`` rheology: the Maxwell ladder (passive, causal; three relaxation times per
    decade) nearest ``k (1 + i eta)`` over ``band``, storage and loss each to its own relative error
    (:func:`~vibss.model.rheology.fit_ladder` with ``parts=True``), which every analysis then uses:
    one mount, one answer. A causal stiffness with a loss cannot keep both flat (Kramers-Kronig:
    the storage stiffness of a constant loss factor rises as ``f^(2 eta / pi)``), so the ladder is
    off by a few per cent over the band; :func:`causal_loss_fit` says by how much.

    Parameters
    ----------
    model : Model
        The model; mounts with a loss factor and no rheology are converted, every other mount is kept.
    band : (2,) sequence of float or None
        [f1, f2] [Hz] the approximation holds over; default the model's frequency band
        (:func:`frequency_band`: its steady sweeps, else a tenth of the lowest to twice the
        highest natural frequency).

    Returns
    -------
    Model
        The same model when no mount has a loss factor.

    Raises
    ------
    ModelError
        A hysteretic mount type with a zero principal stiffness (its axis has no causal loss to fit),
        or a band that is not ``0 < f1 < f2``.

    Examples
    --------
    >>> from vibss import Body, Model, Mount, MountType
    >>> t = MountType("rubber", [1e4, 1e4, 2e4], loss_factor=0.1)
    >>> m = Model([Body("b", 10.0, [1, 1, 1])], [Mount("m", t, "b")])
    >>> causal_loss(m, band=[1.0, 100.0]).mounts[0].type.rheology.kind
    'prony'
    >>> print(causal_loss_fit(m, band=[1.0, 100.0]).note)
    loss factor of mount(s) ['m'] as a causal Maxwell ladder fitted over 1 to 100 Hz: storage stiffness within 15 %, loss factor within 17 % of k (1 + i eta) there
    """
    return causal_loss_fit(model, band).model


def causal_loss_fit(model: Model, band: Sequence[float] | None = None) -> CausalLoss:
    """:func:`causal_loss` with the mounts converted, the band and the errors (:class:`CausalLoss`)."""
    from .model.mounts import MountType
    from .model.rheology import fit_ladder

    if band is None:
        b = frequency_band(model)
        f1, f2 = b.f1, b.f2
    else:
        f1, f2 = (float(x) for x in band)
    if not (0 < f1 < f2 and math.isfinite(f2)):
        raise ModelError(f"causal_loss: band: expected [f1, f2] with 0 < f1 < f2 [Hz], got {list(band or [])}")
    converted: dict[str, Any] = {}
    storage = loss = 0.0
    w = 2 * np.pi * np.geomspace(f1, f2, 200)
    for t in {m.type.name: m.type for m in model.mounts}.values():
        eta = np.asarray(t.loss_factor, float)
        if t.rheology is not None or not np.any(eta * t.stiffness):
            continue
        if np.any(t.stiffness <= 0):
            raise ModelError(f"causal_loss: mount type {t.name!r}: stiffness {t.stiffness.tolist()} N/m has a "
                             "zero axis; a causal loss is fitted to a positive stiffness on every axis")
        target = t.stiffness * (1 + 1j * eta)
        lad = fit_ladder(lambda w: np.broadcast_to(target, (np.size(w), 3)), [f1, f2], parts=True)
        converted[t.name] = MountType(t.name, damping=t.damping,
                                      rheology={"type": "prony", "k_0": lad.static, "k": lad.k, "tau": lad.tau},
                                      rotational_stiffness=t.rotational_stiffness,
                                      rotational_damping=t.rotational_damping)
        kstar = lad.stiffness(w)
        storage = max(storage, float(np.max(np.abs(kstar.real / t.stiffness - 1))))
        lossy = eta > 0
        loss = max(loss, float(np.max(np.abs(kstar.imag[:, lossy] / kstar.real[:, lossy] / eta[lossy] - 1))))
    if not converted:
        return CausalLoss(model, (), (f1, f2), 0.0, 0.0)
    mounts = [replace(m, type=converted.get(m.type.name, m.type)) for m in model.mounts]
    names = tuple(m.name for m in model.mounts if m.type.name in converted)
    return CausalLoss(model.replace(mounts=mounts), names, (f1, f2), storage, loss)
