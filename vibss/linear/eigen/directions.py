"""Direction bookkeeping for shapes: dominant DOF, clean bases of repeated modes, text descriptions.

A mode (or a free motion) is labelled by the DOF name (x y z rx ry rz) that holds the largest share
of its kinetic energy summed over the bodies. Where frequencies repeat (symmetric layouts, the six
zero modes of a free body), any basis of the eigenspace is valid and a solver returns an arbitrary
mixture; :func:`align_cluster` rotates such a basis so each vector is as pure in one (body, DOF)
as the subspace allows.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import cast

import numpy as np

from ...model.model import DOF_NAMES
from .checks import _six_blocks, fast_matrix
from .small import symmetric_eigen

__all__ = ["energy_fractions", "direction_shares", "dominant_direction", "align_cluster",
           "cluster_slices", "describe_motion", "dof_labels"]

# Distinct, well-separated weights: one per (body, DOF) pair, used to split repeated modes.
_GOLDEN = 0.6180339887498949


def energy_fractions(shapes: np.ndarray, mass: np.ndarray) -> np.ndarray:
    """Kinetic-energy fraction per DOF of each shape.

    Parameters
    ----------
    shapes : (n, k) ndarray
        Shapes (columns), any scaling.
    mass : (n, n) ndarray
        Mass matrix.

    Returns
    -------
    (k, n) ndarray
        ``E[i, j] = phi_j (M phi)_j / (phi^T M phi)`` for shape i; each row sums to 1.
    """
    dense = isinstance(mass, np.ndarray) and mass.shape[0] > 6
    blocks = _six_blocks(mass) if dense else None
    if blocks is not None:        # rigid bodies: by their 6x6 blocks (a dense GEMM was 0.4 s at 2,400 DOF)
        cols = shapes.shape[1] if shapes.ndim == 2 else 1
        mp = np.matmul(blocks, shapes.reshape(blocks.shape[0], 6, cols)).reshape(shapes.shape)
    else:
        mp = (fast_matrix(mass) if dense else mass) @ shapes
    # real shapes: the conjugate is the shapes themselves (no copy; the same products)
    num = ((shapes.conj() if np.iscomplexobj(shapes) else shapes) * mp).real.T
    return num / num.sum(axis=1, keepdims=True)


def direction_shares(fractions: np.ndarray) -> np.ndarray:
    """(k, 6) energy fractions summed over bodies, per DOF name x..rz."""
    k, n = fractions.shape
    return fractions.reshape(k, n // 6, 6).sum(axis=1)


def dominant_direction(fractions: np.ndarray) -> list[str]:
    """DOF name holding the largest summed energy share, per shape (rows of ``fractions``)."""
    return [DOF_NAMES[i] for i in np.argmax(direction_shares(fractions), axis=1)]


def dof_labels(fractions: np.ndarray, dofs: Sequence[str]) -> list[str]:
    """Mode labels from energy fractions over named DOFs (``'<body>.<dof>'``), as
    :attr:`vibss.modal.Modes.labels` gives them: the direction (x y z rx ry rz) with the largest
    summed kinetic-energy share, prefixed with the body holding most of it when the DOFs belong
    to more than one body (``"tank.y"``; one body: ``"y"``).

    Works on any subset of DOFs (a plant whose prescribed DOFs were dropped); DOFs whose name
    does not end in a direction are ignored.

    Parameters
    ----------
    fractions : (k, n) ndarray
        Kinetic-energy fraction per DOF of each mode (:func:`energy_fractions`).
    dofs : sequence of str
        The n DOF names.

    Returns
    -------
    list of str
        One label per mode ("" when no DOF carries a direction).
    """
    split = [d.rsplit(".", 1) for d in dofs]
    bodies = list(dict.fromkeys(p[0] for p in split if len(p) == 2 and p[1] in DOF_NAMES))
    e = np.abs(np.asarray(fractions, dtype=float))
    table = np.zeros((e.shape[0], max(len(bodies), 1), 6))
    where = {b: i for i, b in enumerate(bodies)}
    named = [(j, where[p[0]], DOF_NAMES.index(p[1])) for j, p in enumerate(split) if len(p) == 2 and p[1] in DOF_NAMES]
    if named:                                 # every DOF's share added to its (body, direction) at once
        col, body, dof = np.array(named, dtype=int).T
        cell = body * 6 + dof
        if np.unique(cell).size == cell.size:     # each (body, direction) once: placed, not added (0.17 s
            table.reshape(e.shape[0], -1)[:, cell] = e[:, col]          # of np.add.at at 2,400 DOF)
        else:
            np.add.at(table.transpose(1, 2, 0), (body, dof), e[:, col].T)    # (body, dof, mode) view
    if not bodies:
        return [""] * e.shape[0]
    empty = np.logical_not(table.any(axis=(1, 2))).tolist()
    direction = np.argmax(table.sum(axis=1), axis=1)                                # (k,)
    holder = np.argmax(table[np.arange(e.shape[0]), :, direction], axis=1)          # (k,) body
    if len(bodies) == 1:
        return ["" if empty[k] else DOF_NAMES[d] for k, d in enumerate(direction.tolist())]
    return ["" if empty[k] else f"{bodies[b]}.{DOF_NAMES[d]}"
            for k, (d, b) in enumerate(zip(direction.tolist(), holder.tolist()))]


def cluster_slices(values: np.ndarray, rtol: float, atol: float) -> list[slice]:
    """Runs of sorted ``values`` closer than ``atol + rtol * |value|`` to their neighbour."""
    out, start = [], 0
    values = np.asarray(values, float).tolist()     # Python floats: the same float64 arithmetic, no NumPy scalars
    for i in range(1, len(values) + 1):
        if i == len(values) or values[i] - values[i - 1] > atol + rtol * abs(values[i]):
            if i - start > 1:
                out.append(slice(start, i))
            start = i
    return out


def align_cluster(shapes: np.ndarray, mass: np.ndarray) -> np.ndarray:
    """Rotate an M-orthonormal basis of one eigenspace so each vector is as pure as possible.

    The energy matrices ``E_j = Phi^T sym(M S_j) Phi`` of the single DOFs j sum to the identity;
    diagonalising a combination with distinct weights gives the orthogonal rotation that separates
    the basis by (body, DOF) — exactly, when the eigenspace is spanned by pure motions.

    Parameters
    ----------
    shapes : (n, k) ndarray
        M-orthonormal basis of (nearly) repeated modes.
    mass : (n, n) ndarray
        Mass matrix.

    Returns
    -------
    (n, k) ndarray
        The rotated basis, still M-orthonormal.
    """
    n = shapes.shape[0]
    mp = mass @ shapes
    weights = (1.0 + _GOLDEN * np.arange(n)) % 1.0 + np.arange(n) * 1e-3
    # sum_j w_j * sym(phi_j (M phi)_j) as a k x k matrix
    w = (shapes * weights[:, None]).T @ mp
    w = 0.5 * (w + w.T)
    _, q = symmetric_eigen(w)
    return shapes @ q


def describe_motion(vector: np.ndarray, bodies: Sequence[str], tol: float = 0.05) -> str:
    """Words for a motion vector: ``"body 'a' is free to move in x"`` or a weighted combination."""
    v = np.real(vector)
    big = np.abs(v).max()
    if big == 0:
        return "no motion"
    parts = cast("list[tuple[int, float]]", [(i, v[i] / big) for i in np.flatnonzero(np.abs(v) > tol * big)])
    if len(parts) == 1:
        i = parts[0][0]
        dof = DOF_NAMES[i % 6]
        verb = "rotate about" if dof.startswith("r") else "move in"
        return f"body {bodies[i // 6]!r} is free to {verb} {dof[-1] if dof.startswith('r') else dof}"
    terms = ", ".join(f"{bodies[i // 6]}.{DOF_NAMES[i % 6]} ({c:+.2f})" for i, c in parts)
    return f"a combination of {terms}"
