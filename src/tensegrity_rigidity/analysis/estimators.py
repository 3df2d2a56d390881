"""Estimators for ensembles of samples: probabilities, efficacies, energy scaling.

All functions take plain arrays or pandas frames of sweep rows and return numbers with their
uncertainties; each states its estimator.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
import pandas as pd
from scipy import optimize, stats


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
        ``k / n`` and the interval (NaN where ``n = 0``).

    Examples
    --------
    >>> from tensegrity_rigidity.analysis.estimators import wilson
    >>> p, lo, hi = wilson(8, 10)
    >>> print(f"{p:.2f} [{lo:.3f}, {hi:.3f}]")
    0.80 [0.490, 0.943]
    """
    k = np.asarray(k, dtype=float)
    n = np.asarray(n, dtype=float)
    with np.errstate(invalid="ignore", divide="ignore"):
        p = np.where(n > 0, k / n, np.nan)
        denom = 1 + z**2 / n
        centre = (p + z**2 / (2 * n)) / denom
        half = z * np.sqrt(p * (1 - p) / n + z**2 / (4 * n**2)) / denom
    return p, centre - half, centre + half


def probability_from_thresholds(thresholds: np.ndarray, p_r: np.ndarray) -> np.ndarray:
    """P(p_r) from per-sample thresholds: the fraction of samples with ``s* < p_r``.

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
    t = np.asarray(thresholds, dtype=float)
    t = np.where(np.isnan(t), np.inf, t)
    return np.array([np.mean(t < p) for p in np.atleast_1d(p_r)])


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


def resampler(n_rows: int, groups=None, rng: np.random.Generator | None = None):
    """A function returning the row indices of one bootstrap replica.

    Parameters
    ----------
    n_rows : int
        Rows of the data.
    groups : (n_rows,) array, optional
        Label of each row's independent unit. Rows of one unit are drawn together (a cluster
        bootstrap): the same sample measured under several strains is one unit, not several.
        Without it every row is a unit.
    rng : numpy.random.Generator, optional
        Source of the draws.

    Returns
    -------
    callable
        ``draw()`` -> (R,) int row indices of a replica (``R = n_rows`` without groups, and
        with groups of equal size). Without groups a draw is ``rng.integers(0, n_rows,
        n_rows)``, exactly the rows the estimators drew before groups existed.
    """
    rng = rng or np.random.default_rng(0)
    if groups is None:
        return lambda: rng.integers(0, n_rows, n_rows)
    labels = np.asarray(groups)
    if labels.shape != (n_rows,):
        raise ValueError(f"groups has shape {labels.shape}, expected ({n_rows},)")
    _, unit = np.unique(labels, return_inverse=True)
    order = np.argsort(unit, kind="stable")
    members = np.split(order, np.cumsum(np.bincount(unit))[:-1])
    k = len(members)
    return lambda: np.concatenate([members[i] for i in rng.integers(0, k, k)])


def n_units(n_rows: int, groups=None) -> int:
    """Independent units behind ``n_rows`` rows.

    Parameters
    ----------
    n_rows : int
        Rows of the data.
    groups : (n_rows,) array, optional
        Label of each row's independent unit, as in :func:`resampler`.

    Returns
    -------
    int
        Distinct labels in ``groups``; ``n_rows`` without groups.
    """
    return n_rows if groups is None else int(np.unique(np.asarray(groups)).size)


# --------------------------------------------------------------------------- efficacy ratio


@dataclass(frozen=True)
class CollapseFit:
    """Fit of P(p_r, p_t) = F((p_r + lam p_t - x0) / w), F the logistic function.

    Attributes
    ----------
    lam : float
        Estimate of S_t / S_r (the efficacy of a one-sided element relative to a rod).
    x0 : float
        Where P = 1/2 at ``p_t = 0``.
    w : float
        Width of the transition.
    lam_err, x0_err, w_err : float
        Bootstrap standard errors (resampling samples, which keeps the correlations of common
        random numbers).
    n_samples : int
        Samples behind the fit.
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
    groups=None,
) -> CollapseFit:
    """Binomial-likelihood fit of P = F(p_r + lam p_t) to per-sample outcomes.

    Parameters
    ----------
    outcomes : (S, G) bool
        Rigidity of sample s at grid point g (the same S samples at every point: common random
        numbers; points may also hold independent samples).
    p_r, p_t : (G,) float
        Coordinates of the grid points.
    n_boot : int
        Bootstrap replicas for the errors.
    rng : numpy.random.Generator, optional
        Source of the bootstrap (a fixed seed by default).
    groups : (S,) array, optional
        Independent unit of each row (:func:`resampler`): rows of the same sample under
        several strains are resampled together.

    Returns
    -------
    CollapseFit
        ``lam`` (S_t / S_r), ``x0``, ``w`` and their errors.

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
    fits = []
    draw = resampler(y.shape[0], groups, rng)
    for _ in range(n_boot):
        idx = draw()
        kb = y[idx].sum(axis=0)
        fits.append(_fit_counts(p_r, p_t, kb, np.full(y.shape[1], float(idx.size)), best))
    boots = np.array(fits) if fits else np.full((1, 3), np.nan)
    sd = boots.std(axis=0, ddof=1) if len(boots) > 1 else np.full(3, np.nan)
    w_samples = np.exp(boots[:, 2])
    return CollapseFit(
        float(best[0]),
        float(best[1]),
        float(np.exp(best[2])),
        float(sd[0]),
        float(sd[1]),
        float(w_samples.std(ddof=1)) if len(boots) > 1 else np.nan,
        n_units(y.shape[0], groups),
    )


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
        s = np.where(np.isnan(s), np.inf, s)
        for p in p_r_grid:
            if p + p_t <= 1 + 1e-12:
                cols.append(s < p)
                pr.append(p)
                pt.append(p_t)
    return np.array(cols).T, np.array(pr), np.array(pt)


@dataclass(frozen=True)
class Derivative:
    """A derivative of P (or a slope) with its standard error.

    Attributes
    ----------
    value : float
        The estimate.
    err : float
        Its standard error.
    """

    value: float
    err: float


def paired_derivative(minus: np.ndarray, plus: np.ndarray, h: float) -> Derivative:
    """(P(x + h) - P(x - h)) / 2h from the outcomes of the same samples at x - h and x + h.

    Parameters
    ----------
    minus, plus : (S,) float
        Outcomes (0/1, NaN where missing) of the same samples at ``x - h`` and ``x + h``.
    h : float
        Half the step.

    Returns
    -------
    Derivative
        The central difference and its standard error.

    Notes
    -----
    The standard error uses the per-sample differences (common random numbers make most of
    them zero). Samples missing at either point are dropped.
    """
    d = np.asarray(plus, float) - np.asarray(minus, float)
    d = d[np.isfinite(d)]
    n = d.size
    err = d.std(ddof=1) / np.sqrt(n) if n > 1 else np.nan
    return Derivative(float(d.mean() / (2 * h)), float(err / (2 * h)))


# --------------------------------------------------------------------------- efficacy surface


def fit_logistic(k: np.ndarray, m: np.ndarray, X: np.ndarray, max_iter: int = 100) -> np.ndarray:
    """Firth-penalised maximum-likelihood logistic regression on binomial counts.

    Parameters
    ----------
    k, m : (G,) float
        Successes and trials at each design point.
    X : (G, q) float
        Design matrix.
    max_iter : int
        Newton iterations at most.

    Returns
    -------
    beta : (q,) float
        Coefficients of ``logit P = X beta`` (NaN if Newton's method does not converge).

    Notes
    -----
    Firth's penalty (half the log-determinant of the Fisher information) keeps the estimate
    finite when the outcomes are separated (P = 0 or 1 at every point, as happens with few
    samples) and removes the O(1/m) bias of the maximum-likelihood estimate; its effect vanishes
    as the counts grow. Newton steps on the modified score
    ``X^T (k - m p + h (1/2 - p))`` (h: leverages), halved until the penalised likelihood rises.
    """
    k, m, X = (np.asarray(a, float) for a in (k, m, X))
    beta = np.zeros(X.shape[1])

    def penalised(b):
        eta = X @ b
        w = m * _sigmoid(eta) * _sigmoid(-eta)
        sign, logdet = np.linalg.slogdet(X.T @ (w[:, None] * X))
        ll = float(np.sum(k * -np.logaddexp(0, -eta) + (m - k) * -np.logaddexp(0, eta)))
        return ll + 0.5 * logdet if sign > 0 else -np.inf

    current = penalised(beta)
    for _ in range(max_iter):
        p = _sigmoid(X @ beta)
        w = m * p * (1 - p)
        info = X.T @ (w[:, None] * X)
        try:
            inv = np.linalg.inv(info)
        except np.linalg.LinAlgError:
            return np.full(X.shape[1], np.nan)
        h = w * np.einsum("ij,jk,ik->i", X, inv, X)
        step = inv @ (X.T @ (k - m * p + h * (0.5 - p)))
        t = 1.0
        while t > 1e-8:
            trial = penalised(beta + t * step)
            if trial >= current - 1e-12:
                break
            t /= 2
        beta = beta + t * step
        current = penalised(beta)
        if np.max(np.abs(t * step)) < 1e-9:
            return beta
    return np.full(X.shape[1], np.nan)


def _sigmoid(x):
    return 0.5 * (1 + np.tanh(0.5 * np.asarray(x, float)))


@dataclass(frozen=True, eq=False)
class EfficacyCurves:
    """Efficacies along f_c at a point (p_r0, p_t0), with bootstrap covariances.

    Attributes
    ----------
    f_c : (F,) float
        Where the curves are evaluated.
    values : dict
        Name -> (F,) float: "P", "S_r", "S_t", "D_f" (dP/df_c), "S_c", "S_s", "S_c_rel"
        (S_c/S_r), "S_s_rel", "sum_rel" ((S_c + S_s)/S_r).
    cov : dict
        Name -> (F, F) bootstrap covariance of ``values[name]`` over f_c.
    n_samples : int
        Samples (rows) behind the fit.
    """

    f_c: np.ndarray
    values: dict
    cov: dict
    n_samples: int

    def err(self, name: str) -> np.ndarray:
        """Standard errors of one curve.

        Parameters
        ----------
        name : str
            A key of ``values`` ("S_c_rel", ...).

        Returns
        -------
        (F,) float
            The square roots of the diagonal of ``cov[name]``.
        """
        return np.sqrt(np.diag(self.cov[name]))


def _surface_design(p_r, p_t, f_c, centre, degrees):
    d_eta, d_slope = degrees
    dr, dt = np.asarray(p_r) - centre[0], np.asarray(p_t) - centre[1]
    f = np.asarray(f_c, float)
    cols = [f**j for j in range(d_eta + 1)]
    cols += [dr * f**j for j in range(d_slope + 1)]
    cols += [dt * f**j for j in range(d_slope + 1)]
    return np.column_stack(cols)


def _surface_derivatives(beta, f, degrees):
    """P, dP/dp_r, dP/dp_t, dP/df at the centre, each (F,), from the coefficients."""
    d_eta, d_slope = degrees
    c = beta[: d_eta + 1]
    a = beta[d_eta + 1 : d_eta + d_slope + 2]
    b = beta[d_eta + d_slope + 2 :]
    eta = sum(c[j] * f**j for j in range(d_eta + 1))
    deta = sum(j * c[j] * f ** (j - 1) for j in range(1, d_eta + 1))
    P = _sigmoid(eta)
    dF = P * (1 - P)
    slope_r = sum(a[j] * f**j for j in range(d_slope + 1))
    slope_t = sum(b[j] * f**j for j in range(d_slope + 1))
    return P, dF * slope_r, dF * slope_t, dF * deta


def fit_efficacies(
    outcomes: np.ndarray,
    p_r: np.ndarray,
    p_t: np.ndarray,
    f_c: np.ndarray,
    centre: tuple[float, float],
    f_eval: np.ndarray,
    degrees: tuple[int, int] = (4, 2),
    n_boot: int = 200,
    rng: np.random.Generator | None = None,
) -> tuple[list[EfficacyCurves], EfficacyCurves]:
    """S_r, S_t, S_c, S_s along f_c from a likelihood fit smooth in f_c, per strain and averaged.

    Parameters
    ----------
    outcomes : (K, S, G) float
        Rigidity (0/1, NaN where missing) of sample s under strain k at design point g; the
        same S samples under every strain and at every point (common random numbers).
    p_r, p_t, f_c : (G,) float
        Design points around ``centre = (p_r0, p_t0)``, at several f_c.
    f_eval : (F,) float
        Where to evaluate the curves.
    centre : (float, float)
        The point ``(p_r0, p_t0)`` at which the derivatives are taken.
    degrees : (int, int)
        Polynomial degrees in f_c of the logit at the centre and of its slopes in p_r, p_t.
    n_boot : int
        Bootstrap replicas for the covariances.
    rng : numpy.random.Generator, optional
        Source of the bootstrap (a fixed seed by default).

    Returns
    -------
    per_strain : list of EfficacyCurves
        One per strain.
    average : EfficacyCurves
        S_r, S_t, dP/df_c averaged over the strains, and the ratios formed from the averages.

    Notes
    -----
    Model, for each strain: ``logit P = eta(f_c) + a(f_c) (p_r - p_r0) + b(f_c) (p_t - p_t0)``
    with eta a polynomial of degree ``degrees[0]`` and a, b of degree ``degrees[1]``, fitted by
    :func:`fit_logistic` to the pooled counts (a pseudo-likelihood: outcomes of one sample are
    correlated). At the centre ``S_r = P (1 - P) a``, ``S_t = P (1 - P) b``,
    ``dP/df_c = P (1 - P) eta'``; ``S_c = S_t + (1 - f_c) dP/df_c / p_t0`` and
    ``S_s = S_t - f_c dP/df_c / p_t0``. The curves are smooth in f_c, so the ends f_c = 0, 1 use
    every point, unlike one-sided differences. Covariances: a bootstrap over samples, the same
    resampled samples for every strain (it keeps the correlations of common random numbers
    across points, f_c and strains). Missing outcomes are left out of the counts.
    """
    rng = rng or np.random.default_rng(5)
    y = np.asarray(outcomes, float)
    if y.ndim == 2:
        y = y[None]
    K, S, _ = y.shape
    X = _surface_design(p_r, p_t, f_c, centre, degrees)
    f = np.asarray(f_eval, float)
    p_t0 = centre[1]

    def curves(idx):
        per, sums = [], None
        for kk in range(K):
            yy = y[kk, idx]
            ok = np.isfinite(yy)
            beta = fit_logistic(np.where(ok, yy, 0).sum(axis=0), ok.sum(axis=0), X)
            P, S_r, S_t, D = _surface_derivatives(beta, f, degrees)
            per.append((P, S_r, S_t, D))
            part = np.array([P, S_r, S_t, D])
            sums = part if sums is None else sums + part
        return per, tuple(sums / K)

    def named(P, S_r, S_t, D):
        S_c = S_t + (1 - f) * D / p_t0
        S_s = S_t - f * D / p_t0
        with np.errstate(divide="ignore", invalid="ignore"):
            return {
                "P": P,
                "S_r": S_r,
                "S_t": S_t,
                "D_f": D,
                "S_c": S_c,
                "S_s": S_s,
                "S_c_rel": S_c / S_r,
                "S_s_rel": S_s / S_r,
                "sum_rel": (S_c + S_s) / S_r,
            }

    per, avg = curves(np.arange(S))
    best = [named(*c) for c in per] + [named(*avg)]
    boots: list[list[dict]] = [[] for _ in best]
    for _ in range(n_boot):
        per_b, avg_b = curves(rng.integers(0, S, S))
        for i, c in enumerate([*per_b, avg_b]):
            boots[i].append(named(*c))
    out = []
    for i, vals in enumerate(best):
        cov = {}
        for name in vals:
            draws = np.array([b[name] for b in boots[i]])
            draws = draws[np.all(np.isfinite(draws), axis=1)]
            cov[name] = (
                np.atleast_2d(np.cov(draws.T, ddof=1))
                if len(draws) > 1
                else np.full((f.size, f.size), np.nan)
            )
        out.append(EfficacyCurves(f, vals, cov, S))
    return out[:-1], out[-1]


# --------------------------------------------------------------------------- energy scaling


@dataclass(frozen=True)
class PowerLawFit:
    """ln E = alpha ln(p_r - p_crit) + beta, least squares with standard errors.

    Attributes
    ----------
    p_crit : float
        The critical point used (an input of the fit).
    alpha, alpha_err : float
        Exponent and its standard error: the least-squares one from
        :func:`fit_energy_power_law`, the bootstrap over samples from
        :func:`fit_energy_exponent`.
    beta, beta_err : float
        Intercept and its standard error (the same two kinds).
    n_points : int
        Points in the fit.
    alpha_ls_err : float
        The least-squares standard error of alpha, which treats the points of the fit as
        independent with p_crit known exactly (equal to ``alpha_err`` for
        :func:`fit_energy_power_law`; kept beside the bootstrap error of
        :func:`fit_energy_exponent` to show what it leaves out).
    """

    p_crit: float
    alpha: float
    alpha_err: float
    beta: float
    beta_err: float
    n_points: int
    alpha_ls_err: float = float("nan")


def fit_energy_power_law(
    p_r: np.ndarray, energy: np.ndarray, p_crit: float, max_distance: float = 0.25
) -> PowerLawFit:
    """Fit mean energies above p_crit (within max_distance of it) to a power law.

    Parameters
    ----------
    p_r : (G,) float
        Grid of rod probabilities.
    energy : (G,) float
        Mean energy at each point.
    p_crit : float
        The critical point (see :func:`critical_point`), not fitted.
    max_distance : float
        Points with ``p_r > p_crit + max_distance`` are left out.

    Returns
    -------
    PowerLawFit
        alpha, beta and their least-squares standard errors (NaN with fewer than 3 points).

    Notes
    -----
    Points with E <= 0 or p_r <= p_crit are excluded.
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
        float(res.stderr),
    )


def fit_energy_exponent(
    p_r: np.ndarray,
    energy: np.ndarray,
    critical,
    n_boot: int = 200,
    max_distance: float = 0.25,
    rng: np.random.Generator | None = None,
) -> PowerLawFit:
    """The power law of the mean energy above p_crit, with errors from a bootstrap over samples.

    Parameters
    ----------
    p_r : (G,) float
        Grid of rod probabilities.
    energy : (S, G) float
        Per-sample energies (rows: samples, the same disorder at every p_r; NaN where a
        sample has no decided value at a point, left out of that point's mean).
    critical : callable
        ``critical(idx)`` -> p_crit from the samples ``idx`` ((S,) int row indices of
        ``energy``, with repeats in a replica): the median threshold of those samples, say, or
        the paper's first positive mean energy. Called with ``arange(S)`` for the estimate.
    n_boot : int
        Bootstrap replicas.
    max_distance : float
        As in :func:`fit_energy_power_law`.
    rng : numpy.random.Generator, optional
        Source of the bootstrap (a fixed seed by default).

    Returns
    -------
    PowerLawFit
        alpha and beta of :func:`fit_energy_power_law` on the mean energies of all samples
        from ``critical(arange(S))``; ``alpha_err`` and ``beta_err`` the standard deviations
        over replicas that redraw the samples, recompute p_crit *from the redrawn samples*
        and refit; ``alpha_ls_err`` the least-squares error of the estimate.

    Notes
    -----
    The least-squares error of :func:`fit_energy_power_law` misses the two largest sources
    of error near the transition. The points of the fit are the same samples at every p_r
    (nested configurations), so their errors are correlated, not independent; and p_crit is
    itself estimated from those samples, while ``d alpha / d p_crit`` is large because the
    fit's abscissa is ``ln(p_r - p_crit)`` (about 37 at n = 32, p_t = 0: an error of 0.003
    in p_crit moves alpha by 0.1). Resampling whole samples and re-estimating p_crit in each
    replica carries both. Replicas whose fit has fewer than three points are left out.

    The estimator itself (the paper's) is unstable when a grid point lies within the error of
    p_crit above it: ``ln(p_r - p_crit)`` of that point is very negative and it dominates the
    fit. On synthetic samples with p_crit on a grid point alpha comes out biased low (1.11 at
    24 samples and 1.03 at 96 against 1.34); the bootstrap error shows the spread, not that
    bias.
    """
    p_r = np.asarray(p_r, float)
    e = np.asarray(energy, float)
    S = e.shape[0]
    rng = rng or np.random.default_rng(5)

    def fit(idx) -> PowerLawFit:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)  # an all-NaN column: no mean there
            curve = np.nanmean(e[idx], axis=0)
        return fit_energy_power_law(p_r, curve, float(critical(idx)), max_distance)

    best = fit(np.arange(S))
    boots = [fit(rng.integers(0, S, S)) for _ in range(n_boot if S > 1 else 0)]
    a = np.array([b.alpha for b in boots if np.isfinite(b.alpha)])
    b = np.array([b.beta for b in boots if np.isfinite(b.alpha)])
    a_err = float(np.std(a, ddof=1)) if a.size > 1 else np.nan
    b_err = float(np.std(b, ddof=1)) if b.size > 1 else np.nan
    return PowerLawFit(
        best.p_crit, best.alpha, a_err, best.beta, b_err, best.n_points, best.alpha_err
    )


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


def critical_point(thresholds: np.ndarray, groups=None) -> tuple[float, float]:
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

    Returns
    -------
    p_crit, err : float
        The median and its bootstrap standard error (200 replicas, a fixed seed).
    """
    t = np.asarray(thresholds, float)
    rng = np.random.default_rng(1)
    draw = resampler(t.size, groups, rng)
    boots = [median_threshold(t[draw()]) for _ in range(200)]
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


# --------------------------------------------------------------------------- paired statistics


def paired_slope(outcomes: np.ndarray, x: np.ndarray) -> Derivative:
    """Least-squares slope of mean outcome over ``x``, with its standard error.

    Parameters
    ----------
    outcomes : (S, G) float
        Outcome (e.g. rigidity 0/1) of sample s at point g; the same samples at every point
        (common random numbers). Samples with any NaN are dropped.
    x : (G,) float
        Coordinates of the points.

    Returns
    -------
    Derivative
        The slope and its standard error.

    Notes
    -----
    The least-squares slope is linear in the outcomes, so the slope of the mean curve equals the
    mean of the per-sample slopes ``b_s = sum_g (x_g - xbar) y_sg / sum_g (x_g - xbar)^2``; its
    standard error is the standard error of that mean (samples are independent, points of one
    sample are not).
    """
    y = np.asarray(outcomes, float)
    x = np.asarray(x, float)
    y = y[np.all(np.isfinite(y), axis=1)]
    dx = x - x.mean()
    b = y @ dx / float(dx @ dx)
    err = b.std(ddof=1) / np.sqrt(b.size) if b.size > 1 else np.nan
    return Derivative(float(b.mean()) if b.size else np.nan, float(err))


@dataclass(frozen=True)
class Location:
    """A point estimate on the parameter axis (a crossing, a slope of a contour) and its error.

    Attributes
    ----------
    value : float
        The estimate.
    err : float
        Its standard error.
    """

    value: float
    err: float


def peak_locations(
    values: list[np.ndarray],
    x: list[np.ndarray],
    statistic: str = "mean",
    n_boot: int = 200,
    rng: np.random.Generator | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Grid points where several curves have their maximum, with their joint covariance.

    Parameters
    ----------
    values : list of (S, G_j) float
        Per-sample observable of curve j (NaN where missing) at its grid points ``x[j]``
        (G_j,); row s of every curve is the same sample (common random numbers).
    x : list of (G_j,) float
        Grid points of each curve.
    statistic : str
        "mean" or "median" over samples: the curve whose maximum is located.
    n_boot : int
        Bootstrap replicas.
    rng : numpy.random.Generator, optional
        Source of the bootstrap (a fixed seed by default).

    Returns
    -------
    peaks : (J,) float
        Grid point of each curve's maximum.
    cov : (J, J) float
        Bootstrap covariance of the peaks (resampling samples jointly for all curves) plus the
        grid resolution ``h_j^2 / 12`` on the diagonal (the maximum lies anywhere within half a
        step of the grid point).
    """
    rng = rng or np.random.default_rng(2)
    reduce = {"mean": np.nanmean, "median": np.nanmedian}[statistic]
    vals = [np.asarray(v, float) for v in values]
    xs = [np.asarray(g, float) for g in x]
    S = vals[0].shape[0]

    def peaks(idx):
        out = []
        for v, g in zip(vals, xs, strict=True):
            m = reduce(v[idx], axis=0)
            out.append(g[int(np.nanargmax(m))] if np.isfinite(m).any() else np.nan)
        return out

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN columns
        best = np.array(peaks(np.arange(S)))
        boots = np.array([peaks(rng.integers(0, S, S)) for _ in range(n_boot)])
    boots = boots[np.all(np.isfinite(boots), axis=1)]
    J = len(vals)
    cov = np.cov(boots.T, ddof=1).reshape(J, J) if len(boots) > 1 else np.full((J, J), np.nan)
    h = np.array([np.min(np.diff(np.sort(g))) if g.size > 1 else 0.0 for g in xs])
    return best, cov + np.diag(h**2 / 12)


def first_positive(
    values: np.ndarray, x: np.ndarray, n_boot: int = 200, rng: np.random.Generator | None = None
) -> Location:
    """Smallest grid point where the mean of ``values`` over samples is positive.

    Parameters
    ----------
    values : (S, G) float
        Per-sample values (energies; NaN counts as 0).
    x : (G,) float
        Grid points, increasing.
    n_boot : int
        Bootstrap replicas.
    rng : numpy.random.Generator, optional
        Source of the bootstrap (a fixed seed by default).

    Returns
    -------
    Location
        The grid point (NaN when no mean is positive) and its error.

    Notes
    -----
    The paper's p_crit ("the value of p_r at which E first becomes positive") applied to
    per-sample energies ``values`` (S, G) on the grid ``x`` (G,); NaN when no mean is positive.
    The error is a bootstrap over samples. Unlike the median threshold (P = 1/2) this is an
    extreme-value statistic: it moves to smaller p_r as the number of samples grows. The
    error combines the bootstrap spread with the grid's resolution ``h / sqrt(12)``.
    """
    rng = rng or np.random.default_rng(4)
    v = np.nan_to_num(np.asarray(values, float), nan=0.0)
    x = np.asarray(x, float)

    def first(rows):
        pos = np.flatnonzero(rows.mean(axis=0) > 0)
        return float(x[pos[0]]) if pos.size else np.nan

    best = first(v)
    S = v.shape[0]
    boots = np.array([first(v[rng.integers(0, S, S)]) for _ in range(n_boot)])
    boots = boots[np.isfinite(boots)]
    sd = float(np.std(boots, ddof=1)) if boots.size > 1 else np.nan
    h = float(np.min(np.diff(np.sort(x)))) if x.size > 1 else 0.0
    return Location(best, float(np.hypot(sd, h / np.sqrt(12))))


def contour_slope(
    thresholds: np.ndarray, p_t: np.ndarray, n_boot: int = 200, rng=None, groups=None
) -> Location:
    """S_t/S_r as minus the slope of the P = 1/2 contour, p_r*(p_t) = x0 - lam p_t.

    Parameters
    ----------
    thresholds : (S, J) float
        Per-sample threshold in p_r (NaN: never rigid) of the same S samples at J values of
        ``p_t``.
    p_t : (J,) float
        The values of p_t.
    n_boot : int
        Bootstrap replicas.
    rng : numpy.random.Generator, optional
        Source of the bootstrap (a fixed seed by default).
    groups : (S,) array, optional
        Independent unit of each row (:func:`resampler`).

    Returns
    -------
    Location
        ``lam`` = S_t / S_r and its bootstrap standard error.

    Notes
    -----
    Model-free alternative to :func:`fit_collapse`: at each p_t the median threshold is where P
    crosses 1/2; ``lam`` is minus the least-squares slope of the medians over p_t (exactly
    S_t/S_r when P = F(p_r + lam p_t)). The error is a bootstrap over samples, which keeps the
    correlation of the medians through common random numbers.
    """
    rng = rng or np.random.default_rng(3)
    t = np.asarray(thresholds, float)
    t = np.where(np.isnan(t), np.inf, t)
    p_t = np.asarray(p_t, float)

    def lam(rows):
        med = np.median(rows, axis=0)
        ok = np.isfinite(med)
        if ok.sum() < 2:
            return np.nan
        d = p_t[ok] - p_t[ok].mean()
        return -float(d @ med[ok] / (d @ d))

    best = lam(t)
    draw = resampler(t.shape[0], groups, rng)
    lams = np.array([lam(t[draw()]) for _ in range(n_boot)])
    boots = lams[np.isfinite(lams)]
    return Location(best, float(np.std(boots, ddof=1)) if boots.size > 1 else np.nan)


def crossing_point(
    outcomes: np.ndarray,
    x: np.ndarray,
    n_boot: int = 200,
    rng: np.random.Generator | None = None,
    groups=None,
) -> Location:
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
    Location
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
    draw = resampler(y.shape[0], groups, rng)
    boots = np.array([cross(y[draw()]) for _ in range(n_boot)])
    boots = boots[np.isfinite(boots)]
    return Location(best, float(np.std(boots, ddof=1)) if boots.size > 1 else np.nan)


@dataclass(frozen=True)
class PairedEstimate:
    """A statistic computed two ways on the same samples, and the difference b - a.

    Attributes
    ----------
    a, a_err : float
        The statistic of the first data set and its bootstrap error.
    b, b_err : float
        The same for the second.
    diff, diff_err : float
        ``b - a`` and its paired bootstrap error.
    """

    a: float
    a_err: float
    b: float
    b_err: float
    diff: float
    diff_err: float


def paired_bootstrap(
    statistic, a: np.ndarray, b: np.ndarray, n_boot: int = 200, rng=None, groups=None
) -> PairedEstimate:
    """``statistic`` of two data sets of the same samples, with errors of each and of b - a.

    Parameters
    ----------
    statistic : callable
        Maps an array of samples (rows) to a float.
    a, b : (S, ...) array
        The same S samples measured two ways (e.g. exact and inexact verdicts).
    n_boot : int
        Bootstrap replicas.
    rng : numpy.random.Generator, optional
        Source of the bootstrap (a fixed seed by default).
    groups : (S,) array, optional
        Independent unit of each row (:func:`resampler`).

    Returns
    -------
    PairedEstimate
        Both values, their difference and the errors.

    Notes
    -----
    Each bootstrap replica resamples the same rows of ``a`` and ``b``, so the error of the
    difference keeps their correlation (most samples get the same verdict both ways, and the
    difference is far better determined than either value).
    """
    rng = rng or np.random.default_rng(7)
    a, b = np.asarray(a), np.asarray(b)
    va, vb = statistic(a), statistic(b)
    draw = resampler(a.shape[0], groups, rng)
    draws = []
    for _ in range(n_boot):
        idx = draw()
        draws.append((statistic(a[idx]), statistic(b[idx])))
    d = np.array(draws, float).reshape(-1, 2)
    d = d[np.all(np.isfinite(d), axis=1)]
    sd = d.std(axis=0, ddof=1) if len(d) > 1 else np.full(2, np.nan)
    dd = float(np.std(d[:, 1] - d[:, 0], ddof=1)) if len(d) > 1 else np.nan
    return PairedEstimate(float(va), float(sd[0]), float(vb), float(sd[1]), float(vb - va), dd)


# --------------------------------------------------------------------------- finite size


#: range of 1/nu allowed to the free finite-size fit: nu in [0.5, 3], which brackets every
#: exponent of 2D percolation-type transitions (connectivity 4/3, generic rigidity 1.16-1.21)
THETA = (1 / 3, 2.0)


@dataclass(frozen=True)
class FiniteSizeFit:
    """y(n) = y_inf + a n^(-1/nu), weighted least squares.

    Attributes
    ----------
    y_inf, y_inf_err : float
        The extrapolation to n -> infinity and its error.
    a, a_err : float
        Amplitude of the correction and its error.
    nu, nu_err : float
        The exponent and its error.
    nu_fixed : bool
        Whether nu was an input (its error then the one given with it, used only to widen
        ``y_inf_err``).
    chi2 : float
        Chi-square of the fit.
    dof : int
        Its degrees of freedom; with ``chi2`` they judge the form.
    """

    y_inf: float
    y_inf_err: float
    a: float
    a_err: float
    nu: float
    nu_err: float
    nu_fixed: bool
    chi2: float
    dof: int


def fit_finite_size(
    n: np.ndarray,
    y: np.ndarray,
    err: np.ndarray,
    nu: float | None = None,
    nu_err: float = 0.0,
    n_boot: int = 300,
    rng: np.random.Generator | None = None,
) -> FiniteSizeFit:
    """Extrapolate a size-dependent estimate to n -> infinity.

    Parameters
    ----------
    n : (K,) float
        Linear sizes.
    y, err : (K,) float
        Estimates at each size and their standard errors (independent samples per size).
    nu : float, optional
        Exponent of the correction. None: fitted with y_inf and a (needs K >= 3); given: the
        fit is linear in (y_inf, a), and ``nu_err`` widens ``y_inf_err`` by half the change of
        y_inf between nu - nu_err and nu + nu_err.
    nu_err : float
        Standard error of a given ``nu``.
    n_boot : int
        Parametric bootstrap replicas (fitted nu only).
    rng : numpy.random.Generator, optional
        Source of the bootstrap (a fixed seed by default).

    Returns
    -------
    FiniteSizeFit
        The extrapolation, the correction and the exponent, with errors and chi-square.

    Notes
    -----
    The standard finite-size form of a percolation threshold defined at fixed P (here the
    median threshold, P = 1/2): ``p_c(n) = p_c + a n^(-1/nu)``. With nu given, errors are the
    weighted-least-squares ones (the given errors taken as right, not rescaled by chi-square).
    With nu fitted, errors are the standard deviations of a parametric bootstrap
    (``n_boot`` refits of y + N(0, err)): with four sizes and three parameters the
    least-squares curvature understates the spread several times. NaN where the fit fails
    (too few sizes, errors not finite).
    """
    n, y, err = (np.asarray(a, float) for a in (n, y, err))
    ok = np.isfinite(y) & np.isfinite(err) & (err > 0)
    n, y, err = n[ok], y[ok], err[ok]
    nan = FiniteSizeFit(np.nan, np.nan, np.nan, np.nan, np.nan, np.nan, nu is not None, np.nan, 0)

    def linear(nu_):
        X = np.column_stack([np.ones(n.size), n ** (-1.0 / nu_)])
        W = 1 / err**2
        cov = np.linalg.inv(X.T @ (W[:, None] * X))
        beta = cov @ (X.T @ (W * y))
        chi2 = float(np.sum(W * (y - X @ beta) ** 2))
        return beta, cov, chi2

    if nu is not None:
        if n.size < 2:
            return nan
        beta, cov, chi2 = linear(nu)
        extra = 0.0
        if nu_err and np.isfinite(nu_err):
            lo, hi = linear(max(nu - nu_err, 0.05))[0][0], linear(nu + nu_err)[0][0]
            extra = 0.5 * abs(hi - lo)
        return FiniteSizeFit(
            float(beta[0]),
            float(np.hypot(np.sqrt(cov[0, 0]), extra)),
            float(beta[1]),
            float(np.sqrt(cov[1, 1])),
            float(nu),
            float(nu_err),
            True,
            chi2,
            int(n.size - 2),
        )
    if n.size < 3:
        return nan

    def model(nn, y_inf, a, theta):
        return y_inf + a * nn ** (-theta)

    start = [y[np.argmax(n)], (y[np.argmin(n)] - y[np.argmax(n)]) * n.min() ** 0.85, 0.85]
    try:
        popt, pcov = optimize.curve_fit(
            model,
            n,
            y,
            p0=start,
            sigma=err,
            absolute_sigma=True,
            bounds=([-np.inf, -np.inf, THETA[0]], [np.inf, np.inf, THETA[1]]),
            maxfev=20000,
        )
    except (RuntimeError, ValueError):
        return nan
    chi2 = float(np.sum(((y - model(n, *popt)) / err) ** 2))
    # parametric bootstrap: with few sizes the three parameters are strongly correlated and
    # their distribution far from normal, so the curvature errors understate the spread
    rng = rng or np.random.default_rng(8)
    refits = []
    for _ in range(n_boot):
        yb = y + rng.normal(0.0, err)
        try:
            pb, _ = optimize.curve_fit(
                model,
                n,
                yb,
                p0=popt,
                sigma=err,
                absolute_sigma=True,
                bounds=([-np.inf, -np.inf, THETA[0]], [np.inf, np.inf, THETA[1]]),
                maxfev=20000,
            )
        except (RuntimeError, ValueError):
            continue
        refits.append([pb[0], pb[1], 1 / pb[2]])
    draws = np.array(refits).reshape(-1, 3)

    def spread(col):
        return float(np.std(draws[:, col], ddof=1)) if len(draws) >= 10 else np.nan

    return FiniteSizeFit(
        float(popt[0]),
        spread(0),
        float(popt[1]),
        spread(1),
        float(1 / popt[2]),
        spread(2),
        False,
        chi2,
        int(n.size - 3),
    )


@dataclass(frozen=True)
class WidthScaling:
    """Threshold distributions against size: nu and p_c without a fitted exponent.

    Attributes
    ----------
    n : (K,) float
        Linear sizes.
    width, width_err : (K,) float
        Standard deviation of the per-sample thresholds at each size and its bootstrap error.
    centre, centre_err : (K,) float
        Median threshold (the P = 1/2 point) at each size and its bootstrap error.
    nu, nu_err : float
        The exponent of ``width ~ n^(-1/nu)`` (weighted least squares in log-log) and its
        bootstrap error.
    nu_chi2 : float
        Chi-square of that fit (``K - 2`` degrees of freedom).
    p_c, p_c_err : float
        Intercept of ``centre = p_c + b width`` and its bootstrap error.
    slope : float
        The ``b`` of that line.
    p_c_chi2 : float
        Its chi-square (``K - 2`` degrees of freedom).
    """

    n: np.ndarray
    width: np.ndarray
    width_err: np.ndarray
    centre: np.ndarray
    centre_err: np.ndarray
    nu: float
    nu_err: float
    nu_chi2: float
    p_c: float
    p_c_err: float
    slope: float
    p_c_chi2: float


def _line(x: np.ndarray, y: np.ndarray, err: np.ndarray) -> tuple[float, float, float]:
    """Weighted least-squares line ``y = c0 + c1 x``: (c0, c1, chi-square)."""
    X = np.column_stack([np.ones(x.size), x])
    W = 1.0 / err**2
    c0, c1 = np.linalg.solve(X.T @ (W[:, None] * X), X.T @ (W * y))
    return float(c0), float(c1), float(np.sum(W * (y - c0 - c1 * x) ** 2))


def width_scaling(
    n: np.ndarray,
    thresholds: list[np.ndarray],
    n_boot: int = 500,
    rng: np.random.Generator | None = None,
) -> WidthScaling:
    """The width and the centre of threshold distributions at several sizes.

    Parameters
    ----------
    n : (K,) float
        Linear sizes, K >= 3.
    thresholds : list of K arrays, (S_k,) float
        Per-sample thresholds at each size (independent samples).
    n_boot : int
        Bootstrap replicas (samples resampled within each size).
    rng : numpy.random.Generator, optional
        Source of the bootstrap (a fixed seed by default).

    Returns
    -------
    WidthScaling
        NaN throughout when a size has fewer than 3 finite thresholds or any threshold is not
        finite (a never-rigid sample has no place in a standard deviation).

    Notes
    -----
    Finite-size scaling of a threshold distribution (Stauffer & Aharony, *Introduction to
    Percolation Theory*, sec. 4.1): its width and the shift of its centre both scale as
    ``n^(-1/nu)``. The width therefore gives nu without p_c, from a straight line in log-log,
    and since ``centre - p_c`` is proportional to the width, the centre is a straight line in
    the width whose intercept is p_c: no exponent is fitted. Corrections to scaling bend both
    lines at small n; their chi-squares judge that. Errors are bootstrap standard deviations
    of the refits over replicas that resample each size's samples, so the correlation of a
    size's centre and width is kept.
    """
    n = np.asarray(n, float)
    t = [np.asarray(a, float) for a in thresholds]
    nan = np.full(n.size, np.nan)
    if n.size < 3 or any(a.size < 3 or not np.all(np.isfinite(a)) for a in t):
        return WidthScaling(n, nan, nan, nan, nan, *(np.nan,) * 7)
    rng = rng or np.random.default_rng(9)

    def moments(parts):
        return (
            np.array([np.std(a, ddof=1) for a in parts]),
            np.array([np.median(a) for a in parts]),
        )

    width, centre = moments(t)
    boots = [moments([a[rng.integers(0, a.size, a.size)] for a in t]) for _ in range(n_boot)]
    bw = np.array([b[0] for b in boots])
    bc = np.array([b[1] for b in boots])
    width_err, centre_err = bw.std(axis=0, ddof=1), bc.std(axis=0, ddof=1)
    log_err = width_err / width
    if not (np.all(log_err > 0) and np.all(centre_err > 0)):  # too few distinct thresholds
        return WidthScaling(n, width, width_err, centre, centre_err, *(np.nan,) * 7)

    def fits(w, c):
        _, k, chi_w = _line(np.log(n), np.log(w), log_err)
        p_c, b, chi_c = _line(w, c, centre_err)
        return -1.0 / k, p_c, b, chi_w, chi_c

    nu, p_c, slope, nu_chi2, p_c_chi2 = fits(width, centre)
    # a replica of a few equal thresholds has width 0 and no logarithm: it is left out
    keep = np.all(bw > 0, axis=1)
    draws = np.array([fits(w, c)[:2] for w, c in zip(bw[keep], bc[keep], strict=True)])
    nu_err, p_c_err = draws.std(axis=0, ddof=1) if len(draws) >= 10 else (np.nan, np.nan)
    return WidthScaling(
        n,
        width,
        width_err,
        centre,
        centre_err,
        float(nu),
        float(nu_err),
        nu_chi2,
        float(p_c),
        float(p_c_err),
        float(slope),
        p_c_chi2,
    )


# --------------------------------------------------------------------------- agreement


def agreement_z(ours, cov, reference, reference_err=0.0) -> float:
    """Distance between our values and a reference in units of both error bars.

    Parameters
    ----------
    ours : (k,) float
        Our values.
    cov : (k, k) float
        Their covariance (only the variances are used; a scalar or (k,) is read as variances).
    reference : (k,) float
        The reference values (the paper's), broadcast.
    reference_err : (k,) float
        Their standard errors.

    Returns
    -------
    z : float
        For k = 1, ``|ours - ref| / sqrt(err_ours^2 + err_ref^2)``. For k > 1 the largest of the
        k per-point z, expressed as the two-sided normal deviate of its family-wise tail
        probability ``1 - (1 - p_max)^k`` (Sidak), so that ``z < 2`` means the same 95.4 %
        level whatever k. Sidak's inequality makes this valid (conservative) for normal errors
        whatever their correlation, so no covariance matrix need be inverted (bootstrap
        covariances of smooth curves are nearly singular). A point without error on either
        side counts only if it differs (z = inf). NaN when any input is not finite.
    """
    y = np.atleast_1d(np.asarray(ours, float))
    k = y.size
    C = np.asarray(cov, float)
    var = np.diag(C) if C.ndim == 2 else np.broadcast_to(C, (k,))
    ref = np.broadcast_to(np.asarray(reference, float), (k,))
    rerr = np.broadcast_to(np.asarray(reference_err, float), (k,))
    finite = [np.all(np.isfinite(a)) for a in (y, var, ref, rerr)]
    if not all(finite):
        return float("nan")
    delta = np.abs(y - ref)
    sigma = np.sqrt(var + rerr**2)
    if np.any((sigma == 0) & (delta != 0)):
        return float("inf")
    zs = delta[sigma > 0] / sigma[sigma > 0]
    if zs.size == 0:
        return 0.0
    if k == 1:
        return float(zs[0])
    p_max = min(2.0 * stats.norm.sf(zs.max()), 1.0)  # two-sided tail of the largest
    if p_max >= 1.0:
        return 0.0
    family = -np.expm1(k * np.log1p(-p_max))
    return float(stats.norm.isf(max(family / 2, 1e-300)))


def sign_z(value: float, err: float, sign: int) -> float:
    """z of a claim that a quantity has a sign: its distance to the claimed half-line.

    Parameters
    ----------
    value, err : float
        The measured quantity and its standard error.
    sign : int
        The claimed sign, +1 or -1.

    Returns
    -------
    float
        ``max(0, -sign * value) / err``: zero when the value lies on the claimed side, else the
        number of standard errors by which it lies on the other side (NaN for non-finite
        input).
    """
    if not (np.isfinite(value) and np.isfinite(err)):
        return float("nan")
    gap = max(0.0, -sign * value)
    if gap == 0:
        return 0.0
    return float(gap / err) if err > 0 else float("inf")
