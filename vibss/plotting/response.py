"""Time responses grouped by quantity: one panel per kind of output, sharing the time axis."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from matplotlib.figure import Figure

from .._validate import choice, name_index
from ._draw import new_figure

__all__ = ["plot_time_groups", "quantity_of", "plot_time_response", "plot_sweep_envelope"]

_ORDER = ("body translation", "body rotation", "relative translation", "relative rotation", "acceleration", "angular acceleration", "velocity",
          "mount deflection", "mount force", "force into ground", "moment into ground", "force into bodies",
          "moment into bodies")


def quantity_of(name: str, unit: str) -> str:
    """The panel an output goes to, from its signal name and SI unit.

    Examples
    --------
    >>> quantity_of("engine.z", "m"), quantity_of("mount.front.dz", "m"), quantity_of("engine.x.acc", "m/s^2")
    ('body translation', 'mount deflection', 'acceleration')
    >>> quantity_of("engine.z.rel", "m")
    'relative translation'
    >>> quantity_of("ground.mx", "N m"), quantity_of("frame.into.fz", "N")
    ('moment into ground', 'force into bodies')
    """
    if name.startswith("mount."):
        return "mount force" if unit in ("N", "N m") else "mount deflection"
    head, _, comp = name.partition(".")
    reaction = unit in ("N", "N m") and comp in ("fx", "fy", "fz", "mx", "my", "mz")   # ground or a support
    if name.startswith("ground.") or reaction or ".into." in name:
        where = "ground" if name.startswith("ground.") or reaction else "bodies"
        return f"{'moment' if unit == 'N m' else 'force'} into {where}"
    if name.endswith(".acc"):
        return "angular acceleration" if unit.startswith("rad") else "acceleration"
    if name.endswith(".vel"):
        return "velocity"
    if name.endswith(".rel"):
        return "relative rotation" if unit == "rad" else "relative translation"
    return "body rotation" if unit == "rad" else "body translation"


def plot_time_groups(response: Any, max_lines: int = 6, order: Sequence[str] | None = None,
                     show_inputs: bool = False, acceleration: str = "m/s^2") -> Figure:
    """Plot a time response with one panel per quantity (translation, rotation, acceleration,
    mount deflection ...), each showing its ``max_lines`` outputs of largest peak, peaks marked. A
    quantity of round-off only (nothing above 1e-15, or displacements and rotations below 1e-9 of the
    largest of them, rotations read at a 1 m lever) gets no panel; the title names it.

    Parameters
    ----------
    response : vibss.time.TimeResponse
        The response (``time``, ``outputs``, ``output_names``, ``units``).
    max_lines : int
        Most lines per panel (the outputs with the largest peaks).
    order : sequence of str or None
        Panels first in this order (quantities as :func:`quantity_of` names them); the rest after.
    show_inputs : bool
        A first panel with the input signals (the excitation drawn).
    acceleration : {"m/s^2", "g"}
        Unit of the translational accelerations drawn, outputs and inputs (``"g"``: divided by
        standard gravity, 9.80665 m/s^2).

    Returns
    -------
    Figure
    """
    from ..model.units import STANDARD_GRAVITY

    acceleration = choice(acceleration, "acceleration", ("m/s^2", "g"), who="plot")
    scale = 1.0 / STANDARD_GRAVITY if acceleration == "g" else 1.0

    def shown_unit(unit: str) -> str:
        return "g" if unit == "m/s^2" and scale != 1.0 else unit

    def shown_values(unit: str, y: np.ndarray) -> np.ndarray:
        return y * scale if unit == "m/s^2" else y

    groups: dict[str, list[int]] = {}
    for i, (n, u) in enumerate(zip(response.output_names, response.units)):
        groups.setdefault(quantity_of(n, u), []).append(i)
    rank = list(order or ()) + [k for k in _ORDER if k not in (order or ())]
    keys = sorted(groups, key=lambda k: rank.index(k) if k in rank else len(rank))
    top = {k: float(np.abs(response.outputs[groups[k]]).max(initial=0.0)) for k in keys}
    motion = max((top[k] for k in keys if response.units[groups[k][0]] in ("m", "rad")), default=0.0)
    # a panel of round-off: nothing above 1e-15, or displacements and rotations below 1e-9 of the largest
    # of them (rotations read at a 1 m lever: a symmetric body's 1e-14 rad beside its 1e-2 m)
    small = [k for k in keys if top[k] <= 1e-15
             or (response.units[groups[k][0]] in ("m", "rad") and top[k] < 1e-9 * motion)]
    keys = [k for k in keys if k not in small] or keys[:1]
    extra = 1 if show_inputs and len(response.input_names) else 0
    fig = new_figure(8.5, 1.0 + 2.1 * max(len(keys) + extra, 1))
    axes = np.atleast_1d(fig.subplots(max(len(keys) + extra, 1), 1, sharex=True, squeeze=False)[:, 0])
    t = response.time
    if extra:
        from ..model.units import input_unit

        ax0, axes = axes[0], axes[1:]
        for j, name in enumerate(response.input_names):
            ax0.plot(t, shown_values(input_unit(name, _kind_of(name)), response.inputs[j]), lw=1.1,
                     color="0.25", ls=("-", "--", ":")[j % 3], label=name)
        units = {shown_unit(input_unit(n, _kind_of(n))) for n in response.input_names}
        ax0.set_ylabel("input\n[" + (units.pop() if len(units) == 1 else "SI") + "]", fontsize=9)
        ax0.grid(True, lw=0.3, alpha=0.6)
        ax0.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.0, 1.0), frameon=False)
    for ax, key in zip(axes, keys):
        rows = groups[key]
        peak = np.array([np.max(np.abs(response.outputs[i]), initial=0.0) for i in rows])
        shown = [rows[j] for j in np.argsort(peak)[::-1][:max_lines] if peak[j] > 1e-9 * peak.max()]
        for i in shown:
            y = shown_values(response.units[i], response.outputs[i])
            (line,) = ax.plot(t, y, lw=1.1, label=response.output_names[i])
            if y.size:
                k = int(np.argmax(np.abs(y)))
                ax.plot(t[k], y[k], "o", ms=4, color=line.get_color())
        unit = shown_unit(response.units[rows[0]])
        ax.set_ylabel(f"{key}\n[{unit}]", fontsize=9)
        ax.grid(True, lw=0.3, alpha=0.6)
        hidden = len(rows) - len(shown)
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.0, 1.0), frameon=False,
                  title=f"+{hidden} smaller" if hidden else None, title_fontsize=7)
    axes[-1].set_xlabel("time [s]")
    fig.suptitle(f"Time response of {response.name!r} (peaks marked)"
                 + (f"; round-off only: {', '.join(small)}" if small else ""),
                 fontsize=10)
    return fig


def _kind_of(name: str) -> str:
    """What an input signal is, from its name's suffix."""
    last = name.rsplit(".", 1)[-1]
    return {"disp": "displacement", "vel": "velocity", "acc": "acceleration"}.get(last, "force")


def plot_time_response(response: Any, outputs: Sequence[str] | None = None, by: str = "body",
                       ax: Any = None, inputs: bool | None = None) -> Figure:
    """Outputs of a time response against time, peaks marked and annotated, one unit per axes.

    Parameters
    ----------
    response : vibss.time.TimeResponse
        The response.
    outputs : sequence of str or None
        Outputs to draw (default all).
    by : {"body", "all"}
        One axes per body (the part of the name before the first dot) and unit, or one per unit.
    ax : Axes, sequence of Axes or None
        Axes to draw in, one per group (the input's first when drawn); default: a new figure.
    inputs : bool or None
        Draw the inputs in a panel of their own on top; default: when a motion (of ground, a support
        or a body) is prescribed (base excitation: the pulse the response answers) and no ``ax``
        is given.

    Returns
    -------
    Figure
    """
    from ..model.units import input_unit

    r = response
    choice(by, "by", ("body", "all"), who="TimeResponse.plot")
    names = list(outputs) if outputs is not None else list(r.output_labels)
    groups: dict[tuple[str, str], list[int]] = {}
    for n in names:
        i = name_index(n, r.output_labels, "output")
        groups.setdefault((n.split(".")[0] if by == "body" else "", r.units[i]), []).append(i)
    given = list(getattr(r, "input_names", ()) or ())
    history = np.asarray(getattr(r, "inputs", np.zeros((0, 0))))
    if inputs is None:
        # base motion (of ground or a support) drives the response: show it
        inputs = ax is None and any(u.startswith("ground.") or u.endswith((".disp", ".vel", ".acc")) for u in given)
    inputs = bool(inputs) and bool(given) and history.shape[0] == len(given)
    panels = len(groups) + int(inputs)
    if ax is None:
        fig = new_figure(8, 2.2 + 1.8 * panels)
        axes = list(fig.subplots(panels, 1, sharex=True, squeeze=False)[:, 0])
    else:
        axes = list(np.atleast_1d(ax))
        fig = axes[0].figure
    if inputs:
        a = axes.pop(0)
        kinds = {"disp": "displacement", "vel": "velocity", "acc": "acceleration"}
        units = []
        for j, u in enumerate(given):
            unit = input_unit(u, kinds.get(u.rsplit(".", 1)[-1], "force"))
            units.append(unit)
            a.plot(r.time, history[j], color="0.3", label=f"{u} [{unit}]")
        a.set_title("input", fontsize=9)
        a.set_ylabel(f"[{', '.join(dict.fromkeys(units))}]", fontsize=8)
        a.grid(True, alpha=0.3)
        a.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    for a, ((key, unit), rows) in zip(axes, groups.items()):
        for i in rows:
            y = r.outputs[i]
            (line,) = a.plot(r.time, y, label=r.output_labels[i])
            if y.size:
                k = int(np.argmax(np.abs(y)))
                a.plot(r.time[k], y[k], "o", color=line.get_color())
                a.annotate(f"{y[k]:.3g}", (r.time[k], y[k]), textcoords="offset points",
                           xytext=(4, 4), fontsize=8)
        a.set_title(key if by == "body" else r.name, fontsize=9)
        a.set_ylabel(f"[{unit}]", fontsize=8)
        a.grid(True, alpha=0.3)
        a.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    (axes[-1] if axes else fig.axes[-1]).set_xlabel("time [s]")
    fig.suptitle(f"{r.name} ({r.method})", fontsize=10)
    return fig


def plot_sweep_envelope(envelope: Any, outputs: Sequence[str] | None = None, ax: Any = None) -> Figure:
    """Envelope of a finite-rate sweep and the steady-state amplitude against frequency.

    Parameters
    ----------
    envelope : vibss.time.SweepEnvelope
        The result of :func:`vibss.time.sweep_envelope`.
    outputs : sequence of str or None
        Outputs to draw, one axes each (default all).
    ax : Axes, sequence of Axes or None
        Axes to draw in, one per output; default: a new figure.

    Returns
    -------
    Figure
    """
    e = envelope
    names = list(outputs) if outputs is not None else list(e.output_labels)
    rows = [name_index(n, e.output_labels, "output") for n in names]
    if ax is None:
        fig = new_figure(8, 1.5 + 2.0 * len(rows))
        axes = list(fig.subplots(len(rows), 1, sharex=True, squeeze=False)[:, 0])
    else:
        axes = list(np.atleast_1d(ax))
        fig = axes[0].figure
    for a, i in zip(axes, rows):
        a.plot(e.frequency_hz, e.steady[i], "k--", lw=1, label="steady state")
        a.plot(e.frequency_hz, e.envelope[i], lw=1.2, label="sweep envelope")
        a.set_ylabel(f"{e.output_labels[i]} [{e.units[i]}]", fontsize=8)
        a.grid(True, alpha=0.3)
        a.legend(fontsize=7)
    axes[-1].set_xlabel("instantaneous frequency [Hz]")
    return fig
