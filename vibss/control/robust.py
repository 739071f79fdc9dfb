"""Does the isolator loop hold when the mounts are off? A batched Monte Carlo of the design
parameters' tolerances, plus the worst corners of the tolerance box.

Per variant: closed-loop stability, the smallest closed-loop damping ratio, the smallest
loop-at-a-time balanced disk margin (and the MIMO lower bound) and the peak transmissibility of one
channel. Two methods (:data:`METHODS`):

- ``"lft"`` (rates, rate ratios and tied rates): the rate changes as an internal feedback on the
  nominal loop (:mod:`vibss.control.variants`): frequency responses exact, the lowest ``states``
  closed-loop poles solved per variant in one batched eigen-solve, the poles above held (static
  residual). It checks itself: the worst variant is rebuilt (:func:`vibss.design.parameters.apply`,
  :func:`~vibss.control.plant`, full eigenvalues) and its damping compared.
- ``"rebuild"`` (any parameter, shifts and angles too): every variant's model rebuilt and the loop
  closed again: exact and slow (the stock path).

Samples are drawn as :func:`vibss.design.monte_carlo` draws them (a rate's tolerance relative, a
shift's [m] and an angle's [rad] absolute; uniform on +-tolerance or normal).
"""

from __future__ import annotations

import itertools
import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validate import choice, integer, number
from ..design.montecarlo import DISTRIBUTIONS, SAMPLINGS, _unit_samples
from ..design.parameters import Parameter, apply, current_values, parameters_of
from ..errors import ArgumentError, ControlDesignError, VibssWarning
from ..methods import Check, Claim, Method
from ..linear.eigen.small import state_eigenvalues
from ..model.model import Model
from ..results import Result, TextTable, jsonable, require_pandas
from .variants import HOLD, closed_modes, extend, frequency_metrics, mount_rates, open_loop, reduced_poles

__all__ = ["robustness", "Robustness", "METHODS"]

METHODS: dict[str, Method] = {
    "lft": Method("lft", lambda: None, summary="rate changes as an internal feedback on the nominal loop; "
                  "batched eigenvalues of the lowest closed-loop poles",
                  claim=Claim(1e-3, conditions="the poles above the solved ones stay far from the loop's band")),
    "rebuild": Method("rebuild", lambda: None, exact=True, summary="every variant rebuilt and closed again",
                      claim=Claim(1e-9, exact=True)),
}
"""Methods of :func:`robustness`."""

STABLE_TOL = 1e-9
"""A pole counts as unstable when its real part exceeds this times its magnitude (at least 1 rad/s)."""


@dataclass(frozen=True, eq=False)
class Robustness(Result):
    """Closed-loop robustness over the tolerance set.

    Attributes
    ----------
    model : Model
        The nominal model.
    parameters : tuple of str
        Parameter names (``"<mount>.<kind>"`` or tied :class:`~vibss.design.parameters.Parameter`).
    nominal : (p,) ndarray
        Nominal values [N/m, -, m, rad].
    tolerances : (p,) ndarray
        Tolerances (relative for rates).
    values : (N + C, p) ndarray
        Parameter values of the N samples, then the C corners.
    corner : (N + C,) bool ndarray
        Which rows are corners.
    stable : (N + C,) bool ndarray
        Closed-loop stability.
    damping : (N + C,) ndarray
        Smallest closed-loop damping ratio [-].
    disk_margin : (N + C,) ndarray
        Smallest loop-at-a-time balanced disk margin [-].
    mimo_disk_margin : (N + C,) ndarray
        MIMO balanced disk margin, lower bound [-].
    peak : (N + C,) ndarray
        Peak transmissibility of :attr:`channel` [-] (output unit per input unit).
    nominal_metrics : dict of str to float
        The same four numbers of the nominal loop.
    channel : tuple of str
        (disturbance, output) of the transmissibility.
    frequency_hz : (nf,) ndarray
        Grid of the margins and peaks [Hz].
    confidence : float
        Level of :attr:`p_stable_interval` [-].
    method : str
        ``"lft"`` or ``"rebuild"``.
    check : Check or None
        The self-check (``lft``: the worst variant rebuilt).
    note : str
        What was solved how.
    """

    model: Model
    parameters: tuple[str, ...]
    param_objects: tuple[Parameter, ...]
    nominal: np.ndarray
    tolerances: np.ndarray
    values: np.ndarray
    corner: np.ndarray
    stable: np.ndarray
    damping: np.ndarray
    disk_margin: np.ndarray
    mimo_disk_margin: np.ndarray
    peak: np.ndarray
    nominal_metrics: dict[str, float]
    channel: tuple[str, str]
    frequency_hz: np.ndarray
    confidence: float = 0.95
    method: str = "lft"
    check: Check | None = None
    note: str = ""

    @property
    def n(self) -> int:
        """Number of Monte Carlo samples (corners not counted)."""
        return int((~self.corner).sum())

    @property
    def p_stable(self) -> float:
        """Fraction of the Monte Carlo samples whose loop is stable [-]."""
        return float(self.stable[~self.corner].mean())

    @property
    def p_stable_interval(self) -> tuple[float, float]:
        """Clopper-Pearson interval of P(stable) at :attr:`confidence` [-]."""
        from scipy.stats import beta

        k, n = int(self.stable[~self.corner].sum()), self.n
        a = 1.0 - self.confidence
        lo = 0.0 if k == 0 else float(beta.ppf(a / 2, k, n - k + 1))
        hi = 1.0 if k == n else float(beta.ppf(1 - a / 2, k + 1, n - k))
        return lo, hi

    @property
    def worst_index(self) -> int:
        """Row of the worst variant: the least stable if any is unstable, else the smallest disk margin."""
        if not self.stable.all():
            return int(np.argmin(np.where(self.stable, np.inf, self.damping)))
        return int(np.argmin(self.disk_margin))

    @property
    def worst(self) -> Model:
        """The worst variant as a model (:func:`vibss.design.parameters.apply`)."""
        return apply(self.model, self.param_objects, self.values[self.worst_index])

    @property
    def table(self) -> TextTable:
        """Per metric: nominal, mean, 5 and 95 % of the samples, worst sample, worst corner."""
        rows = []
        for key, label, low in (("damping", "min damping ratio [-]", True), ("disk_margin", "disk margin [-]", True),
                                ("mimo_disk_margin", "MIMO disk margin [-]", True),
                                ("peak", f"peak |T| {self.channel[0]} -> {self.channel[1]}", False)):
            v = getattr(self, key)
            s, c = v[~self.corner], v[self.corner]
            worst = s.min() if low else s.max()
            wc = (c.min() if low else c.max()) if c.size else np.nan
            rows.append([label, f"{self.nominal_metrics[key]:.4g}", f"{s.mean():.4g}", f"{np.percentile(s, 5):.4g}",
                         f"{np.percentile(s, 95):.4g}", f"{worst:.4g}", "-" if not c.size else f"{wc:.4g}"])
        lo, hi = self.p_stable_interval
        return TextTable(["metric", "nominal", "mean", "5 %", "95 %", "worst sample", "worst corner"], rows,
                         title=f"Robustness over {self.n} variants + {int(self.corner.sum())} corners "
                               f"({self.method}): P(stable) = {self.p_stable:.4f} "
                               f"[{lo:.4f}, {hi:.4f}] at {100 * self.confidence:.0f} %")

    def summary(self) -> TextTable:
        """The :attr:`table`."""
        return self.table

    def report(self) -> str:
        """Text: the table, the worst variant's parameter values, the check and the note."""
        w = self.worst_index
        vals = ", ".join(f"{p} = {v:.4g} (nominal {x:.4g})" for p, v, x in
                         zip(self.parameters, self.values[w], self.nominal))
        kind = "corner" if self.corner[w] else "sample"
        parts = [self.table.render(), f"worst variant ({kind} {w}): {vals}"]
        if self.check is not None:
            parts.append(f"self-check: {self.check.text()}")
        parts.append(self.note)
        return "\n\n".join(parts)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready statistics (every variant: :meth:`to_pandas`)."""
        return jsonable({"model": self.model.name, "parameters": list(self.parameters), "nominal": self.nominal,
                         "tolerances": self.tolerances, "n": self.n, "corners": int(self.corner.sum()),
                         "p_stable": self.p_stable, "p_stable_interval": list(self.p_stable_interval),
                         "nominal_metrics": self.nominal_metrics, "channel": list(self.channel),
                         "worst": {"index": self.worst_index, "values": self.values[self.worst_index]},
                         "damping_min": float(self.damping.min()), "disk_margin_min": float(self.disk_margin.min()),
                         "peak_max": float(self.peak.max()), "method": self.method,
                         "check": None if self.check is None else self.check.text(), "note": self.note})

    def to_pandas(self) -> Any:
        """DataFrame: one row per variant (parameter values, corner flag, the four metrics)."""
        pd = require_pandas()
        data: dict[str, Any] = {p: self.values[:, j] for j, p in enumerate(self.parameters)}
        data.update(corner=self.corner, stable=self.stable, damping=self.damping, disk_margin=self.disk_margin,
                    mimo_disk_margin=self.mimo_disk_margin, peak=self.peak)
        return pd.DataFrame(data, index=pd.RangeIndex(len(self.values), name="variant"))

    def plot(self, ax: Any = None, **kwargs: Any) -> Any:
        """Histograms of damping, disk margin and peak transmissibility, the nominal marked
        (:func:`vibss.plotting.robust.plot_robustness`).

        Parameters
        ----------
        ax : sequence of 3 Axes or None
            Draw into existing axes; default: a new figure.
        **kwargs
            Passed to :func:`vibss.plotting.robust.plot_robustness`.
        """
        from ..plotting.robust import plot_robustness

        return plot_robustness(self, ax=ax, **kwargs)


def _samples(model: Model, params: tuple[Parameter, ...], tol: np.ndarray, n: int, sampling: str,
             distribution: str, seed: int | None) -> np.ndarray:
    """(n, p) values as :func:`vibss.design.monte_carlo` draws them."""
    from scipy.stats import norm

    nominal = current_values(model, params)
    u = _unit_samples(n, len(params), sampling, seed)
    x = (2 * u - 1) if distribution == "uniform" else norm.ppf(np.clip(u, 1e-12, 1 - 1e-12))
    rate = np.array([p.is_rate for p in params])
    out = np.where(rate, nominal * (1 + x * tol), x * tol)
    if np.any(out[:, rate] <= 0):
        raise ArgumentError("robustness: tolerances: some sampled rates are not positive; a relative rate "
                            "tolerance must stay below 1 (uniform) or about 1/4 (normal)", argument="tolerances")
    return out


def _corners(params: tuple[Parameter, ...], nominal: np.ndarray, tol: np.ndarray, which: np.ndarray) -> np.ndarray:
    """(2^k, p) corners of the tolerance box in the parameters ``which``, the others nominal."""
    rate = np.array([p.is_rate for p in params])
    out = []
    for signs in itertools.product((-1.0, 1.0), repeat=len(which)):
        x = np.zeros(len(params))
        x[which] = signs
        out.append(np.where(rate, nominal * (1 + x * tol), x * tol))
    return np.array(out).reshape(-1, len(params))


def _channel(plant: Any, ext: Any, channel: Any) -> tuple[tuple[str, str], tuple[int, int]]:
    from .loop import interconnect_indices
    from .plant import vibss_name

    w, z = plant.groups["w"], plant.groups["z"] or plant.groups["y"]
    if channel is None:
        if not w or not z:
            raise ArgumentError("robustness: channel: the plant needs a disturbance and a performance output",
                                argument="channel")
        channel = (w[0], z[0])
    if isinstance(channel, str) or len(channel) != 2:
        raise ArgumentError(f"robustness: channel: expected (disturbance, output), got {channel!r}",
                            argument="channel", received=channel)
    i = interconnect_indices(list(ext.inputs), [channel[0]], "channel (disturbance)")[0]
    o = interconnect_indices(list(ext.outputs), [channel[1]], "channel (output)")[0]
    return (vibss_name(str(channel[0])), vibss_name(str(channel[1]))), (i, o)


def _pole_metrics(poles: np.ndarray, held: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(stable, min damping) per row of poles, the held poles included."""
    allp = np.concatenate([poles, np.broadcast_to(held, (poles.shape[0], held.size))], axis=1)
    mag = np.abs(allp)
    zeta = np.where(mag > 0, -allp.real / np.where(mag > 0, mag, 1.0), 1.0)
    stable = np.all(allp.real <= STABLE_TOL * np.maximum(mag, 1.0), axis=1)
    return stable, zeta.min(axis=1)


def _grid(poles: np.ndarray, frequencies: Any) -> np.ndarray:
    """[rad/s]: the user's frequencies [Hz], or :func:`default_grid` of the solved poles (peaks are
    refined between the points)."""
    if frequencies is not None:
        f = np.asarray(frequencies, dtype=float).ravel()
        if f.size < 3 or not np.all(np.isfinite(f)) or np.any(f <= 0):
            raise ArgumentError("robustness: frequencies: expected at least 3 frequencies > 0 [Hz]",
                                argument="frequencies", received=frequencies)
        return 2 * np.pi * np.unique(f)
    return default_grid(poles, 400)


def default_grid(poles: np.ndarray, n: int) -> np.ndarray:
    """``n`` log-spaced frequencies [rad/s] from a hundredth of the smallest nonzero pole magnitude to
    three times the largest, and 0 (the static response, where an isolator's transmissibility is 1)
    unless a pole sits there."""
    mags = np.abs(poles)
    nonzero = mags > 1e-9 * max(mags.max(initial=1.0), 1.0)
    lo, hi = (mags[nonzero].min() / 100, mags[nonzero].max() * 3) if nonzero.any() else (0.01, 1e4)
    grid = np.geomspace(lo, hi, n)
    return np.r_[0.0, grid] if nonzero.all() else grid


def _axes(model: Model, params: tuple[Parameter, ...]) -> list[tuple[int, int]]:
    """(mount index, local axis) of every rate a parameter sets (a ratio sets its numerator)."""
    from ..design.parameters import _RATE, ratio_axes

    index = {m.name: i for i, m in enumerate(model.mounts)}
    out: list[tuple[int, int]] = []
    for p in params:
        for mount, kind, _ in p.targets:
            j = _RATE.index(kind) if kind in _RATE else ratio_axes(kind)[0]
            if (index[mount], j) not in out:
                out.append((index[mount], j))
    return out


def _evaluate_lft(ext: Any, plant: Any, controller: Any, params: tuple[Parameter, ...], values: np.ndarray,
                  channel: Any, omega: np.ndarray | None, frequencies: Any,
                  states: int, memo: dict[str, Any]) -> tuple[dict[str, np.ndarray], np.ndarray, tuple[str, str]]:
    """Metrics of every row of ``values`` through the internal-feedback form (one batched pass);
    ``memo`` keeps the nominal loop's modes and open-loop responses for the next pass (the corners)."""
    model = plant.model
    r0 = np.array([m.type.stiffness for m in model.mounts], dtype=float)
    rates = mount_rates(model, params, values)
    q = np.array([a[0] for a in ext.axes], dtype=int)
    j = np.array([a[1] for a in ext.axes], dtype=int)
    delta = rates[:, q, j] - r0[q, j]
    if "modes" not in memo:
        memo["modes"] = closed_modes(ext.closed)
    modes = memo["modes"]
    poles, held, solved = reduced_poles(ext.closed, ext.f_in, ext.d_out, delta, states, modes=modes, hold=HOLD)
    memo.setdefault("solved", []).append(solved)
    if omega is None:        # the nominal loop's lowest `states` poles (those solved or held among them)
        omega = _grid(modes[0][:min(states, len(modes[0]))], frequencies)
    names, ch = _channel(plant, ext, channel)
    if "open" not in memo:
        memo["open"] = open_loop(ext, controller, omega)
    fm = frequency_metrics(ext, controller, delta, omega, ch, modes=modes, h=memo["open"])
    stable, zeta = _pole_metrics(poles, held)
    return {"stable": stable, "damping": zeta, **fm}, omega, names


def _evaluate_rebuild(plant: Any, controller: Any, params: tuple[Parameter, ...], values: np.ndarray,
                      channel: Any, omega: np.ndarray | None,
                      frequencies: Any) -> tuple[dict[str, np.ndarray], np.ndarray, tuple[str, str]]:
    """Metrics of every row of ``values``, each variant's model rebuilt and its loop closed again."""
    from .plant import plant as build

    out: dict[str, list[Any]] = {}
    names: tuple[str, str] = ("", "")
    for v in values:
        pv = build(apply(plant.model, params, v), **plant.recipe)
        ext = extend(pv, controller, ())
        poles, held, _ = reduced_poles(ext.closed, ext.f_in, ext.d_out, np.zeros((1, 0)), len(ext.closed[0]))
        if omega is None:
            omega = _grid(poles[0], frequencies)
        names, ch = _channel(plant, ext, channel)
        fm = frequency_metrics(ext, controller, np.zeros((1, 0)), omega, ch)
        stable, zeta = _pole_metrics(poles, held)
        for k, x in {"stable": stable, "damping": zeta, **fm}.items():
            out.setdefault(k, []).append(x[0])
    assert omega is not None
    return {k: np.array(x) for k, x in out.items()}, omega, names


def robustness(plant: Any, controller: Any, tolerances: Mapping[Any, float], n: int = 1000, *, seed: int | None = 0,
               sampling: str = "lhs", distribution: str = "uniform", channel: Any = None,
               frequencies: Any = None, corners: int = 6, states: int = 120, method: str = "auto",
               confidence: float = 0.95) -> Robustness:
    """Monte Carlo and worst corners of a closed loop over the mounts' tolerances.

    Parameters
    ----------
    plant : GeneralizedPlant
        From :func:`vibss.control.plant` (it knows how it was built).
    controller : Controller
        ``u = K y`` (:func:`vibss.control.skyhook`, :func:`~vibss.control.pid` ...).
    tolerances : mapping of str or Parameter to float
        ``{"fl.k3": 0.2}``: relative for rates and ratios [-], [m] for shifts, [rad] for angles.
    n : int
        Monte Carlo samples.
    seed : int or None
        Seed of the sampler.
    sampling : {"lhs", "random", "sobol"}
        As :func:`vibss.design.monte_carlo`.
    distribution : {"uniform", "normal"}
        Uniform on +-tolerance, or normal with the tolerance as standard deviation.
    channel : (str, str) or None
        (disturbance, output) of the peak transmissibility; default the first of each.
    frequencies : array_like or None
        Grid of the margins and peaks [Hz]; default 0 and 400 log points from a hundredth of the lowest
        closed-loop pole to three times the highest solved one.
    corners : int
        Corners: all ``2^p`` when ``p <= corners`` parameters, else the ``2^corners`` corners of
        the most sensitive ones (largest correlation with damping or disk margin), the others nominal.
    states : int
        Closed-loop poles solved per variant by ``lft`` (the rest held; see :mod:`vibss.control.variants`).
    method : {"auto", "lft", "rebuild"}
        ``auto``: ``lft`` when every parameter is a rate or rate ratio, else ``rebuild``.
    confidence : float
        Level of the interval of P(stable) [-].

    Returns
    -------
    Robustness

    Raises
    ------
    ControlDesignError
        The nominal loop is unstable, or ``lft`` asked for with shifts or angles.

    Examples
    --------
    >>> import vibss, vibss.control as vc
    >>> m = vibss.load_example("platform")
    >>> P = vc.plant(m, ["ground.z.vel"], performance=["table.z.vel"])
    >>> r = vc.robustness(P, vc.skyhook(P, 2000.0), {"m1.k3": 0.2}, n=50)   # doctest: +SKIP
    """
    who = "robustness"
    if not hasattr(plant, "recipe") or not hasattr(plant, "model"):
        raise ArgumentError(f"{who}: plant: expected a vibss.control.plant(...) (it knows how it was built)",
                            argument="plant", received=type(plant).__name__)
    if not isinstance(tolerances, Mapping) or not tolerances:
        raise ArgumentError(f"{who}: tolerances: expected a mapping of parameter to tolerance, got {tolerances!r}",
                            argument="tolerances", received=tolerances)
    model = plant.model
    params = parameters_of(model, list(tolerances))
    tol = np.array([number(v, f"tolerances[{k!r}]", who=who, minimum=0.0) for k, v in tolerances.items()])
    n = integer(n, "n", who=who)
    corners = integer(corners, "corners", who=who, minimum=0)
    states = integer(states, "states", who=who)
    sampling = choice(sampling, "sampling", SAMPLINGS, who=who)
    distribution = choice(distribution, "distribution", DISTRIBUTIONS, who=who)
    method = choice(method, "method", ("auto", *METHODS), who=who)
    level = number(confidence, "confidence", who=who, minimum=0.0, strict=True)
    all_rates = all(p.is_rate for p in params)
    if method == "lft" and not all_rates:
        raise ControlDesignError(f"{who}: method 'lft' takes rates and rate ratios only; "
                                 f"{[p.name for p in params if not p.is_rate]} move the mounts: use method='rebuild'")
    use_lft = method == "lft" or (method == "auto" and all_rates)
    nominal = current_values(model, params)
    samples = _samples(model, params, tol, n, sampling, distribution, seed)
    ext = extend(plant, controller, _axes(model, params)) if use_lft else None
    memo: dict[str, Any] = {}

    def run(values: np.ndarray, omega: np.ndarray | None) -> tuple[dict[str, np.ndarray], np.ndarray, tuple[str, str]]:
        if ext is not None:
            return _evaluate_lft(ext, plant, controller, params, values, channel, omega, frequencies, states, memo)
        return _evaluate_rebuild(plant, controller, params, values, channel, omega, frequencies)

    first, omega, names = run(np.vstack([nominal[None], samples]), None)
    if not first["stable"][0]:
        raise ControlDesignError(f"{who}: the nominal closed loop is unstable; close it with vibss.control.close "
                                 "to see the pole")
    which = _sensitive(params, samples, first, corners)
    cvals = _corners(params, nominal, tol, which) if corners else np.zeros((0, len(params)))
    cm = run(cvals, omega)[0] if len(cvals) else {k: v[:0] for k, v in first.items()}
    metric = {k: np.concatenate([first[k][1:], cm[k]]) for k in first}
    values = np.vstack([samples, cvals])
    corner = np.r_[np.zeros(n, bool), np.ones(len(cvals), bool)]
    keys = ("damping", "disk_margin", "mimo_disk_margin", "peak")
    res = Robustness(model=model, parameters=tuple(p.name for p in params), param_objects=params, nominal=nominal,
                     tolerances=tol, values=values, corner=corner, stable=metric["stable"],
                     damping=metric["damping"], disk_margin=metric["disk_margin"],
                     mimo_disk_margin=metric["mimo_disk_margin"], peak=metric["peak"],
                     nominal_metrics={k: float(first[k][0]) for k in keys}, channel=names,
                     frequency_hz=omega / (2 * np.pi), confidence=level, method="lft" if use_lft else "rebuild",
                     note=_note(use_lft, ext, states, omega, max(memo.get("solved", [0]))))
    if use_lft:
        chk = _self_check(plant, controller, params, res)
        res = _with_check(res, chk)
    return res


def _sensitive(params: tuple[Parameter, ...], samples: np.ndarray, first: dict[str, np.ndarray],
               corners: int) -> np.ndarray:
    """Indices of the parameters whose corners are taken (all, or the most correlated with damping or
    disk margin)."""
    p = len(params)
    if p <= corners:
        return np.arange(p)
    xs = (samples - samples.mean(0)) / np.maximum(samples.std(0), 1e-300)
    score = np.zeros(p)
    for key in ("damping", "disk_margin"):
        y = first[key][1:]
        ys = (y - y.mean()) / max(float(y.std()), 1e-300)
        score = np.maximum(score, np.abs(xs.T @ ys) / len(y))
    return np.sort(np.argsort(-score, kind="stable")[:corners])


def _note(lft: bool, ext: Any, states: int, omega: np.ndarray, solved: int = 0) -> str:
    f = omega / (2 * np.pi)
    grid = f"margins and peaks on {f.size} frequencies {f[0]:.3g}-{f[-1]:.3g} Hz (peaks refined by a parabola)"
    if not lft:
        return f"every variant rebuilt and closed again (exact); {grid}"
    n = len(ext.closed[0])
    low = min(states, n)
    return (f"rate changes on {len(ext.axes)} mount axes as an internal feedback (frequency responses exact); "
            f"{solved} of {n} closed-loop poles solved per variant: those of the lowest {low} the rate channels "
            f"see (a first-order bound on the relative shift of the others within {HOLD:.0e})"
            + ("" if solved == n else ", the others held at their nominal values") + f"; {grid}")


def _self_check(plant: Any, controller: Any, params: tuple[Parameter, ...], res: Robustness) -> Check:
    """Rebuild the variant of smallest damping and compare its stability and damping."""
    from .plant import plant as build

    w = int(np.argmin(np.where(res.stable, res.damping, -np.inf)))
    pv = build(apply(res.model, params, res.values[w]), **plant.recipe)
    ext = extend(pv, controller, ())
    poles = state_eigenvalues(ext.closed[0])[None]               # every pole of the rebuilt loop
    stable, zeta = _pole_metrics(poles, poles[0, :0])
    err = abs(float(zeta[0]) - float(res.damping[w])) / max(abs(float(zeta[0])), 1e-3)
    if bool(stable[0]) != bool(res.stable[w]):
        err = np.inf
    limit = METHODS["lft"].claim.tolerance if METHODS["lft"].claim else 1e-3
    chk = Check(err, limit, f"variant {w} rebuilt (damping {float(zeta[0]):.6g} against {float(res.damping[w]):.6g})")
    if not chk.ok:
        warnings.warn(f"robustness: {chk.text()}: raise states= (poles solved per variant) or use "
                      "method='rebuild'", VibssWarning, stacklevel=3)
    return chk


def _with_check(res: Robustness, chk: Check) -> Robustness:
    import dataclasses

    return dataclasses.replace(res, check=chk)
