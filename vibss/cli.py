"""The ``vibss`` command line: a thin layer over the library.

Each sub-command lives in :mod:`vibss.commands` as a module with ``register(subparsers)``, which
adds its parser and sets ``func(args) -> int``. Errors in the model or the analysis print as one
line on stderr with exit status 2 (model) or 3 (analysis), never a traceback.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from . import __version__
from .commands import COMMANDS
from .errors import AnalysisError, ModelError

__all__ = ["main", "build_parser"]

DESCRIPTION = """\
vibss: vibration of rigid bodies on flexible mounts (engines, machines, equipment on isolators).

Describe bodies and mounts in a TOML model file (see docs/model-file.md), then run an analysis:
  vibss modes model.toml            natural frequencies, mode shapes, kinetic-energy table
  vibss static model.toml           static deflection under the file's loads (and gravity)
  vibss modes --example prism       the same on a built-in example (vibss example list)
Add --format json for machine-readable results (SI units).
"""


def build_parser() -> argparse.ArgumentParser:
    """The argument parser with every sub-command registered."""
    parser = argparse.ArgumentParser(
        prog="vibss", description=DESCRIPTION, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--version", action="version", version=f"vibss {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for module in COMMANDS:
        module.register(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 1
    try:
        return int(args.func(args) or 0)
    except ModelError as exc:
        print(f"vibss: error in model: {exc}", file=sys.stderr)
        return 2
    except AnalysisError as exc:
        print(f"vibss: analysis failed: {exc}", file=sys.stderr)
        return 3
    except ValueError as exc:  # e.g. an unknown method name: the library's message names it
        print(f"vibss: error: {exc}", file=sys.stderr)
        return 2
    except (FileNotFoundError, IsADirectoryError, PermissionError) as exc:
        print(f"vibss: {exc.strerror}: {exc.filename}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # pragma: no cover - e.g. piped into head
        return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
