"""Periodic networks and strained instances as plain, validated data.

A periodic network lives in ``d = 2`` or ``3`` dimensions, in a box whose *rows* are the ``d``
lattice vectors. Node ``i`` sits at ``positions[i]``; bond ``b`` joins node ``bonds[b, 0]`` to
the periodic image of node ``bonds[b, 1]`` shifted by ``shifts[b] @ box``, so its bond vector
is::

    d_b = positions[j] + shifts[b] @ box - positions[i]

Each bond site holds one element kind (:class:`Element`): empty, rod (resists extension and
compression), cable (resists only extension) or strut (resists only compression), and an
optional stiffness (unit by default).

An :class:`Instance` is a network plus a symmetric ``d x d`` strain tensor ``eps`` (magnitude
included). It is exactly what an instance file stores (see :mod:`tensegrity_rigidity.model.io`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields, replace
from enum import IntEnum

import numpy as np

from ..errors import InputError

#: Largest ``max |position|`` in units of the box's linear size. Beyond it the positions keep
#: fewer than ~10 significant digits inside the cell, and the bond vectors computed from them
#: (differences of nearly equal numbers) lose the rest: a translation by 1e12 box lengths
#: changed energies by 6e-4, one by 1e15 flipped verdicts.
MAX_POSITION_REACH = 1e6

#: Largest magnitude of an image shift. The certificates sum a bond vector from its terms in
#: extended precision, exactly only while ``shift x box`` fits a 64-bit mantissa (a double's
#: 53 bits times an integer below 2^11); a bond spanning more periodic images than this is
#: not a network of this box.
MAX_SHIFT = 2**11 - 1

#: The dimensions a network may live in.
DIMENSIONS = (2, 3)

#: Integer arrays are held as int64: larger values are refused, not wrapped.
_INT64_MAX = np.iinfo(np.int64).max


class Element(IntEnum):
    """Element kinds, with the integer codes used in ``kinds`` arrays and instance files.

    Attributes
    ----------
    EMPTY
        0: no element, the site carries no force.
    ROD
        1: resists extension and compression (tension of either sign).
    CABLE
        2: resists only extension (tension ``t >= 0``).
    STRUT
        3: resists only compression (tension ``t <= 0``).
    """

    EMPTY = 0
    ROD = 1
    CABLE = 2
    STRUT = 3


#: Longest value quoted in an error message (longer ones are cut, so that the message stays
#: one short line whatever was passed: an array, a whole table).
_SHOWN_CHARACTERS = 60


def show(value) -> str:
    """``repr(value)`` on one line, cut to a readable length, for an error message.

    Parameters
    ----------
    value : object
        Whatever was passed.

    Returns
    -------
    str
        Its repr with runs of white space as one space, at most about 60 characters.
    """
    text = " ".join(repr(value).split())
    if len(text) > _SHOWN_CHARACTERS:
        text = text[: _SHOWN_CHARACTERS - 3] + "..."
    return text


def short_repr(obj, items: list[tuple[str, object]]) -> str:
    """``Name(field=value, ...)`` with arrays shown by shape and dtype only (a repr of a few
    lines instead of every tension and displacement), floats to 6 digits.

    Parameters
    ----------
    obj : object
        Whose repr (its class name heads it).
    items : list of (str, object)
        The fields shown, in order.

    Returns
    -------
    str
    """

    def brief(value: object) -> str:
        if isinstance(value, np.ndarray):
            return f"<{value.shape} {value.dtype} array>"
        if isinstance(value, (float, np.floating)):
            return f"{float(value):.6g}"
        return repr(value)

    inner = ", ".join(f"{name}={brief(value)}" for name, value in items)
    return f"{type(obj).__name__}({inner})"


def fields_repr(obj) -> str:
    """:func:`short_repr` of every field of a dataclass that is shown (``field(repr=False)`` is
    not): a dataclass's ``__repr__`` of one line whatever its arrays hold.

    Parameters
    ----------
    obj : dataclass instance
        Whose repr.

    Returns
    -------
    str
    """
    return short_repr(obj, [(f.name, getattr(obj, f.name)) for f in fields(obj) if f.repr])


def check_real(name: str, value) -> float:
    """A finite real number: a Python or NumPy scalar, not a bool, a string or an array.

    Parameters
    ----------
    name : str
        The argument's name, for the message.
    value : object
        What was passed.

    Returns
    -------
    float
        The value as a float.

    Raises
    ------
    InputError
        One sentence naming the argument and quoting the value.
    """
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.number)):
        raise InputError(f"{name} must be a number, got {show(value)}")
    if isinstance(value, (complex, np.complexfloating)):
        raise InputError(f"{name} must be a real number, got {show(value)}")
    try:
        out = float(value)
    except OverflowError:
        out = math.inf
    if not math.isfinite(out):
        raise InputError(f"{name} must be finite, got {show(value)}")
    return out


def check_count(name: str, value, least: int = 0) -> int:
    """An integer (Python or NumPy, not a bool or a float) of at least ``least``.

    Parameters
    ----------
    name : str
        The argument's name, for the message.
    value : object
        What was passed.
    least : int
        The smallest value accepted.

    Returns
    -------
    int
        The value.

    Raises
    ------
    InputError
        One sentence naming the argument and quoting the value.
    """
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
        raise InputError(f"{name} must be an integer, got {show(value)}")
    if value < least:
        raise InputError(f"{name} must be at least {least}, got {show(value)}")
    return int(value)


def check_generator(rng) -> np.random.Generator:
    """A NumPy random generator.

    Parameters
    ----------
    rng : object
        What was passed.

    Returns
    -------
    numpy.random.Generator
        ``rng``.

    Raises
    ------
    InputError
        On anything else (a seed: wrap it, ``numpy.random.default_rng(seed)``).
    """
    if not isinstance(rng, np.random.Generator):
        raise InputError(
            f"rng must be a numpy.random.Generator, got {show(rng)} (for a seed s, pass "
            "numpy.random.default_rng(s))"
        )
    return rng


def _as_float_array(name: str, value, shape: tuple[int | None, ...]) -> np.ndarray:
    try:
        raw = np.asarray(value)
    except (TypeError, ValueError) as exc:
        raise InputError(f"{name} must be a numeric array ({exc})") from None
    if raw.dtype.kind == "c":  # a cast would drop the imaginary part silently
        raise InputError(f"{name} must be real, got complex values (dtype {raw.dtype})")
    if raw.dtype.kind == "b":
        raise InputError(f"{name} must be a numeric array, got booleans")
    try:
        arr = np.array(raw, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InputError(f"{name} must be a numeric array ({exc})") from None
    _check_shape(name, arr, shape)
    if not np.all(np.isfinite(arr)):
        raise InputError(f"{name} contains NaN or infinite values")
    return arr


def _as_int_array(name: str, value, shape: tuple[int | None, ...]) -> np.ndarray:
    try:
        raw = np.asarray(value)
    except (TypeError, ValueError) as exc:
        raise InputError(f"{name} must be an integer array ({exc})") from None
    if raw.size and raw.dtype.kind == "f":
        if not np.all(np.isfinite(raw)):
            raise InputError(f"{name} contains NaN or infinite values")
        if not np.all(raw == np.round(raw)):
            raise InputError(f"{name} must hold integers")
        if np.any(np.abs(raw) >= 2.0**63):
            raise InputError(f"{name} holds {raw.flat[np.argmax(np.abs(raw))]:.3g}, beyond int64")
    elif raw.dtype.kind == "b":  # True/False would pass as 1/0: almost surely a mistake
        raise InputError(f"{name} must be an integer array, got booleans")
    elif raw.size and raw.dtype.kind not in "iu":
        raise InputError(f"{name} must be an integer array, got dtype {raw.dtype}")
    elif raw.size and raw.dtype.kind == "u" and int(raw.max()) > _INT64_MAX:
        raise InputError(f"{name} holds {int(raw.max())}, beyond int64")
    arr = raw.astype(np.int64)
    _check_shape(name, arr, shape)
    return arr


def vector_norms(v: np.ndarray) -> np.ndarray:
    """Euclidean norms of the rows of ``v``, without overflow or underflow at any scale.

    Parameters
    ----------
    v : (m, d) float
        Vectors, ``d = 2`` or ``3``.

    Returns
    -------
    (m,) float
        ``hypot`` in 2D; in 3D the square root of the sum of squares, by
        :func:`norms_from_squares`.
    """
    if v.shape[1] == 2:
        return np.hypot(v[:, 0], v[:, 1])
    v = np.asarray(v, dtype=float)
    with np.errstate(over="ignore"):  # such rows are computed again, scaled
        squares = np.einsum("bi,bi->b", v, v)
    return norms_from_squares(v, squares)


def norms_from_squares(v: np.ndarray, squares: np.ndarray) -> np.ndarray:
    """Norms of the rows of ``v`` from their sums of squares, safe where those leave the range.

    Parameters
    ----------
    v : (m, d) float or longdouble
        Vectors.
    squares : (m,) of v's dtype
        ``sum_i v[:, i]^2`` as the caller computes it.

    Returns
    -------
    (m,) of v's dtype
        ``sqrt(squares)`` where the sum lies where no square in it lost a digit to underflow and
        it did not overflow (above the smallest normal number times ``2^(p + 1)``, ``p`` the
        mantissa bits, and below a quarter of the largest); elsewhere the same computed on
        the row divided by a power of two near its largest component. That scaling is exact,
        so the digits are those the plain formula gives at ordinary scales, and a bond of
        ``1e-170`` or ``1e200`` keeps them too.
    """
    info = np.finfo(squares.dtype)
    low = np.ldexp(info.tiny, info.nmant + 1)
    high = info.max / 4
    norms = np.sqrt(squares)
    out_of_range = ~((squares >= low) & (squares <= high))
    if np.any(out_of_range):
        rows = v[out_of_range]
        _, exponent = np.frexp(np.abs(rows).max(axis=1))
        unit = np.ldexp(rows, -exponent[:, None])
        norms[out_of_range] = np.ldexp(np.sqrt((unit * unit).sum(axis=1)), exponent)
    return norms


def _check_shape(name: str, arr: np.ndarray, shape: tuple[int | None, ...]) -> None:
    ok = arr.ndim == len(shape) and all(
        s is None or s == a for s, a in zip(shape, arr.shape, strict=True)
    )
    if not ok:
        want = "(" + ", ".join("*" if s is None else str(s) for s in shape) + ")"
        raise InputError(f"{name} must have shape {want}, got {arr.shape}")


@dataclass(frozen=True, eq=False)
class PeriodicNetwork:
    """A network of bond sites in a periodic box.

    Parameters
    ----------
    box : (d, d) float
        Rows are the lattice vectors of the periodic box (``d = 2`` or ``3``); must have
        positive area (volume).
    positions : (N, d) float
        Node positions.
    bonds : (m, 2) int
        Node indices ``(i, j)`` of each bond site.
    shifts : (m, d) int
        Integer image offsets: the bond joins ``i`` to ``j``'s image at ``shifts[b] @ box``.
    kinds : (m,) int
        :class:`Element` code of each site (0 empty, 1 rod, 2 cable, 3 strut).
    stiffness : (m,) float, optional
        Positive spring constants; ``None`` means unit stiffness everywhere.

    Raises
    ------
    InputError
        On wrong or mixed dimensions, non-finite values, indices out of range, unknown kinds,
        zero-length bonds, non-positive stiffness or a degenerate box.
    """

    box: np.ndarray
    positions: np.ndarray
    bonds: np.ndarray
    shifts: np.ndarray
    kinds: np.ndarray
    stiffness: np.ndarray | None = field(default=None)

    def __post_init__(self) -> None:
        box = _as_float_array("box", self.box, (None, None))
        dim = box.shape[0]
        if box.shape[1] != dim or dim not in DIMENSIONS:
            raise InputError(f"box must have shape (2, 2) or (3, 3), got {box.shape}")
        # relative to the box's own scale (divided out first, so that a box at 1e-300 or
        # 1e300 neither underflows nor overflows): |det| = |b1| |b2| sin(angle between them)
        box_scale = float(np.abs(box).max())
        unit_box = box / box_scale if box_scale > 0 else box
        norms = float(np.prod(vector_norms(unit_box)))
        unit_area = abs(float(np.linalg.det(unit_box)))
        if not unit_area > 1e-12 * norms:
            what = "two independent lattice vectors (zero area)"
            if dim == 3:
                what = "three independent lattice vectors (zero volume)"
            raise InputError(f"box must have {what}")
        positions = _as_float_array("positions", self.positions, (None, dim))
        n_nodes = positions.shape[0]
        if n_nodes == 0:
            raise InputError("positions must hold at least one node")
        bonds = _as_int_array("bonds", self.bonds, (None, 2))
        m = bonds.shape[0]
        shifts = _as_int_array("shifts", self.shifts, (m, dim))
        kinds = _as_int_array("kinds", self.kinds, (m,))
        if m and int(np.abs(shifts).max()) > MAX_SHIFT:
            b = int(np.argmax(np.abs(shifts).max(axis=1)))
            raise InputError(
                f"bond {b} has image shift {shifts[b].tolist()}: shifts must lie within "
                f"+-{MAX_SHIFT} periodic images"
            )
        bad = np.flatnonzero((bonds < 0) | (bonds >= n_nodes))
        if bad.size:
            raise InputError(
                f"bond {bad[0] // 2} has node index {bonds.ravel()[bad[0]]}, "
                f"out of range for {n_nodes} nodes"
            )
        if m and (kinds.min() < 0 or kinds.max() > 3):
            raise InputError("kinds must be 0 (empty), 1 (rod), 2 (cable) or 3 (strut)")
        stiffness = None
        if self.stiffness is not None:
            stiffness = _as_float_array("stiffness", self.stiffness, (m,))
            if np.any(stiffness <= 0):
                raise InputError("stiffness must be positive on every bond site")
        vec = positions[bonds[:, 1]] + shifts @ box - positions[bonds[:, 0]]
        length = vector_norms(vec)
        scale = box_scale * float(unit_area ** (1.0 / dim))
        reach = float(np.abs(positions).max()) / scale
        if reach > MAX_POSITION_REACH:
            raise InputError(
                f"positions lie up to {reach:.1e} box lengths from the origin: in double "
                "precision their digits no longer resolve the bond vectors (wrap them into "
                "the box, e.g. positions % 1 in fractional coordinates)"
            )
        if m and np.any(length <= 1e-12 * scale):
            raise InputError(f"bond {int(np.argmin(length))} has zero length")
        for name, arr in (
            ("box", box),
            ("positions", positions),
            ("bonds", bonds),
            ("shifts", shifts),
            ("kinds", kinds),
            ("stiffness", stiffness),
        ):
            if arr is not None:
                arr.setflags(write=False)
            object.__setattr__(self, name, arr)

    @property
    def dim(self) -> int:
        """Dimension d of the space (2 or 3)."""
        return int(self.box.shape[0])

    @property
    def n_nodes(self) -> int:
        """Number of nodes N."""
        return int(self.positions.shape[0])

    @property
    def n_sites(self) -> int:
        """Number of bond sites m (empty ones included)."""
        return int(self.bonds.shape[0])

    def bond_vectors(self) -> np.ndarray:
        """Bond vectors ``d_b = positions[j] + shifts[b] @ box - positions[i]``.

        Returns
        -------
        (m, d) float
            One row per bond site (empty sites included).
        """
        return (
            self.positions[self.bonds[:, 1]]
            + self.shifts @ self.box
            - self.positions[self.bonds[:, 0]]
        )

    def bond_lengths(self) -> np.ndarray:
        """Bond lengths ``|d_b|``.

        Returns
        -------
        (m,) float
            One per bond site (empty sites included).
        """
        return vector_norms(self.bond_vectors())

    def stiffness_or_ones(self) -> np.ndarray:
        """Stiffness per site, ones when none was given.

        Returns
        -------
        (m,) float
            Spring constants ``k_b``.
        """
        return np.ones(self.n_sites) if self.stiffness is None else self.stiffness

    def with_kinds(self, kinds) -> PeriodicNetwork:
        """The same geometry with other element kinds.

        Parameters
        ----------
        kinds : (m,) int
            :class:`Element` codes, one per site.

        Returns
        -------
        PeriodicNetwork
            A new, validated network (this one is unchanged).
        """
        return replace(self, kinds=kinds)

    def count(self, kind: Element) -> int:
        """Number of sites holding ``kind``.

        Parameters
        ----------
        kind : Element
            The element kind.

        Returns
        -------
        int
            How many of the ``m`` sites hold it.
        """
        return int(np.count_nonzero(self.kinds == kind))


def check_strain(strain, dim: int | None = None) -> np.ndarray:
    """Validate a strain tensor: finite, square of dimension 2 or 3 (``dim`` if given),
    symmetric.

    Parameters
    ----------
    strain : (d, d) array_like
        The tensor; off-diagonal entries may differ by round-off (``1e-12`` of the largest
        entry), the lower one is then set to the upper one.
    dim : int, optional
        The dimension it must have (the network's).

    Returns
    -------
    (d, d) float
        A symmetric float copy.

    Raises
    ------
    InputError
        On a wrong shape or dimension, non-finite or complex values, or an asymmetric tensor.
    """
    eps = _as_float_array("strain", strain, (None, None))
    d = eps.shape[0]
    if eps.shape[1] != d or d not in DIMENSIONS:
        raise InputError(f"strain must have shape (2, 2) or (3, 3), got {eps.shape}")
    if dim is not None and d != dim:
        raise InputError(
            f"strain has shape {eps.shape} but the network is {dim}-dimensional: give a "
            f"({dim}, {dim}) tensor"
        )
    top = float(np.abs(eps).max())
    for a, b in zip(*np.triu_indices(d, 1), strict=True):
        if abs(eps[a, b] - eps[b, a]) > 1e-12 * top:
            raise InputError(
                "strain must be symmetric, got off-diagonal entries "
                f"{eps[a, b]!r} and {eps[b, a]!r}"
            )
        eps[b, a] = eps[a, b]
    return eps


@dataclass(frozen=True, eq=False)
class Instance:
    """A periodic network under a metric strain: the input of :func:`solve`.

    Parameters
    ----------
    network : PeriodicNetwork
        Geometry and elements.
    strain : (d, d) float
        Symmetric strain tensor eps, magnitude included, of the network's dimension. The
        affine extension of bond b is ``e0_b = dhat_b . eps . d_b``.
    """

    network: PeriodicNetwork
    strain: np.ndarray

    def __post_init__(self) -> None:
        if not isinstance(self.network, PeriodicNetwork):
            raise InputError("network must be a PeriodicNetwork")
        eps = check_strain(self.strain, self.network.dim)
        eps.setflags(write=False)
        object.__setattr__(self, "strain", eps)

    @classmethod
    def from_arrays(cls, box, positions, bonds, shifts, kinds, strain, stiffness=None) -> Instance:
        """Build and validate an instance from raw arrays.

        Parameters
        ----------
        box : (d, d) float
            Lattice vectors of the periodic box, as rows (``d = 2`` or ``3``).
        positions : (N, d) float
            Node positions.
        bonds : (m, 2) int
            Node indices ``(i, j)`` of each bond site.
        shifts : (m, d) int
            Integer image offsets of node ``j``.
        kinds : (m,) int
            :class:`Element` codes.
        strain : (d, d) float
            Symmetric strain tensor, magnitude included.
        stiffness : (m,) float, optional
            Positive spring constants (unit when omitted).

        Returns
        -------
        Instance
            The validated instance.

        Raises
        ------
        InputError
            As :class:`PeriodicNetwork` and :func:`check_strain`.
        """
        return cls(PeriodicNetwork(box, positions, bonds, shifts, kinds, stiffness), strain)

    def with_kinds(self, kinds) -> Instance:
        """The same instance with other element kinds.

        Parameters
        ----------
        kinds : (m,) int
            :class:`Element` codes, one per site.

        Returns
        -------
        Instance
            Same geometry and strain.
        """
        return Instance(self.network.with_kinds(kinds), self.strain)

    def with_strain(self, strain) -> Instance:
        """The same network under another strain tensor.

        Parameters
        ----------
        strain : (d, d) float
            Symmetric strain tensor, magnitude included.

        Returns
        -------
        Instance
            Same network and elements.
        """
        return Instance(self.network, strain)
