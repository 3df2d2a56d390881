"""Estimators for ensembles of samples: probabilities, efficacies, energy scaling.

All functions take plain arrays or pandas frames of sweep rows and return numbers with their
uncertainties; each states its estimator.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd
from scipy import optimize, stats


def wilson(k, n, z: float = 1.96):
    """Wilson score interval of a binomial proportion: (p_hat, lower, upper), arrays like k."""
    k = np.asarray(k, dtype=float)
    n = np.asarray(n, dtype=float)
    with np.errstate(invalid="ignore", divide="ignore"):
        p = np.where(n > 0, k / n, np.nan)
        denom = 1 + z**2 / n
        centre = (p + z**2 / (2 * n)) / denom
        half = z * np.sqrt(p * (1 - p) / n + z**2 / (4 * n**2)) / denom
    return p, centre - half, centre + half


def probability_from_thresholds(thresholds: np.ndarray, p_r: np.ndarray) -> np.ndarray:
    """P(p_r) = fraction of samples with threshold < p_r, for each value of p_r (shape (k,))."""
    t = np.asarray(thresholds, dtype=float)
    t = np.where(np.isnan(t), np.inf, t)
    return np.array([np.mean(t < p) for p in np.atleast_1d(p_r)])


def rigidity_probability(df: pd.DataFrame, by: list[str]) -> pd.DataFrame:
    """P with Wilson 95% intervals per group of sweep rows: columns P, lo, hi, k, N."""
    g = df.groupby(by, sort=True)["rigid"].agg(["sum", "count"]).reset_index()
    p, lo, hi = wilson(g["sum"], g["count"])
    return g.assign(P=p, lo=lo, hi=hi).rename(columns={"sum": "k", "count": "N"})


# --------------------------------------------------------------------------- efficacy ratio


@dataclass(frozen=True)
class CollapseFit:
    """Fit of P(p_r, p_t) = F((p_r + lam p_t - x0) / w), F the logistic function.

    ``lam`` estimates S_t / S_r; ``lam_err``, ``x0_err``, ``w_err`` are bootstrap standard
    errors (resampling samples, which keeps the correlations of common random numbers).
    """

    lam: float
    x0: float
    w: float
    lam_err: float
    x0_err: float
    w_err: float
    n_samples: int


def _nll(params, x_r, x_t, k, n):
    lam, x0, logw = params
    z = (x_r + lam * x_t - x0) / np.exp(logw)
    logp = -np.logaddexp(0.0, -z)
    log1mp = -np.logaddexp(0.0, z)
    return -float(np.sum(k * logp + (n - k) * log1mp))


def _fit_counts(x_r, x_t, k, n, start):
    res = optimize.minimize(
        _nll,
        start,
        args=(x_r, x_t, k, n),
        method="Nelder-Mead",
        options={"xatol": 1e-7, "fatol": 1e-9, "maxiter": 4000},
    )
    return res.x


def fit_collapse(
    outcomes: np.ndarray,
    p_r: np.ndarray,
    p_t: np.ndarray,
    n_boot: int = 200,
    rng: np.random.Generator | None = None,
) -> CollapseFit:
    """Binomial-likelihood fit of P = F(p_r + lam p_t) to per-sample outcomes.

    Parameters
    ----------
    outcomes : (S, G) bool
        Rigidity of sample s at grid point g (the same S samples at every point: common random
        numbers; points may also hold independent samples).
    p_r, p_t : (G,) float
        Coordinates of the grid points.

    Notes
    -----
    The estimator maximises the binomial likelihood of the pooled counts over (lam, x0, log w);
    outcomes of one sample at different points are correlated, so the point estimate is a
    pseudo-likelihood estimate and its errors come from a bootstrap over samples (rows).
    """
    rng = rng or np.random.default_rng(0)
    y = np.asarray(outcomes, dtype=float)
    p_r, p_t = np.asarray(p_r, float), np.asarray(p_t, float)
    k, n = y.sum(axis=0), np.full(y.shape[1], y.shape[0], dtype=float)
    # start: lam = 1/2, x0 where P crosses 1/2, width from the spread
    x_mid = p_r + 0.5 * p_t
    pbar = k / n
    x0 = float(np.interp(0.5, np.sort(pbar), x_mid[np.argsort(pbar)]))
    start = np.array([0.5, x0, np.log(0.03)])
    best = _fit_counts(p_r, p_t, k, n, start)
    boots = []
    for _ in range(n_boot):
        idx = rng.integers(0, y.shape[0], y.shape[0])
        kb = y[idx].sum(axis=0)
        boots.append(_fit_counts(p_r, p_t, kb, n, best))
    boots = np.array(boots) if boots else np.full((1, 3), np.nan)
    sd = boots.std(axis=0, ddof=1) if len(boots) > 1 else np.full(3, np.nan)
    w_samples = np.exp(boots[:, 2])
    return CollapseFit(
        float(best[0]),
        float(best[1]),
        float(np.exp(best[2])),
        float(sd[0]),
        float(sd[1]),
        float(w_samples.std(ddof=1)) if len(boots) > 1 else np.nan,
        int(y.shape[0]),
    )


def outcomes_from_thresholds(
    thresholds: pd.DataFrame, p_r_grid: np.ndarray, p_t_col: str = "p_t"
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Expand per-sample thresholds (path "p_r", several p_t) into outcome matrices.

    Returns (outcomes (S, G), p_r (G,), p_t (G,)) with G = len(p_t values) * len(p_r_grid);
    grid points with p_r + p_t > 1 are dropped. Samples are matched by their index; a sample
    missing at any p_t (dropped as undecided) is left out everywhere, keeping the rows paired.
    """
    cols, pr, pt = [], [], []
    groups = [set(sub["sample"]) for _, sub in thresholds.groupby(p_t_col)]
    samples = np.array(sorted(set.intersection(*groups))) if groups else np.array([], int)
    for p_t, sub in thresholds.groupby(p_t_col):
        s = sub.set_index("sample").reindex(samples)["threshold_p_r"].to_numpy()
        s = np.where(np.isnan(s), np.inf, s)
        for p in p_r_grid:
            if p + p_t <= 1 + 1e-12:
                cols.append(s < p)
                pr.append(p)
                pt.append(p_t)
    return np.array(cols).T, np.array(pr), np.array(pt)


@dataclass(frozen=True)
class Derivative:
    """A derivative of P estimated by a paired (common random numbers) central difference."""

    value: float
    err: float


def paired_derivative(minus: np.ndarray, plus: np.ndarray, h: float) -> Derivative:
    """(P(x + h) - P(x - h)) / 2h from the outcomes of the same samples at x - h and x + h.

    The standard error uses the per-sample differences (CRN makes most of them zero). Samples
    missing (nan) at either point are dropped.
    """
    d = np.asarray(plus, float) - np.asarray(minus, float)
    d = d[np.isfinite(d)]
    n = d.size
    err = d.std(ddof=1) / np.sqrt(n) if n > 1 else np.nan
    return Derivative(float(d.mean() / (2 * h)), float(err / (2 * h)))


# --------------------------------------------------------------------------- energy scaling


@dataclass(frozen=True)
class PowerLawFit:
    """ln E = alpha ln(p_r - p_crit) + beta, least squares with standard errors."""

    p_crit: float
    alpha: float
    alpha_err: float
    beta: float
    beta_err: float
    n_points: int


def fit_energy_power_law(
    p_r: np.ndarray, energy: np.ndarray, p_crit: float, max_distance: float = 0.25
) -> PowerLawFit:
    """Fit mean energies above p_crit (within max_distance of it) to a power law.

    ``p_crit`` is given (see :func:`critical_point`); points with E <= 0 or p_r <= p_crit are
    excluded. Errors are the least-squares standard errors of slope and intercept.
    """
    p_r, energy = np.asarray(p_r, float), np.asarray(energy, float)
    m = (p_r > p_crit) & (p_r <= p_crit + max_distance) & (energy > 0)
    if m.sum() < 3:
        return PowerLawFit(p_crit, np.nan, np.nan, np.nan, np.nan, int(m.sum()))
    x, y = np.log(p_r[m] - p_crit), np.log(energy[m])
    res = stats.linregress(x, y)
    return PowerLawFit(
        p_crit,
        float(res.slope),
        float(res.stderr),
        float(res.intercept),
        float(res.intercept_stderr),
        int(m.sum()),
    )


def critical_point(thresholds: np.ndarray) -> tuple[float, float]:
    """p_crit as the median per-sample threshold (where P = 1/2), with a bootstrap error."""
    t = np.asarray(thresholds, float)
    t = np.where(np.isnan(t), np.inf, t)
    rng = np.random.default_rng(1)
    med = float(np.median(t))
    boots = [np.median(t[rng.integers(0, t.size, t.size)]) for _ in range(200)]
    return med, float(np.std(boots, ddof=1))


def probability_curve(thresholds: np.ndarray, p_grid: np.ndarray):
    """P on a grid from thresholds, with Wilson intervals: (P, lo, hi)."""
    t = np.asarray(thresholds, float)
    k = probability_from_thresholds(t, p_grid) * t.size
    return wilson(k, np.full_like(k, t.size))
