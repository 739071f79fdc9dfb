"""``vibss design``: the decoupling certificate of a layout; optionally a tolerance study and an
optimisation of the mount rates."""

from __future__ import annotations

import argparse
import dataclasses
import sys
from typing import Any

from .._deprecated import warn
from ..errors import ArgumentError
from .common import add_model_arguments, emit, linear_from_args


_FROM_FILE = -1.0      # --tolerance given without a value: the file's [design.tolerances]


class _Optimize(argparse.Action):
    """``--optimize``; ``--optimise``, the old spelling, still works for one release with a warning."""

    def __call__(self, parser: argparse.ArgumentParser, namespace: argparse.Namespace, values: Any,
                 option_string: str | None = None) -> None:
        if option_string == "--optimise":
            warn("vibss design --optimise", "--optimize", stacklevel=2)
        setattr(namespace, self.dest, True)


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``design`` sub-command."""
    p = sub.add_parser("design", help="decoupling certificate; tolerance study; rate optimisation",
                       description="Decoupling certificate of the mount layout: kinetic-energy matrix "
                                   "from the full mass matrix, purity of each rigid-body mode against a "
                                   "target, frequency windows, sag under weight and drive torque. With "
                                   "--tolerance: a Monte Carlo study of every mount rate. With "
                                   "--optimize: the rates of each mount type (x0.5 ... x2) that maximise "
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
    p.add_argument("--optimize", "--optimise", dest="optimize", action=_Optimize, nargs=0, default=False,
                   help="optimize the file's [design.variables] (without them: the rates of each "
                        "mount type between x0.5 and x2)")
    p.add_argument("--output", metavar="FILE", help="with --optimize: write the optimized model here")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Print the certificate (and the study and optimisation asked for)."""
    from ..design.filespec import design_spec, run_design

    model = linear_from_args(args)
    spec = design_spec(model)                         # the file's [design] table, or the defaults
    change: dict[str, Any] = {k: v for k, v in (("windows", args.window), ("frame", args.frame),
                                                ("axis", args.axis)) if v is not None}
    if args.purity is not None:
        change.update(purity=args.purity, purity_given=True)
    spec = dataclasses.replace(spec, **change)
    if args.tolerance == _FROM_FILE and not spec.tolerances:
        raise ArgumentError("--tolerance without a value needs a [design.tolerances] table in the "
                            "model file; give a relative tolerance (e.g. --tolerance 0.15)", argument="tolerance")
    tolerance = {None: False, _FROM_FILE: True}.get(args.tolerance, args.tolerance)
    run_ = run_design(model, spec, optimize_layout=args.optimize, damped=args.damped, samples=args.samples,
                      tolerance=tolerance)
    emit(run_.certificate, args.format)
    if run_.optimization is not None:
        emit(run_.optimization, args.format)
        if args.output:
            run_.optimization.write(args.output)
            print(f"optimised model written to {args.output}", file=sys.stderr)
    if run_.tolerance is not None:
        emit(run_.tolerance, args.format)
    return 0
