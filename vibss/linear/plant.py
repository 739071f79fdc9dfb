"""The second-order input/output description of a study ("plant"), shared by every dynamic analysis.

A study picks **inputs** (forces on bodies or points; prescribed displacement, velocity or
acceleration of ground or body DOFs) and **outputs** (motions of DOFs and points, mount deflections
and forces, total transmitted forces). A :class:`Plant` holds the second-order matrices of the
unknown (free) DOFs and the maps of every input and output, in SI:

    M q'' + C q' + K q = F u_f - (Kz z + Cz z' + Mz z'')
    y = Oq q + Ov q' + Oa q'' + Pz z + Pv z' + Pa z'' + Pf u_f   (+ i (Oh q + Ph z), frequency domain)

where ``u_f`` are the force inputs and ``z`` the prescribed coordinates. Each input column ``j``
is one named signal; a force input has a nonzero column in ``F`` and zero columns in ``Kz, Cz, Mz,
Pz, Pv, Pa``; a motion input has the reverse. ``kinds[j]`` says what the signal ``u_j`` *is*:
``"force"`` (u = f), ``"displacement"`` (u = z), ``"velocity"`` (u = z'), ``"acceleration"``
(u = z''). In the frequency domain ``z = u / (i w)^order`` with order 0, 1, 2; in the time domain
each kind gets an exact realization (see :mod:`vibss.statespace`).

Frequency-domain-only hysteretic stiffness enters as ``K + i H`` and ``Kz + i Hz``.

The plant is built by :func:`vibss.linear.signals.build_plant`; analyses take a Plant, never re-derive it.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

__all__ = ["Plant", "MountForm", "INPUT_KINDS", "MOTION_ORDER"]

INPUT_KINDS = ("force", "displacement", "velocity", "acceleration")
"""What an input signal is."""

MOTION_ORDER = {"displacement": 0, "velocity": 1, "acceleration": 2}
"""Time derivative of the prescribed coordinate that a motion input gives."""


@dataclass(frozen=True, eq=False)
class MountForm:
    """The dynamic stiffness of a plant kept as a sum over its mounts: ``K + iH + sC = R(s) + B^T Z(s) B``.

    Assembling ``K = sum B_p^T k_p B_p`` rounds every entry at the level of the stiffest mount it
    holds; the soft modes beside stiff mounts (stiffness ratios of 1e5 and more) are sensitive to
    exactly that round-off. Kept apart, the mount forces ``lam = Z B q`` become unknowns of their
    own (:mod:`vibss.linear.solve`, ``form="mounts"``) and nothing large is ever summed.

    Attributes
    ----------
    B : (3 q, n) scipy.sparse CSR matrix
        Deflection (global axes) of each of the q mounts kept apart per unit free-DOF motion [m/m, m/rad].
    kp, cp, hp : (q, 3, 3) ndarray
        Their stiffness [N/m], viscous damping [N s/m] and hysteretic stiffness [N/m] in global
        axes; every ``kp`` is positive definite.
    K, C, H : (n, n) scipy.sparse CSR matrix
        The rest, assembled: mounts with a zero principal stiffness, added modal damping.
    source : tuple of ndarray
        The plant's own ``(K, C, H, M)`` arrays this form reproduces; the solve uses the form only
        for a plant holding these very arrays (a plant derived with ``dataclasses.replace`` and
        new matrices falls back to them).
    stiffness_ratio : float
        Largest over smallest principal stiffness of the mounts kept apart.
    """

    B: Any
    kp: np.ndarray
    cp: np.ndarray
    hp: np.ndarray
    K: Any
    C: Any
    H: Any
    source: tuple
    stiffness_ratio: float

    def matches(self, plant: Plant) -> bool:
        """Whether ``plant`` holds the very ``K, C, H, M`` arrays this form was built for."""
        return all(a is b for a, b in zip(self.source, (plant.K, plant.C, plant.H, plant.M)))


@dataclass(frozen=True, eq=False)
class Plant:
    """Second-order matrices of the free DOFs plus named input and output maps.

    Attributes
    ----------
    dofs : tuple of str
        Labels of the free (unknown) DOFs, ``'<body>.<dof>'`` (n of them).
    M, C, K, H : (n, n) ndarray
        Mass, viscous damping, stiffness and hysteretic stiffness of the free DOFs (SI).
    inputs : tuple of str
        Input signal names (m of them).
    kinds : tuple of str
        ``INPUT_KINDS`` entry per input.
    F : (n, m) ndarray
        Generalised force per unit force input [N/N, N m/N ...].
    Kz, Cz, Mz, Hz : (n, m) ndarray
        Coupling of each prescribed coordinate into the free DOFs (moved to the right-hand side
        with a minus sign).
    outputs : tuple of str
        Output signal names (p of them).
    units : tuple of str
        SI unit of each output (``"m"``, ``"rad"``, ``"m/s"``, ``"N"`` ...).
    Oq, Ov, Oa : (p, n) ndarray
        Output per free-DOF displacement, velocity and acceleration.
    Pz, Pv, Pa, Pf : (p, m) ndarray
        Output per prescribed displacement, velocity, acceleration, and per force input
        (direct feedthrough).
    name : str
        System name (the model's).
    Oh, Ph : (p, n), (p, m) ndarray or None
        Hysteretic part of the outputs (frequency domain only): ``y += i (Oh q + Ph z)``, e.g. the
        loss-factor force ``i H_p delta`` of a mount force output. None means zero.
    Kf : (r, n) ndarray or scipy.sparse matrix or None
        Stiffness factor of the free DOFs, ``K = Kf^T Kf`` (one row per mount principal axis,
        ``sqrt(k) T^T B``); the eigen path and statics use it to stay exact beside stiff links
        (K formed in floats loses soft mounts next to 1e16 N/m links). None: not known (e.g. a
        projected plant); analyses then work from K. Restricting a plant to DOFs keeps
        ``Kf[:, dofs]`` only when the dropped DOFs are prescribed (not condensed).
    mounts : MountForm or None
        ``K, C, H`` kept as a sum over the mounts, for the exact solve on badly scaled models
        (:func:`vibss.linear.signals.build_plant` sets it; None: only the assembled matrices).
    """

    dofs: tuple[str, ...]
    M: np.ndarray
    C: np.ndarray
    K: np.ndarray
    H: np.ndarray
    inputs: tuple[str, ...]
    kinds: tuple[str, ...]
    F: np.ndarray
    Kz: np.ndarray
    Cz: np.ndarray
    Mz: np.ndarray
    Hz: np.ndarray
    outputs: tuple[str, ...]
    units: tuple[str, ...]
    Oq: np.ndarray
    Ov: np.ndarray
    Oa: np.ndarray
    Pz: np.ndarray
    Pv: np.ndarray
    Pa: np.ndarray
    Pf: np.ndarray
    name: str = "vibss"
    Oh: np.ndarray | None = None
    Ph: np.ndarray | None = None
    Kf: Any = None
    mounts: MountForm | None = None
    _cache: dict[str, Any] = field(default_factory=dict, init=False, repr=False)

    def cached(self, key: str, make: Callable[[], Any]) -> Any:
        """``make()``, computed once per plant (sparse forms, factorisations of its matrices).

        The plant is frozen, so a derived quantity never goes stale; ``dataclasses.replace`` makes
        a new plant with an empty cache (the field is not an init argument).

        Parameters
        ----------
        key : str
            Name of the quantity (e.g. ``"sparse C"``, ``"solve K"``).
        make : callable
            Computes it.
        """
        if key not in self._cache:
            self._cache[key] = make()
        return self._cache[key]

    @property
    def n(self) -> int:
        """Number of free DOFs."""
        return len(self.dofs)

    @property
    def order(self) -> np.ndarray:
        """(m,) time-derivative order of each input's prescribed coordinate (-1 for forces)."""
        return np.array([MOTION_ORDER.get(k, -1) for k in self.kinds])
