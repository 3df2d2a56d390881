"""Builders of periodic networks: the paper's triangular lattice, a square lattice, the kagome and
honeycomb lattices of topological mechanics, the FCC lattice in 3D, random networks.

Every builder takes an explicit ``numpy.random.Generator``; nothing here touches global random
state. Builders return networks with all bond sites *empty*; elements are placed afterwards by
:func:`tensegrity_rigidity.model.elements.place_elements`.
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from ..errors import InputError
from .limits import check_memory, stage_bytes
from .network import (
    MAX_SHIFT,
    Element,
    PeriodicNetwork,
    check_count,
    check_generator,
    check_real,
    show,
)

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
#: On the FCC lattice the same argument for its regular tetrahedra (edge 1) gives
#: 1 / (3 sqrt 2) = 0.2357: a node kicked through the opposite face of one of its tetrahedra.
CROSSING_DELTA = {
    "triangular": (3.0 - np.sqrt(3.0)) / 4.0,
    "square": 0.5,
    "square+diagonals": 0.25,
    "fcc": 1.0 / (3.0 * np.sqrt(2.0)),
}


class CrossingBondsWarning(UserWarning):
    """The node disorder turned some triangles of a lattice inside out: bonds cross."""


B1 = np.array([1.0, 0.0])
B2 = np.array([-0.5, np.sqrt(3.0) / 2.0])

#: bytes per node or bond of a random network (positions, bonds, shifts, kinds and the
#: generator's draws: at most 9 numbers of 8 bytes per item, with room for temporaries)
RANDOM_NETWORK_BYTES_PER_ITEM = 200

#: Primitive vectors of the FCC lattice with nearest-neighbour distance 1 (rows).
FCC_VECTORS = np.array([[0.0, 1.0, 1.0], [1.0, 0.0, 1.0], [1.0, 1.0, 0.0]]) / np.sqrt(2.0)
#: The six bond steps per FCC node, in primitive coordinates: a1, a2, a3, a1 - a2, a1 - a3,
#: a2 - a3 (with their opposites, the 12 nearest neighbours).
FCC_STEPS = ((1, 0, 0), (0, 1, 0), (0, 0, 1), (1, -1, 0), (1, 0, -1), (0, 1, -1))


def _check_size(n: int, lattice: str, dim: int = 2, basis: int = 1) -> int:
    """``n`` as an int, refused in one line unless an integer >= 2 whose lattice of ``n^dim``
    cells of ``basis`` nodes fits in memory (an unmeasured ``lattice`` is priced as the costliest
    measured one of its dimension)."""
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)):
        raise InputError(f"n must be an integer, got {show(n)}")
    if n < 2:
        raise InputError(f"n must be at least 2, got {n}")
    nodes = basis * float(n) ** dim if n < 2**63 else math.inf
    check_memory(
        stage_bytes("build", nodes, lattice, dim),
        f"a lattice of n = {show(n)} ({show(n)}^{dim} nodes)",
    )
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
    delta = check_real("delta", delta)
    if delta < 0:
        raise InputError(f"delta must be non-negative, got {delta}")
    if delta >= 0.5:
        raise InputError(f"delta must be below 0.5 (half a bond length), got {delta}")
    return delta


def _periodic_grid_bonds(n: int, neighbours):
    """Bonds of an n x n periodic grid: each node (a, b) to (a + da, b + db), wrapped."""
    coords, bonds, shifts = _grid_bonds(n, neighbours)
    return coords[:, 0], coords[:, 1], bonds, shifts


def _grid_bonds(n: int, steps) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Bonds of a periodic grid of ``n^d`` nodes, ``d = len(steps[0])``: node ``c`` (index
    ``c_0 n^(d-1) + ... + c_(d-1)``) to ``c + step`` wrapped, step after step.

    Returns
    -------
    coords : (n^d, d) int
        Grid coordinates of the nodes.
    bonds : (len(steps) n^d, 2) int
        Node pairs.
    shifts : (len(steps) n^d, d) int
        Image shifts of the second node.
    """
    d = len(steps[0])
    grids = np.meshgrid(*[np.arange(n)] * d, indexing="ij")
    coords = np.stack([g.ravel() for g in grids], axis=1)
    weights = n ** np.arange(d - 1, -1, -1)
    index = coords @ weights
    bonds, shifts = [], []
    for step in steps:
        moved = coords + np.asarray(step)
        bonds.append(np.c_[index, (moved % n) @ weights])
        shifts.append(moved // n)
    return coords, np.concatenate(bonds), np.concatenate(shifts)


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
    n = _check_size(n, "triangular")
    delta = _check_delta(delta)
    rng = None if rng is None else check_generator(rng)
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
    n = _check_size(n, "square")
    delta = _check_delta(delta)
    rng = None if rng is None else check_generator(rng)
    if not isinstance(diagonals, (bool, np.bool_)):
        raise InputError(f"diagonals must be True or False, got {show(diagonals)}")
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


#: Kagome lattice with nearest-neighbour distance 1: cell vectors (rows), the three nodes of a cell
#: (fractional coordinates) and its six bonds ``(node a, node b, cell step of b)``.
KAGOME_CELL = (
    np.array([[2.0, 0.0], [1.0, np.sqrt(3.0)]]),
    np.array([[0.0, 0.0], [0.5, 0.0], [0.0, 0.5]]),
    (
        (0, 1, (0, 0)),
        (0, 2, (0, 0)),
        (1, 2, (0, 0)),
        (1, 0, (1, 0)),
        (2, 0, (0, 1)),
        (1, 2, (1, -1)),
    ),
)
#: Honeycomb lattice with nearest-neighbour distance 1: cell vectors, two nodes, three bonds.
HONEYCOMB_CELL = (
    np.array([[np.sqrt(3.0), 0.0], [np.sqrt(3.0) / 2.0, 1.5]]),
    np.array([[0.0, 0.0], [1.0 / 3.0, 1.0 / 3.0]]),
    ((0, 1, (0, 0)), (1, 0, (1, 0)), (1, 0, (0, 1))),
)


def _decorated_lattice(n: int, cell, delta: float, rng, name: str) -> PeriodicNetwork:
    """n x n cells of the lattice ``name`` with a basis: node ``(c, a)`` (index ``c nb + a`` for
    cell ``c = i n + j`` and basis node ``a`` of ``nb``), the bonds of the cell's table in turn,
    each over every cell."""
    vectors, basis, table = cell
    n = _check_size(n, name, basis=len(basis))
    delta = _check_delta(delta)
    rng = None if rng is None else check_generator(rng)
    nb = len(basis)
    coords, _, _ = _grid_bonds(n, [(0, 0)])
    cell_index = coords @ np.array([n, 1])
    positions = ((coords[:, None, :] + basis[None, :, :]) @ vectors).reshape(-1, 2)
    bonds, shifts = [], []
    for a, b, step in table:
        moved = coords + np.asarray(step)
        bonds.append(np.c_[cell_index * nb + a, ((moved % n) @ np.array([n, 1])) * nb + b])
        shifts.append(moved // n)
    if delta > 0:
        if rng is None:
            raise InputError("a random generator (rng) is needed when delta > 0")
        positions = positions + rng.uniform(-delta, delta, size=positions.shape)
    bonds_all = np.concatenate(bonds)
    kinds = np.full(len(bonds_all), Element.EMPTY, dtype=np.int64)
    return PeriodicNetwork(n * vectors, positions, bonds_all, np.concatenate(shifts), kinds)


def kagome_lattice(
    n: int, delta: float = 0.0, rng: np.random.Generator | None = None
) -> PeriodicNetwork:
    """The periodic kagome lattice: n x n cells of three nodes, 6 n^2 empty bond sites.

    Corner-sharing triangles with nearest-neighbour distance 1 (:data:`KAGOME_CELL`: cell vectors
    ``(2, 0)``, ``(1, sqrt 3)``), every node with four neighbours: Maxwell's count is exactly
    balanced (``z = 2d``), the lattice of topological mechanics. Node ``a`` of cell ``(i, j)`` has
    index ``(i n + j) 3 + a``; site ``k n^2 + c`` is bond ``k`` of the cell table in cell ``c``.

    Parameters
    ----------
    n : int
        Cells along each cell vector, at least 2.
    delta : float
        Uniform kick in ``[-delta, delta]`` per coordinate, ``0 <= delta < 0.5`` (default 0, the
        perfect lattice; no check for crossing bonds).
    rng : numpy.random.Generator, optional
        Source of the kicks; required when ``delta > 0``.

    Returns
    -------
    PeriodicNetwork
        ``3 n^2`` nodes, ``6 n^2`` empty sites, box rows ``n (2, 0)`` and ``n (1, sqrt 3)``.
    """
    return _decorated_lattice(n, KAGOME_CELL, delta, rng, "kagome")


def honeycomb_lattice(
    n: int, delta: float = 0.0, rng: np.random.Generator | None = None
) -> PeriodicNetwork:
    """The periodic honeycomb lattice: n x n cells of two nodes, 3 n^2 empty bond sites.

    Nearest-neighbour distance 1 (:data:`HONEYCOMB_CELL`: cell vectors ``(sqrt 3, 0)``,
    ``(sqrt 3 / 2, 3 / 2)``), three neighbours per node. Node ``a`` of cell ``(i, j)`` has index
    ``(i n + j) 2 + a``; site ``k n^2 + c`` is bond ``k`` of the cell table in cell ``c``.

    Parameters
    ----------
    n : int
        Cells along each cell vector, at least 2.
    delta : float
        Uniform kick in ``[-delta, delta]`` per coordinate, ``0 <= delta < 0.5`` (default 0).
    rng : numpy.random.Generator, optional
        Source of the kicks; required when ``delta > 0``.

    Returns
    -------
    PeriodicNetwork
        ``2 n^2`` nodes, ``3 n^2`` empty sites.
    """
    return _decorated_lattice(n, HONEYCOMB_CELL, delta, rng, "honeycomb")


def fcc_lattice(
    n: int, delta: float = DEFAULT_DELTA, rng: np.random.Generator | None = None
) -> PeriodicNetwork:
    """The periodic FCC lattice on its primitive cell: n^3 nodes, 6 n^3 empty bond sites.

    Node ``(i, j, k)`` (index ``(i n + j) n + k``) sits at ``i a1 + j a2 + k a3``
    (:data:`FCC_VECTORS`, nearest-neighbour distance 1) plus an independent uniform kick in
    ``[-delta, delta]`` on each coordinate. Bond sites join every node to its neighbours along
    :data:`FCC_STEPS` (``a1, a2, a3, a1 - a2, a1 - a3, a2 - a3``; sites ``s n^3`` to
    ``(s + 1) n^3 - 1`` for step ``s``), 12 neighbours per node, in the box of rows
    ``n a1, n a2, n a3``.

    Parameters
    ----------
    n : int
        Linear size, at least 2.
    delta : float
        Disorder amplitude, ``0 <= delta < 0.5``. From ``delta = 1 / (3 sqrt 2) = 0.2357``
        kicks can turn a tetrahedron inside out; a :class:`CrossingBondsWarning` says when
        they did.
    rng : numpy.random.Generator, optional
        Source of the kicks; required when ``delta > 0``.

    Returns
    -------
    PeriodicNetwork
        ``n^3`` nodes, ``6 n^3`` empty sites, ``dim == 3``.

    Examples
    --------
    >>> from tensegrity_rigidity.model.lattice import fcc_lattice
    >>> net = fcc_lattice(3, delta=0.0)
    >>> net.n_nodes, net.n_sites, net.dim
    (27, 162, 3)
    """
    n = _check_size(n, "fcc", dim=3)
    delta = _check_delta(delta)
    rng = None if rng is None else check_generator(rng)
    coords, bonds, shifts = _grid_bonds(n, FCC_STEPS)
    positions = coords @ FCC_VECTORS
    if delta > 0:
        if rng is None:
            raise InputError("a random generator (rng) is needed when delta > 0")
        positions = positions + rng.uniform(-delta, delta, size=positions.shape)
    kinds = np.full(len(bonds), Element.EMPTY, dtype=np.int64)
    net = PeriodicNetwork(n * FCC_VECTORS, positions, bonds, shifts, kinds)
    if delta >= CROSSING_DELTA["fcc"]:
        bad = inverted_tetrahedra(net)
        if bad:
            warnings.warn(
                f"delta = {delta} turned {bad} tetrahedra of the fcc lattice inside out "
                f"(possible from delta = {CROSSING_DELTA['fcc']:.4f})",
                CrossingBondsWarning,
                stacklevel=2,
            )
    return net


def inverted_tetrahedra(net: PeriodicNetwork) -> int:
    """Number of inside-out tetrahedra of a network from :func:`fcc_lattice`.

    Every node ``x`` is a corner of the tetrahedra ``(x, x + a1, x + a2, x + a3)`` and
    ``(x, x - a1, x - a2, x - a3)``; their edges from ``x`` are the bond vectors of the
    first three sites of ``x`` and minus those of the nodes ``x - a_s``. Both have positive
    volume in the undisturbed lattice.

    Parameters
    ----------
    net : PeriodicNetwork
        A network with ``6 N`` sites in :func:`fcc_lattice`'s order.

    Returns
    -------
    int
        Tetrahedra whose orientation flipped (0 for another network).
    """
    n_nodes = net.n_nodes
    if net.dim != 3 or net.n_sites != 6 * n_nodes:
        return 0
    # in units of a power of two near the box's size (exact): triple products of bonds of
    # 1e-170 or 1e150 would under- or overflow and read as flat tetrahedra
    _, exponent = np.frexp(float(np.abs(net.box).max()))
    d = np.ldexp(net.bond_vectors(), -int(exponent))
    up = [d[s * n_nodes : (s + 1) * n_nodes] for s in range(3)]
    # the node x - a_s is the first node of site s ending at x
    down = []
    for s in range(3):
        sites = np.arange(s * n_nodes, (s + 1) * n_nodes)
        into = np.empty(n_nodes, dtype=np.int64)
        into[net.bonds[sites, 1]] = sites
        down.append(-d[into])
    v_up = np.einsum("bi,bi->b", up[0], np.cross(up[1], up[2]))
    v_down = np.einsum("bi,bi->b", down[0], np.cross(down[1], down[2]))
    return int(np.count_nonzero(v_up <= 0) + np.count_nonzero(-v_down <= 0))


def random_periodic_network(
    n_nodes: int,
    n_bonds: int,
    rng: np.random.Generator,
    box: np.ndarray | None = None,
    max_shift: int = 1,
    dim: int | None = None,
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
    box : (d, d) float, optional
        Lattice vectors as rows; a random skewed box of area (volume) about ``n_nodes`` when
        omitted.
    max_shift : int
        Largest image shift in each direction (at least 1, at most
        :data:`~.network.MAX_SHIFT`).
    dim : int, optional
        Dimension d, 2 or 3: that of ``box`` when one is given (a box of another dimension
        is refused), else 2.

    Returns
    -------
    PeriodicNetwork
        ``n_nodes`` nodes, ``n_bonds`` empty sites.

    Raises
    ------
    InputError
        On counts that are not integers of the right range, a ``box`` whose dimension is not
        ``dim``, or an ``rng`` that is not a generator.
    """
    n_nodes = check_count("n_nodes", n_nodes, least=1)
    n_bonds = check_count("n_bonds", n_bonds)
    max_shift = check_count("max_shift", max_shift, least=1)
    if max_shift > MAX_SHIFT:
        raise InputError(f"max_shift must be at most {MAX_SHIFT}, got {show(max_shift)}")
    rng = check_generator(rng)
    if dim is not None and not (
        isinstance(dim, (int, np.integer)) and not isinstance(dim, bool) and dim in (2, 3)
    ):
        raise InputError(f"dim must be 2 or 3, got {show(dim)}")
    items = n_nodes + n_bonds
    check_memory(
        RANDOM_NETWORK_BYTES_PER_ITEM * (float(items) if items < 2**63 else math.inf),
        f"a random network of {show(n_nodes)} nodes and {show(n_bonds)} bonds",
    )
    if box is None:
        if dim in (None, 2):
            box = np.array([[1.0, 0.0], [rng.uniform(-0.6, 0.6), rng.uniform(0.6, 1.4)]])
            box = box * np.sqrt(n_nodes)
        else:
            box = np.diag(rng.uniform(0.7, 1.3, 3)) + np.tril(rng.uniform(-0.4, 0.4, (3, 3)), -1)
            box = box * n_nodes ** (1.0 / 3.0)
    box = _as_box(box)
    d = box.shape[0]
    if dim is not None and d != dim:
        raise InputError(f"box has shape {box.shape} but dim = {dim}: give a ({dim}, {dim}) box")
    frac = rng.random((n_nodes, d))
    positions = frac @ box
    bonds = rng.integers(0, n_nodes, size=(n_bonds, 2))
    shifts = rng.integers(-max_shift, max_shift + 1, size=(n_bonds, d))
    same = (bonds[:, 0] == bonds[:, 1]) & np.all(shifts == 0, axis=1)
    shifts[same, 0] = 1
    kinds = np.full(n_bonds, Element.EMPTY, dtype=np.int64)
    return PeriodicNetwork(box, positions, bonds, shifts, kinds)


def _as_box(box) -> np.ndarray:
    """A (2, 2) or (3, 3) array of finite reals (the network checks its volume)."""
    try:
        arr = np.asarray(box, dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"box must be a (2, 2) or (3, 3) array, got {show(box)}") from None
    if arr.shape not in ((2, 2), (3, 3)):
        raise InputError(f"box must have shape (2, 2) or (3, 3), got {arr.shape}")
    return arr
