"""What a model file's ``[design]`` table asks for, in one place: the command line
(``vibss design FILE``) and the report's design section read it through :func:`design_spec` and
run it through :func:`run_design`.

A model without a ``[design]`` table gets the defaults: purity target 0.9, global axes, crank axis
x, no windows; ``--optimize`` then varies every rate of every mount type between ×0.5 and ×2.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from .._deprecated import renamed_attribute, renamed_keywords
from ..errors import ArgumentError
from ..model.model import Model
from .certificate import Certificate, certificate
from .montecarlo import MonteCarlo, monte_carlo
from .optimize import Optimization, optimize
from .parameters import Parameter

__all__ = ["DesignSpec", "design_spec", "type_rate_variables", "run_design", "DesignRun"]


@dataclass(frozen=True)
class DesignSpec:
    """The ``[design]`` table of a model (defaults where it is silent); values in SI.

    Attributes
    ----------
    purity : float
        Purity target of every rigid-body mode [-].
    purity_given : bool
        Whether the file gives the target (then it is also a constraint of the optimisation).
    windows : (2,) sequence, mapping or None
        Frequency windows [Hz].
    frame, axis : str
        Axes of the energy split and crank axis.
    variables : mapping or None
        Design variable to bounds (rates [N/m], shifts [m], angles [rad], ratios [-]).
    options : mapping
        Further keywords of :func:`~vibss.design.optimize` (modes, max_sag, method, starts,
        catalogue).
    tolerances : mapping or None
        Parameter to tolerance (relative for rates and ratios, absolute [m, rad] otherwise).
    samples : int
        Monte Carlo variants.
    sampling : str
        ``"lhs"``, ``"random"`` or ``"sobol"``.
    beta : float or None
        Reliability index: optimise with the windows kept this many deviations inside under the
        tolerances (:mod:`vibss.design.reliability`); None: a deterministic optimisation.
    """

    purity: float = 0.9
    purity_given: bool = False
    windows: Any = None
    frame: str = "global"
    axis: str = "x"
    variables: Mapping[Any, tuple[float, float]] | None = None
    options: Mapping[str, Any] = field(default_factory=dict)
    tolerances: Mapping[Any, float] | None = None
    samples: int = 10_000
    sampling: str = "lhs"
    beta: float | None = None

    @property
    def targets(self) -> dict[str, Any]:
        """Keywords shared by certificate, optimize and monte_carlo."""
        return {"windows": self.windows, "frame": self.frame, "axis": self.axis}


def design_spec(model: Model) -> DesignSpec:
    """The model's ``[design]`` table (``model.settings["design"]``) as a :class:`DesignSpec`."""
    d: Mapping[str, Any] = (model.settings or {}).get("design", {})
    return DesignSpec(
        purity=d.get("purity", 0.9), purity_given="purity" in d, windows=d.get("windows"),
        frame=d.get("frame", "global"), axis=d.get("axis", "x"),
        variables=_variables(d["variables"]) if d.get("variables") else None,
        options={k: d[k] for k in ("modes", "max_sag", "method", "starts", "catalogue") if k in d},
        tolerances=_tolerances(d) if d.get("tolerances") else None,
        samples=d.get("samples", 10_000), sampling=d.get("sampling", "lhs"), beta=d.get("beta"))


def _variables(table: Mapping[str, Any]) -> dict[Any, tuple[float, float]]:
    """``[design.variables]`` entries: ``name = [lo, hi]`` or a tied ``{bounds, targets}``."""
    out: dict[Any, tuple[float, float]] = {}
    for name, v in table.items():
        if isinstance(v, Mapping):
            out[Parameter(name, [tuple(t) for t in v["targets"]])] = (float(v["bounds"][0]), float(v["bounds"][1]))
        else:
            out[name] = (float(v[0]), float(v[1]))
    return out


def _tolerances(d: Mapping[str, Any]) -> dict[Any, float]:
    """``[design.tolerances]``, a tied variable's name standing for its :class:`Parameter`."""
    tied = {p.name: p for p in _variables(d.get("variables", {})) if isinstance(p, Parameter)}
    return {tied.get(k, k): float(v) for k, v in d["tolerances"].items()}


def type_rate_variables(model: Model) -> dict[Any, tuple[float, float]]:
    """Every non-zero rate of every mount type, tied over the type's mounts, between ×0.5 and ×2."""
    variables: dict[Any, tuple[float, float]] = {}
    for name, mtype in model.mount_types.items():
        users = [m.name for m in model.mounts if m.type.name == name]
        for j, k in enumerate(mtype.stiffness):
            if k > 0:
                variables[Parameter(f"{name}.k{j + 1}", [(u, f"k{j + 1}", 1.0) for u in users])] = (0.5 * k, 2.0 * k)
    return variables


@dataclass(frozen=True)
class DesignRun:
    """What :func:`run_design` computed (None where not asked)."""

    certificate: Certificate
    optimization: Optimization | None = None
    tolerance: MonteCarlo | None = None

    optimisation = renamed_attribute("optimisation", "optimization", "DesignRun")


@renamed_keywords(optimise_layout="optimize_layout")
def run_design(model: Model, spec: DesignSpec | None = None, *, optimize_layout: bool | None = None,
               tolerance: float | bool | None = None, damped: bool = False,
               samples: int | None = None) -> DesignRun:
    """Certificate, and the optimisation and tolerance study a ``[design]`` table asks for.

    Parameters
    ----------
    model : Model
        The layout.
    spec : DesignSpec or None
        The targets (None: :func:`design_spec` of the model).
    optimize_layout : bool or None
        Optimize (None: when the spec has variables; ``optimise_layout=``, the old spelling, is
        accepted with a DeprecationWarning for one release).
    tolerance : float, bool or None
        The tolerance study: a relative tolerance of every mount rate; True: the spec's
        tolerances; False: none; None: the spec's tolerances if it has any.
    damped : bool
        Also the complex (damped) modes in the certificate.
    samples : int or None
        Monte Carlo variants (None: the spec's).

    Returns
    -------
    DesignRun
        The tolerance study is of the optimised layout when there is one.
    """
    spec = spec or design_spec(model)
    cert = certificate(model, purity=spec.purity, damped=damped, **spec.targets)
    opt = None
    if optimize_layout or (optimize_layout is None and spec.variables):
        variables = dict(spec.variables) if spec.variables else type_rate_variables(model)
        reliable: dict[str, Any] = {"tolerances": spec.tolerances, "beta": spec.beta, "samples": spec.samples} \
            if spec.beta is not None and spec.tolerances else {}
        opt = optimize(model, variables, purity=spec.purity if spec.purity_given else None,
                       **spec.targets, **spec.options, **reliable)
        model = opt.model
    tol = None
    if isinstance(tolerance, bool) or tolerance is None:
        tolerances = dict(spec.tolerances or {}) if tolerance is not False else {}
        if tolerance is True and not tolerances:
            raise ArgumentError("tolerance=True needs tolerances in the [design] table "
                                "([design.tolerances]); give a relative tolerance instead (e.g. 0.15)",
                                argument="tolerance")
    else:
        tolerances = {f"{m.name}.k{j + 1}": float(tolerance) for m in model.mounts for j in range(3)
                      if m.type.stiffness[j] > 0}
    if tolerances:
        tol = monte_carlo(model, tolerances, n=samples or spec.samples, purity=spec.purity,
                          sampling=spec.sampling, **spec.targets)
    return DesignRun(cert, opt, tol)
