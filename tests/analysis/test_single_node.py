"""Single-node theory: the supplement's formula against brute force and simulation."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from tensegrity_rigidity.analysis.estimators import wilson
from tensegrity_rigidity.analysis.single_node import (
    class_weights,
    qbar_table,
    simulate_single_node,
    single_node_probability,
)
from tensegrity_rigidity.errors import InputError

# the supplement's table (columns A = mixed, B = same-sign), used only to check the derivation
SUPPLEMENT = {
    (1, 1, 1): (2 / 3, 0),
    (0, 1, 2): (1 / 3, 0),
    (0, 2, 1): (1 / 3, 0),
    (1, 0, 2): (1 / 3, 1),
    (1, 2, 0): (1 / 3, 1),
    (2, 0, 1): (1, 1),
    (2, 1, 0): (1, 1),
    (3, 0, 0): (1, 1),
    (0, 3, 0): (0, 1),
    (0, 0, 3): (0, 1),
}


def test_derived_table_and_weights_match_the_supplement():
    for row in qbar_table():
        key = (row["n_r"], row["n_c"], row["n_s"])
        assert (row["qbar_mixed"], row["qbar_same"]) == pytest.approx(SUPPLEMENT[key])
    assert class_weights() == pytest.approx({"mixed": 3 / 5, "same": 2 / 5})


def _brute_force(p_r, p_c, p_s):
    """Independent route: every generic sign pattern of a node with three bonds (same-sign with
    weight 2/5, each mixed pattern with weight 1/5) and every element triple, each bond i.i.d."""
    probs = {"r": p_r, "c": p_c, "s": p_s}
    total = sum(probs.values())
    patterns = [((1, 1, 1), 2 / 5), ((1, -1, 1), 1 / 5), ((-1, 1, 1), 1 / 5), ((1, 1, -1), 1 / 5)]
    out = 0.0
    for elems in itertools.product("rcs", repeat=3):
        w = np.prod([probs[e] / total for e in elems])
        for pat, pw in patterns:
            ok = any(
                all(
                    e == "r" or (e == "c" and sg * s > 0) or (e == "s" and sg * s < 0)
                    for e, s in zip(elems, pat, strict=False)
                )
                for sg in (1, -1)
            )
            out += w * pw * ok
    return out


@pytest.mark.parametrize("p_r", [0.0, 0.1, 0.3, 0.5, 0.9])
@pytest.mark.parametrize("f_c", [0.0, 0.2, 0.5, 1.0])
def test_formula_equals_brute_force(p_r, f_c):
    p_c, p_s = f_c * (1 - p_r), (1 - f_c) * (1 - p_r)
    assert single_node_probability(p_r, p_c, p_s) == pytest.approx(_brute_force(p_r, p_c, p_s))


@pytest.mark.parametrize("p_r,f_c", [(0.2, 0.0), (0.2, 0.5), (0.5, 0.25), (0.7, 1.0)])
def test_simulation_within_wilson_interval(p_r, f_c):
    p_c, p_s = f_c * (1 - p_r), (1 - f_c) * (1 - p_r)
    k, n = simulate_single_node(
        p_r, p_c, p_s, 6000, np.random.default_rng(int(100 * p_r + 10 * f_c))
    )
    _, lo, hi = wilson(k, n, z=3.0)
    assert lo <= single_node_probability(p_r, p_c, p_s) <= hi


def test_cables_only_or_struts_only_beat_a_mixture():
    for p_r in (0.1, 0.4, 0.7):
        q = 1 - p_r
        mixed = single_node_probability(p_r, q / 2, q / 2)
        assert single_node_probability(p_r, q, 0) > mixed
        assert single_node_probability(p_r, 0, q) > mixed


def test_bad_probabilities():
    with pytest.raises(InputError):
        single_node_probability(0.5, 0.4, 0.3)
    with pytest.raises(InputError):
        single_node_probability(0, 0, 0)
