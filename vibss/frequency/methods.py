"""Frequency-response methods: the registry, the resolver and ``auto``'s choice.

:data:`METHODS` (from :mod:`vibss.frequency.kernels`) holds :class:`FrequencyMethod` objects that
carry their facts (exact, needs the modal basis, accepts sparse plants, falls back to ...);
:func:`resolve_method` turns a name, a Method or a user kernel ``f(plant, s, basis)`` into one;
:func:`choose` is ``auto``: it picks by the model's size, its damping and the measured cost of
each kernel, and says why.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..linear.banded import structure
from ..linear.eigen import ModalBasis
from ..linear.plant import Plant
from ..methods import resolve
from .kernels import (COMPLEX_MODE_RISK, METHODS, FrequencyMethod, classical_damping, complex_mode_risk,
                      custom_method, project_damping)

__all__ = ["METHODS", "FrequencyMethod", "resolve_method", "choose"]


def resolve_method(method: Any, where: str = "frequency_response") -> FrequencyMethod | None:
    """The :class:`FrequencyMethod` for ``method`` (None for ``"auto"``, which :func:`choose` settles).

    Parameters
    ----------
    method : str, FrequencyMethod or callable
        A name of :data:`METHODS`, ``"auto"``, a Method, or a kernel ``f(plant, s, basis)``.
    where : str
        Public function named in messages.

    Returns
    -------
    FrequencyMethod or None

    Raises
    ------
    ModelError
        An unknown name (the valid ones listed, with a did-you-mean).
    """
    if isinstance(method, str) and method == "auto":
        return None
    return resolve(method, METHODS, where=where, custom=custom_method, extra=["auto"])


_K_EIG = 4.6e-10     # [s] per N^3 of the complex-mode eig (N = 2n states)
_K_SUPERPOSE = 4e-10  # [s] per frequency x mode x channel of the superposition


def choose(plant: Plant, nf: int, basis: ModalBasis | None) -> tuple[str, str]:
    """``auto``'s choice of a :data:`METHODS` name, and why; the cost estimates use constants
    measured by benchmarks/bench_frf.py.

    The undamped modes are computed anyway (grid, natural frequencies), so classical damping
    takes the modal superposition. General damping takes the cheaper of the complex modes (one
    ``eig`` of the 2n-state matrix) and the sparse direct solve (one banded or sparse LU per
    frequency).

    Parameters
    ----------
    plant : Plant
        Dense plant.
    nf : int
        Number of frequencies.
    basis : ModalBasis or None
        Its undamped modes; None for a sparse plant (no dense eigen-analysis).

    Returns
    -------
    name, reason : str
        A key of :data:`METHODS` and the reason recorded in the result.
    """
    if basis is None:
        return "sparse", "sparse plant: sparse direct solve per frequency"
    if plant.branches is not None:
        name = "direct" if plant.n + plant.branches.r <= 12 else "sparse"
        return name, f"{plant.branches.note()}: exact solve with them as DOFs"
    if plant.n <= 12:
        return "direct", f"small model ({plant.n} DOF): direct solve is exact and cheap"
    if not np.any(plant.C) and not np.any(plant.H):
        return "sparse", ("undamped: sparse direct solve (a modal sum of an undamped model loses "
                          "digits next to each resonance, where its eigenvalue errors are not damped)")
    projected = project_damping(plant, basis)
    ok, why = classical_damping(plant, basis, projected)
    if ok:
        return "modal", f"{why}: modal superposition is the fastest"
    st = plant.cached("band structure", lambda: structure(plant))
    risk = complex_mode_risk(basis, projected)
    if risk > COMPLEX_MODE_RISK:
        what = ("a mode has no damping, so eig's pole error is not damped at its resonance"
                if np.isinf(risk) else f"eig's pole error relative to the slowest decay rate ~{risk:.1g}")
        return "sparse", f"{why}: sparse direct solve; complex modes could lose accuracy ({what})"
    t_sparse = nf * st.seconds_per_frequency
    n2 = 2 * plant.n
    t_complex = _K_EIG * n2**3 + _K_SUPERPOSE * nf * n2 * len(plant.inputs) * len(plant.outputs)
    how = f"banded LU, half-bandwidth {st.band}" if st.banded else "SuperLU"
    if t_sparse <= t_complex:
        return "sparse", (f"{why}: sparse direct solve per frequency ({how}), estimated {t_sparse:.2g} s "
                          f"against {t_complex:.2g} s for complex modes")
    return "complex_modal", (f"{why}: complex-mode superposition, estimated {t_complex:.2g} s against "
                             f"{t_sparse:.2g} s for the sparse direct solve ({how})")
