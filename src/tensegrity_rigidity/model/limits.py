"""Size guards: what a request would need, compared with what this machine has.

Every guard raises :class:`~tensegrity_rigidity.errors.InputError` *before* allocating, with one
sentence that says how much was asked and how much there is, so that a typo such as
``n = 100000`` or ``samples = 1e9`` ends in one line instead of an exhausted machine.

The memory of one sample's work is measured per lattice (so per dimension) and stage by
``benchmarks/measure_memory.py``, which writes ``memory_costs.toml`` beside this module: bytes
per node of building a sample, of one solve, of one threshold search and of the pebble game,
and how the cost per node grows with the size (3D factorisations fill in). A lattice of linear
size ``n`` has ``n^d`` nodes.
"""

from __future__ import annotations

import math
import os
import tomllib
from importlib import resources

import numpy as np

from ..errors import InputError
from .network import show

#: Bytes per node of each stage of one sample's work, per lattice: ``dim``, then per stage
#: (``build``, ``solve``, ``threshold``, ``clusters``) the bytes per node at ``{stage}_nodes``
#: nodes and the exponent of the growth beyond (read from ``memory_costs.toml``, measured and
#: written by benchmarks/measure_memory.py).
MEMORY_COSTS: dict[str, dict] = tomllib.loads(
    resources.files(__package__).joinpath("memory_costs.toml").read_text(encoding="utf-8")
)
#: The stages whose memory is measured.
STAGES = ("build", "solve", "threshold", "clusters")


def lattice_dimension(lattice: str) -> int:
    """The dimension of a lattice of :data:`MEMORY_COSTS` (2 for another).

    Parameters
    ----------
    lattice : str
        The lattice's name.

    Returns
    -------
    int
        2 or 3.
    """
    return int(MEMORY_COSTS.get(lattice, {}).get("dim", 2))


def lattice_nodes(lattice: str, n: int) -> float:
    """Nodes of a lattice of linear size ``n``: ``n^d`` (``n^3`` on the FCC lattice).

    Parameters
    ----------
    lattice : str
        A lattice of :data:`MEMORY_COSTS` (another counts as 2D).
    n : int
        Linear size.

    Returns
    -------
    float
        The node count (a float: ``n`` may be absurd).
    """
    return float(n) ** lattice_dimension(lattice)


def stage_bytes(stage: str, nodes: float, lattice: str | None = None, dim: int = 2) -> float:
    """Memory of one ``stage`` of a sample's work on ``nodes`` nodes.

    Parameters
    ----------
    stage : {"build", "solve", "threshold", "clusters"}
        What is done (:data:`STAGES`).
    nodes : float
        Nodes of the network.
    lattice : str, optional
        Its lattice; for any other network (or a lattice not measured) the largest cost of
        the measured lattices of its dimension (``dim``), else of any.
    dim : int
        The dimension, when ``lattice`` is not given.

    Returns
    -------
    float
        Bytes: the cost per node times ``nodes``, times ``(nodes / measured)^(e - 1)`` above
        the largest size measured when the cost per node grows (``e > 1``).
    """
    measured = [c for c in MEMORY_COSTS.values() if stage in c]
    if lattice in MEMORY_COSTS and stage in MEMORY_COSTS[lattice]:
        entries = [MEMORY_COSTS[lattice]]
    else:  # the dimension's lattices, else every lattice: never no guard at all
        dim = int(MEMORY_COSTS.get(lattice or "", {}).get("dim", dim))
        entries = [c for c in measured if int(c["dim"]) == dim] or measured
    need = 0.0
    for costs in entries:
        if stage not in costs:
            continue
        per_node = float(costs[stage])
        growth = max(1.0, nodes / float(costs[f"{stage}_nodes"])) ** (
            float(costs[f"{stage}_exponent"]) - 1.0
        )
        need = max(need, per_node * nodes * growth)
    return need


#: Range of the largest affine extension ``max |e0|`` (physical length units) that the solver
#: accepts. The search works in units of it; outside this range its square, which energies
#: carry, leaves double precision.
STRAIN_SCALE_RANGE = (1e-150, 1e150)
#: Range of the strain magnitude ``gamma`` accepted by the strain builders, sample files and
#: sweep specs. Lattice bonds have lengths of order one, so ``max |e0|`` stays inside
#: :data:`STRAIN_SCALE_RANGE` with ten decades to spare.
GAMMA_RANGE = (1e-140, 1e140)
#: Range of the energy scale ``stiffness x max |e0|^2`` (summed over the sites, for the upper
#: end) within which energies, their bounds and the affine energy are finite doubles and not
#: flushed to zero.
ENERGY_RANGE = (1e-300, 1e300)


def check_gamma(gamma: float, what: str = "gamma") -> float:
    """Refuse a strain magnitude outside :data:`GAMMA_RANGE` (or not a positive finite number).

    Parameters
    ----------
    gamma : float
        The magnitude.
    what : str
        Its name in the message ("[strain] gamma" in a spec, "--gamma" on the command line).

    Returns
    -------
    float
        ``gamma`` as a float.

    Raises
    ------
    InputError
        One sentence naming the accepted range.
    """
    lo, hi = GAMMA_RANGE
    if isinstance(gamma, (bool, np.bool_)) or not isinstance(gamma, (int, float, np.number)):
        raise InputError(f"{what} must be a number, got {show(gamma)}")
    try:
        value = float(gamma)
    except (TypeError, ValueError, OverflowError):
        value = math.nan
    if not math.isfinite(value) or value <= 0:
        raise InputError(f"{what} must be a positive finite number, got {show(gamma)}")
    if not lo <= value <= hi:
        raise InputError(
            f"{what} = {value:.1e} lies outside [{lo:.0e}, {hi:.0e}]: energies (proportional to "
            "its square) would leave double precision; verdicts do not depend on it, so "
            "rescale it"
        )
    return value


def check_energy_scale(scale: float, stiffness: np.ndarray) -> None:
    """Refuse an instance whose energies cannot be represented in double precision.

    Parameters
    ----------
    scale : float
        ``max |e0|`` over the bond sites (physical units; 0 when nothing is strained, which is
        accepted: the verdict is floppy with zero energy).
    stiffness : (m,) float
        Positive stiffnesses of the non-empty sites.

    Raises
    ------
    InputError
        When ``scale`` lies outside :data:`STRAIN_SCALE_RANGE`, or ``stiffness x scale^2``
        outside :data:`ENERGY_RANGE` (computed in logarithms, so the check cannot overflow).
    """
    if scale == 0:
        return
    lo, hi = STRAIN_SCALE_RANGE
    if not lo <= scale <= hi:
        raise InputError(
            f"the largest affine extension is {scale:.1e}, outside [{lo:.0e}, {hi:.0e}]: "
            "energies (proportional to its square) are not representable in double "
            "precision; rescale the strain (verdicts do not depend on its magnitude)"
        )
    k = np.asarray(stiffness, dtype=float)
    if k.size == 0:
        return
    log_scale2 = 2.0 * math.log10(scale)
    top = math.log10(float(k.max())) + log_scale2 + math.log10(0.5 * k.size)
    bottom = math.log10(float(k.min())) + log_scale2
    e_lo, e_hi = ENERGY_RANGE
    if top > math.log10(e_hi) or bottom < math.log10(e_lo):
        raise InputError(
            f"stiffness x (largest affine extension)^2 spans 1e{bottom:.0f} to 1e{top:.0f}, "
            f"outside [{e_lo:.0e}, {e_hi:.0e}]: energies are not representable in double "
            "precision; rescale the stiffnesses or the strain (verdicts depend on neither)"
        )


def physical_memory() -> int:
    """Bytes of physical memory of this machine.

    Returns
    -------
    int
        ``SC_PAGE_SIZE * SC_PHYS_PAGES``; ``2**50`` where it cannot be read (no guard).
    """
    try:
        return int(os.sysconf("SC_PAGE_SIZE")) * int(os.sysconf("SC_PHYS_PAGES"))
    except (ValueError, OSError, AttributeError):  # not POSIX: do not guard
        return 1 << 50


def format_bytes(n: float) -> str:
    """A byte count for people: ``format_bytes(1.5e12) == '1.4 TiB'``.

    Parameters
    ----------
    n : float
        Bytes.

    Returns
    -------
    str
        The count in bytes, KiB, MiB, GiB, TiB or PiB.
    """
    value = float(n)
    for unit in ("bytes", "KiB", "MiB", "GiB", "TiB", "PiB"):
        if value < 1024 or unit == "PiB":
            return f"{value:.0f} {unit}" if unit == "bytes" else f"{value:.1f} {unit}"
        value /= 1024
    raise AssertionError("unreachable")


def check_memory(need: float, what: str) -> None:
    """Refuse ``what`` (a phrase: "n = 100000") when it needs more than the physical memory.

    Parameters
    ----------
    need : float
        Estimated bytes.
    what : str
        What is asked, for the message ("building n = 100000", "member 'positions'").

    Raises
    ------
    InputError
        When ``need`` exceeds this machine's physical memory.
    """
    have = physical_memory()
    if need > have:
        raise InputError(
            f"{what} needs about {format_bytes(need)} of memory; this machine has "
            f"{format_bytes(have)}"
        )
