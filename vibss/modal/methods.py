"""The modal analyses' automatic choices as registries of :class:`~vibss.methods.Method` objects.

:data:`METHODS` lists the eigen routes of :func:`vibss.modes` (``method=``): the one eigen path,
:func:`vibss.linear.eigen.undamped.undamped`, runs them and settles ``"auto"`` (Jacobi SVD of the
stiffness factor up to :data:`~vibss.linear.eigen.undamped.JACOBI_MAX` DOFs, shift-invert for a few
modes of a large sparse model, dense ``eigh`` otherwise); each entry carries the reason ``auto``
records when it picks it. :data:`DAMPED_ROUTES` lists the routes of :func:`vibss.damped_modes`, and
:func:`damped_route` is its choice among them (by the mounts and the projected damping).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..linear.eigen.undamped import FREQ_RTOL, JACOBI_MAX, undamped

from ..linear.eigen.basis import damping_coupling
from ..linear.plant.assemble import Assembly
from ..methods import Check, Claim, Method
from .kernels import poles_classical, poles_general, poles_undamped, poles_with_branches

__all__ = ["EigenRoute", "METHODS", "auto_note", "DampedRoute", "DAMPED_ROUTES", "damped_route",
           "FREQUENCY_CLAIM", "check_frequencies"]

FREQUENCY_CLAIM = 1e-6
"""What every eigen route promises [-]: each elastic natural frequency within this relative error,
held to by its a-posteriori Kato-Temple bound (:func:`check_frequencies`). The measured errors are
far smaller (the 60-digit campaign, tests/robustness/test_contract_campaign.py: 9.6e-11 at most,
2.2e-14 by Jacobi), but the claim is what the *check* can certify: the bound stays under 1e-8 on
ordinary models, reaches 2.4e-8 on the graded chain (masses over 7 decades), 1e-6-5e-5 on the
softest modes beside penalty links 1e9-1e10 times their mounts and 1e-3 beside 1e16 N/m links (the
round-off of ``G phi`` beside the links; the error itself stays ~1e-14). 1e-6 keeps the word for
those, where the bound cannot certify the answer: a :class:`~vibss.errors.VibssWarning` with the bound."""


@dataclass(frozen=True)
class EigenRoute(Method):
    """An eigen route of :func:`vibss.modes`: its kernel is ``f(K, M, factor, n_modes) -> Spectrum``.

    Attributes
    ----------
    auto_reason : str
        What ``auto``'s note says when it picks this route.
    needs_factor : bool
        Works on the stiffness factor (``K = G^T G``); without one the eigen path runs ``dense``.
    sparse_ok : bool
        Takes a sparse model without forming dense n x n matrices (the lowest ``n_modes`` only).
    """

    auto_reason: str = ""
    needs_factor: bool = False
    sparse_ok: bool = False


def _route(name: str) -> Callable[..., Any]:
    def kernel(K: Any, M: Any, factor: Any = None, n_modes: int | None = None) -> Any:
        return undamped(K, M, factor, n_modes, name)
    kernel.__name__ = name
    return kernel


METHODS: dict[str, EigenRoute] = {
    "jacobi": EigenRoute(
        "jacobi", _route("jacobi"), exact=True, needs_factor=True,
        claim=Claim(FREQUENCY_CLAIM, exact=True, conditions="each elastic frequency (relative), by the "
                    "Kato-Temple bound on the stiffness factor; without a factor it runs dense"),
        summary="Jacobi SVD of the factored problem: every frequency to high relative accuracy",
        auto_reason=f"auto: Jacobi SVD of the stiffness factor (high relative accuracy; up to {JACOBI_MAX} DOFs)"),
    "dense": EigenRoute(
        "dense", _route("dense"),
        claim=Claim(FREQUENCY_CLAIM, conditions="each elastic frequency (relative), by the Kato-Temple bound; "
                    "modes whose bound exceeds it refined, the Jacobi SVD when refinement cannot certify them"),
        summary="eigh on dense matrices, refined where the a-posteriori estimate says so",
        auto_reason=f"auto: dense eigh, modes whose error estimate exceeds {FREQ_RTOL:g} refined on the stiffness factor"),
    "shift-invert": EigenRoute(
        "shift-invert", _route("shift-invert"), sparse_ok=True,
        claim=Claim(FREQUENCY_CLAIM, conditions="each of the lowest n_modes elastic frequencies (relative), "
                    "by the Kato-Temple bound"),
        summary="sparse shift-invert about a small negative shift: the lowest n_modes of a large sparse model",
        auto_reason="auto: sparse model and fewer than a tenth of the modes asked for: shift-invert"),
}
"""The eigen routes of :func:`vibss.modes`, by name (``"auto"`` is settled by the eigen path)."""


def check_frequencies(error: np.ndarray, rigid: np.ndarray, limit: float = FREQUENCY_CLAIM) -> Check:
    """The eigen routes' a-posteriori check: the largest Kato-Temple bound of an elastic frequency.

    Parameters
    ----------
    error : (k,) ndarray
        Relative error bound of each frequency [-] (:attr:`vibss.linear.eigen.undamped.Spectrum.error`;
        NaN for rigid modes).
    rigid : (k,) bool ndarray
        Rigid-body modes (their 0 is exact and not checked).
    limit : float
        The claim's tolerance [-].

    Returns
    -------
    Check

    Examples
    --------
    >>> check_frequencies(np.array([np.nan, 2e-15, 3e-12]), np.array([True, False, False])).text()
    'checked: error 3.0e-12 <= 1e-06 at the Kato-Temple bound of 2 elastic frequencies'
    """
    elastic = np.asarray(error, float)[~np.asarray(rigid, bool)]
    worst = float(np.maximum.reduce(elastic, initial=0.0))     # NaN propagates: a NaN bound is inf
    worst = worst if worst == worst else float("inf")
    return Check(worst, limit, f"the Kato-Temple bound of {elastic.size} elastic frequencies")


def auto_note(method: Any, name: str) -> str:
    """Why ``auto`` chose the solver named ``name`` by the eigen path ("" for a solver chosen by the caller)."""
    if not isinstance(method, str) or method != "auto":
        return ""
    for key in ("shift-invert", "jacobi"):
        if name.startswith(key):
            return METHODS[key].auto_reason
    return METHODS["dense"].auto_reason


@dataclass(frozen=True)
class DampedRoute(Method):
    """A route of :func:`vibss.damped_modes`: its kernel is ``f(a, und, chat) -> (poles, shapes,
    paired, note)`` (:mod:`vibss.modal.kernels`); ``summary`` is what the result reports as ``method``."""


DAMPED_ROUTES: dict[str, DampedRoute] = {
    "undamped": DampedRoute("undamped", poles_undamped, exact=True, summary="undamped (poles i w)"),
    "classical": DampedRoute("classical", poles_classical, exact=True,
                             summary="classical damping: closed form per undamped mode"),
    "general": DampedRoute("general", poles_general,
                           summary="general damping: eig of the scaled modal state matrix"),
    "branches": DampedRoute("branches", poles_with_branches, internal_states=True,
                            summary="frequency-dependent mounts: eig of the state matrix with their internal states"),
}
"""The routes of :func:`vibss.damped_modes`, by name."""


def damped_route(a: Assembly, chat: np.ndarray | None) -> DampedRoute:
    """The route for assembly ``a`` with projected damping ``chat`` (None: not computed, which only
    the route with frequency-dependent mounts allows): their branches first, then no damping,
    classical damping (``chat`` diagonal), general damping."""
    if any(t.has_branches for t in a.model.mount_types.values()):
        return DAMPED_ROUTES["branches"]
    assert chat is not None
    if not np.any(chat):
        return DAMPED_ROUTES["undamped"]
    if not bool(np.any(damping_coupling(chat) > 0)):
        return DAMPED_ROUTES["classical"]
    return DAMPED_ROUTES["general"]
