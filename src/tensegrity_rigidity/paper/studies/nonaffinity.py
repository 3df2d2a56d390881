"""Fig. 2's nonaffinity and taut-fraction bookkeeping: masks, brackets, tails and peaks."""

from __future__ import annotations

import copy
import math

import numpy as np
import pandas as pd

from ...analysis import estimators as an
from ...solver.core import energy_certified
from ..study import stream
from .rows import per_sample


def gamma_median_brackets(rows: pd.DataFrame) -> pd.DataFrame:
    """Per (phi, p_t, p_r): the median nonaffinity over every sample, bracketed.

    Samples without a certified nonaffinity (NaN after :func:`mask_min_norm`) enter at their
    certified lower bound ``nonaffinity_lower`` (at 0 where the row has none) for
    ``gamma_median_low`` and at ``+inf`` for ``gamma_median_high``
    (:func:`~tensegrity_rigidity.analysis.binomial.median_bracket`); ``gamma_bounded``
    counts those known from a bound. Rows written before the bound existed have none.
    """
    lower = rows["nonaffinity_lower"] if "nonaffinity_lower" in rows else np.nan
    rows = rows.assign(_lower=lower)
    out = []
    for (phi, p_t, p_r), g in rows.groupby(["phi", "p_t", "p_r"]):
        gamma, low = g.nonaffinity.to_numpy(), g._lower.to_numpy(dtype=float)
        lo, hi = an.median_bracket(gamma, low)
        bounded = int(np.sum(np.isnan(gamma) & np.isfinite(low)))
        out.append((phi, p_t, p_r, lo, hi, bounded))
    columns = ["phi", "p_t", "p_r", "gamma_median_low", "gamma_median_high", "gamma_bounded"]
    return pd.DataFrame(out, columns=columns)


def q25(x: pd.Series) -> float:
    return float(x.quantile(0.25))


def q75(x: pd.Series) -> float:
    return float(x.quantile(0.75))


def mask_min_norm(rows: pd.DataFrame) -> tuple[pd.DataFrame, int | None]:
    """Nonaffinity NaN where the displacements are not the verified minimum-norm minimiser.

    Rows with ``min_norm_ok == False`` carry whatever minimiser the solver stopped at, whose
    Gamma can be off by orders of magnitude: their ``nonaffinity`` becomes NaN and
    they are counted. Returns (rows, count); the count is None when the rows have no
    ``min_norm_ok`` column (written before it existed), and missing values in it count as ok.
    """
    if "min_norm_ok" not in rows:
        return rows, None
    bad = rows["min_norm_ok"].eq(False).to_numpy()
    if bad.any():
        rows = rows.copy()
        rows.loc[bad, "nonaffinity"] = np.nan
    return rows, int(bad.sum())


def mask_uncertified_tensions(rows: pd.DataFrame) -> tuple[pd.DataFrame, int | None]:
    """Taut fractions NaN where the relaxed tensions are not certified to be t*.

    A rigid row's ``frac_cables_taut`` and ``frac_struts_taut`` count the elements its relaxed
    tensions engage. Where the relaxation has not converged (not
    :func:`~tensegrity_rigidity.solver.core.energy_certified`: near a sample's own threshold)
    those tensions need not be t*, and engage more elements: at the paper scale's grid p_r
    nearest p_crit (p_t = 0.1, compression) two such samples had 0.43 and 0.50 where the four
    certified ones averaged 0.31. Their fractions become NaN and they are counted. Returns
    (rows, count); the count is None when the rows have no ``energy_lower`` column.
    """
    if "energy_lower" not in rows:
        return rows, None
    certified = energy_certified(
        rows["energy"].to_numpy(dtype=float), rows["energy_lower"].to_numpy(dtype=float)
    )
    bad = rows["rigid"].to_numpy(dtype=bool) & ~certified
    if bad.any():
        rows = rows.copy()
        rows.loc[bad, ["frac_cables_taut", "frac_struts_taut"]] = np.nan
    return rows, int(bad.sum())


def at_transition(rows: pd.DataFrame, crit: pd.DataFrame) -> pd.DataFrame:
    """Per-sample Gamma and energy at the grid p_r nearest p_crit (compression), per p_t."""
    parts = []
    for _, c in crit[np.isclose(crit.phi, math.pi)].sort_values("p_t").iterrows():
        sub = rows[np.isclose(rows.phi, math.pi) & np.isclose(rows.p_t, c.p_t)]
        grid = np.unique(sub.p_r)
        if not grid.size or not np.isfinite(c.p_crit):
            continue
        p_r = grid[int(np.argmin(np.abs(grid - c.p_crit)))]
        at = sub[np.isclose(sub.p_r, p_r)]
        parts.append(at[["p_t", "p_r", "sample", "nonaffinity", "energy", "rigid"]])
    cols = ["p_t", "p_r", "sample", "nonaffinity", "energy", "rigid"]
    return pd.concat(parts, ignore_index=True) if parts else pd.DataFrame(columns=cols)


def tail_statistics(at_pcrit: pd.DataFrame) -> pd.DataFrame:
    """What a mean over samples at the transition is sensitive to, per p_t and observable.

    For Gamma and the energy at p_crit: the number of samples, mean, median, quartiles,
    largest value, the share of the sum carried by the largest sample (``top_share``) and the
    mean with that sample left out (``mean_without_top``).
    """
    out = []
    for p_t, sub in at_pcrit.groupby("p_t"):
        for name, col in (("Gamma", "nonaffinity"), ("energy", "energy")):
            v = sub[col].to_numpy(float)
            v = v[np.isfinite(v)]
            if not v.size:
                continue
            total = v.sum()
            out.append(
                {
                    "p_t": p_t,
                    "p_r": float(sub.p_r.iloc[0]),
                    "observable": name,
                    "N": v.size,
                    "mean": v.mean(),
                    "median": float(np.median(v)),
                    "q25": float(np.quantile(v, 0.25)),
                    "q75": float(np.quantile(v, 0.75)),
                    "max": v.max(),
                    "top_share": v.max() / total if total > 0 else np.nan,
                    "mean_without_top": np.sort(v)[:-1].mean() if v.size > 1 else np.nan,
                }
            )
    return pd.DataFrame(out)


def worst_tail(tails: pd.DataFrame) -> dict | None:
    """The row of :func:`tail_statistics` (Gamma) whose largest sample carries most of the sum."""
    g = tails[tails.observable == "Gamma"] if len(tails) else tails
    g = g[np.isfinite(g.top_share)] if len(g) else g
    if not len(g):
        return None
    return g.loc[g.top_share.idxmax()].to_dict()


def gamma_peaks(
    rows: pd.DataFrame, crit: pd.DataFrame, n_boot: int, rng: np.random.Generator | None = None
) -> dict:
    """Where the mean (and the median) nonaffinity peaks under compression, per p_t.

    Returns {"p_t": (J,), "p_crit": (J,), "p_crit_err": (J,), "mean": (peaks, cov),
    "median": (peaks, cov)}; the peaks' covariance comes from one bootstrap over samples shared
    by every p_t (common random numbers correlate the curves), and the mean's and the median's
    peaks are located on the same replicas (each statistic draws from a copy of ``rng``; by
    default the ``"peaks"`` stream at seed offset 0).
    """
    rng = rng or stream("peaks")
    comp = crit[np.isclose(crit.phi, math.pi)].sort_values("p_t")
    samples = np.arange(1, int(rows["sample"].max()) + 1)
    vals, xs = [], []
    for p_t in comp.p_t:
        sub = rows[np.isclose(rows.phi, math.pi) & np.isclose(rows.p_t, p_t)]
        v, x = per_sample(sub, "nonaffinity", samples)
        vals.append(v)
        xs.append(x)
    out = {"p_t": comp.p_t.to_numpy(), "p_crit": comp.p_crit.to_numpy()}
    for stat in ("mean", "median"):
        out[stat] = an.peak_locations(vals, xs, stat, n_boot=n_boot, rng=copy.deepcopy(rng))
    return out
