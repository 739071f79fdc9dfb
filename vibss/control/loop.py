"""Closing loops on named plants: the closed loop, its poles and damping, and per-loop margins.

Convention: a controller maps measurements to actuator commands, ``u = K y`` (its sign included:
velocity feedback is ``u = -g v``). Signals are matched **by name**: the controller's inputs must be
outputs of the plant and its outputs inputs of the plant, in either spelling and any order.

Margins are loop-at-a-time at the plant input: loop ``i`` is broken at its actuator command with
every other loop closed, and the return ratio ``L_i = -u_i / r_i`` gives the gain and phase margins
(crossovers found on a dense grid and refined by Brent's method; they equal python-control's
``stability_margins``, which fails on high-order loops) and the balanced disk margin
``alpha = 1 / max |S - 1/2|`` (skew 0, as python-control's ``disk_margins``: a simultaneous gain
and phase change that keeps the loop stable). The MIMO disk margin is
the balanced disk margin of all loops at once, bounded from below by ``1 / max sigma(S - I/2)``
(``S`` the input sensitivity; ``S - I/2 = (S - T)/2``; exact for one loop, conservative for several).
"""

from __future__ import annotations

import warnings

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import ControlDesignError, ModelError, SignalError, VibssWarning, did_you_mean
from ..linear.eigen.small import state_eigenvalues
from ..linear.plant.labels import control_name
from ..linear.statespace import NamedStateSpace
from ..results import Result, TextTable
from .plant import vibss_name

__all__ = ["close", "ClosedLoop", "Controller", "LoopMargins", "interconnect_indices"]


class Controller(NamedStateSpace):
    """A named controller ``u = K y``: inputs are measurement names, outputs actuator commands.

    Attributes
    ----------
    design : dict
        What made it (``{"design": "skyhook", "gains": ...}``), printed by :meth:`summary`.
    """

    design: dict[str, Any]

    def summary(self) -> str:
        """One line per design parameter."""
        info = getattr(self, "design", {})
        lines = [f"controller {self.name}: {info.get('design', 'user')} "
                 f"({self.ninputs} measurements -> {self.noutputs} commands, {self.nstates} states)"]
        for k, v in info.items():
            if k == "design" or isinstance(v, np.ndarray):
                continue
            if isinstance(v, dict) and len(v) > 3:
                vals = list(v.values())
                if all(x == vals[0] for x in vals):
                    v = f"{vals[0]} on each of {len(v)} loops"
                else:
                    v = ", ".join(f"{a}: {b}" for a, b in list(v.items())[:3]) + f", ... ({len(v)} in all)"
            lines.append(f"  {k}: {v}")
        return "\n".join(lines)


def controller(A: Any, B: Any, C: Any, D: Any, inputs: Sequence[str], outputs: Sequence[str],
               design: dict[str, Any], name: str = "controller", states: Sequence[str] | None = None) -> Controller:
    """A :class:`Controller` from matrices and vibss signal names."""
    k = Controller(A, B, C, D, inputs=[control_name(s) for s in inputs],
                   outputs=[control_name(s) for s in outputs], name=name,
                   **({"states": list(states)} if states is not None else {}))
    k.design = design
    return k


def interconnect_indices(labels: Sequence[str], wanted: Sequence[str], what: str) -> list[int]:
    """Positions of signal names (either spelling) among python-control labels."""
    out = []
    for s in wanted:
        c = control_name(s)
        if c not in labels:
            vib = [vibss_name(x) for x in labels]
            raise SignalError(f"{what}: no signal named {vibss_name(s)!r}" + did_you_mean(vibss_name(s), vib)
                              + f"; they are {vib}", argument=what, received=s, expected=tuple(vib))
        out.append(list(labels).index(c))
    return out


def _close(plant: Any, k: Any, fed: Sequence[int] | None = None) -> tuple[np.ndarray, ...]:
    """State-space matrices of the loop ``u = K y`` closed on the plant.

    Returns ``(A, B, C, D, ext, iy, iu)``: inputs are the plant inputs not driven by the controller
    plus the driven ones that are not ``fed`` back (loop broken there), outputs every plant output
    followed by every controller output.
    """
    iy = interconnect_indices(plant.output_labels, k.input_labels, "controller inputs (measurements)")
    iu = interconnect_indices(plant.input_labels, k.output_labels, "controller outputs (commands)")
    fed_set = set(range(len(iu))) if fed is None else set(fed)
    fb = [j for j in range(len(iu)) if j in fed_set]
    ext = [i for i in range(plant.ninputs) if i not in [iu[j] for j in fb]]
    A, B, C, D = (np.asarray(x, dtype=float) for x in (plant.A, plant.B, plant.C, plant.D))
    Ak, Bk, Ck, Dk = (np.asarray(x, dtype=float).reshape(s) for x, s in (
        (k.A, (k.nstates, k.nstates)), (k.B, (k.nstates, k.ninputs)), (k.C, (k.noutputs, k.nstates)),
        (k.D, (k.noutputs, k.ninputs))))
    # only fed commands enter the plant from the controller
    S = np.zeros((plant.ninputs, k.noutputs))
    for j in fb:
        S[iu[j], j] = 1.0
    Bu, Du = B @ S, D @ S
    Be, De = B[:, ext], D[:, ext]
    Cy, Dyu, Dye = C[iy], Du[iy], De[iy]
    F = np.eye(k.noutputs) - Dk @ Dyu
    if np.linalg.cond(F) > 1e12:
        raise ControlDesignError("the loop is ill-posed: I - K D22 is singular (the controller's direct "
                                 "feedthrough cancels the plant's)")
    E = np.linalg.inv(F)
    ux, uxk, ue = E @ Dk @ Cy, E @ Ck, E @ Dk @ Dye
    yx, yxk, ye = Cy + Dyu @ ux, Dyu @ uxk, Dye + Dyu @ ue
    n, nk = A.shape[0], Ak.shape[0]
    Acl = np.block([[A + Bu @ ux, Bu @ uxk], [Bk @ yx, Ak + Bk @ yxk]])
    Bcl = np.vstack([Be + Bu @ ue, Bk @ ye])
    Ccl = np.vstack([np.hstack([C + Du @ ux, Du @ uxk]), np.hstack([ux, uxk])])
    Dcl = np.vstack([De + Du @ ue, ue])
    return Acl.reshape(n + nk, n + nk), Bcl, Ccl, Dcl, np.array(ext, dtype=int), np.array(iy), np.array(iu)


@dataclass(frozen=True)
class LoopMargins:
    """Stability margins of one loop (broken at its actuator command, the others closed).

    Attributes
    ----------
    loop : str
        The actuator command (vibss spelling).
    gain_margin_db : float
        Gain margin [dB] (inf: no phase crossover).
    phase_margin_deg : float
        Phase margin [deg] (inf: no gain crossover): the smallest phase change, lag or lead, that
        puts ``L`` on -1 at a gain crossover.
    disk_margin : float
        Balanced disk margin alpha [-].
    disk_gain_margin_db, disk_phase_margin_deg : float
        The gain [dB] and phase [deg] variations the disk margin guarantees together.
    """

    loop: str
    gain_margin_db: float
    phase_margin_deg: float
    disk_margin: float
    disk_gain_margin_db: float
    disk_phase_margin_deg: float


@dataclass(frozen=True, eq=False)
class ClosedLoop(Result):
    """A closed loop: the named system, its poles and damping, margins per loop.

    Attributes
    ----------
    system : NamedStateSpace
        Inputs: the plant's disturbances; outputs: every plant output, then the commands.
    plant, controller : NamedStateSpace
        What was closed.
    poles : (N,) complex ndarray
        Closed-loop poles [rad/s] (ascending natural frequency).
    margins : tuple of LoopMargins
        Per loop.
    mimo_disk_margin : float
        Balanced disk margin of all loops at once (a lower bound, see the module docstring).
    peak_sensitivity : float
        Largest singular value of the input sensitivity ``(I - K P)^-1`` over the grid [-].
    """

    system: Any
    plant: Any
    controller: Any
    poles: np.ndarray
    margins: tuple[LoopMargins, ...]
    mimo_disk_margin: float
    peak_sensitivity: float
    name: str = "closed loop"
    outputs: tuple[str, ...] = field(default=())

    @property
    def output_labels(self) -> tuple[str, ...]:
        """Output signal names (vibss spelling): the plant's outputs, then the commands."""
        return self.outputs

    @property
    def input_labels(self) -> tuple[str, ...]:
        """Input signal names (vibss spelling): the disturbances."""
        return tuple(vibss_name(s) for s in self.system.input_labels)

    @property
    def control(self) -> Any:
        """The closed loop as a python-control system (:attr:`system`)."""
        return self.system

    @property
    def frequency_hz(self) -> np.ndarray:
        """(N,) natural frequency of each pole [Hz]."""
        return np.abs(self.poles) / (2 * np.pi)

    @property
    def damping(self) -> np.ndarray:
        """(N,) damping ratio of each pole [-] (1 for real stable poles)."""
        mag = np.abs(self.poles)
        return np.where(mag > 0, -self.poles.real / np.where(mag > 0, mag, 1.0), 1.0)

    def _item(self, i: int, j: int | None) -> Any:
        return self.system[i, :] if j is None else self.system[i, j]

    def transmissibility(self, inputs: Sequence[str], outputs: Sequence[str],
                         frequencies: Any = None) -> tuple[Any, Any]:
        """Passive (actuators off: the plant with ``u = 0``) and closed-loop transmissibility.

        Parameters
        ----------
        inputs, outputs : sequence of str
            Disturbances and outputs (see :func:`vibss.transmissibility`).
        frequencies : array_like or None
            [Hz]; default: a grid around the closed-loop poles.

        Returns
        -------
        (FrequencyResponse, FrequencyResponse)
            Passive, then active, on the same frequencies.
        """
        from ..frequency.sweep import transmissibility

        active = transmissibility(self.system, inputs, outputs, frequencies)
        passive_sys = NamedStateSpace(self.plant.A, self.plant.B, self.plant.C, self.plant.D,
                                      inputs=self.plant.input_labels, outputs=self.plant.output_labels,
                                      states=self.plant.state_labels, name=f"{self.plant.name}:passive")
        passive_sys.vibss_units = getattr(self.system, "vibss_units", {})
        passive = transmissibility(passive_sys, inputs, outputs, active.frequency_hz)
        return passive, active

    def demand(self, environment: Any, outputs: Sequence[str] | None = None, **kwargs: Any) -> Any:
        """RMS under PSDs, or peaks under shocks, of the outputs and actuator commands
        (:func:`vibss.control.demand.demand`)."""
        from .demand import demand

        return demand(self, environment, outputs, **kwargs)

    def noise_budget(self, outputs: Sequence[str], frequencies: Any, *, ground: Any = None,
                     disturbances: Any = None, noise: Any = None) -> Any:
        """Each sensor noise's PSD contribution to the outputs beside the ground motion's, with RMS
        values (:func:`vibss.control.noise.noise_budget`).

        Parameters
        ----------
        outputs : sequence of str
            Output signals (payload motion, commands).
        frequencies : array_like
            Frequencies [Hz], increasing.
        ground : PSD spec or None
            PSD of the plant's ground motion [unit^2/Hz] (constant, function of frequency, or table).
        disturbances : mapping or None
            ``{disturbance: PSD spec}`` instead of ``ground``.
        noise : mapping or None
            ``{measurement: PSD spec}``, overriding the sensors' own ``noise``.
        """
        from .noise import noise_budget

        return noise_budget(self, outputs, frequencies, ground=ground, disturbances=disturbances, noise=noise)

    def plot_transmissibility(self, inputs: Sequence[str], outputs: Sequence[str], frequencies: Any = None,
                              ax: Any = None) -> Any:
        """One figure: passive and closed-loop transmissibility magnitude [dB] against frequency [Hz]."""
        from ..plotting.control import plot_transmissibility

        passive, active = self.transmissibility(inputs, outputs, frequencies)
        return plot_transmissibility(passive, active, ax=ax, title=self.name)

    def summary(self) -> TextTable:
        """Poles with frequency [Hz] and damping ratio, one per oscillating pair."""
        keep = self.poles.imag >= 0
        rows = [(f"{f:.4g}", f"{z:.4f}", f"{p.real:.4g}{p.imag:+.4g}j")
                for p, f, z in zip(self.poles[keep], self.frequency_hz[keep], self.damping[keep])]
        return TextTable(("frequency [Hz]", "damping ratio [-]", "pole [rad/s]"), rows,
                     title=f"{self.name}: closed-loop poles")

    def margin_table(self) -> TextTable:
        """Gain, phase and disk margins per loop."""
        rows = [(m.loop, _fmt(m.gain_margin_db), _fmt(m.phase_margin_deg), f"{m.disk_margin:.3g}",
                 _fmt(m.disk_gain_margin_db), _fmt(m.disk_phase_margin_deg)) for m in self.margins]
        return TextTable(("loop", "gain margin [dB]", "phase margin [deg]", "disk margin [-]",
                      "disk gain [dB]", "disk phase [deg]"), rows, title=f"{self.name}: loop margins")

    def report(self) -> str:
        """Poles, damping and margins as text."""
        return (f"{self.summary()}\n\n{self.margin_table()}\nMIMO disk margin (lower bound): "
                f"{self.mimo_disk_margin:.3g}; peak input sensitivity {self.peak_sensitivity:.3g} "
                f"({20 * np.log10(self.peak_sensitivity):.2f} dB)")

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready poles, damping and margins (SI)."""
        keep = self.poles.imag >= 0
        return {"poles": [{"frequency_hz": float(f), "damping_ratio": float(z)}
                          for f, z in zip(self.frequency_hz[keep], self.damping[keep])],
                "margins": [{k: (v if isinstance(v, str) else _json(v)) for k, v in vars(m).items()}
                            for m in self.margins],
                "mimo_disk_margin": _json(self.mimo_disk_margin),
                "peak_sensitivity": _json(self.peak_sensitivity)}


def _fmt(x: float) -> str:
    return "inf" if not np.isfinite(x) else f"{x:.3g}"


def _json(x: float) -> float | None:
    return float(x) if np.isfinite(x) else None


class _Loops:
    """Loop-at-a-time return ratios ``L_i(i w)`` at the plant input, from ``Q = K(i w) G(i w)``
    (``G`` the plant from commands to measurements): with loop ``i`` broken and the others closed,
    ``L_i = -(Q_ii + Q_io (I - Q_oo)^-1 Q_oi)``."""

    def __init__(self, plant: Any, k: Any, iy: np.ndarray, iu: np.ndarray) -> None:
        from ..frequency.statespace_response import Evaluator

        self.G = Evaluator(plant, outputs=list(iy), inputs=list(iu))
        self.K = Evaluator(k)

    def q(self, omega: np.ndarray) -> np.ndarray:
        return np.einsum("ijf,jkf->fik", self.K(omega), self.G(omega))     # (nf, nu, nu)

    @staticmethod
    def loop(i: int, q: np.ndarray) -> np.ndarray:
        """(nf,) return ratio ``L_i`` of loop ``i`` from ``q = K G`` (nf, nu, nu), the others closed."""
        n = q.shape[1]
        o = [j for j in range(n) if j != i]
        if not o:
            return -q[:, i, i]
        qoo = np.eye(n - 1)[None] - q[:, o][:, :, o]
        x = np.linalg.solve(qoo, q[:, o][:, :, [i]])
        return -(q[:, i, i] + (q[:, [i]][:, :, o] @ x)[:, 0, 0])

    def at(self, i: int, w: float) -> complex:
        return complex(self.loop(i, self.q(np.array([w])))[0])


def _grid(poles: np.ndarray, extra: np.ndarray) -> np.ndarray:
    """Frequencies [rad/s] dense around every pole and across the band."""
    mags = np.abs(np.concatenate([poles, extra]))
    mags = mags[mags > 0]
    lo = mags.min() / 100 if mags.size else 1e-2
    hi = mags.max() * 100 if mags.size else 1e4
    base = np.geomspace(lo, hi, 800)
    osc = [p for p in poles if abs(p) > 0 and p.imag > 0]
    osc = sorted(osc, key=lambda p: abs(p.real) / abs(p))[:100]        # the 100 most lightly damped
    near = [np.abs(p) * (1 + np.linspace(-3, 3, 31) * max(min(abs(p.real) / max(abs(p), 1e-300), 0.3), 1e-4))
            for p in osc]
    return np.unique(np.concatenate([base, *near])) if near else base


def _margins(lw: np.ndarray, omega: np.ndarray, at: Any, loop: str) -> LoopMargins:
    """Gain, phase and balanced disk margins of a SISO return ratio ``lw`` on ``omega`` [rad/s]
    (``at(w)`` evaluates it anywhere), with every crossover refined by Brent's method. python-control's ``stability_margins`` converts a state
    space to polynomials, which overflow for loops of more than a few dozen states (measured: NaN
    and an IndexError on the 12-loop platform)."""
    from scipy.optimize import brentq

    mag = np.abs(lw)
    pm = np.inf
    logm = np.log(np.maximum(mag, 1e-300))
    for i in np.flatnonzero(np.sign(logm[:-1]) * np.sign(logm[1:]) < 0):
        wc = brentq(lambda w: np.log(max(abs(at(w)), 1e-300)), omega[i], omega[i + 1], xtol=1e-12 * omega[i])
        pm = min(pm, 180.0 - abs(float(np.degrees(np.angle(at(wc))))))
    gm_db = np.inf
    im = lw.imag
    for i in np.flatnonzero(np.sign(im[:-1]) * np.sign(im[1:]) < 0):
        if lw.real[i] >= 0 and lw.real[i + 1] >= 0:
            continue
        wp = brentq(lambda w: at(w).imag, omega[i], omega[i + 1], xtol=1e-12 * omega[i])
        lp = at(wp)
        if lp.real < 0:
            g = -20 * np.log10(abs(lp))
            gm_db = g if abs(g) < abs(gm_db) else gm_db
    with np.errstate(divide="ignore", invalid="ignore"):
        sens = 1.0 / (1.0 + lw)
    worst = float(np.max(np.abs(sens - 0.5)))
    alpha = 1.0 / worst if worst > 0 else np.inf
    if alpha < 2:
        dgm = 20 * np.log10((1 + alpha / 2) / (1 - alpha / 2))
    else:
        dgm = np.inf
    dpm = float(np.degrees(2 * np.arctan(alpha / 2))) if np.isfinite(alpha) else 180.0
    return LoopMargins(vibss_name(loop), float(gm_db), float(pm), float(alpha), float(dgm), dpm)


def close(plant: Any, controller: Any, *, margins: bool = True, allow_unstable: bool = False,
          name: str | None = None) -> ClosedLoop:
    """Close ``u = K y`` on a named plant; poles, damping and margins, stability checked first.

    Parameters
    ----------
    plant : NamedStateSpace or control.StateSpace
        A :func:`vibss.control.plant` (or any system whose signals carry names).
    controller : control.StateSpace
        Inputs named after plant outputs, outputs after plant inputs (either spelling).
    margins : bool
        Compute the loop margins (python-control ``stability_margins`` and ``disk_margins``).
    allow_unstable : bool
        Return an unstable loop instead of raising (for studies of the instability itself).
    name : str or None
        Name of the closed loop (default ``"<plant> (closed loop)"``: it titles its figures and tables).

    Returns
    -------
    ClosedLoop

    Raises
    ------
    ControlDesignError
        An ill-posed loop, or an unstable one (names the pole).
    SignalError
        A controller signal that is not a plant signal.
    """
    if plant.dt not in (0, None) or controller.dt not in (0, None):
        raise ModelError("close: continuous-time systems only (dt = 0)")
    A, B, C, D, ext, iy, iu = _close(plant, controller)
    poles = state_eigenvalues(A)
    poles = poles[np.lexsort((poles.imag, np.abs(poles)))]
    tol = 1e-9 * max(np.abs(poles).max(initial=1.0), 1.0)
    unstable = poles[poles.real > tol]
    nm = name or f"{plant.name} (closed loop)"
    if unstable.size and not allow_unstable:
        p = unstable[np.argmax(unstable.real)]
        raise ControlDesignError(f"{nm}: the closed loop is unstable: pole at s = {p.real:.4g}{p.imag:+.4g}j "
                                 f"rad/s ({abs(p) / (2 * np.pi):.4g} Hz); reduce the gains or check the "
                                 "feedback signs (u = K y: negative feedback has K < 0)")
    ins = [plant.input_labels[i] for i in ext]
    outs = list(plant.output_labels) + [f"{lab}" if lab not in plant.output_labels else f"{lab}:cmd"
                                        for lab in controller.output_labels]
    states = list(plant.state_labels) + [f"{controller.name}:{s}" for s in controller.state_labels]
    sys = NamedStateSpace(A, B, C, D, inputs=ins, outputs=outs, states=states, name=nm)
    units = dict(getattr(plant, "units", {}) or {})
    units.update({vibss_name(o): units.get(vibss_name(o[:-4] if o.endswith(":cmd") else o), "N")
                  for o in outs[plant.noutputs:]})
    sys.vibss_units = units
    loops: list[LoopMargins] = []
    dm, peak = np.nan, np.nan
    if margins:
        ol_poles = state_eigenvalues(plant.A)
        omega = _grid(np.concatenate([poles, ol_poles]), np.zeros(0))
        lp = _Loops(plant, controller, iy, iu)
        q = lp.q(omega)
        for i, lab in enumerate(controller.output_labels):
            loops.append(_margins(lp.loop(i, q), omega, lambda w, i=i: lp.at(i, w), lab))
        dm, peak = _mimo(q)
        _warn_fragile(nm, loops, dm)
    return ClosedLoop(sys, plant, controller, poles, tuple(loops), dm, peak, nm,
                      tuple(vibss_name(o) for o in outs))


FRAGILE_DISK = 0.5
"""A loop whose balanced disk margin is below this is fragile: it tolerates less than about +/-4.4 dB
and 28 deg together (``alpha = 0.5``), less than plant tolerances and actuator lags take away."""

FRAGILE_GAIN_DB = 6.0
"""Classical gain margin below which a loop is fragile [dB] (either sign: a gain decrease too)."""

FRAGILE_PHASE_DEG = 30.0
"""Classical phase margin below which a loop is fragile [deg]."""


def _warn_fragile(name: str, loops: list[LoopMargins], mimo: float) -> None:
    """One VibssWarning naming every fragile loop and its margins (an H-infinity design closed on the
    full plant once had a 2.66 dB gain margin and a disk margin of 0.3, and nothing said so)."""
    bad = []
    for lm in loops:
        why = [f"gain margin {lm.gain_margin_db:.3g} dB" if abs(lm.gain_margin_db) < FRAGILE_GAIN_DB else "",
               f"phase margin {lm.phase_margin_deg:.3g} deg" if abs(lm.phase_margin_deg) < FRAGILE_PHASE_DEG else "",
               f"disk margin {lm.disk_margin:.3g}" if lm.disk_margin < FRAGILE_DISK else ""]
        why = [w for w in why if w]
        if why:
            bad.append(f"loop {lm.loop!r}: {', '.join(why)}")
    if len(loops) > 1 and mimo < FRAGILE_DISK:
        bad.append(f"all loops at once: disk margin {mimo:.3g}")
    if bad:
        warnings.warn(f"close: {name}: a fragile loop ({'; '.join(bad)}; fragile below {FRAGILE_GAIN_DB:g} dB, "
                      f"{FRAGILE_PHASE_DEG:g} deg or a disk margin of {FRAGILE_DISK:g}): lower the gains, add "
                      "phase lead, or check it against the plant's tolerances", VibssWarning, stacklevel=3)


def _mimo(q: np.ndarray) -> tuple[float, float]:
    """Balanced MIMO disk margin lower bound ``1 / max sigma(S - I/2)`` and the peak of
    ``sigma(S)``, ``S = (I - K G)^-1`` the input sensitivity, over the grid of ``q = K G``."""
    nu = q.shape[1]
    S = np.linalg.inv(np.eye(nu)[None] - q)
    worst = float(np.linalg.svd(S - 0.5 * np.eye(nu)[None], compute_uv=False)[:, 0].max())
    peak = float(np.linalg.svd(S, compute_uv=False)[:, 0].max())
    return (1.0 / worst if worst > 0 else np.inf), peak
