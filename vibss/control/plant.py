"""Synthesis-ready generalized plants ``(w, u) -> (z, y)`` built from a model's actuators and sensors.

The plant is the one state-space realization of :mod:`vibss.linear.statespace` (modal, well scaled)
with four named groups:

- ``w`` disturbances: ground motion (``ground.z.acc``, ``ground.x.vel``, ``ground.z.disp``) or a
  support's (``<support>.z.acc`` ...),
  forces on bodies (``table.fz``), and optionally measurement noise ``<measurement>.noise``;
- ``u`` actuator commands ``actuator.<name>.u`` (through each actuator's bandwidth, if any);
- ``z`` performance outputs: any output signal, plus an actuator command (``actuator.<name>.u``:
  the control effort);
- ``y`` measurements: sensors (``sensor.<name>``) or any output signal; or ``"states"`` (the
  plant's states themselves, for state feedback).

**Ground motion without integrators.** A ground velocity or acceleration input realized in absolute
coordinates carries one or two integrator states (the ground's own displacement and velocity) that
no actuator can move and no relative sensor can see: ``lqr``, ``lqe`` and ``hinfsyn`` then fail. The
plant is written instead in the motion relative to ground, ``q = T z + r`` (``T`` moves every free
DOF rigidly with ground, so ``K T + Kz = 0`` and ``C T + Cz = 0``): an acceleration ``a`` enters as
the inertia force ``-M T a`` and a velocity ``v`` as the displacement-like input of
``M r'' + C r' + K r = -M T v'`` (the states are then the relative displacement and the absolute
velocity ``r' + T v``), each with ``2 n`` states. For a support's motion ``T`` is its quasi-static
influence ``T = -K^-1 Kz`` (the free DOFs' static displacement under a unit motion of that support
alone; the rigid motion for the whole ground), so ``K T + Kz = 0`` again; ``C T + Cz = 0`` then holds
when the mounts' damping is proportional to their stiffness, and otherwise the support's velocity or
acceleration is refused with the advice to give it as a displacement. Outputs that need the
integral of the disturbance (absolute displacement under a velocity input; absolute displacement or
velocity under an acceleration input) are refused with the input kind that gives them.

Examples
--------
>>> from vibss import Body, Model, Mount, MountType
>>> from vibss.model.actuation import Actuator, Sensor
>>> t = MountType("iso", [1e4, 1e4, 1e4], [20.0, 20.0, 20.0])
>>> m = Model([Body("b", 10.0, [1, 1, 1])], [Mount("m", t, "b")],
...           actuators=[Actuator("a", mount="m", axis=3)],
...           sensors=[Sensor("v", "velocity", body="b", direction=[0, 0, 1])])
>>> P = plant(m, disturbances=["ground.z.vel"], performance=["b.z.acc"], measurements=["sensor.v"],
...           dofs=["b.z"])
>>> P.groups["w"], P.groups["u"], P.nstates
(['ground:z:vel'], ['actuator:a:u'], 2)
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from ..errors import ControlDesignError, ModelError
from ..linear.plant.assemble import Assembly, assemble
from ..linear.plant.plant import Plant
from ..linear.plant.build import build_plant
from ..linear.plant.labels import control_name
from ..linear.solve.exact import SingularMatrixError, lu_solver
from ..linear.statespace import NamedStateSpace, statespace
from ..model.geometry import point_transfer
from ..model.model import DOF_NAMES, GROUND, Model

__all__ = ["plant", "GeneralizedPlant", "vibss_name"]


def vibss_name(label: str) -> str:
    """A python-control signal label in the vibss spelling (``engine:z`` -> ``engine.z``)."""
    return label.replace(":", ".")


class GeneralizedPlant(NamedStateSpace):
    """A :class:`~vibss.linear.statespace.NamedStateSpace` with input groups ``w, u`` and output
    groups ``z, y`` (inputs ordered ``[w, u]``, outputs ``[z, y]``, as ``control.hinfsyn`` wants).

    Attributes
    ----------
    groups : dict of str to list of str
        ``"w"``, ``"u"``, ``"z"``, ``"y"``: the python-control labels of each group.
    units : dict of str to str
        SI unit of every input and output (vibss spelling).
    model : Model
        The model it was built from.
    recipe : dict
        The arguments of :func:`plant` that built it (a variant of the model is built alike by
        :func:`vibss.control.robustness`).
    """

    groups: dict[str, list[str]]
    units: dict[str, str]
    recipe: dict[str, Any]

    @property
    def nw(self) -> int:
        """Number of disturbance inputs."""
        return len(self.groups["w"])

    @property
    def nu(self) -> int:
        """Number of control inputs."""
        return len(self.groups["u"])

    @property
    def nz(self) -> int:
        """Number of performance outputs."""
        return len(self.groups["z"])

    @property
    def ny(self) -> int:
        """Number of measurements."""
        return len(self.groups["y"])

    def block(self, outputs: str, inputs: str) -> NamedStateSpace:
        """One block of the partition, e.g. ``P.block("y", "u")`` (P22).

        Parameters
        ----------
        outputs : {"z", "y"}
        inputs : {"w", "u"}
        """
        if outputs not in ("z", "y") or inputs not in ("w", "u"):
            raise ModelError(f"block: expected outputs 'z' or 'y' and inputs 'w' or 'u', got {outputs!r}, {inputs!r}")
        return self[self.groups[outputs], self.groups[inputs]]


def _names(items: Any, what: str) -> list[str]:
    if items is None:
        return []
    if isinstance(items, str):
        items = [items]
    out = []
    for x in items:
        if not isinstance(x, str):
            raise ModelError(f"{what}: expected signal names (str), got {x!r}")
        out.append(x.replace(":", "."))
    dup = sorted({x for x in out if out.count(x) > 1})
    if dup:
        raise ModelError(f"{what}: signal(s) {dup} given more than once")
    return out


def _actuators(model: Model, actuators: Any) -> list[Any]:
    found = {a.name: a for a in model.actuators}
    if actuators is None:
        if not found:
            raise ModelError("actuators: the model has no actuators; add Actuator(...) to the model "
                             "(or [[actuator]] tables to the file)")
        return list(model.actuators)
    out = []
    for name in _names(actuators, "actuators"):
        key = name[len("actuator."):].rsplit(".", 1)[0] if name.startswith("actuator.") else name
        if key not in found:
            from ..errors import did_you_mean
            raise ModelError(f"actuators: unknown actuator {name!r}; the model's actuators are "
                             f"{sorted(found)}" + did_you_mean(key, found))
        out.append(found[key])
    if not out:
        raise ModelError("actuators: give at least one actuator")
    return out


def _rigid_map(model: Model, dofs: Sequence[str], name: str) -> np.ndarray:
    """(n,) motion of the free DOFs when ground moves rigidly by one unit of ``name``'s DOF."""
    parts = name.split(".")
    k = DOF_NAMES.index(parts[1])
    g = np.zeros(6)
    g[k] = 1.0
    out = np.zeros(len(dofs))
    for i, label in enumerate(dofs):
        body, dof = label.rsplit(".", 1)
        j = DOF_NAMES.index(dof)
        full = np.concatenate([point_transfer(model.body(body).cog) @ g, g[3:]])
        out[i] = full[j]
    return out


def _support_map(mech: Plant, j: int, name: str) -> np.ndarray:
    """(n,) quasi-static motion of the free DOFs under a unit motion of one support: ``-K^-1 Kz``."""
    try:
        t = np.asarray(lu_solver(mech.K)(-np.asarray(mech.Kz[:, j], dtype=float)))
    except SingularMatrixError:
        t = np.full(mech.K.shape[0], np.nan)
    if not np.all(np.isfinite(t)):
        raise ControlDesignError(f"disturbances: {name!r}: the stiffness is singular (a free motion), so "
                                 "the quasi-static motion under the support is not defined; give the support "
                                 f"motion as a displacement ('{name.rsplit('.', 1)[0]}.disp') instead")
    return t


def relative_plant(mech: Plant, model: Model) -> Plant:
    """The plant with its ground velocity/acceleration inputs written relative to ground (see the
    module docstring): no integrator states in its realization.

    Parameters
    ----------
    mech : Plant
        From :func:`~vibss.linear.plant.build.build_plant` (possibly restricted to some DOFs).
    model : Model
        Its model (for the rigid motion of ground).

    Returns
    -------
    Plant
        Acceleration inputs become inertia-force columns, velocity inputs displacement-like
        inputs (``Cz = M T``); the input names stay. For state-space realization only (the
        ``kinds`` no longer say what the signals are).

    Raises
    ------
    ControlDesignError
        A body DOF is prescribed, the rigid-motion identity fails, or an output needs the integral of
        a disturbance.
    """
    changes: dict[str, Any] = {k: np.array(getattr(mech, k), dtype=float)
                                      for k in ("F", "Kz", "Cz", "Mz", "Hz", "Pz", "Pv", "Pa", "Pf")}
    kinds = list(mech.kinds)
    scale_k = np.abs(mech.K).max(initial=0.0) or 1.0
    scale_c = np.abs(mech.C).max(initial=0.0) or 1.0
    for j, (u, kind) in enumerate(zip(mech.inputs, mech.kinds)):
        if kind == "force" or kind == "displacement":
            continue
        head = u.split(".", 1)[0]
        if head != GROUND and head not in model.support_names:
            raise ControlDesignError(f"disturbances: {u!r} prescribes a body DOF; a control plant takes "
                                     "ground motion (ground.<dof>.acc|vel|disp), a support's motion "
                                     "(<support>.<dof>.acc|vel|disp) and forces as disturbances")
        if getattr(mech, "branches", None) is not None:
            raise ControlDesignError(f"disturbances: {u!r}: the model has frequency-dependent mounts (rheology), "
                                     "whose internal states the relative-motion realization does not carry; "
                                     "give the ground motion as a displacement ('.disp') instead")
        t = _rigid_map(model, mech.dofs, u) if head == GROUND else _support_map(mech, j, u)
        bad_k = np.abs(mech.K @ t + mech.Kz[:, j]).max(initial=0.0) > 1e-9 * scale_k * max(1.0, np.abs(t).max())
        bad_c = np.abs(mech.C @ t + mech.Cz[:, j]).max(initial=0.0) > 1e-9 * scale_c * max(1.0, np.abs(t).max())
        if (bad_k or bad_c or np.any(mech.Mz[:, j])) and head != GROUND:
            raise ControlDesignError(f"disturbances: {u!r}: the dampers do not follow the quasi-static motion "
                                     f"under support {head!r} (damping not proportional to stiffness: "
                                     "C T + Cz != 0), so its relative-motion realization is not exact; "
                                     f"give the support motion as a displacement ('{u.rsplit('.', 1)[0]}.disp') instead")
        if bad_k or bad_c or np.any(mech.Mz[:, j]):
            raise ControlDesignError(f"disturbances: {u!r}: the free DOFs do not follow a rigid motion of ground "
                                     "without deflecting a mount (DOFs restricted away that couple to it?); "
                                     "give the ground motion as a displacement ('.disp') instead")
        mt = mech.M @ t
        integral = mech.Oq @ t + mech.Pz[:, j]
        need = [y for y, v in zip(mech.outputs, integral) if abs(v) > 1e-12]
        if kind == "acceleration":
            first = mech.Ov @ t + mech.Pv[:, j]
            need += [y for y, v in zip(mech.outputs, first) if abs(v) > 1e-12 and y not in need]
        if need:
            better = "'.vel' (for velocities) or '.disp'" if kind == "acceleration" else "'.disp'"
            raise ControlDesignError(f"outputs {need} need the integral of the {kind} disturbance {u!r} "
                                     f"(absolute motion of lower order than the input); give the ground motion "
                                     f"as {better}, or measure relative motion or acceleration")
        for key in ("Kz", "Cz", "Mz", "Hz", "Pz", "Pv", "Pa"):
            changes[key][:, j] = 0.0
        if kind == "acceleration":           # M r'' + C r' + K r = -M T a
            changes["F"][:, j] = -mt
            changes["Pf"][:, j] = mech.Oa @ t + mech.Pa[:, j]
            kinds[j] = "force"
        else:                                # velocity v: M r'' + C r' + K r = -M T v', v displacement-like
            changes["Cz"][:, j] = mt
            changes["Pz"][:, j] = mech.Ov @ t + mech.Pv[:, j]
            changes["Pv"][:, j] = mech.Oa @ t + mech.Pa[:, j]
            kinds[j] = "displacement"
    return dataclasses.replace(mech, kinds=tuple(kinds), mounts=None, **changes)


def _dynamics(actuator: Any) -> Any:
    """The command -> force system of an actuator (None: ideal)."""
    import control

    if actuator.dynamics is not None:
        return control.ss(actuator.dynamics)
    if actuator.bandwidth is None:
        return None
    wb = 2 * np.pi * actuator.bandwidth
    return control.ss([[-wb]], [[wb]], [[1.0]], [[0.0]])


def plant(model: Model | Assembly, disturbances: Sequence[str] | None = None,
          actuators: Sequence[str] | None = None, performance: Sequence[str] | None = None,
          measurements: Sequence[str] | str | None = None, *, noise: float | Mapping[str, float] | None = None,
          dofs: Sequence[str] | None = None, modal_damping: float | None = None,
          ideal_actuators: bool = False, name: str | None = None) -> GeneralizedPlant:
    """The generalized plant ``(w, u) -> (z, y)`` of a model with actuators and sensors.

    Parameters
    ----------
    model : Model or Assembly
        With :class:`~vibss.model.actuation.Actuator` and (usually) :class:`~vibss.model.actuation.Sensor`
        elements.
    disturbances : sequence of str
        ``w``: ground motion (``ground.<dof>.acc|vel|disp``) and force inputs (see :mod:`vibss.signals`).
    actuators : sequence of str or None
        Actuator names (or their signals); default every actuator of the model. The control
        inputs are their commands ``actuator.<name>.u`` [N or N m].
    performance : sequence of str
        ``z``: output signals, and actuator commands (``actuator.<name>.u``) to weigh effort.
    measurements : sequence of str, "states" or None
        ``y``: output signals (sensors ``sensor.<name>`` or any other); ``"states"`` measures the
        plant's states (for state feedback); default every sensor of the model.
    noise : float, mapping or None
        Add a noise input ``<measurement>.noise`` to ``w`` for every measurement (a float: its
        scale in the measurement's unit; a mapping: per measurement, vibss or python-control spelling).
        Output feedback synthesis (H2, H-infinity, LQG) needs it (``D21`` full row rank).
    dofs : sequence of str or None
        Keep only these free DOFs (e.g. ``["body.z", "wheel.z"]`` for a vertical model); exact when the
        others are not coupled to them.
    modal_damping : float or None
        Extra modal damping ratio (as :func:`~vibss.linear.plant.build.build_plant`).
    ideal_actuators : bool
        Leave out the actuators' bandwidths (force = command): a design model for synthesis when the
        actuator poles are far above the loop's band; close the loop on the full plant to check it.
    name : str or None
        System name (default: the model's, python-control spelling).

    Returns
    -------
    GeneralizedPlant
        Inputs ``[w, u]``, outputs ``[z, y]``; modal states (``mode<k>:pos``, ``mode<k>:vel``) plus one
        state per actuator bandwidth (``actuator:<name>:force``).

    Raises
    ------
    ModelError
        Unknown or repeated signals, actuators or measurements.
    ControlDesignError
        An output needs the integral of a disturbance (see the module docstring).
    """
    import control

    asm = model if isinstance(model, Assembly) else assemble(model)
    mdl = asm.model
    w = _names(disturbances, "disturbances")
    if not w and noise is None:
        raise ModelError("disturbances: give at least one disturbance, e.g. 'ground.z.acc' or "
                         f"'{mdl.body_names[0]}.fz'")
    acts = _actuators(mdl, actuators)
    z = _names(performance, "performance")
    y, states_y = _measurements(mdl, measurements)
    commands = {a.command: k for k, a in enumerate(acts)}
    bad = [s for s in y if s in commands]
    if bad:
        raise ModelError(f"measurements: {bad} are actuator commands, not measurements")
    wrong = [s for s in w if s.startswith("actuator.")]
    if wrong:
        raise ModelError(f"disturbances: {wrong} are actuators; list them in actuators=")
    mech_out = list(dict.fromkeys([s for s in z if s not in commands] + y))
    mech = build_plant(asm, [*w, *[a.signal for a in acts]], mech_out, modal_damping=modal_damping)
    if dofs is not None:
        mech = mech.restrict(list(dofs))
    rel = relative_plant(mech, mdl)
    core = statespace(rel)
    nw, na = len(w), len(acts)
    A, B, C, D, states = _actuator_dynamics(core.A, core.B, core.C, core.D, list(core.state_labels), acts, nw,
                                            ideal_actuators)
    ns = A.shape[0]
    y_labels = [vibss_name(s) for s in states] if states_y else y
    Cg, Dg = _output_rows(C, D, z, y, mech_out, commands, nw + na, states_y)
    # measurement noise inputs
    noise_names: list[str] = []
    if noise is not None:
        scales = _noise_scales(noise, y_labels)
        Dn = np.zeros((Cg.shape[0], len(y_labels)))
        Dn[len(z):, :] = np.diag(scales)
        noise_names = [f"{s}.noise" for s in y_labels]
        Dg = np.hstack([Dg[:, :nw], Dn, Dg[:, nw:]])
        B = np.hstack([B[:, :nw], np.zeros((ns, len(y_labels))), B[:, nw:]])
    units = _units(mech, mdl, z, y, y_labels, states_y, acts, w, noise_names)
    win = [control_name(s) for s in [*w, *noise_names]]
    uin = [control_name(a.command) for a in acts]
    zout = [control_name(s) for s in z]
    yout = [control_name(s) for s in y_labels]
    P = GeneralizedPlant(A, B, Cg, Dg, inputs=win + uin, outputs=zout + yout, states=states,
                         name=control_name(name or mdl.name).replace(" ", "_"))
    P.groups = {"w": win, "u": uin, "z": zout, "y": yout}
    P.units = units
    P.model = mdl
    P.actuator_elements = acts
    P.recipe = {"disturbances": list(disturbances or []), "actuators": [a.name for a in acts],
                "performance": list(performance or []),
                "measurements": measurements if isinstance(measurements, str) or measurements is None
                else list(measurements), "noise": noise, "dofs": None if dofs is None else list(dofs),
                "modal_damping": modal_damping, "ideal_actuators": ideal_actuators, "name": name}
    return P


def _measurements(model: Model, measurements: Sequence[str] | str | None) -> tuple[list[str], bool]:
    """The measured output signals ``y``, and whether the plant's states are measured instead."""
    if isinstance(measurements, str) and measurements == "states":
        return [], True
    if measurements is None:
        y = [s.signal for s in model.sensors]
        if not y:
            raise ModelError("measurements: the model has no sensors; name output signals or add "
                             "Sensor(...) elements (or measurements='states')")
        return y, False
    return _names(measurements, "measurements"), False


def _actuator_dynamics(A: np.ndarray, B: np.ndarray, C: np.ndarray, D: np.ndarray, states: list[str],
                       acts: Sequence[Any], nw: int, ideal: bool) -> tuple[Any, Any, Any, Any, list[str]]:
    """Each actuator's command -> force dynamics in series with its input column ``nw + k`` (none
    for ``ideal`` actuators), its states appended."""
    for k, a in enumerate(acts):
        dyn = None if ideal else _dynamics(a)
        if dyn is None:
            continue
        col = nw + k
        na_ = dyn.nstates
        n0 = A.shape[0]
        A = np.block([[A, B[:, [col]] @ dyn.C], [np.zeros((na_, n0)), dyn.A]])
        bcol = np.vstack([B[:, [col]] @ dyn.D, dyn.B])
        B = np.vstack([B, np.zeros((na_, B.shape[1]))])
        B[:, [col]] = bcol
        C = np.hstack([C, D[:, [col]] @ dyn.C])
        D = D.copy()
        D[:, [col]] = D[:, [col]] @ dyn.D
        states = states + [f"actuator:{a.name}:force" if na_ == 1 else f"actuator:{a.name}:x{i + 1}"
                           for i in range(na_)]
    return A, B, C, D, states


def _output_rows(C: np.ndarray, D: np.ndarray, z: Sequence[str], y: Sequence[str], mech_out: list[str],
                 commands: Mapping[str, int], n_in: int, states_y: bool) -> tuple[np.ndarray, np.ndarray]:
    """``(Cg, Dg)``: the z rows (mechanical outputs, or actuator commands fed through), then the y
    rows (mechanical outputs, or every state)."""
    ns, nw = C.shape[1], n_in - len(commands)
    rows, drows = [], []
    for s in z:
        if s in commands:
            rows.append(np.zeros(ns))
            d = np.zeros(n_in)
            d[nw + commands[s]] = 1.0
            drows.append(d)
        else:
            i = mech_out.index(s)
            rows.append(C[i])
            drows.append(D[i])
    for s in y:
        i = mech_out.index(s)
        rows.append(C[i])
        drows.append(D[i])
    if states_y:
        rows += list(np.eye(ns))
        drows += [np.zeros(n_in)] * ns
    return np.array(rows).reshape(len(rows), ns), np.array(drows).reshape(len(rows), n_in)


def _noise_scales(noise: Any, y: Sequence[str]) -> np.ndarray:
    if isinstance(noise, Mapping):
        given = {str(k).replace(":", "."): v for k, v in noise.items()}
        unknown = sorted(set(given) - set(y))
        if unknown:
            raise ModelError(f"noise: {unknown} are not measurements; measurements are {list(y)}")
        vals = [given.get(s, 0.0) for s in y]
    else:
        vals = [noise] * len(y)
    out = np.array(vals, dtype=float)
    if out.shape != (len(y),) or not np.all(np.isfinite(out)) or np.any(out < 0):
        raise ModelError(f"noise: expected scales >= 0 (one per measurement or one for all), got {noise!r}")
    return out


def _units(mech: Plant, model: Model, z: Sequence[str], y: Sequence[str], y_labels: Sequence[str],
           states_y: bool, acts: Sequence[Any], w: Sequence[str], noise: Sequence[str]) -> dict[str, str]:
    out = dict(zip(mech.outputs, mech.units))
    for a in acts:
        out[a.command] = "N" if a.kind == "force" else "N m"
    for s in w:
        if s.rsplit(".", 1)[-1] in ("disp", "vel", "acc"):
            dof = s.split(".")[-2]
            base = "rad" if dof.startswith("r") else "m"
            out[s] = base + {"disp": "", "vel": "/s", "acc": "/s^2"}[s.rsplit(".", 1)[-1]]
        else:
            out[s] = "N m" if s.rsplit(".", 1)[-1].startswith("m") else "N"
    for s in noise:
        out[s] = out.get(s[:-len(".noise")], "-")
    if states_y:
        for s in y_labels:
            out[s] = "state"
    return {k: v for k, v in out.items() if k in {*z, *y_labels, *w, *noise, *(a.command for a in acts)}}
