"""The pebble game's strain rigidity against the certified verdict, on random rods-only samples.

Every decided verdict of :func:`~tensegrity_rigidity.decide` (an LP certificate: a self-stress
doing work on the strain, or a displacement accommodating it) must equal
``rigid_clusters(...).wraps``; strains are generic (random type and angle). A mismatch is a bug
in one of the two.
"""

from __future__ import annotations

import numpy as np
import pytest

from tensegrity_rigidity import decide, rigid_clusters

from .helpers import lattice_rods, random_rods

#: (instances, smallest n, largest n) of the default run and of the slow run
DEFAULT = (150, 5, 12)
SLOW = (500, 5, 32)


def _compare(count: int, n_lo: int, n_hi: int, seed: int) -> tuple[int, int, list]:
    rng = np.random.default_rng(seed)
    decided, wrapping, mismatches = 0, 0, []
    for k in range(count):
        inst = lattice_rods(rng, (n_lo, n_hi))
        verdict = decide(inst)
        wraps = rigid_clusters(inst).wraps
        wrapping += wraps
        if verdict.status != "undecided":
            decided += 1
            if (verdict.status == "rigid") != wraps:
                mismatches.append((k, inst.network.n_nodes, verdict.status, wraps))
    return decided, wrapping, mismatches


def test_wraps_equals_the_certified_verdict_near_p_c():
    count, n_lo, n_hi = DEFAULT
    decided, wrapping, mismatches = _compare(count, n_lo, n_hi, seed=660)
    assert mismatches == []
    assert decided >= 0.95 * count
    assert 0.2 * count < wrapping < 0.8 * count  # both verdicts well represented


def test_wraps_equals_the_certified_verdict_on_random_networks():
    rng = np.random.default_rng(661)
    for _ in range(150):
        inst = random_rods(rng)
        verdict = decide(inst)
        if verdict.status != "undecided":
            assert (verdict.status == "rigid") == rigid_clusters(inst).wraps


@pytest.mark.slow
def test_wraps_equals_the_certified_verdict_up_to_n_32():
    count, n_lo, n_hi = SLOW
    decided, wrapping, mismatches = _compare(count, n_lo, n_hi, seed=662)
    assert mismatches == []
    assert decided >= 0.95 * count


def test_a_strip_wrapping_one_way_ignores_the_shear_along_it():
    # rods on the two lowest rows of a full lattice: a stressed strip whose cycles wrap along
    # b1 only; it resists every strain with L . eps . L != 0 (L = n b1), not the pure shear
    # whose neutral axis lies along b1: that strain is not generic, and wraps speaks of generic
    # strains
    from tensegrity_rigidity import Element, Instance, lattice_instance, strain_tensor

    n = 8
    net = lattice_instance(n, p_r=1.0, seed=2).network
    row = net.bonds % n  # node a n + b sits on row b
    strip = (row[:, 0] <= 1) & (row[:, 1] <= 1)
    assert np.all(net.shifts[strip, 1] == 0)
    net = net.with_kinds(np.where(strip, Element.ROD, Element.EMPTY))
    assert rigid_clusters(net).wraps
    neutral_along_b1 = strain_tensor("shear", theta=np.pi / 4)
    assert neutral_along_b1[0, 0] == pytest.approx(0, abs=1e-15)
    assert decide(Instance(net, neutral_along_b1)).status == "floppy"
    for phi, theta in (("shear", 0.3), ("dilation", 0.0), ("compression", 1.0)):
        assert decide(Instance(net, strain_tensor(phi, theta=theta))).status == "rigid"
