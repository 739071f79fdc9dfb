"""Decoupling certificate of a mount layout: the modal kinetic-energy matrix from the FULL mass
matrix, per-mode purity against a target, frequency windows, sag under weight and drive torque.

The kinetic-energy (KE) matrix ``E[i, j] = phi_ij (M phi_i)_j / phi_i^T M phi_i`` uses the full
mass matrix, products of inertia included (tools that use ``diag(M)`` are off by several points per
entry on a real powertrain). Its rows sum to one (the energy of one mode), and so do its columns
(``Phi Phi^T M = I`` for a complete mass-normalised basis). Fractions can be taken in a frame
other than the global axes: ``frame="tra"`` puts axis 1 along the torque-roll axis, so a roll
mode about the TRA shows as pure ``rx'``.

Examples
--------
>>> import vibss
>>> cert = certificate(vibss.load_example("powertrain"), purity=0.8, windows=(5.0, 26.7 / 2**0.5))
>>> cert.frequency_hz.round(2).tolist()
[5.59, 6.75, 8.29, 8.54, 10.83, 13.03]
>>> cert.purity.round(2).tolist(), bool(cert.passed)
([0.98, 0.75, 0.46, 0.93, 0.94, 0.52], False)
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from .._validate import array, number
from ..errors import AnalysisError, ArgumentError
from ..linear.plant.assemble import assemble
from ..linear.solve.static import static_solve
from ..modal.api import damped_modes, modes as undamped_modes
from ..model.model import DOF_NAMES, Model
from ..model.units import G
from ..results import Result, TextTable, jsonable, number_text, require_pandas
from ._common import body_name, frame_axes, frame_rotation, ke_fractions, unit_axis

__all__ = ["Certificate", "certificate", "windows_for", "in_windows", "STANDARD_GRAVITY", "WINDOW_RTOL"]

WINDOW_RTOL = 1e-6
"""A frequency within this (relative) of a window's edge counts as inside (optimisers meet
constraints to about this accuracy)."""

STANDARD_GRAVITY = (0.0, 0.0, -G)
"""Gravity used for the sag under weight when the model defines none [m/s^2]: standard gravity
(:data:`vibss.model.units.STANDARD_GRAVITY`) along -z."""


def in_windows(frequency_hz: np.ndarray, windows: np.ndarray) -> np.ndarray:
    """(..., k) bool: each frequency [Hz] inside its window (within :data:`WINDOW_RTOL`)."""
    return ((frequency_hz >= windows[:, 0] * (1 - WINDOW_RTOL))
            & (frequency_hz <= windows[:, 1] * (1 + WINDOW_RTOL)))


def windows_for(windows: Any, directions: list[str], who: str = "certificate") -> np.ndarray:
    """(k, 2) frequency window [Hz] of each mode from ``windows`` (see :func:`certificate`)."""
    k = len(directions)
    out = np.tile([0.0, np.inf], (k, 1))
    if windows is None:
        return out
    if isinstance(windows, Mapping):
        for key, win in windows.items():
            lo, hi = array(win, f"windows[{key!r}]", (2,), who=who, unit="Hz", finite=False)
            if isinstance(key, str):
                if key not in DOF_NAMES:
                    raise ArgumentError(f"{who}: windows: unknown direction {key!r}; keys are {list(DOF_NAMES)} "
                                        "or mode numbers (1-based)", argument="windows", received=key)
                rows = [i for i, d in enumerate(directions) if d == key]
            else:
                if not 1 <= int(key) <= k:
                    raise ArgumentError(f"{who}: windows: mode {key!r} out of range 1 ... {k}",
                                        argument="windows", received=key)
                rows = [int(key) - 1]
            out[rows] = lo, hi
        return out
    lo, hi = array(windows, "windows", (2,), who=who, unit="Hz", finite=False)
    out[:] = lo, hi
    return out


@dataclass(frozen=True, eq=False)
class Certificate(Result):
    """Decoupling certificate of a layout (the result protocol; ``cert['engine.rx']`` is the KE
    fraction of every mode in that coordinate).

    Attributes
    ----------
    model : Model
        The model.
    body : str
        The body whose sag and torque response are reported.
    coordinates : tuple of str
        Labels of the KE matrix columns (``'<body>.<dof>'``; with a primed DOF in a frame other
        than the global axes).
    frame : (3, 3) ndarray
        Axes of the coordinates (columns, global) [-].
    frame_name : str
        ``"global"``, ``"tra"``, ``"principal"`` or ``"custom"``.
    frequency_hz : (k,) ndarray
        Natural frequencies [Hz].
    ke_matrix : (k, n) ndarray
        Kinetic-energy fractions, modes x coordinates (full M) [-].
    purity : (k,) ndarray
        Largest KE fraction of each mode [-].
    dominant : tuple of str
        Coordinate holding it.
    target : float
        Purity target [-].
    windows : (k, 2) ndarray
        Frequency window of each mode [Hz] (0, inf where none).
    sag_weight : (n,) ndarray
        Static displacement under self-weight [m, rad] (model DOFs, global axes).
    sag_torque : (n,) ndarray
        Static displacement under the drive torque [m, rad].
    torque : (3,) ndarray
        The drive torque [N m].
    ke_matrix_damped : (k, n) ndarray or None
        With ``damped=True`` and viscous damping: the same fractions of the complex (damped) modes,
        ``Re(conj(psi_j) (M psi)_j) / Re(psi^H M psi)``, in the undamped modes' order (NaN where no
        damped mode pairs with an undamped one) [-].
    damping_ratio : (k,) ndarray or None
        Damping ratio of each damped mode [-].
    method : str
        ``"dense"``: undamped modes from the one eigen path.
    note : str
        Gravity used, frame.
    """

    signal_kind: ClassVar[str] = "coordinate"

    model: Model
    body: str
    coordinates: tuple[str, ...]
    frame: np.ndarray
    frame_name: str
    frequency_hz: np.ndarray
    ke_matrix: np.ndarray
    purity: np.ndarray
    dominant: tuple[str, ...]
    target: float
    windows: np.ndarray
    sag_weight: np.ndarray
    sag_torque: np.ndarray
    torque: np.ndarray
    ke_matrix_damped: np.ndarray | None = None
    damping_ratio: np.ndarray | None = None
    method: str = "dense"
    note: str = ""

    @property
    def output_labels(self) -> tuple[str, ...]:
        """Coordinate labels (columns of the KE matrix)."""
        return self.coordinates

    @property
    def units(self) -> tuple[str, ...]:
        """KE fractions are dimensionless."""
        return ("-",) * len(self.coordinates)

    def _item(self, i: int, j: int | None) -> np.ndarray:
        return self.ke_matrix[:, i]

    @property
    def purity_damped(self) -> np.ndarray | None:
        """(k,) purity of the damped modes (None without ``damped=True``)."""
        return None if self.ke_matrix_damped is None else np.max(self.ke_matrix_damped, axis=1)

    @property
    def pure(self) -> np.ndarray:
        """(k,) bool: purity meets the target."""
        return self.purity >= self.target

    @property
    def in_window(self) -> np.ndarray:
        """(k,) bool: frequency inside its window."""
        return in_windows(self.frequency_hz, self.windows)

    @property
    def passed(self) -> bool:
        """Every mode pure enough and inside its window."""
        return bool(np.all(self.pure) and np.all(self.in_window))

    def _sag(self, q: np.ndarray) -> np.ndarray:
        i = self.model.body_index(self.body)
        return q[6 * i:6 * i + 6]

    def summary(self) -> TextTable:
        """One row per mode: frequency, window, dominant coordinate, purity, verdict."""
        rows = []
        for k in range(len(self.frequency_hz)):
            lo, hi = self.windows[k]
            win = "-" if lo == 0 and not np.isfinite(hi) else f"{lo:.3g} ... {hi:.3g}"
            rows.append([f"{k + 1}", f"{self.frequency_hz[k]:.3f}", win,
                         "yes" if self.in_window[k] else "NO", self.dominant[k],
                         f"{100 * self.purity[k]:.1f}", "yes" if self.pure[k] else "NO"]
                        + ([] if self.damping_ratio is None or self.purity_damped is None else
                           [f"{100 * self.purity_damped[k]:.1f}", f"{100 * self.damping_ratio[k]:.2f}"]))
        damped = [] if self.damping_ratio is None else ["damped purity [%]", "zeta [%]"]
        return TextTable(["mode", "f [Hz]", "window [Hz]", "in window", "dominant", "purity [%]",
                      f">= {100 * self.target:.0f} %"] + damped, rows,
                     title=f"Decoupling certificate ({self.frame_name} frame)")

    def ke_table(self) -> TextTable:
        """The KE matrix [%]."""
        rows = [[f"{k + 1}", f"{self.frequency_hz[k]:.3f}"] + [f"{100 * e:.1f}" for e in self.ke_matrix[k]]
                for k in range(len(self.frequency_hz))]
        return TextTable(["mode", "f [Hz]"] + list(self.coordinates), rows,
                     title="Modal kinetic energy [%] (full mass matrix, products of inertia included)")

    def report(self) -> str:
        """Text certificate: verdict, per-mode table, KE matrix, sag."""
        verdict = "PASSED" if self.passed else "FAILED"
        sw, st = self._sag(self.sag_weight), self._sag(self.sag_torque)
        def motion(q: np.ndarray) -> str:
            return (" ".join(number_text(1e3 * v, ".3f") for v in q[:3]) + " mm, "
                    + " ".join(number_text(v, ".4f") for v in np.degrees(q[3:])) + " deg")

        sag = (f"Sag of {self.body!r} under weight: {motion(sw)}\n"
               f"Under drive torque {np.round(self.torque, 3).tolist()} N m: {motion(st)}")
        head = (f"Decoupling certificate of {self.model.name!r}: {verdict} "
                f"({int(self.pure.sum())}/{len(self.purity)} modes >= {100 * self.target:.0f} % pure, "
                f"{int(self.in_window.sum())}/{len(self.purity)} in window)")
        return "\n\n".join([head, self.summary().render(), self.ke_table().render(), sag]
                           + ([self.note] if self.note else []))

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready certificate: ``ke_matrix`` (modes x coordinates), per-mode ``purity`` ..."""
        return jsonable({
            "model": self.model.name, "body": self.body, "frame": self.frame_name,
            "frame_axes": self.frame, "coordinates": list(self.coordinates),
            "frequency_hz": self.frequency_hz, "ke_matrix": self.ke_matrix, "purity": self.purity,
            "dominant": list(self.dominant), "target": self.target, "pure": self.pure,
            "windows_hz": self.windows, "in_window": self.in_window, "passed": self.passed,
            "sag_weight": self.sag_weight, "sag_torque": self.sag_torque, "torque": self.torque,
            "ke_matrix_damped": self.ke_matrix_damped, "purity_damped": self.purity_damped,
            "damping_ratio": self.damping_ratio, "method": self.method, "note": self.note})

    def to_pandas(self) -> Any:
        """DataFrame: one row per mode (frequency, window, purity, verdicts, KE fractions)."""
        pd = require_pandas()
        df = pd.DataFrame({"frequency_hz": self.frequency_hz, "f_low_hz": self.windows[:, 0],
                           "f_high_hz": self.windows[:, 1], "in_window": self.in_window,
                           "dominant": list(self.dominant), "purity": self.purity, "pure": self.pure})
        if self.damping_ratio is not None:
            df["purity_damped"] = self.purity_damped
            df["damping_ratio"] = self.damping_ratio
        for j, c in enumerate(self.coordinates):
            df[f"ke_{c}"] = self.ke_matrix[:, j]
        df.index = pd.RangeIndex(1, len(df) + 1, name="mode")
        df.attrs["units"] = {c: ("Hz" if c.endswith("_hz") else "-") for c in df.columns}
        return df

    def plot(self, ax: Any = None, **kwargs: Any) -> Any:
        """KE matrix heat map with purity and windows: :func:`vibss.plotting.plot_certificate`.

        Parameters
        ----------
        ax : Axes or None
            Draw into existing axes; default: a new figure.
        **kwargs
            Passed to :func:`vibss.plotting.plot_certificate`.

        Returns
        -------
        matplotlib.figure.Figure
        """
        from ..plotting.design import plot_certificate

        return plot_certificate(self, ax=ax, **kwargs)


def certificate(model: Model, body: str | None = None, *, purity: float = 0.9, windows: Any = None,
                frame: Any = "global", axis: Any = "x", torque: float = 1.0,
                damped: bool = False) -> Certificate:
    """Decoupling certificate of a mount layout.

    Parameters
    ----------
    model : Model
        The system (ground fixed).
    body : str or None
        Body whose sag and TRA are reported, and whose inertia defines ``frame="tra"`` or
        ``"principal"`` (None: the only body).
    purity : float
        Target: the largest KE fraction of every mode must reach it [-] (e.g. 0.8 or 0.9).
    windows : (2,) array_like, mapping or None
        Frequency windows [Hz]: one ``(f_low, f_high)`` for every mode; or a mapping from a
        direction (``"z"``, ``"rx"``: modes whose dominant coordinate has that DOF name) or a
        1-based mode number to ``(f_low, f_high)``; None: no windows.
    frame : {"global", "tra", "principal"} or (3, 3) array_like
        Axes in which the KE is split (see the module docstring).
    axis : {"x", "y", "z"} or (3,) array_like
        Crank axis: the drive torque's axis and the TRA's [-].
    torque : float
        Drive torque for the sag under torque [N m].
    damped : bool
        Also split the energy of the complex (damped) modes, for non-proportional viscous damping
        (:func:`vibss.damped_modes`); ignored for an undamped model.

    Returns
    -------
    Certificate
    """
    who = "certificate"
    name = body_name(model, body, who)
    target = number(purity, "purity", who=who, minimum=0.0)
    if target > 1.0:
        raise ArgumentError(f"{who}: purity: expected a fraction between 0 and 1, got {purity!r}",
                            argument="purity", received=purity, expected="0 ... 1")
    e = unit_axis(axis, "axis", who)
    axes = frame_axes(model, name, frame, axis, who)
    frame_name = frame if isinstance(frame, str) else "custom"
    a = assemble(model)
    md = undamped_modes(a)
    if np.any(md.rigid):
        raise AnalysisError(f"{who}: the model has {int(md.rigid.sum())} rigid-body (zero-frequency) "
                            "modes; the mounts must restrain every body", argument="model")
    M = a.dense("M")
    R = frame_rotation(a.n, axes)
    E = ke_fractions(md.shapes, M, R)
    prime = "" if frame_name == "global" else "'"
    coords = tuple(f"{d}{prime}" for d in a.dofs)
    dominant_idx = np.argmax(E, axis=1)
    dominant = tuple(coords[j] for j in dominant_idx)
    dirs = [DOF_NAMES[j % 6] for j in dominant_idx]
    win = windows_for(windows, dirs, who)
    g = model.gravity if model.gravity is not None else np.array(STANDARD_GRAVITY)
    weight = np.zeros(a.n)
    for i, b in enumerate(model.bodies):
        weight[6 * i:6 * i + 3] = b.masses * g
    i = model.body_index(name)
    drive = np.zeros(a.n)
    drive[6 * i + 3:6 * i + 6] = float(torque) * e
    sag = static_solve(a, np.column_stack([weight, drive])).x     # exact on badly scaled K
    ke_damped = zeta = None
    if damped and a.has_damping:
        dm = damped_modes(a, undamped=md)
        osc = np.flatnonzero(dm.poles.imag > 0)
        psi = R.T @ dm.shapes[:, osc]
        mp = (R.T @ M @ R) @ psi
        num = (psi.conj() * mp).real.T
        fr = num / num.sum(axis=1, keepdims=True)
        ke_damped = np.full_like(E, np.nan)
        zeta = np.full(len(E), np.nan)
        for row, k in zip(fr, dm.paired[osc]):
            ke_damped[k] = row
        zeta[dm.paired[osc]] = dm.damping_ratio[osc]
    note = (f"gravity {np.round(g, 5).tolist()} m/s^2 ({'the model' if model.gravity is not None else 'standard, the model has none'}); "
            f"KE fractions in the {frame_name} frame")
    return Certificate(model=model, body=name, coordinates=coords, frame=axes, frame_name=frame_name,
                       frequency_hz=md.frequency_hz.copy(), ke_matrix=E, purity=E.max(axis=1),
                       dominant=dominant, target=target, windows=win, sag_weight=sag[:, 0],
                       sag_torque=sag[:, 1], torque=float(torque) * e, ke_matrix_damped=ke_damped,
                       damping_ratio=zeta, note=note)
