"""The time run's local laws (:class:`vibss.time.kernels.laws.LocalLaws`) evaluate every curve at once from
its cubic pieces; against each axis's own law (:class:`vibss.model.nonlinearity.AxisLaw`: scipy's PCHIP, the
end slopes beyond the points, the stop's rate past its clearance) at random deflections inside, between and
beyond the points, in every regime."""

from __future__ import annotations

import numpy as np

from vibss.model.nonlinearity import AxisLaw
from vibss.time.kernels.laws import LocalLaws

MM = 1e-3
HARDENING = np.array([[-4, -300], [-3, -210], [-2, -125], [-1, -60], [0, 0], [1, 60], [2, 120], [4, 240.0]]) * [MM, 1]
SHORT = np.array([[-1, -50], [0, 0], [2, 90], [3, 200.0]]) * [MM, 1]


def test_the_curves_at_once_equal_each_axis_law() -> None:
    laws = (AxisLaw.build(6e4, ((4 * MM, 6 * MM), 1.2e6), HARDENING), AxisLaw.build(3e4, ((5 * MM, 5 * MM), 6e5)),
            AxisLaw.build(4e4, None, SHORT), AxisLaw.build(2e4))
    d0 = np.array([1 * MM, 0.0, -0.2 * MM, 0.0])
    local = LocalLaws(("a.z", "b.x", "c.z", "d.y"), laws, d0)
    rng = np.random.default_rng(7)
    for d in rng.uniform(-8 * MM, 8 * MM, (500, 4)):
        regime = local.regime(d)
        g, g1, g2 = local.force(d - d0, regime)
        for i, law in enumerate(laws):
            # beyond the linear rate the plant carries, from the operating point's force
            f = float(law.force(d[i]) - law.force(d0[i])) - law.stiffness * (d[i] - d0[i])
            k = float(law.tangent(d[i])) - law.stiffness
            assert abs(g[i] - f) <= 1e-12 * 300 and abs(g1[i] - k) <= 1e-12 * 1.2e6, (i, d[i])
            lo, hi = law.span
            curv = float(law.curve(d[i], 2)) if law.curve is not None and lo < d[i] < hi else 0.0
            assert abs(g2[i] - curv) <= 1e-9 * 1e8, (i, d[i])
