"""``vibss time``: time response to the model file's excitations (shocks, forces, base motion)."""

from __future__ import annotations

import argparse
import sys

from ..errors import ModelError
from .common import (RegistryNames, add_method_argument, add_model_arguments, add_save_argument, check_save, emit,
                     load_from_args, save)

METHODS = RegistryNames("vibss.time.methods")
"""Names of :data:`vibss.time.methods.METHODS`, read from the registry when first needed (building
the parser imports no analysis)."""


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``time`` sub-command."""
    p = sub.add_parser("time", help="time response to the file's excitations",
                       description="Simulate from t = 0 the response to the model file's "
                                   "[[excitation]] entries and initial conditions, with the "
                                   "settings of [analysis] time = {end, step, record_from, "
                                   "tolerance} unless given here, else the window and step the "
                                   "report uses (vibss.studies: the excitations' end plus the "
                                   "slowest mode's decay; a twentieth of the shortest period or "
                                   "pulse). Prints the peak and RMS of each output (text) or the "
                                   "whole history (--format json).")
    add_model_arguments(p)
    p.add_argument("--end", type=float, metavar="T", help="end time [s] (default: file, else excitations' end + slowest decay)")
    p.add_argument("--step", type=float, metavar="DT", help="sample interval [s] (default: file, else from the modes and excitations)")
    p.add_argument("--record-from", type=float, metavar="T", help="first recorded time [s]")
    add_method_argument(p, "vibss.time.methods", "simulation method (auto = exact modal)")
    p.add_argument("--output", action="append", metavar="SIGNAL",
                   help="an output signal (repeatable), e.g. engine.z, sensor.x.acc, mount.front.fz; "
                        "default as in the report: under ground motion the mount deflections and body "
                        "accelerations first (absolute motion last), under forces body motion and "
                        "mount forces first")
    p.add_argument("--absolute", action="store_true",
                   help="under ground motion, body motions absolute (default: relative to the ground)")
    p.add_argument("--plot", metavar="PNG", help="also save a plot of the outputs to this file")
    p.add_argument("--g", action="store_true", help="translational accelerations in g (9.80665 m/s^2) in the "
                   "table and the plot (default: as the model file's units say, else m/s^2)")
    add_save_argument(p, "output time histories")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Run the simulation and print it."""
    check_save(args.save)
    from ..studies import steady_sweeps, time_outputs, time_window, transient_excitations
    from ..time.api import simulate
    from ..time.drift import ground_drifts

    model = load_from_args(args)
    # a sweep with sweep_time = 0 is a steady state: frequency studies only
    excitations = list(transient_excitations(model))
    for e in steady_sweeps(model):
        print(f"vibss time: skipping excitation {e.name!r} (sweep_time = 0: steady state, "
              "frequency studies only)", file=sys.stderr)
    if not excitations and not (model.settings or {}).get("initial"):
        raise ModelError("the model has no time-domain [[excitation]] and no body initial "
                         "conditions: nothing drives a time response")
    window = time_window(model, end=args.end)   # the report's window (vibss.studies)
    end = window.end
    step = args.step if args.step is not None else min(window.step, end)
    record = args.record_from if args.record_from is not None else window.record_from
    chosen = time_outputs(model, excitations, absolute=args.absolute)
    outputs = args.output or list(chosen.outputs)
    result = simulate(model, excitations, outputs=outputs, t_end=end, dt=step, record_from=record,
                      method=args.method, rtol=window.tolerance)
    for drift in ground_drifts(excitations, end):        # a drift is flagged, never a headline
        print(f"vibss time: drift: {drift.text()}", file=sys.stderr)
    in_g = args.g or (model.settings or {}).get("units", {}).get("acceleration") == "g"
    emit(result.in_g() if in_g and args.format == "text" else result, args.format)   # JSON stays SI
    save(result, args.save)
    if args.plot:
        import matplotlib

        matplotlib.use("Agg")
        if args.output:
            fig = result.plot()
        else:                   # the report's figure: what matters first, the input drawn on top
            from ..plotting import plot_time_groups

            fig = plot_time_groups(result, order=list(chosen.lead), show_inputs=True,
                                   acceleration="g" if in_g else "m/s^2")
        fig.savefig(args.plot, dpi=120)
        print(f"plot written to {args.plot}", file=sys.stderr)
    return 0
