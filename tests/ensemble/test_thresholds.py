"""Threshold bisection: warm starts change the path through the solver, never the threshold."""

from __future__ import annotations

import numpy as np
import pytest

from tensegrity_rigidity.ensemble.thresholds import find_threshold
from tensegrity_rigidity.model.sampling import lattice_geometry
from tensegrity_rigidity.model.strain import strain_tensor


@pytest.mark.parametrize("path,p_t", [("p_r", 0.2), ("total", 0.8)])
def test_warm_and_cold_bisection_find_the_same_threshold(path, p_t):
    rng = np.random.default_rng(12)
    found = 0
    for k in range(12):
        net, u, v = lattice_geometry(8, 0.2, rng)
        eps = strain_tensor(("dilation", "shear", "compression")[k % 3], 0.3)
        f_c = (0.0, 0.5, 1.0)[k % 3]
        cold = find_threshold(net, u, v, eps, p_t, f_c, path, warm_start=False)
        warm = find_threshold(net, u, v, eps, p_t, f_c, path, warm_start=True)
        assert cold.decided and warm.decided
        assert cold.solves == warm.solves
        np.testing.assert_equal(warm.s, cold.s)
        found += np.isfinite(cold.s)
    assert found >= 6
