"""``vibss frf``: frequency response (steady state of the file's swept-sine excitations, or FRFs)."""

from __future__ import annotations

import argparse

from ..errors import ModelError
from .common import add_method_argument, add_model_arguments, add_save_argument, check_save, emit, linear_from_args, save


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``frf`` sub-command."""
    p = sub.add_parser("frf", help="frequency response (swept-sine steady state or FRFs)",
                       description="Steady-state response to the model file's excitations "
                                   "(sine_sweep functions with sweep_time = 0; amplitude linear from "
                                   "a1 at f1 to a2 at f2), or with --input the FRF per unit input. "
                                   "Outputs default to every body DOF's displacement. The band comes "
                                   "from [analysis] frequency = {f1, f2, points, spacing} or the options; "
                                   "points are added at each resonance.")
    add_model_arguments(p)
    p.add_argument("--input", action="append", metavar="SIGNAL",
                   help="input signal (repeatable), e.g. engine.fz or ground.z.acc: FRF per unit input")
    p.add_argument("--output", action="append", metavar="SIGNAL",
                   help="output signal (repeatable), e.g. engine.z, sensor.x.acc, mount.front.f3, ground.fz, frame.into.fz")
    p.add_argument("--f1", type=float, help="lowest frequency [Hz]")
    p.add_argument("--f2", type=float, help="highest frequency [Hz]")
    p.add_argument("--points", type=int, help="number of base points (default 1000)")
    p.add_argument("--no-refine", action="store_true",
                   help="exactly the base points: no points added at the resonances")
    p.add_argument("--spacing", choices=("log", "linear"), help="base grid spacing (default log)")
    p.add_argument("--quantity", choices=("receptance", "mobility", "accelerance"), default="receptance",
                   help="outputs as named (default), or their first or second time derivative")
    add_method_argument(p, "vibss.frequency.methods", "frequency-response method (auto: chosen per model, "
                        "the reason in the result's note)")
    p.add_argument("--plot", metavar="PNG", help="also save a Bode plot of the response")
    add_save_argument(p, "frequency response")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Compute and print the frequency response."""
    check_save(args.save)
    from ..frequency.api import frequency_response
    from ..frequency.grid import FrequencyGrid
    from ..frequency.sweep import sweep_response
    from ..studies import frequency_band, steady_sweeps

    model = linear_from_args(args)
    settings = frequency_band(model).grid()     # the report's band (vibss.studies)
    for key in ("f1", "f2", "points", "spacing"):
        if getattr(args, key) is not None:
            settings[key] = getattr(args, key)
    if args.no_refine:
        settings["refine"] = False
    outputs = args.output or None
    if args.input:
        result = frequency_response(model, args.input, outputs, FrequencyGrid(**settings),
                                    args.quantity, args.method)
    else:
        if not model.excitations:
            raise ModelError("the model has no [[excitation]] entries; name inputs with --input "
                             "(e.g. --input engine.fz)")
        result = sweep_response(model, list(steady_sweeps(model)) or None, settings["f1"],
                                settings["f2"], int(settings["points"]), settings["spacing"],
                                outputs, args.quantity, refine=settings.get("refine", True),
                                method=args.method)
    emit(result, args.format)
    save(result, args.save)
    if args.plot:
        fig = result.plot()
        fig.savefig(args.plot, dpi=120)
    return 0
