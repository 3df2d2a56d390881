"""rigid_clusters: known answers, input errors, dense linear-algebra oracles and invariants."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sl
from hypothesis import given, settings
from hypothesis import strategies as st

from tensegrity_rigidity import (
    Element,
    InputError,
    Instance,
    PeriodicNetwork,
    RigidClusters,
    decide,
    lattice_instance,
    rigid_clusters,
)
from tensegrity_rigidity.combinatorics import pebble
from tensegrity_rigidity.combinatorics.clusters import NO_COMP, first_wrapping, game_arrays
from tensegrity_rigidity.model.mechanics import rigidity_matrix
from tensegrity_rigidity.model.strain import strain_tensor

from .helpers import (
    dense_rigidity,
    lattice_rods,
    random_rods,
    rotation_partition,
    same_partition,
    stress_support,
)

#: a generic strain for the hand-built networks
STRAIN = strain_tensor(0.3, 1.1)


def k4_network(wraps: tuple[tuple[int, int], ...] = ((1, 0),)) -> PeriodicNetwork:
    """A K4 (a balanced circuit) in a box, plus bonds 0-1 with the given image shifts."""
    rng = np.random.default_rng(0)
    pos = rng.random((4, 2)) * 2 + 1
    bonds = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)] + [(0, 1)] * len(wraps)
    shifts = [(0, 0)] * 6 + list(wraps)
    box = np.array([[5.0, 0.0], [0.7, 4.6]])
    return PeriodicNetwork(box, pos, bonds, shifts, [Element.ROD] * len(bonds))


def test_full_lattice_is_rigid_with_one_stressed_cluster():
    inst = lattice_instance(6, p_r=1.0, seed=3)
    r = rigid_clusters(inst)
    assert isinstance(r, RigidClusters)
    assert r.wraps and r.rank == 2 * 36 - 2 and r.floppy_modes == 2
    assert r.self_stresses == 3 * 36 - r.rank
    assert r.n_clusters == 1 and np.all(r.labels == 0) and r.overconstrained.all()


def test_empty_network_has_every_mode_floppy():
    inst = lattice_instance(5, p_r=0.0, seed=3)
    r = rigid_clusters(inst)
    assert not r.wraps and r.rank == 0 and r.floppy_modes == 50 and r.n_clusters == 0
    assert np.all(r.labels == -1) and not r.overconstrained.any()


def test_a_bond_to_its_own_image_resists_strain_alone():
    net = PeriodicNetwork(np.eye(2), [[0.2, 0.3]], [[0, 0]], [[1, 0]], [Element.ROD])
    r = rigid_clusters(net)
    assert r.wraps and r.rank == 0 and r.floppy_modes == 2 and r.overconstrained.all()
    assert decide(Instance(net, STRAIN)).status == "rigid"


def test_balanced_circuit_on_a_wrapping_body_does_not_resist_strain():
    # K4 plus one wrapping bond: the wrapping bond is independent (the body becomes rigid on
    # the torus), K4's stress is balanced, so its virial vanishes: floppy under every strain
    net = k4_network()
    r = rigid_clusters(net)
    assert not r.wraps and r.rank == 6 and r.self_stresses == 1
    np.testing.assert_array_equal(r.overconstrained, [True] * 6 + [False])
    assert r.n_clusters == 1
    assert decide(Instance(net, STRAIN)).status == "floppy"
    # inserted last, K4's sixth bond meets a tight set of the torus (2 pebbles only): the
    # lifted test of the kernel must find its balanced circuit
    eu, ev, gx, gy = game_arrays(net)
    status, first, _, _ = pebble.play(
        4, eu, ev, gx, gy, np.array([6, 0, 1, 2, 3, 4, 5]), False, True, NO_COMP
    )
    assert status[5] == pebble.BALANCED and first == -1


def test_second_wrapping_direction_makes_it_rigid():
    net = k4_network(((1, 0), (0, 1)))
    r = rigid_clusters(net)
    assert r.wraps and r.self_stresses == 2 and r.overconstrained.all()
    assert decide(Instance(net, STRAIN)).status == "rigid"


def test_one_sided_elements_are_refused_unless_as_rods():
    inst = lattice_instance(5, p_r=0.5, p_t=0.3, seed=1)
    with pytest.raises(InputError, match="rods only") as info:
        rigid_clusters(inst)
    assert "\n" not in str(info.value)
    as_rods = inst.with_kinds(np.where(inst.network.kinds != Element.EMPTY, Element.ROD, 0))
    r, s = rigid_clusters(inst, as_rods=True), rigid_clusters(as_rods)
    assert (r.rank, r.wraps) == (s.rank, s.wraps)
    np.testing.assert_array_equal(r.labels, s.labels)
    with pytest.raises(InputError, match="as_rods must be True or False"):  # was read as True
        rigid_clusters(inst, as_rods="yes")  # type: ignore[arg-type]
    assert len(repr(r)) < 300 and "<(75,) int64 array>" in repr(r)


def test_not_a_network_is_refused():
    with pytest.raises(InputError, match="PeriodicNetwork"):
        rigid_clusters(np.eye(2))


@pytest.mark.parametrize("seed", range(30))
def test_rank_overconstrained_and_clusters_match_dense_linear_algebra(seed):
    rng = np.random.default_rng([77, seed])
    inst = lattice_rods(rng, (4, 7), (0.45, 0.9)) if seed % 2 else random_rods(rng, 6)
    net = inst.network
    r = rigid_clusters(inst)
    sites, R = dense_rigidity(net)
    rank = int(np.linalg.matrix_rank(R)) if sites.size else 0
    assert r.rank == rank and r.floppy_modes == 2 * net.n_nodes - rank
    np.testing.assert_array_equal(r.overconstrained, stress_support(net))
    part = rotation_partition(net)
    keep = part >= 0
    assert same_partition(part[keep], r.labels[sites][keep])
    assert np.all(r.labels[net.kinds == Element.EMPTY] == -1)
    assert np.all(r.labels[sites] >= 0)


def _shuffled(net: PeriodicNetwork, perm: np.ndarray) -> PeriodicNetwork:
    return PeriodicNetwork(
        net.box, net.positions, net.bonds[perm], net.shifts[perm], net.kinds[perm]
    )


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), lattice=st.booleans())
def test_verdicts_do_not_depend_on_the_order_of_the_sites(seed, lattice):
    rng = np.random.default_rng(seed)
    net = (lattice_rods(rng, (3, 6), (0.4, 0.95)) if lattice else random_rods(rng, 6)).network
    perm = rng.permutation(net.n_sites)
    a, b = rigid_clusters(net), rigid_clusters(_shuffled(net, perm))
    assert (a.rank, a.wraps, a.self_stresses) == (b.rank, b.wraps, b.self_stresses)
    np.testing.assert_array_equal(a.overconstrained[perm], b.overconstrained)
    assert same_partition(a.labels[perm], b.labels)


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_adding_rods_never_lowers_rank_or_unwraps(seed):
    rng = np.random.default_rng(seed)
    net = lattice_rods(rng, (3, 6), (0.0, 1.0)).network
    order = rng.permutation(net.n_sites)
    first = first_wrapping(net, order)
    previous = None
    for q in range(0, net.n_sites + 1, max(1, net.n_sites // 6)):
        kinds = np.zeros(net.n_sites, dtype=np.int64)
        kinds[order[:q]] = Element.ROD
        r = rigid_clusters(net.with_kinds(kinds))
        assert r.wraps == (first >= 0 and q > first)
        assert r.rank <= 2 * net.n_nodes - 2 and r.self_stresses >= 0
        assert r.wraps <= (r.self_stresses > 0)
        assert r.overconstrained.any() == (r.self_stresses > 0)
        if previous is not None:
            assert r.rank >= previous.rank and r.wraps >= previous.wraps
        previous = r


@pytest.mark.parametrize("seed", range(16))
def test_each_circuit_is_balanced_iff_its_stress_has_zero_virial(seed):
    # every dependent bond of a pass in random order closes one circuit with the bonds
    # accepted before it; its stress (the null space of R^T there) must have zero macroscopic
    # stress exactly when the kernel calls the circuit balanced
    rng = np.random.default_rng([78, seed])
    inst = lattice_rods(rng, (3, 5), (0.5, 1.0)) if seed % 2 else random_rods(rng, 10)
    net = inst.network
    order = rng.permutation(np.flatnonzero(net.kinds != Element.EMPTY)).astype(np.int64)
    eu, ev, gx, gy = game_arrays(net)
    status, _, _, _ = pebble.play(net.n_nodes, eu, ev, gx, gy, order, False, False, NO_COMP)
    d = net.bond_vectors()
    dhat = d / np.hypot(d[:, 0], d[:, 1])[:, None]
    lattice_part = net.shifts @ net.box
    accepted: list[int] = []
    for b in order:
        if status[b] == pebble.INDEPENDENT:
            accepted.append(int(b))
            continue
        rows = np.array(accepted + [int(b)])
        R = rigidity_matrix(net, rows).toarray()
        stress = sl.null_space(R.T, rcond=1e-9)
        assert stress.shape[1] == 1
        t = stress[:, 0]
        virial = np.einsum("b,bi,bj->ij", t, lattice_part[rows], dhat[rows])
        unbalanced = np.abs(virial + virial.T).max() > 1e-8
        assert unbalanced == (status[b] == pebble.UNBALANCED)


def test_3d_networks_are_refused_not_counted_as_2d():
    """The (2, 3) count is a 2D theorem: a 3D network is refused in one line, never played."""
    from tensegrity_rigidity import InputError, find_threshold, lattice_instance, parse_spec
    from tensegrity_rigidity.model.sampling import lattice_geometry
    from tensegrity_rigidity.model.strain import strain_tensor

    inst = lattice_instance(3, 0.7, lattice="fcc", seed=1)
    with pytest.raises(InputError, match="2D networks"):
        rigid_clusters(inst)
    net, u, v = lattice_geometry(3, 0.2, np.random.default_rng(1), "fcc")
    with pytest.raises(InputError, match="2D networks"):
        find_threshold(net, u, v, strain_tensor("dilation", dim=3), 0.0, 0.5, "p_r", None, "pebble")
    spec = {"n": 3, "phi": "dilation", "lattice": {"kind": "fcc"}}
    with pytest.raises(InputError, match="2D lattices"):
        parse_spec(spec | {"threshold": {"path": "p_r", "method": "pebble"}})


@pytest.mark.parametrize("seed", range(6))
def test_the_spanning_cluster_is_the_full_labelling_cluster_of_the_threshold_bond(seed):
    from tensegrity_rigidity.combinatorics.clusters import spanning_cluster

    rng = np.random.default_rng([91, seed])
    net = lattice_rods(rng, (5, 9), (1.0, 1.0)).network
    order = rng.permutation(net.n_sites)
    sc = spanning_cluster(net, order)
    assert sc.position == first_wrapping(net, order) >= 0
    kinds = np.zeros(net.n_sites, dtype=np.int64)
    kinds[order[: sc.position + 1]] = Element.ROD
    full = rigid_clusters(net.with_kinds(kinds))
    assert full.wraps
    members = np.flatnonzero(full.labels == full.labels[order[sc.position]])
    np.testing.assert_array_equal(sc.sites, members)
    np.testing.assert_array_equal(sc.stressed, full.overconstrained[members])
    assert sc.stressed[np.searchsorted(sc.sites, order[sc.position])]  # it closed a circuit
    assert sc.nodes == np.unique(net.bonds[members]).size
    assert sc.stressed_nodes == np.unique(net.bonds[members[sc.stressed]]).size


def test_a_network_that_never_wraps_has_no_spanning_cluster():
    from tensegrity_rigidity.combinatorics.clusters import spanning_cluster

    net = lattice_instance(6, p_r=1.0, seed=2).network
    sc = spanning_cluster(net, np.arange(3))  # three rods cannot wrap
    assert sc.position == -1 and sc.sites.size == 0 and sc.nodes == sc.stressed_nodes == 0


def test_labelling_can_stop_after_the_first_seeded_cluster():
    net = lattice_instance(8, p_r=0.7, seed=5).network
    eu, ev, gx, gy = game_arrays(net)
    sites = np.flatnonzero(net.kinds == Element.ROD).astype(np.int64)
    _, _, out, _ = pebble.play(net.n_nodes, eu, ev, gx, gy, sites, False, False, NO_COMP)
    every = pebble.label_clusters(net.n_nodes, eu, ev, gx, gy, sites, out)
    one = pebble.label_clusters(net.n_nodes, eu, ev, gx, gy, sites, out, 1)
    np.testing.assert_array_equal(one >= 0, every == every[sites[0]])
    assert every.max() > 0  # there were others to leave out


@pytest.mark.parametrize(
    "order, match",
    [
        ([0, 1, 10**6], "out of range"),
        ([-1, 0], "out of range"),
        ([0, 0, 1], "twice"),
        ([0.0, 1.0], "integer"),
        ([[0, 1]], "1D"),
        (["a"], "integer"),
    ],
)
def test_orders_the_kernel_cannot_take_are_refused(order, match):
    """The compiled pebble game does not check its indices: a site past the network read and
    wrote outside its arrays. Every entry into it checks the order first."""
    from tensegrity_rigidity.combinatorics.clusters import spanning_cluster

    net = lattice_instance(4, 0.0, seed=1).network
    for entry in (first_wrapping, spanning_cluster):
        with pytest.raises(InputError, match=match):
            entry(net, np.array(order))
    with pytest.raises(InputError, match="PeriodicNetwork"):
        first_wrapping("net", np.arange(3))


def _strain_stress(net, order, position, strain):
    """(m,) |t*| / max |t*| of the rods ``order[: position + 1]`` under ``strain``: the
    projection of the affine extensions onto the self-stresses (dense oracle)."""
    from tensegrity_rigidity.model.mechanics import affine_extensions

    kinds = np.zeros(net.n_sites, dtype=np.int64)
    kinds[order[: position + 1]] = Element.ROD
    at = net.with_kinds(kinds)
    sites = np.flatnonzero(kinds != Element.EMPTY)
    stresses = sl.null_space(rigidity_matrix(at, sites).toarray().T, rcond=1e-9)
    e0 = affine_extensions(at, strain)[sites]
    t = np.zeros(net.n_sites)
    t[sites] = np.abs(stresses @ (stresses.T @ e0))
    return t / t.max()


@pytest.mark.parametrize(
    "n, sample", [(16, 8), (16, 1), (12, 3), pytest.param(32, 3, marks=pytest.mark.slow)]
)
def test_the_backbone_is_what_a_strain_stresses_at_the_threshold(n, sample):
    """The threshold bond's component in the rigidity matroid carries every bond a generic
    strain stresses, and no other: the backbone (at n = 16, sample 8 and n = 32, sample 3
    smaller than the overconstrained part of the spanning cluster, by 12 and 108 bonds)."""
    from tensegrity_rigidity.combinatorics.clusters import spanning_cluster
    from tensegrity_rigidity.model.sampling import lattice_geometry

    net, u, _ = lattice_geometry(n, 0.2, np.random.default_rng([n, sample]), "triangular")
    order = np.argsort(u).astype(np.int64)
    sc = spanning_cluster(net, order)
    backbone = np.zeros(net.n_sites, dtype=bool)
    backbone[sc.sites[sc.backbone]] = True
    assert backbone[order[sc.position]] and np.all(sc.stressed[sc.backbone])
    assert sc.backbone_nodes == np.unique(net.bonds[backbone]).size
    t = _strain_stress(net, order, sc.position, strain_tensor(1.0, 0.3))
    # stresses of the backbone stand clear of the dense oracle's rounding elsewhere
    assert t[backbone].min() > 100 * t[~backbone].max()
    if (n, sample) in ((16, 8), (32, 3)):
        assert sc.backbone.sum() < sc.stressed.sum()


def test_bonds_of_a_lone_node_to_its_own_images_are_one_body():
    """Two bonds of node 1 to its own images (and nothing else at it) got labels 1 and 2, while
    on a node with other bonds they join that node's cluster."""
    net = PeriodicNetwork(
        np.eye(2) * 3.0,
        [[0.3, 0.4], [1.7, 2.1]],
        [[0, 0], [1, 1], [1, 1]],
        [[2, 2], [-2, 0], [2, 1]],
        [Element.ROD] * 3,
    )
    labels = rigid_clusters(net).labels
    assert labels[1] == labels[2] != labels[0]
