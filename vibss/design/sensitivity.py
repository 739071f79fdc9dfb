"""Exact sensitivities of a mount layout: natural frequencies, mode shapes, kinetic-energy fractions
and static sag with respect to mount rates, positions and orientation angles.

With mass-normalised modes ``phi_i`` (``K phi = lambda M phi``) and a parameter ``p`` that changes
``K`` only (``dM = 0``):

- ``d lambda_i = phi_i^T dK phi_i``; ``d f_i = d lambda_i / (8 pi^2 f_i)``;
- ``d phi_i = sum_{j != i} phi_j (phi_j^T dK phi_i) / (lambda_i - lambda_j)``: the modal sum over
  the complete basis (all ``6 n_bodies`` modes), exact for these small dense problems;
- ``d E_ij`` (KE fractions, full M, in the certificate's frame) from ``d phi`` by the product rule;
- ``d x = -K^-1 dK x`` for the sag ``x = K^-1 f`` under self-weight.

Repeated frequencies (relative gap below :data:`REPEAT_RTOL`) have no derivative of their own
(any basis of the eigenspace is a mode); they are refused with an :class:`~vibss.errors.AnalysisError`
naming the modes — break the symmetry, or study the pair's mean.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from ..errors import AnalysisError
from ..linear.plant.assemble import assemble
from ..linear.solve.static import static_solve
from ..modal.api import modes as undamped_modes
from ..model.model import Model
from .._deprecated import renamed_attribute
from ..results import Result, TextTable, jsonable, require_pandas
from ._common import body_name, frame_axes, frame_rotation, ke_fractions
from .certificate import STANDARD_GRAVITY
from .parameters import Parameter, _angles, apply, current_values, parameters_of, stiffness_derivatives

__all__ = ["Sensitivity", "sensitivity", "REPEAT_RTOL", "evaluate"]

REPEAT_RTOL = 1e-6
"""Modes whose ``omega^2`` differ by less than this (relative) are repeated: no derivative."""


@dataclass(frozen=True, eq=False)
class Sensitivity(Result):
    """Values and exact first derivatives of a layout's modal and static quantities.

    ``sens['f3', 'engine.k3']`` is ``d f_3 / d k3`` of mount engine [Hz per N/m].

    Attributes
    ----------
    model : Model
        The model (at the parameters' values).
    parameters : tuple of str
        Parameter names (columns of every derivative).
    values : (p,) ndarray
        Their values [N/m, m, rad].
    parameter_units : tuple of str
        Their units.
    dofs : tuple of str
        DOF labels.
    frequency_hz : (k,) ndarray
        Natural frequencies [Hz].
    d_frequency : (k, p) ndarray
        ``d f / d p`` [Hz per unit].
    shapes : (n, k) ndarray
        Mass-normalised shapes (largest component positive, as :func:`vibss.modes`).
    d_shapes : (n, k, p) ndarray
        Their derivatives.
    ke_matrix : (k, n) ndarray
        KE fractions in ``frame`` [-].
    d_ke : (k, n, p) ndarray
        Their derivatives.
    purity : (k,) ndarray
        Largest KE fraction of each mode [-].
    d_purity : (k, p) ndarray
        Derivative of that entry (the dominant coordinate held fixed).
    sag : (n,) ndarray
        Static displacement under self-weight [m, rad].
    d_sag : (n, p) ndarray
        Its derivative.
    frame : (3, 3) ndarray
        Axes of the KE coordinates.
    method : str
        ``"modal-sum"``.
    note : str
        Gravity used.
    """

    signal_kind: ClassVar[str] = "quantity"

    model: Model
    parameters: tuple[str, ...]
    values: np.ndarray
    parameter_units: tuple[str, ...]
    dofs: tuple[str, ...]
    frequency_hz: np.ndarray
    d_frequency: np.ndarray
    shapes: np.ndarray
    d_shapes: np.ndarray
    ke_matrix: np.ndarray
    d_ke: np.ndarray
    purity: np.ndarray
    d_purity: np.ndarray
    sag: np.ndarray
    d_sag: np.ndarray
    frame: np.ndarray
    method: str = "modal-sum"
    note: str = ""

    @property
    def output_labels(self) -> tuple[str, ...]:
        """``f1 ... fk`` (frequencies), ``purity1 ...``, then ``sag.<dof>``."""
        k = len(self.frequency_hz)
        return tuple([f"f{i + 1}" for i in range(k)] + [f"purity{i + 1}" for i in range(k)]
                     + [f"sag.{d}" for d in self.dofs])

    @property
    def input_labels(self) -> tuple[str, ...]:
        """The parameters."""
        return self.parameters

    @property
    def units(self) -> tuple[str, ...]:
        """Units of the outputs (Hz, -, m or rad)."""
        k = len(self.frequency_hz)
        return ("Hz",) * k + ("-",) * k + tuple("rad" if d.rsplit(".", 1)[1].startswith("r") else "m"
                                                for d in self.dofs)

    @property
    def jacobian(self) -> np.ndarray:
        """(outputs, p) derivatives in ``output_labels`` order."""
        return np.vstack([self.d_frequency, self.d_purity, self.d_sag])

    def _item(self, i: int, j: int | None) -> Any:
        return self.jacobian[i] if j is None else float(self.jacobian[i, j])

    def normalized(self, quantity: str = "frequency") -> np.ndarray:
        """(k, p) change of each mode's frequency or purity [%] per 1 % of a rate, 1 mm of shift,
        1 degree of angle."""
        step = np.array([0.01 * v if u == "N/m" else (1e-3 if u == "m" else np.pi / 180)
                         for v, u in zip(self.values, self.parameter_units)])
        d, y = (self.d_frequency, self.frequency_hz) if quantity == "frequency" else (self.d_purity, self.purity)
        return 100 * d * step[None, :] / y[:, None]

    normalised = renamed_attribute("normalised", "normalized", "Sensitivity")

    def summary(self) -> TextTable:
        """Frequency derivatives, normalized (see :meth:`normalized`)."""
        d = self.normalized("frequency")
        rows = [[p, f"{v:.4g} {u}"] + [f"{x:+.3f}" for x in d[:, j]]
                for j, (p, v, u) in enumerate(zip(self.parameters, self.values, self.parameter_units))]
        return TextTable(["parameter", "value"] + [f"f{i + 1} {self.frequency_hz[i]:.2f} Hz"
                                                for i in range(len(self.frequency_hz))], rows,
                     title="Frequency change [%] per 1 % rate, 1 mm shift, 1 deg rotation")

    def report(self) -> str:
        """Text: frequency and purity sensitivities."""
        dp = self.normalized("purity")
        rows = [[p] + [f"{x:+.3f}" for x in dp[:, j]] for j, p in enumerate(self.parameters)]
        purity = TextTable(["parameter"] + [f"mode {i + 1} ({100 * self.purity[i]:.0f} %)"
                                        for i in range(len(self.purity))], rows,
                       title="Purity change [% of its value] per 1 % rate, 1 mm shift, 1 deg rotation")
        return "\n\n".join([f"Exact sensitivities of {self.model.name!r} ({len(self.parameters)} parameters, "
                            f"{self.method})", self.summary().render(), purity.render(), self.note])

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready values and derivatives."""
        return jsonable({"model": self.model.name, "parameters": list(self.parameters),
                         "values": self.values, "units": list(self.parameter_units),
                         "frequency_hz": self.frequency_hz, "d_frequency": self.d_frequency,
                         "purity": self.purity, "d_purity": self.d_purity, "ke_matrix": self.ke_matrix,
                         "d_ke": self.d_ke, "sag": self.sag, "d_sag": self.d_sag,
                         "method": self.method, "note": self.note})

    def to_pandas(self) -> Any:
        """DataFrame: one row per parameter, ``df_i`` and ``dpurity_i`` columns (SI)."""
        pd = require_pandas()
        data: dict[str, Any] = {"value": self.values, "unit": list(self.parameter_units)}
        for i in range(len(self.frequency_hz)):
            data[f"df{i + 1}"] = self.d_frequency[i]
        for i in range(len(self.frequency_hz)):
            data[f"dpurity{i + 1}"] = self.d_purity[i]
        df = pd.DataFrame(data, index=pd.Index(list(self.parameters), name="parameter"))
        per = dict(zip(self.parameters, self.parameter_units))
        df.attrs["units"] = {"value": "the row's unit", "df": "Hz per the row's unit",
                             "dpurity": "1 per the row's unit", "by row": per}
        return df

    def plot(self, ax: Any = None, **kwargs: Any) -> Any:
        """Tornado of the normalized sensitivities: :func:`vibss.plotting.design.plot_sensitivity`.

        Parameters
        ----------
        ax : Axes or None
            Draw into existing axes; default: a new figure.
        **kwargs
            Passed to :func:`vibss.plotting.design.plot_sensitivity` (``quantity``).

        Returns
        -------
        matplotlib.figure.Figure
        """
        from ..plotting.design import plot_sensitivity

        return plot_sensitivity(self, ax=ax, **kwargs)


def evaluate(base: Model, parameters: Sequence[Parameter], values: Any, body: str | None = None,
             frame: Any = "global", axis: Any = "x", shapes: bool = True) -> Sensitivity:
    """Sensitivities of ``apply(base, parameters, values)`` with respect to ``values``.

    Parameters
    ----------
    base : Model
        Model the shifts and angles are measured from.
    parameters : sequence of Parameter
        Validated parameters (:func:`~vibss.design.parameters.parameters_of`).
    values : (p,) array_like
        Parameter values [N/m, m, rad].
    body : str or None
        Body whose inertia defines the frame (None: the only or first body).
    frame : {"global", "tra", "principal"} or (3, 3) array_like
        Axes of the KE fractions.
    axis : {"x", "y", "z"} or (3,) array_like
        Crank axis for ``frame="tra"``.
    shapes : bool
        Compute shape and KE derivatives (False: frequencies and sag only).

    Returns
    -------
    Sensitivity
    """
    values = np.asarray(values, dtype=float)
    model = apply(base, parameters, values)
    a = assemble(model, sparse=False)
    dK = stiffness_derivatives(a, parameters, _angles(base, parameters, values))
    md = undamped_modes(a)
    if np.any(md.rigid):
        raise AnalysisError("sensitivity: the model has rigid-body (zero-frequency) modes; the mounts "
                            "must restrain every body", argument="model")
    lam = md.omega ** 2
    gap = np.abs(lam[:, None] - lam[None, :]) / np.maximum(lam[:, None], lam[None, :])
    np.fill_diagonal(gap, np.inf)
    if np.any(gap < REPEAT_RTOL):
        i, j = np.unravel_index(np.argmin(gap), gap.shape)
        raise AnalysisError(f"sensitivity: modes {min(i, j) + 1} and {max(i, j) + 1} have repeated "
                            f"frequencies ({md.frequency_hz[i]:.6g} Hz): their shapes, and the "
                            "frequencies as individual modes, have no derivative; break the symmetry "
                            "(e.g. a slightly different rate) or study another parameter set",
                            argument="model")
    phi = md.shapes
    M = a.dense("M")
    G = np.einsum("ik,pij,jl->pkl", phi, dK, phi)                     # phi^T dK phi, (p, k, k)
    dlam = np.einsum("pkk->kp", G)
    f = md.frequency_hz
    dfreq = dlam / (8 * np.pi ** 2 * f[:, None])
    name = body_name(model, body, "sensitivity") if body is not None or len(model.bodies) == 1 \
        else model.bodies[0].name
    axes = frame_axes(model, name, frame, axis, "sensitivity")
    R = frame_rotation(a.n, axes)
    E = ke_fractions(phi, M, R)
    dom = np.argmax(E, axis=1)
    k = len(f)
    if shapes:
        with np.errstate(divide="ignore"):
            inv = 1.0 / (lam[None, :] - lam[:, None])                  # [j, i] = 1/(lam_i - lam_j)
        np.fill_diagonal(inv, 0.0)
        dphi = np.einsum("nj,pji,ji->nip", phi, G, inv)                  # (n, k, p)
        pr = R.T @ phi                                                   # frame coordinates
        Mr = R.T @ M @ R
        dpr = np.einsum("ab,bip->aip", R.T, dphi)
        mp = Mr @ pr
        den = np.einsum("ai,ai->i", pr, mp)
        num = pr * mp
        dnum = dpr * mp[:, :, None] + pr[:, :, None] * np.einsum("ab,bip->aip", Mr, dpr)
        dden = 2 * np.einsum("ai,aip->ip", mp, dpr)
        dE = (dnum / den[None, :, None] - num[:, :, None] * dden[None, :, :] / den[None, :, None] ** 2)
        dE = dE.transpose(1, 0, 2)                                       # (k, n, p)
    else:
        dphi = np.full((a.n, k, len(parameters)), np.nan)
        dE = np.full((k, a.n, len(parameters)), np.nan)
    g = model.gravity if model.gravity is not None else np.array(STANDARD_GRAVITY)
    weight = np.concatenate([np.concatenate([b.masses * g, np.zeros(3)]) for b in model.bodies])
    x = static_solve(a, weight).x                                     # exact on badly scaled K
    dx = -static_solve(a, np.einsum("pij,j->ip", dK, x)).x
    return Sensitivity(model=model, parameters=tuple(p.name for p in parameters), values=values,
                       parameter_units=tuple(p.unit for p in parameters), dofs=a.dofs,
                       frequency_hz=f.copy(), d_frequency=dfreq, shapes=phi, d_shapes=dphi,
                       ke_matrix=E, d_ke=dE, purity=E[np.arange(k), dom],
                       d_purity=dE[np.arange(k), dom], sag=x, d_sag=dx, frame=axes,
                       note=f"sag under gravity {np.round(g, 5).tolist()} m/s^2")


def sensitivity(model: Model, parameters: Any, *, body: str | None = None, frame: Any = "global",
                axis: Any = "x") -> Sensitivity:
    """Exact first derivatives of frequencies, mode shapes, KE fractions and sag.

    Parameters
    ----------
    model : Model
        The layout (ground fixed, no rigid-body modes, no repeated frequencies).
    parameters : str, Parameter or sequence of them
        ``"<mount>.<kind>"`` (kinds ``k1 k2 k3`` [N/m], ``x y z`` [m], ``rx ry rz`` [rad], rate
        ratios ``k1/k3`` ... [-]; see
        :mod:`vibss.design.parameters`) or tied :class:`~vibss.design.parameters.Parameter`.
    body : str or None
        Body whose inertia defines ``frame`` (None: the only or first body).
    frame : {"global", "tra", "principal"} or (3, 3) array_like
        Axes of the KE fractions (as :func:`~vibss.design.certificate`).
    axis : {"x", "y", "z"} or (3,) array_like
        Crank axis for ``frame="tra"``.

    Returns
    -------
    Sensitivity

    Examples
    --------
    >>> import vibss
    >>> s = sensitivity(vibss.load_example("powertrain"), ["engine.k3", "engine.z"])
    >>> s.parameters, s.d_frequency.shape
    (('engine.k3', 'engine.z'), (6, 2))
    """
    params = parameters_of(model, parameters)
    return evaluate(model, params, current_values(model, params), body=body, frame=frame, axis=axis)
