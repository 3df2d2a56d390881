"""Limits n -> infinity with their systematics, paired efficacies and threshold widths.

* :func:`paired_efficacies`: the one-sided efficacies of one system under compression and
  dilation from thresholds of the same samples (the same disorder and uniforms), their
  asymmetry and sum, with paired bootstrap errors (medians, the P = 1/2 points, beside means).
* :func:`fit_law`, :func:`limit_laws`: a size series fitted by several laws (a finite limit
  ``a + b n^-x``, a power law to zero ``b n^-x``, a constant), each with its chi-square and
  p-value; the limit is the finite law's, with the spread over the laws the data allow as its
  systematic, and :func:`vanishing_verdict` applies one rule fixed in advance.
* :func:`binomial_variance`, :func:`width_exponents`: the spread of per-sample thresholds split
  into the binomial part (how many sites fall below each p) and the geometric part, and the
  exponent of the geometric part's decay, ``n^(-1/nu)``; :func:`widths_against_binomial`:
  whether the widths are the binomial part alone.
* :func:`exponent_envelope`: a limit whose correction's exponent is not known, from every
  exponent of a declared range the data allow (an exponent-agnostic error).
* :func:`fit_corrected`, :func:`corrected_limit`: a threshold extrapolated with a known nu and
  one correction to scaling, ``p_c + a n^(-1/nu) (1 + b n^-omega)``, over a range of omega
  (the systematic).
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np
from scipy import optimize, stats

from .bootstrap import replicas

#: a law fits when its chi-square's p-value is at least this (fixed before any data were seen)
ACCEPT_P = 0.05
#: a limit differs from zero when it lies this many standard errors from it
Z_NONZERO = 2.0
#: the exponents x a law's correction may take (a profile over this grid: no local minima)
X_GRID = np.round(np.arange(0.1, 4.0001, 0.01), 2)
#: the laws :func:`fit_law` knows: name -> (parameters, a finite limit?)
LAWS = {"finite": 3, "zero": 2, "constant": 1}
#: the normal distribution's central 68.27 % (one standard error either side), in percent
ONE_SIGMA = (15.865, 84.135)


def robust_spread(draws: np.ndarray, axis: int = 0) -> np.ndarray:
    """Half the central 68 % range of bootstrap draws: a standard error that heavy tails do
    not inflate.

    Parameters
    ----------
    draws : array
        Bootstrap replicas along ``axis`` (non-finite ones left out).
    axis : int
        The replicas' axis.

    Returns
    -------
    numpy.ndarray
        The spread of each remaining entry (NaN with fewer than two finite replicas): for a
        normal spread its standard deviation, while a fit that runs off at a few replicas
        does not inflate it, as it does a standard deviation.
    """
    d = np.moveaxis(np.asarray(draws, float), axis, 0)
    flat = d.reshape(d.shape[0], -1)
    out = np.full(flat.shape[1], np.nan)
    for j, col in enumerate(flat.T):
        col = col[np.isfinite(col)]
        if col.size > 1:
            lo, hi = np.percentile(col, ONE_SIGMA)
            out[j] = 0.5 * (hi - lo)
    return out.reshape(d.shape[1:])


def allowed(chi2: float, dof: int) -> tuple[float, bool]:
    """Whether the data allow a fit, by the rule fixed in advance.

    Parameters
    ----------
    chi2 : float
        The fit's chi-square.
    dof : int
        Its degrees of freedom.

    Returns
    -------
    p_value : float
        Of the chi-square (NaN without a degree of freedom).
    allowed : bool
        Unless ``p_value < ACCEPT_P``; a fit with no degree of freedom cannot be rejected and
        is allowed; a non-finite chi-square is not.
    """
    if not np.isfinite(chi2):
        return np.nan, False
    if dof <= 0:
        return np.nan, True
    p = float(stats.chi2.sf(chi2, dof))
    return p, p >= ACCEPT_P


@dataclass(frozen=True)
class PairedEfficacies:
    """S_t/S_r of one system under compression and dilation from thresholds of the same
    samples; every error a paired bootstrap's (:func:`robust_spread`), with half the range
    over the ends of interval thresholds added in quadrature where those are given.

    Attributes
    ----------
    samples : int
        Samples given.
    never : int
        Samples never rigid on some path (their threshold counts as above every other's in
        the medians, and they are left out of the means).
    c, c_err, d, d_err : float
        The efficacies under compression and dilation from the P = 1/2 points (medians).
    asym, asym_err : float
        The asymmetry ``d - c``.
    total, total_err : float
        The sum ``c + d``.
    asym_mean, asym_mean_err, total_mean, total_mean_err : float
        The same from the means of per-sample threshold differences.
    """

    samples: int
    never: int
    c: float
    c_err: float
    d: float
    d_err: float
    asym: float
    asym_err: float
    total: float
    total_err: float
    asym_mean: float
    asym_mean_err: float
    total_mean: float
    total_mean_err: float


def _efficacy_stats(rods, comp, dil, p_t) -> np.ndarray:
    """(c, d, d - c, c + d, mean of d - c, mean of c + d) of one replica's thresholds."""
    med = [float(np.median(np.where(np.isfinite(a), a, np.inf))) for a in (rods, comp, dil)]
    c, d = (med[0] - med[1]) / p_t, (med[0] - med[2]) / p_t
    ok = np.isfinite(rods) & np.isfinite(comp) & np.isfinite(dil)
    diff = (comp[ok] - dil[ok]) / p_t
    total = (2 * rods[ok] - comp[ok] - dil[ok]) / p_t
    means = (diff.mean(), total.mean()) if ok.any() else (np.nan, np.nan)
    return np.array([c, d, d - c, c + d, *means])


def paired_efficacies(
    rods: np.ndarray,
    compression: np.ndarray,
    dilation: np.ndarray,
    p_t: float,
    n_boot: int = 200,
    rng: np.random.Generator | None = None,
    ends: tuple | None = None,
) -> PairedEfficacies:
    """Efficacies under compression and dilation from paired thresholds.

    Parameters
    ----------
    rods, compression, dilation : (S,) float
        Per-sample thresholds along p_r of the same samples: rods only (p_t = 0), and the
        one-sided system at ``p_t`` under compression and under dilation (NaN: never rigid).
    p_t : float
        The one-sided elements' probability of the last two.
    n_boot : int
        Paired bootstrap replicas (one draw of samples for all three).
    rng : numpy.random.Generator, optional
        Source of the draws.
    ends : ((S,), (S,)) x 3, optional
        The lower and upper ends of each threshold (rods, compression, dilation), where some
        are intervals (a probe inside the search stayed undecided; the thresholds given are
        their centres). Each statistic's error then adds half its range over the corners of
        the ends in quadrature: each statistic is monotone in every threshold, so its extremes
        over any choice inside the intervals lie at corners.

    Returns
    -------
    PairedEfficacies

    Notes
    -----
    With the collapse ``P(p_r, p_t) = F(p_r + lambda p_t)``, the P = 1/2 point moves by
    ``lambda p_t``: ``lambda = (p_c(0) - p_c(p_t)) / p_t``, the slope of the P = 1/2 contour.
    The asymmetry needs no rods-only point: ``(p_c^C(p_t) - p_c^D(p_t)) / p_t``. Sample k is
    one disorder under both strains, so its two thresholds are strongly correlated and the
    asymmetry far better determined than either efficacy; the bootstrap draws the samples once
    for all three thresholds and keeps that correlation.
    """
    arrays = [np.asarray(a, float) for a in (rods, compression, dilation)]
    if len({a.shape for a in arrays}) != 1 or arrays[0].ndim != 1:
        raise ValueError("rods, compression and dilation must be (S,) arrays of the same samples")
    r, c, d = arrays
    value = _efficacy_stats(r, c, d, p_t)
    rng = rng or np.random.default_rng(7)
    draws = np.array(replicas(lambda i: _efficacy_stats(r[i], c[i], d[i], p_t), r.size,
                              n_boot, rng), float).reshape(-1, value.size)  # fmt: skip
    err = robust_spread(draws)
    if ends is not None:
        ends_ = [[np.asarray(e, float) for e in pair] for pair in ends]
        corners = np.array([_efficacy_stats(ends_[0][i], ends_[1][j], ends_[2][k], p_t)
                            for i, j, k in itertools.product((0, 1), repeat=3)])  # fmt: skip
        err = np.hypot(err, (corners.max(axis=0) - corners.min(axis=0)) / 2)
    never = int(np.sum(~(np.isfinite(r) & np.isfinite(c) & np.isfinite(d))))
    pairs = [x for v, e in zip(value, err, strict=True) for x in (float(v), float(e))]
    return PairedEfficacies(int(r.size), never, *pairs)


@dataclass(frozen=True)
class LawFit:
    """One law fitted to a size series by weighted least squares.

    Attributes
    ----------
    law : str
        ``"finite"`` (``a + b n^-x``), ``"zero"`` (``b n^-x``) or ``"constant"`` (``a``).
    y_inf, y_inf_err : float
        The limit n -> infinity (0 for ``"zero"``, exactly) and its parametric-bootstrap error.
    x, x_err : float
        The correction's exponent and its error (NaN for ``"constant"``).
    x_at_bound : bool
        Whether the best x lies at an end of :data:`X_GRID` (the law then has no interior
        optimum on these sizes).
    chi2 : float
    dof : int
    p_value : float
        Of the chi-square with ``dof`` degrees of freedom (NaN without any).
    acceptable : bool
        Whether the data allow the law (:func:`allowed`: ``p_value >= ACCEPT_P``, or no
        degree of freedom to reject it).
    """

    law: str
    y_inf: float
    y_inf_err: float
    x: float
    x_err: float
    x_at_bound: bool
    chi2: float
    dof: int
    p_value: float
    acceptable: bool


def _linear(law: str, xs: np.ndarray, n, y, w) -> tuple[np.ndarray, np.ndarray]:
    """(chi2, y_inf) of the best amplitudes of ``law`` at each exponent of ``xs`` (the law is
    linear in them: 2 x 2 normal equations, solved for every x at once)."""
    f = n[None, :] ** -xs[:, None]  # (G, K)
    sff, sfy = (w * f * f).sum(axis=1), (w * f * y).sum(axis=1)
    if law == "zero":
        b = sfy / sff
        return (w * (y - b[:, None] * f) ** 2).sum(axis=1), np.zeros_like(b)
    sw, swy, sf = np.sum(w), np.sum(w * y), (w * f).sum(axis=1)
    det = sw * sff - sf**2
    a, b = (sff * swy - sf * sfy) / det, (sw * sfy - sf * swy) / det
    return (w * (y - a[:, None] - b[:, None] * f) ** 2).sum(axis=1), a


def _profile(law: str, n, y, w) -> tuple[float, float, float]:
    """(chi2, y_inf, x) of the best fit of ``law``: the exponent profiled over
    :data:`X_GRID` (no start, no local minimum), then refined between the best point's
    neighbours (bounded Brent), so the grid's step does not quantise x or the chi-square."""
    if law == "constant":
        mean = float(np.sum(w * y) / np.sum(w))
        return float(np.sum(w * (y - mean) ** 2)), mean, np.nan
    chi2, a = _linear(law, X_GRID, n, y, w)
    i = int(np.nanargmin(chi2))
    lo, hi = X_GRID[max(i - 1, 0)], X_GRID[min(i + 1, X_GRID.size - 1)]
    best = optimize.minimize_scalar(lambda x: _linear(law, np.array([x]), n, y, w)[0][0],
                                    bounds=(lo, hi), method="bounded",
                                    options={"xatol": 1e-5})  # fmt: skip
    if best.success and best.fun < chi2[i]:
        c, a_ = _linear(law, np.array([best.x]), n, y, w)
        return float(c[0]), float(a_[0]), float(best.x)
    return float(chi2[i]), float(a[i]), float(X_GRID[i])


def fit_law(
    law: str,
    n: np.ndarray,
    y: np.ndarray,
    err: np.ndarray,
    n_boot: int = 300,
    rng: np.random.Generator | None = None,
) -> LawFit:
    """Fit one law of :data:`LAWS` to ``y(n) +- err``.

    Parameters
    ----------
    law : {"finite", "zero", "constant"}
    n, y, err : (K,) float
        Sizes, values and their standard errors (independent between sizes).
    n_boot : int
        Parametric bootstrap replicas (``y + N(0, err)`` refitted) of the errors: each error
        is half the central 68 % range of the refits (:func:`robust_spread`).
    rng : numpy.random.Generator, optional

    Returns
    -------
    LawFit
        NaN throughout when fewer sizes than parameters have a finite value.

    Notes
    -----
    The exponent is profiled over :data:`X_GRID` (each x a linear fit), so the fit has no
    start and no local minimum, and refined between grid points; a best x at an end of the
    grid is flagged.
    """
    if law not in LAWS:
        raise ValueError(f"unknown law {law!r}; use one of {', '.join(LAWS)}")
    n, y, err = (np.asarray(a, float) for a in (n, y, err))
    ok = np.isfinite(y) & np.isfinite(err) & (err > 0)
    n, y, err = n[ok], y[ok], err[ok]
    k = LAWS[law]
    if n.size < k:
        return LawFit(law, *(np.nan,) * 4, False, np.nan, 0, np.nan, False)
    w = 1.0 / err**2
    chi2, y_inf, x = _profile(law, n, y, w)
    rng = rng or np.random.default_rng(11)
    draws = np.array([_profile(law, n, y + rng.normal(0.0, err), w)[1:] for _ in range(n_boot)])
    dof = int(n.size - k)
    p, ok_ = allowed(chi2, dof)
    spread = robust_spread(draws) if n_boot > 1 else np.full(2, np.nan)
    at_bound = bool(np.isfinite(x) and np.isclose(x, (X_GRID[0], X_GRID[-1]), atol=1e-4).any())
    return LawFit(law, y_inf, float(spread[0]), x, float(spread[1]), at_bound, chi2, dof, p, ok_)


def runaway(fit: LawFit) -> bool:
    """Whether a law's limit is not determined by the sizes.

    Parameters
    ----------
    fit : LawFit
        From :func:`fit_law`.

    Returns
    -------
    bool
        True when its exponent ends at the slow end of :data:`X_GRID`: the data ask for a
        slower approach than any allowed, and ``a + b n^-x`` tends to a constant whose split
        between ``a`` (the limit) and ``b`` the sizes do not fix.
    """
    return bool(fit.x_at_bound and np.isclose(fit.x, X_GRID[0], atol=1e-4))


def drifts(fit: LawFit, flat: LawFit) -> bool:
    """Whether a law fits a size series significantly better than no size dependence.

    Parameters
    ----------
    fit : LawFit
        The ``"finite"`` law (the one nested in the constant, so that the drop is a test).
    flat : LawFit
        The ``"constant"`` law on the same series.

    Returns
    -------
    bool
        True when the drop in chi-square from ``flat`` to ``fit`` has a p-value below
        :data:`ACCEPT_P` for the difference in degrees of freedom (2 for the finite law: its
        amplitude and its exponent, a free parameter of the fit even at a bound). Where the
        law's limit also runs off (:func:`runaway`), the series moves with size at a rate the
        sizes do not fix: a constant the data might still allow is not its limit.
    """
    ddof = flat.dof - fit.dof
    if ddof <= 0 or not (np.isfinite(flat.chi2) and np.isfinite(fit.chi2)):
        return False
    return bool(stats.chi2.sf(max(flat.chi2 - fit.chi2, 0.0), ddof) < ACCEPT_P)


@dataclass(frozen=True)
class Limit:
    """A size series' limit over several laws.

    Attributes
    ----------
    fits : dict
        Law name -> :class:`LawFit`.
    law : str
        The law ``value`` is read from: the first of the laws asked for that the data allow
        ("" when they allow none).
    value, stat : float
        That law's limit and its statistical error (NaN when no law is allowed: no limit is
        quoted from a law the data reject).
    syst : float
        The fit-form systematic: the largest distance from ``value`` of another allowed law's
        limit; 0 when no other law is allowed.
    low, high : float
        The range of the limits of the allowed laws (NaN when none is).

    A law whose limit :func:`runaway` says is not determined counts as not allowed here (its
    fit stays in ``fits``); where such a law the data allow also fits significantly better than
    no size dependence (:func:`drifts`), no limit is quoted at all.
    """

    fits: dict
    law: str
    value: float
    stat: float
    syst: float
    low: float
    high: float


def limit_laws(
    n,
    y,
    err,
    laws: tuple[str, ...] = ("finite", "zero"),
    n_boot: int = 300,
    rng: np.random.Generator | None = None,
) -> Limit:
    """A size series' limit n -> infinity from several laws, with its fit-form systematic.

    Parameters
    ----------
    n, y, err : (K,) float
        Sizes, values and standard errors, as :func:`fit_law`.
    laws : tuple of str
        Laws of :data:`LAWS`; the first is the reference, a law with a finite limit (the
        power law to zero only where the physics allows a vanishing limit).
    n_boot : int
        Parametric bootstrap replicas per law.
    rng : numpy.random.Generator, optional

    Returns
    -------
    Limit
        The limit of the first allowed law in the order of ``laws`` and its statistical
        error, and the spread over the laws the data allow: the systematic.
    """
    rng = rng or np.random.default_rng(11)
    fits = {law: fit_law(law, n, y, err, n_boot, rng) for law in laws}
    good = [f for f in fits.values()
            if f.acceptable and np.isfinite(f.y_inf) and not runaway(f)]  # fmt: skip
    # only the finite law is nested in the constant (b = 0): its chi-square drop is a test
    loose = [f for f in fits.values() if f.law == "finite" and f.acceptable and runaway(f)]
    if loose:
        flat = fits.get("constant") or fit_law("constant", n, y, err, 0, rng)
        if any(drifts(f, flat) for f in loose):
            good = []
    if not good:
        return Limit(fits, "", np.nan, np.nan, np.nan, np.nan, np.nan)
    ref, ok = good[0], [f.y_inf for f in good]
    return Limit(fits, ref.law, ref.y_inf, ref.y_inf_err, max(abs(v - ref.y_inf) for v in ok),
                 min(ok), max(ok))  # fmt: skip


#: the answers of :func:`vanishing_verdict`
VERDICTS = ("finite", "vanishes", "undetermined", "no law fits")


def vanishing_verdict(limit: Limit) -> str:
    """Whether a series stays finite or vanishes as n -> infinity, by a rule fixed in advance.

    Parameters
    ----------
    limit : Limit
        From :func:`limit_laws` with the laws "finite" and "zero".

    Returns
    -------
    str
        One of :data:`VERDICTS`.

    Notes
    -----
    "finite": the power law to zero is rejected (p < :data:`ACCEPT_P`) and the limit (of the
    first law asked for that the data allow and whose limit is determined, :func:`runaway`)
    lies :data:`Z_NONZERO` statistical errors or more from zero; "vanishes": the power law to
    zero fits and that limit lies within that distance of zero (0 itself when the power law is
    the first such law);
    "undetermined": the other cases in which some law fits (the sizes do not decide);
    "no law fits": neither does.
    """
    finite, zero = limit.fits["finite"], limit.fits["zero"]
    if not (finite.acceptable or zero.acceptable):
        return "no law fits"
    value, stat = abs(limit.value), limit.stat
    if not np.isfinite(value):
        z = np.nan
    elif stat > 0:
        z = value / stat
    else:
        z = np.inf if value > 0 else 0.0
    if not zero.acceptable and z >= Z_NONZERO:
        return "finite"
    if zero.acceptable and z < Z_NONZERO:
        return "vanishes"
    return "undetermined"


def binomial_variance(p_r: float, p_t: float, efficacy: float, sites: int) -> float:
    """Variance of a threshold that the numbers of sites below ``p`` alone would cause.

    Parameters
    ----------
    p_r : float
        The threshold (its centre).
    p_t : float
        The one-sided elements' probability along the path (0: rods only).
    efficacy : float
        S_t/S_r of the one-sided elements (unused at ``p_t = 0``).
    sites : int
        Bond sites of the lattice, M.

    Returns
    -------
    float
        ``var(w) / M`` with ``w = 1`` on a rod, ``lambda`` on a one-sided element, 0 on an
        empty site: ``p_r + lambda^2 p_t - (p_r + lambda p_t)^2``, over M. At ``p_t = 0`` it is
        ``p (1 - p) / M``.

    Notes
    -----
    Suppose a sample became rigid exactly when its weighted count ``X = N_r + lambda N_t``
    reached a fixed fraction of M. Along the path, ``E X = M (p_r + lambda p_t)`` grows at
    rate M and ``X`` fluctuates with the multinomial variance ``M var(w)`` of the sites' kinds,
    so the threshold would fluctuate by ``var(w) / M``: the binomial part. The rest of the
    spread, the geometric part, is the spread of the threshold in counts, ``X* / M``; for rods
    alone ``m* / M`` is independent of the sorted uniforms (Newman-Ziff), so the two add.
    """
    mean = p_r + efficacy * p_t
    return float((p_r + efficacy**2 * p_t - mean**2) / sites)


@dataclass(frozen=True, eq=False)
class WidthExponent:
    """Widths of the threshold distributions at several sizes and the geometric part's decay.

    Attributes
    ----------
    n : (K,) float
    total, total_err : (K,) float
        Standard deviation of the thresholds and its bootstrap error.
    binomial : (K,) float
        Its binomial part, ``sqrt(binomial_variance)``.
    geometric, geometric_err : (K,) float
        ``sqrt(total^2 - binomial^2)`` (NaN where negative) and its bootstrap error.
    counts, counts_err : (K,) float
        The standard deviation of the threshold in counts, ``(N_r + lambda N_t) / M``: the
        geometric part measured without a subtraction.
    nu, nu_err, chi2, dof : float
        ``counts ~ n^(-1/nu)`` (weighted least squares in log-log, over ``n >= n_min``) and
        its bootstrap error.
    nu_sub, nu_sub_err, chi2_sub : float
        The same from ``geometric`` (the subtraction).
    negative : float
        Fraction of replicas in which some size's total lies below its binomial part.
    """

    n: np.ndarray
    total: np.ndarray
    total_err: np.ndarray
    binomial: np.ndarray
    geometric: np.ndarray
    geometric_err: np.ndarray
    counts: np.ndarray
    counts_err: np.ndarray
    nu: float
    nu_err: float
    chi2: float
    dof: int
    nu_sub: float
    nu_sub_err: float
    chi2_sub: float
    negative: float


def _slope(n, w, err) -> tuple[float, float]:
    """(nu, chi2) of ``w ~ n^(-1/nu)`` by weighted least squares in log-log."""
    ok = np.isfinite(w) & (w > 0) & np.isfinite(err) & (err > 0)
    if ok.sum() < 2:
        return np.nan, np.nan
    x, ly, le = np.log(n[ok]), np.log(w[ok]), err[ok] / w[ok]
    X = np.column_stack([np.ones(x.size), x])
    W = 1 / le**2
    beta = np.linalg.solve(X.T @ (W[:, None] * X), X.T @ (W * ly))
    return float(-1 / beta[1]) if beta[1] < 0 else np.nan, float(np.sum(W * (ly - X @ beta) ** 2))


def _moments(thresholds, counts, binomial) -> np.ndarray:
    """(3, K): total, geometric (subtraction) and counts widths of one replica."""
    total = np.array([np.std(t, ddof=1) for t in thresholds])
    geo = np.sqrt(np.where(total**2 > binomial**2, total**2 - binomial**2, np.nan))
    return np.vstack([total, geo, [np.std(c, ddof=1) for c in counts]])


def width_exponents(
    n,
    thresholds: list,
    counts: list,
    binomial,
    n_min: float = 0,
    n_boot: int = 300,
    rng: np.random.Generator | None = None,
) -> WidthExponent:
    """The widths of per-sample thresholds, split into binomial and geometric parts.

    Parameters
    ----------
    n : (K,) float
        Linear sizes.
    thresholds, counts : lists of K (S_k,) float arrays
        Per-sample thresholds and the same samples' thresholds in counts (finite ones only).
    binomial : (K,) float
        The binomial variance at each size (:func:`binomial_variance`).
    n_min : float
        Sizes below are left out of the exponent fits (corrections to scaling).
    n_boot : int
        Replicas (each size's samples resampled, thresholds and counts together).
    rng : numpy.random.Generator, optional

    Returns
    -------
    WidthExponent
    """
    n = np.asarray(n, float)
    t = [np.asarray(a, float) for a in thresholds]
    c = [np.asarray(a, float) for a in counts]
    bsd = np.sqrt(np.asarray(binomial, float))
    value = _moments(t, c, bsd)
    rng = rng or np.random.default_rng(12)
    idx = [[rng.integers(0, a.size, a.size) for a in t] for _ in range(n_boot)]
    boots = np.array([_moments([a[i] for a, i in zip(t, ii, strict=True)],
                               [a[i] for a, i in zip(c, ii, strict=True)], bsd)
                      for ii in idx])  # fmt: skip
    err = robust_spread(boots)
    keep = n >= n_min
    fits = [_slope(n[keep], value[k][keep], err[k][keep]) for k in (2, 1)]
    draws = np.array([[_slope(n[keep], b[k][keep], err[k][keep])[0] for k in (2, 1)]
                      for b in boots])  # fmt: skip
    nu_err = [float(e) for e in robust_spread(draws)]
    negative = float(np.mean(np.any(~np.isfinite(boots[:, 1]), axis=1)))
    return WidthExponent(n, value[0], err[0], bsd, value[1], err[1], value[2], err[2],
                         fits[0][0], nu_err[0], fits[0][1], int(keep.sum() - 2), fits[1][0],
                         nu_err[1], fits[1][1], negative)  # fmt: skip


@dataclass(frozen=True)
class CorrectedFit:
    """``y(n) = p_c + a n^(-1/nu) (1 + b n^-omega)`` with nu and omega given, weighted least
    squares.

    Attributes
    ----------
    omega : float
        The correction's exponent (NaN: no correction, ``b = 0``).
    n_min : float
        The smallest size fitted.
    p_c, p_c_err : float
        The limit and its error (nu's error included where given).
    chi2 : float
    dof : int
    p_value : float
    acceptable : bool
        As :func:`allowed`.
    """

    omega: float
    n_min: float
    p_c: float
    p_c_err: float
    chi2: float
    dof: int
    p_value: float
    acceptable: bool


def fit_corrected(
    n,
    y,
    err,
    nu: float,
    omega: float | None = None,
    nu_err: float = 0.0,
    n_min: float = 0,
) -> CorrectedFit:
    """A threshold's limit with a known exponent and one correction to scaling.

    Parameters
    ----------
    n, y, err : (K,) float
        Sizes, thresholds and their standard errors (independent between sizes).
    nu : float
        The correlation-length exponent of this transition (not another's).
    omega : float, optional
        The correction's exponent; None: no correction (``b = 0``).
    nu_err : float
        Standard error of ``nu``: widens ``p_c_err`` by half the change of p_c between
        ``nu - nu_err`` and ``nu + nu_err``.
    n_min : float
        Sizes below are left out.

    Returns
    -------
    CorrectedFit
        NaN where fewer sizes than parameters remain.

    Notes
    -----
    With nu and omega given the law is linear in ``(p_c, a, a b)``: weighted least squares,
    errors from the given ones (not rescaled by the chi-square).
    """
    n, y, err = (np.asarray(a, float) for a in (n, y, err))
    keep = (n >= n_min) & np.isfinite(y) & np.isfinite(err) & (err > 0)
    n, y, err = n[keep], y[keep], err[keep]
    k = 2 if omega is None else 3
    if n.size < k:
        return CorrectedFit(np.nan if omega is None else omega, n_min, np.nan, np.nan, np.nan, 0,
                            np.nan, False)  # fmt: skip

    def solve(nu_):
        cols = [np.ones_like(n), n ** (-1 / nu_)]
        if omega is not None:
            cols.append(n ** (-1 / nu_ - omega))
        X, W = np.column_stack(cols), 1 / err**2
        cov = np.linalg.inv(X.T @ (W[:, None] * X))
        beta = cov @ (X.T @ (W * y))
        return float(beta[0]), float(np.sqrt(cov[0, 0])), float(np.sum(W * (y - X @ beta) ** 2))

    p_c, p_err, chi2 = solve(nu)
    if nu_err:
        p_err = float(np.hypot(p_err, 0.5 * abs(solve(nu + nu_err)[0] - solve(nu - nu_err)[0])))
    dof = int(n.size - k)
    p, ok = allowed(chi2, dof)
    return CorrectedFit(np.nan if omega is None else omega, n_min, p_c, p_err, chi2, dof, p, ok)


@dataclass(frozen=True)
class CorrectedLimit:
    """A threshold from :func:`fit_corrected` over a range of omega and of smallest sizes.

    Attributes
    ----------
    fits : tuple of CorrectedFit
        One per (smallest size, omega), the smallest sizes outermost.
    value, stat : float
        The reference fit's p_c and its error: one correction at ``omega_ref`` over every
        size.
    syst : float
        The largest distance from ``value`` of another allowed fit's p_c: the systematic of
        the correction's unknown exponent (and of the sizes it is trusted from).
    low, high : float
        The range of the allowed fits' p_c.
    allowed : int
        How many fits the data allow (of ``len(fits)``).
    """

    fits: tuple
    value: float
    stat: float
    syst: float
    low: float
    high: float
    allowed: int


def corrected_limit(
    n,
    y,
    err,
    nu: float,
    nu_err: float,
    omegas,
    omega_ref: float,
    n_mins=(0,),
) -> CorrectedLimit:
    """:func:`fit_corrected` for each omega of ``omegas`` (None: no correction) and each
    smallest size of ``n_mins``, summarised as a value, its statistical error and the
    systematic of the fit forms the data allow.

    Parameters
    ----------
    n, y, err : (K,) float
        Sizes, thresholds, errors.
    nu, nu_err : float
        The transition's own exponent and its error.
    omegas : sequence of float or None
        The correction exponents tried (fixed before the fits are seen).
    omega_ref : float
        The reference fit's omega (with the smallest of ``n_mins``).
    n_mins : sequence of float
        Smallest sizes tried.

    Returns
    -------
    CorrectedLimit
    """
    fits = tuple(fit_corrected(n, y, err, nu, w, nu_err, m) for m in n_mins for w in omegas)
    ref = fit_corrected(n, y, err, nu, omega_ref, nu_err, min(n_mins))
    ok = [f.p_c for f in fits if f.acceptable and np.isfinite(f.p_c)]
    syst = max((abs(v - ref.p_c) for v in ok), default=0.0)
    return CorrectedLimit(fits, ref.p_c, ref.p_c_err, float(syst), min(ok, default=np.nan),
                          max(ok, default=np.nan), len(ok))  # fmt: skip


@dataclass(frozen=True, eq=False)
class BinomialWidths:
    """Threshold widths against the binomial bond-count noise alone.

    Attributes
    ----------
    total, total_err : (K,) float
        Standard deviation of each size's thresholds and its bootstrap error.
    binomial : (K,) float
        ``sqrt(binomial_variance)`` at each size's median threshold.
    ratio, ratio_err : (K,) float
        ``total / binomial`` and its error.
    chi2 : float
        Of ``total = binomial`` over the sizes (``dof`` = K): small when the widths are the
        counting noise of the bonds present at each p, with nothing left for a geometric part.
    dof : int
    p_value : float
    """

    total: np.ndarray
    total_err: np.ndarray
    binomial: np.ndarray
    ratio: np.ndarray
    ratio_err: np.ndarray
    chi2: float
    dof: int
    p_value: float


def width_excess(total, total_err, binomial) -> tuple[float, int, float]:
    """How well widths equal their binomial part alone.

    Parameters
    ----------
    total, total_err : (K,) float
        Standard deviations of the thresholds and their errors.
    binomial : (K,) float
        The binomial part, ``sqrt(binomial_variance)``.

    Returns
    -------
    chi2 : float
        Of ``total = binomial`` over the sizes with finite values.
    dof : int
        Those sizes.
    p_value : float
        Of the chi-square (NaN without sizes).
    """
    t, e, b = (np.asarray(a, float) for a in (total, total_err, binomial))
    ok = np.isfinite(t) & np.isfinite(e) & (e > 0) & np.isfinite(b)
    chi2 = float(np.sum(((t[ok] - b[ok]) / e[ok]) ** 2))
    dof = int(ok.sum())
    return chi2, dof, float(stats.chi2.sf(chi2, dof)) if dof else np.nan


def widths_against_binomial(
    thresholds: list,
    sites,
    p_t: float = 0.0,
    efficacy: float = 0.0,
    n_boot: int = 300,
    rng: np.random.Generator | None = None,
) -> BinomialWidths:
    """The spread of per-sample thresholds at each size beside the binomial part alone.

    Parameters
    ----------
    thresholds : list of K (S_k,) float arrays
        Per-sample thresholds along p_r (NaN: never rigid, left out).
    sites : (K,) int
        Bond sites M of the lattice at each size.
    p_t, efficacy : float
        As :func:`binomial_variance` (0: rods only).
    n_boot : int
        Bootstrap replicas of each size's samples.
    rng : numpy.random.Generator, optional

    Returns
    -------
    BinomialWidths

    Notes
    -----
    A width that decays as ``n^(-1/nu)`` measures nu only where the geometric part
    dominates; where the total equals the binomial part, ``M^(-1/2) = n^(-d/2)``, its
    decay is the counting of bonds and says nothing of a correlation length.
    """
    t = [np.asarray(a, float) for a in thresholds]
    t = [a[np.isfinite(a)] for a in t]
    rng = rng or np.random.default_rng(13)
    total = np.array([np.std(a, ddof=1) if a.size > 1 else np.nan for a in t])
    boots = np.array([[np.std(a[rng.integers(0, a.size, a.size)], ddof=1) if a.size > 1
                       else np.nan for a in t] for _ in range(n_boot)])  # fmt: skip
    err = robust_spread(boots) if n_boot > 1 else np.full(len(t), np.nan)
    centres = [float(np.median(a)) if a.size else np.nan for a in t]
    binom = np.sqrt([binomial_variance(c, p_t, efficacy, int(m))
                     for c, m in zip(centres, sites, strict=True)])  # fmt: skip
    chi2, dof, p = width_excess(total, err, binom)
    return BinomialWidths(total, err, binom, total / binom, err / binom, chi2, dof, p)


@dataclass(frozen=True)
class ExponentFit:
    """``y_inf + a n^-x`` with x given, weighted least squares.

    Attributes
    ----------
    n_min : float
        The smallest size fitted.
    x : float
        The exponent.
    y_inf, y_inf_err : float
        The limit and its error.
    chi2 : float
    dof : int
    p_value : float
    acceptable : bool
        As :func:`allowed`.
    """

    n_min: float
    x: float
    y_inf: float
    y_inf_err: float
    chi2: float
    dof: int
    p_value: float
    acceptable: bool


@dataclass(frozen=True)
class Envelope:
    """A limit over every exponent the data allow.

    Attributes
    ----------
    fits : tuple of ExponentFit
        One per (smallest size, exponent).
    value, err : float
        The centre and half-width of the union of the allowed fits' intervals
        ``y_inf +- y_inf_err``: an error that holds the statistical one and the unknown
        exponent's together (NaN when no fit is allowed).
    low, high : float
        That union's ends.
    x_low, x_high : float
        The smallest and largest exponent allowed (at any smallest size).
    allowed : int
    """

    fits: tuple
    value: float
    err: float
    low: float
    high: float
    x_low: float
    x_high: float
    allowed: int


def exponent_envelope(n, y, err, xs, n_mins=(0,)) -> Envelope:
    """The limit n -> infinity of ``y(n) = y_inf + a n^-x`` for an exponent known only to lie
    in a range.

    Parameters
    ----------
    n, y, err : (K,) float
        Sizes, values and standard errors (independent between sizes).
    xs : (G,) float
        The exponents the physics allows (declared before the fits).
    n_mins : sequence of float
        Smallest sizes tried.

    Returns
    -------
    Envelope

    Notes
    -----
    Each x gives a linear fit; an x the data reject (:func:`allowed`) is dropped, and the
    answer is every value some allowed fit leaves within one error. Unlike a fit with a free
    exponent, whose error curvature understates the spread at few sizes, and unlike a fit at
    one assumed exponent, it does not hide how far p_c moves with the exponent.
    """
    n, y, err = (np.asarray(a, float) for a in (n, y, err))
    ok = np.isfinite(y) & np.isfinite(err) & (err > 0)
    n, y, err = n[ok], y[ok], err[ok]
    fits = []
    for m in n_mins:
        keep = n >= m
        if keep.sum() < 2:
            continue
        nn, yy, W = n[keep], y[keep], 1 / err[keep] ** 2
        for x in np.asarray(xs, float):
            X = np.column_stack([np.ones(nn.size), nn**-x])
            cov = np.linalg.inv(X.T @ (W[:, None] * X))
            beta = cov @ (X.T @ (W * yy))
            chi2 = float(np.sum(W * (yy - X @ beta) ** 2))
            dof = int(nn.size - 2)
            p, ok_ = allowed(chi2, dof)
            fits.append(ExponentFit(float(m), float(x), float(beta[0]), float(np.sqrt(cov[0, 0])),
                                    chi2, dof, p, ok_))  # fmt: skip
    good = [f for f in fits if f.acceptable]
    if not good:
        return Envelope(tuple(fits), *(np.nan,) * 6, 0)
    lo = min(f.y_inf - f.y_inf_err for f in good)
    hi = max(f.y_inf + f.y_inf_err for f in good)
    return Envelope(tuple(fits), 0.5 * (lo + hi), 0.5 * (hi - lo), lo, hi,
                    min(f.x for f in good), max(f.x for f in good), len(good))  # fmt: skip
