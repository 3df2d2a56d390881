"""Every estimator of analysis.estimators on synthetic data with a known answer.

Each test draws replicas from a known model (Bernoulli outcomes from a known P, thresholds
from a known distribution, energies from a known power law), checks that the estimate lies
within twice its own stated error of the truth in most replicas (coverage; nominal 95.4 %), and
that the stated error is calibrated: the spread of the estimates over replicas divided by the
mean stated error lies near 1. Replica counts are small so that the suite stays fast; the
bounds (coverage >= 80 to 85 %, ratio within [0.65, 1.5]) allow for that. Seeds are fixed, so
the tests are deterministic.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from scipy.stats import binom, norm

from tensegrity_rigidity.analysis import estimators as an
from tensegrity_rigidity.analysis.fits import _sigmoid


def assert_calibrated(est, err, truth, coverage=0.85, ratio=(0.65, 1.5)):
    """Coverage of truth by est +- 2 err, and spread of est over replicas / mean err."""
    est, err = np.asarray(est, float), np.asarray(err, float)
    truth = np.broadcast_to(np.asarray(truth, float), est.shape)
    covered = np.mean(np.abs(est - truth) <= 2 * err, axis=0)
    spread = np.std(est, axis=0, ddof=1) / np.mean(err, axis=0)
    assert np.all(covered >= coverage), f"coverage {covered}"
    assert np.all((spread >= ratio[0]) & (spread <= ratio[1])), f"spread / error {spread}"


# --------------------------------------------------------------------------- probabilities


@pytest.mark.parametrize("n", [20, 40, 200])
@pytest.mark.parametrize("p", [0.05, 0.3, 0.5])
def test_wilson_interval_has_its_nominal_coverage_exactly(n, p):
    k = np.arange(n + 1)
    _, lo, hi = an.wilson(k, np.full(k.size, n))
    coverage = binom.pmf(k, n, p)[(lo <= p) & (p <= hi)].sum()
    assert coverage >= 0.92  # nominal 0.95; Wilson's known dips stay above 0.92 here


def test_probabilities_from_known_thresholds():
    t = np.array([0.1, 0.5, 0.5, 0.7, np.nan])  # nan: never rigid
    assert an.probability_from_thresholds(t, [0.1, 0.5, 0.51, 1.0]).tolist() == [
        0.0,
        0.2,
        0.6,
        0.8,
    ]
    P, lo, hi = an.probability_curve(t, np.array([0.6]))
    ref = an.wilson(3, 5)
    assert (P[0], lo[0], hi[0]) == pytest.approx(tuple(float(r) for r in ref))
    df = pd.DataFrame({"g": [0, 0, 1, 1, 1], "rigid": [True, False, True, True, False]})
    table = an.rigidity_probability(df, ["g"])
    assert table.k.tolist() == [1, 2] and table.N.tolist() == [2, 3]
    assert table.P.tolist() == pytest.approx([0.5, 2 / 3])


def test_a_sample_rigid_from_the_start_is_rigid_at_p_r_zero():
    """``s* = 0`` (rigid with no event) was counted floppy at p_r = 0, where ``decide`` finds it
    rigid; ``P(0)`` came out too low on a grid that includes 0."""
    t = np.array([0.0, 0.3, np.nan])
    assert an.probability_from_thresholds(t, [0.0, 0.3, 0.5]).tolist() == [1 / 3, 1 / 3, 2 / 3]
    rows = pd.DataFrame({"p_t": [0.4] * 3, "sample": [0, 1, 2], "threshold_p_r": t})
    y, _, _ = an.outcomes_from_thresholds(rows, np.array([0.0]))
    assert y[:, 0].tolist() == [True, False, False]


def test_outcomes_from_thresholds_pair_the_samples():
    rows = pd.DataFrame(
        {
            "p_t": [0.0, 0.0, 0.1, 0.1, 0.1],
            "sample": [1, 2, 1, 2, 3],  # sample 3 missing at p_t = 0: left out everywhere
            "threshold_p_r": [0.6, np.nan, 0.5, 0.55, 0.4],
        }
    )
    y, pr, pt = an.outcomes_from_thresholds(rows, np.array([0.55, 0.95]))
    assert pr.tolist() == [0.55, 0.95, 0.55] and pt.tolist() == [0.0, 0.0, 0.1]  # 0.95+0.1 > 1
    assert y.tolist() == [[False, True, True], [False, False, False]]


# --------------------------------------------------------------------------- S_t / S_r


def _collapse_thresholds(rng, S, lam, p_t):
    """Per-sample thresholds in p_r at each p_t: x* - lam p_t, x* = x0 + sample + point noise.

    P(p_r, p_t) = F(p_r + lam p_t) exactly (F the law of x*), and samples are correlated across
    p_t as with common random numbers.
    """
    x_star = 0.62 + rng.normal(0, 0.025, (S, 1)) + rng.normal(0, 0.015, (S, len(p_t)))
    return x_star - lam * np.asarray(p_t)[None]


def test_collapse_fit_and_contour_slope_are_calibrated():
    lam, p_t = 0.4, np.array([0.0, 0.1, 0.2, 0.3])
    grid = np.arange(0.3, 0.9001, 0.01)
    fit_est, fit_err, con_est, con_err, ml_est, ml_err = [], [], [], [], [], []
    for rep in range(30):
        rng = np.random.default_rng(rep)
        t = _collapse_thresholds(rng, 80, lam, p_t)
        rows = pd.DataFrame(
            {
                "p_t": np.repeat(p_t[None], t.shape[0], 0).ravel(),
                "sample": np.repeat(np.arange(1, t.shape[0] + 1), p_t.size),
                "threshold_p_r": t.ravel(),
            }
        )
        y, pr, pt = an.outcomes_from_thresholds(rows, grid)
        fit = an.fit_collapse(y, pr, pt, n_boot=40, rng=np.random.default_rng(100 + rep))
        fit_est.append(fit.lam)
        fit_err.append(fit.lam_err)
        ml = an.fit_collapse_thresholds(t, p_t, n_boot=40, rng=np.random.default_rng(300 + rep))
        ml_est.append(ml.lam)
        ml_err.append(ml.lam_err)
        c = an.contour_slope(t, p_t, n_boot=100, rng=np.random.default_rng(200 + rep))
        con_est.append(c.value)
        con_err.append(c.err)
    assert_calibrated(fit_est, fit_err, lam)
    assert_calibrated(con_est, con_err, lam)
    assert_calibrated(ml_est, ml_err, lam)


# --------------------------------------------------------------------------- derivatives


def test_paired_derivative_and_slope_are_calibrated():
    mu, sd, x, h = 0.6, 0.05, 0.58, 0.02
    secant = (norm.cdf(x + h, mu, sd) - norm.cdf(x - h, mu, sd)) / (2 * h)
    f = np.linspace(0, 1, 9)
    d_est, d_err, s_est, s_err = [], [], [], []
    for rep in range(40):
        rng = np.random.default_rng(rep)
        thr = rng.normal(mu, sd, 300)
        d = an.paired_derivative(thr < x - h, thr < x + h, h)
        d_est.append(d.value)
        d_err.append(d.err)
        u = rng.random((120, 1))  # comonotone outcomes: y_s(f) = u_s < P(f)
        s = an.paired_slope((u < 0.3 + 0.4 * f[None]).astype(float), f)
        s_est.append(s.value)
        s_err.append(s.err)
    assert_calibrated(d_est, d_err, secant)
    # the grid's P(f) is a step function of u here: its least-squares slope is 0.4 in the mean
    assert_calibrated(s_est, s_err, 0.4)


def test_critical_point_is_calibrated():
    est, err = [], []
    for rep in range(40):
        t = np.random.default_rng(rep).normal(0.6, 0.05, 200)
        pc, e = an.critical_point(t)
        est.append(pc)
        err.append(e)
    assert_calibrated(est, err, 0.6)


def test_energy_power_law_fit_is_calibrated():
    p = np.linspace(0.62, 0.85, 12)
    a_est, a_err, b_est, b_err = [], [], [], []
    for rep in range(40):
        rng = np.random.default_rng(rep)
        e = 700 * (p - 0.6) ** 1.5 * np.exp(rng.normal(0, 0.05, p.size))
        fit = an.fit_energy_power_law(p, e, 0.6, max_distance=0.3)
        a_est.append(fit.alpha)
        a_err.append(fit.alpha_err)
        b_est.append(fit.beta)
        b_err.append(fit.beta_err)
    assert_calibrated(a_est, a_err, 1.5)
    assert_calibrated(b_est, b_err, np.log(700))


def _nested_energies(rng, S, p):
    """Per-sample thresholds t ~ N(0.6125, 0.03) and energies c (p - t)_+^1.5 with one
    amplitude c per sample at every p (nested configurations: correlated points). p_crit lies
    between grid points: on a grid point the estimator is biased (see
    :func:`~tensegrity_rigidity.analysis.estimators.fit_energy_exponent`), which an error
    cannot calibrate."""
    t = rng.normal(0.6125, 0.03, S)
    c = np.exp(rng.normal(0, 0.3, S))[:, None]
    return t, c * np.clip(p[None] - t[:, None], 0, None) ** 1.5


def test_energy_exponent_error_carries_p_crit_and_correlated_points():
    """alpha of the mean energy above the median threshold, both from the same 24 samples: the
    bootstrap error that redraws samples and re-estimates p_crit is calibrated; the
    least-squares error, which takes p_crit as known and the points as independent, is 2 to 3
    times too small (the error the reports quoted before)."""
    p = np.round(np.arange(0.45, 0.951, 0.025), 3)

    def fit(t, e, n_boot):
        return an.fit_energy_exponent(p, e, lambda idx: an.median_threshold(t[idx]), n_boot)

    truth = fit(*_nested_energies(np.random.default_rng(99), 200_000, p), 0).alpha
    est, err, ls = [], [], []
    for rep in range(40):
        f = fit(*_nested_energies(np.random.default_rng(rep + 1000), 24, p), 100)
        est.append(f.alpha)
        err.append(f.alpha_err)
        ls.append(f.alpha_ls_err)
    assert_calibrated(est, err, truth)
    assert np.std(est, ddof=1) / np.mean(ls) > 2
    with pytest.raises(AssertionError):
        assert_calibrated(est, ls, truth)


# --------------------------------------------------------------------------- locations


def test_peak_locations_find_a_known_peak():
    x = np.round(np.arange(0.4, 0.9, 0.025), 3)
    peaks_true = np.array([0.6, 0.55])
    est, err = [], []
    for rep in range(30):
        rng = np.random.default_rng(rep)
        curves = [
            np.exp(-((x[None] - c) ** 2) / (2 * 0.06**2)) * np.exp(rng.normal(0, 1.0, (60, x.size)))
            for c in peaks_true
        ]
        at, cov = an.peak_locations(curves, [x, x], n_boot=100, rng=np.random.default_rng(rep))
        est.append(at)
        err.append(np.sqrt(np.diag(cov)))
        # medians of multiplicative noise peak at the same place
        med, _ = an.peak_locations(curves, [x, x], "median", n_boot=10)
        assert np.all(np.abs(med - peaks_true) <= 0.1)
    assert_calibrated(est, err, peaks_true, coverage=0.8, ratio=(0.5, 1.6))


def test_first_positive_is_the_grid_point_above_the_smallest_threshold():
    x = np.round(np.arange(0.4, 0.9, 0.02), 3)
    for rep in range(20):
        rng = np.random.default_rng(rep)
        t = rng.normal(0.6, 0.04, 30)
        energies = np.clip(x[None] - t[:, None], 0, None)
        loc = an.first_positive(energies, x, n_boot=50)
        assert loc.value == x[x > t.min()][0]
        assert loc.err >= 0.02 / np.sqrt(12) - 1e-12
    # no positive mean anywhere: no p_crit
    assert np.isnan(an.first_positive(np.zeros((5, x.size)), x, n_boot=5).value)


# --------------------------------------------------------------------------- efficacy surface


def test_logistic_fit_recovers_coefficients_and_stays_finite_when_separated():
    X = np.column_stack([np.ones(9), np.linspace(-1, 1, 9)])
    beta = np.array([0.3, 1.5])
    m = np.full(9, 1e6)
    k = m * _sigmoid(X @ beta)
    assert an.fit_logistic(k, m, X) == pytest.approx(beta, abs=1e-3)
    separated = an.fit_logistic(np.array([0, 0, 0, 0, 5, 5, 5, 5, 5.0]), np.full(9, 5.0), X)
    assert np.all(np.isfinite(separated)) and separated[1] > 0


FIG4_FC = np.arange(9) / 8
CENTRE, H_R, H_T = (0.3, 0.6), 0.025, 0.05


def _design():
    pts = [(CENTRE[0], CENTRE[1], f) for f in FIG4_FC]
    pts += [(CENTRE[0] + s * H_R, CENTRE[1], f) for s in (-1, 1) for f in FIG4_FC]
    pts += [(CENTRE[0], CENTRE[1] + s * H_T, f) for s in (-1, 1) for f in FIG4_FC]
    return tuple(np.array(c) for c in zip(*pts, strict=True))


class _Probit:
    """A known P(p_r, p_t, f_c) outside the fitted family: probit link, x0 with a sine.

    P = Phi((p_r + lam(f) p_t - x0(f)) / w), lam = 0.37 + 0.3 f,
    x0 = 0.5556 + 0.1128 f + 0.02 sin(pi f): P runs from 0.2 to 0.8 along f_c at the centre.
    """

    w = 0.04

    def lam(self, f):
        return 0.37 + 0.3 * f

    def x0(self, f):
        return 0.5556 + 0.1128 * f + 0.02 * np.sin(np.pi * f)

    def P(self, p_r, p_t, f):
        return norm.cdf((p_r + self.lam(f) * p_t - self.x0(f)) / self.w)

    def truth(self, f):
        """(S_c + S_s)/S_r, S_c/S_r, S_s/S_r at the centre."""
        p_t = CENTRE[1]
        dz_df = (0.3 * p_t - 0.1128 - 0.02 * np.pi * np.cos(np.pi * f)) / self.w
        S_r, S_t, D = 1 / self.w, self.lam(f) / self.w, dz_df  # common factor phi(z) dropped
        S_c, S_s = S_t + (1 - f) * D / p_t, S_t - f * D / p_t
        return {"sum_rel": (S_c + S_s) / S_r, "S_c_rel": S_c / S_r, "S_s_rel": S_s / S_r}


@pytest.mark.parametrize("coupling", ["common", "independent"])
def test_efficacy_surface_is_calibrated_at_every_f_c_including_the_ends(coupling):
    model = _Probit()
    pr, pt, fc = _design()
    P = model.P(pr, pt, fc)
    truth = model.truth(FIG4_FC)
    est = {k: [] for k in truth}
    err = {k: [] for k in truth}
    for rep in range(30):
        rng = np.random.default_rng(rep)
        # common random numbers: one uniform per sample (outcomes monotone in P); or none
        u = rng.random((96, 1)) if coupling == "common" else rng.random((96, P.size))
        y = (u < P[None]).astype(float)
        _, avg = an.fit_efficacies(
            np.array([y, y]),
            pr,
            pt,
            fc,
            CENTRE,
            FIG4_FC,
            n_boot=60,
            rng=np.random.default_rng(50 + rep),
        )  # two identical "strains": the average equals each
        for k in truth:
            est[k].append(avg.values[k])
            err[k].append(avg.err(k))
    for k in truth:
        assert_calibrated(est[k], err[k], truth[k], coverage=0.8, ratio=(0.6, 1.6))


# --------------------------------------------------------------------------- agreement


def test_agreement_z_holds_its_level_under_the_null():
    rng = np.random.default_rng(0)
    # one point: ours ~ N(paper, 0.02), paper's own error 0.013; z < 2 in 95.4 % of draws
    ours = 0.372 + rng.normal(0, 0.02, 4000) + rng.normal(0, 0.013, 4000)
    z = np.array([an.agreement_z(o, 0.02**2, 0.372, 0.013) for o in ours])
    assert np.mean(z < 2) == pytest.approx(0.954, abs=0.012)
    # nine strongly correlated points: Sidak stays at or above the level, not far above
    C = 0.01 * (0.9 * np.ones((9, 9)) + 0.1 * np.eye(9))
    draws = rng.multivariate_normal(np.ones(9), C, 2000)
    z9 = np.array([an.agreement_z(d, C, 1.0) for d in draws])
    assert 0.954 - 0.012 <= np.mean(z9 < 2) <= 0.995
    # the sign statistic: zero on the claimed side, a plain z on the other
    assert an.sign_z(0.1, 0.05, +1) == 0.0 and an.sign_z(-0.1, 0.05, +1) == pytest.approx(2.0)


# --------------------------------------------------------------------------- method study


def test_crossing_point_is_calibrated():
    x = np.round(np.arange(0.5, 0.81, 0.025), 3)
    est, err = [], []
    for rep in range(30):
        rng = np.random.default_rng(rep)
        t = rng.logistic(0.65, 0.03, 40)  # thresholds: P(x) logistic, crossing 1/2 at 0.65
        loc = an.crossing_point((x[None] > t[:, None]).astype(float), x, n_boot=100, rng=rng)
        est.append(loc.value)
        err.append(loc.err)
    assert_calibrated(est, err, 0.65)


def test_paired_bootstrap_gives_the_error_of_a_difference_on_the_same_samples():
    diff, diff_err, a_err = [], [], []
    for rep in range(40):
        rng = np.random.default_rng(rep)
        a = rng.normal(0.0, 1.0, 200)
        b = a + 0.1 + rng.normal(0.0, 0.1, 200)  # b = a shifted, with small extra noise
        est = an.paired_bootstrap(np.mean, a, b, n_boot=200, rng=rng)
        diff.append(est.diff)
        diff_err.append(est.diff_err)
        a_err.append(est.a_err)
    assert_calibrated(diff, diff_err, 0.1)
    # the correlation makes the difference ten times better determined than either value
    assert np.mean(diff_err) < 0.2 * np.mean(a_err)


# --------------------------------------------------------------------------- finite size


def test_finite_size_extrapolation_is_calibrated():
    """p(n) = 0.66 - 0.2 n^(-1/1.2) at n = 8, 16, 32, 64 with errors 0.003: nu fixed (linear)
    and nu fitted (three parameters from four sizes, errors by a parametric bootstrap)."""
    n = np.array([8.0, 16.0, 32.0, 64.0])
    err = np.full(4, 0.003)
    truth = 0.66 - 0.2 * n ** (-1 / 1.2)
    fixed, fixed_err, free, free_err, nu, nu_err = [], [], [], [], [], []
    for rep in range(25):
        rng = np.random.default_rng(rep)
        y = truth + rng.normal(0, err)
        f = an.fit_finite_size(n, y, err, nu=1.2)
        fixed.append(f.y_inf)
        fixed_err.append(f.y_inf_err)
        g = an.fit_finite_size(n, y, err, n_boot=100, rng=rng)
        free.append(g.y_inf)
        free_err.append(g.y_inf_err)
        nu.append(g.nu)
        nu_err.append(g.nu_err)
    assert_calibrated(fixed, fixed_err, 0.66)
    # one degree of freedom: the free fit's distribution is skewed; measured over 100
    # replicas its 2-sigma coverage is 0.89 and spread / error 1.05
    assert_calibrated(free, free_err, 0.66, coverage=0.8, ratio=(0.6, 1.6))
    assert_calibrated(nu, nu_err, 1.2, coverage=0.75, ratio=(0.6, 1.6))


def test_width_scaling_is_calibrated():
    """Thresholds drawn as p_c + n^(-1/nu) (a + b N(0, 1)) with p_c = 0.66, nu = 1.2 at the pc
    scale's sizes (fewer samples): the widths give nu and the centre against the width gives
    p_c, both within their bootstrap errors, and a wrong exponent (4/3, connectivity
    percolation) is excluded."""
    n = np.array([8.0, 16.0, 32.0, 64.0, 128.0])
    counts = [800, 400, 200, 100, 64]
    p_c, nu = [], []
    for rep in range(20):
        rng = np.random.default_rng(100 + rep)
        draws = [0.66 + k ** (-1 / 1.2) * (-0.06 + 0.1 * rng.normal(size=c)) for k, c in
                 zip(n, counts, strict=True)]  # fmt: skip
        w = an.width_scaling(n, draws, n_boot=100, rng=rng)
        p_c.append((w.p_c, w.p_c_err))
        nu.append((w.nu, w.nu_err))
    p_c, nu = np.array(p_c), np.array(nu)
    assert_calibrated(p_c[:, 0], p_c[:, 1], 0.66)
    assert_calibrated(nu[:, 0], nu[:, 1], 1.2)
    assert np.mean(np.abs(nu[:, 0] - 4 / 3) > 2 * nu[:, 1]) > 0.8


def test_width_scaling_refuses_never_rigid_samples():
    """A non-finite threshold has no standard deviation: NaN, not a number."""
    t = [np.array([0.6, 0.62, 0.65]), np.array([0.64, np.nan, 0.66]), np.array([0.65, 0.66, 0.67])]
    w = an.width_scaling(np.array([8.0, 16.0, 32.0]), t)
    assert np.isnan(w.nu) and np.isnan(w.p_c)


# --------------------------------------------------------------------------- fractal dimension


def test_fractal_dimension_recovers_a_known_exponent_with_a_calibrated_error():
    """Masses A n^d times log-normal scatter (a cluster's mass varies by tens of per cent
    between samples): d is recovered within its stated error, which matches the spread."""
    rng = np.random.default_rng(17)
    n = np.array([16.0, 32.0, 64.0, 128.0])
    d_true = 1.84
    est, err = [], []
    for r in range(60):
        masses = [2.5 * k**d_true * np.exp(rng.normal(0.0, 0.35, 80)) for k in n]
        fit = an.fractal_dimension(n, masses, n_boot=100, rng=np.random.default_rng(r))
        est.append(fit.d)
        err.append(fit.d_err)
        assert fit.dof == 2 and fit.mass.shape == (4,)
    assert_calibrated(est, err, d_true)


def test_fractal_dimension_is_nan_without_two_samples_per_size():
    fit = an.fractal_dimension(np.array([8.0, 16.0]), [np.array([5.0]), np.array([9.0, 11.0])])
    assert np.isnan(fit.d) and np.isnan(fit.d_err)
