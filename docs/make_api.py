"""Write docs/api.md, the API reference, from the docstrings of ``vibss.__all__``.

Run ``python docs/make_api.py``; ``tests/project/test_docs.py`` fails when the file is stale or a public
object has no docstring (the "docs build without warnings" check).
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil
import re
import sys
from pathlib import Path

import vibss

OUT = Path(__file__).with_name("api.md")


def _doc_of(v: object) -> str:
    """Docstring of a function or property (of its getter)."""
    return ((v.fget.__doc__ if isinstance(v, property) else getattr(v, "__doc__", None)) or "")


def _first_paragraph(doc: str) -> str:
    return inspect.cleandoc(doc).split("\n\n")[0].replace("\n", " ")


def _modules() -> list[str]:
    """Every module of the package, in the order of its layout (packages before their modules)."""
    names = [m.name for m in pkgutil.walk_packages(vibss.__path__, "vibss.")
             if not m.name.split(".")[-1].startswith("_")]
    return sorted(names, key=lambda n: n.split("."))


def _module_table() -> list[str]:
    """A table of the modules and the first line of each one's docstring (see docs/architecture.md)."""
    rows = ["## Modules", "",
            "The layout (layers and data flow: [architecture.md](architecture.md)). Every public name "
            "below also says the module that defines it.", "", "| module | what it holds |", "|---|---|"]
    for name in _modules():
        doc = importlib.import_module(name).__doc__ or ""
        first = _first_paragraph(doc).split(". ")[0].rstrip(".") if doc.strip() else ""
        first = re.sub(r":\w+:`~?([^`]+)`", r"`\1`", first).replace("``", "`")   # rst roles -> Markdown
        rows.append(f"| `{name}` | {first.replace('|', '/')} |")
    return rows + [""]


def _where(obj: object) -> str:
    module = getattr(obj, "__module__", None) or ""
    return f" in `{module}`" if module.startswith("vibss") else ""


def render() -> tuple[str, list[str]]:
    """The Markdown text and the list of problems (public objects without a docstring)."""
    problems: list[str] = []
    lines = ["# API reference", "",
             "Generated from the docstrings by `docs/make_api.py`; every name is importable as "
             "`vibss.<name>`. Full docstrings (parameters with units, examples): `help(vibss.<name>)`.", ""]
    lines += _module_table()
    groups = {"Model": [], "Analyses": [], "Results": [], "Files": [], "Errors": [], "Other": []}
    for name in sorted(vibss.__all__, key=str.lower):
        obj = getattr(vibss, name)
        if inspect.isclass(obj) and issubclass(obj, Warning | Exception):
            group = "Errors"
        elif name in ("Body", "MountType", "Mount", "ControlPoint", "Load", "Model", "Orientation",
                      "Excitation", "symmetric", "GROUND", "DOF_NAMES", "Assembly", "assemble", "Plant",
                      "build_plant"):
            group = "Model"
        elif inspect.isclass(obj):
            group = "Results"
        elif name.startswith(("load", "dump", "example")):
            group = "Files"
        elif inspect.isfunction(obj):
            group = "Analyses"
        else:
            group = "Other"
        groups[group].append(name)
    for group, names in groups.items():
        if not names:
            continue
        lines += [f"## {group}", ""]
        for name in names:
            obj = getattr(vibss, name)
            doc = getattr(obj, "__doc__", None) if (inspect.isclass(obj) or callable(obj)) else None
            if inspect.isfunction(obj) or inspect.isclass(obj):
                if not doc:
                    problems.append(f"{name} has no docstring")
                    continue
                try:
                    sig = str(inspect.signature(obj))
                except (TypeError, ValueError):
                    sig = "(...)"
                kind = "class" if inspect.isclass(obj) else "function"
                lines += [f"### `{name}{sig if kind == 'function' else ''}`", "",
                          f"*{kind}*{_where(obj)} — {_first_paragraph(doc)}", ""]
                if inspect.isclass(obj):
                    members = [m for m, v in vars(obj).items() if not m.startswith("_")
                               and (inspect.isfunction(v) or isinstance(v, property))]
                    for m in members:
                        v = vars(obj)[m]
                        mdoc = (v.fget.__doc__ if isinstance(v, property) else v.__doc__) or ""
                        if not mdoc:                # an override documented by its base class
                            mdoc = next((_doc_of(vars(base)[m]) for base in obj.__mro__[1:]
                                         if m in vars(base) and _doc_of(vars(base)[m])), "")
                        if not mdoc:
                            problems.append(f"{name}.{m} has no docstring")
                        lines.append(f"- `.{m}`: {_first_paragraph(mdoc) if mdoc else ''}")
                    if members:
                        lines.append("")
            elif inspect.ismodule(obj):      # by name and summary: a module's repr holds its path
                lines += [f"### `{name}`", "", f"*module* `{obj.__name__}` — {_first_paragraph(obj.__doc__ or '')}", ""]
            else:
                lines += [f"### `{name}`", "", f"constant: `{obj!r}`", ""]
    return "\n".join(lines).rstrip() + "\n", problems


if __name__ == "__main__":
    text, problems = render()
    OUT.write_text(text)
    for p in problems:
        print(f"warning: {p}", file=sys.stderr)
    sys.exit(1 if problems else 0)
