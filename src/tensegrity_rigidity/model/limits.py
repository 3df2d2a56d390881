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

import os

from ..errors import InputError

#: bytes per node of building a lattice sample (geometry, bonds, shifts, kinds, uniforms);
#: measured 490 at n = 1024, rounded up.
BUILD_BYTES_PER_NODE = 600
#: bytes per node of one solve (measured 10 kB at n = 32, 8 kB at n = 64, 7.4 kB at n = 128).
SOLVE_BYTES_PER_NODE = 12_000


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
