"""Fig. 2's energy exponent and taut-cable fraction, with bootstraps over whole samples.

A threshold sweep and a grid sweep of the same seed, n and delta hold the same disorders
(common random numbers): a replica redraws a sample's threshold and its grid rows together and
re-estimates p_crit in each replica.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pandas as pd

from ...analysis import estimators as an
from ..study import stream
from .rows import per_sample


def thresholds_by_sample(
    thresholds: pd.DataFrame, ids: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Per-sample thresholds lined up with the sample ids ``ids`` (S,).

    Returns ``t`` (S,) float (NaN: never rigid, or no threshold row) and ``known`` (S,) bool
    (the sample has a threshold row): a threshold sweep and a grid sweep of the same seed,
    n and delta hold the same disorder as sample k (common random numbers), so a bootstrap
    that redraws samples must redraw a sample's threshold and its grid rows together.
    """
    by = thresholds.set_index("sample").threshold_p_r
    known = np.isin(ids, by.index.to_numpy())
    return by.reindex(ids).to_numpy(float), known


def energy_exponent(
    grid: pd.DataFrame,
    thresholds: pd.DataFrame,
    n_boot: int,
    rng: np.random.Generator | None = None,
) -> an.PowerLawFit:
    """alpha of the mean energy of ``grid`` above the median threshold of ``thresholds``.

    Parameters
    ----------
    grid : DataFrame
        Decided grid rows of one (phi, p_t) curve: ``sample``, ``p_r``, ``energy``.
    thresholds : DataFrame
        Threshold rows of the same (phi, p_t) and seed: ``sample``, ``threshold_p_r``.
    n_boot : int
        Bootstrap replicas.
    rng : numpy.random.Generator, optional
        Source of the replicas (a scale's ``rng("energy_exponent")``; by default that stream
        at seed offset 0).

    Returns
    -------
    PowerLawFit
        :func:`~tensegrity_rigidity.analysis.scaling.fit_energy_exponent`: its errors
        redraw whole samples (a sample's energies at every p_r and its threshold together) and
        re-estimate p_crit in every replica.
    """
    ids = np.union1d(grid["sample"].unique(), thresholds["sample"].unique())
    e, x = per_sample(grid, "energy", samples=ids)
    t, known = thresholds_by_sample(thresholds, ids)
    return an.fit_energy_exponent(
        x,
        e,
        lambda idx: an.median_threshold(t[idx][known[idx]]),
        n_boot=n_boot,
        rng=rng or stream("energy_exponent"),
    )


#: p_t averaged by the taut-cable fraction at the transition (the paper's Fig. 2 inset)
TAUT_PT = (0.1, 0.2, 0.3)


def taut_with_error(
    rows: pd.DataFrame,
    thresholds: pd.DataFrame,
    n_boot: int,
    rng: np.random.Generator | None = None,
):
    """:func:`taut_at_transition` from grid and threshold rows, with a bootstrap error.

    Parameters
    ----------
    rows : DataFrame
        Grid rows (``phi``, ``p_t``, ``p_r``, ``sample``, ``rigid``, ``frac_cables_taut``;
        NaN where the tensions are not certified).
    thresholds : DataFrame
        Threshold rows of the same samples (``phi``, ``p_t``, ``sample``, ``threshold_p_r``).
    n_boot : int
        Bootstrap replicas.
    rng : numpy.random.Generator, optional
        Source of the replicas (a scale's ``rng("taut")``; by default that stream at seed
        offset 0).

    Returns
    -------
    tuple or None
        (mean, error, [(p_t, p_r), ...]) as :func:`taut_at_transition`, with the error a
        bootstrap over samples: a replica redraws whole samples (the same disorders at every
        p_t and p_r and in the thresholds, so the three p_t averaged are not independent),
        re-estimates p_crit per p_t and so may pick another grid p_r. None without a point.

    Notes
    -----
    The error of :func:`taut_at_transition` alone adds the three p_t's standard errors as if
    independent and takes the grid point as known: 0.005 at n = 32 where the same claim
    measured at other sizes and delta had 0.016.
    """
    comp = rows[np.isclose(rows.phi, math.pi)]
    th = thresholds[np.isclose(thresholds.phi, math.pi)]
    ids = np.union1d(comp["sample"].unique(), th["sample"].unique())
    blocks = []
    for p_t in TAUT_PT:
        sub = comp[np.isclose(comp.p_t, p_t)]
        if not len(sub):
            continue
        sub = sub.assign(_taut=np.where(sub.rigid.astype(bool), sub.frac_cables_taut, np.nan))
        f, x = per_sample(sub, "_taut", samples=ids)
        blocks.append((p_t, f, x, *thresholds_by_sample(th[np.isclose(th.p_t, p_t)], ids)))

    def at(idx):
        taut, crit = [], []
        for p_t, f, x, t, known in blocks:
            v = f[idx]
            size = np.isfinite(v).sum(axis=0)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)  # points without a rigid sample
                mean = np.nanmean(v, axis=0)
                sem = np.nanstd(v, axis=0, ddof=1) / np.sqrt(size)
            table = {"p_r": x, "mean": mean, "sem": sem, "size": size}
            taut.append(pd.DataFrame(table).assign(phi=math.pi, p_t=p_t))
            pc = an.median_threshold(t[idx][known[idx]])
            crit.append({"phi": math.pi, "p_t": p_t, "p_crit": pc})
        if not taut:
            return None
        return taut_at_transition(pd.concat(taut, ignore_index=True), pd.DataFrame(crit))

    best = at(np.arange(ids.size))
    if best is None:
        return None
    rng = rng or stream("taut")
    boots = an.replicas(at, ids.size, n_boot, rng)
    vals = np.array([b[0] for b in boots if b is not None])
    err = float(np.std(vals, ddof=1)) if vals.size > 1 else float("nan")
    return best[0], err, best[2]


def taut_at_transition(taut: pd.DataFrame, crit: pd.DataFrame):
    """Fraction of taut cables at the grid p_r nearest p_crit (compression), mean over p_t.

    Only grid points with a rigid sample whose tensions are certified (a finite mean) count:
    at n = 64 the point just below p_crit can have no rigid sample of 8 (p_t = 0.1 in the fss
    energy grids), and the next one is used. A p_t without such a point is left out; the
    returned list says which (p_t, p_r) were averaged.
    """
    vals = []
    for p_t in TAUT_PT:
        pc = crit[np.isclose(crit.phi, math.pi) & np.isclose(crit.p_t, p_t)].p_crit
        sub = taut[np.isclose(taut.phi, math.pi) & np.isclose(taut.p_t, p_t)]
        sub = sub[np.isfinite(sub["mean"].to_numpy(float))]
        if len(pc) and len(sub) and np.isfinite(pc.iloc[0]):
            row = sub.iloc[int(np.argmin(np.abs(sub.p_r - float(pc.iloc[0]))))]
            vals.append((row["mean"], row["sem"], p_t, row.p_r))
    if not vals:
        return None
    v = float(np.mean([x[0] for x in vals]))
    e = float(np.sqrt(np.nansum([x[1] ** 2 for x in vals])) / len(vals))
    return v, e, [(x[2], x[3]) for x in vals]
