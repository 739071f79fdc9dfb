"""State spaces and second-order systems to and from MATLAB ``.mat`` files (scipy.io).

:func:`write_matlab` writes what MATLAB's ``ss(A, B, C, D)`` takes, at the top level of the
file: ``A``, ``B``, ``C``, ``D``, ``dt`` (0: continuous), the cell arrays ``InputName``,
``OutputName``, ``StateName``, ``InputUnit``, ``OutputUnit`` (SI, signal names in vibss spelling,
``engine.z``) and ``name``; for a plant or a model also the struct ``second_order`` with its
M, C, K (and the hysteretic H), the input maps F, Kz, Cz, Mz, the output maps Oq, Ov, Oa, Pz, Pv,
Pa, Pf, and the cells ``dofs`` and ``kinds`` (the equations of :mod:`vibss.linear.plant.plant`):

    M q'' + C q' + K q = F u_f - (Kz z + Cz z' + Mz z''),   y = Oq q + Ov q' + Oa q'' + Pz z + Pv z' + Pa z'' + Pf u_f

In MATLAB: ``s = load('plant.mat'); sys = ss(s.A, s.B, s.C, s.D, 'InputName', s.InputName,
'OutputName', s.OutputName)``. Doubles go out as doubles, so :func:`read_matlab` gives every
matrix back bit for bit.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import ArgumentError, ModelFileError
from ..linear.plant.plant import Plant
from ..model.units import input_unit

__all__ = ["write_matlab", "read_matlab", "MatlabSystem", "SECOND_ORDER", "BRANCH_NOTE"]

BRANCH_NOTE = ("the frequency-dependent mounts' Maxwell branches (their internal states) are in A, B, C, D "
               "only; second_order's M, C, K hold those mounts' static stiffness and damping, without them")
"""What the file's ``second_order.note`` says of a plant with frequency-dependent mounts."""

SECOND_ORDER = ("M", "C", "K", "H", "F", "Kz", "Cz", "Mz", "Hz", "Oq", "Ov", "Oa", "Pz", "Pv", "Pa", "Pf")
"""The plant's matrices written into the ``second_order`` struct."""


@dataclass(frozen=True, eq=False)
class MatlabSystem:
    """What :func:`read_matlab` reads: a state space with its names and units, and the second-order
    system where the file has one.

    Attributes
    ----------
    A, B, C, D : ndarray
        State-space matrices (SI).
    inputs, outputs, states : tuple of str
        Signal and state names (vibss spelling).
    input_units, output_units : tuple of str
        SI unit of each input and output.
    name : str
        System name.
    second_order : dict of str to ndarray
        ``M, C, K, H, F, Kz, Cz, Mz, Hz, Oq, Ov, Oa, Pz, Pv, Pa, Pf`` (empty: the file has none).
    dofs, kinds : tuple of str
        The second-order system's DOF names and each input's kind (``"force"``, ``"acceleration"``).
    note : str
        What the second-order part leaves out (:data:`BRANCH_NOTE`), or empty.
    """

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    inputs: tuple[str, ...]
    outputs: tuple[str, ...]
    states: tuple[str, ...]
    input_units: tuple[str, ...]
    output_units: tuple[str, ...]
    name: str = "vibss"
    second_order: dict[str, np.ndarray] = field(default_factory=dict)
    dofs: tuple[str, ...] = ()
    kinds: tuple[str, ...] = ()
    note: str = ""

    @property
    def statespace(self) -> Any:
        """The system as a :class:`~vibss.linear.statespace.NamedStateSpace`."""
        from ..linear.plant.labels import control_name
        from ..linear.statespace import NamedStateSpace

        return NamedStateSpace(self.A, self.B, self.C, self.D, inputs=[control_name(u) for u in self.inputs],
                               outputs=[control_name(y) for y in self.outputs],
                               states=[control_name(x) for x in self.states], name=control_name(self.name))


def _cell(names: Any) -> np.ndarray:
    out = np.empty((1, len(names)), dtype=object)
    for i, n in enumerate(names):
        out[0, i] = str(n)
    return out


def _vibss(name: str) -> str:
    return name.replace(":", ".")


def write_matlab(system: Any, path: str | Path, *, inputs: Any = None, outputs: Any = None,
                 realization: str = "modal") -> Path:
    """Write a system as a MATLAB ``.mat`` file: A, B, C, D with signal names and units, and for a
    plant or model its M, C, K with their input and output maps.

    Parameters
    ----------
    system : Plant, Model or python-control StateSpace
        A :class:`~vibss.linear.plant.plant.Plant` (from :func:`vibss.build_plant`), a model with
        ``inputs`` (and ``outputs``), or a state space (then no second-order part, no units).
    path : str or Path
        The file (overwritten; ``.mat`` added when missing).
    inputs, outputs : sequence of str or None
        The study's signals when ``system`` is a model (as :func:`vibss.build_plant`).
    realization : {"modal", "physical"}
        State coordinates of A, B, C, D (:func:`vibss.statespace`).

    Returns
    -------
    Path

    Raises
    ------
    ArgumentError
        ``system`` is none of these, or signals given with a plant or a state space.

    Warns
    -----
    VibssWarning
        Frequency-dependent mounts: their Maxwell branches are in A, B, C, D only (the second-order
        part holds their static stiffness; its ``note`` says so).

    Examples
    --------
    >>> import tempfile, pathlib, vibss
    >>> m = vibss.Model([vibss.Body("b", 2.0, [1, 1, 1])],
    ...                 [vibss.Mount("m", vibss.MountType("t", [1e3] * 3, [2.0] * 3), "b")])
    >>> p = write_matlab(m, pathlib.Path(tempfile.mkdtemp()) / "b", inputs=["b.fz"], outputs=["b.z"])
    >>> back = read_matlab(p)
    >>> back.inputs, back.outputs, back.input_units, back.second_order["M"].shape
    (('b.fz',), ('b.z',), ('N',), (6, 6))
    """
    from scipy.io import savemat

    from ..linear.plant.build import build_plant
    from ..linear.statespace import statespace
    from ..model.model import Model

    path = Path(path)
    path = path if path.suffix == ".mat" else path.with_name(path.name + ".mat")
    if isinstance(system, Model):
        if inputs is None:
            raise ArgumentError("write_matlab: inputs: a model needs inputs=[...] (and optionally outputs=[...])",
                                argument="inputs", received=None)
        system = build_plant(system, inputs, outputs)
    elif inputs is not None or outputs is not None:
        raise ArgumentError("write_matlab: inputs, outputs: only with a model (a plant or a state space has its "
                            "signals)", argument="inputs", received=inputs)
    data: dict[str, Any] = {}
    if isinstance(system, Plant):
        sys = statespace(system, realization)
        data["InputUnit"] = _cell([input_unit(u, k) for u, k in zip(system.inputs, system.kinds)])
        data["OutputUnit"] = _cell(system.units)
        second: dict[str, Any] = {k: np.asarray(getattr(system, k), dtype=float) for k in SECOND_ORDER
                  if getattr(system, k, None) is not None}
        second["dofs"] = _cell(system.dofs)
        second["kinds"] = _cell(system.kinds)
        if system.branches is not None:
            import warnings

            from ..errors import VibssWarning

            second["note"] = BRANCH_NOTE
            warnings.warn(f"write_matlab: {BRANCH_NOTE}", VibssWarning, stacklevel=2)
        data["second_order"] = second
        name = system.name
    elif all(hasattr(system, k) for k in ("A", "B", "C", "D", "input_labels", "output_labels")):
        sys = system
        data["InputUnit"] = _cell([""] * sys.ninputs)
        data["OutputUnit"] = _cell([""] * sys.noutputs)
        name = _vibss(str(getattr(sys, "name", "") or "vibss"))
    else:
        raise ArgumentError(f"write_matlab: system: expected a Plant, a Model or a StateSpace, got "
                            f"{type(system).__name__}", argument="system", received=type(system).__name__)
    for key in ("A", "B", "C", "D"):
        data[key] = np.atleast_2d(np.asarray(getattr(sys, key), dtype=float))
    data["dt"] = float(getattr(sys, "dt", 0) or 0)
    data["InputName"] = _cell([_vibss(u) for u in sys.input_labels])
    data["OutputName"] = _cell([_vibss(y) for y in sys.output_labels])
    data["StateName"] = _cell([_vibss(x) for x in sys.state_labels])
    data["name"] = name
    savemat(str(path), data, do_compression=True, oned_as="column")
    return path


def _names(value: Any) -> tuple[str, ...]:
    return tuple(str(np.asarray(v).item()) if np.asarray(v).size else "" for v in np.asarray(value).ravel())


def read_matlab(path: str | Path) -> MatlabSystem:
    """Read a ``.mat`` file written by :func:`write_matlab` (or any with A, B, C, D).

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    MatlabSystem
        Matrices bit for bit as written; ``.statespace`` for python-control.

    Raises
    ------
    ModelFileError
        No such file, not a MAT file, no A, B, C, D, or names that do not match the matrices.
    """
    from scipy.io import loadmat
    from scipy.io.matlab import MatReadError

    path = Path(path)
    if not path.is_file():
        raise ModelFileError(f"read_matlab: {path}: no such file", argument="path", received=str(path))
    try:
        raw = loadmat(str(path))
    except (MatReadError, ValueError, TypeError, OSError) as err:
        raise ModelFileError(f"read_matlab: {path}: not a MAT file ({err})", argument="path",
                             received=str(path)) from None
    missing = [k for k in ("A", "B", "C", "D") if k not in raw]
    if missing:
        raise ModelFileError(f"read_matlab: {path}: no {', '.join(missing)} (a state space needs A, B, C, D)",
                             argument="path", received=sorted(k for k in raw if not k.startswith("__")))
    a, b, c, d = (np.asarray(raw[k], dtype=float) for k in ("A", "B", "C", "D"))
    n, m, p = a.shape[0], d.shape[1], d.shape[0]
    a, b, c = a.reshape(n, n), b.reshape(n, m), c.reshape(p, n)     # an empty matrix comes back (0, 0)

    def names(key: str, count: int, stem: str) -> tuple[str, ...]:
        got = _names(raw[key]) if key in raw else ()
        if not got:
            return tuple(f"{stem}{k + 1}" for k in range(count)) if stem else ("",) * count
        if len(got) != count:
            raise ModelFileError(f"read_matlab: {path}: {key}: {len(got)} names for {count} of the matrices",
                                 argument=key, received=got)
        return got

    second: dict[str, np.ndarray] = {}
    dofs: tuple[str, ...] = ()
    kinds: tuple[str, ...] = ()
    note = ""
    if "second_order" in raw:
        s = raw["second_order"][0, 0]
        for key in s.dtype.names:
            if key == "dofs":
                dofs = _names(s[key])
            elif key == "kinds":
                kinds = _names(s[key])
            elif key == "note":
                note = _names(s[key])[0]
            else:
                second[key] = np.asarray(s[key], dtype=float)
        nd = len(dofs)
        for key, v in list(second.items()):          # MATLAB keeps no empty shapes: (0, 0) back to their sizes
            if v.size == 0:
                rows = nd if key in ("M", "C", "K", "H", "F", "Kz", "Cz", "Mz", "Hz") else p
                cols = nd if key in ("M", "C", "K", "H", "Oq", "Ov", "Oa") else m
                second[key] = np.zeros((rows, cols))
    name = _names(raw["name"])[0] if "name" in raw and np.asarray(raw["name"]).size else "vibss"
    return MatlabSystem(a, b, c, d, names("InputName", m, "u"), names("OutputName", p, "y"),
                        names("StateName", n, "x"), names("InputUnit", m, ""), names("OutputUnit", p, ""),
                        name, second, dofs, kinds, note)
