"""The solve in the mounts' forces on a pattern laid out once (vibss/linear/solve/backends.py ``_Layout``)
gives the dense LU's answer on the same equilibrated system, on a mechanism chain and a soft tower."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from vibss.linear.plant.build import build_plant
from vibss.linear.solve import backends
from vibss.linear.solve.exact import response

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
from models import mechanism_model, tower_model  # noqa: E402


@pytest.mark.parametrize("build", [mechanism_model, tower_model])
def test_the_laid_out_sparse_solve_is_the_dense_one(build, monkeypatch):
    model = build(11, damping="general", seed=4)
    s = 2j * np.pi * np.geomspace(0.01, 300.0, 9)

    def solve() -> np.ndarray:
        plant = build_plant(model, ["b10.fx", "b3.fz"], ["b10.x", "b5.z", "b0.y"])
        return response(plant, s, form="mounts")

    dense = solve()                                         # n + 3 q <= MOUNTS_DENSE_MAX: dense LU
    monkeypatch.setattr(backends, "MOUNTS_DENSE_MAX", 0)    # the same system by SuperLU on the layout
    sparse = solve()
    err = np.linalg.norm(sparse - dense, axis=(0, 1)) / np.linalg.norm(dense, axis=(0, 1))
    assert err.max() < 1e-9
