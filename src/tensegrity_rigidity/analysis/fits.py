"""Fits of the efficacies: the collapse P = F(p_r + lam p_t) and the Fig. 4 surface.

The collapse is fitted to exact per-sample thresholds by maximum likelihood
(:func:`fit_collapse_thresholds`) or, where only grid verdicts exist, to binomial counts
(:func:`fit_collapse`); the surface to binomial counts. The samples are the same at every point
(common random numbers); errors come from a bootstrap over samples (:mod:`.bootstrap`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import optimize

from .bootstrap import Estimate, n_units, replicas


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

    def refit(idx):
        k_b, n_b = y[idx].sum(axis=0), np.full(y.shape[1], float(idx.size))
        return _fit_counts(p_r, p_t, k_b, n_b, best)

    fits = replicas(refit, y.shape[0], n_boot, rng, groups)
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


def _log_cdf(z):
    """log F(z) of the logistic function, stable for any z (infinite included)."""
    return -np.logaddexp(0.0, -z)


def _threshold_nll(params, exact, q_exact, lo, hi, q_int):
    """Minus the log-likelihood of the collapse on thresholds (see
    :func:`fit_collapse_thresholds`): ``exact`` thresholds with their p_t ``q_exact``, and
    thresholds known to lie in ``(lo, hi]`` (infinite ends allowed) with their p_t ``q_int``."""
    lam, x0, logw = params
    w = np.exp(logw)
    z = (exact + lam * q_exact - x0) / w
    # the logistic density: log F(z) + log(1 - F(z)) - log w
    ll = float(np.sum(_log_cdf(z) + _log_cdf(-z))) - exact.size * logw
    if lo.size:
        za, zb = (lo + lam * q_int - x0) / w, (hi + lam * q_int - x0) / w
        # log(F(zb) - F(za)) = log F(zb) + log(1 - F(za)) + log(1 - exp(za - zb)), with
        # za - zb = (lo - hi) / w taken from the ends (not the difference of two rounded z)
        with np.errstate(invalid="ignore"):
            gap = np.where(np.isinf(lo) | np.isinf(hi), 1.0, -np.expm1((lo - hi) / w))
        ll += float(np.sum(_log_cdf(zb) + _log_cdf(-za) + np.log(gap)))
    return -ll if np.isfinite(ll) else np.inf


def threshold_events(thresholds, p_t, low=None, high=None):
    """What each per-sample threshold along p_r says, as the likelihood reads it.

    Parameters
    ----------
    thresholds : (S, J) float
        Threshold ``s*`` of sample s at ``p_t[j]`` along p_r in ``[0, 1 - p_t]`` (NaN: never
        rigid on the path; 0: rigid from its start).
    p_t : (J,) float
    low, high : (S, J) float, optional
        The interval ``(low, high]`` of a threshold that undecided probes left open (equal to
        the threshold where it is exact; ``high`` may be infinite).

    Returns
    -------
    exact : (E,) float and its p_t (E,)
        Thresholds known exactly.
    lo, hi : (I,) float and their p_t (I,)
        Thresholds known to lie in ``(lo, hi]``: an interval; never rigid on the path,
        ``(1 - p_t, inf)`` (right-censored at the path's end); rigid from the start,
        ``(-inf, 0]`` (left-censored).
    """
    t = np.asarray(thresholds, float)
    q = np.broadcast_to(np.asarray(p_t, float), t.shape)
    lo = t.copy() if low is None else np.asarray(low, float).copy()
    hi = t.copy() if high is None else np.asarray(high, float).copy()
    never = np.isnan(t) & ~(np.isfinite(lo) & (hi > lo))
    lo[never], hi[never] = 1.0 - q[never], np.inf
    start = (t == 0) & (hi <= 0)
    lo[start] = -np.inf
    exact = np.isfinite(lo) & (lo == hi)
    rest = ~exact & ((lo < hi) | np.isinf(lo))
    return (t[exact], q[exact]), (lo[rest], hi[rest], q[rest])


def fit_collapse_thresholds(
    thresholds: np.ndarray,
    p_t: np.ndarray,
    low: np.ndarray | None = None,
    high: np.ndarray | None = None,
    n_boot: int = 200,
    rng: np.random.Generator | None = None,
    groups=None,
) -> CollapseFit:
    """Maximum-likelihood fit of P = F((p_r + lam p_t - x0) / w) to exact per-sample thresholds.

    Parameters
    ----------
    thresholds : (S, J) float
        Per-sample thresholds along p_r of the same S samples at J values of p_t (NaN: never
        rigid on the path ``p_r <= 1 - p_t``), as :func:`threshold_events` reads them.
    p_t : (J,) float
    low, high : (S, J) float, optional
        Threshold intervals left by undecided probes (:func:`threshold_events`).
    n_boot : int
        Bootstrap replicas for the errors.
    rng : numpy.random.Generator, optional
        Source of the bootstrap (a fixed seed by default).
    groups : (S,) array, optional
        Independent unit of each row (:func:`~.bootstrap.resampler`).

    Returns
    -------
    CollapseFit
        ``lam`` (S_t / S_r), ``x0``, ``w`` and their bootstrap errors.

    Notes
    -----
    P(p_r) at fixed p_t is the fraction of samples whose threshold lies below p_r, so under
    the collapse a threshold ``s*`` at p_t is a draw of ``x0 - lam p_t + w L`` with L standard
    logistic. The likelihood reads each threshold as it is known: an exact one by its density,
    an interval by its probability, a never-rigid sample as censored at the path's end. No
    grid: binned outcomes on a p_r grid coarser than the transition make thresholds that differ
    by less than a step identical and lock lam where ``lam p_t`` is a whole number of steps.
    Thresholds of one sample at several p_t are correlated (common random numbers), so the
    estimate is a pseudo-likelihood one and its errors come from a bootstrap over samples.
    """
    rng = rng or np.random.default_rng(0)
    t = np.asarray(thresholds, float)
    lo_all = t if low is None else np.asarray(low, float)
    hi_all = t if high is None else np.asarray(high, float)

    def fit(rows, start):
        (e, qe), (a, b, qi) = threshold_events(t[rows], p_t, lo_all[rows], hi_all[rows])
        res = optimize.minimize(
            _threshold_nll, start, args=(e, qe, a, b, qi), method="Nelder-Mead",
            options={"xatol": 1e-10, "fatol": 1e-12, "maxiter": 20000},
        )  # fmt: skip
        return res.x if res.success else np.full(3, np.nan)

    q = np.broadcast_to(np.asarray(p_t, float), t.shape)
    x = t + 0.5 * q
    spread = float(np.nanstd(x)) if np.isfinite(x).sum() > 1 else 0.0
    start = np.array([0.5, float(np.nanmedian(x)) if np.isfinite(x).any() else 0.5,
                      np.log(max(spread, 1e-3) * np.sqrt(3) / np.pi)])  # fmt: skip
    best = fit(np.arange(t.shape[0]), start)
    boots = np.array(replicas(lambda idx: fit(idx, best), t.shape[0], n_boot, rng, groups))
    boots = boots.reshape(-1, 3)
    boots = boots[np.all(np.isfinite(boots), axis=1)]
    sd = boots.std(axis=0, ddof=1) if len(boots) > 1 else np.full(3, np.nan)
    return CollapseFit(
        float(best[0]),
        float(best[1]),
        float(np.exp(best[2])),
        float(sd[0]),
        float(sd[1]),
        float(np.exp(boots[:, 2]).std(ddof=1)) if len(boots) > 1 else np.nan,
        n_units(t.shape[0], groups),
    )


def collapse_contrast(
    systems: list[tuple[np.ndarray, np.ndarray, np.ndarray]],
    weights,
    p_t: np.ndarray,
    n_boot: int = 200,
    rng: np.random.Generator | None = None,
    groups=None,
) -> Estimate:
    """A weighted sum of the lam of several systems measured on the same samples, with one
    bootstrap that redraws the same samples for all of them.

    Parameters
    ----------
    systems : list of (thresholds, low, high), each (S, J)
        Row s of every system is the same sample (common random numbers: the same disorder,
        another cable fraction or strain).
    weights : (K,) float
        The contrast: ``sum_k weights[k] lam_k``.
    p_t : (J,) float
    n_boot : int
    rng : numpy.random.Generator, optional
    groups : (S,) array, optional
        Independent unit of each row.

    Returns
    -------
    Estimate
        The contrast of the fits on every row and its bootstrap standard error (the systems'
        lam are refitted on each replica's rows, so their correlation is kept).
    """
    rng = rng or np.random.default_rng(0)
    w = np.asarray(weights, float)

    def contrast(rows):
        lams = [fit_collapse_thresholds(t[rows], p_t, lo[rows], hi[rows], n_boot=0).lam
                for t, lo, hi in systems]  # fmt: skip
        return float(w @ np.asarray(lams))

    S = systems[0][0].shape[0]
    boots = np.array(replicas(contrast, S, n_boot, rng, groups), float)
    boots = boots[np.isfinite(boots)]
    return Estimate(contrast(np.arange(S)), float(boots.std(ddof=1)) if boots.size > 1 else np.nan)


def paired_derivative(minus: np.ndarray, plus: np.ndarray, h: float) -> Estimate:
    """(P(x + h) - P(x - h)) / 2h from the outcomes of the same samples at x - h and x + h.

    Parameters
    ----------
    minus, plus : (S,) float
        Outcomes (0/1, NaN where missing) of the same samples at ``x - h`` and ``x + h``.
    h : float
        Half the step.

    Returns
    -------
    Estimate
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
    return Estimate(float(d.mean() / (2 * h)), float(err / (2 * h)))


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
    for per_b, avg_b in replicas(curves, S, n_boot, rng):
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


def paired_slope(outcomes: np.ndarray, x: np.ndarray) -> Estimate:
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
    Estimate
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
    return Estimate(float(b.mean()) if b.size else np.nan, float(err))


def contour_slope(
    thresholds: np.ndarray, p_t: np.ndarray, n_boot: int = 200, rng=None, groups=None
) -> Estimate:
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
    Estimate
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
    lams = np.array(replicas(lambda idx: lam(t[idx]), t.shape[0], n_boot, rng, groups))
    boots = lams[np.isfinite(lams)]
    return Estimate(best, float(np.std(boots, ddof=1)) if boots.size > 1 else np.nan)
