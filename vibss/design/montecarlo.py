"""Batched Monte Carlo / tolerance studies of a mount layout.

Every variant's stiffness matrix is built at once (arrays over variants; a Python loop over mounts
only), the stacked problems ``K_v phi = lambda M phi`` are turned into standard ones with the
Cholesky factor of the (shared) mass matrix, ``L^-1 K_v L^-T``, and solved together by
:func:`numpy.linalg.eigh` on an ``(n_variants, n, n)`` array: no Python loop per variant. Samples
are random, Latin hypercube or scrambled Sobol (:mod:`scipy.stats.qmc`), mapped to a uniform
distribution on ``+-tolerance`` or a normal one with standard deviation ``tolerance``.

A tolerance is relative for a rate (``0.15``: +-15 %), absolute for a shift [m] or an angle [rad].
Mode ``i`` of a variant is its ``i``-th lowest frequency (modes that cross swap numbers).
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
from scipy.stats import norm, qmc

from ..linear.eigen.small import symmetric_eigen
from .._validate import choice, integer, number
from ..errors import AnalysisError, ArgumentError
from ..linear.plant.assemble import assemble
from ..model.model import DOF_NAMES, Model
from ..results import Result, TextTable, jsonable, require_pandas
from ._common import body_name, frame_axes, frame_rotation, ke_fractions
from .batch import batch_stiffness
from .certificate import in_windows, windows_for
from .parameters import Parameter, current_values, parameters_of, refuse_coupled

__all__ = ["MonteCarlo", "monte_carlo", "batch_modes", "SAMPLINGS", "DISTRIBUTIONS"]

SAMPLINGS = ("random", "lhs", "sobol")
DISTRIBUTIONS = ("uniform", "normal")
CHUNK = 10_000
"""Variants per batch (bounds the memory: about 3 kB per variant and DOF^2)."""


def batch_modes(model: Model, parameters: tuple[Parameter, ...], values: np.ndarray,
                frame: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Frequencies, shapes and KE fractions of many variants at once.

    Parameters
    ----------
    model : Model
        Base model (shifts and angles measured from it).
    parameters : tuple of Parameter
        The parameters.
    values : (N, p) ndarray
        Parameter values of each variant [N/m, m, rad] (as :func:`~vibss.design.parameters.apply`).
    frame : (3, 3) ndarray or None
        Axes of the KE fractions (None: global).

    Returns
    -------
    frequency_hz : (N, n) ndarray
        Natural frequencies [Hz], ascending.
    shapes : (N, n, n) ndarray
        Mass-normalised shapes (columns), largest component positive.
    ke : (N, n, n) ndarray
        KE fractions (modes x coordinates, full M) [-].
    """
    a = assemble(model, sparse=False)
    refuse_coupled(model, "batch_modes")
    n = a.n
    K = batch_stiffness(model, parameters, values, a)
    M = a.dense("M")
    L = np.linalg.cholesky(M)
    Li = np.linalg.inv(L)
    A = Li @ K @ Li.T
    A = 0.5 * (A + A.transpose(0, 2, 1))
    w2, V = symmetric_eigen(A)
    phi = Li.T @ V
    idx = np.argmax(np.abs(phi), axis=1)                                          # (nv, n)
    sign = np.sign(np.take_along_axis(phi, idx[:, None, :], axis=1))
    phi = phi * sign
    ke = ke_fractions(phi, M, frame_rotation(n, np.eye(3) if frame is None else frame))
    return np.sqrt(np.maximum(w2, 0.0)) / (2 * np.pi), phi, ke


@dataclass(frozen=True, eq=False)
class MonteCarlo(Result):
    """A batched tolerance study: every variant's frequencies and decoupling, probabilities of
    meeting the targets, and which parameters matter.

    Attributes
    ----------
    model : Model
        The nominal model.
    parameters : tuple of str
        Parameter names.
    nominal : (p,) ndarray
        Nominal values [N/m, m, rad].
    tolerances : (p,) ndarray
        Tolerances (relative for rates; m, rad otherwise).
    samples : (N, p) ndarray
        Parameter values of every variant.
    frequency_hz : (N, k) ndarray
        Natural frequencies of every variant [Hz].
    purity : (N, k) ndarray
        Largest KE fraction of each mode [-].
    dominant : (N, k) ndarray
        Index of the coordinate holding it.
    target : float
        Purity target [-].
    windows : (k, 2) ndarray
        Frequency window of each mode [Hz] (from the nominal modes' directions).
    sampling : str
        ``random``, ``lhs`` or ``sobol``.
    distribution : str
        ``uniform`` or ``normal``.
    method : str
        ``"batched-eigh"``.
    note : str
        Conventions.
    """

    signal_kind: ClassVar[str] = "mode"

    model: Model
    parameters: tuple[str, ...]
    nominal: np.ndarray
    tolerances: np.ndarray
    samples: np.ndarray
    frequency_hz: np.ndarray
    purity: np.ndarray
    dominant: np.ndarray
    target: float
    windows: np.ndarray
    sampling: str
    distribution: str
    method: str = "batched-eigh"
    note: str = ""

    @property
    def output_labels(self) -> tuple[str, ...]:
        """``f1 ... fk``: ``mc['f2']`` is every variant's second frequency [Hz]."""
        return tuple(f"f{i + 1}" for i in range(self.frequency_hz.shape[1]))

    @property
    def units(self) -> tuple[str, ...]:
        """Hz."""
        return ("Hz",) * self.frequency_hz.shape[1]

    def _item(self, i: int, j: int | None) -> np.ndarray:
        return self.frequency_hz[:, i]

    @property
    def n(self) -> int:
        """Number of variants."""
        return len(self.samples)

    @property
    def pure(self) -> np.ndarray:
        """(N, k) bool: purity target met."""
        return self.purity >= self.target

    @property
    def in_window(self) -> np.ndarray:
        """(N, k) bool: frequency inside its window."""
        return in_windows(self.frequency_hz, self.windows)

    @property
    def probability(self) -> dict[str, float]:
        """Probability of meeting each target: ``pure i``, ``window i`` per mode and ``all``."""
        out: dict[str, float] = {}
        for i in range(self.frequency_hz.shape[1]):
            out[f"pure {i + 1}"] = float(self.pure[:, i].mean())
            out[f"window {i + 1}"] = float(self.in_window[:, i].mean())
        out["all"] = float((self.pure.all(axis=1) & self.in_window.all(axis=1)).mean())
        return out

    def ranking(self, quantity: str = "purity") -> np.ndarray:
        """(p, k) correlation of each parameter with each mode's ``"purity"`` or ``"frequency"``
        across the variants [-] (a sensitivity ranking: larger magnitude matters more)."""
        y = self.purity if quantity == "purity" else self.frequency_hz
        xs = (self.samples - self.samples.mean(0)) / np.maximum(self.samples.std(0), 1e-300)
        ys = (y - y.mean(0)) / np.maximum(y.std(0), 1e-300)
        return xs.T @ ys / len(xs)

    def summary(self) -> TextTable:
        """Per mode: nominal-free statistics (mean, 5 and 95 % of frequency and purity) and the
        probabilities."""
        p = self.probability
        rows = []
        for i in range(self.frequency_hz.shape[1]):
            f, u = self.frequency_hz[:, i], self.purity[:, i]
            rows.append([f"{i + 1}", f"{f.mean():.3f}", f"{np.percentile(f, 5):.3f} ... {np.percentile(f, 95):.3f}",
                         f"{100 * u.mean():.1f}", f"{100 * np.percentile(u, 5):.1f}",
                         f"{p[f'window {i + 1}']:.3f}", f"{p[f'pure {i + 1}']:.3f}"])
        return TextTable(["mode", "mean f [Hz]", "f 5-95 % [Hz]", "mean purity [%]", "purity 5 % [%]",
                      "P(in window)", f"P(purity >= {100 * self.target:.0f} %)"], rows,
                     title=f"Monte Carlo: {self.n} variants ({self.sampling}, {self.distribution}); "
                           f"P(all targets) = {p['all']:.4f}")

    def report(self) -> str:
        """Text: statistics per mode, and the parameters ranked by their effect on purity."""
        r = self.ranking("purity")
        order = np.argsort(-np.abs(r).max(axis=1))
        rows = [[self.parameters[j], f"{self.tolerances[j]:.4g}"] + [f"{x:+.2f}" for x in r[j]] for j in order]
        rank = TextTable(["parameter", "tolerance"] + [f"mode {i + 1}" for i in range(r.shape[1])], rows,
                     title="Correlation of each parameter with each mode's purity (ranked)")
        return "\n\n".join([f"Tolerance study of {self.model.name!r}", self.summary().render(),
                            rank.render(), self.note])

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready statistics and probabilities (not every variant: see :meth:`to_pandas`)."""
        return jsonable({"model": self.model.name, "n": self.n, "parameters": list(self.parameters),
                         "nominal": self.nominal, "tolerances": self.tolerances,
                         "sampling": self.sampling, "distribution": self.distribution,
                         "target": self.target, "windows_hz": self.windows,
                         "probability": self.probability,
                         "frequency_mean_hz": self.frequency_hz.mean(0),
                         "frequency_std_hz": self.frequency_hz.std(0),
                         "purity_mean": self.purity.mean(0), "purity_p05": np.percentile(self.purity, 5, axis=0),
                         "ranking_purity": self.ranking("purity"), "method": self.method, "note": self.note})

    def to_pandas(self) -> Any:
        """DataFrame: one row per variant (parameter values, frequencies, purities)."""
        pd = require_pandas()
        data: dict[str, Any] = {p: self.samples[:, j] for j, p in enumerate(self.parameters)}
        for i in range(self.frequency_hz.shape[1]):
            data[f"f{i + 1}_hz"] = self.frequency_hz[:, i]
        for i in range(self.frequency_hz.shape[1]):
            data[f"purity{i + 1}"] = self.purity[:, i]
        df = pd.DataFrame(data, index=pd.RangeIndex(self.n, name="variant"))
        units = dict(zip(self.parameters, self.units))
        df.attrs["units"] = {c: units.get(c, "Hz" if c.endswith("_hz") else "-") for c in df.columns}
        return df

    def plot(self, ax: Any = None, **kwargs: Any) -> Any:
        """Histograms of frequencies and purities: :func:`vibss.plotting.design.plot_monte_carlo`.

        Parameters
        ----------
        ax : Axes or None
            Draw the frequency histogram into existing axes; default: a new two-panel figure.
        **kwargs
            Passed to :func:`vibss.plotting.design.plot_monte_carlo`.

        Returns
        -------
        matplotlib.figure.Figure
        """
        from ..plotting.design import plot_monte_carlo

        return plot_monte_carlo(self, ax=ax, **kwargs)


def _unit_samples(n: int, d: int, sampling: str, seed: int | None) -> np.ndarray:
    if sampling == "random":
        return np.random.default_rng(seed).random((n, d))
    if sampling == "lhs":
        return qmc.LatinHypercube(d, seed=seed).random(n)
    with warnings.catch_warnings():          # Sobol balance needs a power of 2; any n is allowed
        warnings.simplefilter("ignore", UserWarning)
        return qmc.Sobol(d, scramble=True, seed=seed).random(n)


def monte_carlo(model: Model, tolerances: Mapping[Any, float], n: int = 10_000, *,
                sampling: str = "lhs", distribution: str = "uniform", seed: int | None = 0,
                purity: float = 0.9, windows: Any = None, frame: Any = "global", axis: Any = "x",
                body: str | None = None) -> MonteCarlo:
    """Batched tolerance study: ``n`` variants of the layout, their frequencies and decoupling.

    Parameters
    ----------
    model : Model
        Nominal layout (ground fixed, no rigid-body modes).
    tolerances : mapping of str or Parameter to float
        Parameter (``"<mount>.<kind>"`` or a tied :class:`~vibss.design.parameters.Parameter`) to
        its tolerance: relative for rates [-], [m] for shifts, [rad] for angles.
    n : int
        Number of variants.
    sampling : {"random", "lhs", "sobol"}
        Sampling of the unit cube (:mod:`scipy.stats.qmc` for LHS and scrambled Sobol).
    distribution : {"uniform", "normal"}
        Uniform on ``+-tolerance``, or normal with standard deviation ``tolerance``.
    seed : int or None
        Seed of the sampler.
    purity : float
        Purity target [-].
    windows : (2,) array_like, mapping or None
        Frequency windows [Hz] as :func:`~vibss.design.certificate` (directions from the nominal modes).
    frame : {"global", "tra", "principal"} or (3, 3) array_like
        Axes of the KE fractions.
    axis : {"x", "y", "z"} or (3,) array_like
        Crank axis for ``frame="tra"``.
    body : str or None
        Body whose inertia defines the frame (None: the only or first body).

    Returns
    -------
    MonteCarlo

    Examples
    --------
    >>> import vibss
    >>> mc = monte_carlo(vibss.load_example("powertrain"), {"engine.k3": 0.15, "gearbox.k3": 0.15},
    ...                  n=1000, purity=0.45)
    >>> mc.frequency_hz.shape, round(mc.probability["pure 3"], 3), round(mc.probability["all"], 3)
    ((1000, 6), 0.71, 0.52)
    """
    who = "monte_carlo"
    if not isinstance(tolerances, Mapping) or not tolerances:
        raise ArgumentError(f"{who}: tolerances: expected a mapping of parameter to tolerance, got "
                            f"{tolerances!r}", argument="tolerances", received=tolerances)
    params = parameters_of(model, list(tolerances))
    tol = np.array([number(v, f"tolerances[{k!r}]", who=who, minimum=0.0) for k, v in tolerances.items()])
    n = integer(n, "n", who=who)
    sampling = choice(sampling, "sampling", SAMPLINGS, who=who)
    distribution = choice(distribution, "distribution", DISTRIBUTIONS, who=who)
    target = number(purity, "purity", who=who, minimum=0.0)
    name = body_name(model, body, who) if body is not None or len(model.bodies) == 1 else model.bodies[0].name
    axes = frame_axes(model, name, frame, axis, who)
    nominal = current_values(model, params)
    u = _unit_samples(n, len(params), sampling, seed)
    x = (2 * u - 1) if distribution == "uniform" else norm.ppf(np.clip(u, 1e-12, 1 - 1e-12))
    x = x * tol
    rate = np.array([p.is_rate for p in params])
    samples = np.where(rate, nominal * (1 + x), x)
    if np.any(samples[:, rate] < 0):
        raise ArgumentError(f"{who}: tolerances: some sampled rates are negative; a relative rate "
                            "tolerance must stay below 1 (uniform) or about 1/4 (normal)",
                            argument="tolerances", received=dict(zip([p.name for p in params], tol)))
    freq, pur, dom = [], [], []
    for start in range(0, n, CHUNK):
        f, _, ke = batch_modes(model, params, samples[start:start + CHUNK], axes)
        if np.any(f[:, 0] <= 0):
            raise AnalysisError(f"{who}: some variants have rigid-body modes (a zero rate leaves a "
                                "motion unrestrained)", argument="tolerances")
        freq.append(f)
        pur.append(ke.max(axis=2))
        dom.append(np.argmax(ke, axis=2).astype(np.int16))
    f0, _, ke0 = batch_modes(model, params, nominal[None], axes)
    dirs = [DOF_NAMES[j % 6] for j in np.argmax(ke0[0], axis=1)]
    return MonteCarlo(model=model, parameters=tuple(p.name for p in params), nominal=nominal,
                      tolerances=tol, samples=samples, frequency_hz=np.concatenate(freq),
                      purity=np.concatenate(pur), dominant=np.concatenate(dom), target=target,
                      windows=windows_for(windows, dirs, who), sampling=sampling,
                      distribution=distribution,
                      note="rates: relative tolerance; shifts [m] and angles [rad]: absolute; mode i is "
                           "the i-th lowest frequency of each variant")
