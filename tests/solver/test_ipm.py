"""The energy's interior point (:mod:`tensegrity_rigidity.solver.ipm`)."""

from __future__ import annotations

import warnings

import numpy as np

from tensegrity_rigidity.ensemble.runner import sample_geometry
from tensegrity_rigidity.ensemble.spec import parse_spec
from tensegrity_rigidity.model.elements import place_elements
from tensegrity_rigidity.model.network import Instance
from tensegrity_rigidity.model.strain import strain_tensor
from tensegrity_rigidity.solver.ipm import IpmState, interior_point, step_to_boundary
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


def _factorizations(p: Problem, run):
    """``run()`` and the numeric factorisations it took on ``p``."""
    before = p.factorizations
    out = run()
    return out, p.factorizations - before


def test_a_run_resumed_where_an_earlier_one_ended_ends_where_the_cold_start_does():
    """The verdict search's interior point (tolerance 1e-9, checkpoints offered to a callback)
    and the relaxation's (1e-10): started where the first ended, the second returns the very
    iterate it returns from the cold start, and skips the steps the first took."""
    p = Problem(_fig4_quick_sample())
    cold, cold_steps = _factorizations(p, lambda: interior_point(p, max_iter=60, tol=1e-10))
    for stop_at in (None, 2):  # run to its tolerance; stopped by the callback at a checkpoint
        offers = []

        def callback(u, lam, stop_at=stop_at, offers=offers):
            offers.append(u)
            return len(offers) == stop_at

        end: list[IpmState] = []
        interior_point(
            p, max_iter=60, tol=1e-9, checkpoints=(1e-3, 1e-5, 1e-7), callback=callback, record=end
        )
        assert len(offers) == (stop_at or 3)
        (state,) = end
        assert 0 < state.steps < cold[3] and state.resumes(p, 60, 1e-10, False)
        resumed, resumed_steps = _factorizations(
            p, lambda state=state: interior_point(p, max_iter=60, tol=1e-10, start=state)
        )
        for a, b in zip(cold, resumed, strict=True):
            np.testing.assert_array_equal(a, b)
        assert resumed_steps == cold_steps - state.steps


def test_a_state_the_run_would_not_pass_through_is_ignored():
    """A state from another problem, a looser run (a tolerance this run would stop before),
    more steps than this run allows, or another objective: the run starts cold."""
    inst = _fig4_quick_sample()
    p = Problem(inst)
    end: list[IpmState] = []
    interior_point(p, max_iter=60, tol=1e-9, record=end)
    (state,) = end
    other = Problem(inst)
    assert state.resumes(p, 60, 1e-9, False)
    for q, max_iter, tol, anchored in (
        (other, 60, 1e-9, False),
        (p, 60, 1e-8, False),
        (p, state.steps - 1, 1e-9, False),
        (p, 60, 1e-9, True),
    ):
        assert not state.resumes(q, max_iter, tol, anchored)
        cold = interior_point(q, max_iter=max_iter, tol=tol, anchored=anchored)
        given = interior_point(q, max_iter=max_iter, tol=tol, anchored=anchored, start=state)
        for a, b in zip(cold, given, strict=True):
            np.testing.assert_array_equal(a, b)


def test_resumes_from_a_run_stopped_by_its_limit_or_by_an_underflow():
    """A run cut at 5 iterations, resumed with 60 allowed; a run stopped at its last finite
    iterate (the unreachable 1e-14 above), resumed with the same settings: each ends where the
    cold start ends."""
    p = Problem(_fig4_quick_sample())
    for first, then in (((5, 1e-10), (60, 1e-10)), ((200, 1e-14), (200, 1e-14))):
        end: list[IpmState] = []
        interior_point(p, max_iter=first[0], tol=first[1], record=end)
        cold, cold_steps = _factorizations(
            p, lambda then=then: interior_point(p, max_iter=then[0], tol=then[1])
        )
        resumed, steps = _factorizations(
            p,
            lambda end=end, then=then: interior_point(
                p, max_iter=then[0], tol=then[1], start=end[0]
            ),
        )
        for a, b in zip(cold, resumed, strict=True):
            np.testing.assert_array_equal(a, b)
        assert steps == cold_steps - end[0].steps


def test_a_run_offering_checkpoints_does_not_resume():
    """Its callback would miss the checkpoints of the steps skipped."""
    p = Problem(_fig4_quick_sample())
    end: list[IpmState] = []
    interior_point(p, max_iter=60, tol=1e-9, record=end)

    def offers(seen):
        def callback(u, lam):
            seen.append(u)
            return False

        return callback

    cold_seen: list = []
    cold = interior_point(p, tol=1e-10, checkpoints=(1e-3, 1e-5), callback=offers(cold_seen))
    seen: list = []
    given = interior_point(
        p, tol=1e-10, checkpoints=(1e-3, 1e-5), callback=offers(seen), start=end[0]
    )
    for a, b in zip(cold, given, strict=True):
        np.testing.assert_array_equal(a, b)
    assert len(seen) == len(cold_seen) == 2
    for a, b in zip(cold_seen, seen, strict=True):
        np.testing.assert_array_equal(a, b)
