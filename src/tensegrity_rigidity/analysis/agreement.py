"""Agreement: paired bootstraps of two estimators on the same samples, and the z statistics
by which a measurement is compared with a claim."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import stats

from .bootstrap import replicas


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
    draws = replicas(
        lambda idx: (statistic(a[idx]), statistic(b[idx])), a.shape[0], n_boot, rng, groups
    )
    d = np.array(draws, float).reshape(-1, 2)
    d = d[np.all(np.isfinite(d), axis=1)]
    sd = d.std(axis=0, ddof=1) if len(d) > 1 else np.full(2, np.nan)
    dd = float(np.std(d[:, 1] - d[:, 0], ddof=1)) if len(d) > 1 else np.nan
    return PairedEstimate(float(va), float(sd[0]), float(vb), float(sd[1]), float(vb - va), dd)


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


def chi2_against(ours, err, reference, reference_err) -> tuple[float, int, float]:
    """Chi-square of independent values against references, both with errors.

    Parameters
    ----------
    ours, err : (k,) float
        Our values and their standard errors.
    reference, reference_err : (k,) float
        The reference values and their standard errors.

    Returns
    -------
    chi2 : float
        ``sum(((ours - ref) / sqrt(err^2 + ref_err^2))^2)`` (inf where a difference has no
        error on either side; NaN for k = 0).
    dof : int
        k: the references are not fitted.
    p_value : float
        ``P(chi2_k >= chi2)`` (NaN for k = 0).
    """
    y, e, r, re_ = (np.atleast_1d(np.asarray(a, float)) for a in (ours, err, reference,
                                                                   reference_err))  # fmt: skip
    if not y.size:
        return float("nan"), 0, float("nan")
    delta, sigma = y - r, np.hypot(e, re_)
    with np.errstate(divide="ignore", invalid="ignore"):
        terms = np.where(delta == 0, 0.0, (delta / sigma) ** 2)
    chi2 = float(np.sum(terms))
    return chi2, int(y.size), float(stats.chi2.sf(chi2, y.size))


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


def holm_adjusted(p_values) -> np.ndarray:
    """Holm's step-down adjusted p-values of a family of tests.

    Sorted ascending, the i-th smallest of m p-values (i = 1..m) becomes ``(m - i + 1) p_(i)``,
    made non-decreasing in that order and capped at 1; rejecting where the adjusted value is at
    most alpha controls the family-wise error rate at alpha whatever the tests' dependence.

    Parameters
    ----------
    p_values : (m,) float
        Raw p-values; NaN entries (tests not made) are left out of the family and stay NaN.

    Returns
    -------
    (m,) float
        The adjusted p-values, in the input's order.
    """
    p = np.asarray(p_values, float)
    out = np.full(p.shape, np.nan)
    made = np.flatnonzero(np.isfinite(p))
    m = made.size
    if m == 0:
        return out
    order = made[np.argsort(p[made], kind="stable")]
    scaled = (m - np.arange(m)) * p[order]
    out[order] = np.minimum(np.maximum.accumulate(scaled), 1.0)
    return out
