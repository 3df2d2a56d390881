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


def _empty_instance() -> Instance:
    """The three-node network with every site empty: the pattern is the diagonal alone."""
    inst = _self_image_instance()
    net = inst.network
    return Instance(net.with_kinds(np.full(net.n_sites, Element.EMPTY)), inst.strain)


def test_values_without_elements_are_the_shift():
    p = Problem(_empty_instance())
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


def _reference_pattern(p: Problem):
    """The pattern and the assembly matrix built per matrix entry, as ``Problem`` built them
    until 2026-11-29 (4228468): every bond's 16 products, those on or above the diagonal
    sorted by entry (a COO -> CSC conversion and a binary search), each entry's terms in bond
    order, then ``k = 4p + q`` (a stable sort)."""
    net = p.instance.network
    i, j = net.bonds[p.sites, 0], net.bonds[p.sites, 1]
    cols = np.c_[2 * i, 2 * i + 1, 2 * j, 2 * j + 1]
    d = net.bond_vectors()[p.sites]
    dhat = d / np.hypot(d[:, 0], d[:, 1])[:, None]
    vals = np.c_[-dhat, dhat]
    rr_rows, rr_cols = np.repeat(cols, 4, axis=1), np.tile(cols, (1, 4))
    rr_vals = np.einsum("bp,bq->bpq", vals, vals).reshape(-1, 16)
    keep = rr_rows <= rr_cols
    diag = np.arange(p.n2)
    rows, colsf = np.r_[rr_rows[keep], diag], np.r_[rr_cols[keep], diag]
    csc = sp.csc_matrix((np.ones(rows.size), (rows, colsf)), shape=(p.n2, p.n2))
    csc.sum_duplicates()
    uniq = np.repeat(np.arange(p.n2, dtype=np.int64), np.diff(csc.indptr)) * p.n2 + csc.indices
    inverse = np.searchsorted(uniq, colsf.astype(np.int64) * p.n2 + rows)
    n_rr = int(keep.sum())
    slot = inverse[:n_rr]
    order = np.argsort(slot, kind="stable")
    assemble = sp.csr_matrix(
        (
            rr_vals[keep][order],
            np.nonzero(keep)[0][order],
            np.r_[0, np.cumsum(np.bincount(slot, minlength=uniq.size))],
        ),
        shape=(uniq.size, p.sites.size),
    )
    return csc.indptr, csc.indices, assemble, inverse[n_rr:]


def _isolated_node_instance() -> Instance:
    """A lattice whose every bond at node 0 is empty: node 0 has only its diagonal."""
    inst = _self_image_instance()
    net = inst.network
    kinds = net.kinds.copy()
    kinds[(net.bonds == 0).any(axis=1)] = Element.EMPTY
    return Instance(net.with_kinds(kinds), inst.strain)


@pytest.mark.parametrize("seed", range(40))
def test_pattern_is_the_per_entry_construction_to_the_last_bit(seed):
    """The per-node-pair construction gives the same pattern, the same assembly matrix (its
    terms in the same order, so the same sums to the last bit) and the same diagonal."""
    rng = np.random.default_rng(seed)
    inst = {
        0: _self_image_instance(),
        1: _isolated_node_instance(),
        2: _empty_instance(),
    }.get(seed)
    p = Problem(inst if inst is not None else random_instance(rng))
    indptr, indices, assemble, diagonal = _reference_pattern(p)
    np.testing.assert_array_equal(p._indptr, indptr)
    np.testing.assert_array_equal(p._indices, indices)
    np.testing.assert_array_equal(p._diagonal, diagonal)
    assert p._assemble.shape == assemble.shape
    np.testing.assert_array_equal(p._assemble.indptr, assemble.indptr)
    np.testing.assert_array_equal(p._assemble.indices, assemble.indices)
    np.testing.assert_array_equal(p._assemble.data, assemble.data)
    w = rng.lognormal(0.0, 3.0, p.sites.size)
    np.testing.assert_array_equal(
        p.values(w),
        assemble @ w + np.where(np.isin(np.arange(assemble.shape[0]), diagonal), p.mu, 0.0),
    )
