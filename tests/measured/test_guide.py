"""The Python blocks of docs/analyses/test-data.md run, and the numbers they quote hold."""

from __future__ import annotations

import re
import warnings

import numpy as np

from cases import ROOT


def test_test_data_guide(capsys):
    text = (ROOT / "docs" / "analyses" / "test-data.md").read_text()
    scope: dict = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for block in re.findall(r"```python\n(.*?)```", text, re.S):
            exec(compile(block, "test-data.md", "exec"), scope)
    out = capsys.readouterr().out
    assert "measured | measured: no model behind it | FRAC 1.0" in out
    assert "fractional: RMS log error 0.0009, alpha 0.500" in out and "fractional: RMS log error 0.0009" in text
    assert "zener: RMS log error 0.074 (1 warning)" in out
    assert f"here {scope['fit'].rheology.ladder().fit_error:.1e}" in text
    err = float(out.split("FBS against the whole model: ")[1].split()[0])
    assert err < 1e-13
    assert "('engine.fz', 'ground.z.acc') ('N', 'm/s^2') (6, 6)" in out
    line = next(x for x in out.splitlines() if x.startswith("z of the plate under m1"))
    assert line in text and sum(int(p.split()[1]) for p in line.split(": ")[1].split(", ")) in (99, 100, 101)
    assert "blocked z force of m1 at 0 Hz: 0.265 N/N" in out and "0.265 N/N" in text
    np.testing.assert_allclose(scope["mount"].dynamic_stiffness([100.0])[0, 0].real, 3.30e5, rtol=3e-3)
