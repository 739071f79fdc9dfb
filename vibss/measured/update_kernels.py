"""The residuals of model updating and their exact derivatives (:func:`vibss.update`).

**Frequency responses.** The model's response at the measured frequencies is the exact solve
(:mod:`vibss.linear.solve.exact`): ``A(s) X = R(s)``, ``Y = O(s) X + P(s) Z + Pf`` with
``A = K + iH + sC + s^2 M``. Its derivative by a parameter ``p`` is

    dX = A^-1 (dR - dA X),      dY = dO X + dP Z + dPf + O dX

(one more solve with the same ``A``, one right-hand side per parameter and input). The derivatives
of the plant's fields (``dK, dH, dKz, dHz, dOq`` ... of mount force outputs) are taken as the
difference of two assembled plants, at ``p`` and ``p + h``, divided by ``h``: every field is affine
in a rate (``K = sum B^T T diag(k) T^T B``, ``H = eta K`` per mount, the damping and mass do not
move) and in a rate ratio, so that difference is the derivative itself, with rounding only (no
truncation error, whatever ``h``; ``h = p``). Positions and angles enter the plant nonlinearly:
FRF updating refuses them (measured modes take them, by the exact design sensitivities).

The derivative plants of rates are constant (``K`` is linear in a rate), so they are built once per
problem; only a rate ratio whose denominator rate is itself a parameter (and that rate) move with
the values and are built again at each evaluation. An evaluation then costs one plant and two
solves (the second with one right-hand side per parameter and input), where a finite-difference
Jacobian costs one plant and one solve per parameter.

The residual per channel and frequency is the complex relative error ``Y_model / Y_measured - 1``
(real and imaginary parts), so channels and frequencies spanning decades weigh alike; its
derivative is ``dY / Y_measured``. The log ratio ``log(Y_model / Y_measured)`` (log-magnitude and
phase) was tried first: its phase wraps at +-pi where a model resonance sits on the wrong side of
the measured one, and from seeded starts 0.7 to 1.4 times the true rates it stopped in a false
minimum two times in three, where the relative error reached the true rates every time
(benchmarks/bench_update.py). The relative error has a plateau of its own (-1 where the model's
response is far below the measured one, a model much too stiff): :func:`vibss.update` first scales
the rates by the common factor that minimises the log-magnitude error (:meth:`FrfProblem.log_misfit`),
which has neither.

**Modes.** The design sensitivities (:func:`vibss.design.sensitivity.evaluate`: ``d f``, ``d phi``
by the modal sum, exact) give the model's frequencies and its shapes at the measured outputs
``c = C phi``. Each measured mode is paired with a model mode by the MAC at those outputs (an
optimal one-to-one assignment); the residuals are the relative frequency error ``(f - f_m) / f_m``
and the shape error ``(a c - m) / |m|`` with the best scale ``a = m.c / c.c`` (sign and scale of a
measured shape are arbitrary), whose derivative is exact by the product rule.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np
from scipy.optimize import linear_sum_assignment

from ..design.parameters import Parameter, apply
from ..design.sensitivity import evaluate
from ..errors import AnalysisError
from ..linear.plant.build import build_plant
from ..linear.plant.plant import Plant
from ..linear.solve.exact import forcing, observe, states, zfactor
from ..modal.tracking import mac

__all__ = ["FrfProblem", "ModesProblem", "plant_derivative", "frf_and_derivative", "DIFFERENCED"]

DIFFERENCED = ("K", "C", "M", "H", "F", "Kz", "Cz", "Mz", "Hz", "Oq", "Ov", "Oa", "Oh",
               "Pz", "Pv", "Pa", "Pf", "Ph")
"""The plant fields a rate moves (differenced between two assembled plants)."""


def plant_derivative(p1: Plant, p0: Plant, h: float) -> Plant:
    """The plant of the derivatives ``(p1 - p0) / h`` of every field in :data:`DIFFERENCED`, exact
    when the fields are affine in the parameter (rates, rate ratios). No mount form, stiffness
    factor or branches (the frequency-dependent mounts' branches do not move with a rate)."""
    change: dict[str, Any] = {"mounts": None, "Kf": None, "branches": None}
    for key in DIFFERENCED:
        a, b = getattr(p1, key), getattr(p0, key)
        if a is None and b is None:
            continue
        a = np.zeros_like(np.asarray(b)) if a is None else np.asarray(a)
        b = np.zeros_like(a) if b is None else np.asarray(b)
        change[key] = (a - b) / h
    return dataclasses.replace(p0, **change)


def _outputs_of(plant: Plant, s: np.ndarray, x: np.ndarray) -> np.ndarray:
    """``O(s) x`` (nf, p, m) of DOF solutions ``x`` (nf, n, m): :func:`observe` without the inputs'
    direct terms (its ``Pf`` taken back off)."""
    zero = np.zeros((s.size, x.shape[2]), dtype=complex)
    return observe(plant, s, x, zero) - plant.Pf[None]


def frf_and_derivative(plant: Plant, derivatives: Sequence[Plant], s: np.ndarray,
                       jacobian: bool = True) -> tuple[np.ndarray, np.ndarray | None]:
    """Exact response ``Y`` (nf, p, m) at Laplace values ``s`` and its derivatives (k, nf, p, m)
    by the parameters whose plant derivatives are ``derivatives`` (None when not ``jacobian``)."""
    zf = zfactor(s, plant.order)
    x, bad = states(plant, s, rhs=forcing(plant, s, zf))
    if bad.any():
        raise AnalysisError(f"update: the model is exactly singular at {abs(s[bad][0]) / (2 * np.pi):g} Hz (an "
                            "undamped resonance on a measured frequency); add damping to the model",
                            argument="measured")
    y = observe(plant, s, x, zf)
    if not jacobian:
        return y, None
    m = x.shape[2]
    sc = s[:, None, None]
    rhs = []
    for d in derivatives:
        da_x = (d.K + 1j * d.H) @ x + sc * (d.C @ x) + sc**2 * (d.M @ x)
        rhs.append(forcing(d, s, zf) - da_x)
    dx, _ = states(plant, s, rhs=np.concatenate(rhs, axis=2))
    dy = np.stack([observe(d, s, x, zf) + _outputs_of(plant, s, dx[:, :, i * m:(i + 1) * m])
                   for i, d in enumerate(derivatives)])
    return y, dy


@dataclass(frozen=True, eq=False)
class FrfProblem:
    """Residuals of a measured frequency response against the model at parameter values.

    Attributes
    ----------
    model : Model
        The base model (the values are applied to it).
    parameters : tuple of Parameter
        Rates and rate ratios.
    inputs, outputs : tuple of str
        The measured channels' signals.
    s : (nf,) complex ndarray
        ``2 pi i f`` at the measured frequencies [rad/s].
    power : int
        0 receptance, 1 mobility, 2 accelerance (the response times ``s^power``).
    data : (p, m, nf) complex ndarray
        The measured response.
    weights : (p, m) ndarray
        Weight of each channel's residuals [-] (0: left out).
    """

    model: Any
    parameters: tuple[Parameter, ...]
    inputs: tuple[str, ...]
    outputs: tuple[str, ...]
    s: np.ndarray
    power: int
    data: np.ndarray
    weights: np.ndarray
    _constant: dict[int, Plant] = dataclasses.field(default_factory=dict, repr=False)

    @cached_property
    def moving(self) -> frozenset[int]:
        """Parameters whose derivative plant moves with the values: a rate ratio whose denominator
        rate is a parameter too, and that rate (the numerator rate is their product)."""
        rated = {(m, k): i for i, p in enumerate(self.parameters) for m, k, _ in p.targets if k in ("k1", "k2", "k3")}
        out: set[int] = set()
        for i, p in enumerate(self.parameters):
            for mount, kind, _ in p.targets:
                if "/" in kind and (mount, kind.split("/")[1]) in rated:
                    out |= {i, rated[(mount, kind.split("/")[1])]}
        return frozenset(out)

    def derivative(self, values: np.ndarray, i: int, p0: Plant) -> Plant:
        """The derivative plant of parameter ``i`` at ``values`` (plant ``p0`` there)."""
        if i in self._constant:
            return self._constant[i]
        h = values[i] if values[i] != 0 else 1.0
        v = values.copy()
        v[i] += h
        d = plant_derivative(self.plant(v), p0, h)
        if i not in self.moving:
            self._constant[i] = d
        return d

    def plant(self, values: np.ndarray) -> Plant:
        """The plant of the model at ``values``."""
        return build_plant(apply(self.model, self.parameters, values), list(self.inputs), list(self.outputs))

    def response(self, values: np.ndarray, jacobian: bool = True) -> tuple[np.ndarray, np.ndarray | None]:
        """(p, m, nf) response and its (k, p, m, nf) derivatives [per unit of each parameter]."""
        p0 = self.plant(values)
        ders = [self.derivative(values, i, p0) for i in range(values.size)] if jacobian else []
        y, dy = frf_and_derivative(p0, ders, self.s, jacobian)
        scale = self.s[:, None, None] ** self.power
        y = (y * scale).transpose(1, 2, 0)
        return y, None if dy is None else (dy * scale[None]).transpose(0, 2, 3, 1)

    def log_misfit(self, values: np.ndarray) -> float:
        """Sum of the squared weighted log-magnitude errors ``log |Y_model / Y_measured|`` [-]: no
        phase to wrap and no plateau where the model's response is far below the measured one, for
        the scan of a common scale of the rates (:func:`vibss.measured.update.update`)."""
        y, _ = self.response(values, False)
        keep = self.weights > 0
        with np.errstate(divide="ignore"):
            z = self.weights[keep][:, None] * np.log(np.abs(y[keep] / self.data[keep]))
        return float(np.sum(z**2)) if np.all(np.isfinite(z)) else float("inf")

    def residual(self, values: np.ndarray, jacobian: bool = True) -> tuple[np.ndarray, np.ndarray | None]:
        """Real residuals (real and imaginary parts of the relative errors, weighted) and their
        (N, k) derivatives."""
        y, dy = self.response(values, jacobian)
        keep = self.weights > 0
        w = self.weights[keep][:, None]
        z = w * (y[keep] / self.data[keep] - 1)
        bad = ~np.isfinite(z)
        if bad.any():
            i, j = np.argwhere(keep)[np.argwhere(bad)[0][0]]
            raise AnalysisError(f"update: the model's response {self.outputs[i]}/{self.inputs[j]} is not finite at "
                                "a measured frequency", argument="measured",
                                received=f"{self.outputs[i]}/{self.inputs[j]}")
        r = np.concatenate([z.real.ravel(), z.imag.ravel()])
        if dy is None:
            return r, None
        dz = w[None] * dy[:, keep] / self.data[keep][None]
        jac = np.concatenate([dz.real.reshape(len(dz), -1), dz.imag.reshape(len(dz), -1)], axis=1).T
        return r, jac


@dataclass(frozen=True, eq=False)
class ModesProblem:
    """Residuals of measured modes against the model at parameter values.

    Attributes
    ----------
    model : Model
        The base model.
    parameters : tuple of Parameter
        Rates, ratios, positions, angles.
    rows : (q, n) ndarray
        The measured outputs per model DOF (constant: body and control-point outputs).
    frequency_hz : (k,) ndarray
        Measured natural frequencies [Hz].
    shapes : (q, k) ndarray
        Measured shapes.
    weights : (2, k) ndarray
        Weights of each mode's frequency residual and shape residual [-].
    """

    model: Any
    parameters: tuple[Parameter, ...]
    rows: np.ndarray
    frequency_hz: np.ndarray
    shapes: np.ndarray
    weights: np.ndarray

    def modal(self, values: np.ndarray, jacobian: bool = True) -> dict[str, Any]:
        """The model's modes at ``values`` paired with the measured ones: ``pair`` (k,) model mode
        of each measured mode, ``f`` (k,) their frequencies [Hz], ``c`` (q, k) shapes at the outputs,
        ``mac`` (k,), and with ``jacobian`` ``df`` (k, p) and ``dc`` (q, k, p)."""
        sens = evaluate(self.model, self.parameters, values, shapes=jacobian)
        c_all = self.rows @ sens.shapes
        macs = mac(self.shapes, c_all, np.eye(len(self.rows)))
        meas, model = linear_sum_assignment(-macs)
        pair = np.empty(len(self.frequency_hz), dtype=int)
        pair[meas] = model
        out: dict[str, Any] = {"pair": pair, "f": sens.frequency_hz[pair], "c": c_all[:, pair],
                               "mac": macs[np.arange(pair.size), pair]}
        if jacobian:
            out["df"] = sens.d_frequency[pair]
            out["dc"] = np.einsum("qn,nkp->qkp", self.rows, sens.d_shapes[:, pair])
        return out

    def residual(self, values: np.ndarray, jacobian: bool = True) -> tuple[np.ndarray, np.ndarray | None]:
        """Real residuals (relative frequency errors, then scaled shape errors, weighted) and their
        (N, k) derivatives."""
        md = self.modal(values, jacobian)
        fm, m, c = self.frequency_hz, self.shapes, md["c"]
        wf, ws = self.weights
        norm = np.linalg.norm(m, axis=0)
        cc = np.einsum("qk,qk->k", c, c)
        mc = np.einsum("qk,qk->k", m, c)
        a = mc / cc
        r = np.concatenate([wf * (md["f"] - fm) / fm, ((a * c - m) * (ws / norm)).T.ravel()])
        if not jacobian:
            return r, None
        dc = md["dc"]
        da = (np.einsum("qk,qkp->kp", m, dc) - 2 * (a * np.einsum("qk,qkp->kp", c, dc).T).T) / cc[:, None]
        dshape = (c[:, :, None] * da[None] + a[None, :, None] * dc) * (ws / norm)[None, :, None]
        jac = np.vstack([(wf / fm)[:, None] * md["df"], dshape.transpose(1, 0, 2).reshape(-1, dc.shape[2])])
        return r, jac
