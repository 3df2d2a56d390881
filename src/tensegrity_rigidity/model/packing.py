"""Packings of disks and spheres as networks of struts, and the crystal packings of the literature.

A periodic packing is positions ``(N, d)``, radii ``(N,)`` and a box ``(d, d)`` whose rows are the
lattice vectors. Two particles touch when their gap ``|d_ij| - (a_i + a_j)`` is at most
``tolerance`` times the mean diameter, where ``d_ij = r_j + s @ box - r_i`` for some integer
image shift ``s``. A contact pushes and never pulls: :func:`contact_network` returns every contact
as a bond of kind :attr:`~.network.Element.STRUT`, each periodic image of a pair as a bond of its
own (the one-cell boxes of the honeycomb and kagome packings have several per pair, and a particle
may touch its own images).

Contacts are found by SciPy's ``cKDTree``: with ``boxsize`` in an orthogonal box at least twice as
wide as the largest contact distance (each pair touches through one image at most), otherwise on
the images of the particles for every shift within reach of the cutoff (fractional coordinates
bound the shifts: a triclinic box, or a box of a few cells), in the box's Gauss-reduced lattice
vectors (a strongly tilted box spans the lattice of a nearly orthogonal one).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from ..errors import InputError
from .limits import check_memory
from .network import Element, PeriodicNetwork, _as_float_array, check_real, show

__all__ = [
    "CRYSTALS",
    "DEFAULT_CONTACT_TOLERANCE",
    "Packing",
    "contact_network",
    "crystal_packing",
    "packing_fraction",
]

#: Default contact tolerance, in units of the mean diameter: gaps up to it count as contacts. Far
#: above the round-off of a crystal's exact contacts (about 1e-16) and far below any real gap.
DEFAULT_CONTACT_TOLERANCE = 1e-9
#: The largest contact tolerance, in mean diameters: a gap of a whole diameter is no contact, and
#: a larger cutoff only multiplies the images searched.
MAX_CONTACT_TOLERANCE = 1.0
#: Two particles closer than this (in mean diameters) sit at the same place: no contact direction.
SAME_PLACE = 1e-12
#: A particle wider than the shortest lattice vector by more than this fraction overlaps its own
#: image (exactly as wide touches it: the one-cell crystal boxes; the slack absorbs round-off).
OWN_IMAGE_SLACK = 1e-9
#: Bytes per particle image of the general contact search (coordinates and the tree over them).
IMAGE_BYTES = 96
#: Bytes per particle of :func:`crystal_packing` (grid, fractional and Cartesian coordinates,
#: radius, with room for temporaries), for its memory guard.
CRYSTAL_BYTES_PER_PARTICLE = 200


@dataclass(frozen=True, eq=False)
class Packing:
    """Disks (d = 2) or spheres (d = 3) in a periodic box.

    Parameters
    ----------
    positions : (N, d) float
        Particle centres.
    radii : (N,) float
        Positive radii.
    box : (d, d) float
        Lattice vectors of the box, as rows.
    """

    positions: np.ndarray
    radii: np.ndarray
    box: np.ndarray

    def __post_init__(self) -> None:
        pos, radii, box = _check_packing(self.positions, self.radii, self.box)
        for name, arr in (("positions", pos), ("radii", radii), ("box", box)):
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)

    @property
    def dim(self) -> int:
        """Dimension d (2 or 3)."""
        return int(self.box.shape[0])

    @property
    def n_particles(self) -> int:
        """Number of particles N."""
        return int(self.radii.size)

    def packing_fraction(self) -> float:
        """Volume of the particles over the volume of the box (overlaps counted twice).

        Returns
        -------
        float
            ``sum_i v(a_i) / |det box|`` with ``v(a) = pi a^2`` (2D) or ``4 pi a^3 / 3`` (3D).
        """
        return packing_fraction(self.radii, self.box)

    def contact_network(self, tolerance: float = DEFAULT_CONTACT_TOLERANCE) -> PeriodicNetwork:
        """The contacts as a network of struts (:func:`contact_network`).

        Parameters
        ----------
        tolerance : float
            Largest gap of a contact, in units of the mean diameter.

        Returns
        -------
        PeriodicNetwork
            One strut per contact (and per periodic image of a pair).
        """
        return contact_network(self.positions, self.radii, self.box, tolerance=tolerance)


def packing_fraction(radii, box) -> float:
    """Packing fraction of particles with ``radii`` in a box.

    Parameters
    ----------
    radii : (N,) float
        Radii.
    box : (d, d) float
        Lattice vectors as rows.

    Returns
    -------
    float
        ``sum_i v(a_i) / |det box|``, ``v(a) = pi a^2`` in 2D and ``4 pi a^3 / 3`` in 3D.
    """
    radii = np.asarray(radii, dtype=float)
    box = np.asarray(box, dtype=float)
    dim = box.shape[0]
    unit = float(np.abs(box).max())  # in units of the box, so that no power over- or underflows
    a = radii / unit
    volume = np.pi * a**2 if dim == 2 else 4.0 * np.pi * a**3 / 3.0
    return float(volume.sum() / abs(np.linalg.det(box / unit)))


def _check_packing(positions, radii, box):
    box = _as_float_array("box", box, (None, None))
    dim = box.shape[0]
    if box.shape != (dim, dim) or dim not in (2, 3):
        raise InputError(f"box must have shape (2, 2) or (3, 3), got {box.shape}")
    largest = float(np.abs(box).max())
    if not (largest > 0 and abs(np.linalg.det(box / largest)) > 1e-12):  # any scale
        raise InputError("box must have linearly independent rows (non-zero volume)")
    positions = _as_float_array("positions", positions, (None, dim))
    if positions.shape[0] == 0:
        raise InputError("positions must hold at least one particle")
    radii = _as_float_array("radii", radii, (positions.shape[0],))
    if np.any(radii <= 0):
        raise InputError(f"radii must be positive, got {float(radii.min())!r}")
    return positions, radii, box


def contact_network(
    positions, radii, box, tolerance: float = DEFAULT_CONTACT_TOLERANCE
) -> PeriodicNetwork:
    """The contact network of a periodic packing: every contact a strut.

    Parameters
    ----------
    positions : (N, d) float
        Particle centres (any periodic image; they are kept as given).
    radii : (N,) float
        Positive radii.
    box : (d, d) float
        Lattice vectors of the periodic box, as rows (orthogonal or triclinic).
    tolerance : float
        Largest gap of a contact, in units of the mean diameter (``>= 0``; 0 keeps touching and
        overlapping pairs only, as for the overlaps of a soft packing).

    Returns
    -------
    PeriodicNetwork
        The particles as nodes; one bond ``(i, j)`` with image shift ``s`` (``d_ij = r_j + s @ box
        - r_i``) per contact, ``i < j``, or ``i == j`` with ``s`` lexicographically positive for a
        particle touching its own image; all of kind ``Element.STRUT``. Bonds are sorted by
        ``(i, j, s)``.

    Raises
    ------
    InputError
        On bad shapes or values, a negative tolerance, or two particles at the same place.

    Examples
    --------
    >>> from tensegrity_rigidity import contact_network, crystal_packing
    >>> p = crystal_packing("honeycomb", 1)
    >>> net = contact_network(p.positions, p.radii, p.box)
    >>> net.n_nodes, net.n_sites  # two particles touching through three images
    (2, 3)
    """
    positions, radii, box = _check_packing(positions, radii, box)
    tolerance = check_real("tolerance", tolerance)
    if not 0 <= tolerance <= MAX_CONTACT_TOLERANCE:
        raise InputError(
            f"tolerance must be between 0 and {MAX_CONTACT_TOLERANCE:g} mean diameters, "
            f"got {show(tolerance)}"
        )
    given_positions, given_box = positions, box
    # in units of the mean diameter: no squared length over- or underflows at any scale
    unit = 2.0 * float(radii.mean())
    positions, radii, box = positions / unit, radii / unit, box / unit
    if not (np.all(np.isfinite(positions)) and np.all(radii > 0) and np.all(np.isfinite(box))):
        raise InputError(
            "the packing's lengths span more than double precision: positions and box in units "
            "of the mean diameter must be finite and every radius positive"
        )
    slack = tolerance * 2.0 * float(radii.mean())
    cutoff = 2.0 * float(radii.max()) + slack
    reduced, basis = reduce_box(box)
    shortest = float(np.linalg.norm(reduced, axis=1).min())
    if 2.0 * float(radii.max()) > shortest * (1.0 + OWN_IMAGE_SLACK):
        raise InputError(
            f"particle {int(np.argmax(radii))} is wider than the box (diameter "
            f"{2.0 * float(radii.max()) * unit:.6g} > shortest lattice vector "
            f"{shortest * unit:.6g}): it overlaps its own periodic image"
        )
    widths = 1.0 / np.linalg.norm(np.linalg.inv(reduced), axis=0)  # between lattice planes
    orthogonal = np.array_equal(box, np.diag(np.diag(box))) and bool(np.all(np.diag(box) > 0))
    if orthogonal and bool(np.all(widths > 2.0 * cutoff)):
        i, j, s = _pairs_orthogonal(positions, np.diag(box), cutoff)
    else:
        i, j, s = _pairs_general(positions, reduced, widths, cutoff)
        s = s @ basis  # back to the given box's lattice vectors
        s = np.where(((i == j) & (_first_nonzero(s) < 0))[:, None], -s, s)  # lexicographically > 0
    d = positions[j] + s @ box - positions[i]
    dist = np.sqrt(np.einsum("bi,bi->b", d, d))
    keep = dist - (radii[i] + radii[j]) <= slack
    i, j, s, dist = i[keep], j[keep], s[keep], dist[keep]
    if np.any(dist <= SAME_PLACE):
        b = int(np.argmin(dist))
        raise InputError(f"particles {i[b]} and {j[b]} sit at the same place")
    order = np.lexsort((*s.T[::-1], j, i))
    bonds = np.c_[i, j][order]
    kinds = np.full(len(bonds), Element.STRUT, dtype=np.int64)
    return PeriodicNetwork(given_box, given_positions, bonds, s[order], kinds)


def _canonical(i, j, s):
    """Keep each contact once: ``i < j``, or ``i == j`` with ``s`` lexicographically positive."""
    keep = (i < j) | ((i == j) & (_first_nonzero(s) > 0))
    return i[keep], j[keep], s[keep]


def _first_nonzero(s):
    """The first non-zero component of each row of ``s`` (0 for a zero row)."""
    first = np.zeros(len(s), dtype=np.int64)
    for a in range(s.shape[1] - 1, -1, -1):  # read backwards: the first one written last
        first = np.where(s[:, a] != 0, s[:, a], first)
    return first


def _pairs_orthogonal(positions, lengths, cutoff):
    """Candidate pairs by ``cKDTree(boxsize=L)``: each pair through its nearest image only."""
    frac = positions / lengths
    wrap = np.floor(frac)
    inside = (frac - wrap) * lengths
    inside = np.where(inside >= lengths, 0.0, inside)  # a rounding up to L itself
    pairs = cKDTree(inside, boxsize=lengths).query_pairs(cutoff, output_type="ndarray")
    i, j = pairs[:, 0].astype(np.int64), pairs[:, 1].astype(np.int64)
    # nearest image of j seen from i among the wrapped positions, then back to the given ones
    s_wrapped = -np.round((inside[j] - inside[i]) / lengths).astype(np.int64)
    s = s_wrapped - wrap[j].astype(np.int64) + wrap[i].astype(np.int64)
    return _canonical(i, j, s)


def reduce_box(box: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Short lattice vectors of the same lattice (pairwise Gauss reduction).

    A strongly tilted box (a HOOMD tilt of 200, say) spans the same lattice as a nearly
    orthogonal one; searched as given, its images within reach of a contact run to billions.

    Parameters
    ----------
    box : (d, d) float
        Lattice vectors as rows.

    Returns
    -------
    reduced : (d, d) float
        ``basis @ box``: no row shortened further by adding a whole multiple of another.
    basis : (d, d) int64
        The unimodular integer change of basis (a shift ``s`` in the reduced box is ``s @ basis``
        in the given one).
    """
    reduced = np.array(box, dtype=float)
    dim = reduced.shape[0]
    basis = np.eye(dim, dtype=np.int64)
    changed = True
    while changed:  # each step strictly shortens a row, so this ends
        changed = False
        for a, b in itertools.permutations(range(dim), 2):
            k = round(float(reduced[a] @ reduced[b]) / float(reduced[b] @ reduced[b]))
            if k != 0:
                reduced[a] -= k * reduced[b]
                basis[a] -= k * basis[b]
                changed = True
    return reduced, basis


def _pairs_general(positions, box, widths, cutoff):
    """Candidate pairs by a tree over the images of every particle for each shift in reach."""
    frac = positions @ np.linalg.inv(box)
    wrap = np.floor(frac)
    inside = (frac - wrap) @ box
    reach = np.floor(1.0 + cutoff / widths).astype(np.int64)
    images = math.prod(int(2 * k + 1) for k in reach) * len(positions)
    check_memory(IMAGE_BYTES * float(images), f"a contact search over {images:,} particle images")
    shifts = np.array(list(itertools.product(*[range(-k, k + 1) for k in reach])), dtype=np.int64)
    n = len(positions)
    images = (inside[None, :, :] + (shifts @ box)[:, None, :]).reshape(-1, box.shape[0])
    found = cKDTree(inside).sparse_distance_matrix(cKDTree(images), cutoff, output_type="ndarray")
    i = found["i"].astype(np.int64)
    image = found["j"].astype(np.int64)
    j, s_wrapped = image % n, shifts[image // n]
    s = s_wrapped - wrap[j].astype(np.int64) + wrap[i].astype(np.int64)
    return _canonical(i, j, s)


#: Crystal packings of unit diameter (nearest neighbours touch): cell vectors (rows), basis in
#: fractional coordinates of the cell, and the number of contacts per particle.
CRYSTALS: dict[str, tuple[np.ndarray, np.ndarray, int]] = {
    "triangular": (np.array([[1.0, 0.0], [0.5, np.sqrt(3) / 2]]), np.zeros((1, 2)), 6),
    "square": (np.eye(2), np.zeros((1, 2)), 4),
    "honeycomb": (
        np.array([[np.sqrt(3), 0.0], [np.sqrt(3) / 2, 1.5]]),
        np.array([[0.0, 0.0], [1 / 3, 1 / 3]]),
        3,
    ),
    "kagome": (
        np.array([[2.0, 0.0], [1.0, np.sqrt(3)]]),
        np.array([[0.0, 0.0], [0.5, 0.0], [0.0, 0.5]]),
        4,
    ),
    "sc": (np.eye(3), np.zeros((1, 3)), 6),
    "bcc": (np.eye(3) * 2 / np.sqrt(3), np.array([[0, 0, 0], [0.5, 0.5, 0.5]]), 8),
    "fcc": (
        np.eye(3) * np.sqrt(2),
        np.array([[0, 0, 0], [0, 0.5, 0.5], [0.5, 0, 0.5], [0.5, 0.5, 0]]),
        12,
    ),
    "hcp": (
        np.array([[1.0, 0.0, 0.0], [0.5, np.sqrt(3) / 2, 0.0], [0.0, 0.0, np.sqrt(8 / 3)]]),
        np.array([[0.0, 0.0, 0.0], [1 / 3, 1 / 3, 0.5]]),
        12,
    ),
    "diamond": (
        np.eye(3) * 4 / np.sqrt(3),
        np.array(
            [[0, 0, 0], [0, 0.5, 0.5], [0.5, 0, 0.5], [0.5, 0.5, 0]]
            + [[0.25, 0.25, 0.25], [0.25, 0.75, 0.75], [0.75, 0.25, 0.75], [0.75, 0.75, 0.25]]
        ),
        4,
    ),
}


def crystal_packing(name: str, cells) -> Packing:
    """A crystal packing of unit diameter in a periodic box of ``cells`` unit cells.

    Parameters
    ----------
    name : str
        "triangular", "square", "honeycomb", "kagome" (2D) or "sc", "bcc", "fcc", "hcp",
        "diamond" (3D); nearest neighbours touch (:data:`CRYSTALS`: cell vectors and basis).
        The cubic crystals use their conventional cubic cell (1, 2, 4 and 8 particles), the others
        their primitive one (hcp's is hexagonal, so its box is triclinic).
    cells : int or sequence of int
        Unit cells along each cell vector (one int: the same along every one).

    Returns
    -------
    Packing
        ``prod(cells) x basis`` particles of radius 1/2, the box rows ``cells[a] x cell vector a``.

    Examples
    --------
    >>> from tensegrity_rigidity import crystal_packing
    >>> p = crystal_packing("kagome", 2)
    >>> p.n_particles, round(p.packing_fraction(), 4)
    (12, 0.6802)
    """
    if name not in CRYSTALS:
        raise InputError(f"unknown crystal {name!r}; choose from {', '.join(CRYSTALS)}")
    vectors, basis, _ = CRYSTALS[name]
    dim = vectors.shape[0]
    counts = np.asarray(cells)
    if counts.ndim > 1 or counts.size not in (1, dim):
        raise InputError(f"cells must be one int or {dim} ints for {name!r}, got {show(cells)}")
    counts = np.broadcast_to(counts.reshape(-1), (dim,))
    if counts.dtype.kind not in "iu" or np.any(counts < 1):
        raise InputError(f"cells must be positive integers, got {show(cells)}")
    particles = math.prod(int(c) for c in counts) * len(basis)
    check_memory(
        CRYSTAL_BYTES_PER_PARTICLE * float(particles),
        f"a packing of {particles:,} {name} particles",
    )
    grid = np.indices(tuple(int(c) for c in counts)).reshape(dim, -1).T.astype(float)
    frac = (grid[:, None, :] + basis[None, :, :]).reshape(-1, dim)
    positions = frac @ vectors
    box = counts[:, None] * vectors
    return Packing(positions, np.full(len(positions), 0.5), box)
