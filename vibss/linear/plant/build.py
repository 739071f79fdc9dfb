"""The :class:`~vibss.linear.plant.plant.Plant` of a study: its free-DOF matrices and the maps of its
named inputs and outputs (the names: :mod:`vibss.linear.plant.names`).

Examples
--------
>>> from ... import Body, Model, Mount, MountType
>>> t = MountType("t", [1e4, 1e4, 1e4])
>>> m = Model([Body("b", 10.0, [1, 1, 1])], [Mount("m", t, "b")])
>>> p = build_plant(m, ["b.fz"], ["b.z", "mount.m.fz"])
>>> p.inputs, p.outputs, p.units
(('b.fz',), ('b.z', 'mount.m.fz'), ('m', 'N'))
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
import scipy.sparse as sp

from ...model.nonlinearity import refuse_nonlinear
from .assemble import Assembly, assemble
from ...errors import ModelError
from ..eigen.undamped import undamped
from ...model.model import Model
from .branches import build_branches
from .memo import remembered
from .mountform import mount_form
from .names import actuator_reactions, default_outputs, output_row, parse_input
from .plant import Plant

__all__ = ["build_plant", "input_maps"]


def input_maps(asm: Assembly, parsed: Sequence[Any]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Generalised-force and prescribed-motion columns of parsed inputs, and the free DOFs.

    Parameters
    ----------
    asm : Assembly
        The assembled model.
    parsed : sequence
        Inputs parsed by :func:`parse_input` (each has ``force`` (n,) or ``motion`` (n + nz,)).

    Returns
    -------
    force : (n, m) ndarray
        Generalised force per unit force input.
    motion : (n + nz, m) ndarray
        Prescribed motion (body, ground and support DOFs) per unit motion input.
    free : (k,) int ndarray
        DOFs that are not prescribed (the unknowns).
    """
    n, m = asm.n, len(parsed)
    motion, force = np.zeros((n + asm.nz, m)), np.zeros((n, m))
    for j, p in enumerate(parsed):
        if p.force is not None:
            force[:, j] = p.force
        else:
            motion[:, j] = p.motion
    prescribed = np.flatnonzero(np.any(motion[:n] != 0, axis=1))
    free = np.setdiff1d(np.arange(n), prescribed)
    if free.size == 0:
        raise ModelError("inputs: every body DOF is prescribed; nothing is left to respond")
    return force, motion, free


def build_plant(model_or_assembly: Model | Assembly, inputs: Sequence[Any],
                outputs: Sequence[str] | None = None,
                modal_damping: float | Sequence[float] | None = None, sparse: bool = False) -> Plant:
    """The second-order plant of a study: free-DOF matrices plus the named input/output maps.

    Only the requested input columns and output rows are built.

    Parameters
    ----------
    model_or_assembly : Model or Assembly
        The system (a sparse assembly is densified unless ``sparse``).
    inputs : sequence of str or Excitation
        Input signals (see the module docstring), e.g. ``["engine.fz", "ground.z.acc"]``.
    outputs : sequence of str or None
        Output signals; default: the displacement of every body DOF.
    modal_damping : float, (n_free,) array_like or None
        Extra modal damping ratio(s) [-] of the free DOFs' undamped elastic modes (ascending
        frequency), added to C as ``M Phi diag(2 zeta w) Phi^T M``. It belongs to no mount, so
        mount and ground force outputs do not include it.
    sparse : bool
        Keep ``M, C, K, H`` as ``scipy.sparse`` CSR matrices (no dense n x n matrix): for large
        models, with ``frequency_response(plant, frequencies=..., method="sparse")`` or
        :func:`vibss.reduce`. Not with ``modal_damping``.

    Returns
    -------
    Plant

    Raises
    ------
    ModelError
        Unknown signal names (with the valid forms and a did-you-mean), duplicates, no inputs.

    Examples
    --------
    >>> from ... import Body, Model, Mount, MountType
    >>> t = MountType("t", [1e4, 1e4, 1e4])
    >>> m = Model([Body("b", 10.0, [1, 1, 1])], [Mount("m", t, "b")])
    >>> p = build_plant(m, ["ground.z.disp"], ["b.z"])
    >>> p.dofs[:3], p.kinds, float(p.Kz[2, 0])
    (('b.x', 'b.y', 'b.z'), ('displacement',), -10000.0)

    The plant of a small Model and signals named by strings is remembered
    (:mod:`vibss.linear.plant.memo`): the same model and signals give the same read-only Plant, with the
    modal basis and factorisations already cached on it.
    """
    if isinstance(model_or_assembly, Model) and modal_damping is None:
        key = _plant_key(inputs, outputs, sparse)
        if key is not None:
            return remembered(model_or_assembly, key,
                              lambda: _build_plant(model_or_assembly, inputs, outputs, None, sparse))
    return _build_plant(model_or_assembly, inputs, outputs, modal_damping, sparse)


def _plant_key(inputs: Any, outputs: Any, sparse: bool) -> tuple | None:
    """The memo key of a plant whose signals are all named by strings (None otherwise)."""
    names = [inputs] if isinstance(inputs, str) else inputs
    outs = [outputs] if isinstance(outputs, str) else outputs
    if not isinstance(names, (list, tuple)) or not all(isinstance(x, str) for x in names):
        return None
    if outs is not None and (not isinstance(outs, (list, tuple)) or not all(isinstance(x, str) for x in outs)):
        return None
    return ("plant", tuple(names), None if outs is None else tuple(outs), bool(sparse))


def _build_plant(model_or_assembly: Model | Assembly, inputs: Sequence[Any], outputs: Sequence[str] | None,
                 modal_damping: float | Sequence[float] | None, sparse: bool) -> Plant:
    asm = (model_or_assembly if isinstance(model_or_assembly, Assembly)
           else assemble(model_or_assembly, sparse=True if sparse else None))
    model = asm.model
    refuse_nonlinear(model, "build_plant")
    if sparse and modal_damping is not None:
        raise ModelError("modal_damping: needs the dense plant (sparse=False): it adds a full matrix to C")
    if isinstance(inputs, str) or not hasattr(inputs, "__iter__"):
        inputs = [inputs]
    parsed = [parse_input(asm, item) for item in inputs]
    if not parsed:
        raise ModelError("inputs: give at least one input signal, e.g. "
                         f"'{model.body_names[0]}.fz' or 'ground.z.disp'")
    outputs = default_outputs(model) if outputs is None else outputs
    if isinstance(outputs, str):
        outputs = [outputs]
    outputs = tuple(outputs)
    for what, names in (("inputs", [p.name for p in parsed]), ("outputs", outputs)):
        dup = sorted({x for x in names if names.count(x) > 1})
        if dup:
            raise ModelError(f"{what}: signal(s) {dup} given more than once")

    n, m = asm.n, len(parsed)
    mats = {key: sp.csr_matrix(getattr(asm, key)) if sparse else asm.dense(key) for key in ("M", "K", "C", "H")}
    coupling = {"K": asm.Kg, "C": asm.Cg, "H": asm.Hg}
    force, motion, free = input_maps(asm, parsed)

    every = free.size == n and bool(np.all(free == np.arange(n)))     # nothing prescribed: no copies

    def ff(a: Any) -> Any:
        if sparse:
            return a.tocsr(copy=True) if every else a[free][:, free].tocsr()
        # the assembly's dense matrix is read-only, as the plant's are: shared, not copied (4 x 46 MB
        # and 0.48 s at 2,400 DOF)
        return a if every else a[np.ix_(free, free)]

    def fz(key: str) -> np.ndarray:
        out = np.asarray((mats[key] if every else mats[key][free]) @ motion[:n])
        if key in coupling:
            out = out + np.asarray(coupling[key][free] @ motion[n:])
        return out

    C = ff(mats["C"])
    if modal_damping is not None:
        C = C + _modal_damping(ff(mats["M"]), ff(mats["K"]), modal_damping, _columns(asm.stiffness_factor(), free))
    cache: dict = {}
    rows, units = zip(*(output_row(asm, name, cache) for name in outputs)) if outputs else ((), ())
    full = {key: np.array([getattr(r, key) for r in rows]).reshape(len(outputs), n + asm.nz)
            for key in ("d", "v", "a", "h")}
    o = {key: full[key][:, free] for key in full}
    pz = {key: full[key] @ motion for key in full}
    K, H, M = ff(mats["K"]), ff(mats["H"]), ff(mats["M"])
    extra_c = None if modal_damping is None else C - ff(mats["C"])
    return Plant(
        dofs=tuple(asm.dofs[i] for i in free),
        M=M, C=C, K=K, H=H,
        mounts=mount_form(asm, free, (K, C, H, M), extra_c),
        inputs=tuple(p.name for p in parsed), kinds=tuple(p.kind for p in parsed),
        F=force[free], Kz=fz("K"), Cz=fz("C"), Mz=fz("M"), Hz=fz("H"),
        outputs=outputs, units=tuple(units),
        Oq=o["d"], Ov=o["v"], Oa=o["a"], Pz=pz["d"], Pv=pz["v"], Pa=pz["a"],
        Pf=actuator_reactions(model, [p.name for p in parsed], outputs), name=model.name,
        Oh=o["h"], Ph=pz["h"], Kf=_columns(asm.stiffness_factor(), free),
        branches=build_branches(model, asm.deflection_matrix(), free, motion, np.array(
            [np.zeros(3 * len(model.mounts)) if r.f is None else r.f for r in rows]).reshape(
            len(outputs), 3 * len(model.mounts))) if any(t.has_branches for t in model.mount_types.values()) else None,
    )


def _columns(g: sp.csr_matrix, cols: np.ndarray) -> sp.csr_matrix:
    """``g[:, cols]`` as CSR with sorted indices (so no product sorts them in place later and the
    summation order, hence the last bits, never change between calls)."""
    out = g[:, cols].tocsr()
    out.sort_indices()
    return out


def _modal_damping(M: np.ndarray, K: np.ndarray, zeta: float | Sequence[float], factor: Any = None) -> np.ndarray:
    spec = undamped(K, M, factor)
    w2, phi, rigid = spec.omega2, spec.phi, spec.rigid
    w = np.sqrt(w2)
    z = np.broadcast_to(np.asarray(zeta, dtype=float), w.shape) if np.ndim(zeta) == 0 else np.asarray(zeta, float)
    if z.shape != w.shape or np.any(z < 0) or not np.all(np.isfinite(z)):
        raise ModelError(f"modal_damping: expected a ratio >= 0 or {w.size} of them, got {zeta!r}")
    g = np.where(rigid, 0.0, 2.0 * z * w)
    mp = M @ phi
    c = (mp * g) @ mp.T
    c = 0.5 * (c + c.T)
    # entries at the round-off of the diagonal are zeros that the eigenvectors' last bits blurred
    d = np.sqrt(np.abs(np.diag(c)))
    c[np.abs(c) <= 4 * c.shape[0] * np.finfo(float).eps * np.outer(d, d)] = 0.0
    return c
