"""Every figure of a reproduction: each study draws its own (its ``figures``), in one style."""

from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt

from .style import STYLE


def all_figures(results: dict, figdir: Path) -> dict[str, list[Path]]:
    """Draw the figures of every study in ``results`` (study name -> result) in
    :data:`~tensegrity_rigidity.paper.style.STYLE`; returns {figure id: [png, svg]}."""
    from .registry import STUDIES

    out: dict[str, list[Path]] = {}
    with plt.rc_context(STYLE):
        for name, result in results.items():
            out |= STUDIES[name].figures(result, Path(figdir))
    return out
