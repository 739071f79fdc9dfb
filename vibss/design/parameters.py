"""Design parameters of a mount layout: rates, positions and orientation angles of mounts, alone or
tied together, with a model rebuilt for any values and the exact stiffness derivatives.

A parameter names one mount quantity (``"front.k3"``) or ties several with factors
(:class:`Parameter`). Kinds and what a value means:

- ``k1``, ``k2``, ``k3``: the mount's rate along its local axis 1, 2, 3 [N/m], absolute
  (``factor * value`` for each tied mount). A mount whose rate changes gets a mount type of its
  own (``"<type>.<mount>"``) unless every mount of that type gets the same rates.
- ``x``, ``y``, ``z``: a shift of the mount point along a global axis [m] from where the model
  puts it (value 0 = as given).
- ``rx``, ``ry``, ``rz``: a rotation of the mount's local axes about a global axis [rad] from the
  model's orientation (value 0 = as given); several on one mount compose as
  ``R_x(rx) R_y(ry) R_z(rz) T_0``.
- ``k1/k3``, ``k2/k3``, ``k1/k2``, ``k2/k1``, ``k3/k1``, ``k3/k2``: a rate ratio [-]: the numerator
  rate is ``factor * value`` times the denominator rate (as the model gives it, or as a rate
  parameter of the same mount sets it). A mount cannot have both a ratio and a rate on the same
  numerator axis.

Derivatives of ``K = sum_p B_p^T k_p B_p`` (``k_p = T diag(k) T^T``, ``B_p`` the map from DOFs to
mount deflection): a rate gives ``B^T t_j t_j^T B``; a shift along ``e_i`` changes the lever arms,
``dB = [0 | -[e_i]x]`` on the mount's body minus the same on its other end; a rotation about an
axis ``w`` gives ``dk_p = [w]x k_p - k_p [w]x``.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.spatial.transform import Rotation

from ..errors import ArgumentError, ModelError, did_you_mean
from ..linear.plant.assemble import Assembly
from ..model.geometry import Orientation, point_transfer, skew
from ..model.model import Model, MountType

__all__ = ["Parameter", "KINDS", "parameters_of", "apply", "stiffness_derivatives", "current_values"]

KINDS: dict[str, str] = {"k1": "N/m", "k2": "N/m", "k3": "N/m", "x": "m", "y": "m", "z": "m",
                         "rx": "rad", "ry": "rad", "rz": "rad",
                         "k1/k3": "-", "k2/k3": "-", "k1/k2": "-", "k2/k1": "-", "k3/k1": "-", "k3/k2": "-"}
"""Parameter kinds and their units."""

_RATE = ("k1", "k2", "k3")
_SHIFT = ("x", "y", "z")
_ANGLE = ("rx", "ry", "rz")
_RATIO = ("k1/k3", "k2/k3", "k1/k2", "k2/k1", "k3/k1", "k3/k2")


def ratio_axes(kind: str) -> tuple[int, int]:
    """(numerator, denominator) local axes (0-based) of a rate-ratio kind ``"ki/kj"``."""
    num, den = kind.split("/")
    return _RATE.index(num), _RATE.index(den)


@dataclass(frozen=True)
class Parameter:
    """One design variable: a mount quantity, or several tied with factors.

    Parameters
    ----------
    name : str
        Label (e.g. ``"engine.k3"``, ``"front pair height"``).
    targets : sequence of (mount, kind, factor)
        Mount name, kind (``k1 k2 k3 x y z rx ry rz``) and factor [-]: the mount quantity is
        ``factor * value``. All targets share one unit.

    Examples
    --------
    >>> Parameter.coerce("engine.xz.k3").targets
    (('engine.xz', 'k3', 1.0),)
    >>> Parameter("height", [("a", "z", 1.0), ("b", "z", 1.0)]).unit
    'm'
    """

    name: str
    targets: Any

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name:
            raise ArgumentError(f"parameter: name must be a non-empty string, got {self.name!r}",
                                argument="name", received=self.name)
        out = []
        for t in self.targets:
            if not (isinstance(t, (tuple, list)) and len(t) == 3 and isinstance(t[0], str)
                    and t[1] in KINDS):
                raise ArgumentError(f"parameter {self.name!r}: targets: expected (mount, kind, factor) "
                                    f"with kind one of {list(KINDS)}, got {t!r}", argument="targets",
                                    received=t, expected=list(KINDS))
            out.append((t[0], t[1], float(t[2])))
        if not out:
            raise ArgumentError(f"parameter {self.name!r}: needs at least one target", argument="targets")
        if len({KINDS[k] for _, k, _ in out}) != 1:
            raise ArgumentError(f"parameter {self.name!r}: targets mix units "
                                f"{sorted({KINDS[k] for _, k, _ in out})}", argument="targets")
        object.__setattr__(self, "targets", tuple(out))

    @property
    def unit(self) -> str:
        """Unit of the value (N/m, m or rad)."""
        return KINDS[self.targets[0][1]]

    @property
    def is_rate(self) -> bool:
        """Whether the value is a rate or a rate ratio (absolute, positive) rather than a shift or
        an angle (an increment)."""
        return self.targets[0][1] in _RATE or self.targets[0][1] in _RATIO

    @classmethod
    def coerce(cls, value: Any) -> Parameter:
        """A Parameter, or ``"<mount>.<kind>"``."""
        if isinstance(value, Parameter):
            return value
        if isinstance(value, str) and "." in value:
            mount, kind = value.rsplit(".", 1)
            if kind in KINDS:
                return cls(value, [(mount, kind, 1.0)])
        raise ArgumentError(f"parameters: expected a Parameter or '<mount>.<kind>' with kind one of "
                            f"{list(KINDS)}, got {value!r}", argument="parameters", received=value,
                            expected=list(KINDS))


def parameters_of(model: Model, parameters: Any) -> tuple[Parameter, ...]:
    """Validated parameters (every target mount exists; names unique)."""
    if isinstance(parameters, (str, Parameter)) or not isinstance(parameters, Iterable):
        parameters = [parameters]
    out = tuple(Parameter.coerce(p) for p in parameters)
    names = [m.name for m in model.mounts]
    for p in out:
        for mount, _, _ in p.targets:
            if mount not in names:
                raise ArgumentError(f"parameter {p.name!r}: unknown mount {mount!r}"
                                    + did_you_mean(mount, names), argument="parameters",
                                    received=mount, expected=names)
    if len({p.name for p in out}) != len(out):
        raise ArgumentError("parameters: names must be unique", argument="parameters")
    rated = {(mount, _RATE.index(kind)): p.name for p in out for mount, kind, _ in p.targets if kind in _RATE}
    for p in out:
        for mount, kind, _ in p.targets:
            if kind in _RATIO and (mount, ratio_axes(kind)[0]) in rated:
                raise ArgumentError(f"parameter {p.name!r}: mount {mount!r}: {kind} sets k{ratio_axes(kind)[0] + 1}, "
                                    f"which parameter {rated[(mount, ratio_axes(kind)[0])]!r} also sets; "
                                    "give one of them", argument="parameters", received=p.name)
    if not out:
        raise ArgumentError("parameters: give at least one", argument="parameters")
    return out


def current_values(model: Model, parameters: Sequence[Parameter]) -> np.ndarray:
    """Values of the parameters in ``model``: rates from the first target, 0 for shifts and angles."""
    by_name = {m.name: m for m in model.mounts}
    out = np.zeros(len(parameters))
    for i, p in enumerate(parameters):
        mount, kind, factor = p.targets[0]
        k = by_name[mount].type.stiffness
        if kind in _RATE:
            out[i] = k[_RATE.index(kind)] / factor
        elif kind in _RATIO:
            num, den = ratio_axes(kind)
            if k[den] == 0:
                raise ArgumentError(f"parameter {p.name!r}: mount {mount!r} has no rate along axis "
                                    f"{den + 1}, so {kind} is undefined", argument="parameters", received=p.name)
            out[i] = k[num] / k[den] / factor
    return out


def _angles(model: Model, parameters: Sequence[Parameter], values: np.ndarray) -> dict[str, np.ndarray]:
    ang: dict[str, np.ndarray] = {}
    for p, v in zip(parameters, values):
        for mount, kind, factor in p.targets:
            if kind in _ANGLE:
                ang.setdefault(mount, np.zeros(3))[_ANGLE.index(kind)] += factor * v
    return ang


def apply(model: Model, parameters: Sequence[Parameter], values: Any) -> Model:
    """Copy of ``model`` with the parameters set to ``values`` (see the module docstring).

    Parameters
    ----------
    model : Model
        The base model (shifts and angles are measured from it).
    parameters : sequence of Parameter
        The parameters (:func:`parameters_of`).
    values : (p,) array_like
        Their values [N/m, m, rad].

    Returns
    -------
    Model
    """
    values = np.asarray(values, dtype=float)
    by_name = {m.name: m for m in model.mounts}
    rates = {m: by_name[m].type.stiffness.copy() for m in by_name}
    shift = {m: np.zeros(3) for m in by_name}
    for p, v in zip(parameters, values):
        for mount, kind, factor in p.targets:
            if kind in _RATE:
                rates[mount][_RATE.index(kind)] = factor * v
            elif kind in _SHIFT:
                shift[mount][_SHIFT.index(kind)] += factor * v
    for p, v in zip(parameters, values):          # ratios after rates: the denominator is final
        for mount, kind, factor in p.targets:
            if kind in _RATIO:
                num, den = ratio_axes(kind)
                rates[mount][num] = factor * v * rates[mount][den]
    angles = _angles(model, parameters, values)
    # one mount type per (type, rates): keep the type's name where all its mounts agree
    groups: dict[str, set[bytes]] = {}
    for m in model.mounts:
        groups.setdefault(m.type.name, set()).add(rates[m.name].tobytes())
    types: dict[tuple[str, bytes], MountType] = {}
    mounts = []
    for m in model.mounts:
        r = rates[m.name]
        if np.array_equal(r, m.type.stiffness):
            mtype = m.type
        elif len(groups[m.type.name]) == 1:         # every mount of the type gets these rates
            mtype = types.setdefault((m.type.name, r.tobytes()), _with_rates(m.type, r))
        else:
            mtype = _own(m, r, types)
        change: dict[str, Any] = {"type": mtype}
        if np.any(shift[m.name]):
            change["at"] = m.at + shift[m.name]
        if m.name in angles:
            rot = Rotation.from_euler("XYZ", angles[m.name]).as_matrix()     # Rx Ry Rz
            change["orientation"] = Orientation(rot @ m.orientation.matrix)
        mounts.append(dataclasses.replace(m, **change))
    return model.replace(mounts=mounts)


def _own(m: Any, r: np.ndarray, types: dict[tuple[str, bytes], MountType]) -> MountType:
    """A mount type of the mount's own (named after it)."""
    name = f"{m.type.name}.{m.name}"
    return types.setdefault((name, r.tobytes()), _with_rates(m.type, r, name))


def _with_rates(t: MountType, r: np.ndarray, name: str | None = None) -> MountType:
    """The type with principal stiffnesses ``r``; a diagonal 6x6 matrix becomes the rates it is
    (a coupled one is refused before: the design tools vary principal rates only)."""
    if t.coupled:
        raise ModelError(f"design: mount type {t.name!r} has a 6x6 matrix with coupling terms; the design "
                         "tools vary principal rates only and do not take it yet")
    return dataclasses.replace(t, name=name or t.name, stiffness=r, stiffness_matrix=None, damping_matrix=None)


def refuse_coupled(model: Any, where: str) -> None:
    """A ModelError naming the first mount whose type has a coupled 6x6 matrix: the design tools
    vary the principal rates, which do not describe such a mount."""
    for m in model.mounts:
        if m.type.coupled:
            raise ModelError(f"{where}: mount {m.name!r} (type {m.type.name!r}) has a 6x6 stiffness_matrix "
                             "or damping_matrix with coupling terms; the design tools vary principal rates "
                             "only and do not take it yet")


def stiffness_derivatives(a: Assembly, parameters: Sequence[Parameter],
                          angles: dict[str, np.ndarray] | None = None) -> np.ndarray:
    """(p, n, n) exact ``dK/dp`` of each parameter at the assembled model.

    Parameters
    ----------
    a : Assembly
        The model at the parameters' values.
    parameters : sequence of Parameter
        The parameters.
    angles : mapping of mount name to (3,) ndarray or None
        The angle parameters' current values per mount [rad] (``rx ry rz``): the rotation axes of
        the composed ``R_x R_y R_z`` at those values; None: all zero.

    Returns
    -------
    (p, n, n) ndarray
        Derivatives [N/m per unit of each parameter].
    """
    model = a.model
    refuse_coupled(model, "stiffness_derivatives")
    index = {m.name: i for i, m in enumerate(model.mounts)}
    n = a.n
    out = np.zeros((len(parameters), n, n))
    lb, la = point_transfer(a.r_b), point_transfer(a.r_a)
    # rate ratios on a mount: a rate parameter on the denominator also moves the numerator
    follows: dict[tuple[str, int], list[int]] = {}
    for p in parameters:
        for mount, kind, _ in p.targets:
            if kind in _RATIO:
                num, den = ratio_axes(kind)
                follows.setdefault((mount, den), []).append(num)
    for ip, p in enumerate(parameters):
        for mount, kind, factor in p.targets:
            q = index[mount]
            B = np.zeros((3, n + a.nz))
            B[:, 6 * a.b_index[q]:6 * a.b_index[q] + 6] += lb[q]
            B[:, 6 * a.a_index[q]:6 * a.a_index[q] + 6] -= la[q]
            B = B[:, :n]
            kp = a.kp[q]
            if kind in _RATE or kind in _RATIO:
                j = _RATE.index(kind) if kind in _RATE else ratio_axes(kind)[0]
                k = model.mounts[q].type.stiffness
                T = model.mounts[q].orientation.matrix
                bt = T[:, j] @ B
                # d k_j / d value: 1 for a rate; the denominator rate for a ratio
                d = np.outer(bt, bt) * (1.0 if kind in _RATE else k[ratio_axes(kind)[1]])
                for num in follows.get((mount, j), ()) if kind in _RATE else ():
                    bn = T[:, num] @ B                  # k_num = ratio * k_j moves with k_j
                    d = d + (k[num] / k[j]) * np.outer(bn, bn)
            elif kind in _SHIFT:
                dl = np.zeros((3, n + a.nz))
                s = -skew(np.eye(3)[_SHIFT.index(kind)])
                dl[:, 6 * a.b_index[q] + 3:6 * a.b_index[q] + 6] += s
                dl[:, 6 * a.a_index[q] + 3:6 * a.a_index[q] + 6] -= s
                dB = dl[:, :n]
                d = dB.T @ kp @ B
                d = d + d.T
            else:
                w = _rotation_axis(_ANGLE.index(kind), (angles or {}).get(mount, np.zeros(3)))
                S = skew(w)
                d = B.T @ (S @ kp - kp @ S) @ B
                if np.any(a.krp[q]):                 # a 6x6 mount's rotational rates turn too
                    R = a.rotation_matrix()[3 * q:3 * q + 3].toarray()[:, :n]
                    d = d + R.T @ (S @ a.krp[q] - a.krp[q] @ S) @ R
            out[ip] += factor * d
    return out


def _rotation_axis(i: int, theta: np.ndarray) -> np.ndarray:
    """Axis of ``d/d theta_i (R_x R_y R_z)`` as a rotation applied on the left, at ``theta``."""
    e = np.eye(3)
    if i == 0:
        return e[0]
    rx = Rotation.from_euler("X", theta[0]).as_matrix()
    if i == 1:
        return rx @ e[1]
    ry = Rotation.from_euler("Y", theta[1]).as_matrix()
    return rx @ ry @ e[2]
