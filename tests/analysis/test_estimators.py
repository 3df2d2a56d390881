"""Estimators recover known parameters on synthetic data."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from tensegrity_rigidity.analysis import estimators as an
from tensegrity_rigidity.analysis.estimators import (
    contour_slope,
    critical_point,
    fit_collapse,
    fit_energy_power_law,
    paired_bootstrap,
    paired_derivative,
    resampler,
    wilson,
)


def test_wilson_interval_known_values():
    p, lo, hi = wilson(5, 10)
    assert p == 0.5
    assert lo == pytest.approx(0.2366, abs=1e-4) and hi == pytest.approx(0.7634, abs=1e-4)
    _, lo0, hi0 = wilson(0, 20)
    assert lo0 == pytest.approx(0.0, abs=1e-12) and 0 < hi0 < 0.2


@pytest.mark.parametrize("lam", [0.37, 0.5, 0.67])
def test_collapse_fit_recovers_lambda(lam):
    rng = np.random.default_rng(int(lam * 100))
    s = 300
    x_star = rng.normal(0.62, 0.03, s)  # per-sample threshold in p_r + lam p_t
    pr, pt = np.meshgrid(np.linspace(0.35, 0.85, 26), [0.0, 0.1, 0.2, 0.3])
    keep = (pr + pt <= 1).ravel()
    pr, pt = pr.ravel()[keep], pt.ravel()[keep]
    y = (pr[None] + lam * pt[None]) > x_star[:, None]
    fit = fit_collapse(y, pr, pt, n_boot=60, rng=np.random.default_rng(1))
    assert abs(fit.lam - lam) <= 3 * fit.lam_err
    assert fit.lam_err < 0.02
    assert fit.x0 == pytest.approx(0.62, abs=0.01)


def _logistic_thresholds(rng, S, lam, p_t, x0=0.62, w=0.02):
    """(S, J) thresholds along p_r with P(p_r, p_t) = F((p_r + lam p_t - x0) / w) exactly, NaN
    above the path's end 1 - p_t (never rigid there)."""
    t = x0 + w * rng.logistic(size=(S, 1)) - lam * np.asarray(p_t)[None]
    return np.where(t > 1 - np.asarray(p_t)[None], np.nan, t)


@pytest.mark.parametrize("lam", [0.37, 0.5, 0.67])
def test_threshold_collapse_fit_recovers_lambda_x0_and_w(lam):
    rng = np.random.default_rng(int(lam * 100) + 1)
    p_t = np.array([0.0, 0.3])
    t = _logistic_thresholds(rng, 300, lam, p_t)
    fit = an.fit_collapse_thresholds(t, p_t, n_boot=60, rng=np.random.default_rng(1))
    assert abs(fit.lam - lam) <= 3 * fit.lam_err and fit.lam_err < 0.01
    assert abs(fit.x0 - 0.62) <= 3 * fit.x0_err and abs(fit.w - 0.02) <= 3 * fit.w_err


def test_threshold_collapse_fit_censors_never_rigid_samples():
    """Samples that never become rigid on the path carry information (their threshold lies
    beyond its end): dropping them biases x0 low; censoring them does not."""
    rng = np.random.default_rng(11)
    p_t = np.array([0.0, 0.1])
    t = _logistic_thresholds(rng, 400, 1.0, p_t, x0=0.99, w=0.02)  # 2 in 5 never rigid
    assert 0.25 < np.isnan(t).mean() < 0.6
    fit = an.fit_collapse_thresholds(t, p_t, n_boot=40, rng=np.random.default_rng(2))
    assert abs(fit.x0 - 0.99) <= 3 * fit.x0_err and abs(fit.lam - 1.0) <= 3 * fit.lam_err
    kept = t[np.all(np.isfinite(t), axis=1)]
    dropped = an.fit_collapse_thresholds(kept, p_t, n_boot=0)
    assert dropped.x0 < fit.x0 - 0.01


def test_threshold_collapse_fit_reads_intervals_as_intervals():
    """A threshold known only to lie in (lo, hi] (undecided probes) enters as that interval:
    narrow intervals around the exact thresholds give the exact fit, and the fit follows the
    intervals, not the estimate written beside them."""
    rng = np.random.default_rng(12)
    p_t = np.array([0.0, 0.3])
    t = _logistic_thresholds(rng, 200, 0.45, p_t)
    exact = an.fit_collapse_thresholds(t, p_t, n_boot=0)
    narrow = an.fit_collapse_thresholds(t, p_t, t - 1e-9, t + 1e-9, n_boot=0)
    assert narrow.lam == pytest.approx(exact.lam, abs=1e-6)
    # the estimate of an interval is not read (but for the optimiser's start)
    lo, hi = t - 0.004, t + 0.004
    a = an.fit_collapse_thresholds(t, p_t, lo, hi, n_boot=0)
    b = an.fit_collapse_thresholds(t + 0.003, p_t, lo, hi, n_boot=0)
    assert b.lam == pytest.approx(a.lam, abs=1e-7) and b.x0 == pytest.approx(a.x0, abs=1e-7)
    assert abs(a.lam - exact.lam) < 0.01 and a.w < exact.w  # the intervals' width is not noise


def test_a_contrast_of_collapse_fits_refits_the_same_samples():
    """Two systems on the same samples share their rods-only thresholds (p_t = 0) and the
    disorder: the contrast's paired error is well below the two errors added in quadrature."""
    rng = np.random.default_rng(13)
    p_t = np.array([0.0, 0.3])
    base = 0.62 + 0.02 * rng.logistic(size=200)  # the same disorder in both systems
    rods = base + 0.005 * rng.logistic(size=200)
    a = np.column_stack([rods, base - 0.4 * 0.3 + 0.005 * rng.logistic(size=200)])
    b = np.column_stack([rods, base - 0.6 * 0.3 + 0.005 * rng.logistic(size=200)])
    c = an.collapse_contrast([(a, a, a), (b, b, b)], [1.0, -1.0], p_t, n_boot=60,
                             rng=np.random.default_rng(3))  # fmt: skip
    fa, fb = (an.fit_collapse_thresholds(x, p_t, n_boot=60) for x in (a, b))
    assert c.value == pytest.approx(fa.lam - fb.lam, abs=1e-12)
    assert abs(c.value + 0.2) <= 3 * c.err
    assert c.err < 0.8 * np.hypot(fa.lam_err, fb.lam_err)


def test_power_law_fit_recovers_exponent():
    rng = np.random.default_rng(3)
    p = np.linspace(0.5, 0.9, 30)
    e = np.where(p > 0.6, 700 * np.clip(p - 0.6, 1e-12, None) ** 1.5, 0.0)
    e *= np.exp(rng.normal(0, 0.02, p.size))
    fit = fit_energy_power_law(p, e, 0.6, max_distance=0.3)
    assert abs(fit.alpha - 1.5) <= 3 * fit.alpha_err
    assert fit.beta == pytest.approx(np.log(700), abs=0.1)


def test_paired_derivative_and_critical_point():
    rng = np.random.default_rng(4)
    thr = rng.normal(0.6, 0.05, 4000)
    d = paired_derivative(thr < 0.58, thr < 0.62, 0.02)
    exact = np.exp(-0.5 * (0 / 0.05) ** 2) / (0.05 * np.sqrt(2 * np.pi))  # density at the mean
    assert abs(d.value - exact) <= 4 * d.err
    pc, err = critical_point(thr)
    assert abs(pc - 0.6) <= 4 * err


def test_resampler_without_groups_draws_the_rows_it_always_drew():
    draw = resampler(7, rng=np.random.default_rng(5))
    ref = np.random.default_rng(5)
    for _ in range(3):
        assert np.array_equal(draw(), ref.integers(0, 7, 7))


def test_resampler_draws_whole_groups():
    groups = np.array([3, 1, 3, 2, 1, 2])  # three units of two rows, interleaved
    draw = resampler(6, groups, np.random.default_rng(0))
    for _ in range(20):
        idx = draw()
        assert idx.size == 6
        picked = groups[idx]
        # every unit drawn brings both of its rows, once per draw
        for g in np.unique(picked):
            rows = idx[picked == g]
            assert sorted(set(rows)) == sorted(np.flatnonzero(groups == g))
            assert rows.size % 2 == 0
    with pytest.raises(ValueError, match="shape"):
        resampler(5, groups)


def test_the_same_samples_under_three_strains_are_one_unit_each():
    """Rods-only thresholds do not depend on the strain: pooled over three strains they are the
    same samples three times, and their error is that of one copy, not sqrt(3) smaller."""
    rng = np.random.default_rng(8)
    t = rng.normal(0.66, 0.01, 300)
    tripled, units = np.tile(t, 3), np.tile(np.arange(t.size), 3)
    pc1, err1 = critical_point(t)
    pc3, err3 = critical_point(tripled, groups=units)
    _, naive = critical_point(tripled)
    assert pc3 == pc1
    assert 0.8 < err3 / err1 < 1.25
    assert naive / err1 < 0.75  # what resampling rows as independent samples reports

    # the collapse fit, the contour slope and a paired bootstrap the same way
    x_star = rng.normal(0.62, 0.03, 200)
    pr, pt = np.meshgrid(np.linspace(0.4, 0.85, 19), [0.0, 0.3])
    pr, pt = pr.ravel(), pt.ravel()
    y = (pr[None] + 0.5 * pt[None]) > x_star[:, None]
    y3, g3 = np.vstack([y, y, y]), np.tile(np.arange(y.shape[0]), 3)
    one = fit_collapse(y, pr, pt, n_boot=60)
    three = fit_collapse(y3, pr, pt, n_boot=60, groups=g3)
    assert three.lam == pytest.approx(one.lam, abs=1e-6) and three.n_samples == 200
    assert 0.7 < three.lam_err / one.lam_err < 1.4
    thr = np.column_stack([x_star, x_star - 0.5 * 0.3])
    c1 = contour_slope(thr, np.array([0.0, 0.3]), n_boot=100)
    c3 = contour_slope(np.vstack([thr] * 3), np.array([0.0, 0.3]), n_boot=100, groups=g3)
    assert c3.value == pytest.approx(c1.value)
    assert 0.7 < c3.err / c1.err < 1.4
    est = paired_bootstrap(np.mean, tripled, tripled + 0.01, n_boot=200, groups=units)
    est1 = paired_bootstrap(np.mean, t, t + 0.01, n_boot=200)
    assert 0.8 < est.a_err / est1.a_err < 1.25


@given(
    st.lists(
        st.tuples(
            st.floats(0, 1e8),  # the true value
            st.floats(0, 1),  # its lower bound, as a fraction of it
            st.sampled_from(["known", "bounded", "unknown"]),
        ),
        min_size=1,
        max_size=15,
    )
)
def test_the_median_bracket_holds_the_median_of_the_true_values(samples):
    """Whatever the true values of the samples known only from below (or not at all), their
    median lies in :func:`median_bracket`'s interval."""
    from tensegrity_rigidity.analysis.estimators import median_bracket

    true = np.array([x for x, _, _ in samples])
    values = np.array([x if how == "known" else np.nan for x, _, how in samples])
    lower = np.array([x * f if how == "bounded" else np.nan for x, f, how in samples])
    low, high = median_bracket(values, lower)
    median = float(np.median(true))
    assert low <= median * (1 + 1e-12) and median <= high * (1 + 1e-12)
    if np.all([how == "known" for _, _, how in samples]):
        assert low == high == median


def test_wilson_is_scipy_s_and_the_closed_form():
    """wilson() is SciPy's binomtest(...).proportion_ci(method="wilson"), and gives the closed
    form of the score interval that it replaced (to round-off), NaN where n = 0."""
    from scipy.stats import binomtest

    from tensegrity_rigidity.analysis.binomial import wilson as wilson_

    k, n, z = np.array([0, 1, 5, 10, 400, 3]), np.array([10, 10, 10, 10, 4000, 0]), 1.96
    p, lo, hi = wilson_(k, n, z)
    with np.errstate(invalid="ignore", divide="ignore"):
        q = k / n
        centre = (q + z**2 / (2 * n)) / (1 + z**2 / n)
        half = z * np.sqrt(q * (1 - q) / n + z**2 / (4 * n**2)) / (1 + z**2 / n)
    assert np.allclose(lo, centre - half, atol=1e-14, equal_nan=True)
    assert np.allclose(hi, centre + half, atol=1e-14, equal_nan=True)
    assert np.isnan(p[-1]) and np.isnan(lo[-1])
    ci = binomtest(5, 10).proportion_ci(confidence_level=0.95, method="wilson")
    assert wilson_(5, 10, 1.959963984540054)[1:] == pytest.approx((ci.low, ci.high), abs=1e-12)


def test_one_estimate_type_and_one_bootstrap_helper():
    from tensegrity_rigidity.analysis import bootstrap

    assert an.Estimate is bootstrap.Estimate
    assert not hasattr(an, "Derivative") and not hasattr(an, "Location")
    # the helper draws what the hand-written loops drew: rng.integers(0, S, S) per replica
    got = bootstrap.replicas(lambda idx: idx.tolist(), 5, 3, np.random.default_rng(4))
    rng = np.random.default_rng(4)
    assert got == [rng.integers(0, 5, 5).tolist() for _ in range(3)]
    # groups are drawn whole
    groups = np.array([0, 0, 1, 1, 2, 2])
    for idx in bootstrap.replicas(np.asarray, 6, 5, np.random.default_rng(1), groups):
        assert all((groups[idx] == g).sum() % 2 == 0 for g in range(3))
