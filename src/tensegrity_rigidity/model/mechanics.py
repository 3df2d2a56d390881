"""Linear mechanics of a strained periodic network: rigidity matrix, extensions, energy, tensions.

Notation (MODEL.md): node displacements ``u`` (N, 2), flattened to 2N as
``(u_0x, u_0y, u_1x, ...)``.
Bond extensions ``e = e0 + R u`` with ``R`` the (m, 2N) rigidity matrix (row b: ``-dhat_b`` at
node i, ``+dhat_b`` at node j) and ``e0_b = dhat_b . eps . d_b`` the affine extension. The energy
is ``E(u) = 1/2 sum_b k_b h_b(e_b) e_b^2`` with ``h = 1`` (rod), ``Theta(e)`` (cable),
``Theta(-e)`` (strut), ``0`` (empty), and the tension is ``t_b = k_b h_b(e_b) e_b``
(positive = pulling).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from .network import Element, Instance, PeriodicNetwork


def unit_vectors(network: PeriodicNetwork) -> np.ndarray:
    """Unit bond vectors dhat, shape (m, 2)."""
    d = network.bond_vectors()
    return d / np.hypot(d[:, 0], d[:, 1])[:, None]


def rigidity_matrix(network: PeriodicNetwork, sites: np.ndarray | None = None) -> sp.csr_matrix:
    """Sparse rigidity matrix R, shape (m, 2N) (or (len(sites), 2N) for a subset of sites).

    A bond joining a node to its own image has a zero row: its length cannot change by
    displacing nodes, only by the strain.
    """
    bonds = network.bonds if sites is None else network.bonds[sites]
    dhat = unit_vectors(network) if sites is None else unit_vectors(network)[sites]
    m = bonds.shape[0]
    i, j = bonds[:, 0], bonds[:, 1]
    rows = np.repeat(np.arange(m), 4)
    cols = np.c_[2 * i, 2 * i + 1, 2 * j, 2 * j + 1].ravel()
    vals = np.c_[-dhat, dhat].ravel()
    return sp.csr_matrix((vals, (rows, cols)), shape=(m, 2 * network.n_nodes))


def affine_extensions(network: PeriodicNetwork, strain: np.ndarray) -> np.ndarray:
    """Affine extensions e0_b = dhat_b . eps . d_b, shape (m,)."""
    d = network.bond_vectors()
    length = np.hypot(d[:, 0], d[:, 1])
    return np.einsum("bi,ij,bj->b", d, np.asarray(strain, dtype=float), d) / length


def tensions_from_extensions(kinds: np.ndarray, stiffness: np.ndarray, e: np.ndarray) -> np.ndarray:
    """Tensions t_b = k_b h_b(e_b) e_b, shape (m,)."""
    t = np.zeros_like(e)
    rod = kinds == Element.ROD
    cable = (kinds == Element.CABLE) & (e > 0)
    strut = (kinds == Element.STRUT) & (e < 0)
    on = rod | cable | strut
    t[on] = stiffness[on] * e[on]
    return t


def energy_from_extensions(kinds: np.ndarray, stiffness: np.ndarray, e: np.ndarray) -> float:
    """E = 1/2 sum_b k_b h_b(e_b) e_b^2 for extensions e of shape (m,)."""
    t = tensions_from_extensions(kinds, stiffness, e)
    return 0.5 * float(np.dot(t, e))


def extensions(instance: Instance, displacements: np.ndarray | None = None) -> np.ndarray:
    """Total extensions e = e0 + R u, shape (m,); ``displacements`` is (N, 2) or None (affine)."""
    net = instance.network
    e = affine_extensions(net, instance.strain)
    if displacements is not None:
        e = e + rigidity_matrix(net) @ np.asarray(displacements, dtype=float).ravel()
    return e


def energy(instance: Instance, displacements: np.ndarray | None = None) -> float:
    """Energy E(u) of the instance for displacements (N, 2); the affine energy when None."""
    net = instance.network
    return energy_from_extensions(
        net.kinds, net.stiffness_or_ones(), extensions(instance, displacements)
    )


def tensions(instance: Instance, displacements: np.ndarray | None = None) -> np.ndarray:
    """Tensions t (m,) for displacements (N, 2); affine tensions when None."""
    net = instance.network
    return tensions_from_extensions(
        net.kinds, net.stiffness_or_ones(), extensions(instance, displacements)
    )


def net_forces(network: PeriodicNetwork, t: np.ndarray) -> np.ndarray:
    """Net force on each node from bond tensions t (m,): R^T t reshaped to (N, 2)."""
    return (rigidity_matrix(network).T @ t).reshape(-1, 2)
