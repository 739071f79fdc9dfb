"""``vibss static``: static deflection under the model file's loads (and gravity)."""

from __future__ import annotations

import argparse

from .common import add_model_arguments, emit, load_from_args


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``static`` sub-command."""
    p = sub.add_parser("static", help="static deflection under the file's loads and gravity",
                       description="Static deflection of every body (with its centre of rotation), "
                                   "of the control points, and of every mount in global and local "
                                   "axes, with mount forces, under the file's [[load]] entries and, "
                                   "if [model] sets gravity, self-weight.")
    add_model_arguments(p)
    p.add_argument("--no-gravity", action="store_true", help="leave out self-weight")
    p.add_argument("--case", metavar="NAME", default=None,
                   help="load case: the unnamed loads plus this case's (named cases are opt-in: without --case only the unnamed loads apply); "
                        "'self-weight': gravity alone")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Print the static deflection."""
    from ..nonlinear.kernels import nonlinear_mounts
    from ..statics import static

    model = load_from_args(args)
    if nonlinear_mounts(model):       # stops or curves: the operating point, its tangent rates and clearances
        from ..nonlinear.api import operating_point

        emit(operating_point(model, gravity=not args.no_gravity, case=args.case), args.format)
    else:
        emit(static(model, gravity=not args.no_gravity, case=args.case), args.format)
    return 0
