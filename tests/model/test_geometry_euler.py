"""The Euler-angle rotation vibss writes out (vibss.model.geometry.euler_matrix) against scipy's
Rotation.from_euler, every valid sequence, intrinsic and extrinsic, random angles: the same matrix to
rounding (scipy.spatial is no longer imported at start-up; this keeps the two in step)."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from vibss import Orientation
from vibss.errors import ModelError
from vibss.model.geometry import euler_matrix

SEQUENCES = ["".join(p) for p in itertools.product("XYZ", repeat=3) if p[0] != p[1] and p[1] != p[2]]


@pytest.mark.parametrize("sequence", SEQUENCES + [s.lower() for s in SEQUENCES])
def test_euler_matrix_is_scipys(sequence: str) -> None:
    rng = np.random.default_rng(abs(hash(sequence)) % 2**32)
    for _ in range(5):
        a = rng.uniform(-np.pi, np.pi, 3)
        assert np.abs(euler_matrix(sequence, a) - Rotation.from_euler(sequence, a).as_matrix()).max() < 1e-14
    o = Orientation.from_euler([10.0, -20.0, 30.0], sequence, degrees=True)
    assert np.abs(o.matrix - Rotation.from_euler(sequence, [10, -20, 30], degrees=True).as_matrix()).max() < 1e-14


def test_repeated_axes_and_scipy_rotations():
    with pytest.raises(ModelError, match="consecutive axes must differ"):
        Orientation.from_euler([0.1, 0.2, 0.3], "XXY")
    r = Rotation.from_euler("ZYX", [0.3, 0.2, 0.1])
    assert np.abs(Orientation.coerce(r).matrix - r.as_matrix()).max() < 1e-15
