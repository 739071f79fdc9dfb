"""Well-scaled python-control state-space realizations of a :class:`~vibss.linear.plant.plant.Plant`.

Realization
-----------
The plant ``M q'' + C q' + K q = F u_f - (Kz z + Cz z' + Mz z'')`` is realized so that **no input
is differentiated** and every input enters as itself:

- force inputs (``u = f``) and acceleration inputs (``u = z''``, two integrator states ``z, z'``)
  and velocity inputs (``u = z'``, one integrator state ``z``) use the physical coordinates;
- mass coupling of prescribed coordinates whose ``z''`` is not an input is absorbed by
  ``w = q + G z``, ``G = M^-1 Mz`` (so ``M w'' + C w' + K w`` sees no ``z''``);
- displacement inputs (``u = z``) are realized with ``z`` as the *only* input through
  ``xi = w' + E z``, ``E = M^-1 (Cz - C G)``: a piecewise-linear ``z`` is then handled exactly by
  a first-order hold (no ``z'`` input, which would be inconsistent).

With no displacement input and no mass coupling, ``w = q`` and ``xi = q'``. Outputs are the
physical ones, ``y = Oq q + Ov q' + Oa q'' + Pz z + Pv z' + Pa z'' + Pf u``, expressed in these
states. An output that would need the derivative of an input (e.g. an absolute acceleration or a
damper force under a *displacement* input of a damped mount) has no proper realization: it raises
:class:`~vibss.errors.AnalysisError` naming the pair and the input kind that works.

Scaling (``realization=``)
--------------------------
``"modal"`` (default): mass-normalised undamped modes ``Phi`` (``Phi^T M Phi = I``,
``Phi^T K Phi = Omega^2``), states ``[S eta; eta']`` with ``w = Phi eta``, ``S = Omega`` (rigid-body
modes, ``omega = 0``, use the lowest elastic ``omega`` instead, so they stay exact double
integrators): ``A = [[0, S], [-Omega^2 S^-1, -Phi^T C Phi]]``. Every entry of A is of the order of
the natural frequencies, so SLICOT's unbalanced TB05AD (``control.frequency_response``) and
``expm`` are accurate. State names ``mode<k>:pos`` (= omega_k eta_k [sqrt(kg) m/s]) and
``mode<k>:vel`` (= eta_k'), k from 1 in ascending frequency.

``"physical"``: states ``[w; xi]`` named ``<body>:<dof>`` and ``<body>:<dof>:vel``, diagonally
balanced (``scipy.linalg.matrix_balance``) unless ``balance=False``: the stored state ``i`` is the
physical one divided by a power of 2 (``StateSpace.vibss_state_scale`` holds the factors).

Integrator states of motion inputs are named ``<input>:z`` and ``<input>:zdot``. Signal names are
the vibss names with ``.`` replaced by ``:`` (python-control reserves ``.``;
:func:`vibss.linear.plant.names.control_name`). Hysteretic damping (``H``) is frequency-domain only and is
left out of every time-domain realization, with a :class:`~vibss.errors.VibssWarning` naming the mounts
(:func:`vibss.linear.plant.hysteresis.dropped_hysteresis`).

Examples
--------
>>> from vibss import Body, Model, Mount, MountType
>>> from vibss.linear.plant.build import build_plant
>>> t = MountType("t", [1e4, 1e4, 1e4], [10.0, 10.0, 10.0])
>>> m = Model([Body("b", 10.0, [1, 1, 1])], [Mount("m", t, "b")])
>>> sys = statespace(build_plant(m, ["ground.z.disp"], ["b.z"]))
>>> sys.ninputs, sys.noutputs, sys.nstates, sys.input_labels
(1, 1, 12, ['ground:z:disp'])
"""

from __future__ import annotations

import operator
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from typing import Any

import control
import numpy as np
import scipy.linalg as sl
import scipy.sparse as sp

from .plant.assemble import Assembly
from .._validate import choice
from ..errors import (AnalysisError, ArgumentError, ArgumentTypeError, ModelError, SignalError,
                      SignalIndexError, did_you_mean)
from .plant.branches import close
from .eigen.basis import modal_basis, projected_damping
from .plant.hysteresis import dropped_hysteresis
from ..model.model import Model
from .plant.plant import Plant
from .plant.build import build_plant
from .plant.names import control_name
from .solve.mass import mass_solver

__all__ = ["statespace", "NamedStateSpace", "REALIZATIONS"]

REALIZATIONS = ("modal", "physical")
"""Valid ``realization`` names."""


def _control_key(key: Any) -> Any:
    """A signal key with vibss names (``engine.z``) spelled the python-control way (``engine:z``)."""
    if isinstance(key, str):
        return control_name(key)
    if isinstance(key, (list, tuple)):
        return type(key)(control_name(k) if isinstance(k, str) else k for k in key)
    return key


def _rebuild(args: tuple, scale: np.ndarray | None) -> "NamedStateSpace":
    """Unpickle a :class:`NamedStateSpace` (python-control's own objects do not pickle)."""
    a, b, c, d, dt, inputs, outputs, states, name = args
    sys = NamedStateSpace(a, b, c, d, dt, inputs=inputs, outputs=outputs, states=states, name=name)
    if scale is not None:
        sys.vibss_state_scale = scale
    return sys


class NamedStateSpace(control.StateSpace):
    """A python-control ``StateSpace`` that also takes vibss signal names.

    python-control reserves ``.`` in signal names (``control.interconnect`` reads ``sys.signal``),
    so the labels are stored as ``engine:z``. Indexing and the ``find_*`` lookups also accept the
    vibss spelling, ``sys['engine.z', 'ground.z.acc']``; a name that is not there raises a
    ``ValueError`` naming the valid ones, and an index out of range an ``IndexError``. Sub-systems
    and :meth:`sample` keep the class, the state names and ``vibss_state_scale``; it pickles.
    Everything else is python-control's own (``feedback``, ``interconnect``, ``series`` return
    plain ``StateSpace`` objects).

    Examples
    --------
    >>> sys = NamedStateSpace([[-1.0]], [[1.0, 2.0]], [[1.0]], [[0.0, 0.0]],
    ...                       inputs=["ground:z:acc", "b:fz"], outputs=["b:z"])
    >>> sub = sys["b.z", "ground.z.acc"]
    >>> sub.input_labels, float(sub.B[0, 0]), sys.find_input("b.fz")
    (['ground:z:acc'], 1.0, 1)
    """

    def _side(self, key: Any, labels: list[str], other: list[str], what: str) -> Any:
        """One side of an index, checked and in python-control's spelling."""
        if isinstance(key, slice):
            return key
        if isinstance(key, (str, int, np.integer)):
            return self._one(key, labels, other, what)
        if isinstance(key, (list, tuple, range, np.ndarray)):
            items = [self._one(k, labels, other, what) for k in list(key)]
            picked = [labels.index(k) if isinstance(k, str) else k for k in items]
            if len(set(picked)) < len(picked):
                raise ArgumentError(f"{what}s: {list(key)!r} names a signal twice", argument=f"{what}s",
                                    received=list(key))
            return items
        raise ArgumentTypeError(f"{what}s: expected a name, an index, a slice or a list of them, got {key!r}",
                                argument=f"{what}s", received=key)

    @staticmethod
    def _one(key: Any, labels: list[str], other: list[str], what: str) -> Any:
        if isinstance(key, str):
            name = control_name(key)
            if name in labels:
                return name
            vibss = [lab.replace(":", ".") for lab in labels]
            hint = (f" ({key!r} is an {'input' if what == 'output' else 'output'}, not an {what})"
                    if name in other else did_you_mean(key.replace(":", "."), vibss))
            raise SignalError(f"{what}s: no {what} named {key!r}{hint}; the {what}s are {vibss}",
                              argument=f"{what}s", received=key, expected=tuple(vibss))
        i = operator.index(key)
        if not -len(labels) <= i < len(labels):
            raise SignalIndexError(f"{what}s: index {i} out of range for {len(labels)} {what}s",
                                   argument=f"{what}s", received=i, expected=f"-{len(labels)} .. {len(labels) - 1}")
        return i % len(labels)

    def _wrap(self, sub: control.StateSpace) -> "NamedStateSpace":
        out = NamedStateSpace(sub.A, sub.B, sub.C, sub.D, sub.dt, inputs=sub.input_labels,
                              outputs=sub.output_labels, states=self.state_labels, name=sub.name)
        if hasattr(self, "vibss_state_scale"):
            out.vibss_state_scale = self.vibss_state_scale
        return out

    def __getitem__(self, key: Any) -> "NamedStateSpace":
        if isinstance(key, str) or not isinstance(key, Iterable) or len(list(key)) != 2:
            return super().__getitem__(key)           # python-control's own error
        outs, ins = list(key)
        key = (self._side(outs, self.output_labels, self.input_labels, "output"),
               self._side(ins, self.input_labels, self.output_labels, "input"))
        return self._wrap(super().__getitem__(key))

    def __reduce__(self) -> tuple:
        args = (self.A, self.B, self.C, self.D, self.dt, self.input_labels, self.output_labels,
                self.state_labels, self.name)
        return _rebuild, (args, getattr(self, "vibss_state_scale", None))

    def sample(self, Ts: float, method: str = "zoh", alpha: float | None = None,
               prewarp_frequency: float | None = None, name: str | None = None,
               copy_names: bool = True) -> "NamedStateSpace":
        """The discrete-time system (:meth:`control.StateSpace.sample`), still a ``NamedStateSpace``.

        Parameters
        ----------
        Ts : float
            Sampling period [s].
        method : str
            Discretisation method (python-control's, default ``"zoh"``).
        alpha : float or None
            Weight of the generalised bilinear transform (``method="gbt"``).
        prewarp_frequency : float or None
            Pre-warping frequency [rad/s] (``"bilinear"``, ``"tustin"``, ``"gbt"``).
        name : str or None
            Name of the new system.
        copy_names : bool
            Keep the signal and state names.
        """
        return self._wrap(super().sample(Ts, method=method, alpha=alpha, prewarp_frequency=prewarp_frequency,
                                         name=name, copy_names=copy_names))

    def feedback(self, other: Any = 1, sign: float = -1) -> "NamedStateSpace":
        """``control.feedback(self, other, sign)`` keeping this system's signal names.

        When ``other`` names its signals after this system's (its inputs are outputs here and its
        outputs inputs here, either spelling, any order), it is reordered to match; unnamed signals
        (python-control's ``u[0]``) are taken by position.

        Parameters
        ----------
        other : StateSpace, array_like or float
            Feedback path.
        sign : float
            -1 for negative feedback (default), +1 for positive.
        """
        if isinstance(other, control.StateSpace):
            other = _matched(self, other)
        out = super().feedback(other, sign)
        extra = [] if not isinstance(other, control.StateSpace) else [
            f"{other.name}:{s}" for s in other.state_labels]
        sys = NamedStateSpace(out.A, out.B, out.C, out.D, out.dt, inputs=self.input_labels,
                              outputs=self.output_labels, states=list(self.state_labels) + extra,
                              name=f"{self.name}:feedback")
        return sys

    def find_input(self, name: Any) -> int | None:
        """Index of an input (``engine.fz`` or ``engine:fz``), None if absent."""
        return super().find_input(_control_key(name))

    def find_output(self, name: Any) -> int | None:
        """Index of an output (``engine.z`` or ``engine:z``), None if absent."""
        return super().find_output(_control_key(name))

    def find_state(self, name: Any) -> int | None:
        """Index of a state (``frame.z`` or ``frame:z``), None if absent."""
        return super().find_state(_control_key(name))

    def find_inputs(self, name_list: Any) -> list[int | None]:
        """Indices of inputs by name (either spelling, or a python-control pattern)."""
        return super().find_inputs(_control_key(name_list))

    def find_outputs(self, name_list: Any) -> list[int | None]:
        """Indices of outputs by name (either spelling, or a python-control pattern)."""
        return super().find_outputs(_control_key(name_list))

    def find_states(self, name_list: Any) -> list[int | None]:
        """Indices of states by name (either spelling, or a python-control pattern)."""
        return super().find_states(_control_key(name_list))


def _matched(forward: control.StateSpace, back: control.StateSpace) -> control.StateSpace:
    """``back`` with its inputs ordered as ``forward``'s outputs and its outputs as ``forward``'s inputs,
    when its signals carry those names; unchanged when they are python-control's defaults."""
    def generic(labels: list[str]) -> bool:
        return all(lab.endswith("]") and "[" in lab for lab in labels)

    ins, outs = [control_name(x) for x in back.input_labels], [control_name(x) for x in back.output_labels]
    if generic(ins) and generic(outs):
        return back
    want_in, want_out = list(forward.output_labels), list(forward.input_labels)
    missing = [x for x in ins if x not in want_in] + [x for x in outs if x not in want_out]
    if missing or len(ins) != len(want_in) or len(outs) != len(want_out):
        raise SignalError(f"feedback: the feedback system's signals {[x.replace(':', '.') for x in missing] or ins} "
                          f"do not match the forward system's outputs {[x.replace(':', '.') for x in want_in]} "
                          f"and inputs {[x.replace(':', '.') for x in want_out]}; connect subsystems by name "
                          "with vibss.control.interconnect or vibss.control.close",
                          argument="feedback", received=ins + outs)
    sub = back[[outs.index(x) for x in want_out], [ins.index(x) for x in want_in]]
    return control.ss(sub.A, sub.B, sub.C, sub.D, sub.dt, inputs=want_in, outputs=want_out,
                      states=back.state_labels, name=back.name)


@dataclass(frozen=True)
class _Basis:
    """Coordinates w = Tw a, xi = Tv b and the operators of the realization in them."""

    Tw: np.ndarray     # (n, n)
    Tv: np.ndarray     # (n, n)
    R: np.ndarray      # Tw^-1 Tv
    Kt: np.ndarray     # Tv^-1 M^-1 K Tw
    Ct: np.ndarray     # Tv^-1 M^-1 C Tv
    lm: Callable[[np.ndarray], np.ndarray]  # X -> Tv^-1 M^-1 X
    names: tuple[list[str], list[str]]


def _modal(plant: Plant) -> _Basis:
    mb = modal_basis(plant)
    phi, s = mb.phi, mb.scale
    k = np.arange(1, plant.n + 1)
    return _Basis(Tw=phi / s, Tv=phi, R=np.diag(s), Kt=np.diag(mb.omega2 / s), Ct=projected_damping(plant, mb)[0],
                  lm=lambda x: phi.T @ x,
                  names=([f"mode{i}:pos" for i in k], [f"mode{i}:vel" for i in k]))


def _physical(plant: Plant) -> _Basis:
    try:
        solve = mass_solver(plant)
    except np.linalg.LinAlgError:
        raise ModelError("mass matrix of the free DOFs is not positive definite") from None
    eye = np.eye(plant.n)
    dofs = [control_name(d) for d in plant.dofs]
    return _Basis(Tw=eye, Tv=eye, R=eye, Kt=solve(plant.K), Ct=solve(plant.C),
                  lm=solve, names=(dofs, [f"{d}:vel" for d in dofs]))


def _improper(plant: Plant, coef: np.ndarray, scale: np.ndarray, cols: np.ndarray, what: str) -> None:
    bad = (np.abs(coef) > 1e-8 * scale) & (scale > 0) & cols[None, :]
    if np.any(bad):
        i, j = map(int, np.argwhere(bad)[0])
        u = plant.inputs[j]
        better = "velocity or acceleration" if what == "first" else "acceleration"
        raise AnalysisError(
            f"output {plant.outputs[i]!r} depends on the {what} derivative of input {u!r} "
            f"({plant.kinds[j]}); no state-space realization takes {u!r} as its input without "
            f"differentiating it. Prescribe the same motion as a {better} input, or drop the output")


def statespace(plant: Plant | Model | Assembly, realization: str = "modal", balance: bool = True,
               name: str | None = None, *, inputs: Sequence[Any] | None = None,
               outputs: Sequence[str] | None = None) -> NamedStateSpace:
    """A python-control StateSpace of the plant, with named inputs, outputs and states.

    Parameters
    ----------
    plant : Plant, Model or Assembly
        From :func:`vibss.linear.plant.build.build_plant`; or a model, with ``inputs`` and ``outputs``, to
        build the study's system in one call.
    realization : {"modal", "physical"}
        State coordinates (see the module docstring). ``"modal"`` (default) is well scaled for
        SLICOT's frequency response and for ``expm``.
    balance : bool
        Diagonally balance the ``"physical"`` realization (ignored for ``"modal"``).
    name : str or None
        System name (default: the plant's, with ``.`` replaced by ``:``).
    inputs, outputs : sequence of str, optional
        Signals of the study when ``plant`` is a model (see :mod:`vibss.signals`).

    Returns
    -------
    NamedStateSpace
        A ``control.StateSpace`` that also takes vibss signal names when indexed.
        Inputs, outputs: the plant's signals with ``.`` -> ``:``; states: see the module docstring.
        Attribute ``vibss_state_scale`` ((nstates,) ndarray): physical state = scale * state.

    Raises
    ------
    ValueError
        Unknown ``realization``.
    AnalysisError
        An output needs the derivative of an input (see the module docstring).

    Examples
    --------
    >>> from vibss import Body, Model, Mount, MountType
    >>> from vibss.linear.plant.build import build_plant
    >>> m = Model([Body("b", 10.0, [1, 1, 1])], [Mount("m", MountType("t", [1e4] * 3), "b")])
    >>> sys = statespace(build_plant(m, ["b.fz"], ["b.z"]))
    >>> sys.nstates, sys.state_labels[:2], sys.output_labels
    (12, ['mode1:pos', 'mode2:pos'], ['b:z'])
    >>> statespace(m, inputs=["ground.z.acc"], outputs=["b.z.acc"]).input_labels   # in one call
    ['ground:z:acc']
    """
    if not isinstance(plant, Plant):
        if inputs is None:
            raise ModelError("statespace: a model needs inputs=[...] (and optionally outputs=[...])")
        dropped_hysteresis(plant, "statespace")
        plant = build_plant(plant, inputs, outputs)
    elif inputs is not None or outputs is not None:
        raise ModelError("statespace: inputs/outputs are fixed by the Plant; pass them to build_plant")
    else:
        dropped_hysteresis(plant, "statespace")
    if sp.issparse(plant.K):
        raise AnalysisError("statespace: the plant has sparse matrices (build_plant(..., sparse=True)); "
                            "a state space is dense: build the plant densely, or reduce it (vibss.reduce)")
    choice(realization, "realization", REALIZATIONS)
    if plant.branches is not None:       # frequency-dependent mounts: their internal states appended
        scales: list[np.ndarray] = []

        def make(mech: Plant) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, list[str]]:
            a, b, c, d, names, sc = _matrices(mech, realization, balance)
            scales.append(sc)
            return a, b, c, d, names
        A, B, Cm, D, states = close(plant, make)
        scale = np.concatenate([scales[0], np.ones(A.shape[0] - scales[0].size)])
    else:
        A, B, Cm, D, states, scale = _matrices(plant, realization, balance)
    ins = [control_name(u) for u in plant.inputs]
    sys = NamedStateSpace(A, B, Cm, D, inputs=ins, outputs=[control_name(y) for y in plant.outputs],
                          states=states, name=control_name(name or plant.name))
    sys.vibss_state_scale = scale
    return sys


def _matrices(plant: Plant, realization: str, balance: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray,
                                                                       np.ndarray, list[str], np.ndarray]:
    """``(A, B, C, D, state names, scale)`` of a plant without branches (the module docstring)."""
    basis = _modal(plant) if realization == "modal" else _physical(plant)
    n, m, p = plant.n, len(plant.inputs), len(plant.outputs)
    o = plant.order
    d0, d1, d2 = o == 0, o == 1, o == 2
    lm = basis.lm
    lmz = lm(plant.Mz)
    g = lmz * (o < 2)                       # G = Tv g
    lc1 = lm(plant.Cz) - basis.Ct @ g       # Tv^-1 M^-1 (Cz - C G)
    e = lc1 * d0                            # E = Tv e
    bz = basis.Ct @ e - lm(plant.Kz) + basis.Kt @ (basis.R @ g)
    bzd = -lc1 * (o >= 1)
    bzdd = -lmz * d2
    lf = lm(plant.F)
    oq, ov, oa = plant.Oq @ basis.Tw, plant.Ov @ basis.Tv, plant.Oa @ basis.Tv
    oqv = plant.Oq @ basis.Tv
    ya, yb = oq - oa @ basis.Kt, ov - oa @ basis.Ct
    yu = plant.Pf + oa @ lf
    yz = -oqv @ g - ov @ e + oa @ bz + plant.Pz
    yzd = -ov @ g - oa @ e + oa @ bzd + plant.Pv
    yzdd = -oa @ g + oa @ bzdd + plant.Pa
    mag = np.abs
    _improper(plant, yzd, mag(ov) @ mag(g) + mag(oa) @ (mag(e) + mag(bzd)) + mag(plant.Pv), d0, "first")
    _improper(plant, yzdd, mag(oa) @ (mag(g) + mag(bzdd)) + mag(plant.Pa), (o == 0) | d1, "second")

    # integrator states: zeta (z) for velocity/acceleration inputs, nu (z') for acceleration inputs
    iz, inu = np.flatnonzero(o >= 1), np.flatnonzero(d2)
    nz, nn = iz.size, inu.size
    N = 2 * n + nz + nn
    zx, zu = np.zeros((m, N)), np.diag(d0.astype(float))
    zx[iz, 2 * n + np.arange(nz)] = 1.0
    zdx, zdu = np.zeros((m, N)), np.diag(d1.astype(float))
    zdx[inu, 2 * n + nz + np.arange(nn)] = 1.0
    zddu = np.diag(d2.astype(float))

    A = np.zeros((N, N))
    B = np.zeros((N, m))
    A[:n, n:2 * n] = basis.R
    B[:n] = -basis.R @ e @ zu
    A[n:2 * n, :n], A[n:2 * n, n:2 * n] = -basis.Kt, -basis.Ct
    A[n:2 * n] += bz @ zx + bzd @ zdx
    B[n:2 * n] = lf + bz @ zu + bzd @ zdu + bzdd @ zddu
    A[2 * n:2 * n + nz] = zdx[iz]
    B[2 * n:2 * n + nz] = zdu[iz]
    B[2 * n + nz:, inu] = np.eye(nn)
    Cm = np.zeros((p, N))
    Cm[:, :n], Cm[:, n:2 * n] = ya, yb
    Cm += yz @ zx + yzd @ zdx
    D = yu + yz @ zu + yzd @ zdu + yzdd @ zddu
    scale = np.ones(N)
    if realization == "physical" and balance:
        _, (scale, _) = sl.matrix_balance(A, permute=False, separate=True)
        A = A / scale[:, None] * scale[None, :]
        B = B / scale[:, None]
        Cm = Cm * scale[None, :]
    ins = [control_name(u) for u in plant.inputs]
    states = (basis.names[0] + basis.names[1] + [f"{ins[j]}:z" for j in iz]
              + [f"{ins[j]}:zdot" for j in inu])
    return A, B, Cm, D, list(states), scale
