"""Static deflection: K q = F, with prescribed displacements, self-weight and clear failure modes.

The solve itself is the core's :func:`~vibss.linear.solve.static.static_solve` (the stiffness
factor's pivoted QR on models up to :data:`~vibss.linear.solve.static.FACTOR_MAX` DOFs, so soft
mounts beside 1e16 N/m links keep their digits; an equilibrated, condition-checked factorisation
above). A system that is not fully restrained (a body not connected to ground, a direction no mount
resists) has a singular K: if the load pushes along one of its free motions
:class:`~vibss.errors.AnalysisError` names it ("body 'engine' is free to move in x"); a load
orthogonal to every free motion is solved in the minimum-norm sense and the free motions are listed
in the result.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import Any, ClassVar

import numpy as np
import scipy.sparse as sp

from .linear.plant.assemble import Assembly, assemble
from ._validate import number, vector
from .nonlinear.kernels import equilibrium, nonlinear_mounts
from .linear.solve.static import SINGULAR_RCOND, static_solve
from ._deprecated import module_aliases, renamed_attribute
from .errors import AnalysisError, ModelError, did_you_mean
from .model.geometry import point_transfer
from .model.model import DOF_NAMES, GROUND, Model
from .results import Result, TextTable, jsonable, number_text, require_pandas

__all__ = ["StaticResult", "static", "center_of_rotation", "SINGULAR_RCOND"]

def center_of_rotation(deflection: np.ndarray, cog: np.ndarray,
                       rtol: float = 1e-9) -> np.ndarray | None:
    """Point of a rigid body whose small displacement is smallest: on the instantaneous screw axis.

    For a COG displacement u and rotation theta the point is ``g + theta x u / |theta|^2``, its
    displacement the part of u along theta. Pure translation has no centre (returns None).

    Parameters
    ----------
    deflection : (6,) array_like
        COG displacement [m] and rotation [rad].
    cog : (3,) array_like
        Centre of gravity [m].
    rtol : float
        Rotation counts as zero when ``|theta| * 1 m <= rtol * |u|``.
    """
    u, th = np.asarray(deflection[:3], float), np.asarray(deflection[3:], float)
    t2 = float(th @ th)
    if t2 == 0.0 or np.sqrt(t2) <= rtol * np.linalg.norm(u):
        return None
    return np.asarray(cog, float) + np.cross(th, u) / t2


@dataclass(frozen=True, eq=False)
class StaticResult(Result):
    """Static deflection of a model.

    Follows the result protocol (:mod:`vibss.results`): ``r['engine.z']`` is one DOF's deflection
    [m or rad]; ``output_labels`` are the body DOFs; there are no inputs and no python-control
    twin (``control`` is None).

    Attributes
    ----------
    model : Model
        The model.
    q : (n,) ndarray
        Deflection of every body DOF (x y z [m], rx ry rz [rad] per body).
    ground : (6,) ndarray
        Prescribed ground displacement (zeros when ground is fixed).
    load : (n,) ndarray
        Generalised load applied [N, N m].
    mount_deflection : (n_mounts, 3) ndarray
        Mount stretch ``d_body - d_to`` in global axes [m].
    mount_deflection_local : (n_mounts, 3) ndarray
        The same along each mount's local axes 1, 2, 3 [m].
    mount_force : (n_mounts, 3) ndarray
        Force each mount transmits into its ``to`` side (ground or the other body), global axes [N];
        the force on ``body`` is its negative.
    free_motions : tuple of str
        Descriptions of unrestrained motions the load did not excite (empty if fully restrained).
    mount_rotation : (n_mounts, 3) ndarray or None
        Relative rotation ``theta_body - theta_to`` of each mount, global axes [rad] (None: no
        6x6 mount in the model).
    mount_moment : (n_mounts, 3) ndarray or None
        Moment each 6x6 mount transmits into its ``to`` side, global axes [N m] (zero for the
        others; None: no 6x6 mount).
    case : str
        The load case solved ("" when the model names none).
    method : str
        How K q = F was solved.
    note : str
        Why (and what was left out: unrestrained motions, named load cases not applied).
    cases_left_out : tuple of str
        The model's named load cases this solve did not apply (named cases are opt-in).
    iterations : int
        Newton steps of the operating point of a model with nonlinear mounts (stops, curves); 0 for
        a linear model (one solve).
    """

    signal_kind: ClassVar[str] = "DOF"

    model: Model
    q: np.ndarray
    ground: np.ndarray
    load: np.ndarray
    mount_deflection: np.ndarray
    mount_deflection_local: np.ndarray
    mount_force: np.ndarray
    free_motions: tuple[str, ...] = field(default=())
    mount_rotation: np.ndarray | None = None
    mount_moment: np.ndarray | None = None
    case: str = ""
    method: str = "direct"
    note: str = ""
    cases_left_out: tuple[str, ...] = field(default=())
    iterations: int = 0

    @property
    def output_labels(self) -> tuple[str, ...]:
        """Body DOF labels (``'engine.z'``), in the order of :attr:`q`."""
        return tuple(f"{b}.{d}" for b in self.model.body_names for d in DOF_NAMES)

    @property
    def units(self) -> tuple[str, ...]:
        """Unit of each DOF: m for translations, rad for rotations."""
        return ("m", "m", "m", "rad", "rad", "rad") * len(self.model.bodies)

    def _item(self, i: int, j: int | None) -> float:
        return float(self.q[i])

    def body(self, name: str) -> np.ndarray:
        """(6,) deflection of body ``name``."""
        i = self.model.body_index(name)
        return self.q[6 * i:6 * i + 6]

    @property
    def deflections(self) -> np.ndarray:
        """(n_bodies, 6) deflections, one row per body."""
        return self.q.reshape(-1, 6)

    centre_of_rotation = renamed_attribute("centre_of_rotation", "center_of_rotation", "StaticResult")

    def center_of_rotation(self, name: str) -> np.ndarray | None:
        """Centre of rotation of body ``name`` in global coordinates [m], None for translation."""
        return center_of_rotation(self.body(name), self.model.body(name).cog)

    def point(self, body: str, at: Any, frame: str = "body") -> np.ndarray:
        """(3,) displacement of a point of ``body`` [m]."""
        return point_transfer(self.model.point(body, at, frame)) @ self.body(body)

    @property
    def control_points(self) -> dict[str, np.ndarray]:
        """Displacement of each control point [m]."""
        return {c.name: self.point(c.body, c.at, c.frame) for c in self.model.control_points}

    @property
    def reaction(self) -> np.ndarray:
        """(6,) total force [N] and moment about the global origin [N m] into ground, every support
        included (in statics a support is fixed ground); :attr:`reactions` splits it per support."""
        return np.sum(list(self.reactions.values()), axis=0)

    @property
    def reactions(self) -> dict[str, np.ndarray]:
        """(6,) force [N] and moment about the global origin [N m] into the rigid ``"ground"`` and
        into each named support, keyed by name (``"ground"`` first, then the supports in model
        order); a support no mount stands on gets zeros."""
        out = {GROUND: np.zeros(6)} | {s: np.zeros(6) for s in self.model.support_names}
        for p, m in enumerate(self.model.mounts):
            if m.to == GROUND:
                f = self.mount_force[p]
                r = out[m.support or GROUND]
                r[:3] += f
                r[3:] += np.cross(self.model.mount_point(m), f)
                if self.mount_moment is not None:
                    r[3:] += self.mount_moment[p]
        return out

    def to_dict(self) -> dict[str, Any]:
        """The spec's JSON structure (SI)."""
        bodies = {}
        for b in self.model.bodies:
            c = self.center_of_rotation(b.name)
            bodies[b.name] = {"deflection": self.body(b.name).tolist(),
                              "centre_of_rotation": None if c is None else c.tolist()}
        mounts = [{"name": m.name, "body": m.body, "to": m.to,
                   "deflection_global": self.mount_deflection[p].tolist(),
                   "deflection_local": self.mount_deflection_local[p].tolist(),
                   "force_global": self.mount_force[p].tolist(),
                   "force_local": (m.orientation.matrix.T @ self.mount_force[p]).tolist()}
                  | ({} if self.mount_moment is None or self.mount_rotation is None else {
                      "rotation_global": self.mount_rotation[p].tolist(),
                      "moment_global": self.mount_moment[p].tolist(),
                      "moment_local": (m.orientation.matrix.T @ self.mount_moment[p]).tolist()})
                  for p, m in enumerate(self.model.mounts)]
        return jsonable({"model": self.model.name, "case": self.case, "bodies": bodies, "mounts": mounts,
                         "control_points": self.control_points, "reaction": self.reaction,
                         **({"reactions": self.reactions} if self.model.support_names else {}),
                         "free_motions": self.free_motions, "method": self.method, "note": self.note})

    def summary(self) -> TextTable:
        """Body deflections [mm, mrad] and centres of rotation [m]."""
        rows = []
        for b in self.model.bodies:
            d = self.body(b.name)
            c = self.center_of_rotation(b.name)
            rows.append([b.name] + [f"{1e3 * v:.4f}" for v in d[:3]] + [f"{1e3 * v:.4f}" for v in d[3:]]
                        + ["pure translation" if c is None else "(" + ", ".join(number_text(v) for v in c) + ")"])
        return TextTable(["body", "x [mm]", "y [mm]", "z [mm]", "rx [mrad]", "ry [mrad]", "rz [mrad]",
                      "centre of rotation [m]"], rows, title="Bodies (COG)")

    def plot(self, ax: Any = None) -> Any:
        """Bar chart of the body deflections: :func:`vibss.plotting.plot_static`.

        Parameters
        ----------
        ax : (2,) sequence of Axes or None
            Axes for translations and rotations; default: a new figure.

        Returns
        -------
        matplotlib.figure.Figure
        """
        from .plotting import plot_static

        return plot_static(self, ax)

    def report(self) -> str:
        """Engineer's text report: body deflections, centres of rotation, points, mounts."""
        parts = [f"Static deflection of {self.model.name!r}" + (f", load case {self.case!r}" if self.case else ""),
                 self.summary().render()]
        if self.model.control_points:
            rows = [[k] + [f"{1e3 * x:.4f}" for x in v] for k, v in self.control_points.items()]
            parts.append(TextTable(["point", "x [mm]", "y [mm]", "z [mm]"], rows, title="Control points").render())
        if self.model.mounts:
            parts.append(self.mount_table().render())
            if self.mount_moment is not None:
                parts.append(self.moment_table().render())
        per_support = self.reactions
        r = np.sum(list(per_support.values()), axis=0)
        parts.append("Total reaction into ground: F = (" + ", ".join(number_text(v, ".2f") for v in r[:3])
                     + ") N, M about origin = (" + ", ".join(number_text(v, ".2f") for v in r[3:]) + ") N m")
        if self.model.support_names:
            rows = [[k] + [number_text(v, ".2f") for v in x] for k, x in per_support.items()]
            parts.append(TextTable(["into", "Fx [N]", "Fy [N]", "Fz [N]", "Mx [N m]", "My [N m]", "Mz [N m]"], rows,
                               title="Reaction per support (moments about the global origin)").render())
        if self.free_motions:
            parts.append("Unrestrained (not loaded, deflection set to zero): " + "; ".join(self.free_motions))
        if self.cases_left_out:
            parts.append("Note: " + _left_out_text(self.cases_left_out))
        return "\n\n".join(parts)

    def mount_table(self, under: str = "") -> TextTable:
        """Mount deflections [mm] in global and local axes, and forces [N] into the other side
        (``under``: what the title adds, e.g. the load case)."""
        rows = []
        for p, m in enumerate(self.model.mounts):
            rows.append([m.name, f"{m.body}->{m.support or m.to}"]
                        + [f"{1e3 * v:.4f}" for v in self.mount_deflection[p]]
                        + [f"{1e3 * v:.4f}" for v in self.mount_deflection_local[p]]
                        + [f"{v:.2f}" for v in self.mount_force[p]])
        return TextTable(["mount", "joins", "dx [mm]", "dy [mm]", "dz [mm]", "d1 [mm]", "d2 [mm]",
                          "d3 [mm]", "Fx [N]", "Fy [N]", "Fz [N]"], rows,
                         title=f"Mounts{under} (deflection = body side minus other side; force into the other side)")

    def html_tables(self) -> list[TextTable]:
        """Bodies, mounts (deflections and forces) and the 6x6 mounts' rotations and moments."""
        out = [self.summary()]
        if self.model.mounts:
            out.append(self.mount_table())
            if self.mount_moment is not None:
                out.append(self.moment_table())
        return out

    def moment_table(self) -> TextTable:
        """Relative rotations [mrad] and moments [N m] of the 6x6 mounts (global axes)."""
        rows = [[m.name, f"{m.body}->{m.support or m.to}"] + [f"{1e3 * v:.4f}" for v in self.mount_rotation[p]]
                + [f"{v:.3f}" for v in self.mount_moment[p]]
                for p, m in enumerate(self.model.mounts) if m.type.rotational] \
            if self.mount_moment is not None and self.mount_rotation is not None else []
        return TextTable(["mount", "joins", "rx [mrad]", "ry [mrad]", "rz [mrad]", "Mx [N m]", "My [N m]",
                      "Mz [N m]"], rows, title="6x6 mounts (rotation = body side minus other side; "
                                              "moment into the other side)")

    def to_pandas(self) -> Any:
        """DataFrame of body deflections (one row per body)."""
        pd = require_pandas()

        df = pd.DataFrame(self.deflections, index=pd.Index(self.model.body_names, name="body"),
                          columns=list(DOF_NAMES))
        df.attrs["units"] = {d: ("rad" if d.startswith("r") else "m") for d in DOF_NAMES}
        return df


def static(model: Model | Assembly, loads: np.ndarray | None = None, *,
           prescribed: Mapping[str, float] | None = None, gravity: bool = True,
           case: str | None = None) -> StaticResult:
    """Static deflection under loads, self-weight and prescribed displacements.

    Parameters
    ----------
    model : Model or Assembly
        The system.
    loads : (n,) array_like or None
        Generalised load vector [N, N m]; default: the model's loads (plus self-weight if the
        model has ``gravity`` and ``gravity=True``).
    prescribed : mapping of str to float, optional
        Prescribed displacements [m or rad] of body DOFs (``"engine.z"``) or ground DOFs
        (``"ground.z"``: every attachment to the rigid ground moves; ground rotations are about the
        origin), or a support's (``"front.z"``: a settlement of that support alone). Supports not
        named here are fixed.
    gravity : bool
        Include self-weight when the model defines gravity.
    case : str or None
        Load case: the unnamed loads plus the loads of this case. Named cases are opt-in: by
        default (None) only the unnamed loads apply, and the result's ``note`` names the cases left
        out. ``"self-weight"`` (:data:`SELF_WEIGHT`): gravity alone, no load at all.

    Returns
    -------
    StaticResult

    Raises
    ------
    AnalysisError
        When a load acts along a motion the mounts do not restrain.

    Examples
    --------
    >>> from vibss import Body, MountType, Mount, Model, symmetric
    >>> t = MountType("t", [1e5, 1e5, 2e5])
    >>> m = Model([Body("b", 100.0, [5, 5, 5])], symmetric(Mount("m", t, "b", at=[0.5, 0.5, 0])),
    ...           gravity=[0, 0, -9.81])
    >>> float(static(m).body("b")[2])   # m g / (4 kz)
    -0.0012262500000000001
    """
    a = model if isinstance(model, Assembly) else assemble(model)
    n = a.n
    cases = a.model.load_cases
    if case == SELF_WEIGHT:
        if a.model.gravity is None:
            raise ModelError(f"case {SELF_WEIGHT!r}: the model defines no gravity (Model(..., gravity=...))")
        if loads is not None:
            raise ModelError(f"case {SELF_WEIGHT!r} and loads: self-weight alone takes no load vector")
        f = a.load_vector(include_gravity=True, include_loads=False)
        return _solved(a, f, prescribed, SELF_WEIGHT)
    if case is not None and case not in cases:
        raise ModelError(f"case: unknown load case {case!r}; the model's cases are "
                         f"{cases + [SELF_WEIGHT] if a.model.gravity is not None else cases}"
                         + did_you_mean(case, cases))
    if loads is not None:
        return _solved(a, _vector(loads, n, "loads"), prescribed, case)
    r = _solved(a, a.load_vector(include_gravity=gravity, case="" if case is None else case), prescribed, case)
    if case is None and cases:          # named cases are opt-in: say which were left out
        r = replace(r, note="; ".join(x for x in (r.note, _left_out_text(tuple(cases))) if x),
                    cases_left_out=tuple(cases))
    return r


def _left_out_text(cases: tuple[str, ...]) -> str:
    """The sentence naming the load cases a solve did not apply."""
    return (f"load case{'s' if len(cases) > 1 else ''} {', '.join(map(repr, cases))} not applied "
            "(named cases are opt-in: static(..., case=NAME), --case NAME)")


SELF_WEIGHT = "self-weight"
"""The ``case`` of :func:`static` that is gravity alone (no load, named or not)."""


def _solved(a: Assembly, f: np.ndarray, prescribed: Mapping[str, float] | None, case: str | None) -> StaticResult:
    """The static deflection under the generalised load ``f`` [N, N m] and prescribed displacements."""
    n = a.n
    q = np.zeros(n)
    qg = np.zeros(a.nz)                   # supports are fixed ground unless prescribed
    fixed = np.zeros(n, dtype=bool)
    if prescribed is not None and not isinstance(prescribed, Mapping):
        raise ModelError(f"prescribed: expected a mapping of DOF label to value, got {prescribed!r}")
    for label, value in (prescribed or {}).items():
        if not isinstance(label, str):
            raise ModelError(f"prescribed: keys are DOF labels like 'engine.z' or 'ground.z', got {label!r}")
        value = number(value, f"prescribed[{label!r}]", unit="m or rad")
        body, _, dof = label.partition(".")
        if body == GROUND or body in a.model.support_names:
            if dof not in DOF_NAMES:
                raise ModelError(f"prescribed: unknown {body} DOF {label!r}; use {body}.x .. {body}.rz")
            qg[a.ground_offset(body) - n + DOF_NAMES.index(dof)] = value
        else:
            i = a.dof_index(label)
            q[i], fixed[i] = value, True
    free = np.flatnonzero(~fixed)
    if nonlinear_mounts(a.model):
        return _nonlinear(a, f, q, qg, fixed, case)
    K = a.K
    rhs = f[free] - _mul(K, q)[free] - a.Kg[free] @ qg
    kff = K[np.ix_(free, free)] if not sp.issparse(K) else K[free][:, free]
    solution = static_solve(a, rhs, free, kff)
    q[free], notes = solution.x, solution.free_motions
    delta, local, force, rotation, moment = _mount_fields(a, np.concatenate([q, qg]))
    method = ("minimum norm on the restrained subspace" if notes
              else "equilibrated sparse LU" if sp.issparse(kff) else "equilibrated Cholesky")
    return StaticResult(model=a.model, q=q, ground=qg[:6], load=f, mount_deflection=delta,
                        mount_deflection_local=local, mount_force=force, free_motions=notes,
                        mount_rotation=rotation, mount_moment=moment,
                        case=case or "", method=method,
                        note="unrestrained, not loaded: " + "; ".join(notes) if notes else "")


def _mount_fields(a: Assembly, full: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray | None, np.ndarray | None]:
    """Mount deflections (global, local) [m], forces [N] and, for 6x6 mounts, relative rotations [rad]
    and moments [N m] of the DOFs and ground motion ``full`` (linear rates; a nonlinear mount's
    forces are replaced by its laws' by the caller)."""
    delta = (a.deflection_matrix() @ full).reshape(-1, 3)
    t = np.array([m.orientation.matrix for m in a.model.mounts]).reshape(-1, 3, 3)
    local = np.einsum("pji,pj->pi", t, delta)
    force = np.einsum("pij,pj->pi", a.kp, delta)
    rotation = moment = None
    if np.any(a.krp) or a.has_coupling:   # 6x6 mounts: their relative rotations and moments
        rotation = (a.rotation_matrix() @ full).reshape(-1, 3)
        moment = np.einsum("pij,pj->pi", a.krp, rotation)
        if a.has_coupling:                # a full 6x6 matrix: force kc theta, moment kc^T delta
            force = force + np.einsum("pij,pj->pi", a.kcp, rotation)
            moment = moment + np.einsum("pji,pj->pi", a.kcp, delta)
    return delta, local, force, rotation, moment


def _nonlinear(a: Assembly, f: np.ndarray, q: np.ndarray, qg: np.ndarray, fixed: np.ndarray,
               case: str | None) -> StaticResult:
    """The operating point of a model with nonlinear mounts (:func:`vibss.nonlinear.kernels.equilibrium`):
    the mount forces from each axis's law."""
    if np.any(fixed) or np.any(qg):
        raise ModelError("prescribed: prescribed displacements with nonlinear mounts (stops, curves) are not "
                         "supported; apply the motion as a load, or linearise at the operating point "
                         "(vibss.operating_point(model).tangent)", argument="prescribed")
    eq = equilibrium(a, f, "static")
    q = eq.q
    delta, local, force, rotation, moment = _mount_fields(a, np.concatenate([q, qg]))
    for i, p in enumerate(eq.laws.mounts):          # their elastic forces from each axis's law
        law = a.model.mounts[p].type.laws
        force[p] = a.model.mounts[p].orientation.matrix @ np.array([float(law[j].force(eq.d[i, j])) for j in range(3)])
    names = [a.model.mounts[p].name for p in eq.laws.mounts]
    return StaticResult(model=a.model, q=q, ground=qg[:6], load=f, mount_deflection=delta,
                        mount_deflection_local=local, mount_force=force, mount_rotation=rotation,
                        mount_moment=moment, case=case or "", method="Newton on the mounts' laws",
                        note=f"nonlinear mounts {names}: the operating point by Newton ({eq.steps} steps)",
                        iterations=eq.steps)


def _vector(v: Any, n: int, what: str) -> np.ndarray:
    return vector(v, n, what, hint="(6 per body)", unit="N, N m", strict=False)


def _mul(K: Any, x: np.ndarray) -> np.ndarray:
    return np.asarray(K @ x).ravel()


__getattr__ = module_aliases("vibss.statics", {
    "centre_of_rotation": ("vibss.statics.center_of_rotation", lambda: center_of_rotation)})
