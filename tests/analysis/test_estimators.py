"""Estimators recover known parameters on synthetic data."""

from __future__ import annotations

import numpy as np
import pytest

from tensegrity_rigidity.analysis.estimators import (
    critical_point,
    fit_collapse,
    fit_energy_power_law,
    paired_derivative,
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
