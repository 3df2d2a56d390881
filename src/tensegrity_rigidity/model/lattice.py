"""Builders of periodic networks: the paper's triangular lattice, a square lattice, random networks.

Every builder takes an explicit ``numpy.random.Generator``; nothing here touches global random
state. Builders return networks with all bond sites *empty*; elements are placed afterwards by
:func:`tensegrity_rigidity.model.elements.place_elements`.
"""

from __future__ import annotations

import warnings

import numpy as np

from ..errors import InputError
from .limits import BUILD_BYTES_PER_NODE, check_memory
from .network import Element, PeriodicNetwork

#: Default node disorder of the triangular lattice. The paper does not state its value; 0.2 (in
#: units of the lattice constant) is large enough to remove the straight lines of the perfect
#: lattice and small enough that no bond comes close to zero length. Keep it a parameter.
DEFAULT_DELTA = 0.2

#: Smallest disorder at which bonds *can* cross, per lattice: a node kicked across the opposite
#: side of one of its triangles. The signed area of a triangle is affine in each kicked
#: coordinate, so its minimum over the kicks lies at a corner of the kick box; the smallest
#: delta at which that minimum reaches zero is (3 - sqrt 3) / 4 on the triangular lattice and
#: 1/4 on the square lattice with diagonals. Without diagonals the square lattice's bonds
#: cannot cross for delta < 1/2.
CROSSING_DELTA = {"triangular": (3.0 - np.sqrt(3.0)) / 4.0, "square": 0.5, "square+diagonals": 0.25}


class CrossingBondsWarning(UserWarning):
    """The node disorder turned some triangles of a lattice inside out: bonds cross."""


B1 = np.array([1.0, 0.0])
B2 = np.array([-0.5, np.sqrt(3.0) / 2.0])


def _check_size(n: int) -> int:
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)):
        raise InputError(f"n must be an integer, got {n!r}")
    if n < 2:
        raise InputError(f"n must be at least 2, got {n}")
    check_memory(BUILD_BYTES_PER_NODE * float(n) ** 2, f"a lattice of n = {n} ({n}^2 nodes)")
    return int(n)


def inverted_triangles(net: PeriodicNetwork) -> int:
    """Number of inside-out triangles of a grid lattice built here (crossing bonds).

    Parameters
    ----------
    net : PeriodicNetwork
        A network from :func:`triangular_lattice` or :func:`square_lattice` (``N`` nodes).

    Returns
    -------
    int
        Triangles whose orientation flipped; 0 for a network without ``3 N`` sites.

    Notes
    -----
    Sites ``0..N-1``, ``N..2N-1``, ``2N..3N-1`` join node ``i`` to its ``+b1``, ``+b2`` and
    ``+(b1 + b2)`` neighbours, so the two triangles at node ``i`` have the sides ``(d1, d3)``
    and ``(d3, d2)``, both counter-clockwise in the undisturbed lattice; a non-positive cross
    product means a node crossed the opposite side. Networks with another number of sites (the
    square lattice without diagonals) have no triangles.
    """
    n_nodes = net.n_nodes
    if net.n_sites != 3 * n_nodes:
        return 0
    d = net.bond_vectors()
    d1, d2, d3 = d[:n_nodes], d[n_nodes : 2 * n_nodes], d[2 * n_nodes :]
    up = d1[:, 0] * d3[:, 1] - d1[:, 1] * d3[:, 0]
    down = d3[:, 0] * d2[:, 1] - d3[:, 1] * d2[:, 0]
    return int(np.count_nonzero(up <= 0) + np.count_nonzero(down <= 0))


def _warn_if_crossing(net: PeriodicNetwork, delta: float, name: str) -> None:
    bad = inverted_triangles(net)
    if bad:
        warnings.warn(
            f"delta = {delta} turned {bad} triangle(s) of the {name} lattice inside out: bonds "
            f"cross (possible from delta = {CROSSING_DELTA[name]:.4f})",
            CrossingBondsWarning,
            stacklevel=3,
        )


def _check_delta(delta: float) -> float:
    delta = float(delta)
    if not np.isfinite(delta):
        raise InputError("delta must be finite")
    if delta < 0:
        raise InputError(f"delta must be non-negative, got {delta}")
    if delta >= 0.5:
        raise InputError(f"delta must be below 0.5 (half a bond length), got {delta}")
    return delta


def _periodic_grid_bonds(n: int, neighbours: list[tuple[int, int]]):
    """Bonds of an n x n periodic grid: each node (a, b) to (a + da, b + db), wrapped."""
    grid_a, grid_b = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    a, b = grid_a.ravel(), grid_b.ravel()
    bonds, shifts = [], []
    for da, db in neighbours:
        a2, b2 = a + da, b + db
        bonds.append(np.c_[a * n + b, (a2 % n) * n + (b2 % n)])
        shifts.append(np.c_[a2 // n, b2 // n])
    return a, b, np.concatenate(bonds), np.concatenate(shifts)


def triangular_lattice(
    n: int, delta: float = DEFAULT_DELTA, rng: np.random.Generator | None = None
) -> PeriodicNetwork:
    """The paper's periodic triangular lattice with n x n nodes and 3 n^2 empty bond sites.

    Node ``(a, b)`` (index ``a * n + b``) sits at ``a b1 + b b2`` plus an independent uniform
    kick in ``[-delta, delta]`` on each coordinate. Bond sites join every node to its ``+b1``,
    ``+b2`` and ``+(b1 + b2)`` neighbours, in that order (sites ``0..n^2-1``, ``n^2..2n^2-1``,
    ``2n^2..3n^2-1``), wrapped periodically.

    Parameters
    ----------
    n : int
        Linear size, at least 2.
    delta : float
        Disorder amplitude, ``0 <= delta < 0.5``. From ``delta = (3 - sqrt 3) / 4 = 0.317``
        kicks can turn a triangle inside out (its bonds cross); a
        :class:`CrossingBondsWarning` says when they did.
    rng : numpy.random.Generator, optional
        Source of the kicks; required when ``delta > 0``.

    Returns
    -------
    PeriodicNetwork
        ``n^2`` nodes, ``3 n^2`` empty sites.
    """
    n = _check_size(n)
    delta = _check_delta(delta)
    a, b, bonds, shifts = _periodic_grid_bonds(n, [(1, 0), (0, 1), (1, 1)])
    positions = np.outer(a, B1) + np.outer(b, B2)
    if delta > 0:
        if rng is None:
            raise InputError("a random generator (rng) is needed when delta > 0")
        positions = positions + rng.uniform(-delta, delta, size=positions.shape)
    box = np.array([n * B1, n * B2])
    kinds = np.full(len(bonds), Element.EMPTY, dtype=np.int64)
    net = PeriodicNetwork(box, positions, bonds, shifts, kinds)
    if delta >= CROSSING_DELTA["triangular"]:
        _warn_if_crossing(net, delta, "triangular")
    return net


def square_lattice(
    n: int,
    delta: float = DEFAULT_DELTA,
    rng: np.random.Generator | None = None,
    diagonals: bool = False,
) -> PeriodicNetwork:
    """Periodic square lattice, n x n nodes, 2 n^2 sites (3 n^2 with one diagonal per square).

    The lattice of the predecessor study (Stephenson et al.). Node ``(a, b)`` (index
    ``a * n + b``) sits at ``(a, b)`` plus a uniform kick in ``[-delta, delta]`` per
    coordinate; sites join every node to its ``+x``, ``+y`` (and ``+x+y`` with diagonals)
    neighbours, in that order, wrapped periodically in the box ``n I``.

    Parameters
    ----------
    n : int
        Linear size, at least 2.
    delta : float
        Disorder amplitude, ``0 <= delta < 0.5``. With diagonals, kicks from
        ``delta = 1/4`` can turn a triangle inside out (a :class:`CrossingBondsWarning` says
        when they did); without them bonds cannot cross.
    rng : numpy.random.Generator, optional
        Source of the kicks; required when ``delta > 0``.
    diagonals : bool
        Add one diagonal per square (then 3 n^2 sites, as on the triangular lattice).

    Returns
    -------
    PeriodicNetwork
        ``n^2`` nodes, ``2 n^2`` (or ``3 n^2``) empty sites.
    """
    n = _check_size(n)
    delta = _check_delta(delta)
    neighbours = [(1, 0), (0, 1)] + ([(1, 1)] if diagonals else [])
    a, b, bonds, shifts = _periodic_grid_bonds(n, neighbours)
    positions = np.c_[a, b].astype(float)
    if delta > 0:
        if rng is None:
            raise InputError("a random generator (rng) is needed when delta > 0")
        positions = positions + rng.uniform(-delta, delta, size=positions.shape)
    box = n * np.eye(2)
    kinds = np.full(len(bonds), Element.EMPTY, dtype=np.int64)
    net = PeriodicNetwork(box, positions, bonds, shifts, kinds)
    if diagonals and delta >= CROSSING_DELTA["square+diagonals"]:
        _warn_if_crossing(net, delta, "square+diagonals")
    return net


def random_periodic_network(
    n_nodes: int,
    n_bonds: int,
    rng: np.random.Generator,
    box: np.ndarray | None = None,
    max_shift: int = 1,
) -> PeriodicNetwork:
    """A random periodic network: uniform nodes in a (possibly skewed) box, random bond sites.

    Bond sites join random node pairs to random images with shifts in ``[-max_shift, max_shift]``;
    a site joining a node to itself needs a non-zero shift. Useful as a test bed far from
    lattice symmetry.

    Parameters
    ----------
    n_nodes, n_bonds : int
        Number of nodes N (at least 1) and of bond sites m.
    rng : numpy.random.Generator
        Source of the positions, bonds and shifts (and of the box when omitted).
    box : (2, 2) float, optional
        Lattice vectors as rows; a random skewed box of area about ``n_nodes`` when omitted.
    max_shift : int
        Largest image shift in each direction.

    Returns
    -------
    PeriodicNetwork
        ``n_nodes`` nodes, ``n_bonds`` empty sites.
    """
    if n_nodes < 1 or n_bonds < 0:
        raise InputError("n_nodes must be >= 1 and n_bonds >= 0")
    if box is None:
        box = np.array([[1.0, 0.0], [rng.uniform(-0.6, 0.6), rng.uniform(0.6, 1.4)]])
        box = box * np.sqrt(n_nodes)
    frac = rng.random((n_nodes, 2))
    positions = frac @ np.asarray(box, dtype=float)
    bonds = rng.integers(0, n_nodes, size=(n_bonds, 2))
    shifts = rng.integers(-max_shift, max_shift + 1, size=(n_bonds, 2))
    same = (bonds[:, 0] == bonds[:, 1]) & np.all(shifts == 0, axis=1)
    shifts[same, 0] = 1
    kinds = np.full(n_bonds, Element.EMPTY, dtype=np.int64)
    return PeriodicNetwork(box, positions, bonds, shifts, kinds)
