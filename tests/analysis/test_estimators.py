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
