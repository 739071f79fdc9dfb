"""Execute the example notebooks (examples/*.ipynb) with nbclient.

One Jupyter kernel per test process runs them all, its namespace reset (``%reset -f``), its figures
closed and matplotlib's settings restored before each notebook: a fresh kernel for each cost 2-4 s of
start-up and imports, a third of the notebooks' time in the suite.

The notebook tools (nbformat, nbclient, jupyter_client, ipykernel) are in the test extra: a missing one is an
error, not a skip, so CI cannot pass without running the notebooks.
"""

from __future__ import annotations


import os

import ipykernel  # noqa: F401  (the kernel the notebooks run in)
import jupyter_client
import nbclient
import nbformat
import pytest
from cases import ROOT

EXAMPLES = ROOT / "examples"

NOTEBOOKS = ["active_isolation.ipynb", "frf_transmissibility.ipynb", "insight_engine.ipynb", "mount_design.ipynb",
             "mount_stiffness_study.ipynb", "nonlinear_cabinet.ipynb", "shock_study.ipynb", "test_data.ipynb"]


def test_every_notebook_is_listed():
    assert sorted(p.name for p in EXAMPLES.glob("*.ipynb")) == NOTEBOOKS


def test_notebooks_are_stored_without_outputs():
    for name in NOTEBOOKS:
        nb = nbformat.read(EXAMPLES / name, as_version=4)
        for cell in nb.cells:
            if cell.cell_type == "code":
                assert cell.outputs == [] and cell.execution_count is None, name


def test_notebooks_are_what_their_generator_writes():
    """examples/make_notebooks.py is their source: it runs, and its cells are the committed ones."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("make_notebooks", EXAMPLES / "make_notebooks.py")
    assert spec is not None and spec.loader is not None
    gen = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(gen)
    assert sorted(gen.NOTEBOOKS) == NOTEBOOKS
    for name, cells in gen.NOTEBOOKS.items():
        stored = nbformat.read(EXAMPLES / name, as_version=4)
        assert [(c.cell_type, c.source) for c in gen.build(cells).cells] == \
               [(c.cell_type, c.source) for c in stored.cells], name


RESET = """%reset -f
import matplotlib as _mpl, matplotlib.pyplot as _plt
_plt.close("all"); _mpl.rc_file_defaults(); del _mpl, _plt
assert not set(k for k in globals() if not k.startswith("_")) - {"In", "Out", "exit", "quit", "get_ipython", "open"}
"""


@pytest.fixture(scope="module")
def kernel():
    """A kernel in examples/ (the notebooks read and write files beside them), shut down at the end."""
    km = jupyter_client.KernelManager(kernel_name="python3")
    km.start_kernel(cwd=str(EXAMPLES), env={**os.environ, "MPLBACKEND": "Agg"})
    yield km
    km.shutdown_kernel(now=True)


@pytest.mark.parametrize("name", NOTEBOOKS)
@pytest.mark.slow
def test_notebook_runs(name, kernel):
    if not kernel.is_alive():               # an earlier notebook killed it: a fresh one, not a cascade of failures
        kernel.restart_kernel(now=True)
    nb = nbformat.read(EXAMPLES / name, as_version=4)
    nb.cells.insert(0, nbformat.v4.new_code_cell(RESET))
    client = nbclient.NotebookClient(nb, km=kernel, timeout=120, interrupt_on_timeout=True,
                                     resources={"metadata": {"path": str(EXAMPLES)}})
    try:
        client.execute()
    finally:
        if client.kc is not None:
            client.kc.stop_channels()
    errors = [o for c in nb.cells if c.cell_type == "code" for o in c.outputs if o.output_type == "error"]
    assert not errors
    images = sum("image/png" in o.get("data", {}) for c in nb.cells if c.cell_type == "code" for o in c.outputs)
    assert images >= 2, f"{name}: expected its plots"
