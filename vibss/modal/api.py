"""Undamped and damped modes: :func:`modes` (K phi = w^2 M phi) and :func:`damped_modes` (poles,
damping ratios and complex shapes, paired with the undamped modes; see :mod:`vibss.modal.kernels`).

Undamped modes
--------------

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
error bound of its frequency (:attr:`Modes.error_estimate`, Kato-Temple). That bound is the routes'
a-posteriori check: each route claims every elastic frequency within
:data:`~vibss.modal.methods.FREQUENCY_CLAIM` (1e-6, relative), the note carries the largest bound
(``"checked: error 3.0e-12 <= 1e-06 ..."``), and a bound past the claim is a
:class:`~vibss.errors.VibssWarning` that states it (decided by :func:`vibss.methods.decide`). Repeated frequencies (symmetric layouts, free bodies) are split into
clean directions by :func:`vibss.linear.eigen.directions.align_cluster`.
"""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np

from .._validate import integer
from ..errors import AnalysisError, ArgumentError, ModelError, VibssWarning
from ..linear.eigen.directions import align_cluster, cluster_slices, energy_fractions
from ..linear.eigen.undamped import DENSE_CHECKS, Solver, undamped
from ..model.nonlinearity import refuse_nonlinear
from ..nonlinear.kernels import equilibrium, nonlinear_mounts, tangent_model
from ..linear.plant.assemble import Assembly, assemble
from ..linear.plant.hysteresis import dropped_hysteresis
from ..methods import Check, Claim, Method, callable_name, decide
from ..model.model import Model
from .kernels import projected_c, rigid_influence
from .methods import FREQUENCY_CLAIM, METHODS, auto_note, check_frequencies, damped_route
from .result import DampedModes, Modes

__all__ = ["modes", "damped_modes"]

REPEAT_RTOL = 1e-8
"""Frequencies closer than this (relative) are treated as repeated and aligned by direction."""


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
    tangent_note = ""
    if nonlinear_mounts(a.model):         # stops or curves: the modes of the tangent at the operating point
        a, tangent_note = _tangent(a)
    n = a.n
    if n_modes is not None:
        if not isinstance(n_modes, (int, np.integer)):      # 6.0 modes is a mistake, not a count
            raise ArgumentError(f"modes: n_modes: expected a positive integer or None, got {n_modes!r}",
                                argument="n_modes", received=n_modes, expected="a positive integer")
        n_modes = min(integer(n_modes, "n_modes", who="modes"), n)
    try:
        decision = decide([_route_of(method)], lambda m: _spectrum(a, n_modes, method), where="modes",
                          auto=False, check=_check)
        spec = decision.answer
    except (np.linalg.LinAlgError, ValueError) as exc:
        if isinstance(exc, ModelError):
            raise
        raise AnalysisError(f"the eigen-solver ({method if isinstance(method, str) else 'custom'}) failed: "
                            f"{exc}; check the model for extreme values (masses, inertias, stiffnesses "
                            "or positions many decades apart)") from None
    w2, phi, rigid, name = spec.omega2, spec.phi.copy(), spec.rigid, spec.method
    M = a.M            # sparse on a large model: post-processing needs M times k vectors, not dense M
    omega = np.sqrt(w2)
    # Repeated frequencies: rigid-body modes form one cluster; elastic ones by relative gap.
    groups = cluster_slices(omega, REPEAT_RTOL, 0.0)
    n_rigid = int(np.count_nonzero(rigid))
    if n_rigid > 1:
        groups = [g for g in groups if not rigid[g.start]] + [slice(0, n_rigid)]
    for g in groups:
        aligned = align_cluster(phi[:, g], M)
        # inside a cluster, list the modes in DOF order (x y z rx ry rz), then by body
        key = np.argmax(np.abs(energy_fractions(aligned, M)), axis=1)
        phi[:, g] = aligned[:, np.argsort(key % 6 * a.n + key, kind="stable")]
    # sign: largest component positive
    idx = np.abs(phi).argmax(axis=0)
    phi = phi * np.sign(phi[idx, np.arange(phi.shape[1])])
    energy = energy_fractions(phi, M)
    gamma = phi.T @ (M @ rigid_influence(a.model))
    # the decider's check when the route has the routes' claim; a user's callable is checked here
    bound = decision.check if decision.check is not None else check_frequencies(spec.error, rigid)
    _warn_implausible_geometry(a.model, omega)
    note = "; ".join(x for x in (auto_note(method, name), bound.text()) if x)
    return Modes(model=a.model, dofs=a.dofs, omega=omega, shapes=phi, energy=energy,
                 effective_mass=gamma ** 2, rigid=rigid, method=name,
                 note="; ".join(x for x in (tangent_note, note) if x),
                 error_estimate=spec.error)


IMPLAUSIBLE_HZ = 1000.0
"""[Hz] Rigid bodies on mounts above this are suspect ..."""
LEVER_RATIO = 20.0
"""... when a mount also sits this many radii of gyration of its body away from the body's centre
of gravity (and over :data:`LEVER_M`): the mark of positions given in mm (a 200 mm lever read as
200 m puts the rocking modes at tens of kHz)."""
LEVER_M = 10.0
"""[m] The lever arm below which no position is called implausible."""


def _warn_implausible_geometry(model: Model, omega: np.ndarray) -> None:
    """A :class:`~vibss.errors.VibssWarning` naming the mounts whose lever arms look like lengths in
    mm, when the highest elastic mode is over :data:`IMPLAUSIBLE_HZ`."""
    # rigid modes are exactly 0 and the others >= 0: the largest of all is the largest elastic one
    top = float(np.maximum.reduce(omega, initial=0.0)) / (2 * np.pi)
    if top <= IMPLAUSIBLE_HZ:
        return
    far = []
    for m in model.mounts:
        b = model.body(m.body)
        gyration = float(np.sqrt(np.max(np.linalg.eigvalsh(b.tensor)) / np.max(b.masses)))
        arm = float(np.linalg.norm(model.point(m.body, m.at, m.frame)))
        if arm > LEVER_M and arm > LEVER_RATIO * gyration:
            far.append(f"mount {m.name!r} {arm:.3g} m from body {m.body!r}'s centre of gravity "
                       f"(radius of gyration {gyration:.3g} m)")
    if far:
        warnings.warn(f"modes: natural frequencies up to {top:.3g} Hz, and {'; '.join(far[:3])}"
                      f"{f' and {len(far) - 3} more' if len(far) > 3 else ''}: positions in mm where m "
                      "were meant?", VibssWarning, stacklevel=3)


AUTO = Method("auto", lambda *args: None, claim=Claim(
    FREQUENCY_CLAIM, conditions="each elastic frequency (relative), by the Kato-Temple bound; the eigen path "
    "has already fallen back (dense eigh, refinement, the Jacobi SVD), so a bound above the claim is a warning"))
"""``modes(method="auto")`` as the decider sees it: the eigen path settles the route and its fallbacks
(:func:`vibss.linear.eigen.undamped.undamped`), and the answer is held to the routes' claim."""


def _route_of(method: str | Solver) -> Method:
    """The Method the decider runs for ``method``: a route of :data:`METHODS`, :data:`AUTO`, or a
    user callable (no claim: its bound goes to the note, never a warning)."""
    if callable(method):
        return Method(callable_name(method), method)
    if method == "auto":
        return AUTO
    return METHODS[method] if method in METHODS else Method(str(method), lambda *args: None)   # the eigen path names the valid ones


def _check(route: Method, spec: Any) -> Check | None:
    """The routes' a-posteriori check (:func:`check_frequencies`) held to the route's claim."""
    return None if route.claim is None else check_frequencies(spec.error, spec.rigid, route.claim.tolerance)


def _tangent(a: Assembly) -> tuple[Assembly, str]:
    """The assembly of the tangent model at the operating point under the model's unnamed loads and
    self-weight (as :func:`vibss.static` solves it), and the note that says so."""
    eq = equilibrium(a, a.load_vector(include_gravity=True, case=""), "modes")
    tangent = tangent_model(a.model, eq.d, eq.laws.mounts)
    names = [a.model.mounts[p].name for p in eq.laws.mounts]
    return assemble(tangent), (f"nonlinear mounts {names}: modes of the tangent model at the operating point "
                               f"under self-weight and the unnamed loads ({eq.steps} Newton steps)")


def _spectrum(a: Assembly, n_modes: int | None, method: str | Solver) -> Any:
    """The assembly's undamped spectrum, solved once per ``(n_modes, method)`` (a named method: a
    callable is the caller's and is run each time); the Spectrum is read-only."""
    # a tiny dense model's factor as the dense array its checks read (its CSR is built only if the
    # Jacobi SVD or the refinement runs: the same digits either way)
    factor = a.dense_factor() if not a.sparse and a.n <= DENSE_CHECKS else a.stiffness_factor()
    if callable(method):
        return undamped(a.K, a.M, factor, n_modes, method)
    key = ("spectrum", n_modes, method)
    if key not in a._cache:
        a._cache[key] = undamped(a.K, a.M, factor, n_modes, method)
    return a._cache[key]


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
    refuse_nonlinear(a.model, "damped_modes")
    und = undamped if undamped is not None else modes(a)
    if len(und) != a.n:
        raise ArgumentError(f"damped_modes: undamped: needs all {a.n} undamped modes (modes(model, "
                            f"n_modes=None)), got {len(und)}", argument="undamped", received=len(und),
                            expected=a.n)
    left_out = dropped_hysteresis(a, "damped_modes")
    branches = any(t.has_branches for t in a.model.mount_types.values())
    chat = None if branches else projected_c(a, und)
    route = damped_route(a, chat)
    poles, shapes, paired, said = route.kernel(a, und, chat)
    return DampedModes(poles=poles, shapes=shapes, paired=paired, undamped=und, method=route.summary,
                       note="; ".join(x for x in (said, left_out) if x))
