"""Size guards: what a request would need, compared with what this machine has.

Every guard raises :class:`~tensegrity_rigidity.errors.InputError` *before* allocating, with one
sentence that says how much was asked and how much there is, so that a typo such as
``n = 100000`` or ``samples = 1e9`` ends in one line instead of an exhausted machine.

The per-node costs below were measured on the triangular lattice (peak resident memory of
``lattice_instance`` and of :func:`~tensegrity_rigidity.solver.core.solve`, n = 32 .. 1024):
building costs about 490 bytes per node; a solve 7 to 10 kB per node (CHOLMOD's factor,
the interior-point work arrays).
"""

from __future__ import annotations

import math
import os

import numpy as np

from ..errors import InputError

#: bytes per node of building a lattice sample (geometry, bonds, shifts, kinds, uniforms);
#: measured 490 at n = 1024, rounded up.
BUILD_BYTES_PER_NODE = 600
#: bytes per node of one solve (measured 10 kB at n = 32, 8 kB at n = 64, 7.4 kB at n = 128).
SOLVE_BYTES_PER_NODE = 12_000


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
    try:
        value = float(gamma)
    except (TypeError, ValueError):
        raise InputError(f"{what} must be a number, got {gamma!r}") from None
    if not math.isfinite(value) or value <= 0:
        raise InputError(f"{what} must be a positive finite number, got {gamma!r}")
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
