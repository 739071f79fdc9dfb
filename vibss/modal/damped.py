"""Damped modes: poles, damping ratios and complex shapes, paired with the undamped modes.

The poles are those of the state-space system ``x' = A x`` of M, C, K. They are computed in
scaled modal coordinates: with the mass-normalised undamped shapes Phi (``Phi^T M Phi = I``,
``Phi^T K Phi = Omega^2``) and ``Chat = Phi^T C Phi``, the states ``[S eta; eta']`` (S = Omega for
elastic modes, 1 for rigid ones) give

    A = [[0, S], [-Omega^2 S^-1, -Chat]],

a similarity transform of the physical A that is balanced by construction, so its eigenvalues
keep the small real parts of lightly damped poles (see docs/performance.md). Two short cuts:

- rigid-body modes that no damper touches (``Chat`` row ~ 0) are exact double zero poles and are
  left out of the eigenvalue problem: a plain eigen-solve of A turns them into spurious
  +-1e-5 poles with damping ratio -0.98;
- classically damped models (``Chat`` diagonal) have closed-form poles per mode,
  ``lambda = -zeta w +- i w sqrt(1 - zeta^2)``, ``zeta = Chat_ii / (2 w)``.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Any, ClassVar

import numpy as np

from ..linear.plant.assemble import Assembly, assemble
from ..errors import ArgumentError
from ..model.model import Model
from ..linear.eigen.complex_modes import eigenpairs
from ..linear.eigen.basis import damping_coupling
from ..linear.plant.hysteresis import dropped_hysteresis
from ..linear.plant.build import build_plant
from ..linear.solve.exact import without_hysteresis
from .undamped import Modes, modes
from ..results import Result, Table, freeze, jsonable, require_pandas

__all__ = ["DampedModes", "damped_modes"]


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

    def table(self) -> Table:
        """Frequencies, damping ratios and the paired undamped modes."""
        rows = []
        for k in range(len(self)):
            j = self.paired[k]
            rows.append([f"{k + 1}", f"{self.frequency_hz[k]:.4f}", f"{self.damped_frequency_hz[k]:.4f}",
                         f"{self.damping_ratio[k]:.5f}", f"{self.poles[k].real:.5g}",
                         f"{self.poles[k].imag:.5g}", f"{j + 1} ({self.undamped.frequency_hz[j]:.3f} Hz, "
                         f"{self.undamped.labels[j]})"])
        return Table(["mode", "fn [Hz]", "fd [Hz]", "zeta", "Re p [1/s]", "Im p [rad/s]", "undamped mode"],
                     rows, title=f"Damped modes ({self.method})")

    def summary(self) -> Table:
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

        return pd.DataFrame({
            "frequency_hz": self.frequency_hz, "damped_frequency_hz": self.damped_frequency_hz,
            "damping_ratio": self.damping_ratio, "pole_real": self.poles.real,
            "pole_imag": self.poles.imag, "undamped_mode": self.paired + 1,
        }, index=pd.RangeIndex(1, len(self) + 1, name="mode"))


def damped_modes(model: Model | Assembly, undamped: Modes | None = None) -> DampedModes:
    """Poles, damping ratios and complex shapes of a viscously damped model.

    Loss factors (hysteretic damping) have no causal time-domain form and are left out: a
    :class:`~vibss.errors.VibssWarning` names the mounts and ``note`` says so.

    Parameters
    ----------
    model : Model or Assembly
        The system (ground fixed).
    undamped : Modes or None
        All undamped modes of the same model, if already computed.

    Returns
    -------
    DampedModes
        Ordered by natural frequency.

    Examples
    --------
    >>> from vibss import Body, MountType, Mount, Model
    >>> t = MountType("t", [1e4, 1e4, 1e4], damping=[20.0, 20.0, 20.0])
    >>> m = Model([Body("b", 1.0, [1e-2, 1e-2, 1e-2])], [Mount("m", t, "b")])
    >>> d = damped_modes(m)   # one mount at the COG: rotations are free (zero poles)
    >>> d.damping_ratio[d.frequency_hz > 0].round(6)   # c / (2 sqrt(k m)) for x, y, z
    array([0.1, 0.1, 0.1])
    """
    a = model if isinstance(model, Assembly) else assemble(model)
    und = undamped if undamped is not None else modes(a)
    if len(und) != a.n:
        raise ArgumentError(f"damped_modes: undamped: needs all {a.n} undamped modes (modes(model, "
                            f"n_modes=None)), got {len(und)}", argument="undamped", received=len(und),
                            expected=a.n)
    left_out = dropped_hysteresis(a, "damped_modes")
    if any(t.has_branches for t in a.model.mount_types.values()):
        return _with_branches(a, und, left_out)
    phi, w = und.shapes, und.omega
    chat = phi.T @ (a.dense("C") @ phi)
    chat = 0.5 * (chat + chat.T)
    scale = max(float(np.abs(chat).max()), np.finfo(float).tiny)
    classical = not bool(np.any(damping_coupling(chat) > 0))
    # rigid modes that no damper touches: exact double zero poles
    untouched = und.rigid & (np.abs(chat).max(axis=1) <= 1e-14 * scale)
    if not np.any(chat):
        poles, eta = 1j * w, np.eye(len(w), dtype=complex)
        method = "undamped (poles i w)"
    elif classical:
        zeta = np.divide(np.diag(chat), 2 * w, out=np.zeros_like(w), where=w > 0)
        poles_list, eta_cols = [], []
        for j in range(len(w)):
            e = np.zeros(len(w), complex)
            e[j] = 1
            if w[j] == 0:                       # damped rigid motion: poles 0 and -c
                poles_list += [0.0 + 0j, -chat[j, j] + 0j] if chat[j, j] > 0 else [0j]
                eta_cols += [e, e] if chat[j, j] > 0 else [e]
            elif zeta[j] < 1:
                poles_list.append(w[j] * (-zeta[j] + 1j * np.sqrt(1 - zeta[j] ** 2)))
                eta_cols.append(e)
            else:                               # overdamped: two real poles
                r = w[j] * np.sqrt(zeta[j] ** 2 - 1)
                poles_list += [-zeta[j] * w[j] + r + 0j, -zeta[j] * w[j] - r + 0j]
                eta_cols += [e, e]
        poles, eta = np.array(poles_list), np.array(eta_cols).T
        method = "classical damping: closed form per undamped mode"
    else:
        keep = np.flatnonzero(~untouched)
        wk = w[keep]
        s = np.where(wk > 0, wk, 1.0)
        nk = len(keep)
        A = np.zeros((2 * nk, 2 * nk))
        A[:nk, nk:] = np.diag(s)
        A[nk:, :nk] = -np.diag(wk ** 2 / s)
        A[nk:, nk:] = -chat[np.ix_(keep, keep)]
        lam, vec = eigenpairs(A)
        sel = lam.imag >= 0                     # one of each conjugate pair, and real poles
        lam, vec = lam[sel], vec[:, sel]
        eta_k = vec[:nk] / s[:, None]
        eta = np.zeros((len(w), len(lam)), complex)
        eta[keep] = eta_k
        extra = np.flatnonzero(untouched)
        lam = np.concatenate([np.zeros(len(extra), complex), lam])
        eye = np.zeros((len(w), len(extra)), complex)
        eye[extra, np.arange(len(extra))] = 1
        poles, eta = lam, np.hstack([eye, eta])
        method = "general damping: eig of the scaled modal state matrix"
    poles = np.where(np.abs(poles.imag) <= 1e-14 * np.abs(poles).max(initial=1.0), poles.real + 0j, poles)
    order = np.lexsort((-poles.real, np.abs(poles)))
    poles, eta = poles[order], eta[:, order]
    paired = np.argmax(np.abs(eta), axis=0)
    shapes = phi @ eta
    big = shapes[np.argmax(np.abs(shapes), axis=0), np.arange(shapes.shape[1])]
    shapes = shapes / np.where(big == 0, 1.0, big)
    return DampedModes(poles=poles, shapes=shapes, paired=paired, undamped=und, method=method, note=left_out)


def _with_branches(a: Assembly, und: Modes, left_out: str) -> DampedModes:
    """Damped modes of a model with frequency-dependent mounts: ``eig`` of the state matrix of
    :func:`vibss.statespace`, whose states include every mount's Maxwell branches (the same ladder
    as the FRF and the time response). The branches add real relaxation poles; shapes are the
    DOF displacements of the eigenvectors."""
    # python-control is heavy at start-up (tests/test_startup.py): only models with branches need it
    from ..linear.statespace import statespace

    plant = without_hysteresis(build_plant(a, [f"{a.model.body_names[0]}.fx"]))   # every DOF out
    sys = statespace(plant)
    lam, vec = eigenpairs(np.asarray(sys.A))
    scale = max(float(np.abs(lam).max(initial=0.0)), np.finfo(float).tiny)
    lam = np.where(np.abs(lam.imag) <= 1e-12 * scale, lam.real + 0j, lam)
    keep = lam.imag >= 0
    lam, shapes = lam[keep], np.asarray(sys.C) @ vec[:, keep]
    order = np.lexsort((-lam.real, np.abs(lam)))
    lam, shapes = lam[order], shapes[:, order]
    mphi = und.shapes.T @ a.dense("M")
    paired = np.argmax(np.abs(mphi @ shapes), axis=0)
    big = shapes[np.argmax(np.abs(shapes), axis=0), np.arange(shapes.shape[1])]
    shapes = shapes / np.where(big == 0, 1.0, big)
    assert plant.branches is not None
    poles_say = ("relaxation poles real, fluid-track poles complex" if plant.branches.inertial.any()
                 else "their relaxation poles are real")
    note = "; ".join(x for x in (plant.branches.note() + f" ({poles_say}; undamped modes at the static "
                                 "stiffness)", left_out) if x)
    return DampedModes(poles=lam, shapes=shapes, paired=paired, undamped=und,
                       method="frequency-dependent mounts: eig of the state matrix with their internal states",
                       note=note)
