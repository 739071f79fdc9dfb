"""``vibss design``: the decoupling certificate of a layout; optionally a tolerance study and an
optimisation of the mount rates."""

from __future__ import annotations

import argparse
import sys

from typing import Any

from ..design import Parameter, certificate, monte_carlo, optimise
from ..errors import ArgumentError
from .common import add_model_arguments, emit, load_from_args


_FROM_FILE = -1.0      # --tolerance given without a value: the file's [design.tolerances]


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
    p.add_argument("--purity", type=float, help="purity target (default: the file's [design] purity, else 0.9)")
    p.add_argument("--window", type=float, nargs=2, metavar=("F_LOW", "F_HIGH"),
                   help="frequency window of every mode [Hz] (default: the file's [design] windows)")
    p.add_argument("--frame", choices=("global", "tra", "principal"),
                   help="axes of the energy split (tra: first axis along the torque-roll axis; "
                        "default: the file's [design] frame, else global)")
    p.add_argument("--axis", choices=("x", "y", "z"), help="crank axis (default: [design] axis, else x)")
    p.add_argument("--damped", action="store_true", help="also the complex (damped) modes")
    p.add_argument("--tolerance", type=float, metavar="REL", nargs="?", const=_FROM_FILE,
                   help="Monte Carlo: every mount rate +-REL (e.g. 0.15), uniform, Latin hypercube; "
                        "without REL: the file's [design.tolerances]")
    p.add_argument("--samples", type=int, help="Monte Carlo variants (default: [design] samples, else 10000)")
    p.add_argument("--optimise", action="store_true",
                   help="optimise the file's [design.variables] (without them: the rates of each "
                        "mount type between x0.5 and x2)")
    p.add_argument("--output", metavar="FILE", help="with --optimise: write the optimised model here")
    p.set_defaults(func=run)


def _type_rates(model: Any) -> dict[Any, tuple[float, float]]:
    """Every rate of every mount type, tied over the type's mounts, between x0.5 and x2."""
    variables: dict[Any, tuple[float, float]] = {}
    for name, mtype in model.mount_types.items():
        users = [m.name for m in model.mounts if m.type.name == name]
        for j, k in enumerate(mtype.stiffness):
            if k > 0:
                variables[Parameter(f"{name}.k{j + 1}", [(u, f"k{j + 1}", 1.0) for u in users])] = (0.5 * k, 2.0 * k)
    return variables


def run(args: argparse.Namespace) -> int:
    """Print the certificate (and the study and optimisation asked for)."""
    model = load_from_args(args)
    spec = dict(model.settings.get("design", {}))     # the file's [design] table (SI)
    purity = args.purity if args.purity is not None else spec.get("purity", 0.9)
    kw = {"windows": args.window if args.window is not None else spec.get("windows"),
          "frame": args.frame or spec.get("frame", "global"), "axis": args.axis or spec.get("axis", "x")}
    emit(certificate(model, purity=purity, damped=args.damped, **kw), args.format)
    if args.optimise:
        variables = {k: tuple(v) for k, v in spec["variables"].items()} if spec.get("variables") else _type_rates(model)
        extra = {k: spec[k] for k in ("modes", "max_sag", "method", "starts", "catalogue") if k in spec}
        opt = optimise(model, variables, purity=purity if "purity" in spec or args.purity is not None else None,
                       **kw, **extra)
        emit(opt, args.format)
        if args.output:
            opt.write(args.output)
            print(f"optimised model written to {args.output}", file=sys.stderr)
        model = opt.model
    if args.tolerance is not None:
        if args.tolerance == _FROM_FILE:
            if not spec.get("tolerances"):
                raise ArgumentError("--tolerance without a value needs a [design.tolerances] table in the "
                                    "model file; give a relative tolerance (e.g. --tolerance 0.15)",
                                    argument="tolerance")
            tol = dict(spec["tolerances"])
        else:
            tol = {f"{m.name}.k{j + 1}": args.tolerance for m in model.mounts for j in range(3)
                   if m.type.stiffness[j] > 0}
        n = args.samples if args.samples is not None else spec.get("samples", 10_000)
        sampling = spec.get("sampling", "lhs")
        emit(monte_carlo(model, tol, n=n, purity=purity, sampling=sampling, **kw), args.format)
    return 0
