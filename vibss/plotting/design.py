"""Figures of mount-system design: the decoupling certificate, sensitivities, Monte Carlo studies."""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.figure import Figure

from .._deprecated import module_aliases
from ..errors import ArgumentError
from ._draw import new_figure

__all__ = ["plot_certificate", "plot_sensitivity", "plot_monte_carlo", "plot_optimization", "plot_axes"]


def _axes(ax: Any, width: float, height: float) -> tuple[Figure, Any]:
    if ax is not None:
        return ax.figure, ax
    fig = new_figure(width, height)
    return fig, fig.add_subplot()


def plot_certificate(cert: Any, ax: Any = None) -> Figure:
    """KE matrix [%] as a heat map; each row labelled with frequency, window verdict and purity.

    Parameters
    ----------
    cert : vibss.design.Certificate
        The certificate.
    ax : Axes or None
        Draw into these axes; default: a new figure.

    Returns
    -------
    Figure
    """
    e = 100 * cert.ke_matrix
    k, n = e.shape
    fig, ax = _axes(ax, 2.4 + 0.62 * n, 1.4 + 0.4 * k)
    im = ax.imshow(e, cmap="Blues", vmin=0, vmax=100, aspect="auto")
    for i in range(k):
        for j in range(n):
            if e[i, j] >= 1:
                ax.text(j, i, f"{e[i, j]:.0f}", ha="center", va="center", fontsize=7,
                        color="w" if e[i, j] > 60 else "k")
    labels = [f"{i + 1}: {cert.frequency_hz[i]:.2f} Hz{'' if cert.in_window[i] else ' (out)'}"
              for i in range(k)]
    ax.set_yticks(range(k), labels, fontsize=8)
    ax.set_xticks(range(n), [c.split(".", 1)[-1] if len(cert.model.bodies) == 1 else c
                             for c in cert.coordinates], rotation=0 if n <= 6 else 90, fontsize=8)
    right = ax.secondary_yaxis("right")
    right.set_yticks(range(k), [f"{100 * p:.0f} % {'ok' if ok else 'LOW'}"
                                for p, ok in zip(cert.purity, cert.pure)], fontsize=8)
    right.set_ylabel(f"purity (target {100 * cert.target:.0f} %)", fontsize=8)
    ax.set_xlabel(f"coordinate ({cert.frame_name} frame)")
    ax.set_ylabel("mode: frequency")
    fig.colorbar(im, ax=ax, label="kinetic energy [%]", shrink=0.9, pad=0.12)
    ax.set_title(f"Decoupling certificate: {'PASSED' if cert.passed else 'FAILED'}", fontsize=10)
    return fig


def plot_sensitivity(sens: Any, quantity: str = "frequency", ax: Any = None) -> Figure:
    """Tornado of each mode's frequency or purity change [%] per 1 % rate, 1 mm shift, 1 degree turn.

    Parameters
    ----------
    sens : vibss.design.Sensitivity
        The sensitivities.
    quantity : {"frequency", "purity"}
        Which output.
    ax : Axes or None
        Draw into these axes; default: a new figure.

    Returns
    -------
    Figure
    """
    d = sens.normalized(quantity)                       # (k, p)
    k, p = d.shape
    fig, ax = _axes(ax, 6.5, 1.5 + 0.28 * p)
    y = np.arange(p)
    h = 0.8 / k
    for i in range(k):
        ax.barh(y + (i - (k - 1) / 2) * h, d[i], height=h, label=f"mode {i + 1}")
    ax.set_yticks(y, list(sens.parameters), fontsize=8)
    ax.axvline(0.0, color="k", lw=0.6)
    ax.set_xlabel(f"change of {quantity} [% of its value] per 1 % rate, 1 mm shift, 1 deg turn")
    ax.set_ylabel("parameter")
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.0, 1.0), frameon=False)
    ax.invert_yaxis()
    return fig


def plot_monte_carlo(mc: Any, ax: Any = None, kind: str = "histogram", mode: int | None = None) -> Figure:
    """Histograms of the natural frequencies [Hz] of every variant (windows shaded) and of the
    purities; or a tornado of the parameters' correlation with one mode's purity.

    Parameters
    ----------
    mc : vibss.design.MonteCarlo
        The study.
    ax : Axes or None
        Draw into these axes; default: a new figure (two panels for the histograms).
    kind : {"histogram", "tornado"}
        What to draw.
    mode : int or None
        Tornado: the mode (1-based); default the one least often pure enough.

    Returns
    -------
    Figure
    """
    if kind == "tornado":
        return _tornado(mc, ax, mode)
    if kind != "histogram":
        raise ArgumentError(f"plot_monte_carlo: kind: expected 'histogram' or 'tornado', got {kind!r}",
                            argument="kind", received=kind, expected=["histogram", "tornado"])
    f = mc.frequency_hz
    if ax is None:
        fig = new_figure(9.0, 3.6)
        ax, ax2 = fig.subplots(1, 2)
    else:
        fig, ax2 = ax.figure, None
    bins = np.linspace(f.min(), f.max(), 80)
    for lo, hi in {tuple(w) for w in mc.windows.tolist()}:
        if lo > 0 or np.isfinite(hi):
            ax.axvspan(max(lo, f.min()), min(hi, f.max()), color="0.85", zorder=0,
                       label=f"window {lo:.3g} ... {hi:.3g} Hz")
    for i in range(f.shape[1]):
        ax.hist(f[:, i], bins=bins, histtype="stepfilled", alpha=0.5, label=f"mode {i + 1}")
    ax.set_xlabel("natural frequency [Hz]")
    ax.set_ylabel("variants")
    ax.legend(fontsize=7, frameon=False)
    ax.set_title(f"{len(f)} variants ({mc.sampling})", fontsize=10)
    if ax2 is not None:
        pb = np.linspace(np.floor(100 * mc.purity.min() / 5) * 5, 100, 41)
        for i in range(f.shape[1]):
            ax2.hist(100 * mc.purity[:, i], bins=pb, histtype="step", label=f"mode {i + 1}")
        ax2.axvline(100 * mc.target, color="k", ls="--", lw=0.8)
        ax2.set_xlabel("purity [%]")
        ax2.set_ylabel("variants")
        ax2.set_title(f"P(all targets met) = {mc.probability['all']:.3f}", fontsize=10)
    return fig


def _tornado(mc: Any, ax: Any, mode: int | None) -> Figure:
    i = int(np.argmin(mc.pure.mean(axis=0))) if mode is None else int(mode) - 1
    r = mc.ranking("purity")[:, i]
    order = np.argsort(np.abs(r))
    fig, ax = _axes(ax, 6.0, 1.4 + 0.28 * len(r))
    y = np.arange(len(r))
    ax.barh(y, r[order], color=np.where(r[order] >= 0, "#1f77b4", "#d62728"))
    ax.set_yticks(y, [mc.parameters[j] for j in order], fontsize=8)
    ax.axvline(0.0, color="k", lw=0.6)
    ax.set_xlim(-1, 1)
    ax.set_xlabel(f"correlation with the purity of mode {i + 1} [-]")
    ax.set_ylabel("parameter")
    ax.set_title(f"What drives mode {i + 1}'s decoupling ({mc.n} variants)", fontsize=10)
    return fig


def plot_optimization(opt: Any, ax: Any = None) -> Figure:
    """Purity [%] of every mode before and after an optimization, with the target.

    Parameters
    ----------
    opt : vibss.design.Optimization
        The optimization.
    ax : Axes or None
        Draw into these axes; default: a new figure.

    Returns
    -------
    Figure
    """
    b, a = opt.before, opt.after
    k = len(a.purity)
    fig, ax = _axes(ax, 1.8 + 0.8 * k, 3.6)
    x = np.arange(k)
    ax.bar(x - 0.2, 100 * b.purity, 0.4, label="before", color="0.7")
    ax.bar(x + 0.2, 100 * a.purity, 0.4, label="after", color="#1f77b4")
    if a.target > 0:
        ax.axhline(100 * a.target, color="k", ls="--", lw=0.8, label=f"target {100 * a.target:.0f} %")
    ax.set_xticks(x, [f"{i + 1}: {a.frequency_hz[i]:.2f} Hz\n{a.dominant[i].split('.', 1)[-1]}" for i in range(k)],
                  fontsize=8)
    ax.set_ylim(0, 105)
    ax.set_xlabel("mode after: frequency, dominant coordinate")
    ax.set_ylabel(f"purity [%] ({a.frame_name} frame)")
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.0, 1.0), frameon=False)
    return fig


def plot_axes(result: Any, view: str = "three", length: float | None = None) -> Figure:
    """The layout (:func:`vibss.plotting.plot_model`) with the torque-roll axis, the static rotation
    axis under a torque, the elastic centre and its axes, and the principal axes of inertia drawn
    through the body, from computed :class:`vibss.design.DesignAxes` (this draws, it computes nothing).

    Parameters
    ----------
    result : vibss.design.DesignAxes
        The computed axes (:func:`vibss.design.design_axes`).
    view : {"three", "iso", "xz", "yz", "xy"}
        As :func:`vibss.plotting.plot_model`.
    length : float or None
        Half-length of the drawn axes [m]; default: half the largest mount distance from the COG.

    Returns
    -------
    Figure
    """
    from .layout import plot_model

    model, tr, ea, pa = result.model, result.torque, result.elastic, result.principal_axes
    fig = plot_model(model, view=view, labels=False)
    b = model.body(tr.body)
    if length is None:
        pts = np.array([model.mount_point(m) for m in model.mounts if m.body == b.name]) - b.cog
        length = 0.5 * float(np.max(np.linalg.norm(pts, axis=1))) if len(pts) else 0.5
    lines: list[tuple[np.ndarray, np.ndarray, str, str, str | None]] = [
        (b.cog, tr.tra, "k", "--", "torque-roll axis"),
        (b.cog, tr.rotation_axis, "tab:orange", "-", "static rotation under torque")]
    lines += [(b.cog, pa[:, j], "0.55", ":", "principal axes of inertia" if j == 0 else None) for j in range(3)]
    lines += [(ea.center_global, ea.axes[:, j], "tab:purple", "-.",
               ("elastic axes" if ea.exists else "rotational axes at the least-squares centre") if j == 0 else None)
              for j in range(3)]
    views = ["xz", "yz", "xy"] if view == "three" else [view]
    for ax, v in zip(fig.axes, views):
        for p, d, colour, style, label in lines:
            seg = np.array([p - length * d, p + length * d])
            if v == "iso":
                ax.plot(seg[:, 0], seg[:, 1], seg[:, 2], color=colour, ls=style, lw=1.4, label=label)
            else:
                i0, i1 = {"xz": (0, 2), "yz": (1, 2), "xy": (0, 1)}[v]
                ax.plot(seg[:, i0], seg[:, i1], color=colour, ls=style, lw=1.4, label=label)
        c = ea.center_global
        if v == "iso":
            ax.scatter(c[0], c[1], c[2], color="tab:purple", marker="x")
        else:
            i0, i1 = {"xz": (0, 2), "yz": (1, 2), "xy": (0, 1)}[v]
            ax.plot(c[i0], c[i1], "x", color="tab:purple", ms=7)
    handles, names = fig.axes[0].get_legend_handles_labels()
    fig.legend(handles, names, loc="outside right upper", fontsize=8, frameon=False)
    fig.suptitle(f"TRA {np.degrees(tr.misalignment):.1f} deg from the static rotation axis; "
                 f"{'elastic centre exists' if ea.exists else 'no elastic centre'}", fontsize=10, x=0.4)
    return fig


def _plot_design_axes() -> Any:
    from ..design.axes import plot_design_axes      # computes: a figure no longer does
    return plot_design_axes


__getattr__ = module_aliases(__name__, {
    "plot_optimisation": ("vibss.plotting.design.plot_optimization", lambda: plot_optimization),
    "plot_design_axes": ("vibss.design.plot_design_axes (or vibss.design.design_axes(...).plot())",
                         _plot_design_axes)})
