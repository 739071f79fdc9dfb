"""``vibss example``: list the built-in example models, or copy one for editing."""

from __future__ import annotations

import argparse
import shutil
import sys
import tomllib
from pathlib import Path



def describe(name: str) -> tuple[str, str]:
    """``(title, one-line description)`` of example ``name``.

    The title is the file's ``[model] name``; the description is the first sentence of the
    file's leading comment (``''`` if it has none).
    """
    from ..io.modelfile import example_path

    path = example_path(name)
    text = path.read_text(encoding="utf-8")
    try:
        title = str(tomllib.loads(text).get("model", {}).get("name", name))
    except tomllib.TOMLDecodeError:
        title = name
    lines = []
    for line in text.splitlines():
        if not line.startswith("#"):
            break
        body = line.lstrip("#").strip()
        if not body:
            break
        lines.append(body)
    lead = " ".join(lines)
    cut = lead.find(". ")
    first = lead[:cut + 1] if cut >= 0 else lead
    return title, first if len(first) <= 110 else first[:first.rfind(" ", 0, 108)] + " ..."


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``example`` sub-command with ``list`` and ``write``."""
    p = sub.add_parser("example", help="list the built-in example models, or copy one to edit",
                       description="Built-in example model files. `vibss example list` names them; "
                                   "`vibss example write NAME [PATH]` copies one (default "
                                   "./NAME.toml) so you can edit it and run `vibss report PATH`.")
    actions = p.add_subparsers(dest="action", metavar="ACTION")
    ls = actions.add_parser("list", help="name and one-line description of each example")
    ls.set_defaults(func=run_list)
    w = actions.add_parser("write", help="copy an example model file for editing")
    w.add_argument("name", metavar="NAME", help="example name (see `vibss example list`)")
    w.add_argument("path", nargs="?", metavar="PATH", type=Path, default=None,
                   help="file or folder to write to (default ./NAME.toml)")
    w.add_argument("--force", action="store_true", help="overwrite an existing file")
    w.set_defaults(func=run_write)
    p.set_defaults(func=lambda args: (p.print_help(), 1)[1])


def run_list(args: argparse.Namespace) -> int:
    """Print each example's name, title and description."""
    from ..io.modelfile import example_names

    names = example_names()
    width = max((len(n) for n in names), default=4)
    for n in names:
        title, text = describe(n)
        print(f"{n:<{width}}  {title}")
        if text and text != title:
            print(f"{'':<{width}}  {text}")
    return 0


def run_write(args: argparse.Namespace) -> int:
    """Copy example ``args.name`` to ``args.path``."""
    from ..io.modelfile import example_path

    src = example_path(args.name)
    dest = args.path if args.path is not None else Path(src.name)
    if dest.is_dir():
        dest = dest / src.name
    if dest.exists() and not args.force:
        print(f"vibss: {dest} exists; pass --force to overwrite it", file=sys.stderr)
        return 1
    shutil.copyfile(src, dest)
    print(f"wrote {dest} (example {src.stem!r}); try: vibss report {dest}", file=sys.stderr)
    return 0
