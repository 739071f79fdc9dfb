"""Frequency-response methods: the registry, the resolver and ``auto``'s choice.

:data:`METHODS` (from :mod:`vibss.frequency.kernels`) holds :class:`FrequencyMethod` objects that
carry their facts (exact, needs the modal basis, accepts sparse plants, falls back to ...);
:func:`resolve_method` turns a name, a Method or a user kernel ``f(plant, s, basis)`` into one;
:func:`choose` is ``auto``: it picks by the model's size, its damping and the measured cost of
each kernel, and says why.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..linear.solve.backends import certified_note
from ..linear.solve.banded import seconds_floor, structure
from ..linear.eigen.basis import ModalBasis, classical_damping, damping_rank, projected_damping
from ..linear.plant.plant import Plant
from ..linear.solve.exact import MOUNTS_RATIO, mounts_form_possible
from ..linear.plant.assemble import Assembly
from ..costs import scale
from ..methods import LARGE_DOFS, SMALL_DOFS, Method, Then, resolve
from ..model.model import Model
from . import statespace_kernels
from .grid import FrequencyGrid
from .contracts import cost_complex_modal, cost_sparse, cost_subspace, cost_woodbury
from .contracts import K_BORDER as _K_BORDER, K_REFINE as _K_REFINE, NEAR_GUESS as _NEAR_GUESS
from .kernels import COMPLEX_MODE_RISK, METHODS, REFINE_PREDICT, FrequencyMethod, custom_method, mode_risks

__all__ = ["METHODS", "FrequencyMethod", "resolve_method", "choose", "choose_without_modes", "estimates",
           "candidates", "applies",
           "stays_sparse", "STATESPACE_METHODS", "StateSpaceMethod", "choose_statespace"]


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


def stays_sparse(system: Any, frequencies: Any, chosen: Any) -> bool:
    """Whether :func:`~vibss.frequency.api.frequency_response` builds the plant sparse: a Model above
    :data:`vibss.methods.LARGE_DOFS` DOFs, no branch mounts, explicit frequencies all > 0 and
    ``method`` ``"auto"``, ``"sparse"`` or ``"subspace"`` (no dense n x n matrix and no dense
    eigen-analysis of all the modes; the grid around the modes, resonance marks and the modal
    methods need them, so a grid spec keeps the dense path)."""
    if isinstance(system, Plant) or not isinstance(system, (Model, Assembly)):
        return False
    model = system.model if isinstance(system, Assembly) else system
    if 6 * len(model.bodies) <= LARGE_DOFS or (chosen is not None and not any(
            chosen is METHODS[k] for k in ("sparse", "subspace"))):
        return False
    if any(t.has_branches for t in model.mount_types.values()):
        return False
    if frequencies is None or isinstance(frequencies, (Mapping, FrequencyGrid)):
        return False
    try:
        f = np.atleast_1d(np.asarray(frequencies, dtype=float))
    except (TypeError, ValueError):
        return False
    return bool(f.size) and bool(np.all(np.isfinite(f))) and bool(np.all(f > 0))


def estimates(plant: Plant, nf: int, basis: ModalBasis, refine: int | None) -> dict[str, float]:
    """``auto``'s cost model: estimated seconds of each modal method for a non-classical plant.

    Counts the inputs ``m``, outputs ``p``, frequencies ``nf``, modes ``n`` and the damper rank ``r``
    (:func:`vibss.linear.eigen.basis.damping_rank`, the columns of
    :func:`~vibss.linear.eigen.basis.damping_factors`' ``U``):

    - ``woodbury``: its method's cost (:func:`~vibss.frequency.contracts.cost_woodbury`: ``nf n (p m +
      r (p + m) + r^2 / 2)`` weighted-sum GEMM work plus ``nf (r + 2)^3`` for the bordered LUs);
    - ``complex_modal``: its method's cost (:func:`~vibss.frequency.contracts.cost_complex_modal`: the
      ``eig`` of the 2n states with its screen and the superposition) plus ``refine n^3`` for the slow
      poles its screen is expected to send to the inverse iteration
      (:data:`~vibss.frequency.kernels.REFINE_PREDICT`); left out when ``refine`` is None (an
      undamped mode: a pole on the axis, whose error nothing damps).

    The sparse solve's cost (its band, :func:`vibss.linear.solve.banded.structure`) is added by
    :func:`choose` only when it could win. The scales are those benchmarks/bench_costs.py fits on
    these same formulas.

    Parameters
    ----------
    plant : Plant
    nf : int
        Number of frequencies.
    basis : ModalBasis
        Undamped modes.
    refine : int or None
        Modes expected to need the complex modes' inverse iteration; None leaves complex modes out.

    Returns
    -------
    dict of str to float
        Estimated seconds by method name.
    """
    # the methods' own costs (:func:`~vibss.frequency.contracts.cost_woodbury`,
    # :func:`~vibss.frequency.contracts.cost_complex_modal`), whose scales benchmarks/bench_costs.py
    # fits: a formula of its own here was 4x under for complex modes (no screen in its eig term)
    # and flipped the 600-DOF chain with general damping to complex modes (1.5 s against 0.47 s)
    n = basis.phi.shape[1]
    out = {"woodbury": cost_woodbury(plant, nf, basis).seconds}
    if refine is not None:
        out["complex_modal"] = cost_complex_modal(plant, nf, basis).seconds + \
            scale("frequency.complex_modal") * _K_REFINE * refine * float(n) ** 3
    return out


def choose(plant: Plant, nf: int, basis: ModalBasis | None) -> tuple[str, str]:
    """``auto``'s choice of a :data:`METHODS` name, and why.

    One obvious method is taken without a cost model: the sparse solve for a sparse plant or an
    undamped one, the dense solve for a small model, the modal superposition for classical damping.
    Frequency-dependent mounts are costed (:func:`_choose_branches`): the low-rank update of the
    undamped modes by their branches (``woodbury``, cheap for a few such mounts) against the banded
    exact solve with the branches in its band; where the branches alone make the update dearer than
    the band, without the modes (:func:`choose_without_modes`). General damping is
    costed (:func:`estimates`): the low-rank update of the undamped modes (``woodbury``), the
    complex modes (one ``eig`` of the 2n-state matrix) and, only where it could win, the sparse
    direct solve (one banded or sparse LU per frequency, by the model's band width).

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
        return _choose_sparse(plant, nf)
    if plant.branches is not None:
        return _choose_branches(plant, nf, basis)
    if plant.n <= SMALL_DOFS:
        how = "" if mounts_form_possible(plant) else certified_note(plant, nf)
        return "direct", f"small model ({plant.n} DOF): direct solve is exact and cheap{'; ' + how if how else ''}"
    if not np.any(plant.C) and not np.any(plant.H):
        return "sparse", ("undamped: sparse direct solve (a modal sum of an undamped model loses "
                          "digits next to each resonance, where its eigenvalue errors are not damped)")
    projected = projected_damping(plant, basis)
    ok, why = classical_damping(plant, basis, projected)
    if ok:
        return "modal", f"{why}: modal superposition is the fastest"
    risks = mode_risks(basis, projected)
    risk = float(risks.max()) if risks.size else 0.0
    refine = None if np.isinf(risk) else int(np.count_nonzero(risks > REFINE_PREDICT))
    rank = damping_rank(plant)
    cost = estimates(plant, nf, basis, refine)
    best = min(cost, key=cost.__getitem__)
    how = ""
    if cost[best] > nf * seconds_floor(plant.n):        # the sparse solve could win: cost its band
        st = plant.cached("band structure", lambda: structure(plant))
        cost["sparse"] = nf * st.seconds_per_frequency
        how = f" ({'banded LU, half-bandwidth ' + str(st.band) if st.banded else 'SuperLU'})"
        best = min(cost, key=cost.__getitem__)
    others = ", ".join(f"{k}{how if k == 'sparse' else ''} {v:.2g} s" for k, v in cost.items() if k != best)
    note = ""
    if refine is None:
        note = ("; complex modes left out, they could lose accuracy (a mode has no damping, so eig's pole "
                "error is not damped at its resonance)")
    elif risk > COMPLEX_MODE_RISK:
        note = (f"; complex modes costed with their slow poles refined (eig's pole error relative to the "
                f"slowest decay rate up to ~{risk:.1g}; {refine} inverse iterations expected)")
    what = {"woodbury": f"undamped modes + damper rank {rank} as a low-rank update",
            "complex_modal": "complex-mode superposition",
            "sparse": f"sparse direct solve per frequency{how}"}[best]
    return best, f"{why}: {best} ({what}), estimated {cost[best]:.2g} s against {others or 'nothing else'}{note}"


def choose_without_modes(plant: Plant, nf: int) -> tuple[str, str] | None:
    """``auto``'s choice for frequency-dependent mounts where sizes and structure settle it, or None
    when the modes are needed to choose (:func:`choose` then costs the methods on them).

    A small model takes the dense solve. Otherwise ``woodbury`` costs at least its bordered LUs,
    ``nf (r + 2)^3`` for the ``r`` branches alone (its rank only grows with non-classical dampers,
    and its GEMM work is left out): when that lower bound already exceeds the exact sparse solve
    (``nf`` banded or SuperLU solves, :attr:`~vibss.linear.solve.banded.Structure.seconds_per_frequency`),
    the full cost model of :func:`choose` would pick the sparse solve too, and no modes are needed
    (the branches of every ground mount of a chain: ``r = n``). No trial solve.

    Parameters
    ----------
    plant : Plant
        Dense plant with branches.
    nf : int
        Number of frequencies.

    Returns
    -------
    (name, reason) or None
    """
    br = plant.branches
    if br is None:
        return None
    note = br.note()
    if plant.n + br.r <= SMALL_DOFS:
        return "direct", f"{note}: small model, exact solve with them as DOFs"
    st = plant.cached("band structure", lambda: structure(plant))
    band = nf * st.seconds_per_frequency
    border = _K_BORDER * nf * (br.r + _NEAR_GUESS) ** 3
    if border <= band:
        return None
    how = f"banded LU, half-bandwidth {st.band}" if st.banded else "SuperLU"
    return "sparse", (f"{note}: sparse (sparse exact solve with the branches in the dynamic stiffness, {how}), "
                      f"estimated {band:.2g} s; {br.r} branches on {plant.n} DOFs: woodbury's bordered LUs "
                      f"alone would take {border:.2g} s (chosen from sizes and structure, no modes computed)")


def _choose_branches(plant: Plant, nf: int, basis: ModalBasis) -> tuple[str, str]:
    """``auto`` for frequency-dependent mounts: the exact sparse solve with the branches in the
    dynamic stiffness, or the undamped modes with the branches (and non-classical dampers) as a
    low-rank update (``woodbury``), by their estimated costs (:func:`choose_without_modes` first)."""
    br = plant.branches
    assert br is not None
    quick = choose_without_modes(plant, nf)
    if quick is not None:
        return quick
    note = br.note()
    projected = projected_damping(plant, basis)
    classical, _ = classical_damping(plant, basis, projected)
    rank = br.r + (0 if classical else damping_rank(plant))
    cost = {"woodbury": estimates(plant, nf, basis, None)["woodbury"]}      # its rank: woodbury_rank
    st = plant.cached("band structure", lambda: structure(plant))
    cost["sparse"] = nf * st.seconds_per_frequency
    best = min(cost, key=cost.__getitem__)
    what = {"woodbury": f"undamped modes + {br.r} branches{'' if classical else ' and the dampers'} as a "
                        f"rank-{rank} update",
            "sparse": "sparse exact solve with the branches in the dynamic stiffness "
                      f"({'banded LU, half-bandwidth ' + str(st.band) if st.banded else 'SuperLU'})"}
    other = next(k for k in cost if k != best)
    return best, (f"{note}: {best} ({what[best]}), estimated {cost[best]:.2g} s against "
                  f"{other} {cost[other]:.2g} s")




def _nonzero(a: Any) -> bool:
    count = getattr(a, "count_nonzero", None)
    return bool(count()) if count is not None and not isinstance(a, np.ndarray) else bool(np.any(np.asarray(a)))


def _choose_sparse(plant: Plant, nf: int) -> tuple[str, str]:
    """``auto`` for a sparse plant: the exact solve per frequency or the channel subspace
    (:mod:`vibss.linear.project.subspace`), by their estimated costs.

    Not the subspace where the exact solve is in the mounts' forces (stiffness ratio past
    :data:`~vibss.linear.solve.exact.MOUNTS_RATIO`): the subspace projects the assembled ``K``,
    whose round-off is why that form was taken, and its checks fail on the soft modes; the exact
    solve then answers after it (6,000-DOF soft tower, ``benchmarks/bench_tower.py``: checked error
    1.6e-4 at 0.2 mHz over 0.1 mHz-10 Hz, 5.8e-4 over 0.01-10 Hz; over 1-10 Hz it converged with
    437 vectors and 79 exact solves, in 2x the exact solve's time).

    The exact path costs ``nf`` solves (:attr:`~vibss.linear.solve.banded.Structure.seconds_per_frequency`);
    the subspace about ``3 N_SHIFTS`` of them (a factorisation per shift, about as many exact checks
    and a few added frequencies) plus its basis work, ``n r^2`` with ``r = N_SHIFTS MOMENTS`` times
    the input and output vectors (the outputs' only when they are few), and with dampers or loss
    factors ``nf r^3`` for the small plant's dense solves: cheaper with many frequencies and few
    channels. Both from :func:`~vibss.frequency.contracts.cost_sparse` and
    :func:`~vibss.frequency.contracts.cost_subspace` (the solve in the mounts' forces counted where
    it is taken: the assembled SuperLU's estimate and the refinement's fixed cost, fitted as ``solve.mounts``).
    """
    st = plant.cached("band structure", lambda: structure(plant))
    how = f"banded LU, half-bandwidth {st.band}" if st.banded else "SuperLU"
    exact = cost_sparse(plant, nf).seconds           # the contracts' estimates: the mounts' form counted
    if plant.branches is not None:
        return "sparse", f"sparse plant: exact sparse solve per frequency ({how}; frequency-dependent mounts)"
    mf = plant.mounts
    if mf is not None and mf.matches(plant) and mf.stiffness_ratio > MOUNTS_RATIO:
        return "sparse", (f"sparse plant whose mounts span a stiffness ratio of {mf.stiffness_ratio:.2g} (past "
                          f"{MOUNTS_RATIO:g}): exact solve per frequency in the mounts' forces ({how} of the "
                          f"assembled matrix, refined), estimated {exact:.2g} s; a channel subspace projects "
                          "the assembled K, whose round-off the soft modes do not survive (its checks fail)")
    sub = cost_subspace(plant, nf).seconds
    if sub < exact:
        return "subspace", (f"sparse plant, {nf} frequencies on {len(plant.outputs)} x {len(plant.inputs)} "
                            f"channels: channel subspace estimated {sub:.2g} s against {exact:.2g} s for the "
                            f"exact solve per frequency ({how})")
    return "sparse", (f"sparse plant: exact sparse solve per frequency ({how}), estimated {exact:.2g} s "
                      f"against {sub:.2g} s for a channel subspace")


def applies(method: FrequencyMethod, plant: Plant, basis: ModalBasis | None) -> bool:
    """Whether ``method`` can answer for ``plant`` at all (named in a refusal's list of methods
    that work): a sparse plant takes the sparse-capable ones, branches the ones with internal
    states, ``modal`` classical damping, ``statespace`` viscous damping only."""
    if basis is None and method.needs_basis:
        return False
    if plant.branches is not None and not method.internal_states:
        return False
    if method is METHODS["modal"]:
        assert basis is not None
        return classical_damping(plant, basis, projected_damping(plant, basis))[0]
    if method is METHODS["statespace"]:
        return not _nonzero(plant.H) and not _nonzero(plant.Hz)
    return True


def candidates(plant: Plant, chosen: FrequencyMethod, nf: int,
               basis: ModalBasis | None) -> Sequence[FrequencyMethod]:
    """``auto``'s order: its pick (:func:`choose`), then, when the pick is not exact, the exact
    fallback: the method's own (``complex_modal``: ``sparse``), else the cheaper exact solve by
    the cost model (``sparse`` on a sparse plant), ranked only if the pick does not answer
    (:class:`~vibss.methods.Then`)."""
    if chosen.exact:
        return [chosen]
    if chosen.fallback is not None:
        return [chosen, METHODS[chosen.fallback]]

    def cheapest_exact() -> list[FrequencyMethod]:
        exact = [m for m in METHODS.values() if m.exact and m.cost is not None and applies(m, plant, basis)
                 and (m.sparse_ok or basis is not None)]
        exact.sort(key=lambda m: m.cost(plant, nf, basis).seconds if m.cost is not None else 0.0)
        return exact[:1]
    return Then(chosen, cheapest_exact)


@dataclass(frozen=True)
class StateSpaceMethod(Method):
    """A way to evaluate a python-control state space's ``C (sI - A)^-1 B`` at many frequencies
    (:mod:`vibss.frequency.statespace_kernels`, kernel ``f(A, B, C) -> h or None``).

    Attributes
    ----------
    min_states : int
        ``auto`` tries it on systems of more states than this only.
    """

    min_states: int = 0


STATESPACE_METHODS: dict[str, StateSpaceMethod] = {
    "modal": StateSpaceMethod(
        "modal", statespace_kernels.modal, fallback="balanced", min_states=150,
        summary="diagonalised once (O(n p m) per frequency) where the eigenvectors are well conditioned"),
    "balanced": StateSpaceMethod(
        "balanced", statespace_kernels.balanced, exact=True,
        summary="balanced, then solved directly at every frequency (batched LU)"),
}
"""The state-space evaluators, in ``auto``'s order: ``modal`` above 150 states (the diagonalisation
once, O(n^3), against an O(n^3) LU at every frequency), falling back to ``balanced`` where it
refuses (ill-conditioned eigenvectors) and below."""


def choose_statespace(A: np.ndarray, B: np.ndarray,
                      C: np.ndarray) -> tuple[StateSpaceMethod, Callable[[np.ndarray], np.ndarray]]:
    """``auto``'s evaluator for the state space ``(A, B, C)`` and its response ``h(s)``: the first
    of :data:`STATESPACE_METHODS` whose ``min_states`` the system exceeds and that accepts it."""
    n = A.shape[0]
    for method in STATESPACE_METHODS.values():
        if n > method.min_states:
            h = method.kernel(A, B, C)
            if h is not None:
                return method, h
    last = STATESPACE_METHODS["balanced"]
    return last, last.kernel(A, B, C)
