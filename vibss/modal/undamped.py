"""Undamped modes: K phi = w^2 M phi, with the tables engineers read.

The modes come from the one eigen path, :func:`vibss.linear.eigen.undamped.undamped` (methods by name, or
pass a callable ``f(K, M, n_modes) -> (w2, shapes)``):

- ``"jacobi"``: Jacobi SVD of the factored problem (``K = G^T G``): every frequency to high
  relative accuracy, also beside 1e16 N/m links (the default up to
  :data:`~vibss.linear.eigen.undamped.JACOBI_MAX` DOFs);
- ``"dense"``: ``eigh`` on dense matrices (all modes, or the lowest ``n_modes``), refined where
  the a-posteriori estimate says so;
- ``"shift-invert"``: sparse shift-invert about a small negative shift: the lowest ``n_modes`` of a
  large sparse model;
- ``"auto"``: shift-invert for a large sparse model when fewer than a tenth of the modes are asked
  for, Jacobi for a small one, dense otherwise.

Zero-frequency (rigid-body) modes are found by :func:`~vibss.linear.eigen.undamped.rigid_mask`, a
unit-independent test of whether each mode's stiffness cancels to round-off on the factor; it does
not depend on ``n_modes``. Rigid modes are reported with frequency 0. Every mode carries a relative
error bound of its frequency (:attr:`Modes.error_estimate`). Repeated frequencies (symmetric layouts, free bodies) are split into
clean directions by :func:`vibss.linear.eigen.directions.align_cluster`.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Any, ClassVar

import numpy as np

from ..linear.plant.assemble import Assembly, assemble
from ..linear.eigen.undamped import FREQ_RTOL, JACOBI_MAX, Solver, undamped
from ..linear.eigen.directions import align_cluster, cluster_slices, direction_shares, dominant_direction, energy_fractions
from .._validate import integer
from ..errors import AnalysisError, ArgumentError, ModelError
from ..model.model import DOF_NAMES, Model
from ..results import Result, TextTable as Table, jsonable, require_pandas

__all__ = ["Modes", "modes", "rigid_influence"]

REPEAT_RTOL = 1e-8
"""Frequencies closer than this (relative) are treated as repeated and aligned by direction."""

CPM_PER_HZ = 60.0

def _read_only(a: np.ndarray) -> np.ndarray:
    a.setflags(write=False)     # cached on a frozen result: nobody may change it in place
    return a


def rigid_influence(model: Model, about: np.ndarray | None = None) -> np.ndarray:
    """(n, 6) DOF motion of all bodies moving as one rigid body: unit x, y, z, rx, ry, rz.

    Rotations are about ``about`` [m] (default: the system's centre of gravity).
    """
    c = model.centre_of_gravity if about is None else np.asarray(about, float)
    nb = len(model.bodies)
    out = np.zeros((nb, 6, 6))
    out[:, :3, :3] = np.eye(3)
    out[:, 3:, 3:] = np.eye(3)
    r = np.array([b.cog for b in model.bodies], dtype=float).reshape(nb, 3) - c
    # translation of the COG for a rotation theta about c: theta x r = -[r]x theta
    out[:, 0, 4], out[:, 0, 5] = r[:, 2], -r[:, 1]
    out[:, 1, 3], out[:, 1, 5] = -r[:, 2], r[:, 0]
    out[:, 2, 3], out[:, 2, 4] = r[:, 1], -r[:, 0]
    return out.reshape(6 * nb, 6)


@dataclass(frozen=True, eq=False)
class Modes(Result):
    """Undamped modes of a model.

    Follows the result protocol (:mod:`vibss.results`): ``m['engine.z']`` is the (k,) component of
    every mass-normalised shape in one DOF; ``output_labels`` are the DOFs; there is no
    python-control twin (``control`` is None).

    Attributes
    ----------
    model : Model
        The model analysed.
    dofs : tuple of str
        DOF labels of the rows of the shapes.
    omega : (k,) ndarray
        Natural frequencies [rad/s], ascending; exactly 0 for rigid-body modes.
    shapes : (n, k) ndarray
        Mass-normalised shapes (``shapes.T @ M @ shapes = I``) [m/sqrt(kg) ...].
    energy : (k, n) ndarray
        Kinetic-energy fraction of each mode in each DOF (rows sum to 1).
    effective_mass : (k, 6) ndarray
        Effective (participating) mass per direction x, y, z [kg] and rx, ry, rz [kg m^2] about
        the system's centre of gravity. Summed over all modes: the total mass and inertia.
    rigid : (k,) bool ndarray
        Zero-frequency (rigid-body) modes.
    method : str
        Eigen-solver used.
    note : str
        Why that solver (for ``method="auto"``).
    error_estimate : (k,) ndarray or None
        Relative error bound of each natural frequency [-] (NaN for rigid modes, whose 0 is exact);
        see :func:`vibss.linear.eigen.undamped.error_estimate`.
    """

    signal_kind: ClassVar[str] = "DOF"

    model: Model
    dofs: tuple[str, ...]
    omega: np.ndarray
    shapes: np.ndarray
    energy: np.ndarray
    effective_mass: np.ndarray
    rigid: np.ndarray
    method: str
    note: str = ""

    @property
    def output_labels(self) -> tuple[str, ...]:
        """DOF labels of the rows of the shapes (``dofs`` is the same)."""
        return self.dofs

    @property
    def units(self) -> tuple[str, ...]:
        """Unit of the motion of each DOF (m or rad); the shapes are per sqrt(kg) of modal mass."""
        return tuple("rad" if d.rsplit(".", 1)[-1].startswith("r") else "m" for d in self.dofs)

    def _item(self, i: int, j: int | None) -> np.ndarray:
        return self.shapes[i]
    error_estimate: np.ndarray | None = None

    @cached_property
    def frequency_hz(self) -> np.ndarray:
        """Natural frequencies [Hz]."""
        return _read_only(self.omega / (2 * np.pi))

    @cached_property
    def cpm(self) -> np.ndarray:
        """Natural frequencies [cycles per minute]."""
        return _read_only(self.frequency_hz * CPM_PER_HZ)

    def __len__(self) -> int:
        return len(self.omega)

    @cached_property
    def relative_shapes(self) -> np.ndarray:
        """(n, k) shapes scaled so the largest-magnitude component of each is +1 [-].

        As the handbook's program printed them ("relative eigenvector values"); note that
        translations [m] and rotations [rad] are compared as numbers.
        """
        idx = np.argmax(np.abs(self.shapes), axis=0)
        return _read_only(self.shapes / self.shapes[idx, np.arange(self.shapes.shape[1])])

    @cached_property
    def modal_mass(self) -> np.ndarray:
        """(k,) modal mass of the relative shapes, ``phi^T M phi`` [kg or kg m^2]."""
        return _read_only(1.0 / np.max(np.abs(self.shapes), axis=0) ** 2)

    @property
    def directions(self) -> list[str]:
        """Dominant direction of each mode (x y z rx ry rz): largest summed kinetic-energy share."""
        return list(self._directions)

    @cached_property
    def _directions(self) -> tuple[str, ...]:
        return tuple(dominant_direction(self.energy))

    @property
    def labels(self) -> list[str]:
        """Mode labels for tables and figures: the dominant direction, with the body holding most of
        that direction's kinetic energy for multi-body models (``"tank.y"``; single body: ``"y"``)."""
        return list(self._labels)

    @cached_property
    def _labels(self) -> tuple[str, ...]:
        bodies = [b.name for b in self.model.bodies]
        if len(bodies) == 1:
            return self._directions
        e = np.asarray(self.energy).reshape(len(self), len(bodies), 6)
        return tuple(f"{bodies[int(np.argmax(e[k, :, DOF_NAMES.index(d)]))]}.{d}"
                     for k, d in enumerate(self._directions))

    @cached_property
    def direction_energy(self) -> np.ndarray:
        """(k, 6) kinetic-energy share per direction, summed over bodies."""
        return _read_only(direction_shares(self.energy))

    def shape_of(self, mode: int, body: str, relative: bool = True) -> np.ndarray:
        """(6,) shape of ``body`` in mode ``mode`` (relative scaling by default)."""
        i = self.model.body_index(body)
        s = self.relative_shapes if relative else self.shapes
        return s[6 * i:6 * i + 6, mode]

    # -- export ------------------------------------------------------------------------------
    def to_dict(self) -> dict[str, Any]:
        """The spec's JSON structure (SI)."""
        rel = self.relative_shapes
        names = self.model.body_names
        modes = []
        for k in range(len(self)):
            modes.append({
                "frequency_hz": float(self.frequency_hz[k]),
                "omega_rad_s": float(self.omega[k]),
                "cpm": float(self.cpm[k]),
                "direction": self.directions[k],
                "rigid": bool(self.rigid[k]),
                "error_estimate": self._estimate(k),
                "shape": {b: rel[6 * i:6 * i + 6, k].tolist() for i, b in enumerate(names)},
                "energy": {b: self.energy[k, 6 * i:6 * i + 6].tolist() for i, b in enumerate(names)},
                "modal_mass": float(self.modal_mass[k]),
                "effective_mass": dict(zip(DOF_NAMES, self.effective_mass[k].tolist())),
            })
        return jsonable({"model": self.model.name, "method": self.method, "note": self.note,
                         "frequencies_hz": self.frequency_hz, "modes": modes})

    def summary(self) -> Table:
        """The frequency table (:meth:`frequency_table`)."""
        return self.frequency_table()

    def _estimate(self, k: int) -> float | None:
        """Relative error bound of mode k as JSON (None: rigid or not estimated)."""
        if self.error_estimate is None or not np.isfinite(self.error_estimate[k]):
            return None
        return float(self.error_estimate[k])

    def energy_table(self) -> Table:
        """Kinetic-energy distribution [%]: one row per mode, one column per body DOF."""
        rows = [[f"{k + 1}", f"{self.frequency_hz[k]:.3f}", self.labels[k]]
                + [f"{100 * e:.1f}" for e in self.energy[k]] for k in range(len(self))]
        return Table(["mode", "f [Hz]", "dir"] + list(self.dofs), rows,
                     title="Modal kinetic-energy distribution [%]")

    @cached_property
    def effective_mass_fraction(self) -> np.ndarray:
        """(k, 6) effective masses as fractions of the total mass / inertia about the system COG."""
        r = rigid_influence(self.model).reshape(-1, 6, 6)          # per body: 6 DOFs x 6 directions
        total = sum(np.diag(r[i].T @ b.mass_matrix @ r[i]) for i, b in enumerate(self.model.bodies))
        return _read_only(self.effective_mass / total)

    def frequency_table(self) -> Table:
        """Frequencies, CPM, direction, modal mass and effective masses [% of total]."""
        rows = []
        frac = 100 * self.effective_mass_fraction
        for k in range(len(self)):
            rows.append([f"{k + 1}", f"{self.frequency_hz[k]:.4f}", f"{self.cpm[k]:.0f}",
                         f"{self.omega[k]:.4g}", self.labels[k] + (" (rigid)" if self.rigid[k] else ""),
                         f"{self.modal_mass[k]:.4g}"]
                        + [f"{m:.1f}" if m >= 0.05 else "0" for m in frac[k]]
                        + [("-" if self._estimate(k) is None else f"{self._estimate(k):.1e}")])
        head = ["mode", "f [Hz]", "CPM", "w [rad/s]", "direction", "modal mass"] + \
               [f"eff. {d} [%]" for d in DOF_NAMES] + ["rel. error"]
        return Table(head, rows, title="Undamped natural frequencies (modal mass of the relative shape; "
                                       "effective mass in % of the total mass and of the inertia about "
                                       "the system COG; rel. error: bound of the frequency's relative error)")

    def shape_table(self) -> Table:
        """Relative eigenvector values (largest component = 1), per mode and body."""
        rel = self.relative_shapes
        rows = []
        for k in range(len(self)):
            for i, b in enumerate(self.model.body_names):
                rows.append([f"{k + 1}" if i == 0 else "", f"{self.frequency_hz[k]:.3f}" if i == 0 else "",
                             b] + [f"{v:.4f}" for v in rel[6 * i:6 * i + 6, k]])
        return Table(["mode", "f [Hz]", "body"] + list(DOF_NAMES), rows,
                     title="Relative eigenvectors (largest component = 1)")

    def report(self) -> str:
        """Engineer's text report: frequencies, relative eigenvectors, energy table."""
        head = f"Undamped modes of {self.model.name!r}: {len(self)} modes, solver {self.method}"
        return "\n\n".join([head, self.frequency_table().render(), self.shape_table().render(),
                            self.energy_table().render()])

    def to_pandas(self) -> Any:
        """DataFrame: one row per mode with frequency, direction, effective masses."""
        pd = require_pandas()

        df = pd.DataFrame({"frequency_hz": self.frequency_hz, "cpm": self.cpm, "omega": self.omega,
                           "direction": self.directions, "rigid": self.rigid,
                           "modal_mass": self.modal_mass})
        for j, d in enumerate(DOF_NAMES):
            df[f"effective_mass_{d}"] = self.effective_mass[:, j]
        df.index = pd.RangeIndex(1, len(self) + 1, name="mode")
        return df

    def plot(self, ax: Any = None, **kwargs: Any) -> Any:
        """Draw the mode shapes: :func:`vibss.plotting.plot_modes`.

        Parameters
        ----------
        ax : Axes, sequence of three Axes, or None
            Draw one mode into existing axes; default: a new figure.
        **kwargs
            Passed to :func:`vibss.plotting.plot_modes` (``which``, ``view``, ``scale`` ...).

        Returns
        -------
        matplotlib.figure.Figure
        """
        from ..plotting import plot_modes

        return plot_modes(self, ax=ax, **kwargs)


def modes(model: Model | Assembly, n_modes: int | None = None,
          method: str | Solver = "auto") -> Modes:
    """Undamped natural frequencies and mode shapes.

    Parameters
    ----------
    model : Model or Assembly
        The system (ground fixed).
    n_modes : int or None
        Number of lowest modes; None for all (6 per body).
    method : {"auto", "jacobi", "dense", "shift-invert"} or callable
        Eigen-solver (see module docstring).

    Returns
    -------
    Modes

    Examples
    --------
    >>> from vibss import Body, MountType, Mount, Model, symmetric
    >>> t = MountType("t", [1e4, 2e4, 3e4])
    >>> m = Model([Body("b", 1000.0, [10, 20, 30])], symmetric(Mount("m", t, "b", at=[1, 2, 0])))
    >>> r = modes(m)
    >>> r.frequency_hz.round(4)[:3], r.directions[:3]
    (array([1.0066, 1.4235, 1.7435]), ['x', 'y', 'z'])
    """
    a = model if isinstance(model, Assembly) else assemble(model)
    n = a.n
    if n_modes is not None:
        if not isinstance(n_modes, (int, np.integer)):      # 6.0 modes is a mistake, not a count
            raise ArgumentError(f"modes: n_modes: expected a positive integer or None, got {n_modes!r}",
                                argument="n_modes", received=n_modes, expected="a positive integer")
        n_modes = min(integer(n_modes, "n_modes", who="modes"), n)
    try:
        spec = _spectrum(a, n_modes, method)
    except (np.linalg.LinAlgError, ValueError) as exc:
        if isinstance(exc, ModelError):
            raise
        raise AnalysisError(f"the eigen-solver ({method if isinstance(method, str) else 'custom'}) failed: "
                            f"{exc}; check the model for extreme values (masses, inertias, stiffnesses "
                            "or positions many decades apart)") from None
    w2, phi, rigid, name = spec.omega2, spec.phi.copy(), spec.rigid, spec.method
    M = a.M            # sparse on a large model: post-processing needs M times k vectors, not dense M
    # Repeated frequencies: rigid-body modes form one cluster; elastic ones by relative gap.
    groups = cluster_slices(np.sqrt(w2), REPEAT_RTOL, 0.0)
    if rigid.sum() > 1:
        groups = [g for g in groups if not rigid[g.start]] + [slice(0, int(rigid.sum()))]
    for g in groups:
        aligned = align_cluster(phi[:, g], M)
        # inside a cluster, list the modes in DOF order (x y z rx ry rz), then by body
        key = np.argmax(np.abs(energy_fractions(aligned, M)), axis=1)
        phi[:, g] = aligned[:, np.argsort(key % 6 * a.n + key, kind="stable")]
    # sign: largest component positive
    idx = np.argmax(np.abs(phi), axis=0)
    phi = phi * np.sign(phi[idx, np.arange(phi.shape[1])])
    omega = np.sqrt(w2)
    energy = energy_fractions(phi, M)
    gamma = phi.T @ (M @ rigid_influence(a.model))
    return Modes(model=a.model, dofs=a.dofs, omega=omega, shapes=phi, energy=energy,
                 effective_mass=gamma ** 2, rigid=rigid, method=name, note=_why(method, name),
                 error_estimate=spec.error)


def _spectrum(a: Assembly, n_modes: int | None, method: str | Solver) -> Any:
    """The assembly's undamped spectrum, solved once per ``(n_modes, method)`` (a named method: a
    callable is the caller's and is run each time); the Spectrum is read-only."""
    if callable(method):
        return undamped(a.K, a.M, a.stiffness_factor(), n_modes, method)
    key = ("spectrum", n_modes, method)
    if key not in a._cache:
        a._cache[key] = undamped(a.K, a.M, a.stiffness_factor(), n_modes, method)
    return a._cache[key]


def _why(method: Any, name: str) -> str:
    """Why ``auto`` chose the solver ("" for a solver chosen by the caller)."""
    if not isinstance(method, str) or method != "auto":
        return ""
    if name.startswith("shift-invert"):
        return "auto: sparse model and fewer than a tenth of the modes asked for: shift-invert"
    if name.startswith("jacobi"):
        return (f"auto: Jacobi SVD of the stiffness factor (high relative accuracy; up to {JACOBI_MAX} "
                "DOFs)")
    return ("auto: dense eigh, modes whose error estimate exceeds "
            f"{FREQ_RTOL:g} refined on the stiffness factor")
