"""Execute the example notebooks (examples/*.ipynb) with nbclient.

A notebook is skipped, with the reason, only when a vibss module it needs has not landed yet, or
when the notebook tools (nbformat, nbclient, ipykernel) are not installed.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

nbformat = pytest.importorskip("nbformat")
nbclient = pytest.importorskip("nbclient")
pytest.importorskip("ipykernel")

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"

NEEDS = {
    "frf_transmissibility.ipynb": ["vibss.frequency"],
    "shock_study.ipynb": ["vibss.time"],
    "mount_stiffness_study.ipynb": [],
}


def test_every_notebook_is_listed():
    assert sorted(p.name for p in EXAMPLES.glob("*.ipynb")) == sorted(NEEDS)


def test_notebooks_are_stored_without_outputs():
    for name in NEEDS:
        nb = nbformat.read(EXAMPLES / name, as_version=4)
        for cell in nb.cells:
            if cell.cell_type == "code":
                assert cell.outputs == [] and cell.execution_count is None, name


@pytest.mark.parametrize("name", sorted(NEEDS))
def test_notebook_runs(name, monkeypatch):
    missing = [m for m in NEEDS[name] if importlib.util.find_spec(m) is None]
    if missing:
        pytest.skip(f"{name} needs {', '.join(missing)}, which is not in this version of vibss yet")
    monkeypatch.setenv("MPLBACKEND", "Agg")
    nb = nbformat.read(EXAMPLES / name, as_version=4)
    client = nbclient.NotebookClient(nb, timeout=120, kernel_name="python3",
                                     resources={"metadata": {"path": str(EXAMPLES)}})
    client.execute()
    errors = [o for c in nb.cells if c.cell_type == "code" for o in c.outputs if o.output_type == "error"]
    assert not errors
    images = sum("image/png" in o.get("data", {}) for c in nb.cells if c.cell_type == "code" for o in c.outputs)
    assert images >= 2, f"{name}: expected its plots"
