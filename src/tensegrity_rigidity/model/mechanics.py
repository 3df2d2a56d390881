"""Linear mechanics of a strained periodic network: rigidity matrix, extensions, energy, tensions.

Notation (docs/model.md): node displacements ``u`` (N, d) in ``d = 2`` or ``3`` dimensions,
flattened to dN as ``(u_0x, u_0y, [u_0z,] u_1x, ...)``.
Bond extensions ``e = e0 + R u`` with ``R`` the (m, dN) rigidity matrix (row b: ``-dhat_b`` at
node i, ``+dhat_b`` at node j) and ``e0_b = dhat_b . eps . d_b`` the affine extension. The energy
is ``E(u) = 1/2 sum_b k_b h_b(e_b) e_b^2`` with ``h = 1`` (rod), ``Theta(e)`` (cable),
``Theta(-e)`` (strut), ``0`` (empty), and the tension is ``t_b = k_b h_b(e_b) e_b``
(positive = pulling).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from .network import Element, Instance, PeriodicNetwork, vector_norms


def unit_vectors(network: PeriodicNetwork) -> np.ndarray:
    """Unit bond vectors ``dhat_b = d_b / |d_b|``.

    Parameters
    ----------
    network : PeriodicNetwork
        The network (``m`` sites).

    Returns
    -------
    (m, d) float
        One unit vector per site (empty sites included).
    """
    d = network.bond_vectors()
    return d / vector_norms(d)[:, None]


def rigidity_matrix(network: PeriodicNetwork, sites: np.ndarray | None = None) -> sp.csr_matrix:
    """Sparse rigidity matrix R: row b is ``-dhat_b`` at node i and ``+dhat_b`` at node j.

    Parameters
    ----------
    network : PeriodicNetwork
        The network (``N`` nodes, ``m`` sites).
    sites : (k,) int, optional
        Rows to build (indices of sites); all ``m`` when omitted.

    Returns
    -------
    scipy.sparse.csr_matrix
        Shape (m, dN) (or (k, dN)); columns ``d i`` to ``d i + d - 1`` are node i's
        coordinates.

    Notes
    -----
    ``R u`` gives the extensions of the bonds to first order in the displacements ``u``
    (flattened (dN,)), ``R^T t`` the net forces of tensions ``t``. A bond joining a node to its
    own image has a zero row: its length cannot change by displacing nodes, only by the
    strain.
    """
    bonds = network.bonds if sites is None else network.bonds[sites]
    dhat = unit_vectors(network) if sites is None else unit_vectors(network)[sites]
    m, d = bonds.shape[0], network.dim
    i, j = bonds[:, 0], bonds[:, 1]
    rows = np.repeat(np.arange(m), 2 * d)
    axes = np.arange(d)
    cols = np.c_[d * i[:, None] + axes, d * j[:, None] + axes].ravel()
    vals = np.c_[-dhat, dhat].ravel()
    return sp.csr_matrix((vals, (rows, cols)), shape=(m, d * network.n_nodes))


def affine_extensions(network: PeriodicNetwork, strain: np.ndarray) -> np.ndarray:
    """Affine extensions ``e0_b = dhat_b . eps . d_b`` (docs/model.md: a scalar per bond).

    Parameters
    ----------
    network : PeriodicNetwork
        The network (``m`` sites).
    strain : (d, d) float
        Strain tensor eps, magnitude included.

    Returns
    -------
    (m,) float
        The extension of every site under the affine deformation ``u = 0``.
    """
    d = network.bond_vectors()
    # in units of a power of two near the box's size (exact, so the same bits at any scale
    # where nothing under- or overflows): the product d . eps . d would square a box of
    # 1e-300 to zero, or one of 1e300 to infinity
    _, exponent = np.frexp(float(np.abs(network.box).max()))
    d = np.ldexp(d, -int(exponent))
    length = vector_norms(d)
    e0 = np.einsum("bi,ij,bj->b", d, np.asarray(strain, dtype=float), d) / length
    return np.ldexp(e0, int(exponent))


def tensions_from_extensions(kinds: np.ndarray, stiffness: np.ndarray, e: np.ndarray) -> np.ndarray:
    """Tensions ``t_b = k_b h_b(e_b) e_b`` (positive pulls).

    Parameters
    ----------
    kinds : (m,) int
        :class:`~.network.Element` codes.
    stiffness : (m,) float
        Spring constants.
    e : (m,) float
        Extensions.

    Returns
    -------
    (m,) float
        ``k e`` on rods, on stretched cables and on compressed struts; 0 elsewhere.
    """
    t = np.zeros_like(e)
    rod = kinds == Element.ROD
    cable = (kinds == Element.CABLE) & (e > 0)
    strut = (kinds == Element.STRUT) & (e < 0)
    on = rod | cable | strut
    t[on] = stiffness[on] * e[on]
    return t


def energy_from_extensions(kinds: np.ndarray, stiffness: np.ndarray, e: np.ndarray) -> float:
    """The energy ``E = 1/2 sum_b k_b h_b(e_b) e_b^2`` of given extensions.

    Parameters
    ----------
    kinds : (m,) int
        :class:`~.network.Element` codes.
    stiffness : (m,) float
        Spring constants.
    e : (m,) float
        Extensions.

    Returns
    -------
    float
        E.

    Notes
    -----
    Summed by NumPy's pairwise summation, not a BLAS dot product: a multithreaded BLAS splits
    a dot product of more than about 10,000 entries between its threads and adds the parts
    in another order, so the energy's last digits depended on the thread count (at n = 64 the
    affine energy of a sweep's rows differed between one worker and two).
    """
    t = tensions_from_extensions(kinds, stiffness, e)
    return 0.5 * float(np.sum(t * e))


def extensions(instance: Instance, displacements: np.ndarray | None = None) -> np.ndarray:
    """Total extensions ``e = e0 + R u``.

    Parameters
    ----------
    instance : Instance
        Network and strain.
    displacements : (N, d) float, optional
        Node displacements ``u``; the affine deformation (``u = 0``) when omitted.

    Returns
    -------
    (m,) float
        Extension of every site.
    """
    net = instance.network
    e = affine_extensions(net, instance.strain)
    if displacements is not None:
        e = e + rigidity_matrix(net) @ np.asarray(displacements, dtype=float).ravel()
    return e


def energy(instance: Instance, displacements: np.ndarray | None = None) -> float:
    """The energy ``E(u)`` of an instance.

    Parameters
    ----------
    instance : Instance
        Network, elements, stiffness and strain.
    displacements : (N, d) float, optional
        Node displacements; the affine energy ``E(u = 0)`` when omitted.

    Returns
    -------
    float
        E.
    """
    net = instance.network
    return energy_from_extensions(
        net.kinds, net.stiffness_or_ones(), extensions(instance, displacements)
    )


def tensions(instance: Instance, displacements: np.ndarray | None = None) -> np.ndarray:
    """Tensions of the elements at given displacements.

    Parameters
    ----------
    instance : Instance
        Network, elements, stiffness and strain.
    displacements : (N, d) float, optional
        Node displacements; the affine tensions when omitted.

    Returns
    -------
    (m,) float
        ``t_b = k_b h_b(e_b) e_b`` (:func:`tensions_from_extensions`).
    """
    net = instance.network
    return tensions_from_extensions(
        net.kinds, net.stiffness_or_ones(), extensions(instance, displacements)
    )


def net_forces(network: PeriodicNetwork, t: np.ndarray) -> np.ndarray:
    """Net force on each node from bond tensions: ``R^T t``.

    Parameters
    ----------
    network : PeriodicNetwork
        The network (``N`` nodes, ``m`` sites).
    t : (m,) float
        Tensions (positive pulls).

    Returns
    -------
    (N, d) float
        Force on every node; zero everywhere for a self-stress.
    """
    return (rigidity_matrix(network).T @ t).reshape(-1, network.dim)
