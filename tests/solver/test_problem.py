"""The verdict's problem: the Newton matrix's values in its fixed pattern."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from tensegrity_rigidity.model.network import Element, Instance, PeriodicNetwork
from tensegrity_rigidity.solver.problem import Problem
from tests.instances import random_instance


def _dense_upper(p: Problem, values: np.ndarray) -> np.ndarray:
    """The (2N, 2N) upper triangle that ``values`` fill in the problem's pattern."""
    M = sp.csc_matrix((values, p._indices, p._indptr), shape=(p.n2, p.n2))
    return M.toarray()


def _self_image_instance() -> Instance:
    """Three nodes in a unit box; node 0 is bonded to its own image (shift (1, 0)) as well as
    to the others, so that one bond adds several terms to the same matrix entries."""
    net = PeriodicNetwork(
        box=np.eye(2),
        positions=np.array([[0.1, 0.2], [0.5, 0.3], [0.3, 0.7]]),
        bonds=np.array([[0, 0], [0, 1], [1, 2], [2, 0], [1, 1], [0, 2]]),
        shifts=np.array([[1, 0], [0, 0], [0, 0], [0, 0], [0, 1], [0, -1]]),
        kinds=np.array(
            [Element.ROD, Element.CABLE, Element.STRUT, Element.ROD, Element.CABLE, Element.ROD]
        ),
    )
    return Instance(net, np.array([[0.01, 0.003], [0.003, -0.02]]))


def test_values_without_elements_are_the_shift():
    net = _self_image_instance().network
    empty = PeriodicNetwork(
        box=net.box,
        positions=net.positions,
        bonds=net.bonds,
        shifts=net.shifts,
        kinds=np.full(net.n_sites, Element.EMPTY),
    )
    p = Problem(Instance(empty, np.eye(2) * 0.01))
    assert p.sites.size == 0
    np.testing.assert_array_equal(_dense_upper(p, p.values(np.zeros(0), 0.5)), 0.5 * np.eye(p.n2))


@pytest.mark.parametrize("seed", range(12))
def test_values_are_the_newton_matrix_in_its_pattern(seed):
    rng = np.random.default_rng(seed)
    inst = _self_image_instance() if seed == 0 else random_instance(rng)
    p = Problem(inst)
    if p.sites.size == 0:
        pytest.skip("no element")
    w = rng.lognormal(0.0, 3.0, p.sites.size) * (rng.random(p.sites.size) < 0.8)
    shift = 10 ** rng.uniform(-14, 0)
    R = p.R.toarray()
    expected = np.triu(R.T @ (w[:, None] * R) + shift * np.eye(p.n2))
    got = _dense_upper(p, p.values(w, shift))
    scale = max(float(np.abs(expected).max()), 1e-300)
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-13 * scale)
    # the default shift is the problem's own regularisation
    np.testing.assert_array_equal(p.values(w), p.values(w, p.mu))
    assert p.mu > 0 and not np.array_equal(p.values(w), p.values(w, 0.0))
