"""Scaling: the energy's power law above p_crit, peaks and onsets on a p_r grid, and the
finite-size extrapolation y(n) = y_inf + a n^(-1/nu) with the widths' nu."""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
from scipy import optimize, stats

from .bootstrap import Estimate, replicas


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
    boots = replicas(fit, S, n_boot if S > 1 else 0, rng)
    a = np.array([b.alpha for b in boots if np.isfinite(b.alpha)])
    b = np.array([b.beta for b in boots if np.isfinite(b.alpha)])
    a_err = float(np.std(a, ddof=1)) if a.size > 1 else np.nan
    b_err = float(np.std(b, ddof=1)) if b.size > 1 else np.nan
    return PowerLawFit(
        best.p_crit, best.alpha, a_err, best.beta, b_err, best.n_points, best.alpha_err
    )


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
        boots = np.array(replicas(peaks, S, n_boot, rng))
    boots = boots[np.all(np.isfinite(boots), axis=1)]
    J = len(vals)
    cov = np.cov(boots.T, ddof=1).reshape(J, J) if len(boots) > 1 else np.full((J, J), np.nan)
    h = np.array([np.min(np.diff(np.sort(g))) if g.size > 1 else 0.0 for g in xs])
    return best, cov + np.diag(h**2 / 12)


def first_positive(
    values: np.ndarray, x: np.ndarray, n_boot: int = 200, rng: np.random.Generator | None = None
) -> Estimate:
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
    Estimate
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
    boots = np.array(replicas(lambda idx: first(v[idx]), S, n_boot, rng))
    boots = boots[np.isfinite(boots)]
    sd = float(np.std(boots, ddof=1)) if boots.size > 1 else np.nan
    h = float(np.min(np.diff(np.sort(x)))) if x.size > 1 else 0.0
    return Estimate(best, float(np.hypot(sd, h / np.sqrt(12))))


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


@dataclass(frozen=True, eq=False)
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


@dataclass(frozen=True, eq=False)
class FractalDimension:
    """Mean mass of a cluster against size: ``M(n) = A n^d``, a line in log-log.

    Attributes
    ----------
    n : (K,) float
        Linear sizes.
    mass, mass_err : (K,) float
        Mean mass at each size and its standard error (standard deviation / sqrt(samples)).
    d, d_err : float
        The exponent (the fractal dimension when the mass is measured at the threshold) and
        its bootstrap error.
    amplitude : float
        ``A``.
    chi2 : float
        Chi-square of the fit.
    dof : int
        ``K - 2``.
    """

    n: np.ndarray
    mass: np.ndarray
    mass_err: np.ndarray
    d: float
    d_err: float
    amplitude: float
    chi2: float
    dof: int


def fractal_dimension(
    n: np.ndarray,
    masses: list[np.ndarray],
    n_boot: int = 500,
    rng: np.random.Generator | None = None,
) -> FractalDimension:
    """The exponent of a cluster's mean mass against the linear size.

    Parameters
    ----------
    n : (K,) float
        Linear sizes, K >= 2.
    masses : list of K arrays, (S_k,) float
        Per-sample masses at each size (independent samples, S_k >= 2).
    n_boot : int
        Bootstrap replicas (samples resampled within each size).
    rng : numpy.random.Generator, optional
        Source of the bootstrap (a fixed seed by default).

    Returns
    -------
    FractalDimension
        NaN exponent when a size has fewer than 2 samples or a mean mass is not positive.

    Notes
    -----
    At the threshold the spanning cluster is a fractal of dimension ``d_f``, its mass scaling
    as ``n^(d_f)`` (Stauffer & Aharony, *Introduction to Percolation Theory*, sec. 5.1): a
    weighted least-squares line of ``log M`` against ``log n``, each size weighted by the
    relative error of its mean. The error is the spread of the refits over replicas that
    resample each size's samples; corrections to scaling bend the line at small n, which the
    chi-square judges.
    """
    n = np.asarray(n, float)
    m = [np.asarray(a, float) for a in masses]
    mean = np.array([a.mean() if a.size else np.nan for a in m])
    err = np.array([a.std(ddof=1) / np.sqrt(a.size) if a.size >= 2 else np.nan for a in m])
    bad = n.size < 2 or not np.all(np.isfinite(err)) or not np.all(mean > 0) or np.any(err <= 0)
    if bad:
        return FractalDimension(n, mean, err, np.nan, np.nan, np.nan, np.nan, max(n.size - 2, 0))
    rng = rng or np.random.default_rng(10)
    x, log_err = np.log(n), err / mean
    c0, d, chi2 = _line(x, np.log(mean), log_err)
    draws = [
        _line(x, np.log([a[rng.integers(0, a.size, a.size)].mean() for a in m]), log_err)[1]
        for _ in range(n_boot)
    ]
    return FractalDimension(
        n, mean, err, float(d), float(np.std(draws, ddof=1)), float(np.exp(c0)), chi2, n.size - 2
    )
