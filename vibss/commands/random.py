"""``vibss random``: RMS response to the file's [random] PSD."""

from __future__ import annotations

import argparse
import sys

from .common import add_model_arguments, add_save_argument, check_save, emit, linear_from_args, save


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``random`` sub-command."""
    p = sub.add_parser("random", help="RMS response to the [random] PSD (output PSDs, 3-sigma)",
                       description="Output PSDs and RMS values of the [random] table's outputs under its input "
                                   "PSD (log-log between breakpoints), integrated adaptively on the exact FRF.")
    add_model_arguments(p)
    p.add_argument("--plot", metavar="PNG", help="also save the PSDs")
    add_save_argument(p, "output PSDs (CSV)")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Print the RMS table."""
    check_save(args.save, (".csv",))
    from ..errors import ArgumentError
    from ..random import PSD, random_response

    model = linear_from_args(args)
    spec = model.settings.get("random")
    if not spec:
        raise ArgumentError("vibss random: the model has no [random] table (docs/model-file.md); the packaged "
                            "example 'packaged_item' has one", argument="file")
    signal = spec["input"]
    last = signal.rsplit(".", 1)[-1]
    unit = {"acc": "(m/s^2)^2/Hz", "vel": "(m/s)^2/Hz", "disp": "m^2/Hz"}.get(last, "N^2/Hz")
    psd = PSD(spec["psd"]["frequency"], spec["psd"]["level"], unit=unit, name=f"[random] {signal}")
    r = random_response(model, {signal: psd}, spec.get("outputs"))
    emit(r, args.format)
    save(r, args.save, (".csv",))
    if args.plot:
        r.plot().savefig(args.plot, dpi=110, bbox_inches="tight")
        print(f"figure written to {args.plot}", file=sys.stderr)
    return 0
