"""Certified threshold searches: intervals instead of dropped samples, certificate transfer,
determinism."""

from __future__ import annotations

import numpy as np
import pytest

from tensegrity_rigidity import Instance, SolverOptions
from tensegrity_rigidity.ensemble.thresholds import EventPath, find_threshold
from tensegrity_rigidity.model.network import Element
from tensegrity_rigidity.model.sampling import lattice_geometry
from tensegrity_rigidity.model.strain import strain_tensor
from tensegrity_rigidity.solver import decide
from tests.instances import near_threshold_sample


def _samples(count, n=8, seed=12):
    rng = np.random.default_rng(seed)
    for k in range(count):
        net, u, v = lattice_geometry(n, 0.2, rng)
        eps = strain_tensor(("dilation", "shear", "compression")[k % 3], 0.3)
        yield net, u, v, eps, (0.0, 0.5, 1.0)[k % 3]


@pytest.mark.parametrize("path,p_t", [("p_r", 0.2), ("total", 0.8)])
def test_the_threshold_separates_certified_floppy_from_certified_rigid(path, p_t):
    """At the reported event the configuration is rigid, just below it floppy, each checked by
    a fresh verdict; and a second search returns the same result (deterministic)."""
    found = 0
    for net, u, v, eps, f_c in _samples(12):
        th = find_threshold(net, u, v, eps, p_t, f_c, path)
        assert th.decided
        assert th == find_threshold(net, u, v, eps, p_t, f_c, path)
        if not np.isfinite(th.s) or th.s == 0:
            continue
        found += 1
        ev = EventPath(u, v, path, p_t, f_c)
        i = int(np.searchsorted(ev.positions, th.s)) + 1  # first configuration past s
        above = decide(Instance(net.with_kinds(ev.kinds(i)), eps))
        below = decide(Instance(net.with_kinds(ev.kinds(i - 1)), eps))
        assert (above.status, below.status) == ("rigid", "floppy")
    assert found >= 6


def test_undecided_probes_give_an_interval_that_contains_the_threshold():
    """With a search that can only certify deep in either phase (the affine stage and the LP
    with tiny iteration limits), probes near the threshold stay undecided. The threshold is
    then an interval of events, never a dropped sample, and it contains the threshold of the
    full search."""
    weak = SolverOptions(stages=("affine", "newton"), min_norm=False)
    widened = 0
    for net, u, v, eps, f_c in _samples(10, n=10, seed=3):
        full = find_threshold(net, u, v, eps, 0.2, f_c)
        th = find_threshold(net, u, v, eps, 0.2, f_c, options=weak)
        if np.isnan(full.s):
            continue
        assert th.s_low <= full.s <= th.s_high, (th, full)
        if th.undecided:
            widened += 1
            assert not th.decided and th.s_low < th.s_high
            # the weak search stops far from either side: its probes are not resolved
            assert th.not_resolved == th.undecided
        assert full.not_resolved == 0
    assert widened >= 3


def test_a_rods_only_threshold_that_the_energy_stages_leave_an_interval_is_one_event():
    """n = 32, rods only (the rods-only set of benchmarks/near_threshold_set.py, sample 10):
    without the refinement stage, with the LP stage unrefined (``LinearProgram(refine=0)``) and
    without polishing, two probes below the threshold stay undecided (zero-energy displacements
    of 1.4e6 times the strain, violations stalled at 1.5e-9) and the threshold is an interval;
    with the refinement stage, with the LP stage's own refinement, or with the floppy
    candidates polished (``SolverOptions.polish``), the threshold is the same one event,
    inside that interval, and the same on a second search."""
    from tensegrity_rigidity.solver.stages import LinearProgram

    net, u, v, eps = near_threshold_sample(32, [32, 100, 10], "dilation")
    unrefined = ("affine", "newton", "ipm", LinearProgram(refine=0))
    energy_only = SolverOptions(stages=unrefined, polish=False)
    lp_refined = SolverOptions(stages=("affine", "newton", "ipm", "lp"))
    with_refine = SolverOptions(stages=("affine", "newton", "refine", "ipm", "lp"))
    wide = find_threshold(net, u, v, eps, 0.0, 0.5, options=energy_only)
    th = find_threshold(net, u, v, eps, 0.0, 0.5, options=with_refine)
    assert wide.undecided > 0 and wide.s_low < wide.s_high
    assert th.decided and th.undecided == 0
    assert wide.s_low <= th.s <= wide.s_high
    assert th == find_threshold(net, u, v, eps, 0.0, 0.5, options=with_refine)
    by_lp = find_threshold(net, u, v, eps, 0.0, 0.5, options=lp_refined)
    assert by_lp.decided and by_lp.s == th.s
    polished = find_threshold(net, u, v, eps, 0.0, 0.5, options=SolverOptions(stages=unrefined))
    assert polished.decided and polished.s == th.s


def test_a_rigid_certificate_holds_from_the_first_configuration_that_admits_it():
    """EventPath.first_admitting: a self-stress on a rod that was a cable earlier is admissible
    as soon as the cable exists when it pulls, only once the rod exists when it pushes."""
    u = np.array([0.1, 0.5, 0.35])
    v = np.array([0.0, 0.0, 0.9])  # sites 0, 1 cables when one-sided, site 2 a strut
    ev = EventPath(u, v, "p_r", 0.2, f_c=0.5)
    # events: rods at s = 0.1, 0.35, 0.5; one-sided at s = U - 0.2 = 0.15 (site 2), 0.3 (site 1)
    kinds = [ev.kinds(i) for i in range(ev.n_events + 1)]
    assert kinds[0].tolist() == [Element.CABLE, Element.EMPTY, Element.EMPTY]
    pull = np.array([1.0, 0.0, 0.0])
    push = np.array([-1.0, 0.0, 0.0])
    assert ev.first_admitting(pull) == 0  # a pulling cable from the start
    assert kinds[ev.first_admitting(push)][0] == Element.ROD  # pushing needs the rod
    assert kinds[ev.first_admitting(push) - 1][0] != Element.ROD


def test_a_floppy_certificate_holds_until_the_first_constraint_it_violates():
    u = np.array([0.1, 0.5, 0.35])
    v = np.array([0.0, 0.0, 0.9])
    ev = EventPath(u, v, "p_r", 0.2, f_c=0.5)
    none = np.zeros(3, bool)
    assert ev.last_admitting(none, none) == ev.n_events + 1
    # violating site 2 only as a rod: valid until site 2 becomes a rod
    as_rod = np.array([False, False, True])
    last = ev.last_admitting(as_rod, none)
    assert ev.kinds(last)[2] != Element.ROD and ev.kinds(last + 1)[2] == Element.ROD
