"""Arguments and output helpers shared by the sub-commands."""

from __future__ import annotations

import argparse
import sys
from typing import Any

from ..errors import ModelError
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ..model.model import Model

__all__ = ["add_model_arguments", "load_from_args", "emit", "finite_json"]


def add_model_arguments(parser: argparse.ArgumentParser) -> None:
    """Add ``FILE`` / ``--example NAME`` and ``--format {text,json}``."""
    parser.add_argument("file", nargs="?", metavar="FILE", help="model file (.toml or .json)")
    parser.add_argument("--example", metavar="NAME",
                        help="use a built-in example model instead of FILE (see `vibss example list`)")
    parser.add_argument("--format", choices=("text", "json"), default="text",
                        help="text report (default) or the JSON of the spec, in SI units")


def load_from_args(args: argparse.Namespace) -> Model:
    """The model named by ``FILE`` or ``--example``."""
    from ..io.modelfile import load_example, load_model

    if args.example and args.file:
        raise ModelError("give either FILE or --example, not both")
    if args.example:
        return load_example(args.example)
    if not args.file:
        raise ModelError("no model given: pass a model FILE or --example NAME")
    return load_model(args.file)


def finite_json(value: Any) -> Any:
    """Old name of :func:`vibss.results.jsonable` (non-finite numbers as None)."""
    from ..results import jsonable

    return jsonable(value)


def emit(result: Any, fmt: str, out: Any = None) -> None:
    """Print a result as its text report or as strict JSON (non-finite numbers as null)."""
    out = out or sys.stdout
    if fmt == "json":
        out.write(result.to_json(indent=2))
        out.write("\n")
    else:
        out.write(result.report())
        out.write("\n")
