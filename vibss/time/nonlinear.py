"""The time response of a model with nonlinear mounts (stops, force-deflection curves).

:func:`vibss.time.simulate` comes here when the model has nonlinear mounts. The linear part of the
model (each nonlinear axis at the rate the assembly used, :func:`linear_part`) is a plant like any
other; on each nonlinear axis a local force ``g`` adds what the law gives beyond that rate
(:mod:`vibss.time.kernels.laws`). The plant is augmented by one force input per nonlinear axis (its
generalised force ``-B_a^T``) and by the axis's deflection and velocity as outputs; the response is
the linear part (the exact modal method, :func:`vibss.time.kernels.run_modal`) plus the response to
the local forces (:func:`vibss.time.kernels.contact.integrate`).

The state starts at the operating point (:func:`vibss.operating_point`: the static equilibrium under
gravity and the model's static loads, stops and curves included); outputs are the motion from there,
as the linear :func:`~vibss.time.simulate` gives the motion from the static state (it leaves gravity
out), and ``initial`` conditions are from there too. The contacts table reads the total deflections.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import ModelError
from ..linear.eigen.basis import modal_basis
from ..linear.plant.build import build_plant
from ..linear.plant.names import default_outputs
from ..linear.plant.plant import Plant
from ..model.model import Model
from ..model.mounts import MountType
from ..nonlinear.api import operating_point
from ..nonlinear.kernels import _laws, nonlinear_axes, nonlinear_mounts, tangent_model
from ..linear.plant.assemble import assemble
from .kernels import make_grid, prepare, run_modal
from .kernels.contact import ContactRun, ContactSystem, integrate
from .kernels.laws import LocalLaws
from .kernels.modal import _modal_sets, channels
from .result import ContactTable

if TYPE_CHECKING:
    from .methods import NonlinearJob

__all__ = ["linear_part", "nonlinear_job", "run_nonlinear", "contact_table", "THETA", "step_limit", "substeps"]

THETA = 0.2
"""Largest ``omega_c h`` of the contact integration's first try at ``rtol = 1e-6`` (``omega_c``: a stop's
contact frequency on the local apparent mass, an upper bound; fourth order: ``theta`` scales as
``(rtol / 1e-6)^(1/4)``). Measured: a 1-DOF stop needs about 0.09 for 1e-6, a stop on a 600-DOF chain
0.3; ``auto`` reruns with the steps the check asks for where this misses."""


def linear_part(model: Model) -> Model:
    """The model with every nonlinear mount at the linear rates the assembly uses (stops open,
    curves at their slope at zero): the plant the time response propagates exactly."""
    idx = nonlinear_mounts(model)
    return tangent_model(model, np.zeros((len(idx), 3)), np.array(idx, int)) if idx else model


_MOTIONS = frozenset({"x", "y", "z", "rx", "ry", "rz", "vel", "acc", "dx", "dy", "dz", "d1", "d2", "d3",
                      "r1", "r2", "r3"})
"""Last parts of output names that are motions (no mount force in them): :func:`_force_rows` skips them."""


def _force_rows(model: Model, lin: Model, axes: list[tuple[int, int]], inputs: list[Any], outputs: list[str],
                plant: Plant, r: int) -> np.ndarray:
    """(p, r) output per unit local force: the user outputs that are mount forces (or sums of them)
    through a nonlinear axis carry its force beyond the linear rate too. Found by doubling the
    axes' linear rates: the outputs that change are those forces."""
    p = len(outputs)
    if not p or all(o.rsplit(".", 1)[-1] in _MOTIONS and not o.startswith("sensor.") for o in outputs):
        return np.zeros((p, r))
    new = list(lin.mounts)
    bump: dict[int, np.ndarray] = {}
    for p_, j in axes:
        bump.setdefault(p_, np.zeros(3))[j] = 1.0
    for p_, b in bump.items():
        m = new[p_]
        t = m.type
        new[p_] = dataclasses.replace(m, type=MountType(t.name + "+", np.asarray(t.stiffness) * (1 + b),
                                      damping=t.damping, loss_factor=t.loss_factor,
                                      rotational_stiffness=t.rotational_stiffness,
                                      rotational_damping=t.rotational_damping))
    twice = build_plant(dataclasses.replace(lin, mounts=tuple(new)), inputs, outputs)
    delta = np.asarray(twice.Oq, float) - np.asarray(plant.Oq, float)[:p]
    if not np.any(delta):
        return np.zeros((p, r))
    k0 = np.array([lin.mounts[p_].type.stiffness[j] for p_, j in axes], float)
    basis = k0[:, None] * np.asarray(plant.Oq, float)[p:p + r]          # (r, n)
    L, *_ = np.linalg.lstsq(basis.T, delta.T, rcond=None)
    if np.abs(L.T @ basis - delta).max() > 1e-8 * np.abs(delta).max():
        rows = [outputs[i] for i in np.flatnonzero(np.any(delta != 0, axis=1))]
        raise ModelError(f"simulate: outputs {rows} are forces through nonlinear mounts whose axes cannot be "
                         "told apart (two nonlinear axes deflect alike); ask for the mounts' own force outputs "
                         "(mount.<name>.f1|f2|f3)", argument="outputs", received=rows)
    return np.asarray(L.T)


def _augmented(plant: Plant, r: int, D: np.ndarray) -> Plant:
    """The plant with one force input per nonlinear axis (generalised force ``-B_a^T``, direct
    feedthrough ``D`` into the user outputs) and each axis's velocity and acceleration appended to its
    deflection (the rows after the user's outputs: deflections, velocities, accelerations)."""
    p = len(plant.outputs) - r
    n, m = plant.n, len(plant.inputs)
    Od = np.asarray(plant.Oq, float)[p:]
    Pz, Pv = np.asarray(plant.Pz, float), np.asarray(plant.Pv, float)
    zc, zr = np.zeros((n, r)), np.zeros((r, n))

    def io(a: np.ndarray, extra: np.ndarray | None = None) -> np.ndarray:     # outputs x inputs
        a = np.hstack([np.asarray(a, float), np.zeros((p + r, r)) if extra is None else extra])
        return np.vstack([a, np.zeros((2 * r, m + r))])

    def ox(a: np.ndarray, v: np.ndarray, acc: np.ndarray) -> np.ndarray:     # outputs x DOFs
        return np.vstack([np.asarray(a, float), v, acc])

    Pv_new, Pa_new = io(Pv), io(plant.Pa)
    Pv_new[p + r:p + 2 * r, :m] = Pz[p:]
    Pa_new[p + r:p + 2 * r, :m] = Pv[p:]
    Pa_new[p + 2 * r:, :m] = Pz[p:]
    names = plant.outputs[p:]
    return Plant(
        dofs=plant.dofs, M=plant.M, C=plant.C, K=plant.K, H=plant.H,
        inputs=plant.inputs + tuple(f"local.{o}" for o in names), kinds=plant.kinds + ("force",) * r,
        F=np.hstack([np.asarray(plant.F, float), -Od.T]), Kz=np.hstack([plant.Kz, zc]),
        Cz=np.hstack([plant.Cz, zc]), Mz=np.hstack([plant.Mz, zc]), Hz=np.hstack([plant.Hz, zc]),
        outputs=plant.outputs + tuple(f"{o}.vel" for o in names) + tuple(f"{o}.acc" for o in names),
        units=plant.units + ("m/s",) * r + ("m/s^2",) * r,
        Oq=ox(plant.Oq, zr, zr), Ov=ox(plant.Ov, Od, zr), Oa=ox(plant.Oa, zr, Od), Pz=io(Pz), Pv=Pv_new,
        Pa=Pa_new, Pf=io(plant.Pf, np.vstack([D, np.zeros((r, r))])), name=plant.name, Kf=plant.Kf,
        mounts=plant.mounts)


def nonlinear_job(model: Model, sources: list[Any], outputs: Sequence[str] | None,
                  hidden: bool) -> tuple[Plant, LocalLaws, int, int]:
    """The augmented plant of a nonlinear model, its local laws and the user's output and input counts.

    Raises
    ------
    ModelError
        Frequency-dependent (branch) mounts beside nonlinear ones.
    """
    if any(t.has_branches for t in model.mount_types.values()):
        raise ModelError("simulate: a model with nonlinear mounts and frequency-dependent (branch) mounts: the "
                         "nonlinear time response takes viscous and linear mounts beside its nonlinear ones",
                         argument="model")
    idx = nonlinear_mounts(model)
    lin = linear_part(model)
    found, dnames = nonlinear_axes(model)
    axes = [(p, j) for _, p, j in found]
    r = len(axes)
    inputs = sources if not hidden else [f"{model.body_names[0]}.fx"]
    asked = list(default_outputs(lin) if outputs is None else outputs)
    extra = [d for d in dnames if d not in asked]          # one plant: the user's outputs, then the axes'
    base = build_plant(lin, inputs, asked + extra)
    user = list(base.outputs[:len(asked)])
    take = list(range(len(asked))) + [asked.index(d) if d in asked else len(asked) + extra.index(d) for d in dnames]
    stacked: dict[str, Any] = {k: np.asarray(getattr(base, k), float)[take]
                               for k in ("Oq", "Ov", "Oa", "Pz", "Pv", "Pa", "Pf")}
    plant = dataclasses.replace(base, outputs=tuple(user) + tuple(dnames), units=tuple(base.units[i] for i in take),
                                Oh=None, Ph=None, **stacked)
    D = _force_rows(model, lin, axes, inputs, user, plant, r)
    aug = _augmented(plant, r, D)
    aug._cache["modal basis"] = modal_basis(base)                    # the same M, K, C: one eigen solve
    a0 = assemble(model)
    loaded = (model.gravity is not None and np.any(model.gravity)) or bool(model.loads)
    local = _laws(a0, idx).local(operating_point(model).q) if loaded else np.zeros((len(idx), 3))   # (k, 3)
    pos = {p: i for i, p in enumerate(idx)}
    laws = LocalLaws(names=tuple(f"{model.mounts[p].name}.{'xyz'[j]}" for p, j in axes),
                     laws=tuple(model.mounts[p].type.laws[j] for p, j in axes),
                     d0=np.array([local[pos[p], j] for p, j in axes], float))
    return aug, laws, len(user), len(inputs) if not hidden else 1


def step_limit(job: "NonlinearJob", rtol: float) -> float:
    """Largest internal step [s] of the contact integration for ``rtol``: ``theta / omega_c`` with
    ``omega_c^2 = k / m_a`` per nonlinear axis (``k`` the stop rate, or a curve's largest departure
    from its linear rate; ``1 / m_a = B_a M^-1 B_a^T`` from the modes)."""
    laws = job.laws
    assert laws is not None
    p, r = job.user_outputs, laws.r
    mb = modal_basis(job.plant)
    rows = np.asarray(job.plant.Oq, float)[p:p + r] @ mb.phi
    flex = (rows**2).sum(axis=1)
    k = laws.ks.copy()
    for i in laws.curved:
        law = laws.laws[i]
        lo, hi = law.span
        pts = np.linspace(lo, hi, 64)
        k[i] += float(np.abs(law.tangent(pts) - law.stiffness).max())
    w = float(np.sqrt((k * flex).max())) if r else 0.0
    theta = THETA * (rtol / 1e-6) ** 0.25
    return theta / w if w > 0 else np.inf


def substeps(job: "NonlinearJob", h_max: float) -> int:
    """Internal steps per sample for steps of at most ``h_max`` [s]: 1, or an even number (so that the
    check can take half as many)."""
    dt = float(job.time[1] - job.time[0])
    sub = max(1, int(np.ceil(dt / h_max * (1 - 1e-12))))
    return sub + sub % 2 if sub > 1 else 1


def run_nonlinear(job: "NonlinearJob", sub: int) -> tuple[np.ndarray, str, ContactRun]:
    """The outputs (ns, p) of a nonlinear job at its samples, with ``sub`` internal steps per sample."""
    laws = job.laws
    assert laws is not None
    plant, p, m, r = job.plant, job.user_outputs, job.user_inputs, laws.r
    dt = float(job.time[1] - job.time[0])
    ns = job.time.size
    fine = make_grid(sub * (ns - 1) + 1, dt / sub, job.breakpoints)
    zeros = tuple(lambda t: np.zeros(np.shape(t)) for _ in range(r))
    full = dataclasses.replace(job, funcs=tuple(job.funcs) + zeros, sinusoids=tuple(job.sinusoids) + ((),) * r
                               if job.sinusoids else ())
    prep = prepare(plant)
    kept = job.memo.get("linear")
    if kept is not None and kept[0] % sub == 0 and len(fine.t) == sub * (ns - 1) + 1:
        lin, how = kept[1][::kept[0] // sub], kept[2]        # a finer run's grid holds this one's points
    else:
        kin = full.sampled(fine)
        lin, how = run_modal(prep, fine, kin, np.arange(len(fine.t)), job.q0, job.v0)
        if len(fine.t) == sub * (ns - 1) + 1:                # no breakpoint inserted: uniform
            job.memo["linear"] = (sub, lin, how)
    samples = fine.samples[::sub]
    if r == 0:                      # a linear model: the exact modal response
        return lin[samples, :p], f"exact modal FOH ({how}); no nonlinear mount", _empty_run()
    sys = job.memo.get("system")
    if sys is None:
        sys = job.memo["system"] = _system(prep, p, m, r, float(fine.t[-1]))
    y_nl, _, run = integrate(sys, laws, fine.t, lin[:, p:], samples, lin[0, p:p + r], lin[0, p + r:p + 2 * r])
    y = lin[samples, :p] + y_nl
    note = (f"exact modal propagation of the linear part ({how}) with the {r} nonlinear mount axes' forces "
            f"as cubic Hermite local forces (Newton on {2 * r} unknowns a step), {sub} internal steps per "
            f"sample (h = {dt / sub:.3g} s), {run.events} stop events and {run.crossings} crossings of curve "
            "breakpoints located")
    return y, note, run


def _system(prep: Any, p: int, m: int, r: int, horizon: float) -> ContactSystem:
    """The modal blocks the local forces drive (:class:`~vibss.time.kernels.contact.ContactSystem`): the
    plant's modal sets from rest, their forcing per local force and their rows of the local coordinates
    and of the user's outputs."""
    plant = prep.plant
    sets, _ = _modal_sets(prep, np.zeros(plant.n), np.zeros(plant.n), horizon)
    Wg = channels(prep)
    A, F, H, Y = [], [], [], []
    for s in sets:
        PW = np.zeros((s.A.shape[0], Wg.shape[1]), np.result_type(s.A, Wg))
        if s.P is not None:
            PW = PW + s.P @ Wg
        if s.Pc is not None:
            PW = PW + s.Pc
        A.append(s.A)
        F.append(np.ascontiguousarray(PW[:, m:m + r]))
        H.append(np.ascontiguousarray(s.Y[p:p + 2 * r]))
        Y.append(np.ascontiguousarray(s.Y[:p]))
    return ContactSystem(tuple(A), tuple(F), tuple(H), tuple(Y), np.asarray(prep.Df, float)[:p, m:m + r])


def _empty_run() -> ContactRun:
    z = np.zeros(0)
    return ContactRun(peak_hi=z, peak_lo=z, t_hi=z, t_lo=z, intervals={})


def contact_table(laws: LocalLaws, run: ContactRun) -> ContactTable:
    """The stops that were hit: per (axis, side) first contact [s], total time in contact [s], peak
    deflection [m] and peak stop force [N]."""
    rows = []
    order = sorted(run.intervals, key=lambda k: min(s[0] for s in run.intervals[k]))   # by first contact
    for a, side in order:
        spans = run.intervals[(a, side)]
        peak = float(run.peak_hi[a] if side > 0 else run.peak_lo[a])
        t_peak = float(run.t_hi[a] if side > 0 else run.t_lo[a])
        gap = laws.hi[a] if side > 0 else laws.lo[a]
        force = float(laws.ks[a] * max(abs(peak) - gap, 0.0))
        rows.append((laws.names[a], "+" if side > 0 else "-", float(spans[0][0]),
                     float(sum(e - s for s, e in spans)), len(spans), peak, t_peak, force))
    axes = tuple(laws.names)
    return ContactTable(
        mount=tuple(r_[0].rsplit(".", 1)[0] for r_ in rows), axis=tuple(r_[0].rsplit(".", 1)[1] for r_ in rows),
        side=tuple(r_[1] for r_ in rows), first=np.array([r_[2] for r_ in rows]),
        duration=np.array([r_[3] for r_ in rows]), count=np.array([r_[4] for r_ in rows], int),
        peak=np.array([r_[5] for r_ in rows]), peak_time=np.array([r_[6] for r_ in rows]),
        force=np.array([r_[7] for r_ in rows]),
        intervals=tuple(tuple((float(s), float(e)) for s, e in run.intervals[k]) for k in order),
        axes=axes, peak_hi=run.peak_hi.copy(), peak_lo=run.peak_lo.copy())
