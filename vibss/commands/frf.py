"""``vibss frf``: frequency response (steady state of the file's swept-sine excitations, or FRFs)."""

from __future__ import annotations

import argparse
import sys

from ..errors import ModelError
from .common import (add_method_argument, add_model_arguments, add_save_argument, check_save, emit, linear_from_args,
                     load_from_args, save)


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
    p.add_argument("--harmonic-balance", action="store_true",
                   help="the steady periodic response with the nonlinear mounts (stops, curves) that the file's "
                        "[analysis] harmonic_balance table asks for, by harmonic balance with its turning points "
                        "(the default when the file asks for one and has no steady sweep and no --input is given); "
                        "--f1/--f2/--points/--output override the table")
    p.add_argument("--harmonics", type=int, metavar="H", help="with --harmonic-balance: highest harmonic kept")
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

    if args.harmonic_balance or (not args.input and _asks_harmonic_balance(args)):
        return _harmonic(args)
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


def _asks_harmonic_balance(args: argparse.Namespace) -> bool:
    """Whether the file asks for a harmonic balance and has no steady sweep of its own."""
    from ..studies import steady_sweeps

    model = load_from_args(args)
    return bool((model.settings or {}).get("harmonic_balance")) and not steady_sweeps(model)


def _harmonic(args: argparse.Namespace) -> int:
    """``vibss frf --harmonic-balance``: the file's harmonic balance, with the options' overrides."""
    from ..io.harmonicfile import harmonic_balance_arguments
    from ..nonlinear.harmonic import harmonic_balance

    if args.save and not args.save.lower().endswith(".csv"):
        raise ModelError(f"--save {args.save}: a harmonic balance is written as CSV only (one row per branch point)")
    model = load_from_args(args)
    spec = dict((model.settings or {}).get("harmonic_balance") or {})
    if not spec:
        raise ModelError("--harmonic-balance: the model file has no [analysis] harmonic_balance table "
                         "(inputs = { signal = amplitude }, f1, f2, harmonics ...; see docs/model-file.md)")
    for key in ("f1", "f2", "points", "harmonics"):
        if getattr(args, key) is not None:
            spec[key] = getattr(args, key)
    if args.output:
        spec["outputs"] = list(args.output)
    if not spec["f2"] > spec["f1"]:
        raise ModelError(f"--harmonic-balance: f2 ({spec['f2']} Hz) must be greater than f1 ({spec['f1']} Hz)")
    result = harmonic_balance(model, **harmonic_balance_arguments(spec, model.excitations))
    emit(result, args.format)
    if args.format == "text":
        print(result.turning_table().render())
    if args.save:
        result.to_pandas().to_csv(args.save, index=False)
        print(f"harmonic balance written to {args.save}", file=sys.stderr)
    if args.plot:
        result.plot().savefig(args.plot, dpi=120)
    return 0
