"""The results of the modal analyses: undamped :class:`Modes` (frequencies, shapes, energies,
effective masses, with the tables engineers read) and :class:`DampedModes` (poles, damping ratios
and complex shapes, paired with the undamped modes). :mod:`vibss.modal.api` computes them."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Any, ClassVar

import numpy as np

from ..linear.eigen.directions import direction_shares, dominant_direction
from ..model.model import DOF_NAMES, Model
from ..results import Result, TextTable, freeze, jsonable, require_pandas
from .kernels import rigid_influence

__all__ = ["Modes", "DampedModes", "CPM_PER_HZ"]

CPM_PER_HZ = 60.0


def _read_only(a: np.ndarray) -> np.ndarray:
    a.setflags(write=False)     # cached on a frozen result: nobody may change it in place
    return a


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

    def summary(self) -> TextTable:
        """The frequency table (:meth:`frequency_table`)."""
        return self.frequency_table()

    def html_tables(self) -> list[TextTable]:
        """Frequencies with effective masses, and the kinetic-energy distribution."""
        return [self.frequency_table(), self.energy_table()]

    def _estimate(self, k: int) -> float | None:
        """Relative error bound of mode k as JSON (None: rigid or not estimated)."""
        if self.error_estimate is None or not np.isfinite(self.error_estimate[k]):
            return None
        return float(self.error_estimate[k])

    def energy_table(self) -> TextTable:
        """Kinetic-energy distribution [%]: one row per mode, one column per body DOF."""
        rows = [[f"{k + 1}", f"{self.frequency_hz[k]:.3f}", self.labels[k]]
                + [f"{100 * e:.1f}" for e in self.energy[k]] for k in range(len(self))]
        return TextTable(["mode", "f [Hz]", "dir"] + list(self.dofs), rows,
                     title="Modal kinetic-energy distribution [%]")

    @cached_property
    def effective_mass_fraction(self) -> np.ndarray:
        """(k, 6) effective masses as fractions of the total mass / inertia about the system COG."""
        r = rigid_influence(self.model).reshape(-1, 6, 6)          # per body: 6 DOFs x 6 directions
        total = sum(np.diag(r[i].T @ b.mass_matrix @ r[i]) for i, b in enumerate(self.model.bodies))
        return _read_only(self.effective_mass / total)

    def frequency_table(self) -> TextTable:
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
        return TextTable(head, rows, title="Undamped natural frequencies (modal mass of the relative shape; "
                                       "effective mass in % of the total mass and of the inertia about "
                                       "the system COG; rel. error: bound of the frequency's relative error)")

    def shape_table(self) -> TextTable:
        """Relative eigenvector values (largest component = 1), per mode and body."""
        rel = self.relative_shapes
        rows = []
        for k in range(len(self)):
            for i, b in enumerate(self.model.body_names):
                rows.append([f"{k + 1}" if i == 0 else "", f"{self.frequency_hz[k]:.3f}" if i == 0 else "",
                             b] + [f"{v:.4f}" for v in rel[6 * i:6 * i + 6, k]])
        return TextTable(["mode", "f [Hz]", "body"] + list(DOF_NAMES), rows,
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
        df.attrs["units"] = {"frequency_hz": "Hz", "cpm": "1/min", "omega": "rad/s", "direction": "-",
                             "rigid": "-", "modal_mass": "kg",
                             **{f"effective_mass_{d}": ("kg m^2" if d.startswith("r") else "kg") for d in DOF_NAMES}}
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


@dataclass(frozen=True, eq=False)
class DampedModes(Result):
    """Damped modes (one entry per complex-conjugate pole pair or real pole).

    Follows the result protocol (:mod:`vibss.results`): ``d['engine.z']`` is the (k,) complex
    component of every damped shape in one DOF; ``output_labels`` are the DOFs; there is no
    python-control twin (``control`` is None; :func:`vibss.statespace` gives the system).

    Attributes
    ----------
    poles : (k,) complex ndarray
        Poles [rad/s] with non-negative imaginary part (one of each conjugate pair); real poles
        of overdamped or damped rigid motions are listed one by one.
    shapes : (n, k) complex ndarray
        Complex mode shapes in the model's DOFs, scaled so the largest component is 1.
    paired : (k,) int ndarray
        Index of the undamped mode each damped mode belongs to (largest modal participation).
    undamped : Modes
        The undamped modes used.
    method : str
        How the poles were found.
    note : str
        Why (the damping found in the model).
    """

    signal_kind: ClassVar[str] = "DOF"

    poles: np.ndarray
    shapes: np.ndarray
    paired: np.ndarray
    undamped: Modes
    method: str
    note: str = ""

    @property
    def output_labels(self) -> tuple[str, ...]:
        """DOF labels of the rows of the shapes."""
        return self.undamped.dofs

    @property
    def units(self) -> tuple[str, ...]:
        """Unit of the motion of each DOF (m or rad); the shapes are relative (largest = 1)."""
        return self.undamped.units

    def _item(self, i: int, j: int | None) -> np.ndarray:
        return self.shapes[i]

    @cached_property
    def natural_frequency(self) -> np.ndarray:
        """Undamped natural frequency of each pole, ``|lambda|`` [rad/s]."""
        return freeze(np.abs(self.poles))

    @cached_property
    def frequency_hz(self) -> np.ndarray:
        """``|lambda| / 2 pi`` [Hz]."""
        return freeze(self.natural_frequency / (2 * np.pi))

    @cached_property
    def damped_frequency_hz(self) -> np.ndarray:
        """Damped frequency ``Im(lambda) / 2 pi`` [Hz] (0 for real poles)."""
        return freeze(self.poles.imag / (2 * np.pi))

    @cached_property
    def damping_ratio(self) -> np.ndarray:
        """``-Re(lambda) / |lambda|`` [-] (0 for zero poles)."""
        wn = self.natural_frequency
        with np.errstate(invalid="ignore", divide="ignore"):
            return freeze(np.where(wn > 0, -self.poles.real / np.where(wn > 0, wn, 1.0), 0.0))

    def __len__(self) -> int:
        return len(self.poles)

    def to_dict(self) -> dict[str, Any]:
        """The spec's JSON structure (SI)."""
        names = self.undamped.model.body_names
        out = []
        for k in range(len(self)):
            s = self.shapes[:, k]
            out.append({
                "frequency_hz": float(self.frequency_hz[k]),
                "damped_frequency_hz": float(self.damped_frequency_hz[k]),
                "damping_ratio": float(self.damping_ratio[k]),
                "pole": [float(self.poles[k].real), float(self.poles[k].imag)],
                "undamped_mode": int(self.paired[k]) + 1,
                "direction": self.undamped.directions[self.paired[k]],
                "shape": {b: {"amplitude": np.abs(s[6 * i:6 * i + 6]).tolist(),
                              "phase_deg": np.degrees(np.angle(s[6 * i:6 * i + 6])).tolist()}
                          for i, b in enumerate(names)},
            })
        return jsonable({"model": self.undamped.model.name, "method": self.method, "note": self.note,
                         "modes": out})

    def table(self) -> TextTable:
        """Frequencies, damping ratios and the paired undamped modes."""
        rows = []
        for k in range(len(self)):
            j = self.paired[k]
            rows.append([f"{k + 1}", f"{self.frequency_hz[k]:.4f}", f"{self.damped_frequency_hz[k]:.4f}",
                         f"{self.damping_ratio[k]:.5f}", f"{self.poles[k].real:.5g}",
                         f"{self.poles[k].imag:.5g}", f"{j + 1} ({self.undamped.frequency_hz[j]:.3f} Hz, "
                         f"{self.undamped.labels[j]})"])
        return TextTable(["mode", "fn [Hz]", "fd [Hz]", "zeta", "Re p [1/s]", "Im p [rad/s]", "undamped mode"],
                     rows, title=f"Damped modes ({self.method})")

    def summary(self) -> TextTable:
        """The table of poles (:meth:`table`)."""
        return self.table()

    def report(self) -> str:
        """Text report."""
        return f"Damped modes of {self.undamped.model.name!r}\n\n" + self.table().render()

    def plot(self, ax: Any = None) -> Any:
        """Pole map: :func:`vibss.plotting.plot_poles`.

        Parameters
        ----------
        ax : Axes or None
            Axes to draw in; default: a new figure.

        Returns
        -------
        matplotlib.figure.Figure
        """
        from ..plotting import plot_poles

        return plot_poles(self, ax)

    def to_pandas(self) -> Any:
        """DataFrame: one row per damped mode."""
        pd = require_pandas()

        df = pd.DataFrame({
            "frequency_hz": self.frequency_hz, "damped_frequency_hz": self.damped_frequency_hz,
            "damping_ratio": self.damping_ratio, "pole_real": self.poles.real,
            "pole_imag": self.poles.imag, "undamped_mode": self.paired + 1,
        }, index=pd.RangeIndex(1, len(self) + 1, name="mode"))
        df.attrs["units"] = {"frequency_hz": "Hz", "damped_frequency_hz": "Hz", "damping_ratio": "-",
                             "pole_real": "rad/s", "pole_imag": "rad/s", "undamped_mode": "-"}
        return df
