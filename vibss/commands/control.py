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
    p.add_argument("--robust", type=float, metavar="TOL",
                   help="also check the loop over +-TOL relative tolerance on every mount rate (e.g. 0.2): "
                        "P(stable), damping, disk margins and peak transmissibility over a Monte Carlo and "
                        "the worst corners (vibss.control.robustness)")
    p.add_argument("--variants", type=int, default=500, metavar="N", help="Monte Carlo variants of --robust "
                   "(default 500)")
    p.add_argument("--robust-plot", metavar="PNG", help="also save the --robust histograms")
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
    if args.robust is not None and not 0 < args.robust < 1:
        raise ArgumentError(f"--robust: expected a relative tolerance between 0 and 1 (0.2: +-20 %), got "
                            f"{args.robust}", argument="robust", received=args.robust)
    if args.variants < 1:
        raise ArgumentError(f"--variants: expected a count >= 1, got {args.variants}", argument="variants",
                            received=args.variants)
    r = run_control(model)
    if args.robust is None or args.format != "json":
        emit(r, args.format)
    if args.plot:
        r.plot().savefig(args.plot, dpi=110, bbox_inches="tight")
        print(f"figure written to {args.plot}", file=sys.stderr)
    if args.robust is not None:
        import json

        from ..control.robust import robustness
        from ..results import jsonable

        tol = {f"{m.name}.k{j + 1}": args.robust for m in model.mounts for j in range(3) if m.type.stiffness[j] > 0}
        rob = robustness(r.loop.plant, r.loop.controller, tol, n=args.variants)
        if args.format == "json":             # one JSON document: the loop and its robustness
            print(json.dumps(jsonable({"control": r.to_dict(), "robustness": rob.to_dict()}), indent=2,
                             allow_nan=False))
        else:
            emit(rob, args.format)
        if args.robust_plot:
            rob.plot().savefig(args.robust_plot, dpi=110, bbox_inches="tight")
            print(f"figure written to {args.robust_plot}", file=sys.stderr)
    return 0
