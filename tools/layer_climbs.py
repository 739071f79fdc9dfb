"""Count how often the calls of a public function go back up a layer (issue 28's "climbs").

A static walk, no import of vibss: every module of the package is parsed, and each function's body
gives the functions it reaches -- names it calls or passes on (a registry's kernels, a callback),
resolved through the module's imports (late ones included), ``module.attr`` on an imported module,
``self.name`` inside a class, a method on an argument annotated with a vibss class, and module
constants (a ``METHODS`` table reaches every kernel it lists). From the entry function the walk goes
depth first, in source order, each function once. Its modules, in the order entered, form the path;
a *climb* is a step of the path into a module of a higher layer than the one before (the layer table
is ``LAYERS`` of the layering test, ``tests/**/test_api.py``); see :data:`SKIPPED` for what is left out.

Usage::

    python tools/layer_climbs.py                       # vibss.frequency.api:frequency_response
    python tools/layer_climbs.py vibss.time.api:simulate --path
    python tools/layer_climbs.py --trace --path        # the path one FRF of the example really takes

The static walk takes every branch (every method of a registry); ``--trace`` follows the one path a
call takes, with the profiler.
"""

from __future__ import annotations

import ast
import functools
import sys
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "vibss"


def layers() -> list[set[str]]:
    """The layer table, read from the layering test without importing it."""
    for path in sorted((ROOT / "tests").rglob("test_api.py")):
        for node in ast.parse(path.read_text()).body:
            if isinstance(node, ast.Assign) and any(getattr(t, "id", "") == "LAYERS" for t in node.targets):
                return [set(ast.literal_eval(s)) for s in node.value.elts]  # type: ignore[attr-defined]
    raise SystemExit("no LAYERS table in tests/**/test_api.py")


def layer_of(module: str, table: list[set[str]]) -> int:
    """The layer of the longest entry naming ``module`` (``vibss.`` stripped) or a package above it."""
    parts = module.removeprefix("vibss.").split(".")
    for k in range(len(parts), 0, -1):
        head = ".".join(parts[:k])
        for i, names in enumerate(table):
            if head in names:
                return i
    return len(table) - 1


@dataclass
class Module:
    name: str
    tree: ast.Module
    names: dict[str, str] = field(default_factory=dict)      # local name -> "module:qualname" or "module"
    functions: dict[str, ast.AST] = field(default_factory=dict)
    constants: dict[str, ast.AST] = field(default_factory=dict)


def _module_name(path: Path) -> str:
    rel = path.relative_to(PACKAGE.parent).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _absolute(module: str, node: ast.ImportFrom, is_package: bool) -> str:
    if not node.level:
        return node.module or ""
    base = module.split(".")
    if not is_package:
        base = base[:-1]
    base = base[:len(base) - node.level + 1]
    return ".".join(base + ([node.module] if node.module else []))


_BLOCKS = ("body", "orelse", "finalbody", "handlers", "cases")
"""The fields of a statement that hold statements: an import is a statement, so the walk for them
never enters an expression (most of a tree's nodes)."""


def _statements(tree: ast.AST) -> list[ast.AST]:
    """Every statement of ``tree`` at any depth (function and class bodies, branches, handlers)."""
    out: list[ast.AST] = []
    todo = [tree]
    while todo:
        node = todo.pop()
        out.append(node)
        for key in _BLOCKS:
            todo.extend(reversed(getattr(node, key, ())))
    return out


def load() -> dict[str, Module]:
    """Every module of the package, parsed once, with its imports (late ones too), functions and constants."""
    mods: dict[str, Module] = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        name = _module_name(path)
        mods[name] = Module(name, ast.parse(path.read_text()))
        mods[name].is_package = path.name == "__init__.py"  # type: ignore[attr-defined]
    for m in mods.values():
        for node in _statements(m.tree):
            if isinstance(node, ast.ImportFrom):
                src = _absolute(m.name, node, m.is_package)  # type: ignore[attr-defined]
                for a in node.names:
                    target = f"{src}.{a.name}"
                    m.names[a.asname or a.name] = target if target in mods else f"{src}:{a.name}"
            elif isinstance(node, ast.Import):
                for a in node.names:
                    if a.asname:
                        m.names[a.asname] = a.name
        for node in m.tree.body:
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                m.functions[node.name] = node
            elif isinstance(node, ast.ClassDef):
                m.functions[node.name] = node
                for sub in node.body:
                    if isinstance(sub, (ast.FunctionDef, ast.AsyncFunctionDef)):
                        m.functions[f"{node.name}.{sub.name}"] = sub
            elif isinstance(node, (ast.Assign, ast.AnnAssign)) and node.value is not None:
                targets = node.targets if isinstance(node, ast.Assign) else [node.target]
                for t in targets:
                    if isinstance(t, ast.Name):
                        m.constants[t.id] = node.value
    return mods


def _where(mods: dict[str, Module], ref: str) -> tuple[str, str] | None:
    """``(module, qualname)`` of a function or constant that ``ref`` ("mod:name") names, following re-exports."""
    for _ in range(10):
        mod, _, name = ref.partition(":")
        m = mods.get(mod)
        if m is None:
            return None
        if name in m.functions or name in m.constants:
            return mod, name
        if name in m.names:
            ref = m.names[name]
            if ":" not in ref:
                return None
            continue
        return None
    return None


def _annotated_classes(fn: ast.AST, m: Module, mods: dict[str, Module]) -> dict[str, tuple[str, str]]:
    """Arguments annotated with a vibss class: name -> (module, class)."""
    out: dict[str, tuple[str, str]] = {}
    if not isinstance(fn, (ast.FunctionDef, ast.AsyncFunctionDef)):
        return out
    args = fn.args
    for a in [*args.posonlyargs, *args.args, *args.kwonlyargs]:
        ann = a.annotation
        if ann is None:
            continue
        for sub in ast.walk(ann):
            if isinstance(sub, ast.Name):
                ref = m.names.get(sub.id, f"{m.name}:{sub.id}")
                hit = _where(mods, ref) if ":" in ref else None
                if hit and isinstance(mods[hit[0]].functions.get(hit[1]), ast.ClassDef):
                    out[a.arg] = hit
                    break
    return out


def reached(mods: dict[str, Module], mod: str, qual: str) -> list[tuple[str, str]]:
    """The functions (and constants' functions) that ``mod:qual`` reaches, in source order."""
    m = mods[mod]
    node = m.functions.get(qual) if qual in m.functions else m.constants.get(qual)
    if node is None:
        return []
    cls = qual.split(".")[0] if "." in qual else None
    typed = _annotated_classes(node, m, mods)
    out: list[tuple[str, str]] = []
    body = node.body if isinstance(node, ast.ClassDef) else [node]
    if isinstance(node, ast.ClassDef):          # a class reaches its __init__/__post_init__ only
        return [(mod, f"{qual}.{k}") for k in ("__init__", "__post_init__") if f"{qual}.{k}" in m.functions]
    for sub in (n for b in body for n in ast.walk(b)):
        hit = None
        if isinstance(sub, ast.Name) and isinstance(sub.ctx, ast.Load):
            if sub.id in m.functions or sub.id in m.constants:
                hit = (mod, sub.id)
            elif sub.id in m.names and ":" in m.names[sub.id]:
                hit = _where(mods, m.names[sub.id])
        elif isinstance(sub, ast.Attribute) and isinstance(sub.value, ast.Name):
            base = sub.value.id
            if base == "self" and cls and f"{cls}.{sub.attr}" in m.functions:
                hit = (mod, f"{cls}.{sub.attr}")
            elif base in typed:
                tm, tc = typed[base]
                if f"{tc}.{sub.attr}" in mods[tm].functions:
                    hit = (tm, f"{tc}.{sub.attr}")
            elif base in m.names and ":" not in m.names[base]:
                hit = _where(mods, f"{m.names[base]}:{sub.attr}")
        if hit and hit != (mod, qual) and hit not in out:
            out.append(hit)
    return out


def walk(entry: str, mods: dict[str, Module] | None = None) -> list[tuple[str, str]]:
    """The functions ``entry`` ("module:qualname") reaches, depth first in source order, each once
    (``mods``: the parsed package, :func:`load`, parsed here when not given)."""
    mods = load() if mods is None else mods
    mod, _, qual = entry.partition(":")
    seen: set[tuple[str, str]] = set()
    order: list[tuple[str, str]] = []

    def visit(node: tuple[str, str]) -> None:
        if node in seen:
            return
        seen.add(node)
        order.append(node)
        for nxt in reached(mods, *node):
            visit(nxt)

    sys.setrecursionlimit(10000)
    visit((mod, qual))
    return order


def _is_field(fn: ast.AST | None) -> bool:
    """A property: reading it is reading a field of a data type, not a step down the core."""
    return any(getattr(d, "id", getattr(d, "attr", "")) in ("property", "cached_property")
               for d in getattr(fn, "decorator_list", ()))


SKIPPED = 1
"""Layers 0 (errors, validators, the result protocol, units) and 1 (the frozen model and the Plant data
type) are left out of the path: every layer reads them, as it calls a builtin, and reading a field of a
Plant (or any property, :func:`_is_field`) is no walk down the core. Module constants (a registry table, a tolerance) are passed through:
the functions they list are on the path, the constant itself is not a step."""


def climbs(entry: str = "vibss.frequency.api:frequency_response") -> tuple[int, list[tuple[str, int]]]:
    """The number of climbs on the path of ``entry``, and the path: (module, layer) as entered."""
    table = layers()
    path: list[tuple[str, int]] = []
    mods = load()
    for mod, qual in walk(entry, mods):
        lay = layer_of(mod, table)
        if lay <= SKIPPED or qual in mods[mod].constants or _is_field(mods[mod].functions.get(qual)):
            continue
        if not path or path[-1][0] != mod:
            path.append((mod, lay))
    count = sum(1 for a, b in zip(path, path[1:]) if b[1] > a[1])
    return count, path


INLINE = ("<listcomp>", "<genexpr>", "<dictcomp>", "<setcomp>", "<module>")
"""Frames that are no call from module to module: comprehensions (part of the function that holds
them) and module bodies (a lazy import runs them on the first call; importing is not the path)."""


def _is_property_frame(frame: Any) -> bool:
    """A property or cached_property getter running (reading a field, not a step down the core)."""
    owner = frame.f_locals.get("self")
    if owner is None:
        return False
    for klass in type(owner).__mro__:
        attr = klass.__dict__.get(frame.f_code.co_name)
        if attr is not None:
            return isinstance(attr, (property, functools.cached_property))
    return False


def trace(run: Callable[[], Any]) -> tuple[int, list[tuple[str, int]]]:
    """Climbs on the path one call of ``run`` really takes: every vibss function entered, in order
    (the profiler's call events), with the same omissions as the static walk (:data:`SKIPPED`,
    properties, comprehensions)."""
    table = layers()
    seq: list[str] = []

    importing = [0]         # module bodies on the stack: what runs under them is an import

    def prof(frame: Any, event: str, arg: Any) -> None:
        if frame.f_code.co_name == "<module>":
            importing[0] += {"call": 1, "return": -1}.get(event, 0)
            return
        if event != "call" or importing[0]:
            return
        mod = frame.f_globals.get("__name__") or ""
        if not mod.startswith("vibss") or frame.f_code.co_name in INLINE or _is_property_frame(frame):
            return
        seq.append(mod)

    sys.setprofile(prof)
    try:
        run()
    finally:
        sys.setprofile(None)
    path: list[tuple[str, int]] = []
    for mod in seq:
        lay = layer_of(mod, table)
        if lay <= SKIPPED:
            continue
        if not path or path[-1][0] != mod:
            path.append((mod, lay))
    return sum(1 for a, b in zip(path, path[1:]) if b[1] > a[1]), path


def example_frf() -> Any:
    """One FRF of the built-in example, as the demo asks it: ground acceleration to the engine's."""
    import vibss

    model = vibss.load_example("powertrain")
    return lambda: vibss.frequency_response(model, ["ground.z.acc"], ["powertrain.z.acc"])


def main(argv: list[str]) -> int:
    entry = next((a for a in argv if not a.startswith("-")), "vibss.frequency.api:frequency_response")
    if "--trace" in argv:
        sys.path.insert(0, str(ROOT))
        entry = "frequency_response of the powertrain example (traced)"
        count, path = trace(example_frf())
    else:
        count, path = climbs(entry)
    if "--path" in argv:
        for (mod, lay), prev in zip(path, [None, *path]):
            up = " ^" if prev is not None and lay > prev[1] else ""
            print(f"{lay}  {mod}{up}")
    print(f"{entry}: {count} climbs over {len(path)} module steps")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
