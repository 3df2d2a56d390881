"""The studies, one module each (the registry lists them), and what they share.

A study module defines its parameters at each scale (``PARAMS``), ``sweeps``, ``analyse``,
``claims``, the numbers its template quotes, its figures, tables and cost, and ends with a
:class:`~tensegrity_rigidity.paper.study.Study`. Shared by several: :mod:`.rows` (reading sweep
rows: undecided samples, threshold intervals, grids), :mod:`.headline` (the headline claims at
one size and node disorder), :mod:`.energy`, :mod:`.nonaffinity` and :mod:`.field`.
"""

from __future__ import annotations

from .rows import STORED

__all__ = ["STORED", "SCALES"]


def __getattr__(name: str):
    if name == "SCALES":  # built by the registry from every study's parameters
        from ..registry import SCALES

        return SCALES
    raise AttributeError(name)
