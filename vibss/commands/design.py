"""``vibss design``: the decoupling certificate of a layout; optionally a tolerance study and an
optimisation of the mount rates."""

from __future__ import annotations

import argparse
import sys

from ..design import Parameter, certificate, monte_carlo, optimise
from .common import add_model_arguments, emit, load_from_args


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``design`` sub-command."""
    p = sub.add_parser("design", help="decoupling certificate; tolerance study; rate optimisation",
                       description="Decoupling certificate of the mount layout: kinetic-energy matrix "
                                   "from the full mass matrix, purity of each rigid-body mode against a "
                                   "target, frequency windows, sag under weight and drive torque. With "
                                   "--tolerance: a Monte Carlo study of every mount rate. With "
                                   "--optimise: the rates of each mount type (x0.5 ... x2) that maximise "
                                   "the mean purity within the windows.")
    add_model_arguments(p)
    p.add_argument("--purity", type=float, default=0.9, help="purity target (default 0.9)")
    p.add_argument("--window", type=float, nargs=2, metavar=("F_LOW", "F_HIGH"),
                   help="frequency window of every mode [Hz]")
    p.add_argument("--frame", choices=("global", "tra", "principal"), default="global",
                   help="axes of the energy split (tra: first axis along the torque-roll axis)")
    p.add_argument("--axis", choices=("x", "y", "z"), default="x", help="crank axis (default x)")
    p.add_argument("--damped", action="store_true", help="also the complex (damped) modes")
    p.add_argument("--tolerance", type=float, metavar="REL",
                   help="Monte Carlo: every mount rate +-REL (e.g. 0.15), uniform, Latin hypercube")
    p.add_argument("--samples", type=int, default=10_000, help="Monte Carlo variants (default 10000)")
    p.add_argument("--optimise", action="store_true", help="optimise the rates of each mount type")
    p.add_argument("--output", metavar="FILE", help="with --optimise: write the optimised model here")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Print the certificate (and the study and optimisation asked for)."""
    model = load_from_args(args)
    kw = {"windows": args.window, "frame": args.frame, "axis": args.axis}
    emit(certificate(model, purity=args.purity, damped=args.damped, **kw), args.format)
    if args.optimise:
        variables = {}
        for name, mtype in model.mount_types.items():
            users = [m.name for m in model.mounts if m.type.name == name]
            for j, k in enumerate(mtype.stiffness):
                if k > 0:
                    variables[Parameter(f"{name}.k{j + 1}", [(u, f"k{j + 1}", 1.0) for u in users])] = (0.5 * k, 2.0 * k)
        opt = optimise(model, variables, **kw)
        emit(opt, args.format)
        if args.output:
            opt.write(args.output)
            print(f"optimised model written to {args.output}", file=sys.stderr)
        model = opt.model
    if args.tolerance is not None:
        tol = {f"{m.name}.k{j + 1}": args.tolerance for m in model.mounts for j in range(3)
               if m.type.stiffness[j] > 0}
        emit(monte_carlo(model, tol, n=args.samples, purity=args.purity, **kw), args.format)
    return 0
