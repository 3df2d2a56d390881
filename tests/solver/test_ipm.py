"""The energy's interior point (:mod:`tensegrity_rigidity.solver.ipm`)."""

from __future__ import annotations

import warnings

import numpy as np

from tensegrity_rigidity.ensemble.runner import sample_geometry
from tensegrity_rigidity.ensemble.spec import parse_spec
from tensegrity_rigidity.model.elements import place_elements
from tensegrity_rigidity.model.network import Instance
from tensegrity_rigidity.model.strain import strain_tensor
from tensegrity_rigidity.solver.ipm import interior_point, step_to_boundary
from tensegrity_rigidity.solver.problem import Problem


def _fig4_quick_sample() -> Instance:
    """Sample 8 of the quick Fig. 4 sweep's point (p_r, p_t, f_c) = (0.3, 0.65, 0.875) under
    shear, as the sweep builds it: on it the relaxation's long run (200 iterations to 1e-14)
    drives a slack below the smallest double, one sample in 21,600 of those sweeps."""
    spec = parse_spec(
        {"n": 12, "delta": 0.2, "p_r": 0.3, "p_t": 0.65, "f_c": 0.875, "phi": np.pi / 2}
        | {"samples": 8, "seed": 41}
    )
    (point,) = spec.points()
    net, u, v, theta = sample_geometry(spec, point, 8)
    kinds = place_elements(u, v, point.p_r, point.p_t, point.f_c)
    return Instance(net.with_kinds(kinds), strain_tensor(point.phi, theta, spec.gamma))


def test_an_unreachable_tolerance_stops_at_a_finite_iterate_without_warnings():
    p = Problem(_fig4_quick_sample())
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)  # overflow in lam / w, then NaN
        u, w, lam, it = interior_point(p, max_iter=200, tol=1e-14)
    assert it < 200  # stopped at the underflow, not run on NaNs to the limit
    assert np.all(np.isfinite(u)) and np.all(np.isfinite(lam)) and np.all(w >= 0)
    # the iterate is a near-minimiser: its energy is below the affine one
    assert p.energy(u) < p.energy(np.zeros(p.n2))


def test_step_to_boundary_with_a_vanishing_direction_is_a_full_step():
    x = np.array([1.0, 2.0])
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        assert step_to_boundary(x, np.array([-1e-320, 0.0])) == 1.0
    assert step_to_boundary(x, np.array([-4.0, 1.0])) == 0.25
