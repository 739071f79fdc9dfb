"""``vibss orders``: steady-state response to the model file's rotating sources over a speed range
(order cuts and critical speeds)."""

from __future__ import annotations

import argparse
import sys


from ..errors import ArgumentError
from .common import add_model_arguments, emit, linear_from_args


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``orders`` sub-command."""
    p = sub.add_parser("orders", help="response to unbalance and engine orders over a speed range",
                       description="Steady-state response of the chosen outputs to the file's [orders] "
                                   "sources (rotating unbalances, engine-order forces and moments) at every "
                                   "speed of a range: peak per output and order, and the critical speeds "
                                   "where an order meets a natural frequency.")
    add_model_arguments(p)
    p.add_argument("--rpm", type=float, nargs=2, metavar=("LOW", "HIGH"),
                   help="speed range [rpm] (default: the file's [orders] rpm)")
    p.add_argument("--points", type=int, help="speeds in the range (default: [orders] points, else 400)")
    p.add_argument("--output", action="append", metavar="SIGNAL",
                   help="output signal (repeatable; default: [orders] outputs, else every body DOF)")
    p.add_argument("--plot", metavar="PNG", help="also save the order cuts")
    p.add_argument("--campbell", metavar="PNG", help="also save the Campbell diagram")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Print the order response."""
    import numpy as np

    from ..orders import order_response
    from ..orders.sources import sources_from_settings

    model = linear_from_args(args)
    spec = model.settings.get("orders", {})
    sources = sources_from_settings(model)
    if not sources:
        raise ArgumentError("vibss orders: the model has no [orders] table with [[orders.unbalance]] or "
                            "[[orders.force]] sources (docs/model-file.md)", argument="file")
    band = args.rpm or spec.get("rpm")
    if band is None:
        raise ArgumentError("vibss orders: no speed range: give --rpm LOW HIGH or rpm = [low, high] in "
                            "[orders]", argument="rpm")
    if not 0 < band[0] < band[1]:
        raise ArgumentError(f"--rpm: expected 0 < LOW < HIGH, got {band}", argument="rpm", received=band)
    points = args.points or spec.get("points", 400)
    if points < 2:
        raise ArgumentError(f"--points: expected >= 2, got {points}", argument="points", received=points)
    r = order_response(model, sources, np.linspace(band[0], band[1], points), args.output or spec.get("outputs"))
    emit(r, args.format)
    for path, draw in ((args.plot, r.plot), (args.campbell, r.campbell)):
        if path:
            draw().savefig(path, dpi=110)
            print(f"figure written to {path}", file=sys.stderr)
    return 0
