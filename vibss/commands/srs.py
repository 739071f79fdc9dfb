"""``vibss srs``: shock response spectra of the file's [shock] input and responses, with the spec check."""

from __future__ import annotations

import argparse
import sys

from .common import add_model_arguments, emit, load_from_args


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``srs`` sub-command."""
    p = sub.add_parser("srs", help="shock response spectra of the [shock] input and responses",
                       description="Shock response spectra (absolute acceleration, maximax, ramp-invariant "
                                   "filter) of the [shock] table's excitation and of the responses it names, "
                                   "and the input's spectrum against the table's spec envelope.")
    add_model_arguments(p)
    p.add_argument("--plot", metavar="PNG", help="also save the spectra")
    p.add_argument("--tripartite", metavar="PNG", help="also save the input's tripartite plot")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Print the spectra."""
    from ..errors import ArgumentError
    from ..shock.filespec import run_shock

    model = load_from_args(args)
    if "shock" not in model.settings:
        raise ArgumentError("vibss srs: the model has no [shock] table (docs/model-file.md); the packaged "
                            "example 'packaged_item' has one", argument="file")
    r = run_shock(model)
    emit(r, args.format)
    if args.plot:
        r.plot().savefig(args.plot, dpi=110, bbox_inches="tight")
        print(f"figure written to {args.plot}", file=sys.stderr)
    if args.tripartite:
        next(iter(r.spectra.values())).tripartite().savefig(args.tripartite, dpi=110, bbox_inches="tight")
        print(f"figure written to {args.tripartite}", file=sys.stderr)
    return 0
