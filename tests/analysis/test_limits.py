"""Limits with their systematics (analysis.limits) on synthetic data with known answers.

A finite limit and a power law to zero are drawn from known laws and recognised by the rule
fixed in advance; the binomial part of a threshold's variance is checked against a Monte Carlo
of site counts; the corrected fit recovers p_c with a known nu. Seeds are fixed.
"""

from __future__ import annotations

import numpy as np
import pytest

from tensegrity_rigidity.analysis import limits

SIZES = np.array([8.0, 16, 32, 64, 128])


def noisy(truth, err, seed):
    return truth + np.random.default_rng(seed).normal(0.0, err)


# --------------------------------------------------------------------------- laws


def test_a_finite_limit_is_recovered_and_the_power_law_to_zero_rejected():
    err = np.full(SIZES.size, 0.002)
    y = noisy(0.3 + 0.5 * SIZES**-0.8, err, 1)
    lim = limits.limit_laws(SIZES, y, err, rng=np.random.default_rng(2))
    finite, zero = lim.fits["finite"], lim.fits["zero"]
    assert abs(finite.y_inf - 0.3) <= 3 * finite.y_inf_err
    assert finite.acceptable and not zero.acceptable
    assert lim.law == "finite" and lim.value == finite.y_inf
    assert lim.syst == 0.0  # no other law allowed
    assert limits.vanishing_verdict(lim) == "finite"


def test_a_power_law_to_zero_is_recognised_with_its_exponent():
    err = 0.02 * 0.5 * SIZES**-0.6  # 2 % errors
    y = noisy(0.5 * SIZES**-0.6, err, 5)
    lim = limits.limit_laws(SIZES, y, err, rng=np.random.default_rng(5))
    zero, finite = lim.fits["zero"], lim.fits["finite"]
    assert zero.acceptable and abs(zero.x - 0.6) <= 3 * zero.x_err
    # both laws allowed: the systematic is the distance between their limits
    assert finite.acceptable and lim.syst == pytest.approx(abs(finite.y_inf))
    assert lim.low == min(0.0, finite.y_inf) and lim.high == max(0.0, finite.y_inf)


@pytest.mark.parametrize(("truth", "verdict"), [("zero", "vanishes"), ("finite", "finite")])
def test_the_verdict_is_right_in_most_replicas_and_wrong_in_few(truth, verdict):
    """A power law to zero (2 % errors) and a finite limit 0.05 with a slow correction, over
    replicas of the noise: the rule names the truth in most, the other answer in few."""
    if truth == "zero":
        err = 0.02 * 0.5 * SIZES**-0.6
        mean = 0.5 * SIZES**-0.6
    else:
        err, mean = np.full(SIZES.size, 0.002), 0.05 + 0.5 * SIZES**-0.6
    verdicts = [limits.vanishing_verdict(limits.limit_laws(SIZES, noisy(mean, err, 300 + k), err,
                                                           n_boot=60, rng=np.random.default_rng(k)))
                for k in range(60)]  # fmt: skip
    other = {"vanishes": "finite", "finite": "vanishes"}[verdict]
    assert verdicts.count(verdict) >= 0.8 * len(verdicts)
    assert verdicts.count(other) <= 0.05 * len(verdicts)


@pytest.mark.parametrize("law", ["zero", "finite"])
def test_a_true_law_is_allowed_at_the_declared_rate(law):
    """Over replicas of the noise, the true law is rejected in about ACCEPT_P of them (its
    chi-square, refined between grid points, is not inflated by the grid's step)."""
    if law == "zero":
        err = 0.02 * 0.5 * SIZES**-0.6
        truth = 0.5 * SIZES**-0.6
    else:
        err, truth = np.full(SIZES.size, 0.002), 0.3 + 0.5 * SIZES**-0.8
    fits = [limits.fit_law(law, SIZES, noisy(truth, err, k), err, n_boot=2) for k in range(300)]
    rejected = 1 - np.mean([f.acceptable for f in fits])
    # binomial: 300 replicas at 5 % give 15 +- 3.8 rejections
    assert rejected <= limits.ACCEPT_P + 3 * np.sqrt(0.05 * 0.95 / 300)


def test_few_sizes_cannot_decide_between_the_laws():
    """Three sizes of a slowly decaying series: both laws are allowed and the finite limit is
    not two errors from zero, so the verdict is 'undetermined', not 'vanishes'."""
    n = SIZES[:3]
    err = np.full(3, 0.01)
    y = noisy(0.05 + 0.3 * n**-0.5, err, 5)
    lim = limits.limit_laws(n, y, err, rng=np.random.default_rng(6))
    assert lim.fits["finite"].dof == 0 and lim.fits["finite"].acceptable
    assert limits.vanishing_verdict(lim) in ("undetermined", "vanishes")
    assert np.isfinite(lim.syst) and lim.low <= lim.value <= lim.high


def test_a_series_no_law_fits_says_so():
    err = np.full(SIZES.size, 0.001)
    y = np.array([0.5, 0.3, 0.5, 0.3, 0.5])
    lim = limits.limit_laws(SIZES, y, err, laws=("finite", "zero", "constant"))
    assert not any(f.acceptable for f in lim.fits.values())
    assert limits.vanishing_verdict(lim) == "no law fits"
    assert lim.law == "" and np.isnan(lim.value) and np.isnan(lim.syst) and np.isnan(lim.low)


def test_a_rejected_reference_law_gives_no_value_and_an_allowed_one_does():
    """Four sizes alternating by 1.2 errors about 0.5: a constant is allowed (chi-square 5.8
    with 3 degrees of freedom), the finite law is not (the same misfit on 1): the limit is the
    constant's, not the rejected law's, with no systematic from the rejected one."""
    n, err = np.array([4.0, 6, 8, 10]), np.full(4, 0.002)
    y = 0.5 + np.array([0.0024, -0.0024, 0.0024, -0.0024])
    lim = limits.limit_laws(n, y, err, laws=("finite", "constant"), n_boot=50)
    assert not lim.fits["finite"].acceptable and lim.fits["constant"].acceptable
    assert lim.law == "constant" and lim.value == pytest.approx(0.5) and lim.syst == 0.0


def test_the_finite_limit_errors_are_calibrated():
    """Coverage of the truth by +- 2 errors over replicas of the noise (nominal 95 %)."""
    err = np.full(SIZES.size, 0.003)
    truth = 0.6 - 0.2 * SIZES**-0.9
    hits = []
    for k in range(60):
        f = limits.fit_law("finite", SIZES, noisy(truth, err, 100 + k), err, n_boot=100,
                           rng=np.random.default_rng(k))  # fmt: skip
        hits.append(abs(f.y_inf - 0.6) <= 2 * f.y_inf_err)
    assert np.mean(hits) >= 0.85


def test_a_constant_beside_a_finite_limit_gives_the_spread_as_systematic():
    err = np.full(SIZES.size, 0.005)
    y = noisy(np.full(SIZES.size, 0.5), err, 7)
    lim = limits.limit_laws(SIZES, y, err, laws=("finite", "constant"),
                            rng=np.random.default_rng(8))  # fmt: skip
    const = lim.fits["constant"]
    assert const.acceptable and const.y_inf == pytest.approx(np.average(y, weights=err**-2))
    assert lim.syst == pytest.approx(abs(const.y_inf - lim.value))


def test_unknown_law_is_refused():
    with pytest.raises(ValueError, match="unknown law"):
        limits.fit_law("linear", SIZES, SIZES, SIZES)


def test_the_robust_spread_ignores_a_few_runaway_replicas():
    rng = np.random.default_rng(9)
    draws = rng.normal(0.0, 1.0, 4000)
    draws[:40] = 1e6  # 1 % of refits run off
    assert limits.robust_spread(draws) == pytest.approx(1.0, rel=0.08)
    assert np.std(draws) > 1e4


# --------------------------------------------------------------------------- binomial part


def order_statistic_thresholds(m_star, sites, rng):
    """Rods only: the threshold of each sample is its m*-th smallest uniform of M sites."""
    return np.array([np.sort(rng.random(sites))[m - 1] for m in m_star])


@pytest.mark.parametrize("geometric", [0.0, 0.01])
def test_binomial_variance_matches_a_monte_carlo_of_site_counts_rods_only(geometric):
    rng = np.random.default_rng(10)
    sites, samples = 3 * 24**2, 3000
    x = np.clip(rng.normal(0.66, geometric, samples), 0.0, 1.0) if geometric else np.full(
        samples, 0.66)  # fmt: skip
    m_star = np.maximum(1, np.round(x * sites).astype(int))
    t = order_statistic_thresholds(m_star, sites, rng)
    expected = np.var(m_star / sites) + limits.binomial_variance(0.66, 0.0, 0.0, sites)
    # the sample variance of S normal draws has relative error sqrt(2 / S) = 2.6 %
    assert np.var(t, ddof=1) == pytest.approx(expected, rel=4 * np.sqrt(2 / samples))
    assert limits.binomial_variance(0.66, 0.0, 0.0, sites) == pytest.approx(0.66 * 0.34 / sites)


def weighted_count_thresholds(sites, p_t, lam, level, samples, rng):
    """Sites kinded as the model places them (rod: u < p_r; one-sided: p_r <= u < p_r + p_t);
    a sample is rigid once N_r + lam N_t reaches ``level`` sites; its threshold along p_r."""
    out = np.empty(samples)
    for k in range(samples):
        u = rng.random(sites)
        # X(p_r) gains 1 - lam where a site turns rod, lam where one enters [p_r, p_r + p_t)
        pos = np.concatenate([u, u[u >= p_t] - p_t])
        gain = np.concatenate([np.full(sites, 1 - lam), np.full(int(np.sum(u >= p_t)), lam)])
        order = np.argsort(pos, kind="stable")
        x = lam * np.sum(u < p_t) + np.cumsum(gain[order])
        out[k] = pos[order][np.searchsorted(x, level - 1e-9)]
    return out


def test_binomial_variance_matches_a_monte_carlo_with_one_sided_elements():
    rng = np.random.default_rng(11)
    sites, samples, p_t, lam = 3 * 16**2, 3000, 0.3, 0.5
    level = (0.45 + lam * p_t) * sites  # the threshold's centre at p_r = 0.45
    t = weighted_count_thresholds(sites, p_t, lam, level, samples, rng)
    assert np.median(t) == pytest.approx(0.45, abs=0.005)
    expected = limits.binomial_variance(0.45, p_t, lam, sites)
    assert np.var(t, ddof=1) == pytest.approx(expected, rel=4 * np.sqrt(2 / samples))
    # the rods-only formula would be wrong here: the one-sided sites add their own counting
    assert abs(limits.binomial_variance(0.45, 0.0, 0.0, sites) / expected - 1) > 0.2


def test_widths_equal_to_the_binomial_part_are_recognised_and_a_geometric_part_is_not():
    rng = np.random.default_rng(12)
    n = np.array([6, 8, 12, 16])
    sites = 3 * n**2
    pure = [order_statistic_thresholds(np.full(400, round(0.66 * m)), m, rng) for m in sites]
    w = limits.widths_against_binomial(pure, sites, n_boot=200, rng=rng)
    assert w.p_value >= limits.ACCEPT_P and w.dof == n.size
    assert np.all(np.abs(w.ratio - 1) < 3 * w.ratio_err)
    extra = [order_statistic_thresholds(np.round(rng.normal(0.66, 0.6 * k**-0.85, 400) * m)
             .astype(int), m, rng) for k, m in zip(n, sites, strict=True)]  # fmt: skip
    w = limits.widths_against_binomial(extra, sites, n_boot=200, rng=rng)
    assert w.p_value < 1e-3 and np.all(w.ratio > 1)


def test_width_exponent_of_the_geometric_part():
    """Thresholds whose counts spread as n^(-1/nu) with nu = 1.2, plus the binomial part: the
    fit of the counts' widths recovers nu; the subtraction too, more loosely."""
    rng = np.random.default_rng(13)
    n = np.array([8, 12, 16, 24, 32])
    sites = 3 * n**2
    counts = [np.clip(rng.normal(0.66, 0.4 * k ** (-1 / 1.2), 600), 0.01, 0.99) for k in n]
    m_star = [np.maximum(1, np.round(c * m).astype(int))
              for c, m in zip(counts, sites, strict=True)]  # fmt: skip
    t = [order_statistic_thresholds(ms, m, rng) for ms, m in zip(m_star, sites, strict=True)]
    binom = [limits.binomial_variance(0.66, 0.0, 0.0, m) for m in sites]
    c = [ms / m for ms, m in zip(m_star, sites, strict=True)]
    w = limits.width_exponents(n, t, c, binom, n_boot=150, rng=rng)
    assert abs(w.nu - 1.2) <= 3 * w.nu_err and w.nu_err < 0.15
    assert abs(w.nu_sub - 1.2) <= 3 * w.nu_sub_err
    assert np.all(w.binomial < w.total)


# --------------------------------------------------------------------------- corrected fits


NU = 1.1694
OMEGAS = (None, 0.5, 1.0, 1.5, 2.0)


def corrected_series(err, seed, p_c=0.6602741, a=-0.05, b=10.0, omega=1.0):
    n = np.array([32.0, 64, 128, 256, 512, 1024])
    y = p_c + a * n ** (-1 / NU) * (1 + b * n**-omega)
    return n, noisy(y, err, seed)


def test_the_corrected_fit_recovers_p_c_with_a_known_nu():
    err = np.full(6, 3e-5)
    n, y = corrected_series(err, 14)
    right = limits.fit_corrected(n, y, err, NU, omega=1.0)
    assert abs(right.p_c - 0.6602741) <= 3 * right.p_c_err and right.acceptable
    # without the correction the same data reject the law (and its p_c is off)
    none = limits.fit_corrected(n, y, err, NU, omega=None)
    assert not none.acceptable and abs(none.p_c - 0.6602741) > 3 * none.p_c_err


def test_the_corrected_errors_are_calibrated():
    err = np.full(6, 5e-5)
    fits = [limits.fit_corrected(*corrected_series(err, 200 + k), err, NU, omega=1.0)
            for k in range(200)]  # fmt: skip
    p_c = np.array([f.p_c for f in fits])
    stated = np.mean([f.p_c_err for f in fits])
    assert np.mean(np.abs(p_c - 0.6602741) <= 2 * stated) >= 0.9
    assert np.std(p_c, ddof=1) / stated == pytest.approx(1.0, abs=0.15)


def test_the_omega_range_is_the_systematic_and_covers_the_truth():
    """True omega 0.8 is not on the grid: the reference (omega = 1) is off by more than its
    statistical error alone might allow, but within stat + syst."""
    err = np.full(6, 2e-5)
    n, y = corrected_series(err, 15, b=6.0, omega=0.8)
    lim = limits.corrected_limit(n, y, err, NU, 0.0008, OMEGAS, 1.0, n_mins=(32, 64))
    assert len(lim.fits) == 2 * len(OMEGAS)
    assert 0 < lim.allowed <= len(lim.fits)
    assert abs(lim.value - 0.6602741) <= 2 * np.hypot(lim.stat, lim.syst)
    assert lim.syst > 0 and lim.low <= lim.value + 1e-15 and lim.high >= lim.value - 1e-15
    assert lim.syst == pytest.approx(max(lim.value - lim.low, lim.high - lim.value))


def test_nu_error_widens_the_corrected_error():
    err = np.full(6, 3e-5)
    n, y = corrected_series(err, 16)
    sharp = limits.fit_corrected(n, y, err, NU, 1.0)
    wide = limits.fit_corrected(n, y, err, NU, 1.0, nu_err=0.05)
    assert wide.p_c == sharp.p_c and wide.p_c_err > sharp.p_c_err


# --------------------------------------------------------------------------- paired efficacies


def test_paired_efficacies_recover_the_asymmetry_better_than_either_efficacy():
    rng = np.random.default_rng(17)
    samples, p_t = 800, 0.3
    rods = rng.normal(0.66, 0.02, samples)
    shared = rng.normal(0.0, 0.02, samples)  # the same disorder under both strains
    comp = rods - 0.45 * p_t + shared + rng.normal(0.0, 0.003, samples)
    dil = rods - 0.55 * p_t + shared + rng.normal(0.0, 0.003, samples)
    e = limits.paired_efficacies(rods, comp, dil, p_t, n_boot=300, rng=rng)
    assert abs(e.c - 0.45) <= 3 * e.c_err and abs(e.d - 0.55) <= 3 * e.d_err
    assert abs(e.asym - 0.10) <= 3 * e.asym_err and abs(e.asym_mean - 0.10) <= 3 * e.asym_mean_err
    assert e.asym_mean_err < e.c_err / 3 and e.never == 0 and e.samples == samples
    assert e.total == pytest.approx(e.c + e.d)


def test_paired_efficacies_count_samples_never_rigid():
    rods = np.array([0.6, 0.62, 0.64, 0.66])
    comp = np.array([0.5, np.nan, 0.52, 0.55])
    e = limits.paired_efficacies(rods, comp, comp - 0.01, 0.2, n_boot=20)
    assert e.never == 1 and e.samples == 4
    with pytest.raises(ValueError, match="same samples"):
        limits.paired_efficacies(rods, comp[:3], comp, 0.2)


def test_a_limit_the_sizes_do_not_fix_is_not_quoted():
    """A series that falls more slowly than any exponent in range (here log n) pins the finite
    law at the slow end, where its limit runs off: no limit is read from it. A flat series
    pins it there too, and its limit is the constant's."""
    n = np.array([8.0, 12, 16, 24, 32, 64])
    err = np.full(n.size, 0.01)
    slow = limits.limit_laws(n, 1.0 - 0.2 * np.log(n), err, laws=("finite", "constant"),
                             n_boot=20)  # fmt: skip
    assert slow.fits["finite"].acceptable and limits.runaway(slow.fits["finite"])
    assert slow.law == "" and np.isnan(slow.value)
    # A on FCC at n = 4 to 12 against the node count N = n^3 (reports/limit)
    a3 = [0.1199, 0.1254, 0.1213, 0.1175, 0.1210, 0.1174]
    a3_err = [0.0080, 0.0081, 0.0061, 0.0051, 0.0032, 0.0054]
    flat = limits.limit_laws(np.array([4.0, 5, 6, 8, 10, 12]) ** 3, a3, a3_err,
                             laws=("finite", "zero", "constant"), n_boot=20)  # fmt: skip
    assert limits.runaway(flat.fits["finite"])
    assert flat.law == "constant" and flat.value == pytest.approx(0.1201, abs=1e-4)
    assert limits.vanishing_verdict(flat) == "finite"
    fast = limits.limit_laws(n, 0.5 + n**-1.0, err, laws=("finite", "constant"), n_boot=20)
    assert fast.law == "finite" and not limits.runaway(fast.fits["finite"])


def test_a_drift_whose_rate_the_sizes_do_not_fix_quotes_no_constant():
    """lambda_C at n = 4 to 12 (reports/paper-size) rises by 0.025 while the constant is still
    allowed (p = 0.055); the finite law runs off to the slow end and fits better by
    chi-square 7.9 on two degrees of freedom (p = 0.02): the series drifts, and n = 32 and 64
    (0.455, 0.470) lie far above the constant 0.434. No limit is quoted."""
    n = np.array([4.0, 6, 8, 10, 12])
    y = [0.418, 0.4266, 0.4275, 0.4419, 0.4426]
    err = [0.010, 0.0065, 0.0057, 0.0055, 0.0060]
    li = limits.limit_laws(n, y, err, laws=("finite", "constant"), n_boot=20)
    assert li.fits["constant"].acceptable and limits.runaway(li.fits["finite"])
    assert limits.drifts(li.fits["finite"], li.fits["constant"])
    assert li.law == "" and np.isnan(li.value)
    # without the constant among the laws asked for, the drift is tested against it all the same
    assert limits.limit_laws(n, y, err, laws=("finite",), n_boot=20).law == ""
    # a finite limit the sizes fix stays quoted beside the power law to zero (which is not
    # nested in the constant, so it is never tested for a drift)
    fast = 0.07 + 0.5 * n**-1.5
    li = limits.limit_laws(n, fast, err, laws=("finite", "zero", "constant"), n_boot=20)
    assert li.law == "finite" and li.value == pytest.approx(0.07, abs=0.02)


def test_interval_thresholds_widen_every_error_by_half_their_range():
    """A threshold known only as an interval (an undecided probe) enters at its centre; each
    statistic's error adds half its range over the intervals' ends in quadrature, so an
    interval wider than the statistical error cannot leave a verdict resting on its centre."""
    rng = np.random.default_rng(3)
    samples, p_t, half = 200, 0.3, 0.01
    rods = rng.normal(0.66, 0.02, samples)
    shared = rng.normal(0.0, 0.02, samples)
    comp = rods - 0.45 * p_t + shared
    dil = rods - 0.55 * p_t + shared
    exact = limits.paired_efficacies(rods, comp, dil, p_t, n_boot=50, rng=np.random.default_rng(1))
    same = limits.paired_efficacies(rods, comp, dil, p_t, n_boot=50, rng=np.random.default_rng(1),
                                    ends=((rods, rods), (comp, comp), (dil, dil)))  # fmt: skip
    assert same == exact
    widened = limits.paired_efficacies(
        rods, comp, dil, p_t, n_boot=50, rng=np.random.default_rng(1),
        ends=((rods, rods), (comp - half, comp + half), (dil - half, dil + half)))  # fmt: skip
    # A = (median comp - median dil) / p_t spans 2 * half / p_t each way: half-range 2 half / p_t
    assert widened.asym == exact.asym
    assert widened.asym_err == pytest.approx(np.hypot(exact.asym_err, 2 * half / p_t))
    assert widened.asym_mean_err == pytest.approx(np.hypot(exact.asym_mean_err, 2 * half / p_t))
    assert widened.c_err == pytest.approx(np.hypot(exact.c_err, half / p_t))


# --------------------------------------------------------------------------- unknown exponent

XS = np.round(np.arange(0.5, 3.0001, 0.05), 2)
SMALL = np.array([4.0, 6, 8, 10, 12])


def test_the_envelope_covers_the_limit_when_the_exponent_is_unknown():
    """Truth with x = 0.7: a fit at an assumed x = 3 is off by several of its own errors; the
    envelope over the declared range holds the truth, with an error wider than any one fit's."""
    err = np.full(SMALL.size, 0.0008)
    y = noisy(0.494 + 0.02 * SMALL**-0.7, err, 18)
    env = limits.exponent_envelope(SMALL, y, err, XS, n_mins=(4, 6))
    assert env.low <= 0.494 <= env.high and env.value == pytest.approx(0.5 * (env.low + env.high))
    at3 = [f for f in env.fits if f.x == 3.0 and f.n_min == 4][0]
    assert abs(at3.y_inf - 0.494) > 3 * at3.y_inf_err
    assert env.err > max(f.y_inf_err for f in env.fits if f.x == 0.7)
    assert len(env.fits) == 2 * XS.size and env.x_low == 0.5


def test_the_envelope_coverage_over_replicas():
    err = np.full(SMALL.size, 0.001)
    truth = 0.494 + 0.03 * SMALL**-1.3
    envs = [limits.exponent_envelope(SMALL, noisy(truth, err, 400 + k), err, XS)
            for k in range(200)]  # fmt: skip
    assert np.mean([e.low <= 0.494 <= e.high for e in envs]) >= 0.85


def test_an_envelope_without_an_allowed_fit_is_nan():
    err = np.full(SMALL.size, 1e-4)
    env = limits.exponent_envelope(SMALL, np.array([0.5, 0.4, 0.5, 0.4, 0.5]), err, XS)
    assert env.allowed == 0 and np.isnan(env.value) and np.isnan(env.err)
