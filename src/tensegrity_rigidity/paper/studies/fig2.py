"""Fig. 2: rods + cables (f_c = 1), energies, nonaffinity and engaged cables versus p_r.

p_crit is the median per-sample threshold (P = 1/2) with a bootstrap error; alpha is the
least-squares slope of ln(mean E) over ln(p_r - p_crit), its error a bootstrap over samples
that re-estimates p_crit in each replica (:mod:`.energy`); the paper's own estimators (p_crit
where the mean energy first becomes positive) are kept as evidence. The nonaffinity's peaks and
tails are in :mod:`.nonaffinity`; Fig. 1A's and 2A's drawn samples in :mod:`.field`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from matplotlib.collections import LineCollection
from matplotlib.colors import LogNorm
from matplotlib.ticker import NullFormatter

from ...analysis import estimators as an
from ...model.network import Element
from ..claims import CLAIMS, Measurement
from ..plotting import KIND_COLOURS, bond_segments, draw_network, window
from ..study import Result, Scale, Study
from ..style import (
    COLUMN,
    PAGE,
    PAPER_MARKER,
    WORDS,
    counts,
    legend_below,
    paper_legend,
    placeholder,
    save,
)
from ..template import load
from .energy import energy_exponent, taut_with_error
from .field import FIELD_P_T, FIELD_SAMPLES, DisplacementField, displacement_field
from .nonaffinity import (
    at_transition,
    gamma_median_brackets,
    gamma_peaks,
    mask_min_norm,
    mask_uncertified_tensions,
    q25,
    q75,
    tail_statistics,
    worst_tail,
)
from .rows import PT4, Rows, interval_straddles, p_r_grid, per_sample, strain_name

NAME = "fig2"
T = load(NAME)
#: the grid sweeps (one per p_t of PT4), whose rows feed the energy analyses
ENERGY_SWEEPS = tuple(f"fig2_pt{p_t:.1f}" for p_t in PT4)
KEYS = ["phi", "p_t", "p_r"]


@dataclass(frozen=True, kw_only=True)
class Params:
    n: int = 32  # lattice size
    samples: int = 0  # grid samples per point
    thresholds: int = 0  # threshold samples per (strain, p_t)
    step: float = 0.025  # p_r grid step


PARAMS = {
    "tiny": Params(n=5, samples=4, thresholds=6, step=0.1),
    "quick": Params(n=12, samples=24, thresholds=48, step=0.05),
    "paper": Params(n=32, samples=24, thresholds=24, step=0.025),
}


@dataclass(frozen=True, eq=False)
class Fig2Result(Result):
    """Rods + cables (f_c = 1) versus p_r.

    ``curves``: per (phi, p_t, p_r) energy and nonaffinity (mean, sem, median, quartiles;
    ``gamma_n`` samples with a nonaffinity, P, N) and the median nonaffinity over all N samples
    bracketed (``gamma_median_low``, ``gamma_median_high``, ``gamma_bounded``). ``taut``: per
    point the fraction of taut cables of rigid samples. ``fits``: per (phi, p_t) the power law
    of the mean energy above p_crit (:func:`energy_exponent`) and ``p_crit_err``. ``crit``:
    ``p_crit`` and where the mean nonaffinity peaks. ``paper_estimators``: the paper's p_crit
    (first positive mean energy) and alpha from it. ``peaks``: the peaks under compression
    (:func:`gamma_peaks`); ``at_pcrit``, ``tails``, ``worst_tail``: the samples at the grid p_r
    nearest p_crit and what a mean over them hangs on. ``min_norm_failed``,
    ``tensions_uncertified``: samples whose Gamma or taut fraction is left out (None when the
    rows do not record it). ``taut_at_transition``: (mean, error, [(p_t, p_r), ...]) or None.
    """

    curves: pd.DataFrame
    taut: pd.DataFrame
    fits: pd.DataFrame
    crit: pd.DataFrame
    paper_estimators: pd.DataFrame
    peaks: dict
    at_pcrit: pd.DataFrame
    tails: pd.DataFrame
    worst_tail: dict | None
    min_norm_failed: int | None
    tensions_uncertified: int | None
    taut_at_transition: tuple | None
    n: int
    samples: int
    rows: pd.DataFrame
    field: DisplacementField
    samples_threshold: int = 0


def sweeps(scale: Scale) -> dict[str, dict]:
    """A grid per p_t, the thresholds on the same samples (seed 21) and the two small sweeps
    that supply the drawn samples of Figs. 2A and 1A."""
    p = scale[NAME]
    grid = p_r_grid(p.step, 0.3, 0.95)
    base = {"n": p.n, "f_c": 1.0, "phi": ["compression", "dilation"], "seed": 21}
    out = {
        f"fig2_pt{p_t:.1f}": base
        | {"p_r": [x for x in grid if x + p_t <= 1 + 1e-12], "p_t": p_t, "samples": p.samples}
        for p_t in PT4
    }
    out["fig2_thresholds"] = base | {"p_t": PT4, "samples": p.thresholds,
                                     "threshold": {"path": "p_r"}}  # fmt: skip
    field = {"n": max(p.n, 8), "samples": FIELD_SAMPLES, "f_c": 1.0, "seed": 1000}
    out["fig2_field"] = field | {"p_t": FIELD_P_T, "phi": "compression",
                                 "threshold": {"path": "p_r"}}  # fmt: skip
    out["fig1a_field"] = field | {"p_r": 0.55, "p_t": 0.4, "f_c": 0.5, "phi": "shear",
                                  "seed": 2000}  # fmt: skip
    return out


def _curves(rows: pd.DataFrame, energy_rows: pd.DataFrame) -> pd.DataFrame:
    """Per (phi, p_t, p_r): the energies over every row kept, the rest over decided rows."""
    e = energy_rows.groupby(KEYS).agg(
        energy=("energy", "mean"), energy_sem=("energy", "sem"),
        energy_median=("energy", "median"), energy_q25=("energy", q25),
        energy_q75=("energy", q75), energy_n=("energy", "size"),
    )  # fmt: skip
    g = rows.groupby(KEYS).agg(
        gamma=("nonaffinity", "mean"), gamma_sem=("nonaffinity", "sem"),
        gamma_median=("nonaffinity", "median"), gamma_q25=("nonaffinity", q25),
        gamma_q75=("nonaffinity", q75), gamma_n=("nonaffinity", "count"),
        P=("rigid", "mean"), N=("rigid", "size"),
    )  # fmt: skip
    out = e.reset_index().merge(g.reset_index(), on=KEYS, how="left")
    return out.merge(gamma_median_brackets(rows), on=KEYS, how="left")


def _per_curve(curves, th, energy_rows, rows, scale: Scale):
    """Per (phi, p_t): p_crit, alpha, where Gamma peaks, and the paper's estimators."""
    fits, crit, paper = [], [], []
    for (phi, p_t), sub in curves.groupby(["phi", "p_t"]):
        one = np.isclose(th.phi, phi) & np.isclose(th.p_t, p_t)
        grid = energy_rows[np.isclose(energy_rows.phi, phi) & np.isclose(energy_rows.p_t, p_t)]
        pc, pc_err = an.critical_point(th[one].threshold_p_r.to_numpy(),
                                       rng=scale.rng("critical_point"))  # fmt: skip
        fit = energy_exponent(grid, th[one], scale.bootstrap, rng=scale.rng("energy_exponent"))
        key = {"phi": phi, "strain": strain_name(phi), "p_t": p_t}
        fits.append(key | {"p_crit_err": pc_err, **fit.__dict__})
        g = sub.set_index("p_r").gamma
        crit.append({"phi": phi, "p_t": p_t, "p_crit": pc, "gamma_peak_p_r": float(g.idxmax())})
        # the paper's estimators on the decided rows: p_crit where the mean energy first becomes
        # positive, and the power law from it (a bracketed energy could make a mean positive)
        e, x = per_sample(rows[np.isclose(rows.phi, phi) & np.isclose(rows.p_t, p_t)], "energy")
        first = an.first_positive(e, x, n_boot=scale.bootstrap, rng=scale.rng("first_positive"))
        pfit = an.fit_energy_exponent(
            x, e, lambda idx, e=e, x=x: an.first_positive(e[idx], x, n_boot=0).value,
            n_boot=scale.bootstrap, rng=scale.rng("energy_exponent"),
        )  # fmt: skip
        paper.append(key | {"p_crit": first.value, "p_crit_err": first.err, "alpha": pfit.alpha,
                            "alpha_err": pfit.alpha_err, "n_points": pfit.n_points})  # fmt: skip
    return pd.DataFrame(fits), pd.DataFrame(crit), pd.DataFrame(paper)


def analyse(sweep_rows: Rows, scale: Scale) -> Fig2Result:
    """Rods + cables (f_c = 1) versus p_r from the rows of :func:`sweeps` (the grids read with
    ``energy``: they keep undecided rows whose energy is bracketed); a grid of a p_t missing
    from them is left out, and without the field sweeps the drawn samples are None."""
    p = scale[NAME]
    grids, excluded, bracketed = [], {}, {}
    for name in ENERGY_SWEEPS:
        if name in sweep_rows:
            g, excluded[name] = sweep_rows[name]
            bracketed[name] = int((~g.decided.astype(bool)).sum())
            grids.append(g)
    energy_rows = pd.concat(grids, ignore_index=True)
    rows = energy_rows[energy_rows.decided.astype(bool)].reset_index(drop=True)
    rows, min_norm_failed = mask_min_norm(rows)
    rows, tensions_uncertified = mask_uncertified_tensions(rows)
    th, excluded["fig2_thresholds"] = sweep_rows["fig2_thresholds"]
    curves = _curves(rows, energy_rows)
    rigid = rows[rows.rigid].groupby(KEYS).frac_cables_taut
    fits, crit, paper = _per_curve(curves, th, energy_rows, rows, scale)
    at_pcrit = at_transition(rows, crit)
    tails = tail_statistics(at_pcrit)
    field = DisplacementField(None, None, float("nan"), FIELD_P_T, None, None)
    if {"fig2_field", "fig1a_field"} <= set(sweep_rows):
        field, excluded["fig2_field"], excluded["fig1a_field"] = displacement_field(
            sweep_rows, sweeps(scale)
        )
    return Fig2Result(
        curves=curves, taut=rigid.agg(["mean", "sem", "size"]).reset_index(), fits=fits,
        crit=crit, paper_estimators=paper,
        peaks=gamma_peaks(rows, crit, scale.bootstrap, rng=scale.rng("peaks")),
        at_pcrit=at_pcrit, tails=tails, worst_tail=worst_tail(tails),
        min_norm_failed=min_norm_failed, tensions_uncertified=tensions_uncertified,
        taut_at_transition=taut_with_error(rows, th, scale.bootstrap, rng=scale.rng("taut")),
        n=p.n, samples=p.samples, rows=rows, field=field, excluded=excluded,
        bracketed=bracketed, straddling=interval_straddles(th, p_r_grid(p.step, 0.3, 0.95)),
        samples_threshold=p.thresholds,
    )  # fmt: skip


def claims(r: Fig2Result) -> tuple[Measurement, ...]:
    """p_crit and alpha per strain and p_t (ours, and the paper's estimators as evidence), the
    taut-cable fraction at the transition and where the nonaffinity peaks."""
    v = {"n": r.n, "samples": r.samples, "thresholds": r.samples_threshold}
    system, out = T.label("system", **v), []
    S = Measurement.scalar
    for row in r.fits.itertuples():
        alt = r.paper_estimators
        alt = alt[np.isclose(alt.phi, row.phi) & np.isclose(alt.p_t, row.p_t)].iloc[0]
        pc, alpha = f"p_crit_{row.strain}_{row.p_t}", f"alpha_{row.strain}_{row.p_t}"
        fit, paper = (
            T.label("fit", system=system, points=row.n_points),
            T.label("fit", system=system, points=alt.n_points),
        )
        out += [
            S(pc, row.p_crit, row.p_crit_err, T.label("pc_system", **v), note=T.label("note.pc"),
              size=r.n),
            S(pc, alt.p_crit, alt.p_crit_err, system, factor="estimator",
              label=T.label("paper_pc"), size=r.n),
            S(alpha, row.alpha, row.alpha_err, fit, note=T.label("note.alpha"), size=r.n),
            S(alpha, alt.alpha, alt.alpha_err, paper, factor="estimator",
              label=T.label("paper_alpha"), size=r.n),
        ]  # fmt: skip
    if r.taut_at_transition is not None:
        value, err, _ = r.taut_at_transition
        out.append(S("taut_cables_transition", value, err, system, note=T.label("note.taut"),
                     size=r.n))  # fmt: skip
    peaks, comp = r.peaks, r.fits[np.isclose(r.fits.phi, math.pi)].sort_values("p_t")
    points = tuple(f"p_t = {p:.1f}" for p in peaks["p_t"])
    var = np.diag(comp.p_crit_err.to_numpy() ** 2)
    for stat, factor, label in (("mean", "ours", ""), ("median", "estimator", "peak_median")):
        at, cov = peaks[stat]
        out.append(Measurement(
            "gamma_peak", at - peaks["p_crit"], cov + var, system, factor=factor,
            label=label and T.label(label), points=points, note=T.label("note.peak"), size=r.n,
        ))  # fmt: skip
    return tuple(out)


def _g(x) -> str:
    return f"{x:.3g}" if np.isfinite(x) else "n/a"


def numbers(r: Fig2Result) -> dict:
    """The heavy tails' section: masked samples, the bracketed medians, the worst tail."""
    c = r.curves
    k = int(c.gamma_bounded.sum()) if "gamma_bounded" in c else 0
    comp = c[np.isclose(c.phi, np.pi)]
    open_ = comp[comp.gamma_median_high > comp.gamma_median_low] if k else comp.iloc[:0]
    w = (open_.loc[(open_.gamma_median_high / open_.gamma_median_low).idxmax()]
         if len(open_) else None)  # fmt: skip
    tail = r.worst_tail or {}
    return {
        "n": r.n, "samples": r.samples, "p_t": FIELD_P_T, "p_r": r.field.p_r,
        "no_record": "" if r.min_norm_failed is None else None,
        "min_norm_failed": r.min_norm_failed, "bounded": k or None, "bracketed": "" if k else None,
        "agree": len(comp) - len(open_), "points": len(comp),
        "widest_low": None if w is None else _g(w.gamma_median_low),
        "widest_high": None if w is None else _g(w.gamma_median_high).replace("n/a", "inf"),
        "widest_p_t": None if w is None else w.p_t, "widest_p_r": None if w is None else w.p_r,
        "widest_median": None if w is None else _g(w.gamma_median),
        "uncertified": r.tensions_uncertified or None,
        **{f"tail_{key}": _g(tail[key]) if key in tail else None for key in (
            "mean", "mean_without_top", "median", "q25", "q75")},
        "tail_p_t": tail.get("p_t"), "tail_p_r": tail.get("p_r"), "tail_N": tail.get("N"),
        "tail_share": 100 * tail["top_share"] if tail else None,
    }  # fmt: skip


def report_tables(r: Fig2Result) -> dict:
    table = r.tails.copy()
    for col in ("mean", "median", "q25", "q75", "max", "mean_without_top"):
        if col in table:
            table[col] = table[col].map(_g)
    if "top_share" in table:
        table["top_share"] = table.top_share.map(lambda x: f"{100 * x:.0f} %" if x == x else "n/a")
    return {"tails": table}


def fig1a(r: Fig2Result, figdir):
    """A force-balanced rigid sample on a window of the network: rods solid, cables dashed,
    struts hollow, coloured by tension (:func:`~..plotting.draw_network`)."""
    inst, res = r.field.mixed_instance, r.field.mixed_result
    if inst is None:
        return placeholder("1A", T.label("no_1a"), figdir)
    fig, ax = plt.subplots(figsize=(COLUMN + 0.4, 3.2))
    below = {"loc": "upper center", "bbox_to_anchor": (0.5, -0.02), "ncol": 3}
    draw_network(ax, inst, res, colour="tension", arrows=False, widths=(1.0, 4.0), legend=below)
    window(ax, inst.network, 3.5)
    ax.set_axis_off()
    ax.set_title(T.label("title.1a"))
    return save(fig, figdir, "1A")


def fig2a(r: Fig2Result, figdir):
    """Nonaffine displacements on a window of the network: unit arrows coloured by |u| over a
    log-scaled background (a few nodes move 1e3 to 1e4 times more than the rest)."""
    inst, res = r.field.instance, r.field.result
    if inst is None or res is None:  # None together: no sample qualified
        return placeholder("2A", T.label("no_2a"), figdir)
    pos, u = inst.network.positions, res.displacements
    mag = np.hypot(u[:, 0], u[:, 1])
    mag_c = np.clip(mag, max(float(mag.max()) * 1e-6, 1e-300), None)
    norm = LogNorm(vmin=mag_c.min(), vmax=mag_c.max())
    fig, ax = plt.subplots(figsize=(COLUMN + 0.4, 3.0))
    ax.tripcolor(pos[:, 0], pos[:, 1], mag_c, shading="gouraud", cmap="Greys", norm=norm, alpha=0.6)
    seg, kinds = bond_segments(inst.network), inst.network.kinds
    ax.add_collection(LineCollection(seg[kinds == Element.ROD], colors="k", linewidths=0.8))
    ax.add_collection(LineCollection(seg[kinds == Element.CABLE], colors=KIND_COLOURS[
        Element.CABLE], linewidths=0.8, linestyles=(0, (3, 2))))  # fmt: skip
    unit = u / np.where(mag > 0, mag, 1.0)[:, None]
    q = ax.quiver(pos[:, 0], pos[:, 1], unit[:, 0], unit[:, 1], mag_c, cmap="viridis", norm=norm,
                  angles="xy", scale_units="xy", scale=2.2, width=0.006)  # fmt: skip
    fig.colorbar(q, ax=ax, label=T.label("colorbar.2a"))
    window(ax, inst.network, 5.0)
    ax.set_axis_off()
    ax.set_title(T.label("title.2a", p_r=r.field.p_r, p_t=r.field.p_t,
                         ratio=mag_c.max() / np.median(mag_c)))  # fmt: skip
    return save(fig, figdir, "2A")


def median_brackets(ax, s, colour, dx: float = 0.0) -> list[tuple[float, float, float]]:
    """At each p_r where samples lack a certified nonaffinity, the bracket of the median over
    all samples (``gamma_median_low`` to ``gamma_median_high``) as a vertical bar: open above
    it ends in a ``^`` above the curves, open below it starts at the lowest value drawn.
    Returns the bars drawn, (p_r + dx, low, high) in data coordinates."""
    if "gamma_median_low" not in s:
        return []
    lo, hi = s.gamma_median_low.to_numpy(float), s.gamma_median_high.to_numpy(float)
    open_ = hi > lo
    shown = np.r_[s.gamma_q25, s.gamma_q75, s.gamma, lo, hi].astype(float)
    shown = shown[np.isfinite(shown) & (shown > 0)]
    if not open_.any() or not shown.size:
        return []
    x = s.p_r.to_numpy(float)[open_] + dx
    low = np.where(lo[open_] > 0, lo[open_], shown.min())
    high = np.where(np.isfinite(hi[open_]), hi[open_], 3.0 * shown.max())
    ax.vlines(x, low, high, color=colour, lw=1.5, alpha=0.7)
    ax.plot(x, low, "_", color=colour, ms=8)
    up = ~np.isfinite(hi[open_])
    ax.plot(x[up], high[up], "^", color=colour, ms=5)
    ax.plot(x[~up], high[~up], "_", color=colour, ms=8)
    return [(float(a), float(b), float(c)) for a, b, c in zip(x, low, high, strict=True)]


def fig2b(r: Fig2Result, figdir):
    """Gamma versus p_r: median with the interquartile band, mean as open markers."""
    sub = r.curves[np.isclose(r.curves.phi, math.pi)]
    fig, ax = plt.subplots(figsize=(COLUMN, 2.8))
    grid = np.unique(sub.p_r.to_numpy(float))
    step = float(np.diff(grid).min()) if grid.size > 1 else 0.0
    curves = list(sub.groupby("p_t"))
    for i, (p_t, s) in enumerate(curves):
        (line,) = ax.plot(s.p_r, s.gamma_median, "-", label=T.label("p_t", p_t=p_t))
        colour = line.get_color()
        ax.fill_between(s.p_r, s.gamma_q25, s.gamma_q75, color=colour, alpha=0.2, lw=0)
        ax.plot(s.p_r, s.gamma, "o", mfc="none", ms=3, color=colour)
        median_brackets(ax, s, colour, dx=0.2 * step * (i - (len(curves) - 1) / 2))
        pc = r.crit[np.isclose(r.crit.phi, math.pi) & np.isclose(r.crit.p_t, p_t)].p_crit
        if len(pc):
            ax.axvline(float(pc.iloc[0]), color=colour, ls="--", lw=1)
    ax.plot([], [], "o", mfc="none", color="grey", label=T.label("mean"))
    ax.set(yscale="log", xlabel=WORDS.label("p_r"), ylabel=T.label("gamma"))
    counts(ax, *sub.groupby("p_r").N.min().reset_index().to_numpy().T)
    ax.set_title(T.label("title.2b", n=r.n))
    legend_below(ax)
    return save(fig, figdir, "2B")


def fig2e(r: Fig2Result, figdir):
    """CCDF of Gamma over samples at the grid p_r nearest p_crit (compression), per p_t."""
    fig, ax = plt.subplots(figsize=(COLUMN, 2.6))
    for p_t, sub in r.at_pcrit.groupby("p_t"):
        v = np.sort(sub.nonaffinity.to_numpy(float))
        v = v[np.isfinite(v) & (v > 0)]
        if v.size:
            ax.step(v, 1.0 - np.arange(v.size) / v.size, where="post",
                    label=T.label("at", p_t=p_t, p_r=sub.p_r.iloc[0], count=v.size))  # fmt: skip
    if ax.lines:
        ax.set(xscale="log", yscale="log")
        ax.legend()
    ax.set(xlabel=T.label("gamma"), ylabel=T.label("ccdf"), title=T.label("title.2e", n=r.n))
    return save(fig, figdir, "2E")


def _energy(r: Fig2Result, phi: float, fid: str, figdir):
    """Energy versus p_r, with the log-log of E against p_r - p_crit and its power-law fits
    in a panel beside it (not an inset: nothing hidden)."""
    strain = strain_name(phi)
    sub = r.curves[np.isclose(r.curves.phi, phi)]
    fig, (ax, right) = plt.subplots(1, 2, figsize=(PAGE, 2.6))
    for p_t, s in sub.groupby("p_t"):
        line = ax.errorbar(s.p_r, s.energy, yerr=s.energy_sem, marker="o", ms=3,
                           label=T.label("p_t", p_t=p_t))  # fmt: skip
        colour = line[0].get_color()
        paper = CLAIMS.get(f"p_crit_{strain}_{p_t}")
        if paper is not None and paper.value is not None:
            ax.errorbar([paper.value], [0], xerr=[paper.error], color=colour, clip_on=False,
                        **PAPER_MARKER)  # fmt: skip
        f = r.fits[np.isclose(r.fits.phi, phi) & np.isclose(r.fits.p_t, p_t)].iloc[0]
        m = (s.p_r > f.p_crit) & (s.energy > 0)
        right.loglog(s.p_r[m] - f.p_crit, s.energy[m], "o", ms=3, color=colour)
        if np.isfinite(f.alpha) and m.sum():
            x = np.geomspace((s.p_r[m] - f.p_crit).min(), (s.p_r[m] - f.p_crit).max(), 20)
            right.loglog(x, np.exp(f.beta) * x**f.alpha, "--", lw=1, color=colour,
                         label=T.label("alpha", p_t=p_t, alpha=f.alpha))  # fmt: skip
    paper_legend(ax)
    counts(ax, *sub.groupby("p_r").energy_n.min().reset_index().to_numpy().T)
    ax.set(xlabel=WORDS.label("p_r"), ylabel=T.label("energy"))
    ax.set_title(T.label("title.energy", strain=strain, n=r.n))
    right.set(xlabel=T.label("distance"), ylabel=T.label("energy"))
    right.xaxis.set_minor_formatter(NullFormatter())
    ax.legend()
    right.legend()
    return save(fig, figdir, fid)


def figures(r: Fig2Result, figdir) -> dict:
    return {
        "1A": fig1a(r, figdir), "2A": fig2a(r, figdir), "2B": fig2b(r, figdir),
        "2C": _energy(r, math.pi, "2C", figdir), "2D": _energy(r, 0.0, "2D", figdir),
        "2E": fig2e(r, figdir),
    }  # fmt: skip


def tables(r: Fig2Result) -> dict:
    return {
        "energy_fits": r.fits,
        "energy_fits_paper_estimators": r.paper_estimators,
        "fig2_curves": r.curves,
        "fig2_tails": r.tails,
        "fig2_at_pcrit": r.at_pcrit,
    }


def cost(scale: Scale, costs) -> float:
    """The analysis and the two drawn samples of Figs. 1A and 2A."""
    n = max(scale[NAME].n, 8)
    grid = costs.row_seconds("grid", n, 0.2)[0] + costs.row_seconds("grid", n, 0.4)[0]
    return costs.analysis(NAME) * scale.bootstrap / 100 + grid


def errors(scale: Scale) -> list[tuple]:
    p = scale[NAME]
    out = [(f"p_crit_{strain}_{p_t}", NAME, "p_crit", p.n, p.thresholds)
           for strain in ("compression", "dilation") for p_t in PT4]  # fmt: skip
    return out + [("taut_cables_transition", NAME, "taut", p.n, p.samples)]


STUDY = Study(
    name=NAME, params=PARAMS, default=Params(), sweeps=sweeps, analyse=analyse, claims=claims,
    cost=cost, numbers=numbers, figures=figures, tables=tables, report_tables=report_tables,
    errors=errors, energy=lambda specs: ENERGY_SWEEPS,
)  # fmt: skip
