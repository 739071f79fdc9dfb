"""Frequency-dependent mount stiffness: rheological models, tables, and their Maxwell ladders.

A mount's complex (dynamic) stiffness per principal axis, ``k*(w) = k'(w) (1 + i eta(w))``, is given
by one of the :data:`RHEOLOGIES` (SI: stiffness [N/m], times [s], frequencies [Hz]):

==================  =========================================================  ==============
type                k*(w) per axis                                             time domain
==================  =========================================================  ==============
``kelvin_voigt``    ``k + i w c``                                              exact
``zener``           ``k_0 + (k_inf - k_0) i w tau / (1 + i w tau)``            exact
``prony``           ``k_0 + sum_i k_i i w tau_i / (1 + i w tau_i)``            exact
``fractional_zener`` ``(k_0 + k_inf (i w tau)^alpha) / (1 + (i w tau)^alpha)``  fitted ladder
``table``           PCHIP of ``k'`` and ``eta`` against frequency              fitted ladder
``hydraulic``       ``k_r + i w c_r + k_b P / (k_b + P)``, ``P = -m_f w^2 + i w c_f``  exact
==================  =========================================================  ==============

Every model becomes a :class:`Ladder` -- a spring ``k_0``, a dashpot ``c`` and Maxwell branches
(spring ``k_i`` in series with a dashpot ``k_i tau_i``) in parallel, and for a hydraulic mount a
branch whose internal coordinate carries a mass (the fluid in the inertia track) -- which is causal
and passive by construction and is what every analysis uses (FRF, time response, damped modes and the
python-control system: one mount, one answer). The rational models are their own ladders; the
others are fitted over a band (non-negative least squares on fixed relaxation times, three per
decade), and the fit's largest relative error ``|k_fit - k*| / |k*|`` over the band is
:attr:`Ladder.fit_error`. A constant loss factor over a band is the table
``{"type": "table", "frequency": [f1, f2], "stiffness": k, "loss_factor": eta}``.

A passive mount has a non-negative loss angle at every frequency and a positive static stiffness:
bad data raise :class:`~vibss.errors.ModelError` naming the mount type, the axis and the frequency.

Examples
--------
>>> z = parse_rheology({"type": "zener", "k_0": [1e4] * 3, "k_inf": [3e4] * 3, "tau": 1e-2}, "t")
>>> z.ladder().k[:, 0].tolist(), z.ladder().tau[:, 0].tolist()
([20000.0, 20000.0, 20000.0], [0.01, 0.01, 0.01])
>>> complex(z.dynamic_stiffness([100.0])[0, 2]).real      # k_0 + 2e4 (1 / (1 + 1)) at w tau = 1
20000.0
"""

# Over 600 lines on purpose (issue 28): the rheological models and the one Maxwell-ladder fit every
# model reduces to; each model's parameters, its exact dynamic stiffness and its ladder are read
# together.

from __future__ import annotations

import warnings
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np
import numpy.typing as npt

from .._validate import is_numeric
from ..errors import ModelError, VibssWarning

__all__ = ["Rheology", "Ladder", "KelvinVoigt", "Zener", "Prony", "FractionalZener", "Table", "Hydraulic",
           "RHEOLOGIES", "QUANTITIES", "parse_rheology", "fit_ladder", "PER_DECADE", "FEW_POINTS", "FIT_WARN"]

PER_DECADE = 3
"""Relaxation times per decade of a fitted ladder."""

FEW_POINTS = 4
"""A table with fewer points than this gets a warning (its interpolation and fit rest on little)."""

FIT_WARN = 0.05
"""A table whose fitted ladder is further than this (relative) from it gets a warning."""

_FIT_POINTS = 400


@dataclass(frozen=True, eq=False)
class Ladder:
    """A causal, passive realization ``k*(s) = k_0 + c s + sum_i k_i P_i(s) / (1 + P_i(s))`` with
    ``P_i(s) = mu_i s^2 + tau_i s``: a Maxwell branch when ``mu_i = 0``, an inertia-track branch of a
    hydraulic mount (``mu_i = m_i / k_i``) otherwise.

    Attributes
    ----------
    static : (3,) ndarray
        Equilibrium (static) stiffness ``k_0`` per axis [N/m].
    viscous : (3,) ndarray
        Parallel dashpot ``c`` per axis [N s/m].
    k : (3, nb) ndarray
        Branch stiffnesses [N/m] (zero: no branch).
    tau : (3, nb) ndarray
        Branch relaxation times [s] (> 0).
    fit_error : float
        Largest ``|k_fit - k*| / |k*|`` over ``band`` (0 for an exact ladder).
    band : (2,) ndarray or None
        Band of the fit [Hz] (None: exact).
    mu : (3, nb) ndarray or None
        Branch mass per unit branch stiffness ``m_i / k_i`` [s^2] (None: zeros, Maxwell branches).
    """

    static: np.ndarray
    viscous: np.ndarray
    k: np.ndarray
    tau: np.ndarray
    fit_error: float = 0.0
    band: np.ndarray | None = None
    mu: np.ndarray | None = None

    def __post_init__(self) -> None:
        if self.mu is None:
            object.__setattr__(self, "mu", np.zeros(np.shape(self.k)))

    def stiffness(self, omega: npt.ArrayLike) -> np.ndarray:
        """(nf, 3) complex ``k*(i w)`` of the ladder at angular frequencies ``omega`` [rad/s]."""
        s = 1j * np.atleast_1d(np.asarray(omega, dtype=float))[:, None, None]
        p = s * s * np.asarray(self.mu)[None] + s * self.tau[None]
        branch = np.sum(self.k[None] * p / (1.0 + p), axis=2)
        return self.static[None] + s[:, :, 0] * self.viscous[None] + branch


@dataclass(frozen=True, eq=False)
class Rheology:
    """Base of the rheological models: exact ``k*(w)``, static stiffness, a ladder, a dict form."""

    kind: ClassVar[str] = ""
    exact: ClassVar[bool] = True
    keys: ClassVar[tuple[str, ...]] = ()
    required: ClassVar[tuple[str, ...]] = ()
    owner: str = field(default="", kw_only=True)

    def dynamic_stiffness(self, omega: npt.ArrayLike) -> np.ndarray:
        """(nf, 3) complex dynamic stiffness at angular frequencies ``omega`` [rad/s]."""
        raise NotImplementedError

    @property
    def static_stiffness(self) -> np.ndarray:
        """(3,) static stiffness [N/m] (that of the ladder every analysis uses)."""
        return self.ladder().static

    def ladder(self) -> Ladder:
        """The :class:`Ladder` every analysis uses."""
        raise NotImplementedError

    def to_dict(self) -> dict[str, Any]:
        """The ``rheology = {...}`` table of a model file (SI)."""
        out: dict[str, Any] = {"type": self.kind}
        for key in self.keys:
            v = getattr(self, key)
            if v is not None:
                out[key] = np.asarray(v).tolist()
        return out

    def _who(self) -> str:
        return f"mount type {self.owner!r}: rheology {self.kind!r}" if self.owner else f"rheology {self.kind!r}"


def _axes(value: Any, who: str, key: str, *, positive: bool = False) -> np.ndarray:
    """A number or 3 numbers per axis, finite and >= 0 (> 0 with ``positive``)."""
    if not is_numeric(value):
        raise ModelError(f"{who}: {key}: expected a number or 3 numbers (one per axis), got {value!r}")
    a = np.asarray(value, dtype=float)
    if a.shape not in ((), (3,)):
        raise ModelError(f"{who}: {key}: expected a number or 3 numbers (one per axis), got shape {a.shape}")
    a = np.broadcast_to(a, (3,)).copy()
    bad = ~np.isfinite(a) | (a <= 0 if positive else a < 0)
    if np.any(bad):
        j = int(np.flatnonzero(bad)[0])
        raise ModelError(f"{who}: {key}: axis {j + 1} is {float(a[j])!r}; expected a finite number "
                         f"{'> 0' if positive else '>= 0'}")
    a.setflags(write=False)
    return a


def _per_axis_list(value: Any, who: str, key: str, *, positive: bool) -> np.ndarray:
    """(3, nb) from nb numbers (every axis) or 3 lists of nb numbers."""
    if not is_numeric(value):
        raise ModelError(f"{who}: {key}: expected a list of numbers (every axis) or 3 lists (one per "
                         f"axis), got {value!r}")
    a = np.asarray(value, dtype=float)
    if a.ndim == 0:
        a = a[None]
    if a.ndim == 1:
        a = np.broadcast_to(a, (3, a.size))
    if a.ndim != 2 or a.shape[0] != 3 or a.shape[1] == 0:
        raise ModelError(f"{who}: {key}: expected nb numbers or 3 lists of nb numbers, got shape {np.shape(value)}")
    bad = ~np.isfinite(a) | (a <= 0 if positive else a < 0)
    if np.any(bad):
        j, i = (int(x[0]) for x in np.nonzero(bad))
        raise ModelError(f"{who}: {key}: axis {j + 1}, term {i + 1} is {float(a[j, i])!r}; expected a finite "
                         f"number {'> 0' if positive else '>= 0'}")
    a = a.copy()
    a.setflags(write=False)
    return a


@dataclass(frozen=True, eq=False)
class KelvinVoigt(Rheology):
    """Spring and dashpot in parallel: ``k* = k + i w c`` (the constant mount, for completeness).

    Parameters
    ----------
    k : float or (3,) array_like
        Stiffness per axis [N/m].
    c : float or (3,) array_like
        Damping per axis [N s/m].
    """

    kind: ClassVar[str] = "kelvin_voigt"
    keys: ClassVar[tuple[str, ...]] = ("k", "c")
    required: ClassVar[tuple[str, ...]] = ("k",)
    k: Any = 0.0
    c: Any = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "k", _axes(self.k, self._who(), "k"))
        object.__setattr__(self, "c", _axes(self.c, self._who(), "c"))

    def dynamic_stiffness(self, omega: npt.ArrayLike) -> np.ndarray:
        w = np.atleast_1d(np.asarray(omega, dtype=float))[:, None]
        return self.k[None] + 1j * w * self.c[None]

    def ladder(self) -> Ladder:
        return Ladder(self.k, self.c, np.zeros((3, 0)), np.ones((3, 0)))


@dataclass(frozen=True, eq=False)
class Zener(Rheology):
    """Standard linear solid: ``k* = k_0 + (k_inf - k_0) i w tau / (1 + i w tau)``.

    Parameters
    ----------
    k_0 : float or (3,) array_like
        Static stiffness per axis [N/m].
    k_inf : float or (3,) array_like
        High-frequency stiffness per axis [N/m], ``>= k_0`` (passive: loss angle >= 0).
    tau : float or (3,) array_like
        Relaxation time per axis [s], > 0.
    """

    kind: ClassVar[str] = "zener"
    keys: ClassVar[tuple[str, ...]] = ("k_0", "k_inf", "tau")
    required: ClassVar[tuple[str, ...]] = keys
    k_0: Any = 0.0
    k_inf: Any = 0.0
    tau: Any = 1.0

    def __post_init__(self) -> None:
        who = self._who()
        k0, kinf = _axes(self.k_0, who, "k_0"), _axes(self.k_inf, who, "k_inf")
        bad = np.flatnonzero(kinf < k0)
        if bad.size:
            j = int(bad[0])
            raise ModelError(f"{who}: axis {j + 1}: k_inf = {kinf[j]:g} N/m is below k_0 = {k0[j]:g} N/m: "
                             "the loss angle would be negative at every frequency (not a passive mount)")
        object.__setattr__(self, "k_0", k0)
        object.__setattr__(self, "k_inf", kinf)
        object.__setattr__(self, "tau", _axes(self.tau, who, "tau", positive=True))

    def dynamic_stiffness(self, omega: npt.ArrayLike) -> np.ndarray:
        s = 1j * np.atleast_1d(np.asarray(omega, dtype=float))[:, None]
        return self.k_0[None] + (self.k_inf - self.k_0)[None] * s * self.tau[None] / (1.0 + s * self.tau[None])

    def ladder(self) -> Ladder:
        return Ladder(self.k_0, np.zeros(3), (self.k_inf - self.k_0)[:, None], self.tau[:, None].copy())


@dataclass(frozen=True, eq=False)
class Prony(Rheology):
    """Generalized Maxwell (Prony series): ``k* = k_0 + sum_i k_i i w tau_i / (1 + i w tau_i)``.

    Parameters
    ----------
    k_0 : float or (3,) array_like
        Static (equilibrium) stiffness per axis [N/m].
    k : (nb,) or (3, nb) array_like
        Branch stiffnesses [N/m], >= 0 (every axis, or one list per axis).
    tau : (nb,) or (3, nb) array_like
        Relaxation times [s], > 0.
    """

    kind: ClassVar[str] = "prony"
    keys: ClassVar[tuple[str, ...]] = ("k_0", "k", "tau")
    required: ClassVar[tuple[str, ...]] = keys
    k_0: Any = 0.0
    k: Any = ()
    tau: Any = ()

    def __post_init__(self) -> None:
        who = self._who()
        k = _per_axis_list(self.k, who, "k", positive=False)
        tau = _per_axis_list(self.tau, who, "tau", positive=True)
        if k.shape != tau.shape:
            raise ModelError(f"{who}: k and tau: need as many terms, got shapes {k.shape} and {tau.shape}")
        object.__setattr__(self, "k_0", _axes(self.k_0, who, "k_0"))
        object.__setattr__(self, "k", k)
        object.__setattr__(self, "tau", tau)

    def dynamic_stiffness(self, omega: npt.ArrayLike) -> np.ndarray:
        return self.ladder().stiffness(omega)

    def ladder(self) -> Ladder:
        return Ladder(self.k_0, np.zeros(3), self.k, self.tau)


def _band(value: Any, who: str, default: tuple[float, float]) -> np.ndarray:
    if value is None:
        return np.array(default, dtype=float)
    if not is_numeric(value) or np.shape(value) != (2,):
        raise ModelError(f"{who}: band: expected [f1, f2] [Hz], got {value!r}")
    b = np.asarray(value, dtype=float)
    if not (np.all(np.isfinite(b)) and 0 < b[0] < b[1]):
        raise ModelError(f"{who}: band: expected 0 < f1 < f2 [Hz], got {b.tolist()}")
    return b


@dataclass(frozen=True, eq=False)
class FractionalZener(Rheology):
    """Fractional-derivative Zener: ``k* = (k_0 + k_inf (i w tau)^alpha) / (1 + (i w tau)^alpha)``.

    Parameters
    ----------
    k_0, k_inf : float or (3,) array_like
        Static and high-frequency stiffness per axis [N/m], ``k_inf >= k_0``.
    tau : float or (3,) array_like
        Characteristic time per axis [s], > 0.
    alpha : float or (3,) array_like
        Fractional order, ``0 < alpha <= 1`` (1: the Zener model).
    band : (2,) array_like or None
        Band of the ladder fit [Hz]; default two decades either side of ``1 / (2 pi tau)``.
    """

    kind: ClassVar[str] = "fractional_zener"
    exact: ClassVar[bool] = False
    keys: ClassVar[tuple[str, ...]] = ("k_0", "k_inf", "tau", "alpha", "band")
    required: ClassVar[tuple[str, ...]] = ("k_0", "k_inf", "tau", "alpha")
    k_0: Any = 0.0
    k_inf: Any = 0.0
    tau: Any = 1.0
    alpha: Any = 1.0
    band: Any = None
    _ladder: Any = field(default=None, init=False, repr=False)

    def __post_init__(self) -> None:
        who = self._who()
        z = Zener(self.k_0, self.k_inf, self.tau, owner=self.owner)     # same checks
        alpha = _axes(self.alpha, who, "alpha", positive=True)
        if np.any(alpha > 1):
            raise ModelError(f"{who}: alpha: expected 0 < alpha <= 1, got {alpha.tolist()}")
        fc = 1.0 / (2 * np.pi * z.tau)
        object.__setattr__(self, "k_0", z.k_0)
        object.__setattr__(self, "k_inf", z.k_inf)
        object.__setattr__(self, "tau", z.tau)
        object.__setattr__(self, "alpha", alpha)
        object.__setattr__(self, "band", _band(self.band, who, (0.01 * fc.min(), 100 * fc.max())))
        object.__setattr__(self, "_ladder", fit_ladder(self.dynamic_stiffness, self.band, static=self.k_0))

    def dynamic_stiffness(self, omega: npt.ArrayLike) -> np.ndarray:
        x = (1j * np.atleast_1d(np.asarray(omega, dtype=float))[:, None] * self.tau[None]) ** self.alpha[None]
        return (self.k_0[None] + self.k_inf[None] * x) / (1.0 + x)

    def ladder(self) -> Ladder:
        return self._ladder


@dataclass(frozen=True, eq=False)
class Table(Rheology):
    """Measured dynamic stiffness ``k'(f)`` and loss factor ``eta(f)``: ``k* = k' (1 + i eta)``.

    Interpolated by PCHIP in ``log f`` (monotone between points, no overshoot); held at the end
    values outside the table, with a :class:`~vibss.errors.VibssWarning` when asked there.

    Parameters
    ----------
    frequency : (nf,) array_like
        Frequencies [Hz], increasing, > 0 (at least 2).
    stiffness : (nf,) or (3, nf) array_like
        Dynamic (storage) stiffness ``k'`` [N/m], > 0 (every axis, or one row per axis).
    loss_factor : float, (nf,) or (3, nf) array_like
        Loss factor ``eta = tan(loss angle)`` [-], >= 0.
    band : (2,) array_like or None
        Band of the ladder fit [Hz]; default the table's.
    """

    kind: ClassVar[str] = "table"
    exact: ClassVar[bool] = False
    keys: ClassVar[tuple[str, ...]] = ("frequency", "stiffness", "loss_factor", "band")
    required: ClassVar[tuple[str, ...]] = ("frequency", "stiffness")
    frequency: Any = ()
    stiffness: Any = ()
    loss_factor: Any = 0.0
    band: Any = None
    _ladder: Any = field(default=None, init=False, repr=False)

    def __post_init__(self) -> None:
        who = self._who()
        if not is_numeric(self.frequency) or np.ndim(self.frequency) != 1:
            raise ModelError(f"{who}: frequency: expected a list of frequencies [Hz], got {self.frequency!r}")
        f = np.asarray(self.frequency, dtype=float)
        nf = f.size
        if nf < 2:
            raise ModelError(f"{who}: frequency: a table needs at least 2 points, got {nf}")
        if not np.all(np.isfinite(f)) or f[0] <= 0 or np.any(np.diff(f) <= 0):
            raise ModelError(f"{who}: frequency: expected increasing frequencies > 0 [Hz], got {f.tolist()}")
        k = self._rows(self.stiffness, "stiffness", nf, who)
        eta = self._rows(self.loss_factor, "loss_factor", nf, who)
        for name, a, ok, need in (("stiffness", k, k > 0, "positive (a passive mount has a positive "
                                   "stiffness)"),
                                  ("loss_factor", eta, eta >= 0, "not negative (a negative loss angle "
                                   "gives energy: not a passive mount)")):
            bad = ~np.isfinite(a) | ~ok
            if np.any(bad):
                j, i = (int(x[0]) for x in np.nonzero(bad))
                raise ModelError(f"{who}: {name} on axis {j + 1} at {f[i]:g} Hz is {float(a[j, i]):g}; it must be "
                                 f"{need}", argument=name, received=float(a[j, i]), expected=need)
        if nf < FEW_POINTS:
            warnings.warn(f"{who}: only {nf} points: the interpolation (PCHIP) and the fitted ladder "
                          "rest on little data", VibssWarning, stacklevel=4)
        for key, v in (("frequency", f), ("stiffness", k), ("loss_factor", eta)):
            v.setflags(write=False)
            object.__setattr__(self, key, v)
        object.__setattr__(self, "band", _band(self.band, who, (float(f[0]), float(f[-1]))))
        ladder = fit_ladder(lambda w: self._interpolate(w), self.band)
        if np.any(ladder.static <= 0):
            j = int(np.flatnonzero(ladder.static <= 0)[0])
            raise ModelError(f"{who}: axis {j + 1}: the fitted static stiffness is {ladder.static[j]:g} N/m; "
                             "a passive mount needs a positive static stiffness (no passive, causal "
                             f"ladder comes near the table at its lowest frequency, {f[0]:g} Hz)")
        if ladder.fit_error > FIT_WARN:
            warnings.warn(f"{who}: the fitted Maxwell ladder, which every analysis uses, is up to "
                          f"{100 * ladder.fit_error:.3g} % off the table over {self.band[0]:g} to "
                          f"{self.band[1]:g} Hz (a passive, causal stiffness cannot follow it closer: e.g. "
                          "a constant loss factor needs a stiffness rising with frequency)", VibssWarning,
                          stacklevel=4)
        object.__setattr__(self, "_ladder", ladder)

    @staticmethod
    def _rows(value: Any, key: str, nf: int, who: str) -> np.ndarray:
        if not is_numeric(value):
            raise ModelError(f"{who}: {key}: expected numbers, got {value!r}")
        a = np.asarray(value, dtype=float)
        if a.ndim == 0:
            a = np.full(nf, float(a))
        if a.ndim == 1 and a.size == nf:
            return np.broadcast_to(a, (3, nf)).copy()
        if a.shape == (3, nf):
            return a.copy()
        raise ModelError(f"{who}: {key}: expected {nf} values (one per frequency) or 3 rows of {nf} "
                         f"(one per axis), got shape {a.shape}")

    def _interpolate(self, omega: np.ndarray) -> np.ndarray:
        from scipy.interpolate import PchipInterpolator   # loads scipy.optimize: heavy at start-up

        x = np.log(np.clip(np.asarray(omega, float) / (2 * np.pi), self.frequency[0], self.frequency[-1]))
        lf = np.log(self.frequency)
        k = PchipInterpolator(lf, self.stiffness, axis=1)(x).T
        eta = PchipInterpolator(lf, self.loss_factor, axis=1)(x).T
        return k * (1 + 1j * eta)

    def dynamic_stiffness(self, omega: npt.ArrayLike) -> np.ndarray:
        w = np.atleast_1d(np.asarray(omega, dtype=float))
        f = w / (2 * np.pi)
        out = (f < self.frequency[0] * (1 - 1e-12)) | (f > self.frequency[-1] * (1 + 1e-12))
        if np.any(out):
            warnings.warn(f"{self._who()}: {int(out.sum())} frequencies outside the table "
                          f"({self.frequency[0]:g} to {self.frequency[-1]:g} Hz, e.g. {f[out][0]:g} Hz): "
                          "the end values are held (extrapolation)", VibssWarning, stacklevel=3)
        return self._interpolate(w)

    def ladder(self) -> Ladder:
        return self._ladder


@dataclass(frozen=True, eq=False)
class Hydraulic(Rheology):
    """Hydraulic mount: a rubber spring in parallel with a fluid column (the inertia track).

    ``k* = k_r + i w c_r + k_b P / (k_b + P)`` with ``P = -m_f w^2 + i w c_f``: the pumping chamber's
    bulge stiffness ``k_b`` drives the fluid's effective mass ``m_f`` through the track's damping
    ``c_f``. Below the track's resonance ``sqrt(k_b / m_f)`` the fluid flows (stiffness ``k_r``, with
    the notch just below it), above it the fluid is locked (``k_r + k_b``); the loss angle peaks near
    it and is never negative (passive). One internal coordinate with mass per axis with ``k_b > 0``,
    so the time domain, the damped modes and the state space carry it exactly.

    Parameters
    ----------
    k_r : float or (3,) array_like
        Rubber (static) stiffness per axis [N/m].
    k_b : float or (3,) array_like
        Bulge stiffness of the pumping chamber, referred to the mount's deflection [N/m]; 0: no fluid on
        that axis.
    m_f : float or (3,) array_like
        Effective mass of the fluid in the track, referred to the mount's deflection
        (``rho L A_p^2 / A_t``) [kg]; > 0 where ``k_b > 0``.
    c_f : float or (3,) array_like
        Damping of the track flow, referred to the deflection [N s/m].
    c_r : float or (3,) array_like
        Rubber damping per axis [N s/m] (default 0).
    """

    kind: ClassVar[str] = "hydraulic"
    keys: ClassVar[tuple[str, ...]] = ("k_r", "k_b", "m_f", "c_f", "c_r")
    required: ClassVar[tuple[str, ...]] = ("k_r", "k_b", "m_f", "c_f")
    k_r: Any = 0.0
    k_b: Any = 0.0
    m_f: Any = 0.0
    c_f: Any = 0.0
    c_r: Any = 0.0

    def __post_init__(self) -> None:
        who = self._who()
        for key in self.keys:
            object.__setattr__(self, key, _axes(getattr(self, key), who, key))
        bad = np.flatnonzero((self.k_b > 0) & (self.m_f <= 0))
        if bad.size:
            j = int(bad[0])
            raise ModelError(f"{who}: axis {j + 1}: m_f must be > 0 where k_b > 0 (the fluid in the track "
                             f"has mass); got m_f = {float(self.m_f[j])!r} kg")

    def dynamic_stiffness(self, omega: npt.ArrayLike) -> np.ndarray:
        w = np.atleast_1d(np.asarray(omega, dtype=float))[:, None]
        p = -self.m_f[None] * w * w + 1j * w * self.c_f[None]
        with np.errstate(invalid="ignore", divide="ignore"):
            branch = np.where(self.k_b[None] > 0, self.k_b[None] * p / (self.k_b[None] + p), 0.0)
        return self.k_r[None] + 1j * w * self.c_r[None] + branch

    def ladder(self) -> Ladder:
        kb = np.asarray(self.k_b, dtype=float)
        on = kb > 0
        safe = np.where(on, kb, 1.0)
        tau = np.where(on, np.asarray(self.c_f) / safe, 1.0)
        mu = np.where(on, np.asarray(self.m_f) / safe, 0.0)
        return Ladder(np.asarray(self.k_r), np.asarray(self.c_r), kb[:, None].copy(), tau[:, None], mu=mu[:, None])


QUANTITIES: dict[str, str] = {"k": "stiffness", "k_0": "stiffness", "k_inf": "stiffness", "stiffness": "stiffness",
                              "c": "damping", "tau": "time", "alpha": "dimensionless",
                              "loss_factor": "dimensionless", "frequency": "frequency", "band": "frequency",
                              "k_r": "stiffness", "k_b": "stiffness", "c_r": "damping", "c_f": "damping",
                              "m_f": "mass"}
"""What each rheology key measures (a model file writes it in its units of that; frequencies in Hz)."""

RHEOLOGIES: dict[str, type[Rheology]] = {c.kind: c for c in (KelvinVoigt, Zener, Prony, FractionalZener, Table,
                                                               Hydraulic)}
"""Rheological models by ``type`` name."""


def parse_rheology(spec: Any, owner: str = "") -> Rheology:
    """A :class:`Rheology` from a mapping ``{"type": name, key: value ...}`` (or one already made).

    Parameters
    ----------
    spec : mapping or Rheology
        ``type`` one of :data:`RHEOLOGIES`, and that model's keys (SI).
    owner : str
        The mount type's name, for messages.

    Returns
    -------
    Rheology

    Raises
    ------
    ModelError
        Unknown type or key, a missing key, or bad values (named).
    """
    who = f"mount type {owner!r}: rheology" if owner else "rheology"
    if isinstance(spec, Rheology):
        return spec if spec.owner == owner else type(spec)(**{k: getattr(spec, k) for k in spec.keys}, owner=owner)
    if not isinstance(spec, Mapping):
        raise ModelError(f"{who}: expected a table {{'type': ..., ...}} with type one of {list(RHEOLOGIES)}, "
                         f"got {spec!r}")
    kind = spec.get("type")
    if kind not in RHEOLOGIES:
        from ..errors import did_you_mean
        raise ModelError(f"{who}: type: unknown {kind!r}{did_you_mean(kind, list(RHEOLOGIES)) if isinstance(kind, str) else ''}; "
                         f"expected one of {list(RHEOLOGIES)}")
    cls = RHEOLOGIES[kind]
    keys = {k: v for k, v in spec.items() if k != "type"}
    unknown = sorted(set(keys) - set(cls.keys))
    missing = [k for k in cls.required if k not in keys]
    if unknown or missing:
        raise ModelError(f"{who} {kind!r}: " + (f"unknown key(s) {unknown}; " if unknown else "")
                         + (f"missing key(s) {missing}; " if missing else "") + f"keys are {list(cls.keys)}")
    return cls(**keys, owner=owner)


def fit_ladder(target: Any, band: npt.ArrayLike, static: np.ndarray | None = None,
               per_decade: int = PER_DECADE, parts: bool = False) -> Ladder:
    """Fit a passive Maxwell ladder to a complex stiffness over a band.

    Relaxation times are fixed, ``per_decade`` per decade from ``1 / w1`` down to half a decade
    beyond ``1 / w2`` (none slower than the band when ``k_0`` is fitted, so the static stiffness stays
    the ladder's own rather than a slow branch's; a decade slower when ``static`` is given); the branch stiffnesses (and ``k_0`` unless given) are the non-negative least-squares
    solution of the real and imaginary parts at 400 log-spaced frequencies, each weighted by
    ``1 / |k*|`` (relative error). Non-negative terms make the ladder passive and stable.

    Parameters
    ----------
    target : callable
        ``omega (nf,) [rad/s] -> (nf, 3)`` complex stiffness [N/m].
    band : (2,) array_like
        [f1, f2] [Hz], 0 < f1 < f2.
    static : (3,) ndarray or None
        Static stiffness to keep (fractional Zener: exactly ``k_0``); None: fitted, >= 0.
    per_decade : int
        Relaxation times per decade.
    parts : bool
        Weight the storage and the loss part each by its own size (relative errors of ``k'`` and
        of ``k''`` balanced) instead of both by ``1 / |k*|``, which lets a small loss part go: a
        constant loss factor of 0.1 fitted by ``|k*|`` keeps only 0.04 of it mid-band.

    Returns
    -------
    Ladder
        With ``fit_error`` the largest relative error over the band (on a grid twice as fine).

    Examples
    --------
    A Zener stiffness whose relaxation time falls between the ladder's is reproduced to a few per
    cent; a constant loss factor is not causal, so over two decades the best passive ladder is some
    5 % off (a causal storage stiffness must rise with frequency):

    >>> z = Zener(1e4, 3e4, 1e-2)
    >>> bool(fit_ladder(z.dynamic_stiffness, [0.1, 1000.0], static=z.k_0).fit_error < 0.03)
    True
    >>> round(fit_ladder(lambda w: np.full((np.size(w), 3), 1e4 * (1 + 0.05j)), [1.0, 100.0]).fit_error, 2)
    0.05
    """
    from scipy.optimize import nnls      # heavy at start-up (tests/project/test_startup.py); only fits need it

    b = np.asarray(band, dtype=float)
    w1, w2 = 2 * np.pi * b[0], 2 * np.pi * b[1]
    below = 0.0 if static is None else 1.0
    decades = np.log10(w2 / w1) + 0.5 + below
    nb = max(int(np.ceil(decades * per_decade)), 1)
    tau = 1.0 / np.logspace(np.log10(w1) - below, np.log10(w2) + 0.5, nb)
    w = np.logspace(np.log10(w1), np.log10(w2), _FIT_POINTS)
    kt = np.asarray(target(w))
    s = 1j * w[:, None] * tau[None]
    basis = s / (1 + s)                                   # (nf, nb) per unit branch stiffness
    k0 = np.zeros(3)
    kb = np.zeros((3, nb))
    for j in range(3):
        size = np.maximum(np.abs(kt[:, j]), np.finfo(float).tiny)
        weight_re = weight_im = 1.0 / size
        if parts:       # each part relative to itself (a lossless axis: its loss held near zero)
            weight_re = 1.0 / np.maximum(np.abs(kt[:, j].real), 1e-3 * size)
            weight_im = 1.0 / np.maximum(np.abs(kt[:, j].imag), 1e-3 * size)
        if static is None:
            a = np.hstack([np.ones((w.size, 1)), basis])
            rhs = kt[:, j]
        else:
            a, rhs = basis, kt[:, j] - static[j]
        x, _ = nnls(np.vstack([a.real * weight_re[:, None], a.imag * weight_im[:, None]]),
                    np.concatenate([rhs.real * weight_re, rhs.imag * weight_im]), maxiter=50 * a.shape[1])
        if static is None:
            k0[j], kb[j] = x[0], x[1:]
        else:
            k0[j], kb[j] = static[j], x
    lad = Ladder(k0, np.zeros(3), kb, np.broadcast_to(tau, (3, nb)).copy(), band=b)
    check = np.logspace(np.log10(w1), np.log10(w2), 2 * _FIT_POINTS)
    ref = np.asarray(target(check))
    err = np.abs(lad.stiffness(check) - ref) / np.maximum(np.abs(ref), np.finfo(float).tiny)
    return Ladder(k0, np.zeros(3), kb, lad.tau, fit_error=float(err.max()), band=b)
