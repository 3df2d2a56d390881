"""Every ensemble estimator in one namespace, for callers that want them together.

The estimators live by concern: :mod:`.binomial` (P, Wilson intervals, thresholds, p_crit),
:mod:`.fits` (the collapse and the efficacy surface), :mod:`.scaling` (energy power laws, peaks,
finite-size extrapolation), :mod:`.agreement` (paired bootstraps, z statistics) and
:mod:`.bootstrap` (the one resampling helper and the :class:`~.bootstrap.Estimate` type).
"""

from __future__ import annotations

from .agreement import (
    PairedEstimate,
    agreement_z,
    holm_adjusted,
    paired_bootstrap,
    sign_z,
)
from .binomial import (
    CRITICAL_POINT_REPLICAS,
    common_samples,
    critical_point,
    crossing_point,
    median_bracket,
    median_threshold,
    outcomes_from_thresholds,
    probability_curve,
    probability_from_thresholds,
    rigidity_probability,
    wilson,
)
from .bootstrap import (
    Estimate,
    n_units,
    replicas,
    resampler,
)
from .fits import (
    CollapseFit,
    EfficacyCurves,
    collapse_contrast,
    contour_slope,
    fit_collapse,
    fit_collapse_thresholds,
    fit_efficacies,
    fit_logistic,
    paired_derivative,
    paired_slope,
)
from .scaling import (
    THETA,
    FiniteSizeFit,
    FractalDimension,
    PowerLawFit,
    WidthScaling,
    first_positive,
    fit_energy_exponent,
    fit_energy_power_law,
    fit_finite_size,
    fractal_dimension,
    peak_locations,
    width_scaling,
)

__all__ = [
    "CRITICAL_POINT_REPLICAS",
    "CollapseFit",
    "EfficacyCurves",
    "Estimate",
    "FiniteSizeFit",
    "FractalDimension",
    "PairedEstimate",
    "PowerLawFit",
    "THETA",
    "WidthScaling",
    "agreement_z",
    "holm_adjusted",
    "collapse_contrast",
    "common_samples",
    "contour_slope",
    "critical_point",
    "crossing_point",
    "first_positive",
    "fit_collapse",
    "fit_collapse_thresholds",
    "fit_efficacies",
    "fit_energy_exponent",
    "fit_energy_power_law",
    "fit_finite_size",
    "fit_logistic",
    "fractal_dimension",
    "median_bracket",
    "median_threshold",
    "n_units",
    "outcomes_from_thresholds",
    "paired_bootstrap",
    "paired_derivative",
    "paired_slope",
    "peak_locations",
    "probability_curve",
    "probability_from_thresholds",
    "replicas",
    "resampler",
    "rigidity_probability",
    "sign_z",
    "width_scaling",
    "wilson",
]
