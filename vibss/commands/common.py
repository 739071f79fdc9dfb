"""Arguments and output helpers shared by the sub-commands."""

from __future__ import annotations

import argparse
import importlib
import sys
from collections.abc import Iterator, Sequence
from typing import TYPE_CHECKING, Any

from ..errors import ModelError

if TYPE_CHECKING:
    from ..model.model import Model

__all__ = ["add_model_arguments", "load_from_args", "emit", "finite_json", "add_save_argument", "check_save", "save",
           "RegistryNames", "add_method_argument"]

SAVE_FORMATS = {".csv": "CSV", ".uff": "UFF", ".unv": "UFF"}


class RegistryNames(Sequence[str]):
    """The names of an analysis' ``METHODS`` registry (and ``extra`` names such as ``"auto"``), read
    from the registry on first use: the command line offers what the library has, and building the
    parser (``vibss --help``) imports no analysis.

    Parameters
    ----------
    module : str
        The module holding the registry (``"vibss.time.methods"``).
    extra : sequence of str
        Names the analysis accepts besides its registry's, listed first.
    attribute : str
        The registry's name in ``module``.
    """

    def __init__(self, module: str, extra: Sequence[str] = (), attribute: str = "METHODS") -> None:
        self.module, self.extra, self.attribute = module, tuple(extra), attribute
        self._names: tuple[str, ...] | None = None

    @property
    def names(self) -> tuple[str, ...]:
        """The names, the registry imported on first use."""
        if self._names is None:
            registry = getattr(importlib.import_module(self.module), self.attribute)
            self._names = (*self.extra, *registry)
        return self._names

    def __getitem__(self, i: Any) -> Any:
        return self.names[i]

    def __len__(self) -> int:
        return len(self.names)

    def __iter__(self) -> Iterator[str]:
        return iter(self.names)

    def __contains__(self, name: object) -> bool:
        return name in self.names

    def __repr__(self) -> str:
        return f"RegistryNames({self.module}.{self.attribute})"


def add_method_argument(parser: argparse.ArgumentParser, module: str, what: str) -> None:
    """``--method NAME``: ``auto`` (default) or a name of ``module``'s ``METHODS`` registry."""
    parser.add_argument("--method", default="auto", metavar="METHOD", choices=RegistryNames(module, ("auto",)),
                        help=f"{what}: one of %(choices)s (default auto)")


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


def linear_from_args(args: argparse.Namespace) -> Model:
    """The model named by ``FILE`` or ``--example``, linearised at its operating point when it has
    nonlinear mounts (stops, curves): the tangent model the linear commands analyse, said on stderr
    (as the report's sections say it in their notes)."""
    from ..nonlinear.kernels import nonlinear_mounts

    model = load_from_args(args)
    if not nonlinear_mounts(model):
        return model
    from ..nonlinear.api import operating_point

    who = " ".join(x for x in ("vibss", getattr(args, "command", None)) if x)
    print(f"{who}: nonlinear mounts: analysing the tangent model at the operating point (vibss static shows it)",
          file=sys.stderr)
    return operating_point(model).tangent


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


def add_save_argument(parser: argparse.ArgumentParser, what: str) -> None:
    """Add ``--save FILE``: the result as test data, CSV or UFF by the file's suffix."""
    parser.add_argument("--save", metavar="FILE",
                        help=f"also write the {what} as test data: FILE.csv (CSV) or FILE.uff / .unv "
                             "(universal file, needs vibss[uff])")


def check_save(path: str | None, formats: tuple[str, ...] = (".csv", ".uff", ".unv")) -> str:
    """The suffix of ``--save FILE`` ('' when not given), checked before any work is done."""
    if not path:
        return ""
    from pathlib import Path

    suffix = Path(path).suffix.lower()
    if suffix not in formats:
        from ..errors import ArgumentError

        raise ArgumentError(f"--save {path}: the suffix says the format; expected one of {', '.join(formats)}",
                            argument="--save", received=path)
    return suffix


def save(result: Any, path: str | None, formats: tuple[str, ...] = (".csv", ".uff", ".unv")) -> None:
    """Write ``result`` to ``path`` (nothing when None) as CSV or UFF, chosen by the suffix."""
    suffix = check_save(path, formats)
    if not suffix or path is None:
        return
    if suffix == ".csv":
        from ..io.csvdata import write_csv

        write_csv(result, path)
    else:
        from ..io.uff import write_uff

        write_uff(result, path)
    print(f"{SAVE_FORMATS[suffix]} written to {path}", file=sys.stderr)
