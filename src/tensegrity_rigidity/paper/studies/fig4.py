"""Fig. 4: P versus f_c at (p_r, p_t) = (0.3, 0.6), and the efficacies of cables and struts.

The efficacies are derivatives of P, and their ratios exist only where P varies: on each
system's own transition. Per-sample thresholds on the lines p_r + p_t = T (one-sided elements
turn into rods as p_r grows, so every sample becomes rigid on them) for T = 0.85, 0.9, 0.95,
the middle line through the paper's point, give per (f_c, strain) the median threshold m(T):
the P = 1/2 contour passes through (m, T - m). Along it S_r dp_r + S_t dp_t = 0, so S_t/S_r =
-m'(T) / (1 - m'(T)) (central difference in T); at fixed T, dP/df_c / S_r = -(1 - S_t/S_r)
dm/df_c (a polynomial in f_c, differentiated). S_c = S_t + (1 - f_c) dP/df_c / p_t and S_s =
S_t - f_c dP/df_c / p_t (from S_t = f_c S_c + (1 - f_c) S_s and dP/df_c = p_t (S_c - S_s)),
relative to S_r per strain and then averaged over five strains. Errors: bootstrap over samples.

At the paper's point itself, the binomial-likelihood surface smooth in f_c, fitted to the
outcomes at (0.3, 0.6) and at steps matched in x = p_r + p_t/2 (h_r = 0.025, h_t = 0.05), gives
the same ratios where P varies there (the claim's factor "point").
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

from ...analysis import estimators as an
from ..claims import Measurement
from ..study import Result, Scale, Study
from ..style import COLUMN, STRAIN_COLOURS, WORDS, counts, errorbar, save, unresolved
from ..template import load
from .rows import PHI5, Rows

NAME = "fig4"
T = load(NAME)
FIG4_PHI = PHI5
FIG4_FC = [i / 8 for i in range(9)]
FIG4_CENTRE = (0.3, 0.6)
#: steps around the centre, matched in x = p_r + p_t / 2 (both move x by +-0.025): near the
#: edge of the transition P is strongly curved and unmatched secants would bias S_t / S_r
H_R, H_T = 0.025, 0.05
#: polynomial degrees in f_c of the efficacy surface (logit at the centre; its slopes)
FIG4_DEGREES = (4, 2)
#: the totals p_r + p_t of the threshold paths; the middle one passes through the paper's point
#: and the contour is read there, the outer two give its slope in T (a central difference)
TOTALS = (0.85, 0.9, 0.95)
#: the cable fractions on the threshold paths (a threshold costs tens of grid points: every
#: other f_c of Fig. 4A, so that the paper scale keeps its budget)
TRANSITION_FC = FIG4_FC[::2]
#: polynomial degree in f_c of the median threshold on the middle path (differentiated): one
#: below interpolation, so that one degree of freedom smooths the medians
TRANSITION_DEGREE = len(TRANSITION_FC) - 2
#: the ratios of the efficacies on the transition, per strain and averaged
RATIOS = ("S_c_rel", "S_s_rel", "sum_rel")


@dataclass(frozen=True, kw_only=True)
class Params:
    n: int = 32  # lattice size
    samples: int = 0  # samples per point
    transition: int = 0  # samples on the threshold paths (their first; 0: ``samples``)

    @property
    def transition_samples(self) -> int:
        return self.transition or self.samples


PARAMS = {"tiny": Params(n=5, samples=6), "quick": Params(n=12, samples=96, transition=16),
          "paper": Params(n=32, samples=8)}  # fmt: skip


@dataclass(frozen=True, eq=False)
class Fig4Result(Result):
    """``average``, ``dilation``, ``compression``: per f_c on each system's transition the
    contour point (p_r, p_t), S_t/S_r (``lam``), S_c/S_r, S_s/S_r and (S_c + S_s)/S_r
    (``sum_rel``) with errors (the average: of the five strains' ratios); ``sum_cov``: (F, F)
    bootstrap covariance of the average's ``sum_rel`` over f_c; ``per_phi``: per (phi, f_c)
    at the paper's point the measured P, N, its Wilson interval (lo, hi) and the fitted S_r,
    S_t, D_f = dP/df_c, S_c, S_s with errors; ``point``: the strain average there (S_r and the
    ratios), ``curves`` with covariances over f_c; ``differences``: the average there from
    paired central differences (with the strain-averaged ``S_r``: the ratio is NaN where it
    is 0); ``slopes``: strain -> least-squares slope of P over f_c at
    the paper's point."""

    average: pd.DataFrame
    dilation: pd.DataFrame
    compression: pd.DataFrame
    sum_cov: np.ndarray
    per_phi: pd.DataFrame
    point: pd.DataFrame
    curves: an.EfficacyCurves
    differences: pd.DataFrame
    slopes: dict[str, an.Estimate]
    n: int
    samples: int
    transition_samples: int = 0


def _ratio_frame(c: an.EfficacyCurves) -> pd.DataFrame:
    cols = {"f_c": c.f_c, "S_r": c.values["S_r"], "S_r_err": c.err("S_r")}
    for name in ("S_c_rel", "S_s_rel", "sum_rel"):
        cols[name], cols[f"{name}_err"] = c.values[name], c.err(name)
    return pd.DataFrame(cols)


def sweeps(scale: Scale) -> dict[str, dict]:
    """The thresholds on the paths p_r + p_t = T (:data:`TOTALS`), the centre and the steps in
    p_r and in p_t around it, on the same samples (seed 41)."""
    (p_r0, p_t0), p = FIG4_CENTRE, scale[NAME]
    base = {"n": p.n, "f_c": FIG4_FC, "phi": FIG4_PHI, "samples": p.samples, "seed": 41}
    return {
        "fig4_total": base
        | {
            "p_t": list(TOTALS),
            "threshold": {"path": "total"},
            "f_c": TRANSITION_FC,
            "samples": p.transition_samples,
        },
        "fig4_centre": base | {"p_r": p_r0, "p_t": p_t0},
        "fig4_dpr": base | {"p_r": [p_r0 - H_R, p_r0 + H_R], "p_t": p_t0},
        "fig4_dpt": base | {"p_r": p_r0, "p_t": [p_t0 - H_T, p_t0 + H_T]},
    }


def median_thresholds(rows: pd.DataFrame, samples: np.ndarray) -> np.ndarray:
    """(K, 3, S, F) thresholds in p_r per strain, total T, sample and f_c (:data:`TRANSITION_FC`).

    Inf where a sample never became rigid on its path (censored above: it raises the median),
    NaN where its row is missing (an excluded sample, left out of the median).
    """
    out = np.full((len(FIG4_PHI), len(TOTALS), samples.size, len(TRANSITION_FC)), np.nan)
    for (k, phi), (i, total), (j, f_c) in itertools.product(
        enumerate(FIG4_PHI), enumerate(TOTALS), enumerate(TRANSITION_FC)
    ):
        m = np.isclose(rows.phi, phi) & np.isclose(rows.p_t, total) & np.isclose(rows.f_c, f_c)
        t = rows[m].set_index("sample").threshold_p_r.astype(float)
        t = t.fillna(np.inf).reindex(samples)
        out[k, i, :, j] = t.to_numpy()
    return out


def transition_ratios(thresholds: np.ndarray) -> np.ndarray:
    """(K, 6, F) per strain: p_r, p_t of the contour point, S_t/S_r and S_c/S_r, S_s/S_r,
    (S_c + S_s)/S_r on each system's transition (the module docstring's estimator).

    Parameters
    ----------
    thresholds : (K, 3, S, F) float
        :func:`median_thresholds` of the samples in use (a bootstrap replica's rows).
    """
    with np.errstate(invalid="ignore"):
        m = np.nanmedian(thresholds, axis=2)  # (K, 3, F)
    f = np.asarray(TRANSITION_FC)
    h = (TOTALS[2] - TOTALS[0]) / 2
    dm = m[:, 2] - m[:, 0]  # (K, F): m'(T) 2h
    lam = -dm / (2 * h - dm)
    mid = m[:, 1]
    p_t = TOTALS[1] - mid
    out = np.full((len(FIG4_PHI), 6, f.size), np.nan)
    for k in range(len(FIG4_PHI)):
        if not np.all(np.isfinite(mid[k])):
            continue
        slope = np.polyval(np.polyder(np.polyfit(f, mid[k], TRANSITION_DEGREE)), f)
        d_rel = -(1 - lam[k]) * slope / p_t[k]  # dP/df_c / (S_r p_t)
        s_c, s_s = lam[k] + (1 - f) * d_rel, lam[k] - f * d_rel
        out[k] = [mid[k], p_t[k], lam[k], s_c, s_s, s_c + s_s]
    return out


def _transition_frame(values: np.ndarray, boots: np.ndarray) -> pd.DataFrame:
    """Per f_c the contour point, S_t/S_r and the ratios, with bootstrap errors."""
    err = np.nanstd(boots, axis=0, ddof=1) if len(boots) > 1 else np.full(values.shape, np.nan)
    cols = {"f_c": np.asarray(TRANSITION_FC)}
    for i, name in enumerate(("p_r", "p_t", "lam", *RATIOS)):
        cols[name], cols[f"{name}_err"] = values[i], err[i]
    return pd.DataFrame(cols)


def outcomes(df: pd.DataFrame, samples: np.ndarray, **sel) -> np.ndarray:
    """Rigidity per sample index (NaN where the sample was undecided and dropped)."""
    m = np.ones(len(df), bool)
    for key, val in sel.items():
        m &= np.isclose(df[key], val)
    return df[m].set_index("sample").rigid.astype(float).reindex(samples).to_numpy()


def _per_phi(per_strain, centre, samples) -> pd.DataFrame:
    table = []
    for phi, c in zip(FIG4_PHI, per_strain, strict=True):
        for i, f in enumerate(FIG4_FC):
            P = outcomes(centre, samples, phi=phi, f_c=f)
            P = P[np.isfinite(P)]
            row = {"phi": phi, "f_c": f, "P": P.mean(), "N": P.size}
            for name in ("S_r", "S_t", "D_f", "S_c", "S_s"):
                row[name], row[f"{name}_err"] = c.values[name][i], c.err(name)[i]
            table.append(row)
    out = pd.DataFrame(table)
    _, out["lo"], out["hi"] = an.wilson(out.P * out.N, out.N)
    return out


def analyse(rows: Rows, scale: Scale) -> Fig4Result:
    """The sweeps on the same samples, each at f_c = 0, 1/8, ..., 1 and five strains: the
    efficacies on each system's transition from the thresholds (:func:`transition_ratios`,
    a bootstrap over samples); at the paper's point the surface
    (:func:`~tensegrity_rigidity.analysis.fits.fit_efficacies`) fitted to all 45 points of each
    strain at once."""
    (p_r0, p_t0), p = FIG4_CENTRE, scale[NAME]
    centre, d_r, d_t = (rows[k][0] for k in ("fig4_centre", "fig4_dpr", "fig4_dpt"))
    samples = np.arange(1, p.samples + 1)
    on_paths = np.arange(1, p.transition_samples + 1)
    thresholds = median_thresholds(rows["fig4_total"][0], on_paths)
    best = transition_ratios(thresholds)  # (K, 6, F)
    boots = np.array(an.replicas(lambda idx: transition_ratios(thresholds[:, :, idx]),
                                 on_paths.size, scale.bootstrap,
                                 scale.rng("transition")))  # fmt: skip
    mean_boots = boots.mean(axis=1)  # the strain average: of the five strains' ratios
    average = best.mean(axis=0)
    sums = mean_boots[:, -1][np.all(np.isfinite(mean_boots[:, -1]), axis=1)]
    sum_cov = (np.atleast_2d(np.cov(sums.T, ddof=1)) if len(sums) > 1
               else np.full((len(TRANSITION_FC),) * 2, np.nan))  # fmt: skip
    design = [(centre, p_r0, p_t0)]
    design += [(d_r, p_r0 + s * H_R, p_t0) for s in (-1, 1)]
    design += [(d_t, p_r0, p_t0 + s * H_T) for s in (-1, 1)]
    pr = np.array([a for _, a, _ in design for _ in FIG4_FC])
    pt = np.array([b for _, _, b in design for _ in FIG4_FC])
    y = np.array([np.column_stack([outcomes(df, samples, phi=phi, f_c=f, p_r=a, p_t=b)
                                   for df, a, b in design for f in FIG4_FC])
                  for phi in FIG4_PHI])  # fmt: skip
    per_strain, average_point = an.fit_efficacies(
        y, pr, pt, np.array(FIG4_FC * len(design)), FIG4_CENTRE, np.array(FIG4_FC), FIG4_DEGREES,
        n_boot=scale.bootstrap, rng=scale.rng("efficacies"),
    )  # fmt: skip
    slopes = {
        name: an.paired_slope(np.column_stack([outcomes(centre, samples, phi=phi, f_c=f)
                                               for f in FIG4_FC]), np.asarray(FIG4_FC))
        for name, phi in (("dilation", 0.0), ("compression", math.pi))
    }  # fmt: skip
    return Fig4Result(
        average=_transition_frame(average, mean_boots),
        dilation=_transition_frame(best[0], boots[:, 0]),
        compression=_transition_frame(best[-1], boots[:, -1]), sum_cov=sum_cov,
        per_phi=_per_phi(per_strain, centre, samples), point=_ratio_frame(average_point),
        curves=average_point, differences=_differences(centre, d_r, d_t, samples), slopes=slopes,
        n=p.n, samples=p.samples, transition_samples=p.transition_samples,
        excluded={name: count for name, (_, count) in rows.items()},
    )  # fmt: skip


def claims(r: Fig4Result) -> tuple[Measurement, ...]:
    """Fig. 4A's signs (slopes of P over f_c at the paper's point) and Fig. 4C's sum
    (S_c + S_s)/S_r = 1 on each system's transition (the fitted surface at the paper's point
    as the evidence of the factor "point")."""
    system = T.label("system", n=r.n, samples=r.samples)
    out = [Measurement.scalar(key, r.slopes[name].value, r.slopes[name].err, system,
                              note=T.label("note.slope"))
           for key, name in (("fig4a_dilation_rises", "dilation"),
                             ("fig4a_compression_falls", "compression"))]  # fmt: skip

    def points(fs):
        return tuple(f"f_c = {f:.3f}" for f in fs)

    on_paths = T.label("system", n=r.n, samples=r.transition_samples)
    return (*out,
            Measurement("fig4c_sum_one", r.average.sum_rel.to_numpy(float), r.sum_cov, on_paths,
                        points=points(TRANSITION_FC), note=T.label("note.sum")),
            Measurement("fig4c_sum_one", r.curves.values["sum_rel"], r.curves.cov["sum_rel"],
                        system, factor="point", label=T.label("point"),
                        points=points(FIG4_FC)))  # fmt: skip


def _derivative(a: np.ndarray, b: np.ndarray, h: float) -> tuple[float, float]:
    e = an.paired_derivative(a, b, h)
    return e.value, e.err


def _differences(centre, d_r, d_t, samples) -> pd.DataFrame:
    """The strain average of (S_c + S_s)/S_r from paired central differences: S_r, S_t over the
    steps H_R, H_T; dP/df_c central inside, second-order one-sided at f_c = 0 and 1; errors from
    the per-sample differences, taken as independent across strains and f_c."""
    (p_r0, p_t0), last = FIG4_CENTRE, len(FIG4_FC) - 1
    rows = []
    for i, f in enumerate(FIG4_FC):
        if 0 < i < last:
            coef, step = {i - 1: -1.0, i + 1: 1.0}, FIG4_FC[i + 1] - FIG4_FC[i - 1]
        else:
            j, sign = ((1, 2), 1.0) if i == 0 else ((last - 1, last - 2), -1.0)
            coef = {i: -3.0 * sign, j[0]: 4.0 * sign, j[1]: -1.0 * sign}
            step = 2 * abs(FIG4_FC[j[0]] - FIG4_FC[i])
        parts = []
        for phi in FIG4_PHI:

            def at(df, phi=phi, **sel):
                return outcomes(df, samples, phi=phi, **sel)

            S_r = _derivative(at(d_r, f_c=f, p_r=p_r0 - H_R), at(d_r, f_c=f, p_r=p_r0 + H_R), H_R)
            S_t = _derivative(at(d_t, f_c=f, p_t=p_t0 - H_T), at(d_t, f_c=f, p_t=p_t0 + H_T), H_T)
            diff = sum(c * at(centre, f_c=FIG4_FC[k]) for k, c in coef.items())
            diff = diff[np.isfinite(diff)]
            parts.append((*S_r, *S_t, diff.mean() / step,
                          diff.std(ddof=1) / np.sqrt(diff.size) / step))  # fmt: skip
        a, k = np.array(parts), len(parts)
        S_r, S_t, D = a[:, 0].mean(), a[:, 2].mean(), a[:, 4].mean()
        S_r_e, S_t_e, D_e = (np.sqrt((a[:, c] ** 2).sum()) / k for c in (1, 3, 5))
        total = 2 * S_t + (1 - 2 * f) * D / p_t0
        total_e = np.hypot(2 * S_t_e, abs(1 - 2 * f) * D_e / p_t0)
        ratio, err = np.nan, np.nan
        if S_r != 0:
            ratio = total / S_r
            err = np.hypot(total_e / S_r, ratio * S_r_e / S_r)
        rows.append({"f_c": f, "sum_rel": ratio, "sum_rel_err": abs(err), "S_r": S_r})
    return pd.DataFrame(rows)


def numbers(r: Fig4Result) -> dict:
    s = r.average
    return {"n": r.n, "samples": r.samples, "transition_samples": r.transition_samples,
            "rises": r.slopes["dilation"].value,
            "rises_err": r.slopes["dilation"].err, "falls": r.slopes["compression"].value,
            "falls_err": r.slopes["compression"].err, "points": len(s),
            "unresolved": int(np.sum(~(s.sum_rel_err <= np.abs(s.sum_rel)))),
            "point_unresolved": int(np.sum(~(r.point.sum_rel_err <= np.abs(r.point.sum_rel)))),
            "point_values": len(r.point),
            "differences_missing": int((r.differences.S_r == 0).sum()) or None,
            "p_r_low": min(float(f.p_r.min()) for f in (r.dilation, r.compression)),
            "p_r_high": max(float(f.p_r.max()) for f in (r.dilation, r.compression))}  # fmt: skip


def figures(r: Fig4Result, figdir) -> dict:
    out = {}
    fig, ax = plt.subplots(figsize=(COLUMN, 2.6))
    cmap = plt.get_cmap("cividis")
    for phi, s in r.per_phi.groupby("phi"):
        err = [np.clip(s.P - s.lo, 0, None), np.clip(s.hi - s.P, 0, None)]
        ax.errorbar(s.f_c, s.P, yerr=err, marker="o", ms=3, color=cmap(phi / math.pi),
                    label=T.label("phi", phi=phi / math.pi))  # fmt: skip
    counts(ax, *r.per_phi.groupby("f_c").N.min().reset_index().to_numpy().T)
    ax.set(xlabel=WORDS.label("f_c"), ylabel=T.label("P"), title=T.label("title.4a", n=r.n))
    ax.legend(ncol=2)
    out["4A"] = save(fig, figdir, "4A")
    fig, ax = plt.subplots(figsize=(COLUMN, 2.6))
    a = r.average
    errorbar(ax, a.f_c, a.S_c_rel, a.S_c_rel_err, label=T.label("S_c"))
    errorbar(ax, a.f_c, a.S_s_rel, a.S_s_rel_err, marker="s", label=T.label("S_s"))
    ax.axhline(0.5, color="grey", ls=":", lw=1)
    unresolved(ax)
    ax.set(xlabel=WORDS.label("f_c"), ylabel=T.label("relative"), title=T.label("title.4b"))
    ax.legend()
    out["4B"] = save(fig, figdir, "4B")
    fig, ax = plt.subplots(figsize=(COLUMN, 2.6))
    for name in ("average", "dilation", "compression"):
        s = getattr(r, name)
        errorbar(ax, s.f_c, s.sum_rel, s.sum_rel_err, color=STRAIN_COLOURS[name], label=name)
    ax.axhline(1.0, color="grey", ls=":", lw=1)
    unresolved(ax)
    ax.set(xlabel=WORDS.label("f_c"), ylabel=T.label("sum"), title=T.label("title.4c"))
    ax.legend()
    out["4C"] = save(fig, figdir, "4C")
    return out


def cost(scale: Scale, costs) -> float:
    return costs.analysis(NAME) * scale.bootstrap / 100


STUDY = Study(
    name=NAME, params=PARAMS, default=Params(), sweeps=sweeps, analyse=analyse, claims=claims,
    cost=cost, numbers=numbers, figures=figures,
    errors=lambda scale: [("fig4c_sum_one", NAME, "fig4c", scale[NAME].n,
                           scale[NAME].transition_samples)],
    tables=lambda r: {"fig4_average": r.average, "fig4_dilation": r.dilation,
                      "fig4_compression": r.compression, "fig4_point": r.point,
                      "fig4_per_strain": r.per_phi, "fig4_differences": r.differences},
)  # fmt: skip
