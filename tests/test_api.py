"""API hygiene: documented parameters, no catch-all keywords, one-way imports between layers."""

from __future__ import annotations

import ast
import inspect
import re
from pathlib import Path

import pytest

import vibss

PACKAGE = Path(vibss.__file__).parent

# Layers, lowest first: a module may import only from its own layer or below.
LAYERS = [
    {"errors", "_validate", "results", "methods", "model.units", "model.geometry", "model.limits", "io.tomlwriter",
     "linear.plant.memo"},
    {"model", "linear.plant.plant", "linear.plant.terms", "linear.plant.branches", "io.filetable"},
    {"io", "examples", "linear.plant.assemble", "linear.eigen.directions", "linear.eigen.undamped", "linear.eigen.checks",
     "linear.eigen.jacobi", "linear.eigen.basis", "linear.solve.mass",
     "linear.plant.hysteresis"},
    {"linear.eigen.complex_modes", "linear.eigen.branch_modes", "linear.solve.banded", "linear.plant.names", "linear.plant.build",
     "linear.plant.mountform", "linear.plant.signals", "linear.solve.exact",
     "linear.solve.backends", "linear.solve.certified", "linear.solve.static", "linear.eigen.projection", "linear.project.krylov", "linear.project.subspace", "statics", "time.integrators",
     "time.phi", "time.recursion", "diagnostics"},
    {"linear", "modal"},
    {"frequency.kernels", "frequency.lowrank", "frequency.terms", "time.kernels", "time.branched", "studies"},
    {"frequency", "time", "reduction", "design", "shock", "orders", "random", "control"},
    {"plotting", "report"},
    {"commands", "cli", "__main__"},
]


def _layer(module: str) -> int:
    """The layer of the longest entry of LAYERS that names ``module`` or a package above it."""
    if module in ("", "__version__"):       # the package root: only the top layer may use it
        return len(LAYERS) - 1
    parts = module.split(".")
    for k in range(len(parts), 0, -1):
        head = ".".join(parts[:k])
        for i, names in enumerate(LAYERS):
            if head in names:
                return i
    raise AssertionError(f"module vibss.{module} is not placed in a layer in tests/test_api.py")


def _modules():
    for path in sorted(PACKAGE.rglob("*.py")):
        rel = path.relative_to(PACKAGE).with_suffix("")
        parts = rel.parts[:-1] if rel.name == "__init__" else rel.parts
        if parts:
            yield ".".join(parts), path


@pytest.mark.parametrize("module,path", list(_modules()), ids=lambda x: str(x))
def test_imports_only_go_down(module, path):
    """The one-way data flow of style.md: model -> assemble -> analyses -> results -> CLI.

    Module-level imports only: the style allows late imports of optional dependencies (plotting)
    inside ``.plot()`` and ``.to_pandas()``.
    """
    mine = _layer(module)
    tree = ast.Module(body=[n for n in ast.parse(path.read_text()).body], type_ignores=[])
    package_parts = module.split(".") if path.name == "__init__.py" else module.split(".")[:-1]
    for node in tree.body:
        if isinstance(node, ast.ImportFrom) and node.level > 0:
            base = package_parts[: len(package_parts) - (node.level - 1)]
            target = ".".join(base + ([node.module] if node.module else []))
            if not target:
                targets = [a.name for a in node.names]
            else:
                targets = [target]
            for t in targets:
                assert _layer(t) <= mine, f"vibss.{module} imports vibss.{t}, a higher layer"


def _public_callables():
    for name in vibss.__all__:
        obj = getattr(vibss, name)
        if inspect.isfunction(obj):
            yield name, obj
        elif inspect.isclass(obj) and not issubclass(obj, BaseException):
            for meth_name, meth in vars(obj).items():
                if inspect.isfunction(meth) and not meth_name.startswith("_"):
                    yield f"{name}.{meth_name}", meth


@pytest.mark.parametrize("name,func", list(_public_callables()), ids=lambda x: x if isinstance(x, str) else "")
def test_no_catch_all_keywords(name, func):
    """Unknown keywords must fail loudly, not be swallowed by **kwargs (except plot pass-through)."""
    sig = inspect.signature(func)
    var_kw = [p for p in sig.parameters.values() if p.kind is p.VAR_KEYWORD]
    if var_kw:
        assert "plot" in name or "Parameters" in (func.__doc__ or ""), name
        assert re.search(r"\*\*" + var_kw[0].name, func.__doc__ or ""), \
            f"{name} accepts **{var_kw[0].name} without documenting where it goes"


@pytest.mark.parametrize("name", [n for n in vibss.__all__ if inspect.isfunction(getattr(vibss, n))])
def test_public_functions_document_every_parameter(name):
    func = getattr(vibss, name)
    doc = func.__doc__ or ""
    assert "Parameters" in doc or not inspect.signature(func).parameters, f"{name} has no Parameters section"
    for p in inspect.signature(func).parameters.values():
        if p.kind in (p.VAR_POSITIONAL, p.VAR_KEYWORD):
            continue
        assert re.search(rf"^\s*{p.name}\b.*:", doc, re.M) or re.search(rf"^\s*[\w, ]*\b{p.name}\b[\w, ]*:", doc, re.M), \
            f"{name}: parameter {p.name!r} is not documented"


@pytest.mark.parametrize("module,path", list(_modules()), ids=lambda x: str(x))
def test_only_plotting_imports_matplotlib_at_module_level(module, path):
    """Plotting is separate (style.md): other modules import matplotlib only inside .plot().

    (python-control itself imports matplotlib when it is imported, so the process will have it;
    the rule keeps vibss's own layering clean.)
    """
    if module.split(".")[0] in ("plotting", "report"):
        return
    for node in ast.parse(path.read_text()).body:
        names = [a.name for a in node.names] if isinstance(node, ast.Import) else \
                [node.module or ""] if isinstance(node, ast.ImportFrom) else []
        assert not any(n.startswith("matplotlib") for n in names), f"vibss.{module} imports matplotlib"
