"""``vibss report``: the full study of a model file, on screen and as an HTML page with figures."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from .common import load_from_args


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``report`` sub-command."""
    p = sub.add_parser(
        "report", help="full study: static, modes, damped modes, FRFs, time responses; HTML + PNG",
        description="Run every analysis that applies to the model - static deflection (with gravity "
                    "where the file sets it), undamped modes with the kinetic-energy table, damped "
                    "modes, the steady-state response to the file's sine sweeps with their "
                    "transmissibility, and the time response to its transient excitations - print "
                    "the text report, and write PNG figures, report.txt and one self-contained "
                    "index.html into a folder.")
    p.add_argument("file", nargs="?", metavar="FILE", help="model file (.toml or .json)")
    p.add_argument("--example", metavar="NAME",
                   help="use a built-in example model instead of FILE (see `vibss example list`)")
    p.add_argument("--out", metavar="DIR", type=Path, default=None,
                   help="folder for index.html and the figures (default ./vibss-report-<model>)")
    p.add_argument("--no-figures", action="store_true",
                   help="text report only (no matplotlib needed, nothing written)")
    p.add_argument("--sections", metavar="KEYS", default=None,
                   help="comma-separated sections to run (the others are listed as not asked for): "
                        "model, static, modes, damped, design, control, frequency, harmonic, orders, time")
    p.add_argument("--quiet", action="store_true", help="no text report and no progress on the terminal")
    p.set_defaults(func=run, format="text")


def run(args: argparse.Namespace) -> int:
    """Run the study, print it and write the folder."""
    from ..report import default_folder, progress_on_stderr, render_report, study

    model = load_from_args(args)
    source = f"example {args.example}" if args.example else str(args.file)
    progress = None if args.quiet else progress_on_stderr()
    report = study(model, figures=not args.no_figures, progress=progress, source=source, sections=args.sections)
    if not args.quiet:
        sys.stdout.write(report.text())
    if not args.no_figures:
        out = args.out or default_folder(args.example or str(args.file), model)
        index, report = render_report(report, out)
        print(f"vibss: report written to {index}", file=sys.stderr)
    failed = report.failed
    if failed:                          # everything that worked is written; the status says what did not
        print(f"vibss: {len(failed)} section(s) failed: {', '.join(failed)}; the others are written "
              "(see their notes)", file=sys.stderr)
        return 3
    return 0

