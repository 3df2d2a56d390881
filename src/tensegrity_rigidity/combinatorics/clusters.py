"""Rigid clusters, stressed bonds and floppy modes of a rods-only network, combinatorially.

For generic positions the rank of the rigidity matrix of a periodic network on a *fixed* torus
is that of a count matroid on its bond sites (Ross 2014), decided here by a pebble game in
integer arithmetic (:mod:`~tensegrity_rigidity.combinatorics.pebble`); whether the network
resists a generic strain follows from the balancedness of its circuits. The rules and their
proofs: docs/guide/rigid-clusters.md.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from ..model.limits import check_memory, stage_bytes
from ..model.network import Element, Instance, PeriodicNetwork, fields_repr, show
from . import pebble


@dataclass(frozen=True, eq=False)
class RigidClusters:
    """The combinatorial rigidity of a rods-only periodic network on its fixed box.

    Attributes
    ----------
    labels : (m,) int64
        Rigid-cluster label of each bond site, ``0 .. n_clusters - 1`` (numbered in order of
        the first site of each cluster), -1 on empty sites. Two bonds share a label when they
        belong to one rigid body: a finite one (balanced: no cycle of it wraps the torus) or a
        rigid region that wraps it.
    overconstrained : (m,) bool
        Sites in the support of some self-stress (in a circuit of the rigidity matroid).
    rank : int
        Generic rank of the rigidity matrix (fixed torus).
    floppy_modes : int
        ``2 N - rank``: zero modes of the rigidity matrix, the 2 rigid translations included
        (on a fixed torus there is no rotation).
    self_stresses : int
        ``(number of bonds) - rank``: dimension of the space of self-stresses.
    wraps : bool
        The network resists a generic metric strain: some circuit is unbalanced, so some
        self-stress has a non-zero macroscopic stress.
    """

    labels: np.ndarray
    overconstrained: np.ndarray
    rank: int
    floppy_modes: int
    self_stresses: int
    wraps: bool

    __repr__ = fields_repr

    @property
    def n_clusters(self) -> int:
        """Number of rigid clusters (a lone bond is a cluster)."""
        return int(self.labels.max(initial=-1)) + 1


def _lone_nodes_one_body(raw: np.ndarray, sites: np.ndarray, eu: np.ndarray,
                         ev: np.ndarray) -> np.ndarray:  # fmt: skip
    """Bonds of a node to its own images, on a node with no other bond, as one body: the node.

    The kernel gives each such bond a label of its own there (and the node's cluster's label
    on a node that has other bonds), so that two bonds of one lone node read as two bodies.
    """
    self_bond = eu[sites] == ev[sites]
    if not self_bond.any():
        return raw
    out = raw.copy()
    other = np.zeros(int(max(eu.max(initial=0), ev.max(initial=0))) + 1, dtype=bool)
    other[eu[sites[~self_bond]]] = other[ev[sites[~self_bond]]] = True
    first: dict[int, int] = {}
    for b in sites[self_bond]:
        node = int(eu[b])
        if not other[node]:
            out[b] = out[first.setdefault(node, int(b))]
    return out


def _as_network(network) -> PeriodicNetwork:
    if isinstance(network, Instance):
        return network.network
    if not isinstance(network, PeriodicNetwork):
        raise InputError(f"needs a PeriodicNetwork or an Instance, got {type(network).__name__}")
    return network


def _check_order(network: PeriodicNetwork, order) -> np.ndarray:
    """``order`` as the kernel takes it: distinct site indices in ``[0, m)``, int64.

    The compiled kernel does not check its indices (an index past the sites reads and writes
    outside its arrays), so every entry into it is checked here first.
    """
    m = network.n_sites
    try:
        raw = np.asarray(order)
    except (TypeError, ValueError):
        raise InputError("order must be a 1D array of bond site indices") from None
    if raw.ndim != 1:
        raise InputError(f"order must be a 1D array of bond site indices, got shape {raw.shape}")
    if raw.size and raw.dtype.kind not in "iu":
        raise InputError(f"order must hold integer site indices, got dtype {raw.dtype}")
    if raw.size and (int(raw.min()) < 0 or int(raw.max()) >= m):
        bad = raw[(raw < 0) | (raw >= m)][0]
        raise InputError(f"order holds site {bad}, out of range for {m} bond sites")
    arr = np.ascontiguousarray(raw, dtype=np.int64)
    if _distinct(arr, m) != arr.size:
        raise InputError("order must not add a bond site twice")
    return arr


def _distinct(indices: np.ndarray, size: int) -> int:
    """How many distinct values ``indices`` (ints in ``[0, size)``) holds: a mask, O(size)
    (``np.unique`` sorts or hashes, a hundred times slower on a million sites)."""
    seen = np.zeros(size, dtype=bool)
    seen[indices] = True
    return int(np.count_nonzero(seen))


#: the kernel's argument when the matroid's components are not tracked
NO_COMP = np.zeros(0, dtype=np.int64)


def game_arrays(network: PeriodicNetwork) -> tuple[np.ndarray, ...]:
    """Ends and gains of every site, as the kernel takes them.

    Parameters
    ----------
    network : PeriodicNetwork
        ``N`` nodes, ``m`` sites.

    Returns
    -------
    eu, ev, gx, gy : (m,) int64
        The ends of each site and its image shift (gain).

    Raises
    ------
    InputError
        When the network is not two-dimensional (generic rigidity in 3D is not a count: no
        pebble game decides it), too large for the kernel's packed potentials, or for this
        machine's memory (the measured cost per node, :mod:`~tensegrity_rigidity.model.limits`).
    """
    if network.dim != 2:
        raise InputError(
            f"the pebble game decides 2D networks; this one is {network.dim}-dimensional "
            "(use the certified verdict: decide, or find_threshold with method 'lp')"
        )
    need = stage_bytes("clusters", network.n_nodes, dim=2)
    check_memory(need, f"the pebble game on {network.n_nodes:,} nodes")
    shifts = network.shifts
    largest = int(np.abs(shifts).max(initial=0))
    if network.n_nodes >= pebble.MAX_NODES or largest >= pebble.MAX_SHIFT:
        raise InputError(
            f"network too large for the pebble game ({network.n_nodes} nodes, image shifts up "
            f"to {largest}); it takes below {pebble.MAX_NODES} nodes and shifts below "
            f"{pebble.MAX_SHIFT}"
        )
    bonds = np.ascontiguousarray(network.bonds, dtype=np.int64)
    return (
        bonds[:, 0].copy(),
        bonds[:, 1].copy(),
        np.ascontiguousarray(shifts[:, 0], dtype=np.int64),
        np.ascontiguousarray(shifts[:, 1], dtype=np.int64),
    )


def first_wrapping(network: PeriodicNetwork, order: np.ndarray) -> int:
    """Position of the bond that makes a growing rods-only network resist a generic strain.

    Parameters
    ----------
    network : PeriodicNetwork
        Geometry (element kinds are ignored).
    order : (k,) int
        Sites added one by one, as rods.

    Returns
    -------
    int
        The smallest ``q`` such that the rods ``order[: q + 1]`` resist a generic strain, -1 if
        even all of them do not. One incremental pass of the pebble game, stopped there.
    """
    network = _as_network(network)
    order = _check_order(network, order)
    eu, ev, gx, gy = game_arrays(network)
    _, first, _, _ = pebble.play(network.n_nodes, eu, ev, gx, gy, order, True, False, NO_COMP)
    return int(first)


@dataclass(frozen=True, eq=False)
class SpanningCluster:
    """The rigid cluster that first resists a generic strain as rods are added one by one.

    Attributes
    ----------
    position : int
        Position in the order of the bond that closed the first unbalanced circuit (the
        threshold event), -1 if none did (then the other fields are empty).
    sites : (k,) int64
        Bond sites of the rigid cluster holding that bond, just after it was added: the cluster
        that wraps the torus at the threshold (its mass is ``sites.size``).
    stressed : (k,) bool
        Which of ``sites`` are overconstrained (in some circuit) at the threshold: the
        overconstrained part of the spanning cluster, the backbone and any stressed region
        hinged to it.
    nodes : int
        Nodes that ``sites`` touch.
    stressed_nodes : int
        Nodes that the stressed sites touch.
    backbone : (k,) bool
        Which of ``sites`` lie in a circuit with the threshold bond (its connected component in
        the rigidity matroid): the bonds a generic strain stresses at the threshold, the
        load-carrying backbone (a stressed region hinged to it at one node carries no load).
    backbone_nodes : int
        Nodes that the backbone touches.
    """

    position: int
    sites: np.ndarray
    stressed: np.ndarray
    nodes: int
    stressed_nodes: int
    backbone: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=bool))
    backbone_nodes: int = 0

    __repr__ = fields_repr


def spanning_cluster(network: PeriodicNetwork, order: np.ndarray) -> SpanningCluster:
    """The spanning rigid cluster and its stressed part at the threshold of a growing network.

    Parameters
    ----------
    network : PeriodicNetwork
        Geometry (element kinds are ignored).
    order : (k,) int
        Sites added one by one, as rods.

    Returns
    -------
    SpanningCluster
        One incremental pass stopped at the threshold event (as :func:`first_wrapping`), with
        the circuits and the matroid's components tracked; then only the cluster of the
        threshold bond is grown, not every cluster (which costs far more at large n, the
        clusters being many).
    """
    network = _as_network(network)
    order = _check_order(network, order)
    eu, ev, gx, gy = game_arrays(network)
    comp = np.arange(network.n_sites, dtype=np.int64)
    _, first, out, over = pebble.play(network.n_nodes, eu, ev, gx, gy, order, True, True, comp)
    if first < 0:
        empty = np.zeros(0, dtype=np.int64)
        return SpanningCluster(-1, empty, np.zeros(0, dtype=bool), 0, 0)
    present = order[: first + 1]
    seeds = np.r_[order[first], present[:first]]
    raw = pebble.label_clusters(network.n_nodes, eu, ev, gx, gy, seeds, out, 1)
    sites = np.flatnonzero(raw == 0).astype(np.int64)
    stressed = over[sites]
    backbone = _roots(comp, sites) == _roots(comp, order[first : first + 1])[0]
    bonds = network.bonds[sites]
    return SpanningCluster(
        position=int(first),
        sites=sites,
        stressed=stressed,
        nodes=_distinct(bonds, network.n_nodes),
        stressed_nodes=_distinct(bonds[stressed], network.n_nodes),
        backbone=backbone,
        backbone_nodes=_distinct(bonds[backbone], network.n_nodes),
    )


def _roots(comp: np.ndarray, sites: np.ndarray) -> np.ndarray:
    """The union-find root of each of ``sites`` in ``comp`` (no compression: read only)."""
    roots = comp[sites]
    while True:
        up = comp[roots]
        if np.array_equal(up, roots):
            return roots
        roots = up


def rigid_clusters(network: PeriodicNetwork | Instance, as_rods: bool = False) -> RigidClusters:
    """Rigid clusters, overconstrained bonds, floppy modes and strain rigidity of a network.

    Parameters
    ----------
    network : PeriodicNetwork or Instance
        The network (of an instance, its strain is ignored: the verdict is for a generic
        strain). Its non-empty sites must all be rods unless ``as_rods``.
    as_rods : bool
        Treat every cable and strut as a rod: an upper bound on a tensegrity's rigidity (Roth
        and Whiteley 1981).

    Returns
    -------
    RigidClusters
        Labels, overconstrained sites, rank, floppy modes, self-stresses and ``wraps``.

    Raises
    ------
    InputError
        On a network with cables or struts (without ``as_rods``), or one too large for the
        kernel.

    Notes
    -----
    Exact for generic positions (the node disorder makes them generic with probability 1) and a
    generic strain: a strain whose work on every self-stress happens to vanish (pure shear whose
    neutral axis lies along the one direction a stressed cluster wraps) is not generic.

    Examples
    --------
    >>> from tensegrity_rigidity import lattice_instance, rigid_clusters
    >>> rigid_clusters(lattice_instance(6, p_r=1.0, seed=1)).wraps
    True
    >>> rigid_clusters(lattice_instance(6, p_r=0.3, seed=1)).wraps
    False
    """
    if not isinstance(as_rods, (bool, np.bool_)):
        raise InputError(f"as_rods must be True or False, got {show(as_rods)}")
    net = _as_network(network)
    kinds = net.kinds
    one_sided = np.flatnonzero((kinds == Element.CABLE) | (kinds == Element.STRUT))
    if one_sided.size and not as_rods:
        raise InputError(
            f"rigid_clusters takes rods only, got {one_sided.size} cables or struts "
            "(pass as_rods=True to treat them as rods)"
        )
    sites = np.flatnonzero(kinds != Element.EMPTY).astype(np.int64)
    eu, ev, gx, gy = game_arrays(net)
    status, first, out, over = pebble.play(net.n_nodes, eu, ev, gx, gy, sites, False, True, NO_COMP)
    independent = status[sites] == pebble.INDEPENDENT
    seeds = np.r_[sites[independent], sites[~independent]]
    raw = _lone_nodes_one_body(pebble.label_clusters(net.n_nodes, eu, ev, gx, gy, seeds, out),
                               sites, eu, ev)  # fmt: skip
    labels = np.full(net.n_sites, -1, dtype=np.int64)
    if sites.size:
        # renumber by first site: labels do not depend on the seeding order
        _, first_at, inverse = np.unique(raw[sites], return_index=True, return_inverse=True)
        rank_of = np.empty(first_at.size, dtype=np.int64)
        rank_of[np.argsort(first_at)] = np.arange(first_at.size)
        labels[sites] = rank_of[inverse]
    rank = int(np.count_nonzero(independent))
    for arr in (labels, over):
        arr.setflags(write=False)
    return RigidClusters(
        labels=labels,
        overconstrained=over,
        rank=rank,
        floppy_modes=2 * net.n_nodes - rank,
        self_stresses=int(sites.size) - rank,
        wraps=bool(first >= 0),
    )
