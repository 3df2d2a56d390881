"""How long each scale of ``reproduce`` takes, as text: the ``expected`` entries of
``data/scales.toml``, read with the standard library alone, so that the command line's help
shows them without importing the studies or the numerical stack."""

from __future__ import annotations

import tomllib
from pathlib import Path

#: the scales of a reproduction (read here and by :mod:`~tensegrity_rigidity.paper.registry`)
SCALES_FILE = Path(__file__).with_name("data") / "scales.toml"


def read_scales(path: Path = SCALES_FILE) -> dict[str, dict]:
    """The scales' settings as the data file states them (without the studies' parameters,
    which :data:`~tensegrity_rigidity.paper.registry.SCALES` joins).

    Parameters
    ----------
    path : path-like
        The data file (default: the package's ``data/scales.toml``).

    Returns
    -------
    dict
        Scale name -> its settings (``bootstrap``, ``budget_minutes``, ``expected``), in the
        file's order.
    """
    return tomllib.loads(Path(path).read_text())


#: wall times of each scale on 2 cores of the reference machine: measured where stated, else the
#: estimate of :mod:`~tensegrity_rigidity.paper.budget` (``reproduce --estimate``; the tests keep
#: the two in step) until someone times a run
EXPECTED: dict[str, str] = {name: s.get("expected", "") for name, s in read_scales().items()}
