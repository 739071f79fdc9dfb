"""Which mode, which mount, which path: :func:`energy_distribution`, :func:`modal_contributions` and
:func:`path_contributions` (issue 31).

Each computes its answer one way and checks it cheaply against a second (:mod:`vibss.methods`):

- energy distribution: the mounts' strain energies summed against ``w^2 / 2`` of the eigen path
  (the dissipated energies against ``pi phi^T (w C + H) phi`` of the assembled matrices); rows sum
  to 1;
- modal contributions: the terms and the residual summed against the exact solve
  (:func:`vibss.linear.solve.exact.response`) at three frequencies;
- path contributions: the paths summed against the receiver's total of the plant's own output rows
  (``ground.fx`` ..., ``<body>.into.fx`` ...).

A miss is a :class:`~vibss.errors.VibssWarning` that states it, and the note carries the bound.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from .._validate import choice, integer, name_index
from ..errors import AnalysisError, ArgumentError, SignalError
from ..frequency.api import frequency_response
from ..frequency.grid import FrequencyGrid, frequency_grid
from ..linear.eigen.basis import classical_damping, modal_basis, projected_damping
from ..linear.plant.assemble import Assembly, assemble
from ..linear.plant.build import build_plant
from ..linear.plant.names import actuator_wrench
from ..linear.plant.plant import Plant
from ..linear.solve.exact import observe, states, zfactor
from ..methods import Check, Claim, Method, decide
from ..modal.api import modes
from ..modal.result import Modes
from ..model.model import DOF_NAMES, GROUND, Model
from .kernels import (AXES, ModalTerms, classical_terms, complex_terms, dissipated_energy, output_maps,
                      strain_energy)
from .result import EnergyDistribution, ModalContributions, PathContributions

__all__ = ["energy_distribution", "modal_contributions", "path_contributions", "KINDS", "ENERGY", "MODAL", "PATHS"]

KINDS = ("strain", "kinetic", "dissipative")
"""The energies :func:`energy_distribution` shares out."""

ENERGY = Method("per-mount sums", strain_energy, exact=True, claim=Claim(
    1e-9, exact=True, conditions="the mounts' energies summed against w^2 / 2 of the eigen path (strain) or "
    "pi phi^T (w C + H) phi of the assembled matrices (dissipative); rows sum to 1"))
"""How :func:`energy_distribution` works, and what it claims."""

MODAL = Method("modal superposition", classical_terms, exact=True, claim=Claim(
    1e-9, exact=True, conditions="all modes kept (or the left-out ones in the residual): the terms and the "
    "residual summed against the exact solve at three frequencies, each output relative to |Y| + ||O|| ||X|| (the "
    "size it is resolved to from the DOF solution X)"))
"""How :func:`modal_contributions` works, and what it claims."""

PATHS = Method("mount forces", frequency_response, exact=True, claim=Claim(
    1e-9, exact=True, conditions="the paths summed against the receiver's total force and moment"))
"""How :func:`path_contributions` works, and what it claims."""


def energy_distribution(model_or_modes: Model | Assembly | Modes, kind: str = "strain") -> EnergyDistribution:
    """Each mode's strain, kinetic or dissipated energy shared among the mounts or bodies.

    - ``"strain"``: mount p's share of mode r is ``phi_r^T K_p phi_r / phi_r^T K phi_r``, also per
      local axis of the mount (deflection along and rotation about its principal axes);
    - ``"kinetic"``: each body's share ``phi^T M_b phi / phi^T M phi``, per DOF as
      :attr:`vibss.modal.Modes.energy`;
    - ``"dissipative"``: each mount's share of the energy dissipated per cycle of the mode,
      ``pi phi^T (w C_p + H_p) phi`` (viscous damping and loss factors).

    Parameters
    ----------
    model_or_modes : Model, Assembly or Modes
        The system (its modes are computed), or modes already computed by :func:`vibss.modes`.
    kind : {"strain", "kinetic", "dissipative"}
        Which energy.

    Returns
    -------
    EnergyDistribution
        ``fractions`` (modes x parts) and ``by_axis`` (modes x parts x 6); rows sum to 1.

    Raises
    ------
    ArgumentError
        Unknown ``kind``.
    AnalysisError
        ``"dissipative"`` on a model without damping.

    Examples
    --------
    >>> from vibss import Body, MountType, Mount, Model
    >>> t = MountType("t", [1e4, 1e4, 1e4])
    >>> m = Model([Body("b", 10.0, [1, 1, 1])], [Mount("m1", t, "b", at=[-0.5, 0, 0]),
    ...                                           Mount("m2", MountType("u", [3e4] * 3), "b", at=[0.5, 0, 0])])
    >>> from vibss import modes
    >>> und = modes(m)
    >>> e = energy_distribution(und, "strain")
    >>> e.fractions[und.directions.index("x")].round(3)     # x deflects both mounts alike: 1 : 3
    array([0.25, 0.75])
    """
    choice(kind, "kind", KINDS, who="energy_distribution")
    und = model_or_modes if isinstance(model_or_modes, Modes) else modes(model_or_modes)
    k, nb = len(und), len(und.model.bodies)
    rigid = np.asarray(und.rigid, bool)
    if kind == "kinetic":
        by_axis = np.asarray(und.energy, float).reshape(k, nb, 6)
        total, reference = by_axis.sum(axis=(1, 2)), np.ones(k)
        parts, axes = tuple(und.model.body_names), tuple(DOF_NAMES)
        energy, method, usable = 0.5 * und.omega**2, "kinetic energy per DOF (the modes' table)", np.ones(k, bool)
    else:
        a = assemble(und.model)
        phi, w = np.asarray(und.shapes), np.asarray(und.omega)
        if kind == "strain":
            e = strain_energy(a, phi)
            reference = 0.5 * w**2
        else:
            if not (a.has_damping or a.has_hysteresis):
                raise AnalysisError("energy_distribution: kind='dissipative': no mount of the model has viscous "
                                    "damping or a loss factor: nothing is dissipated")
            e = dissipated_energy(a, phi, w)
            cp = np.einsum("ik,ik->k", phi, np.asarray(a.C @ phi))      # diag(phi^T C phi), sparse or dense C
            hp = np.einsum("ik,ik->k", phi, np.asarray(a.H @ phi))
            reference = np.pi * (w * cp + hp)
        total = e.sum(axis=(1, 2))
        usable = ~rigid & (np.abs(total) > 0)
        with np.errstate(divide="ignore", invalid="ignore"):
            by_axis = np.where(usable[:, None, None], e / np.where(usable, total, 1.0)[:, None, None], np.nan)
        parts, axes, energy = tuple(m.name for m in und.model.mounts), AXES, total
        method = "per-mount sums"
    fractions = by_axis.sum(axis=2)
    decision = decide([ENERGY], lambda m: fractions, where="energy_distribution", auto=False,
                      check=lambda m, f: _energy_check(f, total, reference, usable, kind))
    notes = [decision.note()]
    if kind != "kinetic" and rigid.any():
        notes.append(f"{int(rigid.sum())} rigid-body mode(s) store no {kind} energy: their rows are NaN")
    if kind == "dissipative":
        notes.append("dissipated per cycle at each mode's natural frequency (viscous w c, hysteretic eta k)")
    return EnergyDistribution(kind=kind, model=und.model, frequency_hz=np.asarray(und.frequency_hz), parts=parts,
                              axes=axes, fractions=fractions, by_axis=by_axis, energy=np.asarray(energy, float),
                              rigid=rigid, method=method, note="; ".join(n for n in notes if n))


def _energy_check(fractions: np.ndarray, total: np.ndarray, reference: np.ndarray, usable: np.ndarray,
                  kind: str) -> Check:
    """The sum over the parts against the independent whole, and the rows' sums against 1."""
    if not usable.any():
        return Check(0.0, ENERGY.claim.tolerance if ENERGY.claim else 0.0, "no mode with energy")
    ref = np.abs(reference[usable])
    scale = np.where(ref > 0, ref, np.abs(total[usable]))
    sums = np.abs(total[usable] - reference[usable]) / scale
    rows = np.abs(fractions[usable].sum(axis=1) - 1.0)
    err = float(max(sums.max(), rows.max()))
    tol = ENERGY.claim.tolerance if ENERGY.claim else 0.0
    return Check(err, tol, f"{int(usable.sum())} modes ({kind}: sum over the parts vs the whole; rows sum to 1)")


def _is_grid(frequencies: Any) -> bool:
    return frequencies is None or isinstance(frequencies, (Mapping, FrequencyGrid))


def _frequencies(plant: Plant, frequencies: Any, basis: Any, who: str) -> np.ndarray:
    """Frequencies [Hz] > 0: explicit, or a grid spec (:func:`vibss.frequency.grid.frequency_grid`)."""
    if _is_grid(frequencies):
        f = frequency_grid(plant, frequencies, basis)
        return f[f > 0]
    return _explicit(frequencies, who)


def _explicit(frequencies: Any, who: str) -> np.ndarray:
    """Explicit frequencies [Hz], each finite and > 0."""
    try:
        f = np.atleast_1d(np.asarray(frequencies, dtype=float))
    except (TypeError, ValueError):
        f = np.array([np.nan])
    if f.ndim != 1 or f.size == 0 or not np.all(np.isfinite(f)) or np.any(f <= 0):
        raise ArgumentError(f"{who}: frequencies: expected a non-empty list of finite frequencies > 0 [Hz], got "
                            f"{frequencies!r}", argument="frequencies", received=frequencies,
                            expected="finite frequencies > 0 [Hz]")
    return f


def modal_contributions(model: Model | Assembly, inputs: Sequence[Any], outputs: Sequence[str] | None = None,
                        frequencies: Any = None, n_modes: int | None = None) -> ModalContributions:
    """A frequency response split into the terms of its modes and a residual.

    With classical damping (``Phi^T C Phi`` and ``Phi^T H Phi`` diagonal) each term is one undamped
    mode's, ``O phi_r phi_r^T R / (w_r^2 + i h_r + i w c_r - w^2)``; otherwise the complex modes'
    terms, each pole given to the undamped mode that dominates its shape (a conjugate pair is one
    term). The residual is the feedthrough and the modes left out by ``n_modes``: terms and
    residual sum to the exact response (checked at three frequencies).

    Parameters
    ----------
    model : Model or Assembly
        The system (no frequency-dependent mounts: their branches' poles belong to no mode).
    inputs : sequence of str or Excitation
        Input signals (see :mod:`vibss.linear.plant.names`).
    outputs : sequence of str or None
        Output signals; default every body DOF's displacement.
    frequencies : (nf,) array_like [Hz], FrequencyGrid, mapping or None
        Frequencies > 0, or a grid spec (default: the refined grid around the modes).
    n_modes : int or None
        Keep the terms of the lowest ``n_modes`` modes; the others go into the residual.

    Returns
    -------
    ModalContributions
        ``terms`` (modes, outputs, inputs, frequencies), ``residual``, ``dominant()``.

    Raises
    ------
    AnalysisError
        A model with frequency-dependent mounts.
    ArgumentError
        Frequencies not > 0, a bad ``n_modes``.

    Examples
    --------
    >>> from vibss import Body, MountType, Mount, Model
    >>> t = MountType("t", [1e4] * 3, damping=[20.0] * 3)
    >>> m = Model([Body("b", 10.0, [1, 1, 1])], [Mount("m", t, "b")])
    >>> c = modal_contributions(m, ["b.fz"], ["b.z"], [5.0, 5.033, 6.0])
    >>> k = int(abs(c.terms[:, 0, 0, 1]).argmax())       # the z mode (5.033 Hz) makes the z response
    >>> float(c.mode_frequency_hz[k].round(3)), c.method
    (5.033, 'modal')
    """
    asm = model if isinstance(model, Assembly) else assemble(model)
    plant = build_plant(asm, inputs, outputs)
    if plant.branches is not None:
        raise AnalysisError("modal_contributions: the model has frequency-dependent mounts; their Maxwell "
                            "branches add poles of their own that belong to no mode (use frequency_response)")
    basis = modal_basis(plant)
    f = _frequencies(plant, frequencies, basis, "modal_contributions")
    s = 2j * np.pi * f
    chat, hhat = projected_damping(plant, basis)
    classical, why = classical_damping(plant, basis, (chat, hhat))
    kernel = classical_terms if classical else complex_terms
    route = Method("modal" if classical else "complex", kernel, exact=True, claim=MODAL.claim)
    decision = decide([route], lambda m: m.kernel(plant, s, basis, chat, hhat), where="modal_contributions",
                      auto=False, check=lambda m, t: _modal_check(plant, s, t))
    mt: ModalTerms = decision.answer
    k = mt.terms.shape[0]
    keep = k if n_modes is None else min(integer(n_modes, "n_modes", who="modal_contributions"), k)
    residual = mt.feedthrough + mt.terms[keep:].sum(axis=0)
    notes = [("classical damping: one term per undamped mode" if classical else
              f"not classical ({why}): complex modes, each pole given to the undamped mode that dominates it"),
             decision.note()]
    if keep < k:
        notes.append(f"{k - keep} higher modes in the residual")
    return ModalContributions(frequency=f, terms=mt.terms[:keep], residual=residual,
                              mode_frequency_hz=basis.omega[:keep] / (2 * np.pi), poles=mt.poles[:keep],
                              output_names=plant.outputs, input_names=plant.inputs, output_units=plant.units,
                              method=route.name, note="; ".join(n for n in notes if n))


def _modal_check(plant: Plant, s: np.ndarray, mt: ModalTerms) -> Check:
    """Terms plus feedthrough against the exact solve at the first, the largest and the last frequency.

    Each output p and input m is measured against ``|Y_pm| + ||O_p(s)|| ||X_m(s)|| + |P_pm Z_m|``, the
    size the output can be resolved to from the DOF solution ``X_m`` (a backward-stable scale: an
    output that the modes' terms cancel to, at the far end of a long chain, or that is zero by
    symmetry, is not measured against its own tiny size)."""
    total = mt.terms.sum(axis=0) + mt.feedthrough
    mag = np.abs(total).reshape(-1, s.size).max(axis=0)
    idx = np.unique([0, int(np.argmax(np.where(np.isfinite(mag), mag, -1.0))), s.size - 1])
    si = s[idx]
    zf = zfactor(si, plant.order)
    x, _ = states(plant, si)
    exact = observe(plant, si, x, zf)                                   # (nf, p, m)
    o_norm = np.linalg.norm(output_maps(plant, si), axis=2)             # (nf, p)
    x_norm = np.linalg.norm(x, axis=1)                                  # (nf, m)
    scale = np.abs(exact) + o_norm[:, :, None] * x_norm[:, None, :] + np.abs(mt.feedthrough[..., idx]).transpose(2, 0, 1)
    diff = np.abs(total[..., idx].transpose(2, 0, 1) - exact)
    with np.errstate(divide="ignore", invalid="ignore"):
        err = float(np.nanmax(np.where(scale > 0, diff / np.where(scale > 0, scale, 1.0), diff)))
    hz = ", ".join(f"{x:.4g}" for x in (si.imag / (2 * np.pi)))
    tol = MODAL.claim.tolerance if MODAL.claim else 0.0
    return Check(err, tol, f"the exact solve at {hz} Hz")


_COMPONENTS = ("fx", "fy", "fz", "mx", "my", "mz")


def _receiver_node(model: Model, receiver: Any) -> int:
    """The node index of ``receiver`` as the assembly numbers them (bodies, ground, supports)."""
    grounds = [GROUND] + list(model.support_names)
    names = list(model.body_names) + grounds
    name_index(receiver, names, "receiver", who="path_contributions")
    nb = len(model.bodies)
    return model.body_index(receiver) if receiver in model.body_names else nb + grounds.index(receiver)


def path_contributions(model: Model | Assembly, inputs: Sequence[Any], frequencies: Any = None,
                       receiver: str = GROUND, method: str = "auto", *,
                       foundation: Any = None) -> PathContributions:
    """The force and moment each mount passes into a receiver, summing to the receiver's total.

    The paths are the mounts whose ``to`` side is the receiver (as ``ground.fx`` and
    ``<body>.into.fx`` count them): each passes ``K delta + C delta' + i H delta`` (and a 6x6
    mount its moment) into it. Moments are about the receiver's reference point (its COG; the
    global origin for ground and supports). Actuator reactions are not paths (the note says when
    an actuator acts into the receiver).

    Parameters
    ----------
    model : Model or Assembly
        The system.
    inputs : sequence of str or Excitation
        Input signals (forces on the bodies, ground motion ...).
    frequencies : (nf,) array_like [Hz], FrequencyGrid, mapping or None
        Frequencies > 0, or a grid spec (default: the refined grid around the modes).
    receiver : str
        ``"ground"``, a support or a body.
    method : str
        :func:`vibss.frequency_response` method for the mount forces.
    foundation : Foundation or None
        A flexible foundation under some of the mounts to ground (:class:`vibss.Foundation`):
        transfer path analysis. The receiver is then one of its points (``"m1"`` or
        ``"foundation.m1"``), the paths are its points' mounts, and each path's contribution is the
        foundation's receptance times the force that mount passes into it in the exactly coupled
        system: the receiver's motion ``x y z`` [m] (``rx ry rz`` [rad]), summing to it. The
        frequencies must be the foundation's (None: those).

    Returns
    -------
    PathContributions
        ``forces`` (paths, 6, inputs, frequencies), ``total``, ``share``.

    Raises
    ------
    SignalError
        An unknown receiver, or one no mount rests on.

    Examples
    --------
    >>> from vibss import Body, MountType, Mount, Model
    >>> t = MountType("t", [1e4] * 3, damping=[20.0] * 3)
    >>> m = Model([Body("b", 10.0, [1, 1, 1])], [Mount("a", t, "b", at=[-0.5, 0, 0]), Mount("c", t, "b", at=[0.5, 0, 0])])
    >>> p = path_contributions(m, ["b.fz"], [2.0, 5.0])
    >>> p.share[:, 2, 0, :].round(6).tolist()       # z force: half through each mount
    [[0.5, 0.5], [0.5, 0.5]]
    """
    if foundation is not None:
        from ..measured.paths import transfer_paths
        return transfer_paths(model, inputs, frequencies, receiver, method, foundation)
    asm = model if isinstance(model, Assembly) else assemble(model)
    mdl = asm.model
    node = _receiver_node(mdl, receiver)
    paths = np.flatnonzero(asm.a_index == node)
    if paths.size == 0:
        raise SignalError(f"path_contributions: receiver: no mount has {receiver!r} as its 'to' side: no path "
                          "leads into it", argument="receiver", received=receiver)
    names = [mdl.mounts[int(p)].name for p in paths]
    moments = [bool(np.any(asm.krp[p]) or np.any(asm.crp[p]) or np.any(asm.kcp[p]) or np.any(asm.ccp[p]))
               if asm.krp.shape[0] else False for p in paths]
    outs = [f"mount.{n}.{c}" for n, mo in zip(names, moments) for c in (_COMPONENTS if mo else _COMPONENTS[:3])]
    head = receiver if node >= len(mdl.bodies) else f"{receiver}.into"
    outs += [f"{head}.{c}" for c in _COMPONENTS]
    if _is_grid(frequencies):
        plant = build_plant(asm, inputs, outs[-6:])
        f = _frequencies(plant, frequencies, modal_basis(plant), "path_contributions")
    else:
        f = _explicit(frequencies, "path_contributions")
    fr = frequency_response(asm, inputs, outs, f, method=method)
    h = np.asarray(fr.response)
    m, nf = h.shape[1], h.shape[2]
    forces = np.zeros((paths.size, 6, m, nf), complex)
    row = 0
    for q, (p, mo) in enumerate(zip(paths, moments)):
        forces[q, :3] = h[row:row + 3]
        forces[q, 3:] = np.cross(asm.r_a[p][:, None, None], h[row:row + 3], axis=0)
        if mo:
            forces[q, 3:] += h[row + 3:row + 6]
        row += 6 if mo else 3
    into = h[-6:]
    acting = [a.name for a in mdl.actuators if actuator_wrench(mdl, a)[1] == receiver]
    notes = [f"method {fr.method}"]
    if acting:
        notes.append(f"actuators {acting} act into {receiver!r}: their reactions are not paths (not checked)")
        decision = decide([PATHS], lambda m_: forces, where="path_contributions", auto=False)
    else:
        decision = decide([PATHS], lambda m_: forces, where="path_contributions", auto=False,
                          check=lambda m_, fo: _path_check(fo, into))
    notes.append(decision.note())
    return PathContributions(receiver=receiver, frequency=f, paths=tuple(names), components=_COMPONENTS,
                             forces=forces, input_names=fr.inputs, method=fr.method,
                             note="; ".join(n for n in notes if n))


def _path_check(forces: np.ndarray, into: np.ndarray) -> Check:
    """The paths' sum against the receiver's total output rows, per component and frequency."""
    total = forces.sum(axis=0)
    scale = np.abs(into).max(axis=(1, 2), keepdims=True)
    scale = np.where(scale > 0, scale, 1.0)
    err = float((np.abs(total - into) / scale).max())
    tol = PATHS.claim.tolerance if PATHS.claim else 0.0
    return Check(err, tol, "the receiver's total force and moment")
