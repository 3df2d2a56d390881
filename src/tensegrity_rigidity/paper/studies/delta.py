"""Node disorder: the headline claims at one size for each delta.

The comparison's evidence for the factor "delta" (the values at each delta, the default one as
a control). At the ``fss`` scale: n = 32, delta = 0.1, 0.2, 0.3; the default delta reads the
first samples of the finite-size study's sweeps at that size (they share names).

Like the figure modules: ``sweeps(scale)``, ``analyse(rows, scale)``, ``claims(result)`` and
``study(out, scale, **kw)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import pandas as pd

from ...model.lattice import DEFAULT_DELTA
from ..claims import CLAIMS, Measurement
from .headline import energy_names, energy_sweeps, headline, headline_sweeps, z_paper
from .rows import Rows, load_sweeps
from .scales import Scale


def sweeps(scale: Scale) -> dict[str, dict]:
    """Sweep name -> spec of the node-disorder study (every delta at ``scale.n_delta``)."""
    out: dict[str, dict] = {}
    for delta in scale.deltas:
        out |= headline_sweeps(scale.n_delta, delta, scale.samples_delta)
        out |= energy_sweeps(scale.n_delta, delta, count=scale.delta_energy_samples)
    return out


@dataclass(frozen=True, eq=False)
class DeltaResult:
    """The headline claims at each node disorder delta (one size).

    Attributes
    ----------
    by_delta : DataFrame
        Per (delta, key): value, err and ``z_paper`` (against the paper's claim).
    deltas : tuple of float
    n, samples : int
        The size and its samples per point.
    excluded, bracketed : dict
        As :class:`~.fss.FiniteSizeResult`'s.
    measured : tuple of Measurement
        The evidence for the factor "delta".
    """

    by_delta: pd.DataFrame
    deltas: tuple[float, ...]
    n: int
    samples: int
    excluded: dict[str, int]
    measured: tuple[Measurement, ...] = ()
    bracketed: dict[str, int] = field(default_factory=dict)


def delta_label(delta: float) -> str:
    """The label of a node-disorder measurement in the comparison's explanations.

    The default delta is listed too, as the control: its samples are not those of our headline
    value (another seed and size), so a claim that agrees at another delta and also at the
    default one on these samples agrees through the sample set, not through delta.
    """
    if math.isclose(delta, DEFAULT_DELTA):
        return f"delta = {delta:g} (control: our delta on this study's samples)"
    return f"delta = {delta:g}"


def analyse(rows: Rows, scale: Scale) -> DeltaResult:
    """The headline claims at n = ``scale.n_delta`` for each delta of ``scale.deltas``."""
    frames: list[pd.DataFrame] = []
    excluded: dict[str, int] = {}
    bracketed: dict[str, int] = {}
    for delta in scale.deltas:
        f, ex, br = headline(
            rows, scale.n_delta, delta, scale,
            samples=scale.samples_delta, energy=scale.delta_energy_samples,
        )  # fmt: skip
        frames.append(f.assign(delta=delta))
        excluded |= ex
        bracketed |= br
    by_delta = pd.concat(frames, ignore_index=True)
    by_delta["z_paper"] = [z_paper(row.key, row.value, row.err) for row in by_delta.itertuples()]
    system = f"n = {scale.n_delta}, {scale.samples_delta} samples per point"
    measured = tuple(
        Measurement.scalar(
            row.key, row.value, row.err, system, factor="delta", label=delta_label(row.delta)
        )
        for row in by_delta.itertuples()
        if row.key in CLAIMS
    )
    return DeltaResult(
        by_delta=by_delta,
        deltas=tuple(scale.deltas),
        n=scale.n_delta,
        samples=scale.samples_delta,
        excluded=excluded,
        measured=measured,
        bracketed=bracketed,
    )


def claims(result: DeltaResult) -> tuple[Measurement, ...]:
    """The evidence for the factor "delta" (:attr:`DeltaResult.measured`)."""
    return result.measured


def study(out, scale: Scale, **kw) -> DeltaResult:
    """Run (or resume) the node-disorder sweeps into ``out`` and analyse them."""
    specs = sweeps(scale)
    return analyse(load_sweeps(out, specs, energy=energy_names(specs), **kw), scale)
