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
    {"_version", "_deprecated", "errors", "threads", "_validate", "results", "methods", "costs", "model.units", "model.geometry", "model.limits", "io.tomlwriter",
     "linear.plant.memo", "linear.eigen.small", "linear.eigen.csr", "linear.plant.labels"},
    {"model", "linear.plant.plant", "linear.plant.terms", "linear.plant.branches", "linear.plant.sums", "linear.plant.assemble",
     "io.filetable"},
    {"io", "examples", "linear.eigen.directions", "linear.eigen.undamped", "linear.eigen.checks",
     "linear.eigen.jacobi", "linear.eigen.ritz", "linear.eigen.basis", "linear.solve.mass",
     "linear.plant.hysteresis", "frequency.compare", "frequency.result", "time.result"},
    {"linear.eigen.complex_modes", "linear.eigen.branch_modes", "linear.solve.banded", "linear.plant.names", "linear.plant.build",
     "linear.plant.mountform", "linear.solve.exact",
     "linear.solve.backends", "linear.solve.refine", "linear.solve.from_modes", "linear.solve.certified", "linear.solve.static", "nonlinear.kernels", "linear.project.krylov", "linear.project.subspace", "statics", "time.integrators",
     "time.phi", "time.recursion", "diagnostics"},
    {"linear", "modal"},
    {"frequency.kernels", "frequency.contracts", "frequency.lowrank", "frequency.terms", "frequency.grid",
     "frequency.statespace_kernels",
     "time.kernels", "time.branched", "time.inputs", "time.sampling", "time.drift", "studies", "measured.kernels",
     "io.matlab"},
    {"frequency", "time", "reduction", "design", "shock", "orders", "random", "control", "nonlinear", "insight",
     "measured"},
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
    raise AssertionError(f"module vibss.{module} is not placed in a layer in tests/project/test_api.py")


def _modules():
    for path in sorted(PACKAGE.rglob("*.py")):
        rel = path.relative_to(PACKAGE).with_suffix("")
        parts = rel.parts[:-1] if rel.name == "__init__" else rel.parts
        if parts:
            yield ".".join(parts), path


FIGURE_METHODS = {"campbell", "tripartite"}
"""Result methods that draw a figure under another name than ``plot*`` (a Campbell diagram, a
tripartite SRS chart): like ``plot*``, they may hand their result to vibss.plotting."""

CLIMBS: dict[tuple[str, str], str] = {
    ("io", "io.matlab"): "vibss.io.write_matlab stays where the file writers are; the MATLAB writer builds "
                         "the state space of a plant or model (layer 5), so vibss.io names it on first use "
                         "and never imports it otherwise",
}
"""Late imports that climb the layers, each with its reason; nothing else may climb."""


def _imports(module: str, path: Path):
    """Every import of a vibss module in ``path``, late ones (inside functions) included: yields
    ``(target, function or None, type_checking_only, line)``."""
    tree = ast.parse(path.read_text())
    package_parts = module.split(".") if path.name == "__init__.py" else module.split(".")[:-1]

    def walk(node, func, typing_only):
        for child in ast.iter_child_nodes(node):
            targets = []
            if isinstance(child, ast.ImportFrom) and child.level > 0:
                base = package_parts[: len(package_parts) - (child.level - 1)]
                target = ".".join(base + ([child.module] if child.module else []))
                targets = [target] if target else [a.name for a in child.names]
            elif isinstance(child, ast.ImportFrom) and (child.module or "").split(".")[0] == "vibss":
                target = child.module.partition(".")[2]
                targets = [target] if target else [a.name for a in child.names]
            elif isinstance(child, ast.Import):
                targets = [a.name.partition(".")[2] for a in child.names if a.name.split(".")[0] == "vibss"]
            for t in targets:
                yield t, func, typing_only, child.lineno
            inner = child.name if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef)) else func
            typing = typing_only or (isinstance(child, ast.If) and "TYPE_CHECKING" in ast.unparse(child.test))
            yield from walk(child, inner, typing)

    yield from walk(tree, None, False)


@pytest.mark.parametrize("module,path", list(_modules()), ids=lambda x: str(x))
def test_imports_only_go_down(module, path):
    """The one-way data flow of style.md: model -> assemble -> analyses -> results -> CLI.

    Late imports (inside functions) are walked too. By rule a result may hand itself to a figure
    (a ``plot*`` function or a FIGURE_METHODS method importing vibss.plotting); optional
    dependencies are not vibss modules, so they never climb. CLIMBS lists the rest, with reasons.
    """
    mine = _layer(module)
    for t, func, _, line in _imports(module, path):
        if _layer(t) <= mine:
            continue
        if t.split(".")[0] == "plotting" and func is not None and \
                (func.startswith("plot") or func in FIGURE_METHODS):
            continue
        assert (module, t) in CLIMBS, f"vibss.{module}:{line} imports vibss.{t}, a higher layer"


FIGURE_INPUTS = {"errors", "_validate", "_deprecated", "results", "model", "plotting"}
"""What a figure may import: it draws computed results and never computes or reads files."""

FIGURE_EXCEPTIONS = {
    ("plotting._scene", "linear.eigen.small"):
        "the principal axes of a body's 3x3 inertia tensor size and orient the box drawn for it: "
        "geometry of the drawing, through the one small-eigenproblem call",
    ("plotting.frequency", "frequency.compare"):
        "the FRAC of two given responses for the overlay's legend: it reads arrays, solves nothing",
    ("plotting.design", "design.axes"):
        "the deprecated alias vibss.plotting.design.plot_design_axes (one release), which computes",
}
"""Imports of figures outside FIGURE_INPUTS, each with its reason."""


@pytest.mark.parametrize("module,path", [(m, p) for m, p in _modules() if m.split(".")[0] == "plotting"],
                         ids=lambda x: str(x))
def test_figures_never_compute(module, path):
    """plotting/ imports no analysis and no file code, late imports included (type-only imports
    excepted: a figure may name the result type it draws)."""
    for t, _, typing_only, line in _imports(module, path):
        if typing_only or t.split(".")[0] in FIGURE_INPUTS or (module, t) in FIGURE_EXCEPTIONS:
            continue
        raise AssertionError(f"vibss.{module}:{line} imports vibss.{t}: figures receive computed results")


def test_allow_lists_are_live():
    """Every allow-list entry still names an import that exists (a fixed one is deleted)."""
    found = {(m, t) for m, p in _modules() for t, *_ in _imports(m, p)}
    assert not set(CLIMBS) - found and not set(FIGURE_EXCEPTIONS) - found


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
