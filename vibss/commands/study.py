"""``vibss study``: one analysis over a grid of mount-parameter values, as a table (CSV or JSON)."""

from __future__ import annotations

import argparse
import sys

from ..errors import ArgumentError
from .common import RegistryNames, load_from_args

ANALYSES = RegistryNames("vibss.design.grid", attribute="ANALYSES")
"""Names of :data:`vibss.design.grid.ANALYSES`, read from it when first needed (building the parser
imports no analysis)."""


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``study`` sub-command."""
    p = sub.add_parser("study", help="an analysis over a grid of mount rates/positions/angles",
                       description="Run an analysis on every combination of parameter values (a full "
                                   "grid) and print one row per variant. Parameters are "
                                   "'<mount>.<kind>' (k1 k2 k3 [N/m], x y z shifts [m], rx ry rz "
                                   "[rad]); e.g. --vary engine.k3=2e5,2.5e5,3e5.")
    p.add_argument("file", nargs="?", metavar="FILE", help="model file (.toml or .json)")
    p.add_argument("--example", metavar="NAME", help="use a built-in example model instead of FILE")
    p.add_argument("--vary", action="append", metavar="PARAM=V1,V2,...",
                   help="a parameter and its values in SI (repeatable: every combination is run); "
                        "default: the model file's [study] table")
    p.add_argument("--analysis", choices=ANALYSES, metavar="ANALYSIS",
                   help="analysis: one of %(choices)s (default: the file's [study] analysis, else modes)")
    p.add_argument("--client", metavar="ADDRESS",
                   help="run on Dask: a scheduler address, or 'local' for a 2-worker LocalCluster")
    p.add_argument("--format", choices=("csv", "json"), default="csv", help="table format (default csv)")
    p.add_argument("--progress", action="store_true", help="show a progress bar on stderr")
    p.set_defaults(func=run)


def _grid(items: list[str]) -> dict[str, list[float]]:
    grid = {}
    for item in items:
        name, sep, values = item.partition("=")
        try:
            grid[name.strip()] = [float(v) for v in values.split(",")]
        except ValueError:
            sep = ""
        if not sep or not name.strip():
            raise ArgumentError(f"--vary: expected PARAM=V1,V2,... with numbers, got {item!r}",
                                argument="vary", received=item)
    return grid


def run(args: argparse.Namespace) -> int:
    """Print the study's table."""
    from ..design.grid import grid_study

    model = load_from_args(args)
    spec = dict(model.settings.get("study", {}))       # the file's [study] table (SI)
    analysis = args.analysis or spec.get("analysis", "modes")
    grid = _grid(args.vary) if args.vary else spec.get("grid")
    table = None if args.vary else spec.get("table")
    if grid is None and table is None:
        raise ArgumentError("vibss study: nothing to vary: give --vary PARAM=V1,V2,... or a [study] table "
                            "in the model file (docs/model-file.md)", argument="vary")
    df = grid_study(model, analysis, grid=grid, table=table, client=args.client, progress=bool(args.progress))
    if args.format == "json":
        sys.stdout.write(df.to_json(orient="records", indent=2) + "\n")
    else:
        sys.stdout.write(df.to_csv())
    return 0
