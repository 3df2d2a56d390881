"""Binomial estimators: P with Wilson intervals, P from per-sample thresholds, p_crit.

A sample's threshold s* (the p_r at which it turns rigid along its path) gives its outcome at
every p_r, so P on any grid, the median threshold (P = 1/2) and the P = 1/2 crossing follow
from thresholds alone.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from scipy import stats

from .bootstrap import Estimate, replicas
from .fits import fit_logistic


def wilson(k, n, z: float = 1.96):
    """Wilson score interval of a binomial proportion.

    Parameters
    ----------
    k : (...) array_like
        Successes (rigid samples).
    n : (...) array_like
        Trials (decided samples), broadcast with ``k``.
    z : float
        Normal quantile of the interval: 1.96 for 95 %.

    Returns
    -------
    p_hat, lower, upper : (...) float
        ``k / n`` and the interval (NaN where ``n = 0``): SciPy's
        ``binomtest(k, n).proportion_ci(method="wilson")`` at the confidence of ``z``.

    Examples
    --------
    >>> from tensegrity_rigidity.analysis.estimators import wilson
    >>> p, lo, hi = wilson(8, 10)
    >>> print(f"{p:.2f} [{lo:.3f}, {hi:.3f}]")
    0.80 [0.490, 0.943]
    """
    k, n = np.broadcast_arrays(np.asarray(k, dtype=float), np.asarray(n, dtype=float))
    level = 2 * stats.norm.cdf(z) - 1  # the interval's confidence, from its normal quantile
    p = np.full(k.shape, np.nan)
    lo, hi = p.copy(), p.copy()
    for i in np.ndindex(k.shape):
        if n[i] > 0:
            ci = stats.binomtest(int(round(k[i])), int(round(n[i]))).proportion_ci(
                confidence_level=level, method="wilson"
            )
            p[i], lo[i], hi[i] = k[i] / n[i], ci.low, ci.high
    if p.ndim == 0:
        return p[()], lo[()], hi[()]
    return p, lo, hi


def rigid_at(thresholds: np.ndarray, p_r: float) -> np.ndarray:
    """Which samples are rigid at ``p_r``, from their thresholds ``s*``.

    A sample is rigid for ``p_r > s*``; ``s* = 0`` marks a sample rigid from the start, which is
    rigid at ``p_r = 0`` too (no event made it rigid; an event at a uniform of exactly 0, of
    probability ``2^-53`` per site, would read the same); NaN (never rigid) is rigid nowhere.

    Parameters
    ----------
    thresholds : (S,) float
        Per-sample thresholds.
    p_r : float
        Where.

    Returns
    -------
    (S,) bool
    """
    t = np.asarray(thresholds, dtype=float)
    return (t < p_r) | (t == 0.0)


def probability_from_thresholds(thresholds: np.ndarray, p_r: np.ndarray) -> np.ndarray:
    """P(p_r) from per-sample thresholds: the fraction of samples rigid there (:func:`rigid_at`).

    Parameters
    ----------
    thresholds : (S,) float
        Per-sample thresholds ``s*`` (NaN: never rigid on the path).
    p_r : (k,) float
        Where to evaluate P (a scalar is read as one value).

    Returns
    -------
    (k,) float
        P at each value of ``p_r``; exactly the fraction of rigid samples a grid sweep of the
        same samples finds there (a sample is rigid for ``p_r > s*``).
    """
    return np.array([np.mean(rigid_at(thresholds, p)) for p in np.atleast_1d(p_r)])


def rigidity_probability(df: pd.DataFrame, by: list[str]) -> pd.DataFrame:
    """P with Wilson 95 % intervals per group of sweep rows.

    Parameters
    ----------
    df : pandas.DataFrame
        Grid-sweep rows with a boolean ``rigid`` column (drop undecided rows first).
    by : list of str
        Columns to group by (grid columns such as ``["p_r", "phi"]``).

    Returns
    -------
    pandas.DataFrame
        One row per group: the ``by`` columns, ``k`` (rigid), ``N`` (samples), ``P``, ``lo``,
        ``hi``.
    """
    g = df.groupby(by, sort=True)["rigid"].agg(["sum", "count"]).reset_index()
    p, lo, hi = wilson(g["sum"], g["count"])
    return g.assign(P=p, lo=lo, hi=hi).rename(columns={"sum": "k", "count": "N"})


def common_samples(rows: pd.DataFrame, p_t_col: str = "p_t") -> np.ndarray:
    """Sample ids present at every value of ``p_t_col``.

    Parameters
    ----------
    rows : pandas.DataFrame
        Threshold-sweep rows with a ``sample`` column and the ``p_t_col`` column.
    p_t_col : str
        Column holding p_t.

    Returns
    -------
    (S,) int
        Sorted sample ids: the rows of :func:`outcomes_from_thresholds`, in order.
    """
    sets = [set(sub["sample"]) for _, sub in rows.groupby(p_t_col)]
    return np.array(sorted(set.intersection(*sets))) if sets else np.array([], int)


def outcomes_from_thresholds(
    thresholds: pd.DataFrame, p_r_grid: np.ndarray, p_t_col: str = "p_t"
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Expand per-sample thresholds (path "p_r", several p_t) into outcome matrices.

    Parameters
    ----------
    thresholds : pandas.DataFrame
        Threshold-sweep rows of one strain and f_c: ``sample``, ``threshold_p_r`` and the
        ``p_t_col`` column.
    p_r_grid : (k,) float
        Values of p_r at which to evaluate the outcomes.
    p_t_col : str
        Column holding p_t.

    Returns
    -------
    outcomes : (S, G) bool
        Rigidity of each sample at each grid point, ``G = len(p_t values) * k`` minus the
        points with ``p_r + p_t > 1`` (dropped).
    p_r, p_t : (G,) float
        Coordinates of the grid points.

    Notes
    -----
    Samples are matched by their index; a sample missing at any p_t (dropped as undecided)
    is left out everywhere, keeping the rows paired.
    """
    cols, pr, pt = [], [], []
    samples = common_samples(thresholds, p_t_col)
    for p_t, sub in thresholds.groupby(p_t_col):
        s = sub.set_index("sample").reindex(samples)["threshold_p_r"].to_numpy()
        for p in p_r_grid:
            if p + p_t <= 1 + 1e-12:
                cols.append(rigid_at(s, p))
                pr.append(p)
                pt.append(p_t)
    return np.array(cols).T, np.array(pr), np.array(pt)


#: bootstrap replicas of :func:`critical_point`'s error, whatever the scale's count
CRITICAL_POINT_REPLICAS = 200


def median_threshold(thresholds: np.ndarray) -> float:
    """The median per-sample threshold, NaN (never rigid) counted above every p_r.

    Parameters
    ----------
    thresholds : (S,) float
        Per-sample thresholds.

    Returns
    -------
    float
        The median (the p_r where P = 1/2; :func:`critical_point`'s estimate); NaN without
        samples.
    """
    t = np.asarray(thresholds, float)
    if t.size == 0:
        return float("nan")
    return float(np.median(np.where(np.isnan(t), np.inf, t)))


def critical_point(
    thresholds: np.ndarray,
    groups=None,
    rng: np.random.Generator | None = None,
    n_boot: int = CRITICAL_POINT_REPLICAS,
) -> tuple[float, float]:
    """p_crit as the median per-sample threshold (where P = 1/2), with a bootstrap error.

    Parameters
    ----------
    thresholds : (S,) float
        Per-sample thresholds (NaN: never rigid, counted above every p_r).
    groups : (S,) array, optional
        Independent unit of each threshold (:func:`resampler`). Rods-only thresholds of one
        sample are the same under every strain: pooled over strains they are one unit, and
        resampling them as independent would shrink the error by the square root of the
        number of strains.
    rng : numpy.random.Generator, optional
        Source of the replicas (a scale's ``rng("critical_point")``; by default seed 1).
    n_boot : int
        Bootstrap replicas.

    Returns
    -------
    p_crit, err : float
        The median and its bootstrap standard error.
    """
    t = np.asarray(thresholds, float)
    rng = rng or np.random.default_rng(1)
    if groups is None and t.size >= 2:  # scipy draws the replicas ours would
        res = stats.bootstrap(
            (t,), median_threshold, n_resamples=n_boot, rng=rng, vectorized=False,
            method="percentile",
        )  # fmt: skip
        return median_threshold(t), float(res.standard_error)
    boots = replicas(lambda idx: median_threshold(t[idx]), t.size, n_boot, rng, groups)
    return median_threshold(t), float(np.std(boots, ddof=1))


def median_bracket(values: np.ndarray, lower: np.ndarray) -> tuple[float, float]:
    """Bounds on the median of samples of which some are known only from below.

    Parameters
    ----------
    values : (S,) float
        The samples' values, NaN where unknown.
    lower : (S,) float
        A lower bound on each value (NaN where there is none); only read where ``values``
        is NaN.

    Returns
    -------
    low, high : float
        The median with every unknown value at its lower bound (at 0 where it has none), and
        with every unknown value at ``+inf``: the median of the true values lies between them
        whenever they are non-negative (the median is monotone in each sample). ``high`` is
        ``inf`` where the unknown values are half the samples or more; both NaN for no samples.

    Notes
    -----
    For the nonaffinity near a sample's own threshold, where the minimum-norm projection can
    stall and leave only a certified lower bound (sweep rows' ``nonaffinity_lower``): the
    median over the certified samples alone leaves the largest ones out and is biased low;
    this bracket counts every sample.
    """
    values = np.asarray(values, dtype=float)
    if values.size == 0:
        return float("nan"), float("nan")
    unknown = np.isnan(values)
    floor = np.where(np.isnan(lower), 0.0, np.asarray(lower, dtype=float))
    low = np.where(unknown, floor, values)
    high = np.where(unknown, np.inf, values)
    return float(np.median(low)), float(np.median(high))


def probability_curve(thresholds: np.ndarray, p_grid: np.ndarray):
    """P on a grid from thresholds, with Wilson intervals.

    Parameters
    ----------
    thresholds : (S,) float
        Per-sample thresholds (NaN: never rigid).
    p_grid : (G,) float
        Where to evaluate P.

    Returns
    -------
    P, lo, hi : (G,) float
        :func:`probability_from_thresholds` and its 95 % Wilson interval.
    """
    t = np.asarray(thresholds, float)
    k = probability_from_thresholds(t, p_grid) * t.size
    return wilson(k, np.full_like(k, t.size))


def crossing_point(
    outcomes: np.ndarray,
    x: np.ndarray,
    n_boot: int = 200,
    rng: np.random.Generator | None = None,
    groups=None,
) -> Estimate:
    """Where P(x) crosses 1/2, from a logistic fit to outcomes on a grid, with a bootstrap error.

    Parameters
    ----------
    outcomes : (S, G) float
        Outcome (0/1, NaN where missing) of sample s at grid point ``x[g]``.
    x : (G,) float
        Grid points.
    n_boot : int
        Bootstrap replicas.
    rng : numpy.random.Generator, optional
        Source of the bootstrap (a fixed seed by default).
    groups : (S,) array, optional
        Independent unit of each row (:func:`resampler`).

    Returns
    -------
    Estimate
        The crossing and its bootstrap standard error.

    Notes
    -----
    Fits ``logit P = b0 + b1 (x - xbar)`` (:func:`fit_logistic`) to the pooled counts and
    returns ``xbar - b0 / b1``; NaN when P does not increase. Needs no per-sample threshold, so
    it applies to verdicts that need not be monotone in x (an inexact minimiser's). Errors: a
    bootstrap over samples.
    """
    rng = rng or np.random.default_rng(6)
    y = np.asarray(outcomes, float)
    x = np.asarray(x, float)
    X = np.column_stack([np.ones(x.size), x - x.mean()])

    def cross(rows):
        ok = np.isfinite(rows)
        b0, b1 = fit_logistic(np.where(ok, rows, 0).sum(axis=0), ok.sum(axis=0), X)
        return float(x.mean() - b0 / b1) if b1 > 0 else np.nan

    best = cross(y)
    boots = np.array(replicas(lambda idx: cross(y[idx]), y.shape[0], n_boot, rng, groups))
    boots = boots[np.isfinite(boots)]
    return Estimate(best, float(np.std(boots, ddof=1)) if boots.size > 1 else np.nan)
