"""The ``vibss`` command line: a thin layer over the library.

Each sub-command lives in :mod:`vibss.commands` as a module with ``register(subparsers)``, which
adds its parser and sets ``func(args) -> int``. Errors in the model or the analysis print as one
line on stderr with exit status 2 (model) or 3 (analysis), never a traceback; any other error (a
bug) prints one line asking for a report and exits with :data:`INTERNAL_ERROR` (70, BSD's
``EX_SOFTWARE``); ``vibss --debug ...`` prints the traceback too.
"""

from __future__ import annotations

import argparse
import sys
import traceback
import warnings
from collections.abc import Sequence
from typing import Any

from ._version import __version__
from .commands import COMMANDS
from .errors import AnalysisError, ArgumentError, ModelError, VibssError

__all__ = ["main", "build_parser", "INTERNAL_ERROR"]

INTERNAL_ERROR = 70
"""Exit status of an unexpected error (a bug in vibss; BSD's ``EX_SOFTWARE``)."""

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
    parser.add_argument("--debug", action="store_true",
                        help="print the Python traceback of an error (for reporting a bug)")
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
        with warnings.catch_warnings():
            warnings.showwarning = _one_line          # no source line, no package path
            return int(args.func(args) or 0)
    except Exception as exc:
        if getattr(args, "debug", False):
            traceback.print_exc()
        return _status(exc)
    except KeyboardInterrupt:
        print("vibss: interrupted", file=sys.stderr)
        return 130


def _one_line(message: Warning | str, category: type[Warning], filename: str, lineno: int,
              file: Any = None, line: str | None = None) -> None:
    """A warning as one line on stderr, ``vibss: warning: ...``: what a user of the command line reads,
    without the Python source line and the installed package's path that the default format shows."""
    text = " ".join(str(message).split())
    kind = "" if issubclass(category, (UserWarning,)) else f"{category.__name__}: "
    print(f"vibss: warning: {kind}{text}", file=sys.stderr if file is None else file)


def _status(exc: Exception) -> int:
    """One line on stderr for ``exc`` and the exit status (never a traceback)."""
    if isinstance(exc, ArgumentError):            # a bad option or name: not the model's fault
        print(f"vibss: error: {exc}", file=sys.stderr)
        return 2
    if isinstance(exc, ModelError):
        print(f"vibss: error in model: {exc}", file=sys.stderr)
        return 2
    if isinstance(exc, AnalysisError):
        print(f"vibss: analysis failed: {exc}", file=sys.stderr)
        return 3
    if isinstance(exc, (ValueError, VibssError)):  # an unknown name, a missing optional dependency ...
        print(f"vibss: error: {exc}", file=sys.stderr)
        return 2
    if isinstance(exc, (FileNotFoundError, IsADirectoryError, PermissionError)):
        print(f"vibss: {exc.strerror}: {exc.filename}", file=sys.stderr)
        return 2
    if isinstance(exc, BrokenPipeError):  # pragma: no cover - e.g. piped into head
        return 0
    text = " ".join(str(exc).split())       # a bug: one line, never a traceback (unless --debug)
    text = text if len(text) <= 300 else text[:297] + "..."
    print(f"vibss: internal error ({type(exc).__name__}{': ' + text if text else ''}); please report "
          "it to the vibss maintainers with the command, the model file and `vibss --version` "
          "(`vibss --debug ...` prints the traceback)", file=sys.stderr)
    return INTERNAL_ERROR


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
