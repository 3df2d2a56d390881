"""Fig. 2: rods + cables (f_c = 1), energies, nonaffinity and engaged cables versus p_r.

Estimators: p_crit is the median per-sample threshold (P = 1/2) with a bootstrap error; alpha
is the least-squares slope of ln(mean E) over ln(p_r - p_crit), its error a bootstrap over
samples that re-estimates p_crit in each replica (:mod:`.energy`); the paper's own estimators
(p_crit where the mean energy first becomes positive) are kept as evidence. Where the
nonaffinity peaks, its tails at p_crit and the taut-cable fraction are in :mod:`.nonaffinity`
and :mod:`.energy`.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
import pandas as pd

from ...analysis import estimators as an
from ..claims import Measurement
from .energy import energy_exponent, taut_with_error
from .field import FIELD_P_T, FIELD_SAMPLES, DisplacementField, displacement_field
from .nonaffinity import (
    at_transition,
    gamma_median_brackets,
    gamma_peaks,
    mask_min_norm,
    mask_uncertified_tensions,
    q25,
    q75,
    tail_statistics,
    worst_tail,
)
from .rows import PT4, Rows, interval_straddles, load_sweeps, p_r_grid, per_sample, strain_name
from .scales import Scale

#: the grid sweeps (one per p_t of PT4), whose rows feed the energy analyses
ENERGY_SWEEPS = tuple(f"fig2_pt{p_t:.1f}" for p_t in PT4)


@dataclass(frozen=True, eq=False)
class Fig2Result:
    """Rods + cables (f_c = 1): energies, nonaffinity, engaged cables versus p_r.

    Attributes
    ----------
    curves : DataFrame
        Per (phi, p_t, p_r): energy and nonaffinity: mean with standard error, median and
        quartiles (``*_median``, ``*_q25``, ``*_q75``; both are heavy-tailed near the
        transition), the number of samples with a nonaffinity (``gamma_n``), P, N; and the
        median nonaffinity over all N samples bracketed (``gamma_median_low``,
        ``gamma_median_high``: :func:`~tensegrity_rigidity.analysis.binomial.median_bracket`
        with the rows' certified lower bounds ``nonaffinity_lower``), with the number of
        samples known only from such a bound (``gamma_bounded``).
    taut : DataFrame
        Per (phi, p_t, p_r): fraction of cables under tension in rigid samples (mean, sem, size).
    fits : DataFrame
        Per (phi, p_t): the power-law fit of the mean energy above p_crit
        (:class:`~tensegrity_rigidity.analysis.scaling.PowerLawFit` fields of
        :func:`energy_exponent`: ``alpha_err`` from a bootstrap over samples that re-estimates
        p_crit, ``alpha_ls_err`` the least-squares error that does not) and ``p_crit_err``.
    crit : DataFrame
        Per (phi, p_t): ``p_crit`` (median threshold) and ``gamma_peak_p_r`` (grid p_r of the
        largest mean nonaffinity).
    paper_estimators : DataFrame
        Per (phi, p_t): the paper's estimators on our grid rows: ``p_crit`` where the mean
        energy first becomes positive and ``alpha`` fitted from it (with errors).
    peaks : dict
        Under compression, per p_t: where the mean and the median Gamma peak, with their joint
        covariance (see :func:`~tensegrity_rigidity.paper.studies.nonaffinity.gamma_peaks`).
    at_pcrit : DataFrame
        Per-sample Gamma and energy at the grid p_r nearest p_crit under compression, per p_t.
    tails : DataFrame
        :func:`tail_statistics` of ``at_pcrit``.
    worst_tail : dict or None
        Its Gamma row with the largest ``top_share`` (:func:`worst_tail`).
    min_norm_failed : int or None
        Grid samples whose displacements are not the verified minimum-norm minimiser (their
        Gamma is NaN); None when the rows do not record it.
    tensions_uncertified : int or None
        Rigid grid samples whose relaxed energy is not certified, so that their tensions need
        not be t* (their taut fractions are NaN, :func:`mask_uncertified_tensions`); None when
        the rows do not record the energy's lower bound.
    taut_at_transition : tuple
        (mean, error, [(p_t, p_r), ...]): the fraction of taut cables in rigid samples at the grid
        p_r nearest p_crit under compression, averaged over p_t = 0.1, 0.2, 0.3; None when no
        such sample exists.
    field : DisplacementField
    """

    curves: pd.DataFrame
    taut: pd.DataFrame
    fits: pd.DataFrame
    crit: pd.DataFrame
    paper_estimators: pd.DataFrame
    peaks: dict
    at_pcrit: pd.DataFrame
    tails: pd.DataFrame
    worst_tail: dict | None
    min_norm_failed: int | None
    tensions_uncertified: int | None
    taut_at_transition: tuple | None
    n: int
    samples: int
    rows: pd.DataFrame
    field: DisplacementField
    excluded: dict[str, int]
    straddling: int | None = None
    measured: tuple[Measurement, ...] = ()
    samples_threshold: int = 0  # threshold samples behind p_crit
    # sweep name -> undecided rows excluded from P, Gamma and the taut cables but kept in the
    # energy analyses (:func:`energy_bracketed`; counted in ``excluded`` too; the curves'
    # ``energy_n`` counts them, ``N`` does not)
    bracketed: dict[str, int] = dataclasses.field(default_factory=dict)


def sweeps(scale: Scale) -> dict[str, dict]:
    """Sweep name -> spec of Fig. 2: a grid per p_t, the thresholds on the same samples
    (seed 21) and the two small sweeps that supply the drawn samples of Figs. 2A and 1A."""
    p_r = p_r_grid(scale.p_r_step, 0.3, 0.95)
    base = {"n": scale.n_grid, "f_c": 1.0, "phi": ["compression", "dilation"], "seed": 21}
    out = {
        f"fig2_pt{p_t:.1f}": base
        | {
            "p_r": [p for p in p_r if p + p_t <= 1 + 1e-12],
            "p_t": p_t,
            "samples": scale.samples_grid,
        }
        for p_t in PT4
    }
    out["fig2_thresholds"] = base | {
        "p_t": PT4,
        "samples": scale.samples_threshold,
        "threshold": {"path": "p_r"},
    }
    field = {"n": max(scale.n_grid, 8), "samples": FIELD_SAMPLES, "f_c": 1.0, "seed": 1000}
    out["fig2_field"] = field | {
        "p_t": FIELD_P_T,
        "phi": "compression",
        "threshold": {"path": "p_r"},
    }
    out["fig1a_field"] = field | {
        "p_r": 0.55,
        "p_t": 0.4,
        "f_c": 0.5,
        "phi": "shear",
        "seed": 2000,
    }
    return out


def analyse(sweep_rows: Rows, scale: Scale) -> Fig2Result:
    """Rods + cables (f_c = 1): nonaffinity, energies and engaged cables versus p_r.

    ``sweep_rows`` holds the rows of :func:`sweeps` (the grids read with ``energy``: they keep
    undecided rows whose energy is bracketed); a grid of a p_t missing from it is left out, and
    without the field sweeps the drawn samples are None.
    """
    p_r = p_r_grid(scale.p_r_step, 0.3, 0.95)
    grids, excluded, bracketed = [], {}, {}
    for p_t in PT4:
        name = f"fig2_pt{p_t:.1f}"
        if name not in sweep_rows:
            continue
        rows, excluded[name] = sweep_rows[name]
        bracketed[name] = int((~rows.decided.astype(bool)).sum())
        grids.append(rows)
    # the energy analyses read every row kept, the others only the decided ones
    energy_rows = pd.concat(grids, ignore_index=True)
    rows = energy_rows[energy_rows.decided.astype(bool)].reset_index(drop=True)
    rows, min_norm_failed = mask_min_norm(rows)
    rows, tensions_uncertified = mask_uncertified_tensions(rows)
    th, excluded["fig2_thresholds"] = sweep_rows["fig2_thresholds"]
    energies = (
        energy_rows.groupby(["phi", "p_t", "p_r"])
        .agg(
            energy=("energy", "mean"),
            energy_sem=("energy", "sem"),
            energy_median=("energy", "median"),
            energy_q25=("energy", q25),
            energy_q75=("energy", q75),
            energy_n=("energy", "size"),
        )
        .reset_index()
    )
    curves = (
        rows.groupby(["phi", "p_t", "p_r"])
        .agg(
            gamma=("nonaffinity", "mean"),
            gamma_sem=("nonaffinity", "sem"),
            gamma_median=("nonaffinity", "median"),
            gamma_q25=("nonaffinity", q25),
            gamma_q75=("nonaffinity", q75),
            gamma_n=("nonaffinity", "count"),
            P=("rigid", "mean"),
            N=("rigid", "size"),
        )
        .reset_index()
    )
    curves = energies.merge(curves, on=["phi", "p_t", "p_r"], how="left")
    curves = curves.merge(gamma_median_brackets(rows), on=["phi", "p_t", "p_r"], how="left")
    taut = (
        rows[rows.rigid]
        .groupby(["phi", "p_t", "p_r"])
        .frac_cables_taut.agg(["mean", "sem", "size"])
        .reset_index()
    )
    fits, crit, paper_est = [], [], []
    for (phi, p_t), sub in curves.groupby(["phi", "p_t"]):
        one = np.isclose(th.phi, phi) & np.isclose(th.p_t, p_t)
        grid = energy_rows[np.isclose(energy_rows.phi, phi) & np.isclose(energy_rows.p_t, p_t)]
        pc, pc_err = an.critical_point(
            th[one].threshold_p_r.to_numpy(), rng=scale.rng("critical_point")
        )
        fit = energy_exponent(grid, th[one], scale.bootstrap, rng=scale.rng("energy_exponent"))
        fits.append(
            {
                "phi": phi,
                "strain": strain_name(phi),
                "p_t": p_t,
                "p_crit_err": pc_err,
                **fit.__dict__,
            }
        )
        g = sub.set_index("p_r").gamma
        crit.append({"phi": phi, "p_t": p_t, "p_crit": pc, "gamma_peak_p_r": float(g.idxmax())})
        # the paper's estimators on the decided grid rows: p_crit where the mean energy first
        # becomes positive, and the power law fitted from that p_crit (an undecided row's
        # bracketed energy could make a mean positive that is not)
        decided = rows[np.isclose(rows.phi, phi) & np.isclose(rows.p_t, p_t)]
        e, x = per_sample(decided, "energy")
        first = an.first_positive(e, x, n_boot=scale.bootstrap, rng=scale.rng("first_positive"))
        pfit = an.fit_energy_exponent(
            x, e, lambda idx, e=e, x=x: an.first_positive(e[idx], x, n_boot=0).value,
            n_boot=scale.bootstrap, rng=scale.rng("energy_exponent"),
        )  # fmt: skip
        paper_est.append(
            {
                "phi": phi,
                "strain": strain_name(phi),
                "p_t": p_t,
                "p_crit": first.value,
                "p_crit_err": first.err,
                "alpha": pfit.alpha,
                "alpha_err": pfit.alpha_err,
                "n_points": pfit.n_points,
            }
        )
    crit, fits, paper_est = pd.DataFrame(crit), pd.DataFrame(fits), pd.DataFrame(paper_est)
    peaks = gamma_peaks(rows, crit, scale.bootstrap, rng=scale.rng("peaks"))
    at_pcrit = at_transition(rows, crit)
    tails = tail_statistics(at_pcrit)
    taut_tr = taut_with_error(rows, th, scale.bootstrap, rng=scale.rng("taut"))
    field_ = DisplacementField(None, None, float("nan"), FIELD_P_T, None, None)
    if {"fig2_field", "fig1a_field"} <= set(sweep_rows):
        field_, excluded["fig2_field"], excluded["fig1a_field"] = displacement_field(
            sweep_rows, sweeps(scale)
        )
    result = Fig2Result(
        curves=curves,
        taut=taut,
        fits=fits,
        crit=crit,
        paper_estimators=paper_est,
        peaks=peaks,
        at_pcrit=at_pcrit,
        tails=tails,
        worst_tail=worst_tail(tails),
        min_norm_failed=min_norm_failed,
        tensions_uncertified=tensions_uncertified,
        taut_at_transition=taut_tr,
        n=scale.n_grid,
        samples=scale.samples_grid,
        rows=rows,
        field=field_,
        excluded=excluded,
        bracketed=bracketed,
        straddling=interval_straddles(th, p_r),
        samples_threshold=scale.samples_threshold,
    )
    return dataclasses.replace(result, measured=claims(result))


def claims(result: Fig2Result) -> tuple[Measurement, ...]:
    """p_crit and alpha per strain and p_t (ours, and the paper's estimators as evidence), the
    taut-cable fraction at the transition and where the nonaffinity peaks."""
    fits, paper_est, peaks = result.fits, result.paper_estimators, result.peaks
    taut_tr, n = result.taut_at_transition, result.n
    system = f"n = {n}, {result.samples} samples per point"
    out = []
    for _, row in fits.iterrows():
        alt = paper_est[np.isclose(paper_est.phi, row.phi) & np.isclose(paper_est.p_t, row.p_t)]
        alt = alt.iloc[0]
        key = f"p_crit_{row.strain}_{row.p_t}"
        out.append(
            Measurement.scalar(
                key,
                row.p_crit,
                row.p_crit_err,
                f"n = {n}, {result.samples_threshold} thresholds",
                note="ours: median threshold (P = 1/2); paper: first positive mean energy",
                size=n,
            )
        )
        out.append(
            Measurement.scalar(
                key,
                alt.p_crit,
                alt.p_crit_err,
                system,
                factor="estimator",
                label="the paper's p_crit (first grid p_r with positive mean energy)",
                size=n,
            )
        )
        key = f"alpha_{row.strain}_{row.p_t}"
        out.append(
            Measurement.scalar(
                key,
                row.alpha,
                row.alpha_err,
                f"{system}; {row.n_points} fit points",
                note="least squares of ln(mean E) over ln(p_r - p_crit), p_crit = P = 1/2; "
                "error: bootstrap over samples, p_crit re-estimated in each replica",
                size=n,
            )
        )
        out.append(
            Measurement.scalar(
                key,
                alt.alpha,
                alt.alpha_err,
                f"{system}; {alt.n_points} fit points",
                factor="estimator",
                label="fitted from the paper's p_crit (first positive mean energy)",
                size=n,
            )
        )
    if taut_tr is not None:
        v, e, _ = taut_tr
        out.append(
            Measurement.scalar(
                "taut_cables_transition",
                v,
                e,
                system,
                note="rigid samples with certified tensions at p_r nearest p_crit, mean over "
                "p_t = 0.1, 0.2, 0.3 (error: bootstrap over samples, p_crit re-estimated)",
                size=n,
            )
        )
    labels = tuple(f"p_t = {p:.1f}" for p in peaks["p_t"])
    pc_var = np.diag(
        fits[np.isclose(fits.phi, math.pi)].sort_values("p_t").p_crit_err.to_numpy() ** 2
    )
    for stat, factor, label in (
        ("mean", "ours", ""),
        ("median", "estimator", "peak of the median Gamma instead of the mean"),
    ):
        at, cov = peaks[stat]
        out.append(
            Measurement(
                "gamma_peak",
                at - peaks["p_crit"],
                cov + pc_var,
                system,
                factor=factor,
                label=label,
                points=labels,
                note="peak of the mean Gamma on the p_r grid minus the median threshold; error: "
                "bootstrap over samples, grid resolution, p_crit's error",
                size=n,
            )
        )
    return tuple(out)


def study(out, scale: Scale, **kw) -> Fig2Result:
    """Run (or resume) the sweeps of Fig. 2 into ``out`` and analyse them."""
    return analyse(load_sweeps(out, sweeps(scale), energy=ENERGY_SWEEPS, **kw), scale)
