"""``vibss modes``: undamped natural frequencies, relative eigenvectors, kinetic-energy table."""

from __future__ import annotations

import argparse

from .common import add_model_arguments, add_save_argument, check_save, emit, linear_from_args, load_from_args, save


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``modes`` and ``damped`` sub-commands."""
    p = sub.add_parser("modes", help="undamped modes: frequencies, shapes, energy distribution",
                       description="Undamped natural frequencies [Hz, CPM], relative eigenvectors per "
                                   "body, dominant directions, effective masses and the modal "
                                   "kinetic-energy distribution table.")
    add_model_arguments(p)
    p.add_argument("-n", "--modes", type=int, default=None, metavar="N",
                   help="only the lowest N modes (default: all, 6 per body)")
    p.add_argument("--energy", choices=("strain", "kinetic", "dissipative"), default=None,
                   help="print the modes' energy shared among the mounts (strain, dissipative) or bodies "
                        "(kinetic), per part and per local axis, instead of the modes' report")
    add_save_argument(p, "mode shapes (UFF datasets 2411 and 55)")
    p.set_defaults(func=run_modes)
    d = sub.add_parser("damped", help="damped modes: poles, damping ratios, complex shapes",
                       description="Damped natural frequencies and damping ratios from the poles of "
                                   "the state-space system, paired with the undamped modes.")
    add_model_arguments(d)
    d.set_defaults(func=run_damped)


def run_modes(args: argparse.Namespace) -> int:
    """Print the undamped modes."""
    check_save(args.save, (".uff", ".unv"))
    from ..modal.api import modes

    result = modes(load_from_args(args), n_modes=args.modes)
    if getattr(args, "energy", None):
        from ..insight.api import energy_distribution

        emit(energy_distribution(result, args.energy), args.format)
    else:
        emit(result, args.format)
    save(result, args.save, (".uff", ".unv"))
    return 0


def run_damped(args: argparse.Namespace) -> int:
    """Print the damped modes."""
    from ..modal.api import damped_modes

    emit(damped_modes(linear_from_args(args)), args.format)
    return 0
