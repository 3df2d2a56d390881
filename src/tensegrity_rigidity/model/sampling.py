"""One random lattice sample: geometry, elements and strain from explicit randomness.

:func:`lattice_instance` is the single place where a sample is drawn, so that the command line,
the sweeps and the tests all build the same sample from the same seed. The node kicks and the
site uniforms ``(U, V)`` come from one generator, in that order; the element kinds follow from the
uniforms and ``(p_r, p_t, f_c)`` by the monotone coupling, so samples that share a seed share
their geometry and uniforms across every ``(p_r, p_t, f_c)`` and strain (common random numbers).
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from .elements import check_probabilities, place_elements, site_uniforms
from .lattice import DEFAULT_DELTA, fcc_lattice, square_lattice, triangular_lattice
from .network import Instance, PeriodicNetwork, show
from .strain import strain_tensor

LATTICES = {"triangular": triangular_lattice, "square": square_lattice, "fcc": fcc_lattice}
#: the dimension of each lattice's networks
LATTICE_DIMENSIONS = {"triangular": 2, "square": 2, "fcc": 3}


def check_seed(seed) -> int | None:
    """Validate a seed: ``None`` or a non-negative integer (what ``SeedSequence`` accepts).

    Parameters
    ----------
    seed : int or None
        The seed.

    Returns
    -------
    int or None
        The seed as a Python int.

    Raises
    ------
    InputError
        On anything else (a negative number, a float, a bool).
    """
    if seed is None:
        return None
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)):
        raise InputError(f"seed must be a non-negative integer, got {show(seed)}")
    if seed < 0:
        raise InputError(f"seed must be a non-negative integer, got {seed}")
    return int(seed)


def lattice_geometry(
    n: int, delta: float, rng: np.random.Generator, lattice: str = "triangular"
) -> tuple[PeriodicNetwork, np.ndarray, np.ndarray]:
    """An empty lattice and its site uniforms, drawn from ``rng`` (kicks first, then U, V).

    Parameters
    ----------
    n : int
        Linear size.
    delta : float
        Node disorder.
    rng : numpy.random.Generator
        Source of the kicks and the uniforms.
    lattice : {"triangular", "square"}
        The builder (:func:`~.lattice.triangular_lattice`, :func:`~.lattice.square_lattice`).

    Returns
    -------
    network : PeriodicNetwork
        ``n^2`` nodes, ``m`` empty sites.
    u, v : (m,) float
        The site uniforms (:func:`~.elements.site_uniforms`).

    Raises
    ------
    InputError
        On an unknown lattice or invalid ``n``, ``delta``.
    """
    builder = LATTICES.get(lattice) if isinstance(lattice, str) else None
    if builder is None:
        raise InputError(f"unknown lattice {show(lattice)}; choose from {', '.join(LATTICES)}")
    net = builder(n, delta, rng)
    u, v = site_uniforms(net.n_sites, rng)
    return net, u, v


def lattice_instance(
    n: int,
    p_r: float,
    p_t: float = 0.0,
    f_c: float = 0.5,
    phi: float | str = "shear",
    theta: float = 0.0,
    gamma: float = 1.0,
    delta: float = DEFAULT_DELTA,
    seed: int | np.random.Generator | None = 0,
    lattice: str = "triangular",
    rotation_matrix: np.ndarray | None = None,
) -> Instance:
    """A random strained lattice sample.

    Parameters
    ----------
    n : int
        Linear size (n x n nodes, 3 n^2 sites on the triangular lattice).
    p_r, p_t, f_c : float
        Rod probability, one-sided probability (``p_r + p_t <= 1``), cable fraction of the
        one-sided elements (``f_c = 1``: cables only, ``0``: struts only).
    phi : float or str
        Strain type: an angle, or "dilation" (0), "shear" (pi/2), "compression" (pi).
    theta : float
        Principal-axis angle of the strain in 2D, radians (a nonzero one is refused on the
        3D lattice, whose axes are ``rotation_matrix``).
    gamma : float
        Strain magnitude (positive); energies scale as ``gamma^2``, verdicts do not change.
    delta : float
        Node disorder, in lattice constants (:data:`~.lattice.DEFAULT_DELTA`).
    seed : int, numpy.random.Generator or None
        Randomness of the geometry and the site uniforms; an integer must be non-negative,
        None draws fresh entropy (a different sample on every call). The same seed gives the
        same geometry and uniforms for every ``(p_r, p_t, f_c)`` and strain (common random
        numbers).
    lattice : {"triangular", "square", "fcc"}
        The lattice builder ("fcc": the 3D FCC lattice, ``n^3`` nodes, ``6 n^3`` sites).
    rotation_matrix : (3, 3) float, optional
        Principal axes of a 3D strain (:func:`~.strain.strain_tensor`; default the
        coordinate axes); ``theta`` sets them in 2D.

    Returns
    -------
    Instance
        The network (``n^2`` nodes, ``3 n^2`` sites on the triangular lattice) and its strain.

    Raises
    ------
    InputError
        On invalid probabilities, sizes, strains or seeds (one sentence).

    Examples
    --------
    >>> from tensegrity_rigidity import lattice_instance, solve
    >>> inst = lattice_instance(8, p_r=0.9, phi="dilation", seed=1)
    >>> inst.network.n_nodes, inst.network.n_sites
    (64, 192)
    >>> solve(inst).status
    'rigid'
    """
    check_probabilities(p_r, p_t, f_c)
    rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(check_seed(seed))
    net, u, v = lattice_geometry(n, delta, rng, lattice)
    kinds = place_elements(u, v, p_r, p_t, f_c)
    strain = strain_tensor(phi, theta, gamma, rotation_matrix=rotation_matrix, dim=net.dim)
    return Instance(net.with_kinds(kinds), strain)
