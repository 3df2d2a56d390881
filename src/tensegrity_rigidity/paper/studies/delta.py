"""Node disorder: the headline claims at one size for each delta.

The comparison's evidence for the factor "delta" (the values at each delta, the default one as
a control). The default delta reads the first samples of the finite-size study's sweeps at that
size (they share names).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import pandas as pd

from ...model.lattice import DEFAULT_DELTA
from ..claims import CLAIMS, Measurement
from ..comparison import fmt
from ..study import Result, Scale, Study
from ..template import load
from .headline import (
    ENERGY_SAMPLES,
    energy_names,
    energy_sweeps,
    headline,
    headline_sweeps,
    z_paper,
)
from .rows import Rows

NAME = "delta"
T = load(NAME)


@dataclass(frozen=True, kw_only=True)
class Params:
    deltas: tuple[float, ...] = (0.1, 0.2, 0.3)
    n: int = 5  # lattice size
    samples: int = 6  # samples per point

    @property
    def energy_samples(self) -> int:
        """Of the energy grids: the first :data:`~.headline.ENERGY_SAMPLES` at most."""
        return min(self.samples, ENERGY_SAMPLES)


PARAMS = {"tiny": Params(samples=3), "fss": Params(n=32, samples=24),
          "fss-cluster": Params(n=32, samples=32)}  # fmt: skip


@dataclass(frozen=True, eq=False)
class DeltaResult(Result):
    """``by_delta``: per (delta, key) value, err and ``z_paper`` (against the paper's claim)."""

    by_delta: pd.DataFrame
    deltas: tuple[float, ...]
    n: int
    samples: int


def sweeps(scale: Scale) -> dict[str, dict]:
    p, out = scale[NAME], dict[str, dict]()
    for delta in p.deltas:
        out |= headline_sweeps(p.n, delta, p.samples)
        out |= energy_sweeps(p.n, delta, count=p.energy_samples)
    return out


def analyse(rows: Rows, scale: Scale) -> DeltaResult:
    """The headline claims at n = ``n`` for each delta; as measurements labelled by delta, the
    default one as the control (its samples are not those of our headline value: a claim that
    agrees at another delta and also at the default one here agrees through the sample set)."""
    p, frames = scale[NAME], []
    excluded: dict[str, int] = {}
    bracketed: dict[str, int] = {}
    for delta in p.deltas:
        f, ex, br = headline(rows, p.n, delta, scale, samples=p.samples, energy=p.energy_samples)
        frames.append(f.assign(delta=delta))
        excluded |= ex
        bracketed |= br
    by = pd.concat(frames, ignore_index=True)
    by["z_paper"] = [z_paper(row.key, row.value, row.err) for row in by.itertuples()]
    system = T.label("system", n=p.n, samples=p.samples)
    measured = tuple(
        Measurement.scalar(
            row.key,
            row.value,
            row.err,
            system,
            factor="delta",
            control=math.isclose(row.delta, DEFAULT_DELTA),
            label=T.label(
                "label",
                delta=row.delta,
                control="" if math.isclose(row.delta, DEFAULT_DELTA) else None,
            ),
        )
        for row in by.itertuples()
        if row.key in CLAIMS
    )
    return DeltaResult(
        by_delta=by,
        deltas=tuple(p.deltas),
        n=p.n,
        samples=p.samples,
        excluded=excluded,
        measured=measured,
        bracketed=bracketed,
    )


def report_tables(r: DeltaResult) -> dict:
    wide, err, z = (r.by_delta.pivot_table(index="key", columns="delta", values=v)
                    for v in ("value", "err", "z_paper"))  # fmt: skip
    table = pd.DataFrame({"claim": [CLAIMS[k].text for k in wide.index],
                          "paper": [CLAIMS[k].paper for k in wide.index]})  # fmt: skip
    for d in wide.columns:
        table[f"delta = {d:g}"] = [
            f"{fmt(v, e)} (z = {x:.1f})" for v, e, x in zip(wide[d], err[d], z[d], strict=True)
        ]
    return {"by_delta": table}


def cost(scale: Scale, costs) -> float:
    """The analysis: per delta, six collapse fits at Fig. 1C's rate."""
    return costs.analysis(NAME) * len(scale[NAME].deltas) * scale.bootstrap / 100


def errors(scale: Scale) -> list[tuple]:
    p = scale[NAME]
    return [("st_sr_cables_compression", NAME, "st_sr", p.n, p.samples),
            ("rods_only_pc", NAME, "p_crit", p.n, p.samples)]  # fmt: skip


STUDY = Study(
    name=NAME, params=PARAMS, default=Params(), sweeps=sweeps, analyse=analyse,
    claims=lambda r: r.measured, cost=cost, report_tables=report_tables, errors=errors,
    numbers=lambda r: {"node_disorder": DEFAULT_DELTA, "deltas": r.deltas, "n": r.n,
                       "samples": r.samples},
    tables=lambda r: {"delta_by_delta": r.by_delta}, energy=energy_names, evidence=True,
)  # fmt: skip
