"""``vibss control``: design and check the model file's active isolation loops ([control] table)."""

from __future__ import annotations

import argparse
import sys

from .common import add_model_arguments, emit, linear_from_args


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``control`` sub-command."""
    p = sub.add_parser("control", help="active isolation: the [control] loops, poles, margins, transmissibility",
                       description="Builds the generalized plant from the file's [[actuator]] and [[sensor]] "
                                   "tables, designs the [control] table's loops (skyhook, velocity_feedback "
                                   "or integral_force), checks that the closed loop is stable, and prints its "
                                   "poles and damping, the gain, phase and disk margins of every loop, and the "
                                   "transmissibility reduction at the passive resonances.")
    add_model_arguments(p)
    p.add_argument("--gain", type=float, help="loop gain (overrides [control] gain)")
    p.add_argument("--plot", metavar="PNG", help="also save passive and closed-loop transmissibility")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Print the closed-loop analysis."""
    from ..control.filespec import run_control
    from ..errors import ArgumentError

    model = linear_from_args(args)
    if "control" not in model.settings:
        raise ArgumentError("vibss control: the model has no [control] table (docs/model-file.md); "
                            "the packaged example 'platform' has one", argument="file")
    if args.gain is not None:
        if not args.gain >= 0:
            raise ArgumentError(f"--gain: expected a gain >= 0, got {args.gain}", argument="gain",
                                received=args.gain)
        settings = dict(model.settings)
        settings["control"] = {**settings["control"], "gain": args.gain}
        model = model.replace(settings=settings)
    r = run_control(model)
    emit(r, args.format)
    if args.plot:
        r.plot().savefig(args.plot, dpi=110, bbox_inches="tight")
        print(f"figure written to {args.plot}", file=sys.stderr)
    return 0
