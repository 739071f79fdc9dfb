"""The insight results follow the result protocol (vibss/results.py): text, HTML, strict JSON,
pandas, a figure without pyplot, lookup by name with did-you-mean, pickling."""

from __future__ import annotations

import json
import pickle
import sys

import numpy as np
import pytest
from matplotlib.figure import Figure

import cases.models as cases
import vibss
from vibss.errors import SignalError


@pytest.fixture(scope="module")
def results():
    m = cases.box(10.0, [1.0, 1.2, 1.5], 1e4, 20.0, at=[0.3, 0.2, 0.0], loss_factor=0.02)
    return {
        "energy": vibss.energy_distribution(m, "dissipative"),
        "modal": vibss.modal_contributions(m, ["b.fz"], ["b.z", "b.rx"], [1.0, 3.0, 4.5, 9.0]),
        "paths": vibss.path_contributions(m, ["b.fz", "ground.z.acc"], [1.0, 3.0, 9.0]),
        "time": vibss.time_contributions(m, inputs={"b.fz": np.r_[0.0, np.ones(200)]}, outputs=["b.z", "b.rx"],
                                         t_end=0.4, dt=2e-3),
    }


@pytest.mark.parametrize("kind", ["energy", "modal", "paths", "time"])
def test_protocol(results, kind, monkeypatch):
    r = results[kind]
    assert r.report() == str(r) and r._repr_html_().count("<table>") == 1
    assert len(r.units) == len(r.output_labels) and r.method and isinstance(r.note, str)
    assert json.loads(r.to_json()) == json.loads(json.dumps(r.to_dict(), allow_nan=False))
    assert r.to_pandas().shape[0] > 0
    first = r.output_labels[0]
    assert np.array_equal(r[first], r[0], equal_nan=True)
    with pytest.raises(SignalError, match="did you mean"):
        r[first + "x"]
    back = pickle.loads(pickle.dumps(r))
    assert np.array_equal(back[first], r[first], equal_nan=True)
    monkeypatch.setitem(sys.modules, "matplotlib.pyplot", None)
    assert isinstance(r.plot(), Figure)


def test_arrays_handed_out_are_read_only(results):
    for r in results.values():
        for name in ("fractions", "by_axis", "terms", "residual", "forces", "total", "share"):
            a = getattr(r, name, None)
            if isinstance(a, np.ndarray):
                assert not a.flags.writeable, name
