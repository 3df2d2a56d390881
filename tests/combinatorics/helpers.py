"""Random rods-only instances and dense linear-algebra oracles for the pebble-game tests."""

from __future__ import annotations

import numpy as np
import scipy.linalg as sl

from tensegrity_rigidity import Element, Instance, lattice_instance, random_periodic_network
from tensegrity_rigidity.model.mechanics import rigidity_matrix
from tensegrity_rigidity.model.network import PeriodicNetwork
from tensegrity_rigidity.model.strain import strain_tensor

#: rods-only threshold of the bond-diluted triangular lattice (Jacobs and Thorpe 1995)
P_C = 0.66
#: rod probabilities of the cross-validation, around P_C
P_RANGE = (0.6, 0.72)
#: singular values below this (relative to the largest) count as zero in the dense oracles
RANK_TOL = 1e-9


def generic_strain(rng: np.random.Generator) -> np.ndarray:
    """A strain of random type and principal-axis angle (generic with probability 1)."""
    return strain_tensor(float(rng.uniform(0, 2 * np.pi)), float(rng.uniform(0, 2 * np.pi)))


def lattice_rods(rng: np.random.Generator, n_range=(5, 12), p_range=P_RANGE) -> Instance:
    """A disordered triangular lattice with rods only, p_r in ``p_range``, a generic strain."""
    n = int(rng.integers(n_range[0], n_range[1] + 1))
    p = float(rng.uniform(*p_range))
    inst = lattice_instance(n, p_r=p, seed=int(rng.integers(1 << 31)))
    return inst.with_strain(generic_strain(rng))


def random_rods(rng: np.random.Generator, max_nodes: int = 8) -> Instance:
    """A random periodic network (skewed box, loops, parallel bonds, shifts up to 2), all rods."""
    nn = int(rng.integers(1, max_nodes + 1))
    mb = int(rng.integers(1, 3 * nn + 4))
    net = random_periodic_network(nn, mb, rng, max_shift=int(rng.integers(1, 3)))
    return Instance(net.with_kinds(np.full(mb, Element.ROD)), generic_strain(rng))


def dense_rigidity(net: PeriodicNetwork) -> tuple[np.ndarray, np.ndarray]:
    """(sites, R): the non-empty sites and their dense rigidity matrix, (k, 2N)."""
    sites = np.flatnonzero(net.kinds != Element.EMPTY)
    return sites, rigidity_matrix(net, sites).toarray()


def stress_support(net: PeriodicNetwork) -> np.ndarray:
    """(m,) bool: sites in the support of the null space of R^T (the self-stresses)."""
    sites, R = dense_rigidity(net)
    support = np.zeros(net.n_sites, dtype=bool)
    if sites.size:
        ns = sl.null_space(R.T, rcond=RANK_TOL)
        if ns.size:
            support[sites] = np.abs(ns).max(axis=1) > 1e-7
    return support


def rotation_partition(net: PeriodicNetwork) -> np.ndarray:
    """Rigid-cluster partition from the zero modes: labels per non-empty, non-loop site.

    Two bonds sharing a node belong to one rigid body iff the angle between them is fixed in
    every zero mode of R (equal rotation rates); clusters are the connected classes.
    """
    sites, R = dense_rigidity(net)
    ns = sl.null_space(R, rcond=RANK_TOL)  # (2N, f) zero modes
    i, j = net.bonds[sites, 0], net.bonds[sites, 1]
    d = net.bond_vectors()[sites]
    length2 = (d**2).sum(axis=1)
    du = ns.reshape(net.n_nodes, 2, -1)
    rel = du[j] - du[i]  # (k, 2, f)
    omega = (d[:, 0, None] * rel[:, 1] - d[:, 1, None] * rel[:, 0]) / length2[:, None]
    parent = list(range(sites.size))

    def find(a):
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    loops = i == j
    for a in range(sites.size):
        for b in range(a + 1, sites.size):
            if loops[a] or loops[b] or not ({i[a], j[a]} & {i[b], j[b]}):
                continue
            if np.abs(omega[a] - omega[b]).max(initial=0.0) < 1e-7:
                parent[find(a)] = find(b)
    roots = np.array([find(a) for a in range(sites.size)])
    return np.where(loops, -1, roots)


def same_partition(a: np.ndarray, b: np.ndarray) -> bool:
    """Whether two label arrays define the same partition."""
    pairs = set(zip(a.tolist(), b.tolist(), strict=True))
    return len(pairs) == len(set(a.tolist())) == len(set(b.tolist()))
