"""Our rods-only threshold against the literature's, and the package's copies of the values."""

from __future__ import annotations

import numpy as np
import pytest

from tensegrity_rigidity.analysis.estimators import critical_point
from tensegrity_rigidity.ensemble.thresholds import find_threshold
from tensegrity_rigidity.model.lattice import DEFAULT_DELTA
from tensegrity_rigidity.model.sampling import lattice_geometry
from tensegrity_rigidity.model.strain import strain_tensor
from tensegrity_rigidity.paper.claims import CLAIMS, REFERENCES

from .literature import LITERATURE


@pytest.mark.parametrize("key", sorted(REFERENCES))
def test_package_references_match_the_literature(key):
    ref, lit = REFERENCES[key], LITERATURE[key]
    assert (ref.value, ref.error) == (lit.value, lit.error)
    assert lit.citation.split(",")[0].split()[-1] in ref.citation  # the first author's name


def test_the_rods_only_claim_is_compared_with_jacobs_and_thorpe():
    c = CLAIMS["rods_only_pc"]
    assert (c.value, c.error) == (LITERATURE["pc_jacobs_thorpe"].value, 0.0003)


def _rods_only_thresholds(n, samples, seed):
    rng = np.random.default_rng(seed)
    out = []
    for k in range(samples):
        net, u, v = lattice_geometry(n, DEFAULT_DELTA, rng)
        eps = strain_tensor(("dilation", "shear", "compression")[k % 3], 0.3 * k)
        out.append(find_threshold(net, u, v, eps, 0.0, 0.5).s)
    return np.array(out)


def test_rods_only_threshold_approaches_the_generic_rigidity_threshold():
    """At n = 16 the P = 1/2 point of rods-only samples lies within its error plus a stated
    finite-size allowance of Jacobs and Thorpe's p_c = 0.6602, and closer to it than at n = 6.

    The allowance, 0.015, is the approach measured from n = 6 to n = 16 (0.638 to 0.658 with 60
    samples each); the finite-size study fits the approach properly.
    """
    p_c = LITERATURE["pc_jacobs_thorpe"].value
    pc16, err16 = critical_point(_rods_only_thresholds(16, 60, 16))
    pc6, err6 = critical_point(_rods_only_thresholds(6, 60, 6))
    assert abs(pc16 - p_c) <= 3 * err16 + 0.015
    assert abs(pc16 - p_c) < abs(pc6 - p_c)
