"""Beyond the paper: when is a random bidisperse disk packing jammed?

Per size N, random 50:50 bidisperse soft-disk packings (diameter ratio 1.4, energy minimised
from uniform positions at fixed packing fraction, :mod:`~tensegrity_rigidity.model.softdisks`)
on a grid of packing fractions, each tested for collective and strict jamming with a certificate
(:func:`~tensegrity_rigidity.solver.jamming.jamming`) by a packing sweep of the ensemble layer.
From them: P(collectively jammed) per (N, phi) with Wilson intervals, the fraction strictly
jammed among the collectively jammed, the jamming point phi_J(N) where a logistic fit of P
crosses 1/2 (bootstrap errors over samples), its finite-size shift ``phi_J(N) = phi_inf + a
N^(-b)`` in every form the data allow (:mod:`~tensegrity_rigidity.analysis.jamming`), the
isostatic count on every jammed packing, and one packing drawn with its contact forces and
rattlers. A sample whose collective test is undecided is counted and left out of P; one whose
strict test is undecided is counted and left out of the strict fraction.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd
from matplotlib.ticker import NullLocator

from ...analysis.binomial import wilson
from ...analysis.jamming import (
    FiniteSizeShift,
    JammingPoint,
    finite_size_shift,
    jamming_points,
    jamming_table,
)
from ...ensemble.jamming import sample_rng, sample_seconds
from ...errors import InputError
from ...model.network import PeriodicNetwork
from ...model.softdisks import DIAMETER_RATIO, SoftPacking, soft_packing
from ...solver.jamming import JammingResult, jamming
from ..claims import REFERENCES
from ..comparison import fmt
from ..jamming_figures import plot_jamming_probability, plot_packing
from ..study import Result, Scale, Study
from ..style import COLUMN, grid, legend_below, save
from ..template import load
from .rows import Rows

NAME = "jamming_onset"
T = load(NAME)
#: root seed of the packings (sample k at (N, phi) derives from (seed, N, phi, k))
SEED = 92
#: the dimension of the study's packings
DIM = 2
#: the literature's jamming point of this system (quoted beside ours, never fitted to)
PHI_J_REFERENCE = REFERENCES["phi_j_ohern"]


@dataclass(frozen=True, kw_only=True)
class Params:
    """Sizes N and samples per packing fraction at each, the packing fractions, and the point
    ``(N, phi)`` of the packing drawn (its first collectively jammed sample)."""

    sizes: tuple[int, ...] = ()
    samples: tuple[int, ...] = ()
    fractions: tuple[float, ...] = ()
    drawn: tuple[int, float] = (0, 0.0)

    def samples_at(self, n: int) -> int:
        return dict(zip(self.sizes, self.samples, strict=True)).get(n, 0)


def _fractions(lo: float, hi: float, step: float) -> tuple[float, ...]:
    return tuple(round(float(x), 6) for x in np.arange(lo, hi + step / 2, step))


PARAMS = {
    "jamming": Params(sizes=(64, 128, 256, 512, 1024), samples=(96, 64, 48, 32, 16),
                      fractions=_fractions(0.81, 0.87, 0.0025), drawn=(256, 0.845)),
    "tiny-jamming": Params(sizes=(16, 32, 64), samples=(8, 8, 8),
                           fractions=_fractions(0.80, 0.88, 0.01), drawn=(64, 0.84)),
}  # fmt: skip


def chunk_size(n: int) -> int:
    """Samples per chunk at N: about half a minute of work (a sample costs about 0.2 s at N =
    64 and 4 s at N = 1024), so an interruption loses little."""
    return max(1, min(32, int(30.0 / sample_seconds(n, DIM))))


def sweeps(scale: Scale) -> dict[str, dict]:
    """One packing sweep per size, ``packings_n{N}``: every packing fraction, one seed."""
    p = scale[NAME]
    return {
        f"packings_n{n}": {"n": n, "fraction": list(p.fractions), "samples": s, "seed": SEED,
                           "packing": {"dim": DIM, "ratio": DIAMETER_RATIO},
                           "output": {"chunk_size": chunk_size(n)}}
        for n, s in zip(p.sizes, p.samples, strict=True)
    }  # fmt: skip


@dataclass(frozen=True)
class Drawn:
    """One packing of the study, rebuilt from its sample's coordinates and tested again."""

    n: int
    fraction: float
    sample: int
    packing: SoftPacking
    network: PeriodicNetwork
    result: JammingResult


@dataclass(frozen=True, eq=False)
class JammingOnsetResult(Result):
    """``table``: :func:`~tensegrity_rigidity.analysis.jamming.jamming_table` over every size
    (its ``phi`` the packing fraction); ``points``: phi_J and the width per size; ``shift``:
    the finite-size fits (None with fewer than two sizes whose phi_J is resolved); ``by_size``:
    per size the samples, undecided counts, the strictly jammed among the collectively jammed
    (pooled over phi, Wilson interval) and the jammed packings below the isostatic count;
    ``drawn``: the packing drawn (None if its point has no sample)."""

    table: pd.DataFrame
    points: tuple[JammingPoint, ...]
    shift: FiniteSizeShift | None
    by_size: pd.DataFrame
    drawn: Drawn | None


def rows_of(rows: Rows) -> pd.DataFrame:
    """The decided rows of every size in one frame, the packing fraction as ``phi`` (the
    column name of :mod:`~tensegrity_rigidity.analysis.jamming`)."""
    frames = [df for df, _ in rows.values() if not df.empty]
    if not frames:
        return pd.DataFrame(columns=["n", "phi", "sample", "collective", "strict"])
    return pd.concat(frames, ignore_index=True).rename(columns={"fraction": "phi"})


def per_size(df: pd.DataFrame, excluded: dict[int, int]) -> pd.DataFrame:
    """Per size: ``samples`` (decided), ``undecided`` (collective test; left out of P),
    ``jammed``, ``strict_tested`` (jammed with a decided strict test), ``strict_undecided``,
    ``strict``, ``p_strict`` with ``lo``/``hi`` (95 % Wilson), ``rattlers`` (mean fraction of
    rattlers in the jammed packings) and ``below_isostatic`` (jammed packings with fewer
    backbone contacts than d (N' - 1) + 1: a jammed packing has none)."""
    out = []
    for n, g in df.groupby("n", sort=True):
        jammed = g[g.collective == "jammed"]
        tested = jammed[jammed.strict != "undecided"]
        k = int((tested.strict == "jammed").sum())
        p, lo, hi = wilson(k, len(tested))
        below = int((jammed.backbone_contacts < jammed.isostatic_contacts).sum())
        out.append({"n": int(n), "samples": len(g), "undecided": excluded.get(int(n), 0),
                    "jammed": len(jammed), "strict_tested": len(tested),
                    "strict_undecided": len(jammed) - len(tested), "strict": k,
                    "p_strict": float(p), "lo": float(lo), "hi": float(hi),
                    "rattlers": float((jammed.rattlers / n).mean()) if len(jammed) else math.nan,
                    "below_isostatic": below})  # fmt: skip
    return pd.DataFrame(out)


def draw(df: pd.DataFrame, n: int, fraction: float) -> Drawn | None:
    """The first collectively jammed sample at ``(n, fraction)`` (the first sample if none is),
    rebuilt from its coordinates and tested again; its contacts and verdict must be its row's."""
    at = df[(df.n == n) & np.isclose(df.phi, fraction)].sort_values("sample")
    if at.empty:
        return None
    jammed = at[at.collective == "jammed"]
    row = (jammed if len(jammed) else at).iloc[0]
    k, seed = int(row["sample"]), int(row["seed"])
    sp = soft_packing(n, float(row.phi), sample_rng(seed, n, float(row.phi), k), dim=DIM)
    net = sp.packing.contact_network(tolerance=0.0)
    result = jamming(net, "collective")
    if (result.status, result.n_contacts) != (row.collective, int(row.contacts)):
        raise InputError(
            f"the drawn packing (N = {n}, phi = {row.phi}, sample {k}) is not its sweep row: "
            f"{result.status} with {result.n_contacts} contacts against {row.collective} with "
            f"{int(row.contacts)}"
        )
    return Drawn(n, float(row.phi), k, sp, net, result)


def analyse(rows: Rows, scale: Scale) -> JammingOnsetResult:
    """P per (N, phi), phi_J per size with bootstrap errors, the shift, the drawn packing."""
    p = scale[NAME]
    df = rows_of(rows)
    excluded = {name: count for name, (_, count) in rows.items()}
    size_of = {name: spec["n"] for name, spec in sweeps(scale).items()}
    by_n = {size_of[name]: count for name, count in excluded.items() if name in size_of}
    points = tuple(jamming_points(df, scale.rng("jamming_point"), replicas=scale.bootstrap))
    try:
        shift = finite_size_shift(list(points))
    except InputError:  # fewer than two sizes with a resolved phi_J: no shift to fit
        shift = None
    return JammingOnsetResult(
        table=jamming_table(df), points=points, shift=shift, by_size=per_size(df, by_n),
        drawn=draw(df, *p.drawn), excluded=excluded,
    )  # fmt: skip


def points_frame(r: JammingOnsetResult) -> pd.DataFrame:
    """Per size: ``n``, ``phi_j``, ``phi_j_err``, ``width``, ``width_err``, ``samples``."""
    return pd.DataFrame([{"n": q.n, "phi_j": q.phi_j.value, "phi_j_err": q.phi_j.err,
                          "width": q.width.value, "width_err": q.width.err,
                          "samples": q.samples} for q in r.points])  # fmt: skip


def shift_frame(r: JammingOnsetResult) -> pd.DataFrame:
    """Every form of the shift: ``exponent``, ``free``, ``phi_inf``, ``phi_inf_err``,
    ``amplitude``, ``amplitude_err``, ``chi2_dof``, ``accepted``."""
    if r.shift is None:
        return pd.DataFrame()
    return pd.DataFrame([{"exponent": f.exponent, "free": f.free, "phi_inf": f.phi_inf.value,
                          "phi_inf_err": f.phi_inf.err, "amplitude": f.amplitude.value,
                          "amplitude_err": f.amplitude.err, "chi2_dof": f.chi2_dof,
                          "accepted": f in r.shift.accepted} for f in r.shift.fits])  # fmt: skip


def _near(table: pd.DataFrame, n: int, phi: float) -> pd.Series:
    """The row of ``table`` at size ``n`` whose packing fraction is nearest ``phi``."""
    g = table[table.n == n]
    return g.iloc[int(np.argmin(np.abs(g.phi.to_numpy(float) - phi)))]


def numbers(r: JammingOnsetResult) -> dict:
    pts, by = points_frame(r), r.by_size
    sizes = [int(n) for n in by.n]
    phis = np.unique(r.table.phi.to_numpy(float)) if len(r.table) else np.array([math.nan])
    # a width below the packing-fraction grid's step rests on one point inside the transition
    step = float(np.diff(phis).min()) if phis.size > 1 else math.nan
    resolved = pts[np.isfinite(pts.phi_j) & np.isfinite(pts.phi_j_err)]
    fits, accepted = (r.shift.fits, r.shift.accepted) if r.shift is not None else ((), ())
    # phi_inf and its spread over the accepted forms (None when no form is accepted)
    inf = (r.shift.phi_inf, r.shift.spread) if r.shift is not None and accepted else None
    d = r.drawn
    rattlers = d.result.n_rattlers if d is not None else None
    at_ref = [_near(r.table, n, PHI_J_REFERENCE.value) for n in sizes]
    return {
        "dim": DIM,
        "ratio": DIAMETER_RATIO,
        "sizes": sizes,
        "counts": [T.label("count", samples=int(s), n=int(n))
                   for n, s in zip(by.n, by.samples + by.undecided, strict=True)],
        "fractions": len(phis),
        "step": step,
        "phi_lo": float(phis.min()),
        "phi_hi": float(phis.max()),
        "excluded": int(by.undecided.sum()),
        "strict_undecided": int(by.strict_undecided.sum()),
        "points": [T.label("point", n=int(q.n), value=fmt(q.phi_j, q.phi_j_err))
                   for q in resolved.itertuples()] or None,
        "unresolved": [int(n) for n in pts.n[~pts.index.isin(resolved.index)]] or None,
        "widths": [T.label("point" if q.width >= step else "point.coarse", n=int(q.n),
                           value=fmt(q.width, q.width_err), step=step)
                   for q in resolved.itertuples()] or None,  # fmt: skip
        "phi_inf": fmt(*inf) if inf is not None else None,
        "forms": [T.label("form", b=f.exponent, free=T.label("free") if f.free else "",
                          value=fmt(f.phi_inf.value, f.phi_inf.err), chi2=f.chi2_dof)
                  for f in accepted] or None,
        "rejected": len(fits) - len(accepted) if len(fits) > len(accepted) else None,
        "reference": PHI_J_REFERENCE.value,
        "from_reference": inf[0] - PHI_J_REFERENCE.value if inf is not None else None,
        "p_at_reference": [T.label("p_at", n=int(q.n), phi=float(q.phi), p=q.p, lo=q.p_lo,
                                   hi=q.p_hi, k=int(q.jammed), m=int(q.decided))
                           for q in at_ref] or None,
        "strict_fractions": [T.label("strict", n=int(q.n), p=q.p_strict, lo=q.lo, hi=q.hi,
                                     k=int(q.strict), m=int(q.strict_tested))
                             for q in by.itertuples() if q.strict_tested > 0] or None,
        "jammed": int(by.jammed.sum()),
        "below_isostatic": int(by.below_isostatic.sum()),
        "rattler_share": [T.label("point", n=int(q.n), value=f"{100 * q.rattlers:.1f} %")
                          for q in by.itertuples() if np.isfinite(q.rattlers)] or None,
        "drawn_n": d.n if d is not None else None,
        "drawn_phi": d.fraction if d is not None else None,
        "drawn_sample": d.sample if d is not None else None,
        "drawn_status": d.result.status if d is not None else None,
        "drawn_rattlers": rattlers,
        "drawn_contacts": d.result.backbone_contacts if d is not None else None,
        "drawn_isostatic": d.result.isostatic_contacts if d is not None else None,
    }  # fmt: skip


def _shift_panel(ax, r: JammingOnsetResult) -> None:
    """phi_J against N (log axis) with the accepted forms of the shift and phi_inf."""
    pts = points_frame(r)
    ok = np.isfinite(pts.phi_j) & np.isfinite(pts.phi_j_err)
    ax.errorbar(pts.n[ok], pts.phi_j[ok], yerr=pts.phi_j_err[ok], marker="o", capsize=2,
                ls="none", color="black", label=T.label("phi_j"))  # fmt: skip
    if r.shift is not None and ok.any():
        ns = np.geomspace(pts.n[ok].min(), pts.n[ok].max(), 60)
        for f in r.shift.accepted:
            ax.plot(ns, f.phi_inf.value + f.amplitude.value * ns ** (-f.exponent), "--", lw=1,
                    label=T.label("fit", b=f.exponent))  # fmt: skip
        if np.isfinite(r.shift.phi_inf):
            ax.axhspan(r.shift.phi_inf - r.shift.spread, r.shift.phi_inf + r.shift.spread,
                       color="grey", alpha=0.15, lw=0, label=T.label("phi_inf"))  # fmt: skip
    ax.axhline(PHI_J_REFERENCE.value, color="grey", ls=":", lw=0.8, label=T.label("reference"))
    ax.set_xscale("log")
    ax.set_xticks(list(pts.n), [f"{v:g}" for v in pts.n])
    ax.xaxis.set_minor_locator(NullLocator())
    ax.set(xlabel=T.label("n"), ylabel=T.label("phi_j"))
    legend_below(ax, ncol=2)


def figures(r: JammingOnsetResult, figdir) -> dict:
    """``jamming``: P(collectively jammed) against phi per size, the strictly jammed among
    them, and phi_J(N) with the shift; ``packing``: the drawn packing with its contact forces
    (line widths) and rattlers (hollow)."""
    out = {}
    fig, axes = grid(3, cols=3, size=(3.8, 3.0))
    if len(r.table):
        plot_jamming_probability(r.table, axes=axes[:2])
    _shift_panel(axes[2], r)
    out["jamming"] = save(fig, figdir, "jamming")
    if r.drawn is not None:
        fig, ax = grid(1, cols=1, size=(COLUMN * 1.4, COLUMN * 1.4))
        plot_packing(r.drawn.packing.packing, r.drawn.network, r.drawn.result, ax=ax[0])
        out["packing"] = save(fig, figdir, "packing")
    return out


def report_tables(r: JammingOnsetResult) -> dict:
    """Per size: samples, undecided, phi_J, width, strictly jammed among the jammed."""
    pts = points_frame(r).set_index("n")
    by = r.by_size.set_index("n")
    table = pd.DataFrame({
        "n": list(by.index),
        "samples": [int(by.samples[n]) for n in by.index],
        "undecided": [f"{int(by.undecided[n])} / {int(by.strict_undecided[n])}"
                      for n in by.index],
        "phi_j": [fmt(pts.phi_j.get(n), pts.phi_j_err.get(n)) for n in by.index],
        "width": [fmt(pts.width.get(n), pts.width_err.get(n)) for n in by.index],
        "strict": [f"{int(by.strict[n])} / {int(by.strict_tested[n])}" for n in by.index],
    })  # fmt: skip
    return {"by_size": table, "shift": shift_frame(r).round(6)}


def cost(scale: Scale, costs) -> float:
    """The analysis (a bootstrap of logistic fits per size) and the drawn packing, minimised
    and tested again."""
    p = scale[NAME]
    drawn = sample_seconds(p.drawn[0], DIM) if p.drawn[0] else 0.0
    return costs.analysis(NAME) * len(p.sizes) * scale.bootstrap / 100 + drawn


STUDY = Study(
    name=NAME, params=PARAMS, default=Params(), sweeps=sweeps, analyse=analyse,
    claims=lambda r: (), cost=cost, numbers=numbers, figures=figures,
    report_tables=report_tables,
    tables=lambda r: {"jamming_table": r.table, "jamming_points": points_frame(r),
                      "jamming_shift": shift_frame(r), "jamming_by_size": r.by_size},
)  # fmt: skip
